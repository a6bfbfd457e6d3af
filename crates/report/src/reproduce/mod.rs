//! The thesis's tables and figures regenerated (`sss reproduce`), as a typed [`Report`]: each of
//! our numbers beside the published one (`configs/thesis_published.toml`), the thesis's
//! qualitative claims checked on both ([`Claim`]), and the report page rendered from the fields
//! ([`Report::html`]). Table 6.2–6.3, 6.5 and 5.1 come from [`fit::evaluate`] ([`tables`]),
//! Fig. 5.15 and 5.17 from [`fit::imitation`] and [`fit::WSweep`] ([`chapter5`]); the
//! rendered Tables 6.4–6.5 ([`RenderedTables`]) are measured by the `gpu` crate, and the
//! comparisons against Mitsuba 3 ([`MitsubaImages`]) are read from `scripts/references`.

mod chapter5;
mod html;
mod tables;

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use fit::KernelModel;

pub use chapter5::{
    Chapter5, Fig515, Fig515Model, Fig517, KSpread, MATERIAL as CHAPTER5_MATERIAL, chapter5,
};
pub use tables::{MaterialRow, Table51Row, Table63Model, Table63Row, Table65, Tables, tables};

/// The five materials of the thesis's main results (Tables 6.3 and 6.5, Fig. 6.2–6.10).
pub const MAIN: [&str; 5] = ["apple", "marble", "ketchup", "skin1", "wholemilk"];

/// One of the thesis's claims, checked on our numbers and on the published ones.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Claim {
    /// The claim, prefixed by the table or figure it is about.
    pub claim: String,
    /// What our numbers show.
    pub ours: String,
    /// What the published numbers show.
    pub published: String,
    /// Whether the claim holds on ours.
    pub holds: bool,
    /// Why it should hold, or why ours differ.
    pub why: String,
}

impl Claim {
    fn new(claim: &str, ours: String, published: String, holds: bool, why: &str) -> Claim {
        Claim {
            claim: claim.into(),
            ours,
            published,
            holds,
            why: why.into(),
        }
    }
}

/// The published numbers of Freude 2014 that the report sets beside ours (Tables 6.3–6.5, per
/// channel R, G, B, normalized as the thesis does: the highest entry of a table is 1).
#[derive(Clone, Debug, PartialEq, Deserialize)]
pub struct Published {
    /// Table 6.3 (kernel-space RMS of the rank-1 models) per material.
    pub table_6_3: BTreeMap<String, PublishedRank1>,
    /// Table 6.4 (image RMS of rendered cut-outs) per thesis scene.
    pub table_6_4: BTreeMap<String, PublishedRank1>,
    /// Table 6.5 (image RMS on the Head with Skin1).
    pub table_6_5: Published65,
}

/// One row of Table 6.3 or 6.4: the four rank-1 models, per channel R, G, B.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
pub struct PublishedRank1 {
    /// SVD rank-1.
    pub svd1: [f64; 3],
    /// Kernel pre-integration.
    pub preint: [f64; 3],
    /// Guided optimization, k = 1.
    pub guided_k1: [f64; 3],
    /// The manual two-Gaussian model.
    pub manual: [f64; 3],
}

impl PublishedRank1 {
    /// The rows in the order of [`fit::evaluate::RANK1`].
    pub fn rows(&self) -> [[f64; 3]; 4] {
        [self.svd1, self.preint, self.guided_k1, self.manual]
    }
}

/// The published Table 6.5: rows N = 1…6, per channel R, G, B.
#[derive(Clone, Debug, PartialEq, Deserialize)]
pub struct Published65 {
    /// SVD rank-N.
    pub svd: Vec<[f64; 3]>,
    /// d'Eon's sum of N Gaussians.
    pub deon: Vec<[f64; 3]>,
}

impl Published {
    /// The thesis's numbers (compiled in; their shape is checked by this module's tests).
    pub fn thesis() -> Published {
        toml::from_str(include_str!("../../../../configs/thesis_published.toml"))
            .expect("configs/thesis_published.toml parses (tested)")
    }
}

/// Tables 6.4 and 6.5 rendered on our scenes, or why they were not.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "status", rename_all = "lowercase")]
pub enum RenderedTables {
    /// Not rendered (no GPU adapter).
    Skipped {
        /// Why.
        reason: String,
    },
    /// Rendered.
    Rendered(Box<Rendered>),
}

