//! Engine parameter sets: the Christensen–Burley profile that best fits a Monte Carlo profile,
//! written in each engine's own fields and units, with what that profile costs against the
//! Monte Carlo ground truth. Conventions, read from each engine's public source or specification:
//!
//! - **Unreal Engine 5**, Subsurface Profile in Burley mode (`FSubsurfaceProfileStruct`,
//!   `SubsurfaceScatteringMath.h`, `BurleyNormalizedSSSCommon.ush`): the shader evaluates Burley's
//!   profile with the searchlight factor s_SL(A) = 3.5 + 100(A − 0.33)⁴ on a diffuse mean free
//!   path DMFP [mm] = 10·MFP[cm]·s_SL(A)/(0.6·s_perp(A)), s_perp(A) = 1.85 − A + 7|A − 0.8|³, so
//!   the shape length is d = DMFP/s_SL = 10·MFP/(0.6·s_perp) mm and MFP [cm] = 0.6·s_perp(A)·d[cm].
//!   Mean Free Path Distance is the largest channel's MFP [cm, one Unreal unit], Mean Free Path
//!   Color the channels divided by it; Surface Albedo is A. A World Unit Scale of 1 keeps the
//!   profile at physical size (read from `CalculateBurleyScale`; not checked in a running editor).
//! - **Unity HDRP**, Diffusion Profile (`DiffusionProfileSettings.cs`, `SubsurfaceScattering.compute`):
//!   Scattering Distance × Multiplier is Burley's d per channel in mm (shape parameter S = 1/d),
//!   World Scale is the size of one world unit in metres (1 for scenes in metres); the albedo is
//!   the material's diffuse colour.
//! - **Blender Cycles**, Principled BSDF with Subsurface Method "Christensen-Burley" (3.x–5.0;
//!   `kernel/closure/bssrdf.h`): Radius × Scale is scaled by 1/(4π) to Burley's d with no albedo
//!   fit, so Radius × Scale = 4π·d, in scene units (metres by default); Base Color is A. With
//!   Subsurface Method "Random Walk" Cycles traces a medium instead, and [`random_walk`] gives
//!   the fields that make it the material's own ([`crate::cycles`]: the remap and radius scale
//!   of Blender 4.0–5.0 inverted).
//! - **OpenPBR 1.1** (and its MaterialX node `open_pbr_surface`): `subsurface_color` is the
//!   index-matched multiple-scattering albedo and `subsurface_radius × subsurface_radius_scale`
//!   the mean free path 1/σt per channel: an exact description of the medium, written from the
//!   material's coefficients through [`mc::artist`] (van de Hulst's inversion), not from a fit.
//!
//! A, the albedo the Burley engines expect, is the Monte Carlo profile's total diffuse
//! reflectance per channel (∫Rd dA, without the specular reflection at entry); d is fitted to
//! the profile's shape by [`crate::Burley::fit`].

use std::fmt;
use std::str::FromStr;

use serde::Serialize;

use crate::analytic::burley::Burley;
use crate::profile::Profile;
use crate::select::Judge;

/// The engines parameters are written for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Engine {
    /// Unreal Engine 5: Subsurface Profile in Burley mode.
    Unreal,
    /// Unity HDRP: Diffusion Profile.
    Unity,
    /// Blender Cycles: Principled BSDF with the Christensen-Burley subsurface method.
    Blender,
    /// OpenPBR 1.1: subsurface parameters from the material's coefficients, not from a fit.
    OpenPbr,
}

impl Engine {
    /// Every engine.
    pub const ALL: [Engine; 4] = [
        Engine::Unreal,
        Engine::Unity,
        Engine::Blender,
        Engine::OpenPbr,
    ];
}

impl fmt::Display for Engine {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Engine::Unreal => "unreal",
            Engine::Unity => "unity",
            Engine::Blender => "blender",
            Engine::OpenPbr => "openpbr",
        })
    }
}

