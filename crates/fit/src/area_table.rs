//! Area pre-integrated kernel tables (Maisch & Ropinski 2020, §3.2 eq. 5 and §7.1–7.2): the
//! average R′(r, A) = (1/A)∫_disc Rd(|x|) dx of a radial profile over a disc of area A whose
//! centre lies r from the profile's origin, so that a pixel's footprint, whatever its size,
//! receives the energy it really covers instead of a point sample's.
//!
//! Layout: `n_a` rows of areas by `n_r` columns of distances, at texel centres
//! r_i = (i + ½)·r_max/n_r and disc radii r_A,j = √(A_j/π) = (j + ½)·r_max/n_a, so A_max = π·r_max²
//! (the texel-centre convention of a GPU lookup; it also keeps away from the point sample A = 0,
//! where profiles like Burley's are infinite). Rows are uniform in the disc radius rather than in
//! A as in the paper: a pixel's footprint is usually far smaller than A_max, and rows uniform in A
//! would put all of them below the first texel. r_max is where the source term Q(r) = α′σt′e^{−σt′r} [cm⁻¹]
//! falls to a threshold (10⁻⁷ in the paper), the largest over the channels.
//!
//! The disc integral is written over circles about the origin: full circles up to
//! max(0, r_A − r), then arcs of angle 2·acos((ρ² − r_A² + r²)/(2rρ)) (their eq. 11). Unlike the
//! paper's trapezoid on fixed nodes (eq. 10), the arcs are integrated with Gauss–Legendre after
//! ρ = m − h·cos θ, which removes the square-root behaviour of the arc length at both ends.

use rayon::prelude::*;

use crate::analytic::Medium;

/// A radial profile tabulated finely as f(ρ) = ρ·Rd(ρ) [cm⁻¹] (finite even where Rd ~ 1/ρ), with
/// its running integral F(ρ) = ∫₀^ρ f. Nodes lie at ρ_k = extent·(k/(N−1))², dense near the
/// origin where profiles peak (single scattering rises like 1/ρ within a fraction of a free path).
#[derive(Clone, Debug)]
pub struct RadialTable {
    extent: f64,
    f: Vec<f64>,
    cumulative: Vec<f64>,
}

impl RadialTable {
    /// Nodes of the fine table.
    pub const NODES: usize = 1 << 15;

    /// Tabulates `rd` (Rd [cm⁻²] at ρ [cm]) on [0, `extent`].
    pub fn new(rd: &(dyn Fn(f64) -> f64 + Sync), extent: f64) -> Self {
        let n = Self::NODES;
        let rho = |k: usize| extent * (k as f64 / (n - 1) as f64).powi(2);
        let f: Vec<f64> = (0..n)
            .into_par_iter()
            .map(|k| {
                let x = if k == 0 { 1e-6 * rho(1) } else { rho(k) };
                x * rd(x)
            })
            .collect();
        let mut cumulative = vec![0.0; n];
        for k in 1..n {
            cumulative[k] = cumulative[k - 1] + 0.5 * (rho(k) - rho(k - 1)) * (f[k - 1] + f[k]);
        }
        RadialTable {
            extent,
            f,
            cumulative,
        }
    }

    /// Linear interpolation in u = √(ρ/extent), the coordinate in which nodes are uniform.
    fn interp(&self, v: &[f64], rho: f64) -> f64 {
        let x = (rho / self.extent).max(0.0).sqrt() * (v.len() - 1) as f64;
        let k = (x.floor() as usize).min(v.len() - 2);
        let t = (x - k as f64).min(1.0);
        v[k] + t * (v[k + 1] - v[k])
    }

    /// ρ·Rd(ρ), interpolated.
    pub fn f(&self, rho: f64) -> f64 {
        self.interp(&self.f, rho)
    }

    /// Rd(ρ) = f(ρ)/ρ; at ρ = 0 the value of the first node (10⁻⁶ of the first spacing out).
    pub fn rd(&self, rho: f64) -> f64 {
        let first = 1e-6 * self.extent / ((self.f.len() - 1) as f64).powi(2);
        if rho <= first {
            self.f[0] / first
        } else {
            self.f(rho) / rho
        }
    }

    /// ∫₀^ρ f, the energy within radius ρ divided by 2π.
    pub fn cumulative(&self, rho: f64) -> f64 {
        self.interp(&self.cumulative, rho)
    }