/// The rendered tables' numbers (the `gpu` crate measures them).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Rendered {
    /// The adapter that rendered them.
    pub adapter: String,
    /// Image width [px].
    pub width: u32,
    /// Image height [px].
    pub height: u32,
    /// Taps per pass.
    pub taps: usize,
    /// Wall time of the whole measurement [s].
    pub seconds: f64,
    /// Table 6.4's models, in column order.
    pub models: Vec<ModelName>,
    /// Table 6.4: one row per scene.
    pub table_6_4: Vec<Rendered64Row>,
    /// Table 6.5 rendered on the first scene.
    pub table_6_5: Rendered65,
    /// The claims these tables check.
    #[serde(skip)]
    pub claims: Vec<Claim>,
}

/// A model with its title, as the report names it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ModelName {
    /// The model.
    pub model: KernelModel,
    /// Its title (`KernelModel::title`).
    pub name: String,
}

impl From<KernelModel> for ModelName {
    fn from(model: KernelModel) -> ModelName {
        ModelName {
            model,
            name: model.title(),
        }
    }
}

/// One scene of the rendered Table 6.4.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Rendered64Row {
    /// Our scene.
    pub scene: String,
    /// The material rendered.
    pub material: String,
    /// The thesis's scene rendered with that material.
    pub thesis_scene: String,
    /// The comparison's kernel scale [cm per pixel].
    pub cm_per_px: f64,
    /// Image RMS per model (the table's columns) and channel, relative to the truth's mean.
    pub raw: Vec<[f64; 3]>,
    /// `raw` over the table's highest per-channel entry.
    pub normalized: Vec<[f64; 3]>,
    /// The thesis's values for its scene.
    pub published: Vec<[f64; 3]>,
    /// No scattering at all, raw.
    pub lambert_raw: [f64; 3],
    /// No scattering at all, normalized as the table.
    pub lambert: [f64; 3],
}

/// Table 6.5 rendered: SVD rank-N against d'Eon's N Gaussians on one scene.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Rendered65 {
    /// The scene.
    pub scene: String,
    /// The material.
    pub material: String,
    /// The N of each row.
    pub n: Vec<usize>,
    /// The rows, ours (image RMS of the rendered scene) beside the thesis's (Head, Skin1).
    #[serde(flatten)]
    pub rows: Table65,
}

/// One scene and material compared against Mitsuba 3, as `scripts/references/images.py` writes
/// it (`images.json`, or an entry of `run.py`'s `summary.json`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MitsubaImages {
    /// The scene.
    #[serde(default = "default_scene")]
    pub scene: String,
    /// The material.
    #[serde(default = "default_material")]
    pub material: String,
    /// Image width [px].
    pub width: u32,
    /// Image height [px].
    pub height: u32,
    /// Mitsuba's samples per pixel.
    pub spp: u32,
    /// The reference's noise on 2×2 blocks, relative to its mean.
    pub reference_noise_rel: f64,
    /// Silhouette blocks excluded, as a fraction of the lit blocks.
    pub silhouette_fraction: f64,
    /// Whether the calibration passed (absent: no calibration).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub calibration_pass: Option<bool>,
    /// The calibration's noise-corrected RMSE, relative.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub calibration_rmse_rel: Option<f64>,
    /// Its standard error.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub calibration_rmse_se: Option<f64>,
    /// The calibration's energy ratio per channel.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub calibration_energy_ratio: Option<[f64; 3]>,
    /// The deliberately wrong render (albedo × 0.8).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub negative_control: Option<NegativeControl>,
    /// Each model's errors.
    pub models: Vec<MitsubaModel>,
    /// Paired rankings: Some(true/false) when resolved at 3 standard errors, None undecided.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub rankings: BTreeMap<String, Option<bool>>,
    /// Where the image error comes from (absent: a scene without both surface gathers).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error_budget: Option<ErrorBudget>,
    /// Every other field `images.py` wrote, kept as it was.
    #[serde(flatten)]
    pub extra: serde_json::Map<String, serde_json::Value>,
}

fn default_scene() -> String {
    "sphere".into()
}

fn default_material() -> String {
    "skin1".into()
}