impl FromStr for Engine {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        Engine::ALL
            .into_iter()
            .find(|e| e.to_string() == s.trim().to_ascii_lowercase())
            .ok_or_else(|| format!("unknown engine {s:?} (unreal, unity, blender, openpbr)"))
    }
}

impl Serialize for Engine {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

/// The Burley profile fitted to a Monte Carlo profile, per channel, and what it costs.
#[derive(Clone, Debug, Serialize)]
pub struct BurleyProfileFit {
    /// Total diffuse reflectance A of the Monte Carlo profile [-].
    pub albedo: [f64; 3],
    /// Burley's shape length d [cm].
    pub d_cm: [f64; 3],
    /// ‖K − B‖₂/‖K‖₂ of the radial Burley kernel B (energy of K) against the normalized ground
    /// truth K [-].
    pub kernel_rms_rel: [f64; 3],
    /// Image RMS on the test signals of the radial Burley kernel applied in 2D (images in [0, 1]).
    pub image_rms: [f64; 3],
    /// Channels that return no diffuse light (Rd ≡ 0: they do not scatter): albedo 0, nothing
    /// to compare (errors 0), d the smallest of the other channels' so that they set the
    /// engine's distance scale.
    pub dark: [bool; 3],
}

impl BurleyProfileFit {
    /// Fits d per channel to `p` at its bins' radii ([`Burley::fit_profile`]) and scores the radial
    /// kernel against the ground truths of `judge` (made from `p`).
    pub fn new(p: &Profile, judge: &Judge) -> Self {
        let (mut d_cm, mut kernel_rms_rel, mut image_rms) = ([0.0; 3], [0.0; 3], [0.0; 3]);
        let mut dark = [false; 3];
        for (c, k) in judge.truths().iter().enumerate() {
            if k.is_delta() {
                dark[c] = true;
                continue;
            }
            let b = Burley::fit_profile(p, c);
            let mut dense = b.kernel(k.half, k.h);
            let s = k.l1() / dense.l1();
            dense.v.iter_mut().for_each(|x| *x *= s);
            let num: f64 = k.v.iter().zip(&dense.v).map(|(p, q)| (p - q).powi(2)).sum();
            let den: f64 = k.v.iter().map(|p| p * p).sum();
            d_cm[c] = b.d;
            kernel_rms_rel[c] = (num / den).sqrt();
            let e = judge.image_rms_dense(c, &dense);
            image_rms[c] = e;
        }
        let lit = (0..3)
            .filter(|&c| !dark[c])
            .map(|c| d_cm[c])
            .fold(f64::INFINITY, f64::min);
        for c in (0..3).filter(|&c| dark[c]) {
            d_cm[c] = lit;
        }
        BurleyProfileFit {
            albedo: [0, 1, 2].map(|c| p.total(c)),
            d_cm,
            kernel_rms_rel,
            image_rms,
            dark,
        }
    }
}

/// One parameter as the engine's user interface names it.
#[derive(Clone, Debug, Serialize)]
pub struct Field {
    /// The parameter's name in the engine's user interface, e.g. `Surface Albedo`.
    pub name: &'static str,
    /// Its value.
    pub value: Value,
    /// Unit, or "" for unitless values and colours.
    pub unit: &'static str,
}

/// A number, an RGB colour or a choice.
#[derive(Clone, Debug, Serialize)]
#[serde(untagged)]
pub enum Value {
    /// A number.
    Number(f64),
    /// An RGB colour.
    Color([f64; 3]),
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::Number(x) => write!(f, "{x:.6}"),
            Value::Color(c) => write!(f, "({:.6}, {:.6}, {:.6})", c[0], c[1], c[2]),
        }
    }
}

/// An engine's parameter set.
#[derive(Clone, Debug, Serialize)]
pub struct EngineParams {
    /// The engine these fields are for.
    pub engine: Engine,
    /// Where in the engine these fields live.
    pub location: &'static str,
    /// The parameters to set, each as the engine names it.
    pub fields: Vec<Field>,
    /// Clamps applied, ranges exceeded, assumptions.
    pub notes: Vec<String>,
}