    /// The average of Rd over the disc of radius `r_a` [cm] centred `r` [cm] from the origin
    /// [cm⁻²]; the point value when `r_a` is 0.
    pub fn disc_average(&self, r: f64, r_a: f64) -> f64 {
        if r_a <= 0.0 {
            return self.f(r) / r;
        }
        let full = 2.0 * std::f64::consts::PI * self.cumulative((r_a - r).max(0.0));
        let (lo, hi) = ((r - r_a).abs(), r + r_a);
        let arcs = if r > 0.0 && hi > lo {
            let (m, half) = (0.5 * (lo + hi), 0.5 * (hi - lo));
            let panels = 2 + (12.0 * half / r_a.min(r)).sqrt().ceil() as usize;
            let panels = panels.min(48);
            let width = std::f64::consts::PI / panels as f64;
            let mut sum = 0.0;
            for p in 0..panels {
                let t0 = p as f64 * width;
                for &(x, w) in gl16() {
                    let theta = t0 + 0.5 * width * (x + 1.0);
                    let rho = m - half * theta.cos();
                    let c = ((rho * rho - r_a * r_a + r * r) / (2.0 * r * rho)).clamp(-1.0, 1.0);
                    sum += 0.5 * width * w * 2.0 * c.acos() * self.f(rho) * half * theta.sin();
                }
            }
            sum
        } else {
            0.0
        };
        (full + arcs) / (std::f64::consts::PI * r_a * r_a)
    }
}

fn gl16() -> &'static [(f64, f64)] {
    static RULE: std::sync::OnceLock<Vec<(f64, f64)>> = std::sync::OnceLock::new();
    RULE.get_or_init(|| {
        gauss_quad::legendre::GaussLegendre::new(16.try_into().expect("16 > 0"))
            .as_node_weight_pairs()
            .to_vec()
    })
}

/// A material's table extent: the largest [`cutoff_radius`] of its three channels [cm] (0 when
/// no channel's source term reaches `q_min`).
pub fn r_max(media: &[Medium; 3], q_min: f64) -> f64 {
    media
        .iter()
        .map(|m| cutoff_radius(m, q_min))
        .fold(0.0, f64::max)
}

/// The zoom effect the table removes, per channel: at 24 pixel pitches [cm] spaced
/// geometrically from a tenth of the shortest transport mean free path of `media` to r_max/8,
/// the energy a screen-space gather collects point-sampled and area pre-integrated
/// ([`gathered_energy`]): `(pitch, point, area)`.
pub fn zoom_effect(
    table: &AreaTable,
    rd: [&(dyn Fn(f64) -> f64 + Sync); 3],
    media: &[Medium; 3],
) -> [Vec<(f64, f64, f64)>; 3] {
    let l_min = media
        .iter()
        .map(|m| m.transport_mfp())
        .fold(f64::INFINITY, f64::min);
    let (p0, p1) = (0.1 * l_min, table.r_max / 8.0);
    [0, 1, 2].map(|c| {
        let radial = RadialTable::new(rd[c], table.r_max);
        (0..24)
            .map(|k| {
                let pitch = p0 * (p1 / p0).powf(k as f64 / 23.0);
                let (point, area) = gathered_energy(table, &radial, c, pitch);
                (pitch, point, area)
            })
            .collect()
    })
}

/// Where the source term α′σt′e^{−σt′r} [cm⁻¹] falls to `q_min` [cm⁻¹] (0 if it starts below).
pub fn cutoff_radius(m: &Medium, q_min: f64) -> f64 {
    let st = m.sigma_t_reduced();
    let q0 = m.albedo_reduced() * st;
    if q0 <= q_min {
        0.0
    } else {
        (q0 / q_min).ln() / st
    }
}

/// An RGB table of R′(r, A) [cm⁻²].
#[derive(Clone, Debug)]
pub struct AreaTable {
    /// Texels along r.
    pub n_r: usize,
    /// Texels along A.
    pub n_a: usize,
    /// Largest distance [cm]; the largest area is π·r_max².
    pub r_max: f64,
    /// R′ per channel, row-major: index j·n_r + i for area A_j and distance r_i.
    pub values: [Vec<f64>; 3],
    /// Per channel, the profile's energy within r_max, 2π∫₀^{r_max} r·Rd(r) dr [1] (its total
    /// diffuse reflectance there): what a gather divides by to make the weights sum to one.
    pub energy: [f64; 3],
}

impl AreaTable {
    /// Distance of column i [cm].
    pub fn r_at(&self, i: usize) -> f64 {
        (i as f64 + 0.5) * self.r_max / self.n_r as f64
    }

    /// Disc radius of row j [cm].
    pub fn disc_radius_at(&self, j: usize) -> f64 {
        (j as f64 + 0.5) * self.r_max / self.n_a as f64
    }

    /// Area of row j [cm²].
    pub fn area_at(&self, j: usize) -> f64 {
        std::f64::consts::PI * self.disc_radius_at(j).powi(2)
    }

    /// The largest area π·r_max² [cm²].
    pub fn a_max(&self) -> f64 {
        std::f64::consts::PI * self.r_max * self.r_max
    }