/// The negative control of a Mitsuba comparison.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct NegativeControl {
    /// Whether the calibration test rejected it, as it must.
    pub rejected: bool,
    /// Every other field, kept as it was.
    #[serde(flatten)]
    pub extra: serde_json::Map<String, serde_json::Value>,
}

/// `images.py`'s error budget of one scene: each term's noise-corrected RMSE against Mitsuba's
/// reference without light between surfaces (relative to that reference's mean), and the light
/// between surfaces on its own.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ErrorBudget {
    /// The reference the terms are measured against.
    pub reference: String,
    /// The screen-space method closest to it.
    pub best_realtime: String,
    /// That method against the full reference (with light between surfaces).
    pub best_realtime_full_reference: BudgetError,
    /// The terms.
    pub terms: BudgetTerms,
    /// For opaque Lambertian surfaces of the same albedo, all bounces over direct light − 1, per
    /// channel: what self-interreflection (and, with several shapes, light between them) is worth.
    pub self_interreflection_lambert: [f64; 3],
    /// Every other field, kept as it was.
    #[serde(flatten)]
    pub extra: serde_json::Map<String, serde_json::Value>,
}

/// A noise-corrected RMSE with its standard error (relative).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct BudgetError {
    /// Noise-corrected RMSE.
    pub rmse_noise_corrected: f64,
    /// Its standard error.
    pub rmse_noise_corrected_se: f64,
}

/// One term of the budget.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BudgetTerm {
    /// Noise-corrected RMSE.
    pub rmse_noise_corrected: f64,
    /// Its standard error.
    pub rmse_noise_corrected_se: f64,
    /// Whether it lies more than 3 standard errors above 0.
    pub resolved: bool,
    /// Energy ratio per channel, the first image over the second.
    pub energy_ratio: [f64; 3],
}

/// The budget's terms (issue 30).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BudgetTerms {
    /// The best screen-space method against the reference.
    pub best_realtime: BudgetTerm,
    /// The radial Monte Carlo gather against the reference.
    pub radial: BudgetTerm,
    /// The directional Monte Carlo gather against the reference: what a half-space BSSRDF cannot
    /// represent.
    pub directional: BudgetTerm,
    /// The real-time method with the radial gather's tables against it: the screen-space part.
    pub screen_space: BudgetTerm,
    /// The radial gather against the directional one: what the entry direction adds.
    pub entry_direction: BudgetTerm,
    /// The real-time method with the entry shift against the directional gather: what it loses
    /// against the exact half-space BSSRDF (absent without such a model).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shifted_screen_space: Option<BudgetTerm>,
    /// The shape-aware Monte Carlo gather against the reference (issue 47; absent without it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shape_aware: Option<BudgetTerm>,
    /// The directional gather against the shape-aware one: what the body's curvature changes
    /// (absent without it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shape: Option<BudgetTerm>,
    /// The full reference against the one without light between surfaces.
    pub between_surfaces: BudgetTerm,
}

impl BudgetTerms {
    /// The terms with their names as `images.json` and the page give them.
    pub fn named(&self) -> Vec<(&'static str, &BudgetTerm)> {
        let mut terms = vec![
            ("best real-time ↔ reference", &self.best_realtime),
            ("radial Monte Carlo gather ↔ reference", &self.radial),
            (
                "directional Monte Carlo gather ↔ reference (what a half-space BSSRDF cannot represent)",
                &self.directional,
            ),
            (
                "screen-space part: real-time with the gather's tables ↔ radial gather",
                &self.screen_space,
            ),
            (
                "entry direction: radial ↔ directional gather",
                &self.entry_direction,
            ),
        ];
        if let Some(t) = &self.shifted_screen_space {
            terms.push((
                "entry-shifted real-time ↔ directional gather (what the shift misses of it)",
                t,
            ));
        }
        if let Some(t) = &self.shape_aware {
            terms.push(("shape-aware Monte Carlo gather ↔ reference", t));
        }
        if let Some(t) = &self.shape {
            terms.push(("shape: directional ↔ shape-aware gather", t));
        }
        terms.push((
            "light between surfaces: full reference ↔ reference",
            &self.between_surfaces,
        ));
        terms
    }
}