impl EngineParams {
    /// The fields as printed for material `slug`: where they live, each field with its value
    /// and unit, the notes; one line each.
    pub fn text(&self, slug: &str) -> String {
        let mut text = format!("{slug} — {} ({}):\n", self.location, self.engine);
        for f in &self.fields {
            text += &format!("  {:<32} {} {}\n", f.name, f.value, f.unit);
        }
        for n in &self.notes {
            text += &format!("  note: {n}\n");
        }
        text
    }
}

/// Christensen–Burley's fit for a pencil beam with the mean free path (UE's "perpendicular").
fn s_perp(a: f64) -> f64 {
    1.85 - a + 7.0 * (a - 0.8).abs().powi(3)
}

/// (colour = values / max, max): engines split per-channel lengths this way.
fn split(v: [f64; 3]) -> ([f64; 3], f64) {
    let m = v.iter().cloned().fold(0.0, f64::max);
    (v.map(|x| if m > 0.0 { x / m } else { 0.0 }), m)
}

fn field(name: &'static str, value: Value, unit: &'static str) -> Field {
    Field { name, value, unit }
}

/// The parameters of a Burley-based engine from the fitted profile.
pub fn burley_engine(engine: Engine, fit: &BurleyProfileFit) -> Option<EngineParams> {
    let (a, d) = (fit.albedo, fit.d_cm);
    let mut notes = Vec::new();
    for c in (0..3).filter(|&c| fit.dark[c]) {
        notes.push(format!(
            "{}: returns no diffuse light (it does not scatter): albedo 0, its length set to the smallest of the other channels' so that they set the distance scale",
            mc::CHANNELS[c]
        ));
    }
    let (location, fields) = match engine {
        Engine::Unreal => {
            let albedo = a.map(|x| x.clamp(0.01, 1.0));
            if albedo != a {
                notes.push(format!(
                    "Surface Albedo clamped to Unreal's range [0.01, 1] from {a:.4?}"
                ));
            }
            let mfp = [0, 1, 2].map(|c| 0.6 * s_perp(albedo[c]) * d[c]);
            let (color, dist) = split(mfp);
            if !(0.1..=50.0).contains(&dist) {
                notes.push(format!(
                    "Mean Free Path Distance {dist:.4} cm is outside the editor's slider range 0.1–50 cm; type it in or rescale World Unit Scale"
                ));
            }
            (
                "Subsurface Profile asset (Burley Normalized)",
                vec![
                    field("Surface Albedo", Value::Color(albedo), ""),
                    field("Mean Free Path Color", Value::Color(color), ""),
                    field(
                        "Mean Free Path Distance",
                        Value::Number(dist),
                        "cm (Unreal units)",
                    ),
                    field("World Unit Scale", Value::Number(1.0), ""),
                    field("Tint", Value::Color([1.0; 3]), ""),
                ],
            )
        }
        Engine::Unity => {
            let (color, mult) = split(d.map(|x| 10.0 * x));
            notes.push(
                "Set the material's Base Color (diffuse albedo) to the listed albedo.".into(),
            );
            notes.push(format!(
                "Max Radius will read {:.3} mm (16.56 × the largest distance).",
                16.56 * mult
            ));
            (
                "HDRP Diffusion Profile",
                vec![
                    field("Scattering Distance", Value::Color(color), ""),
                    field("Multiplier", Value::Number(mult), "mm"),
                    field("World Scale", Value::Number(1.0), "m per world unit"),
                    field("Base Color (albedo)", Value::Color(a), ""),
                ],
            )
        }
        Engine::Blender => {
            let (radius, scale) = split(d.map(|x| 4.0 * std::f64::consts::PI * x / 100.0));
            (
                "Principled BSDF, Subsurface Method: Christensen-Burley",
                vec![
                    field("Base Color", Value::Color(a), ""),
                    field("Subsurface Weight", Value::Number(1.0), ""),
                    field("Subsurface Radius", Value::Color(radius), ""),
                    field(
                        "Subsurface Scale",
                        Value::Number(scale),
                        "m (scene units in metres)",
                    ),
                ],
            )
        }
        Engine::OpenPbr => return None,
    };
    Some(EngineParams {
        engine,
        location,
        fields,
        notes,
    })
}