    /// Builds the table from one radial profile per channel (Rd [cm⁻²] at r [cm]).
    pub fn build(
        rd: [&(dyn Fn(f64) -> f64 + Sync); 3],
        r_max: f64,
        n_r: usize,
        n_a: usize,
    ) -> AreaTable {
        let mut t = AreaTable {
            n_r,
            n_a,
            r_max,
            values: Default::default(),
            energy: [0.0; 3],
        };
        for c in 0..3 {
            // A disc reaches out to r + r_A ≤ 2·r_max.
            let radial = RadialTable::new(rd[c], 2.0 * r_max);
            t.energy[c] = std::f64::consts::TAU * radial.cumulative(r_max);
            t.values[c] = (0..n_a * n_r)
                .into_par_iter()
                .map(|k| {
                    let (j, i) = (k / n_r, k % n_r);
                    radial.disc_average(t.r_at(i), t.disc_radius_at(j))
                })
                .collect();
        }
        t
    }

    /// The texels as a GPU uploads them: little-endian f32, RGB interleaved, row-major (row j =
    /// disc radius, column i = distance).
    pub fn f32_bytes(&self) -> Vec<u8> {
        (0..self.n_a * self.n_r)
            .flat_map(|k| {
                self.values
                    .iter()
                    .flat_map(move |v| (v[k] as f32).to_le_bytes())
            })
            .collect()
    }

    /// The header that describes [`AreaTable::f32_bytes`]: layout, units, extent, the profile's
    /// `source` and the zoom effect `curves` ([`zoom_effect`]) per channel.
    pub fn header(
        &self,
        material: &str,
        source: &str,
        q_min: f64,
        curves: &[Vec<(f64, f64, f64)>],
    ) -> serde_json::Value {
        use serde_json::json;
        let effect: serde_json::Map<String, serde_json::Value> = curves
            .iter()
            .enumerate()
            .map(|(c, v)| {
                let points = v.iter().map(|&(p, point, area)| {
                    json!({"pitch_cm": p, "point_sampled": point, "area_preintegrated": area})
                });
                (
                    mc::CHANNELS[c].to_string(),
                    json!(points.collect::<Vec<_>>()),
                )
            })
            .collect();
        json!({
            "material": material, "source": source, "unit": "1/cm^2",
            "layout": "little-endian f32, RGB interleaved, row-major: row j = disc radius r_A = (j+0.5)*r_max/rows, column i = distance r = (i+0.5)*r_max/columns",
            "columns": self.n_r, "rows": self.n_a, "r_max_cm": self.r_max, "a_max_cm2": self.a_max(),
            "q_min_per_cm": q_min, "zoom_effect": effect,
        })
    }

    /// Bilinear lookup of channel `c` at distance `r` [cm] and area `a` [cm²], clamped to the
    /// texel centres as a GPU sampler with clamp-to-edge does.
    pub fn lookup(&self, c: usize, r: f64, a: f64) -> f64 {
        let coord = |v: f64, max: f64, n: usize| {
            let x = (v / max * n as f64 - 0.5).clamp(0.0, (n - 1) as f64);
            let k = (x.floor() as usize).min(n.saturating_sub(2));
            (k, x - k as f64)
        };
        let (i, ti) = coord(r, self.r_max, self.n_r);
        let (j, tj) = coord((a / std::f64::consts::PI).sqrt(), self.r_max, self.n_a);
        let v = &self.values[c];
        let at = |j: usize, i: usize| v[j.min(self.n_a - 1) * self.n_r + i.min(self.n_r - 1)];
        let row = |j: usize| at(j, i) * (1.0 - ti) + at(j, i + 1) * ti;
        row(j) * (1.0 - tj) + row(j + 1) * tj
    }
}

/// The energy a square pixel grid of pitch `pitch` [cm] gathers from channel `c` of a beam's
/// profile (`radial`, tabulated to at least r_max), relative to the profile's energy within
/// r_max: `(point, area)`. As in a screen-space gather, the kernel's centre sits on a pixel
/// centre and every pixel centre is a sample: `point` weighs each pixel by Rd at its centre,
/// `area` by R′ for the pixel's area. Pixels whose centre lies beyond r_max are left out of both.
pub fn gathered_energy(
    table: &AreaTable,
    radial: &RadialTable,
    c: usize,
    pitch: f64,
) -> (f64, f64) {
    let total = std::f64::consts::TAU * radial.cumulative(table.r_max);
    let n = (table.r_max / pitch).ceil() as i64;
    let area = pitch * pitch;
    let (point, pre): (f64, f64) = (-n..=n)
        .into_par_iter()
        .map(|i| {
            let (mut p, mut q) = (0.0, 0.0);
            for j in -n..=n {
                let (x, y) = (i as f64 * pitch, j as f64 * pitch);
                let r = (x * x + y * y).sqrt();
                if r <= table.r_max {
                    p += radial.rd(r) * area;
                    q += table.lookup(c, r, area) * area;
                }
            }
            (p, q)
        })
        .reduce(|| (0.0, 0.0), |a, b| (a.0 + b.0, a.1 + b.1));
    (point / total, pre / total)
}