/// One model's errors against Mitsuba, relative to the reference's mean.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MitsubaModel {
    /// The model, as `images.py` names it.
    pub model: String,
    /// Raw RMSE.
    pub rmse_rel: f64,
    /// Noise-corrected RMSE: √(MSE − var(reference)).
    pub rmse_noise_corrected: f64,
    /// Its standard error.
    pub rmse_noise_corrected_se: f64,
    /// What remains once each channel is scaled by its best global factor.
    pub rmse_spatial: f64,
    /// SSIM.
    pub ssim: f64,
    /// Energy ratio per channel, ours over Mitsuba's.
    pub energy_ratio: [f64; 3],
    /// Every other field, kept as it was.
    #[serde(flatten)]
    pub extra: serde_json::Map<String, serde_json::Value>,
}

impl MitsubaImages {
    /// The comparisons in a JSON text: `images.py`'s one, or every entry of `run.py`'s summary
    /// (its `images` list). Fields the page shows are required (scene and material default to
    /// the sphere and Skin1); every other field is kept. The error names the entry and what is
    /// missing.
    pub fn parse(text: &str) -> std::result::Result<Vec<MitsubaImages>, String> {
        let v: serde_json::Value = serde_json::from_str(text).map_err(|e| e.to_string())?;
        let list = match v.get("images") {
            Some(serde_json::Value::Array(images)) => images.clone(),
            Some(_) => return Err("\"images\" is not a list".into()),
            None => vec![v],
        };
        list.into_iter()
            .enumerate()
            .map(|(i, entry)| {
                serde_json::from_value(entry).map_err(|e| {
                    format!(
                        "entry {}: {e} (expected images.py's images.json or run.py's summary.json; rerun images.py)",
                        i + 1
                    )
                })
            })
            .collect()
    }
}

/// The whole reproduction: what `report.json` holds and `index.html` shows.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Report {
    /// `quick` (CI size) or `full` (thesis settings).
    pub mode: String,
    /// Photons per channel behind every profile (None: unknown or differing).
    pub photons_per_channel: Option<u64>,
    /// Time to simulate or read the library [s].
    pub simulate_seconds: f64,
    /// Tables 6.2, 6.3, 6.5 and 5.1.
    #[serde(flatten)]
    pub tables: Tables,
    /// Every claim: the tables', the rendered tables', then chapter 5's.
    pub claims: Vec<Claim>,
    /// Fig. 5.15.
    pub fig_5_15: Fig515,
    /// Fig. 5.17.
    pub fig_5_17: Fig517,
    /// Tables 6.4 and 6.5 rendered.
    pub rendered_tables: RenderedTables,
    /// Comparisons against Mitsuba 3 (empty: none given).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub rendered: Vec<MitsubaImages>,
}