/// Blender Cycles' Principled BSDF with Subsurface Method "Random Walk" (Blender 4.0–5.0; "Random
/// Walk (Fixed Radius)" in 3.x): the material's own medium, with Base Color matched to the walk
/// Cycles really runs where g > 0 ([`crate::cycles::matched_alpha`]: its reflectance at normal
/// incidence is the medium's; [`random_walk_exact`] leaves that out). Subsurface Radius ×
/// Subsurface Scale (d) with Subsurface Anisotropy give Cycles' extinction σt = 4π/(d·(1 − g)),
/// and Base Color its single-scattering
/// albedo through the remap of [`crate::cycles`], inverted numerically; lengths in metres (scene
/// units). Cycles has one anisotropy, clamped to [0, 0.9]: a material whose g differs per channel
/// gets their mean, and one outside that range the nearest end (σa and σs stay exact; the phase
/// function does not). Fields as Blender 4.0–5.0 name them (Principled BSDF v2); in 3.x choose
/// "Random Walk (Fixed Radius)", set Subsurface to 1 and Subsurface Color to the Base Color.
pub fn random_walk(m: &mc::Material) -> EngineParams {
    random_walk_fields(m, true)
}

/// [`random_walk`] without the match of Cycles' walk: Base Color is the exact inversion of
/// Cycles' remap, so that Cycles' first ten bounces trace the material's own σa, σs and g (and
/// every bounce where g = 0). Cheap (no runs).
pub fn random_walk_exact(m: &mc::Material) -> EngineParams {
    random_walk_fields(m, false)
}

fn random_walk_fields(m: &mc::Material, matched: bool) -> EngineParams {
    let mean = m.g.iter().sum::<f64>() / 3.0;
    let g = mean.clamp(0.0, crate::cycles::MAX_G);
    let mut notes = vec![
        "Inverts Cycles' random walk of Blender 4.0–5.0 (subsurface_random_walk_remap with its anisotropy polynomials, and the 1/(4π) bssrdf_setup_radius applies to Radius × Scale); in Blender 3.x the same fields belong to \"Random Walk (Fixed Radius)\"; Blender 2.9x's isotropic remap differs.".to_string(),
    ];
    if m.g.iter().any(|x| (x - mean).abs() > 1e-12) {
        notes.push(format!(
            "Cycles has one anisotropy; the material's g per channel {:?} is averaged",
            m.g
        ));
    }
    if g != mean {
        notes.push(format!(
            "Cycles clamps Subsurface Anisotropy to [0, 0.9]: g = {mean} is traced as {g}"
        ));
    }
    if m.eta != 1.0 {
        notes.push(format!(
            "Cycles' walk leaves the surface through a Lambertian BSDF, without Fresnel transmission or internal reflection: behind a boundary of η = {} it reflects more light than this medium does (docs/engines.md, Blender in a loop)",
            m.eta
        ));
    }
    if !(1.01..=3.8).contains(&m.eta) {
        notes.push(format!(
            "Cycles clamps the subsurface IOR to [1.01, 3.8]: η = {} is traced as {}",
            m.eta,
            m.eta.clamp(1.01, 3.8)
        ));
    }
    if matched && corrects(m, g) {
        notes.push(format!(
            "Cycles does not trace the medium it is given at g > 0: bounces 0–9 of its walk trace σs, σt and g, later ones the similarity-scaled medium σs(1 − g), isotropic (SUBSURFACE_RANDOM_WALK_SIMILARITY_LEVEL 9), and walks end after 256 bounces. Base Color is therefore not the exact inversion of Cycles' remap but the single-scattering albedo that makes that walk (mc::cycles, traced by mc) reflect the medium's own total Rd at normal incidence in an index-matched half-space: a secant root find per channel on runs of {} photons at one seed. Subsurface Radius keeps the medium's σt, so Cycles' first flights are the medium's and its later ones have the medium's transport coefficient σa + σs(1 − g). What remains: Rd at other incidences and the profile Rd(r) are not matched, only close (the first ten flights use the lowered albedo; the walk's light leaves from slightly different depths)",
            crate::cycles::MATCH_PHOTONS
        ));
    }
    let (mut color, mut radius_cm) = ([0.0; 3], [0.0; 3]);
    for (c, ch) in mc::CHANNELS.iter().enumerate() {
        let sigma_t = m.sigma_a[c] + m.sigma_s[c];
        if sigma_t <= 0.0 {
            notes.push(format!(
                "{ch}: the material does not interact with light; radius 0 leaves Cycles' channel without subsurface scattering"
            ));
            continue;
        }
        let own = m.sigma_s[c] / sigma_t;
        radius_cm[c] = crate::cycles::radius_for(sigma_t, g);
        let alpha = if matched {
            match_walk(own, m.g[c], g, ch, &mut notes)
        } else {
            own
        };
        color[c] = match crate::cycles::color_for(alpha, g) {
            Some(a) => a,
            None => {
                notes.push(format!(
                    "{ch}: single-scattering albedo {alpha} is above what Cycles traces ({}); Base Color 1 gives that",
                    crate::cycles::alpha(1.0, g)
                ));
                1.0
            }
        };
        if own < crate::cycles::MIN_ALPHA {
            notes.push(format!(
                "{ch}: single-scattering albedo {own:.4} is below 0.2, where Cycles traces 0.2 and scales the light by α/0.2: not the same medium"
            ));
        }
    }
    let (radius, scale_cm) = split(radius_cm);
    EngineParams {
        engine: Engine::Blender,
        location: "Principled BSDF, Subsurface Method: Random Walk",
        fields: vec![
            field("Base Color", Value::Color(color), ""),
            field("Subsurface Weight", Value::Number(1.0), ""),
            field("Subsurface Radius", Value::Color(radius), ""),
            field(
                "Subsurface Scale",
                Value::Number(scale_cm / 100.0),
                "m (scene units in metres)",
            ),
            field("Subsurface Anisotropy", Value::Number(g), ""),
            field("IOR", Value::Number(m.eta), ""),
            // The material's boundary is smooth: Cycles refracts the walk's entry direction
            // through GGX microfacets of α = Roughness² (`subsurface_entry_bounce`), and the
            // Principled BSDF's default Roughness is 0.5.
            field("Roughness", Value::Number(0.0), ""),
        ],
        notes,
    }
}

/// Whether Cycles' walk differs from the material's medium beyond its 256-bounce cap: its
/// anisotropy `g` is not 0 (the walk turns to the similarity-scaled medium after ten flights), or
/// a channel's own g differs from it.
fn corrects(m: &mc::Material, g: f64) -> bool {
    g != 0.0 || m.g.iter().any(|&x| x != g)
}