impl Report {
    /// Assembles the report; the claims are gathered from its parts in the page's order.
    pub fn new(
        quick: bool,
        photons_per_channel: Option<u64>,
        simulate_seconds: f64,
        tables: Tables,
        chapter5: &Chapter5,
        rendered_tables: RenderedTables,
        rendered: Vec<MitsubaImages>,
    ) -> Report {
        let mut claims = tables.claims.clone();
        if let RenderedTables::Rendered(r) = &rendered_tables {
            claims.extend(r.claims.iter().cloned());
        }
        claims.extend(chapter5.claims.iter().cloned());
        Report {
            mode: if quick { "quick" } else { "full" }.into(),
            photons_per_channel,
            simulate_seconds,
            tables,
            claims,
            fig_5_15: chapter5.fig_5_15.clone(),
            fig_5_17: chapter5.fig_5_17.clone(),
            rendered_tables,
            rendered,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The published rows are read in the order of `RANK1`: SVD rank-1, pre-integration,
    /// guided k = 1, manual.
    #[test]
    fn published_rows_follow_rank1() {
        use fit::evaluate::RANK1;
        assert!(matches!(
            RANK1,
            [
                KernelModel::Svd {
                    rank: 1,
                    renormalize: false
                },
                KernelModel::Preint,
                KernelModel::Guided { k: 1.0, b: 0.0 },
                KernelModel::Manual(_)
            ]
        ));
        let p = PublishedRank1 {
            svd1: [1.0; 3],
            preint: [2.0; 3],
            guided_k1: [3.0; 3],
            manual: [4.0; 3],
        };
        assert_eq!(p.rows().map(|r| r[0]), [1.0, 2.0, 3.0, 4.0]);
    }

    /// The published tables have every main material, the six thesis scenes and N = 1…6.
    #[test]
    fn published_tables_are_complete() {
        let p = Published::thesis();
        for m in MAIN {
            assert!(p.table_6_3.contains_key(m), "{m}");
        }
        assert_eq!(p.table_6_4.len(), 6);
        assert_eq!((p.table_6_5.svd.len(), p.table_6_5.deon.len()), (6, 6));
    }

    /// A references file must carry what the page shows; `run.py`'s summary gives each entry.
    #[test]
    fn mitsuba_comparisons_parse_or_say_what_is_missing() {
        let one = r#"{"width": 192, "height": 108, "spp": 128, "reference_noise_rel": 0.06,
            "silhouette_fraction": 0.04, "models": [{"model": "preint", "rmse_rel": 0.2,
            "rmse_noise_corrected": 0.18, "rmse_noise_corrected_se": 0.003, "rmse_spatial": 0.13,
            "ssim": 0.95, "energy_ratio": [0.9, 0.86, 0.84]}],
            "rankings": {"a closer than b": null}}"#;
        let v = MitsubaImages::parse(one).unwrap();
        assert_eq!(
            (v[0].scene.as_str(), v[0].material.as_str()),
            ("sphere", "skin1")
        );
        assert_eq!(v[0].rankings["a closer than b"], None);
        let summary = format!(r#"{{"failed": [], "images": [{one}, {one}]}}"#);
        assert_eq!(MitsubaImages::parse(&summary).unwrap().len(), 2);
        let e = MitsubaImages::parse(r#"{"models": [{"model": "x"}]}"#).unwrap_err();
        assert!(e.contains("entry 1") && e.contains("missing field"), "{e}");
        // Fields the page does not show survive a round trip; absent options stay absent.
        let with_extra = one.replacen("{", r#"{"checks": 13, "#, 1);
        let v = &MitsubaImages::parse(&with_extra).unwrap()[0];
        let back = serde_json::to_value(v).unwrap();
        assert_eq!(back["checks"], 13);
        assert!(back.get("calibration_pass").is_none());
        assert!(back.get("error_budget").is_none());
        // An error budget is typed: a term without its standard error names the field.
        let term = r#"{"rmse_noise_corrected": 0.06, "rmse_noise_corrected_se": 0.002, "resolved": true, "energy_ratio": [1, 1, 1]}"#;
        let budget = format!(
            r#"{{"reference": "Mitsuba", "best_realtime": "preint", "best_realtime_full_reference": {{"rmse_noise_corrected": 0.07, "rmse_noise_corrected_se": 0.002}}, "self_interreflection_lambert": [0, 0, 0], "terms": {{"best_realtime": {term}, "radial": {term}, "directional": {term}, "screen_space": {term}, "entry_direction": {term}, "between_surfaces": {term}}}}}"#
        );
        let with_budget = one.replacen("{", &format!(r#"{{"error_budget": {budget}, "#), 1);
        let v = &MitsubaImages::parse(&with_budget).unwrap()[0];
        let b = v.error_budget.as_ref().unwrap();
        assert_eq!(b.best_realtime, "preint");
        assert!(b.terms.named().iter().all(|(_, t)| t.resolved));
        // The entry-shifted method's term is shown where images.py wrote it.
        assert_eq!(b.terms.named().len(), 6);
        let shifted = with_budget.replacen(
            r#""between_surfaces""#,
            &format!(r#""shifted_screen_space": {term}, "between_surfaces""#),
            1,
        );
        let v = &MitsubaImages::parse(&shifted).unwrap()[0];
        assert_eq!(v.error_budget.as_ref().unwrap().terms.named().len(), 7);
        // And the shape terms (issue 47).
        let shaped = shifted.replacen(
            r#""between_surfaces""#,
            &format!(r#""shape_aware": {term}, "shape": {term}, "between_surfaces""#),
            1,
        );
        let v = &MitsubaImages::parse(&shaped).unwrap()[0];
        assert_eq!(v.error_budget.as_ref().unwrap().terms.named().len(), 9);
        let broken = with_budget.replacen(
            r#""rmse_noise_corrected_se": 0.002, "resolved""#,
            r#""resolved""#,
            1,
        );
        let e = MitsubaImages::parse(&broken).unwrap_err();
        assert!(e.contains("rmse_noise_corrected_se"), "{e}");
    }
}