/// The single-scattering albedo Cycles should trace for a channel of albedo `own` and anisotropy
/// `g_own` when it traces anisotropy `g` ([`crate::cycles::matched_alpha`]), with a note; `own`
/// itself where the walk is the medium's (g = 0 everywhere), where Cycles substitutes 0.2, or
/// where the runs fail (noted).
fn match_walk(own: f64, g_own: f64, g: f64, ch: &str, notes: &mut Vec<String>) -> f64 {
    if (g == 0.0 && g_own == 0.0) || own < crate::cycles::MIN_ALPHA {
        return own;
    }
    let max = crate::cycles::alpha(1.0, g);
    match crate::cycles::matched_alpha(own, g_own, g, max) {
        Ok(m) => {
            notes.push(format!(
                "{ch}: Cycles' walk at the medium's single-scattering albedo {own:.6} reflects Rd(0°) = {:.4} ± {:.4} against the medium's {:.4} ± {:.4} ({:+.1} %); traced at {:.6} it reflects {:.4} ± {:.4}",
                m.walk_at_own.value,
                m.walk_at_own.se,
                m.target.value,
                m.target.se,
                100.0 * (m.walk_at_own.value / m.target.value - 1.0),
                m.alpha,
                m.walk.value,
                m.walk.se
            ));
            m.alpha
        }
        Err(e) => {
            notes.push(format!(
                "{ch}: the walk's albedo could not be matched ({e}); the exact inversion is kept"
            ));
            own
        }
    }
}

/// OpenPBR's subsurface parameters of a material (exact, from its coefficients); lengths in cm.
pub fn openpbr(m: &mc::Material) -> EngineParams {
    let art = m.artist();
    let (scale, radius) = split(art.radius);
    let g = m.g.iter().sum::<f64>() / 3.0;
    let mut notes = vec![
        "Lengths are in cm: divide subsurface_radius by your scene's cm per unit (100 for metres)."
            .into(),
    ];
    if m.g.iter().any(|x| (x - g).abs() > 1e-12) {
        notes.push(format!(
            "OpenPBR has one anisotropy; the material's g per channel {:?} is averaged",
            m.g
        ));
    }
    if art.radius.iter().any(|r| !r.is_finite()) {
        notes.push("A channel does not interact with light (infinite mean free path).".into());
    }
    EngineParams {
        engine: Engine::OpenPbr,
        location: "OpenPBR Surface (MaterialX open_pbr_surface)",
        fields: vec![
            field("base_color", Value::Color(art.color), ""),
            field("subsurface_weight", Value::Number(1.0), ""),
            field("subsurface_color", Value::Color(art.color), ""),
            field("subsurface_radius", Value::Number(radius), "cm"),
            field("subsurface_radius_scale", Value::Color(scale), ""),
            field("subsurface_scatter_anisotropy", Value::Number(g), ""),
            field("specular_ior", Value::Number(m.eta), ""),
        ],
        notes,
    }
}

/// A MaterialX 1.39 document with one `open_pbr_surface` material made of `p`'s fields.
pub fn materialx(p: &EngineParams, name: &str) -> String {
    let ident: String = name
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    let inputs: String = p
        .fields
        .iter()
        .map(|f| match &f.value {
            Value::Number(x) => format!(
                "    <input name=\"{}\" type=\"float\" value=\"{x}\" />\n",
                f.name
            ),
            Value::Color(c) => format!(
                "    <input name=\"{}\" type=\"color3\" value=\"{}, {}, {}\" />\n",
                f.name, c[0], c[1], c[2]
            ),
        })
        .collect();
    format!(
        "<?xml version=\"1.0\"?>\n<materialx version=\"1.39\" colorspace=\"lin_rec709\">\n  <!-- sss engine-params: {name}; lengths in cm -->\n  <open_pbr_surface name=\"SR_{ident}\" type=\"surfaceshader\">\n{inputs}  </open_pbr_surface>\n  <surfacematerial name=\"M_{ident}\" type=\"material\">\n    <input name=\"surfaceshader\" type=\"surfaceshader\" nodename=\"SR_{ident}\" />\n  </surfacematerial>\n</materialx>\n"
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each engine's mapping, read back with the engine's own formula, gives the fitted d.
    #[test]
    fn engine_fields_reproduce_the_burley_shape() {
        let fit = BurleyProfileFit {
            albedo: [0.6, 0.4, 0.2],
            d_cm: [0.12, 0.05, 0.02],
            kernel_rms_rel: [0.0; 3],
            image_rms: [0.0; 3],
            dark: [false; 3],
        };
        let get = |p: &EngineParams, name: &str| {
            p.fields
                .iter()
                .find(|f| f.name == name)
                .unwrap()
                .value
                .clone()
        };
        let num = |v: Value| {
            if let Value::Number(x) = v {
                x
            } else {
                panic!()
            }
        };
        let col = |v: Value| if let Value::Color(x) = v { x } else { panic!() };
        // Unreal: d [mm] = DMFP/s_SL with DMFP = 10·MFP·s_SL/(0.6·s_perp).
        let ue = burley_engine(Engine::Unreal, &fit).unwrap();
        let dist = num(get(&ue, "Mean Free Path Distance"));
        let color = col(get(&ue, "Mean Free Path Color"));
        for c in 0..3 {
            let a = fit.albedo[c];
            let s_sl = 3.5 + 100.0 * (a - 0.33f64).powi(4);
            let dmfp_mm = 10.0 * color[c] * dist * s_sl / (0.6 * s_perp(a));
            assert!((dmfp_mm / s_sl / 10.0 - fit.d_cm[c]).abs() < 1e-12);
        }
        // Unity: Scattering Distance × Multiplier = d in mm.
        let u = burley_engine(Engine::Unity, &fit).unwrap();
        let (sd, m) = (
            col(get(&u, "Scattering Distance")),
            num(get(&u, "Multiplier")),
        );
        // Blender: Radius × Scale / (4π) = d in metres.
        let b = burley_engine(Engine::Blender, &fit).unwrap();
        let (r, s) = (
            col(get(&b, "Subsurface Radius")),
            num(get(&b, "Subsurface Scale")),
        );
        for c in 0..3 {
            assert!((sd[c] * m / 10.0 - fit.d_cm[c]).abs() < 1e-12);
            assert!((r[c] * s / (4.0 * std::f64::consts::PI) * 100.0 - fit.d_cm[c]).abs() < 1e-12);
        }
        assert!(burley_engine(Engine::OpenPbr, &fit).is_none());
        assert_eq!("OpenPBR".parse::<Engine>().unwrap(), Engine::OpenPbr);
        assert!("godot".parse::<Engine>().is_err());
    }

    /// Cycles' own remap applied to the random-walk fields gives back σa, σs and g to 10⁻⁶,
    /// over the library and over extreme albedos and anisotropies.
    #[test]
    fn random_walk_fields_give_back_the_coefficients_through_cycles_remap() {
        let mut materials: Vec<mc::Material> = mc::builtin::names()
            .into_iter()
            .map(|n| mc::Material::builtin(n).unwrap())
            .collect();
        for g in [0.0, 0.5, 0.9] {
            for alpha in [0.2, 0.5, 0.9, 0.99, 0.999, 0.9999, 0.99999] {
                materials.push(mc::Material {
                    name: format!("α {alpha} g {g}"),
                    source: String::new(),
                    sigma_a: [1.0 - alpha, 10.0 * (1.0 - alpha), 100.0 * (1.0 - alpha)],
                    sigma_s: [alpha, 10.0 * alpha, 100.0 * alpha],
                    g: [g; 3],
                    eta: 1.4,
                    thickness: None,
                });
            }
        }
        for m in &materials {
            let p = random_walk_exact(m);
            let v = |n: &str| p.fields.iter().find(|f| f.name == n).unwrap().value.clone();
            let (Value::Color(color), Value::Color(radius), Value::Number(scale), Value::Number(g)) = (
                v("Base Color"),
                v("Subsurface Radius"),
                v("Subsurface Scale"),
                v("Subsurface Anisotropy"),
            ) else {
                panic!()
            };
            // One anisotropy: the material's where its channels share one, else their mean,
            // within Cycles' [0, 0.9].
            let mean = m.g.iter().sum::<f64>() / 3.0;
            assert!((g - mean.clamp(0.0, 0.9)).abs() <= 1e-12, "{}", m.name);
            if m.g.iter().any(|x| (x - mean).abs() > 1e-12) {
                assert!(p.notes.iter().any(|n| n.contains("averaged")), "{}", m.name);
            }
            for c in 0..3 {
                // Cycles scales Radius × Scale by 1/(4π) before the walk sees it
                // (`bssrdf_setup_radius`): σt·(1 − g)·Radius·Scale = 4π, scale in metres.
                let st = m.sigma_a[c] + m.sigma_s[c];
                let four_pi = st * (1.0 - g) * radius[c] * scale * 100.0;
                assert!(
                    (four_pi / (4.0 * std::f64::consts::PI) - 1.0).abs() < 1e-12,
                    "{}",
                    m.name
                );
                // An albedo above what Cycles traces (Spectralon's 1): Base Color 1, said.
                if crate::cycles::alpha(1.0, g) < m.albedo(c) {
                    assert_eq!(color[c], 1.0, "{}", m.name);
                    assert!(
                        p.notes
                            .iter()
                            .any(|n| n.contains("above what Cycles traces")),
                        "{}",
                        m.name
                    );
                    continue;
                }
                // Scene units in metres: the radius in cm is × 100.
                let sigma_t = crate::cycles::sigma_t(radius[c] * scale * 100.0, g);
                let sigma_s = crate::cycles::alpha(color[c], g) * sigma_t;
                let sigma_a = sigma_t - sigma_s;
                let close = |got: f64, want: f64| (got - want).abs() <= 1e-6 * want.abs();
                assert!(
                    close(sigma_s, m.sigma_s[c]) && close(sigma_a, m.sigma_a[c]),
                    "{} channel {c}: σa {sigma_a} σs {sigma_s}, want {} {}",
                    m.name,
                    m.sigma_a[c],
                    m.sigma_s[c]
                );
            }
            assert!(p.notes[0].contains("Blender 4.0–5.0"));
        }
        // Outside Cycles' anisotropy range: the nearest end, said in a note.
        for (g, traced) in [(-0.3, 0.0), (0.95, 0.9)] {
            let m = mc::Material {
                g: [g; 3],
                ..materials[0].clone()
            };
            let p = random_walk_exact(&m);
            let v = p
                .fields
                .iter()
                .find(|f| f.name == "Subsurface Anisotropy")
                .unwrap();
            assert!(matches!(v.value, Value::Number(x) if x == traced));
            assert!(
                p.notes
                    .iter()
                    .any(|n| n.contains("clamps Subsurface Anisotropy"))
            );
        }
    }

    /// OpenPBR's fields invert back to the material's coefficients (the spec's mapping).
    #[test]
    fn openpbr_round_trips_the_coefficients() {
        let m = mc::Material {
            name: "x".into(),
            source: String::new(),
            sigma_a: [0.32, 1.7, 4.8],
            sigma_s: [7.4, 8.8, 10.1],
            g: [0.0; 3],
            eta: 1.3,
            thickness: None,
        };
        let p = openpbr(&m);
        let v = |n: &str| p.fields.iter().find(|f| f.name == n).unwrap().value.clone();
        let (Value::Color(color), Value::Number(r), Value::Color(scale)) = (
            v("subsurface_color"),
            v("subsurface_radius"),
            v("subsurface_radius_scale"),
        ) else {
            panic!()
        };
        let (sa, ss) = mc::artist::Artist {
            color,
            radius: scale.map(|s| s * r),
        }
        .coefficients(m.g)
        .unwrap();
        for c in 0..3 {
            assert!((sa[c] / m.sigma_a[c] - 1.0).abs() < 1e-9);
            assert!((ss[c] / m.sigma_s[c] - 1.0).abs() < 1e-9);
        }
        let x = materialx(&p, "skin 1");
        assert!(
            x.contains("<open_pbr_surface name=\"SR_skin_1\"")
                && x.contains("subsurface_radius_scale")
        );
    }
}
