//! Monte Carlo profile tables: the diffuse reflectance R̂(ρ; α) of a half-space at σt = 1, over a
//! grid of single-scattering albedos α, for one anisotropy g and one relative index η. Every
//! material of that g and η follows by the exact similarity of the transport equation (lengths
//! in mean free paths 1/σt):
//!
//! Rd(r; σa, σs) = σt²·R̂(σt·r; σs/σt),  σt = σa + σs.
//!
//! **What a table holds.** Per albedo, the cumulative reflectance P(ρ_k) — the fraction of the
//! incident power that leaves diffusely (specular reflection excluded, as MCML's `Rd_r`) within
//! ρ_k of the beam — and its per-photon second moment, at edges ρ_k that are the union of
//! [`LEVELS`] uniform grids: bin widths h_j = [`FIRST_WIDTH`]·4^j, edges k·h_j for k = 5…19
//! (1…19 on the first). One walk per albedo tallies all of them at once (a batch whose channels
//! are equal in mean free paths shares their walk, each channel on its own grid), so every edge's
//! P is an exact tally with its standard error; consecutive edges are 1.05–2× apart, from
//! ρ = 10⁻³ to 4980, and nothing is smoothed. The total diffuse reflectance Rd(α) (pbrt's ρ_eff)
//! comes with it.
//!
//! **Interpolation** ([`Table::at`]). In α: the cubic through the four nodes around α (Lagrange),
//! applied to P at every edge and to Rd. (Catmull–Rom, whose slopes are finite differences, was
//! measured to be biased: left-one-out it misses Rd by +0.6 to +3.7 % at α ≤ 0.6 where the cubic's
//! misses are within the noise.) Its error is estimated as |f − f₂|/15, f₂ the same
//! interpolation through every other node (a cubic's error falls as the fourth power of the
//! spacing). In ρ: conservative —
//! P is exact at the edges; within a bin the density follows e^{sρ}, s the slope of ln(density)
//! between the neighbouring bins (the exponential tail of diffusion), and the first bin
//! [0, 10⁻³) follows the single-scattering singularity Rd ∝ 1/ρ (P linear in ρ). An annulus
//! average is (P(b) − P(a))/(π(b² − a²)), with the table's standard error and the α-interpolation
//! error added in quadrature.
//!
//! **One walk for every albedo** ([`TableSpec::white`], the default of `sss table`): the largest
//! albedo's walk, each exit counted for every albedo α with its weight times (α/α_max)ⁿ after n
//! interactions (`white.rs`); the per-albedo build (one walk per albedo) stays as its
//! check. Both give the same accumulators per albedo, so shards, merging and files are shared.
//!
//! Tables are built from [`TableSpec::batch`] like any batch (sharded, merged, bit-identical for
//! any thread or shard count) and written as JSON ([`Table::to_json`], format [`FORMAT`]).

use serde::{Deserialize, Serialize};

use crate::batch::{BatchSpec, ChannelSpec, QUASI_INFINITE_MFP};
use crate::error::{McError, Result};
use crate::grid::Grid;
use crate::layer::Layer;
use crate::output::Estimate;
use crate::shard::{Shard, ShardFile};
use crate::tally::{Accumulator, TallySet};

/// Bin width of the finest radial grid [mean free paths].
pub const FIRST_WIDTH: f64 = 1.0e-3;
/// Uniform radial grids per albedo, each 4× coarser than the last.
pub const LEVELS: usize = 10;
/// Bins per grid; the last also collects everything beyond (MCML's convention).
const LEVEL_BINS: usize = 20;
/// The first edge of every grid but the finest, in bins (20 bins of the grid below = 5 of this).
const FIRST_EDGE: usize = 5;
/// Albedos of a default table (pbrt-v4's `BSSRDFTable` has 100).
pub const DEFAULT_ALBEDOS: usize = 100;
/// Largest albedo of a default table: at α = 1 a half-space walk has no finite mean length.
pub const DEFAULT_MAX_ALBEDO: f64 = 0.99999;
/// The format tag of table files.
pub const FORMAT: &str = "sss-table-1";

/// pbrt-v4's albedo spacing, (1 − e^{−8i/(n−1)})/(1 − e^{−8}), scaled to end at `max`: dense
/// towards α → 1, where profiles change fastest.
pub fn default_albedos(n: usize, max: f64) -> Vec<f64> {
    let last = n.saturating_sub(1).max(1) as f64;
    (0..n)
        .map(|i| max * (1.0 - (-8.0 * i as f64 / last).exp()) / (1.0 - (-8.0f64).exp()))
        .collect()
}

/// The grid of level `j` [mean free paths].
fn level_grid(j: usize) -> Grid {
    Grid {
        dr: FIRST_WIDTH * 4f64.powi(j as i32),
        dz: 1.0,
        nr: LEVEL_BINS,
        nz: 1,
        na: 1,
    }
}

/// Every edge as (level, bins below it on that level), increasing.
fn edge_sources() -> Vec<(usize, usize)> {
    (0..LEVELS)
        .flat_map(|j| {
            let first = if j == 0 { 1 } else { FIRST_EDGE };
            (first..LEVEL_BINS).map(move |k| (j, k))
        })
        .collect()
}

/// The table's radial edges ρ_k [mean free paths 1/σt], increasing.
pub fn radius_edges() -> Vec<f64> {
    edge_sources()
        .into_iter()
        .map(|(j, k)| k as f64 * level_grid(j).dr)
        .collect()
}

/// What to simulate for one table.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TableSpec {
    /// Henyey–Greenstein anisotropy [-].
    pub g: f64,
    /// Refractive index of the medium relative to the one above it [-].
    pub eta: f64,
    /// Single-scattering albedos σs/σt, strictly increasing in [0, 1).
    pub albedos: Vec<f64>,
    /// Photon packets per albedo.
    pub photons: u64,
    /// Seed of every random stream.
    pub seed: u64,
    /// Every albedo from one walk, the largest albedo's, reweighted by (α/α_max)ⁿ after n
    /// interactions (`white.rs`: "white" Monte Carlo); else one walk per albedo. Absent
    /// from files written before it: one walk per albedo.
    #[serde(default)]
    pub white: bool,
}

impl TableSpec {
    /// Checks g, η, the albedos and the photon count; errors name the field.
    pub fn validate(&self) -> Result<()> {
        if !(self.g.is_finite() && self.g > -1.0 && self.g < 1.0) {
            return Err(McError::invalid("g", self.g, "must lie in (-1, 1)"));
        }
        if !(self.eta.is_finite() && (0.1..=10.0).contains(&self.eta)) {
            return Err(McError::invalid("eta", self.eta, "must lie in [0.1, 10]"));
        }
        if self.albedos.len() < 8 {
            return Err(McError::invalid(
                "albedos",
                self.albedos.len(),
                "a table needs at least 8 albedos (cubic interpolation, and again through every other one for its error estimate)",
            ));
        }
        for (i, &a) in self.albedos.iter().enumerate() {
            if !(a.is_finite() && (0.0..1.0).contains(&a)) {
                return Err(McError::invalid(
                    format!("albedos[{i}]"),
                    a,
                    "must lie in [0, 1): at α = 1 a half-space walk has no finite mean length",
                ));
            }
            if i > 0 && a <= self.albedos[i - 1] {
                return Err(McError::invalid(
                    format!("albedos[{i}]"),
                    a,
                    "albedos must increase strictly",
                ));
            }
        }
        self.batch().validate()
    }

    /// One table per (g, η) of `gs` × `etas`, each with `albedos` albedos spaced as
    /// [`default_albedos`] up to `max_albedo`, all validated; errors name the field (`albedos`,
    /// `max_albedo`, `g`, `eta`, …) and the table.
    pub fn grid(
        gs: &[f64],
        etas: &[f64],
        (albedos, max_albedo): (usize, f64),
        photons: u64,
        seed: u64,
        white: bool,
    ) -> Result<Vec<TableSpec>> {
        if !(max_albedo > 0.0 && max_albedo < 1.0) {
            let reason = "must lie in (0, 1); at 1 a half-space walk has no finite mean length";
            return Err(McError::invalid("max_albedo", max_albedo, reason));
        }
        let albedos = default_albedos(albedos, max_albedo);
        let mut out: Vec<TableSpec> = Vec::new();
        for &g in gs {
            for &eta in etas {
                let s = TableSpec {
                    g,
                    eta,
                    albedos: albedos.clone(),
                    photons,
                    seed,
                    white,
                };
                s.validate()?;
                if out.iter().any(|o| o.g == g && o.eta == eta) {
                    let what = format!("g = {g}, η = {eta}");
                    return Err(McError::invalid("table", what, "is asked twice"));
                }
                out.push(s);
            }
        }
        Ok(out)
    }

    /// The batch that builds the table: per albedo (in order), [`LEVELS`] channels with the same
    /// layer (σt = 1 [cm⁻¹], so cm are mean free paths) and one radial grid each. Each albedo is
    /// one walk group, in albedo order.
    pub fn batch(&self) -> BatchSpec {
        let channels = self
            .albedos
            .iter()
            .flat_map(|&a| {
                let layer = Layer {
                    n: self.eta,
                    mu_a: 1.0 - a,
                    mu_s: a,
                    g: self.g,
                    thickness: QUASI_INFINITE_MFP,
                };
                (0..LEVELS).map(move |j| ChannelSpec {
                    layer,
                    grid: level_grid(j),
                })
            })
            .collect();
        BatchSpec {
            n_above: 1.0,
            n_below: 1.0,
            channels,
            photons: self.photons,
            seed: self.seed,
            tallies: TallySet {
                absorption_rz: false,
                absorption_rz_se: false,
                surface_xy: 0,
            },
        }
    }

    /// The table from the batch's group accumulators (one per albedo, as
    /// [`crate::accumulate_batch`] or [`crate::shard::merge`] return them).
    pub fn table(&self, accs: &[Accumulator]) -> Result<Table> {
        self.check_rows(accs.len())?;
        let sources = edge_sources();
        let mut rows = Vec::with_capacity(accs.len());
        for acc in accs {
            let l = acc.layout;
            if l.channels != LEVELS || l.nr != LEVEL_BINS || l.na != 1 {
                return Err(McError::invalid(
                    "accumulator layout",
                    format!("{} channels × {} bins", l.channels, l.nr),
                    "not a table's",
                ));
            }
            let n = acc.photons.max(1) as f64;
            // Exact sums of bins [0, k) of level j, then per photon.
            let below = |j: usize, k: usize| {
                let o = l.rd_ra(j);
                let s: i128 = acc.sum[o..o + k].iter().sum();
                let s2: i128 = acc.sum_sq[o..o + k].iter().sum();
                (fixed(s) / n, fixed(s2) / n)
            };
            let (rd, rd_sq) = below(0, LEVEL_BINS);
            // Each grid sums the same weights in its own order: at the 10⁻¹⁶ level, an edge of
            // one grid may read above the next grid's or above the total. Kept exactly monotone.
            let (mut p, mut q) = (Vec::new(), Vec::new());
            for &(j, k) in &sources {
                let (pk, qk) = below(j, k);
                let (pp, qp) = (
                    p.last().copied().unwrap_or(0.0),
                    q.last().copied().unwrap_or(0.0),
                );
                p.push(pk.clamp(pp, rd.max(pp)));
                q.push(qk.clamp(qp, rd_sq.max(qp)));
            }
            rows.push(Row { p, q, rd, rd_sq });
        }
        Ok(self.assemble(rows, None))
    }

    /// The table from exact sums per albedo over the radial intervals of [`radius_edges`] (one
    /// more than the edges: [0, ρ₀), [ρ₀, ρ₁), …, [ρ_last, ∞)), as a tracer that bins each exit
    /// once returns them (the GPU's); `tracer` names it in the table ([`Table::tracer`]).
    pub fn table_from_intervals(&self, rows: &[IntervalSums], tracer: &str) -> Result<Table> {
        self.check_rows(rows.len())?;
        let intervals = radius_edges().len() + 1;
        let mut out = Vec::with_capacity(rows.len());
        for r in rows {
            if r.sum.len() != intervals || r.sum_sq.len() != intervals {
                return Err(McError::invalid(
                    "interval sums",
                    format!("{} and {}", r.sum.len(), r.sum_sq.len()),
                    "a table needs one per radial interval (radius_edges() + 1)",
                ));
            }
            let n = r.photons.max(1) as f64;
            // Exact prefix sums of non-negative integers: monotone without clamping.
            let prefix = |v: &[i128]| -> Vec<f64> {
                v.iter()
                    .scan(0i128, |acc, &x| {
                        *acc += x;
                        Some(fixed(*acc) / n)
                    })
                    .collect()
            };
            let (mut p, mut q) = (prefix(&r.sum), prefix(&r.sum_sq));
            let (rd, rd_sq) = (p.pop().unwrap_or(0.0), q.pop().unwrap_or(0.0));
            out.push(Row { p, q, rd, rd_sq });
        }
        Ok(self.assemble(out, Some(tracer.to_string())))
    }

    fn check_rows(&self, rows: usize) -> Result<()> {
        if rows != self.albedos.len() {
            return Err(McError::invalid(
                "accumulators",
                rows,
                "one per albedo of the table is required",
            ));
        }
        Ok(())
    }

    fn assemble(&self, rows: Vec<Row>, tracer: Option<String>) -> Table {
        let mut t = Table {
            format: FORMAT.into(),
            g: self.g,
            eta: self.eta,
            photons: self.photons,
            seed: self.seed,
            white: self.white,
            tracer,
            rsp: crate::fresnel::specular(1.0, self.eta, None),
            albedo: self.albedos.clone(),
            radius: radius_edges(),
            cumulative: Vec::new(),
            cumulative_sq: Vec::new(),
            rd: Vec::new(),
            rd_sq: Vec::new(),
        };
        for r in rows {
            t.cumulative.push(r.p);
            t.cumulative_sq.push(r.q);
            t.rd.push(r.rd);
            t.rd_sq.push(r.rd_sq);
        }
        t
    }
}

/// How two builds of a table agree at one albedo node ([`Table::agreement`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NodeAgreement {
    /// Σ (a − b)²/(σa² + σb²) over the resolved rings.
    pub chi2: f64,
    /// The resolved rings.
    pub dof: usize,
    /// |Rd_a − Rd_b| in combined standard errors (0 if both are exact and equal).
    pub rd_z: f64,
}

/// One albedo's exact sums over a table's radial intervals ([`TableSpec::table_from_intervals`]),
/// in the host's fixed point (units of 2⁻⁶⁴ of a photon's weight, as [`Accumulator`]'s).
#[derive(Clone, Debug, PartialEq)]
pub struct IntervalSums {
    /// Σw per interval.
    pub sum: Vec<i128>,
    /// Σw² per interval (each photon leaves once: its squared weight).
    pub sum_sq: Vec<i128>,
    /// Photons traced.
    pub photons: u64,
}

/// One albedo of a table: cumulative reflectance and its second moment per edge, and totals.
struct Row {
    p: Vec<f64>,
    q: Vec<f64>,
    rd: f64,
    rd_sq: f64,
}

fn fixed(s: i128) -> f64 {
    s as f64 / 18_446_744_073_709_551_616.0
}

/// A built table (see the module documentation). Plain data, written as JSON.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Table {
    /// [`FORMAT`].
    pub format: String,
    /// Henyey–Greenstein anisotropy [-].
    pub g: f64,
    /// Relative refractive index of the medium [-].
    pub eta: f64,
    /// Photon packets per albedo.
    pub photons: u64,
    /// Seed of the run.
    pub seed: u64,
    /// Whether every albedo came from one walk ([`TableSpec::white`]); absent from tables
    /// written before: one walk per albedo.
    #[serde(default)]
    pub white: bool,
    /// The GPU adapter that traced the table (`sss table --device gpu`); absent: the CPU tracer.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tracer: Option<String>,
    /// Specular reflectance at normal incidence [-], not included in any reflectance here.
    pub rsp: f64,
    /// Single-scattering albedos σs/σt, increasing [-].
    pub albedo: Vec<f64>,
    /// Radial edges ρ_k [mean free paths 1/σt], increasing.
    pub radius: Vec<f64>,
    /// [albedo][k]: diffuse reflectance within ρ < ρ_k, per unit incident power [-].
    pub cumulative: Vec<Vec<f64>>,
    /// [albedo][k]: the per-photon mean of the squared weight leaving within ρ_k [-] (for
    /// standard errors: se² = (cumulative_sq − cumulative²)/(photons − 1), over any range of
    /// edges by differences).
    pub cumulative_sq: Vec<Vec<f64>>,
    /// [albedo]: total diffuse reflectance Rd(α) [-] (pbrt's ρ_eff).
    pub rd: Vec<f64>,
    /// [albedo]: the per-photon mean of the squared weight leaving diffusely [-].
    pub rd_sq: Vec<f64>,
}

/// Standard error from means of x and x² over n photons.
fn se_of(mean: f64, mean_sq: f64, n: u64) -> f64 {
    let n = n.max(2) as f64;
    ((mean_sq - mean * mean).max(0.0) / (n - 1.0)).sqrt()
}

impl Table {
    /// The file `sss table` writes it to: `g{g}_eta{η}.table.json`.
    pub fn file_name(&self) -> String {
        format!("g{}_eta{}.table.json", self.g, self.eta)
    }

    /// What a build reports of the table written to `file`, as a line for the user and as JSON:
    /// its albedos and photons, total Rd at the largest albedo with its standard error, and the
    /// radii it reaches [mean free paths].
    pub fn summary(&self, file: &std::path::Path) -> (String, serde_json::Value) {
        let last = self.albedo.len() - 1;
        let (rd, se) = (self.rd[last], self.rd_node(last).se);
        let walks = if self.white {
            "one walk for all"
        } else {
            "one walk each"
        };
        let tracer = self.tracer.as_deref().unwrap_or("cpu");
        let line = format!(
            "table g = {}, η = {}: {} albedos up to {} × {} photons ({walks}, {tracer}); Rd at the largest {rd:.5} ± {se:.5}; radii to {:.0} mean free paths → {}",
            self.g,
            self.eta,
            self.albedo.len(),
            self.albedo[last],
            self.photons,
            self.reach(),
            file.display()
        );
        let json = serde_json::json!({
            "g": self.g, "eta": self.eta, "file": file, "albedos": self.albedo.len(),
            "photons_per_albedo": self.photons, "seed": self.seed, "white": self.white,
            "tracer": tracer,
            "max_albedo": self.albedo[last], "rd_at_max_albedo": rd,
            "rd_at_max_albedo_se": se, "reach_mfp": self.reach(),
        });
        (line, json)
    }

    /// The table as JSON (exact: every f64 is written so it reads back to the same bits).
    pub fn to_json(&self) -> String {
        serde_json::to_string(self).expect("a table serializes")
    }

    /// Reads and checks a table file; errors name the file and field.
    pub fn from_json(text: &str, source_name: &str) -> Result<Table> {
        let t: Table = serde_json::from_str(text).map_err(|e| {
            McError::parse(
                source_name,
                e.line(),
                format!("not an sss table ({FORMAT}): {e}"),
            )
        })?;
        t.check(source_name)?;
        Ok(t)
    }

    fn check(&self, source_name: &str) -> Result<()> {
        let field = |f: &str| format!("{source_name}: {f}");
        if self.format != FORMAT {
            return Err(McError::invalid(
                field("format"),
                &self.format,
                "not an sss table of this version (sss-table-1)",
            ));
        }
        let spec = TableSpec {
            g: self.g,
            eta: self.eta,
            albedos: self.albedo.clone(),
            photons: self.photons,
            seed: self.seed,
            white: self.white,
        };
        spec.validate().map_err(|e| match e {
            McError::InvalidValue {
                field: f,
                value,
                reason,
            } => McError::InvalidValue {
                field: field(&f),
                value,
                reason,
            },
            other => other,
        })?;
        if self.radius != radius_edges() {
            return Err(McError::invalid(
                field("radius"),
                format!("{} edges", self.radius.len()),
                "not this version's radial edges",
            ));
        }
        let (na, nk) = (self.albedo.len(), self.radius.len());
        let rows = [
            ("cumulative", &self.cumulative),
            ("cumulative_sq", &self.cumulative_sq),
        ];
        for (name, rows) in rows {
            if rows.len() != na {
                return Err(McError::invalid(
                    field(name),
                    format!("{} rows", rows.len()),
                    "one row per albedo is required",
                ));
            }
            for (i, row) in rows.iter().enumerate() {
                if row.len() != nk {
                    return Err(McError::invalid(
                        field(&format!("{name}[{i}]")),
                        format!("{} entries", row.len()),
                        "one entry per radius is required",
                    ));
                }
            }
        }
        for (name, v) in [("rd", &self.rd), ("rd_sq", &self.rd_sq)] {
            if v.len() != na {
                return Err(McError::invalid(
                    field(name),
                    format!("{} entries", v.len()),
                    "one entry per albedo is required",
                ));
            }
        }
        for i in 0..na {
            let mut prev = 0.0;
            for (k, &p) in self.cumulative[i].iter().enumerate() {
                if !(p.is_finite() && p >= prev && p <= self.rd[i]) {
                    return Err(McError::invalid(
                        field(&format!("cumulative[{i}][{k}]")),
                        p,
                        "must be finite, non-decreasing in radius and at most rd",
                    ));
                }
                prev = p;
            }
            let ok = |x: f64| x.is_finite() && (0.0..=1.0 + 1e-9).contains(&x);
            if !ok(self.rd[i]) {
                return Err(McError::invalid(
                    field(&format!("rd[{i}]")),
                    self.rd[i],
                    "must lie in [0, 1]",
                ));
            }
            let sq = self.cumulative_sq[i].iter().chain([&self.rd_sq[i]]);
            if let Some(bad) = sq.copied().find(|x| !(x.is_finite() && *x >= 0.0)) {
                return Err(McError::invalid(
                    field(&format!("cumulative_sq[{i}] or rd_sq[{i}]")),
                    bad,
                    "must be finite and non-negative",
                ));
            }
        }
        Ok(())
    }

    /// The largest radius the table reaches [mean free paths].
    pub fn reach(&self) -> f64 {
        *self.radius.last().expect("a checked table has edges")
    }

    /// Total diffuse reflectance at the table's own albedo `i`, with its standard error.
    pub fn rd_node(&self, i: usize) -> Estimate {
        Estimate {
            value: self.rd[i],
            se: se_of(self.rd[i], self.rd_sq[i], self.photons),
        }
    }

    /// Diffuse reflectance leaving within [ρ_{k−1}, ρ_k) (ρ₋₁ = 0) at the table's own albedo `i`,
    /// per unit incident power, with its standard error (a photon leaves once: its second
    /// moments difference like its means).
    pub fn ring_node(&self, i: usize, k: usize) -> Estimate {
        let below = |v: &[f64]| if k == 0 { 0.0 } else { v[k - 1] };
        let m = self.cumulative[i][k] - below(&self.cumulative[i]);
        let m2 = self.cumulative_sq[i][k] - below(&self.cumulative_sq[i]);
        Estimate {
            value: m,
            se: se_of(m, m2, self.photons),
        }
    }

    /// How `other`, an independent build of the same table (other seeds, another tracer), agrees
    /// with this one at each albedo node: χ² over the rings between the edges that hold some
    /// hundred photons' worth or more in both (combined standard error below a tenth of the
    /// mean; sparser rings are skewed, Poisson-like, not Gaussian) and the totals' difference in
    /// combined standard errors. Refuses tables of other albedos or edges.
    pub fn agreement(&self, other: &Table) -> Result<Vec<NodeAgreement>> {
        if self.albedo != other.albedo || self.radius != other.radius {
            return Err(McError::invalid(
                "table",
                format!("g = {}, η = {}", other.g, other.eta),
                "has other albedos or edges: not the same table",
            ));
        }
        let agreement = |i: usize| {
            let (mut chi2, mut dof) = (0.0, 0);
            for k in 0..self.radius.len() {
                let (a, b) = (self.ring_node(i, k), other.ring_node(i, k));
                let var = a.se * a.se + b.se * b.se;
                if var > 0.0 && var.sqrt() < 0.1 * (a.value + b.value) / 2.0 {
                    chi2 += (a.value - b.value).powi(2) / var;
                    dof += 1;
                }
            }
            let (a, b) = (self.rd_node(i), other.rd_node(i));
            let var = a.se * a.se + b.se * b.se;
            let rd_z = if var > 0.0 {
                (a.value - b.value).abs() / var.sqrt()
            } else if a.value == b.value {
                0.0
            } else {
                f64::INFINITY
            };
            NodeAgreement { chi2, dof, rd_z }
        };
        Ok((0..self.albedo.len()).map(agreement).collect())
    }

    /// The table interpolated at `albedo` (see the module documentation); refuses an albedo
    /// outside the table's range.
    pub fn at(&self, albedo: f64) -> Result<Interpolated> {
        let (lo, hi) = (self.albedo[0], *self.albedo.last().unwrap());
        if !(albedo.is_finite() && albedo >= lo && albedo <= hi) {
            return Err(McError::invalid(
                "albedo",
                albedo,
                "outside the table's albedos: build a table that reaches it (sss table --max-albedo)",
            ));
        }
        let fine = cubic_weights(&self.albedo, albedo);
        let every_other: Vec<usize> = (0..self.albedo.len())
            .filter(|i| i % 2 == 0 || *i == self.albedo.len() - 1)
            .collect();
        let nodes: Vec<f64> = every_other.iter().map(|&i| self.albedo[i]).collect();
        let coarse: Vec<(usize, f64)> = cubic_weights(&nodes, albedo)
            .into_iter()
            .map(|(i, w)| (every_other[i], w))
            .collect();
        let nk = self.radius.len();
        let mix = |w: &[(usize, f64)], f: &dyn Fn(usize) -> f64| -> f64 {
            w.iter().map(|&(i, c)| c * f(i)).sum()
        };
        // Masses of the bins below each edge, [0, ρ_0) first; their variances per row.
        let mass = |i: usize, k: usize| {
            self.cumulative[i][k]
                - if k > 0 {
                    self.cumulative[i][k - 1]
                } else {
                    0.0
                }
        };
        let mass_var = |i: usize, k: usize| {
            let q = self.cumulative_sq[i][k]
                - if k > 0 {
                    self.cumulative_sq[i][k - 1]
                } else {
                    0.0
                };
            let se = se_of(mass(i, k), q, self.photons);
            se * se
        };
        // The noise of Σ cᵢXᵢ from the nodes' variances σᵢ²: Σ cᵢ²σᵢ² for nodes of independent
        // walks; a white table's nodes share every photon, and neighbouring albedos' weights
        // (α/α_max)ⁿ nearly coincide, so their errors are strongly positively correlated: for a
        // common correlation ρ ∈ [0, 1] the variance lies between Σ cᵢ²σᵢ² (ρ = 0) and
        // (Σ cᵢσᵢ)² (ρ = 1), and the larger of the two bounds it.
        let white = self.white;
        let noise_of = |var: &dyn Fn(usize) -> f64| -> f64 {
            let independent: f64 = fine.iter().map(|&(i, c)| c * c * var(i)).sum();
            if white {
                let correlated: f64 = fine.iter().map(|&(i, c)| c * var(i).sqrt()).sum();
                independent.max(correlated * correlated)
            } else {
                independent
            }
        };
        let mut m = Vec::with_capacity(nk);
        let mut var = Vec::with_capacity(nk);
        for k in 0..nk {
            let v = mix(&fine, &|i| mass(i, k));
            let e = (v - mix(&coarse, &|i| mass(i, k))) / 15.0;
            let noise = noise_of(&|i| mass_var(i, k));
            m.push(v.max(0.0));
            var.push(noise + e * e);
        }
        let rd = mix(&fine, &|i| self.rd[i]);
        let rd_e = (rd - mix(&coarse, &|i| self.rd[i])) / 15.0;
        let rd_noise = noise_of(&|i| self.rd_node(i).se.powi(2));
        let mut p = Vec::with_capacity(nk);
        let mut acc = 0.0;
        for &x in &m {
            acc += x;
            p.push(acc);
        }
        // Slopes of ln(density) per bin, from the neighbouring bins' densities.
        let edge = |k: isize| if k < 0 { 0.0 } else { self.radius[k as usize] };
        let density = |k: usize| {
            let (a, b) = (edge(k as isize - 1), edge(k as isize));
            m[k] / (std::f64::consts::PI * (b * b - a * a))
        };
        let centre = |k: usize| 0.5 * (edge(k as isize - 1) + edge(k as isize));
        let slope: Vec<f64> = (0..nk)
            .map(|k| {
                if k == 0 {
                    return 0.0;
                }
                let (lo, hi) = (k - 1, (k + 1).min(nk - 1));
                let (dl, dh) = (density(lo), density(hi));
                if lo == 0 || hi == lo || dl <= 0.0 || dh <= 0.0 {
                    return 0.0;
                }
                let s = (dh.ln() - dl.ln()) / (centre(hi) - centre(lo));
                let width = edge(k as isize) - edge(k as isize - 1);
                s.clamp(-30.0 / width, 30.0 / width)
            })
            .collect();
        Ok(Interpolated {
            radius: self.radius.clone(),
            cumulative: p,
            mass: m,
            mass_var: var,
            slope,
            rd: Estimate {
                value: rd.max(0.0),
                se: (rd_noise + rd_e * rd_e).sqrt(),
            },
        })
    }
}

/// The format tag of table shard files.
pub const SHARD_FORMAT: &str = "sss-table-shard-1";

/// One slice of a table build: shard `index` (1-based) of `count`, with the tables' specifications
/// and, per table, the exact sums of that slice of its batch's chunks.
#[derive(Clone, Debug, PartialEq)]
pub struct TableShard {
    /// Which slice (1-based).
    pub index: u64,
    /// Of how many.
    pub count: u64,
    /// Per table: what it is and this slice's sums.
    pub tables: Vec<(TableSpec, Shard)>,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct TableShardFile {
    format: String,
    index: u64,
    count: u64,
    tables: Vec<(TableSpec, ShardFile)>,
}

impl TableShard {
    /// Traces slice `index` (1-based) of `count` of every table's chunks.
    pub fn trace(
        specs: &[TableSpec],
        index: u64,
        count: u64,
        progress: &(dyn Fn(u64) + Sync),
    ) -> Result<TableShard> {
        if index == 0 || index > count {
            return Err(McError::invalid(
                "shard",
                format!("{index}/{count}"),
                "expected I/N with 1 ≤ I ≤ N",
            ));
        }
        let mut tables = Vec::with_capacity(specs.len());
        for spec in specs {
            spec.validate()?;
            let batch = spec.batch();
            let chunks = crate::shard::shard_chunks(spec.photons, index - 1, count);
            let groups = if spec.white {
                crate::white::accumulate(&batch, &spec.albedos, chunks.clone(), progress)
            } else {
                crate::accumulate_batch(&batch, chunks.clone(), progress)?
            };
            let labels = label_channels(spec);
            let shard = Shard {
                spec: batch,
                labels,
                chunks,
                groups,
            };
            tables.push((spec.clone(), shard));
        }
        Ok(TableShard {
            index,
            count,
            tables,
        })
    }

    /// Photons this slice traces over all tables (for progress bars): a white table's walk once,
    /// else each albedo's.
    pub fn photons(specs: &[TableSpec], index: u64, count: u64) -> u64 {
        specs
            .iter()
            .map(|s| {
                let chunks = crate::shard::shard_chunks(s.photons, index.max(1) - 1, count.max(1));
                let walks = if s.white { 1 } else { s.albedos.len() as u64 };
                crate::shard::chunk_photons(s.photons, &chunks) * walks
            })
            .sum()
    }

    /// Interaction events traced over all tables (drops).
    pub fn interactions(&self) -> u64 {
        self.tables
            .iter()
            .flat_map(|(_, s)| s.groups.iter().map(|a| a.interactions))
            .sum()
    }

    /// The shard file's text.
    pub fn to_json(&self) -> String {
        let f = TableShardFile {
            format: SHARD_FORMAT.into(),
            index: self.index,
            count: self.count,
            tables: self
                .tables
                .iter()
                .map(|(spec, shard)| (spec.clone(), shard.to_file()))
                .collect(),
        };
        serde_json::to_string(&f).expect("a table shard serializes")
    }

    /// Whether `text` is a table shard file (its `format` is [`SHARD_FORMAT`]), as opposed to a
    /// profile shard of `sss simulate --shard`; says nothing of whether it is a valid one.
    pub fn is_shard(text: &str) -> bool {
        #[derive(serde::Deserialize)]
        struct Tag {
            format: Option<String>,
        }
        serde_json::from_str::<Tag>(text)
            .ok()
            .and_then(|t| t.format)
            .is_some_and(|f| f == SHARD_FORMAT)
    }

    /// Reads a table shard file and checks each table's sums against its specification.
    pub fn from_json(text: &str, source_name: &str) -> Result<TableShard> {
        let f: TableShardFile = serde_json::from_str(text).map_err(|e| {
            McError::parse(
                source_name,
                e.line(),
                format!("not an sss table shard ({SHARD_FORMAT}): {e}"),
            )
        })?;
        if f.format != SHARD_FORMAT {
            return Err(McError::parse(
                source_name,
                0,
                format!("format {:?} is not {SHARD_FORMAT:?}", f.format),
            ));
        }
        if f.index == 0 || f.index > f.count {
            return Err(McError::invalid(
                format!("{source_name}: index"),
                format!("{}/{}", f.index, f.count),
                "expected I/N with 1 ≤ I ≤ N",
            ));
        }
        let mut tables = Vec::with_capacity(f.tables.len());
        for (t, (spec, file)) in f.tables.into_iter().enumerate() {
            let name = format!("{source_name} table {t}");
            spec.validate()
                .map_err(|e| McError::parse(&name, 0, e.to_string()))?;
            let shard = Shard::from_file(file, &name)?;
            if shard.spec != spec.batch() || shard.labels != label_channels(&spec) {
                return Err(McError::parse(
                    &name,
                    0,
                    "its sums are not of its table's batch (a foreign or edited shard)",
                ));
            }
            tables.push((spec, shard));
        }
        Ok(TableShard {
            index: f.index,
            count: f.count,
            tables,
        })
    }
}

fn label_channels(spec: &TableSpec) -> Vec<String> {
    spec.albedos
        .iter()
        .enumerate()
        .flat_map(|(i, _)| (0..LEVELS).map(move |j| format!("albedo {i} level {j}")))
        .collect()
}

/// The tables of a sharded build from all its shard files (named for messages): the same
/// tables in the same order in every file, one file per index 1..=N of one N, and chunks that
/// tile each run (checked by [`crate::shard::merge`]). Bit-identical to the unsharded build.
pub fn merge_tables(files: &[(String, TableShard)]) -> Result<Vec<Table>> {
    let mismatch = |m: String| McError::ShardMismatch(m);
    let (first_name, first) = files
        .first()
        .ok_or_else(|| mismatch("no shards given".into()))?;
    let mut seen = vec![None::<&str>; first.count.min(1 << 20) as usize];
    for (name, f) in files {
        if f.count != first.count {
            return Err(mismatch(format!(
                "{name} is a shard of {} but {first_name} of {}: shards of different builds",
                f.count, first.count
            )));
        }
        let specs = |s: &TableShard| s.tables.iter().map(|(t, _)| t.clone()).collect::<Vec<_>>();
        if specs(f) != specs(first) {
            return Err(mismatch(format!(
                "{name} and {first_name} build different tables (g, η, albedos, photons or seed)"
            )));
        }
        match seen.get_mut(f.index as usize - 1) {
            Some(Some(other)) => {
                return Err(mismatch(format!(
                    "{name} and {other} are both shard {}/{}",
                    f.index, f.count
                )));
            }
            Some(slot) => *slot = Some(name),
            None => {}
        }
    }
    if let Some(i) = seen.iter().position(|s| s.is_none()) {
        return Err(mismatch(format!(
            "shard {}/{} is missing",
            i + 1,
            first.count
        )));
    }
    (0..first.tables.len())
        .map(|t| {
            let shards: Vec<(String, Shard)> = files
                .iter()
                .map(|(name, f)| (name.clone(), f.tables[t].1.clone()))
                .collect();
            let (_, _, accs) = crate::shard::merge(&shards)?;
            first.tables[t].0.table(&accs)
        })
        .collect()
}

/// Builds tables on this machine: every chunk, as one shard of one merged.
pub fn build(specs: &[TableSpec], progress: &(dyn Fn(u64) + Sync)) -> Result<Vec<Table>> {
    merge_tables(&[(String::new(), TableShard::trace(specs, 1, 1, progress)?)])
}

/// Weights (index, weight) of cubic interpolation at `t` through the four nodes of `x`
/// (increasing, at least 4) around it: the two bracketing nodes and one on either side, shifted
/// inwards at the ends (Lagrange's cubic). Reproduces cubics exactly.
fn cubic_weights(x: &[f64], t: f64) -> Vec<(usize, f64)> {
    let n = x.len();
    let i = x.partition_point(|&v| v <= t).clamp(1, n - 1) - 1;
    let lo = i.saturating_sub(1).min(n - 4);
    (lo..lo + 4)
        .map(|j| {
            let w = (lo..lo + 4)
                .filter(|&k| k != j)
                .map(|k| (t - x[k]) / (x[j] - x[k]))
                .product();
            (j, w)
        })
        .collect()
}

/// A table at one albedo: the cumulative reflectance at every radius, and annulus averages.
#[derive(Clone, Debug)]
pub struct Interpolated {
    radius: Vec<f64>,
    /// P at each edge (prefix sums of `mass`).
    cumulative: Vec<f64>,
    /// Mass of each bin [ρ_{k−1}, ρ_k) (bin 0 from 0), clamped at 0.
    mass: Vec<f64>,
    /// Variance of each bin's mass: the table's noise and the α-interpolation error.
    mass_var: Vec<f64>,
    /// Slope s of ln(density) within each bin [1/mean free path].
    slope: Vec<f64>,
    /// Total diffuse reflectance [-].
    pub rd: Estimate,
}

/// ∫_0^X (a + t)·e^{s t} dt, computed without cancellation for small s·X.
fn moment(a: f64, s: f64, x: f64) -> f64 {
    let sx = s * x;
    if sx.abs() < 1e-4 {
        // Series to third order in s·X.
        a * x * (1.0 + sx / 2.0 + sx * sx / 6.0) + x * x * (0.5 + sx / 3.0 + sx * sx / 8.0)
    } else {
        let e1 = sx.exp_m1() / s;
        a * e1 + (x * (sx).exp() - e1) / s
    }
}

impl Interpolated {
    /// The largest radius it reaches [mean free paths].
    pub fn reach(&self) -> f64 {
        *self.radius.last().unwrap()
    }

    /// Bin holding radius `x` (0 for x < ρ_0); `None` beyond the last edge.
    fn bin(&self, x: f64) -> Option<usize> {
        let k = self.radius.partition_point(|&e| e <= x);
        (k < self.radius.len()).then_some(k)
    }

    /// Fraction of bin k's mass below `x` (within the bin).
    fn fraction(&self, k: usize, x: f64) -> f64 {
        if k == 0 {
            return (x / self.radius[0]).clamp(0.0, 1.0);
        }
        let (a, b) = (self.radius[k - 1], self.radius[k]);
        let x = x.clamp(a, b);
        moment(a, self.slope[k], x - a) / moment(a, self.slope[k], b - a)
    }

    /// Diffuse reflectance within radius `x` [mean free paths] (the last edge's beyond reach).
    pub fn cumulative(&self, x: f64) -> f64 {
        if x <= 0.0 {
            return 0.0;
        }
        match self.bin(x) {
            None => *self.cumulative.last().unwrap(),
            Some(k) => {
                let below = if k > 0 { self.cumulative[k - 1] } else { 0.0 };
                below + self.mass[k] * self.fraction(k, x)
            }
        }
    }

    /// Average of R̂ over the annulus [a, b) [per squared mean free path], with its standard
    /// error: the table's noise and the interpolation error estimate of each bin it overlaps,
    /// times the share f of the bin's mass inside (the share is a fixed fraction of a noisy
    /// mass: its variance is f² times the bin's).
    pub fn annulus(&self, a: f64, b: f64) -> Estimate {
        let area = std::f64::consts::PI * (b * b - a * a);
        let value = (self.cumulative(b) - self.cumulative(a)).max(0.0) / area;
        let last = self.radius.len() - 1;
        let (ka, kb) = (self.bin(a).unwrap_or(last), self.bin(b).unwrap_or(last));
        let var: f64 = (ka..=kb)
            .map(|k| {
                let f = (self.fraction(k, b) - self.fraction(k, a)).clamp(0.0, 1.0);
                self.mass_var[k] * f * f
            })
            .sum();
        Estimate {
            value,
            se: var.sqrt() / area,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cubic_weights_reproduce_cubics_and_hit_nodes() {
        let x = [0.0, 0.1, 0.35, 0.4, 0.8, 0.95, 0.97];
        let f = |t: f64| 2.0 * t * t * t - t * t + 3.0 * t - 1.0;
        for t in [0.0, 0.05, 0.1, 0.2, 0.37, 0.6, 0.9, 0.96, 0.97] {
            let w = cubic_weights(&x, t);
            let sum: f64 = w.iter().map(|(_, c)| c).sum();
            let cubic: f64 = w.iter().map(|&(i, c)| c * f(x[i])).sum();
            assert!((sum - 1.0).abs() < 1e-12, "t = {t}: Σw = {sum}");
            assert!(
                (cubic - f(t)).abs() < 1e-12,
                "t = {t}: {cubic} against {}",
                f(t)
            );
        }
        // At a node, the node's value alone.
        let w = cubic_weights(&x, 0.35);
        let at: f64 = w.iter().map(|&(i, c)| c * (i as f64)).sum();
        assert!((at - 2.0).abs() < 1e-12);
    }

    #[test]
    fn edges_increase_by_at_most_twice_and_reach_far() {
        let e = radius_edges();
        assert_eq!(e[0], FIRST_WIDTH);
        for w in e.windows(2) {
            assert!(w[1] > w[0] && w[1] / w[0] <= 2.0 + 1e-12, "{w:?}");
        }
        assert!(*e.last().unwrap() > 4000.0);
    }

    /// The same exits scored on the level grids (as the CPU tracer does) and on the radial
    /// intervals (as the GPU does) give the same table: every level's bin edge is an edge of
    /// the intervals, and an exit on an edge counts above it in both.
    #[test]
    fn interval_sums_give_the_level_grids_table() {
        let spec = TableSpec {
            g: 0.0,
            eta: 1.4,
            albedos: default_albedos(8, 0.99),
            photons: 500,
            seed: 1,
            white: true,
        };
        let edges = radius_edges();
        let layout = crate::tally::Layout {
            nr: LEVEL_BINS,
            nz: 1,
            na: 1,
            layers: 1,
            rz: false,
            rz_se: false,
            channels: LEVELS,
            xy: 0,
            scores: 0,
        };
        let levels: Vec<_> = (0..LEVELS)
            .map(|j| crate::grid::GridIndex::new(&level_grid(j)))
            .collect();
        let (mut accs, mut rows) = (Vec::new(), Vec::new());
        for a in 0..spec.albedos.len() {
            let mut acc = Accumulator::new(layout);
            let mut row = IntervalSums {
                sum: vec![0; edges.len() + 1],
                sum_sq: vec![0; edges.len() + 1],
                photons: spec.photons,
            };
            for i in 0..spec.photons {
                // Radii from 10⁻⁴ to 10⁴ mean free paths, some exactly on edges.
                let r = if i % 7 == 0 {
                    edges[(i as usize * 13 + a) % edges.len()]
                } else {
                    10f64
                        .powf(-4.0 + 8.0 * ((i * 7919 + a as u64 * 104_729) % 1000) as f64 / 1000.0)
                };
                let w = (1 + (i + a as u64) % 5) as i128 * (1 << 50);
                for (j, g) in levels.iter().enumerate() {
                    acc.sum[layout.rd_ra(j) + g.ir(r)] += w;
                    acc.sum_sq[layout.rd_ra(j) + g.ir(r)] += (w * w) >> 64;
                }
                let m = edges.partition_point(|&e| e <= r);
                row.sum[m] += w;
                row.sum_sq[m] += (w * w) >> 64;
            }
            acc.photons = spec.photons;
            accs.push(acc);
            rows.push(row);
        }
        let by_levels = spec.table(&accs).unwrap();
        let by_intervals = spec.table_from_intervals(&rows, "test").unwrap();
        assert_eq!(by_intervals.tracer.as_deref(), Some("test"));
        assert_eq!(
            Table {
                tracer: None,
                ..by_intervals
            },
            by_levels
        );
        let short = IntervalSums {
            sum: vec![0; 3],
            ..rows[0].clone()
        };
        let e = spec.table_from_intervals(&vec![short; 8], "test");
        assert!(e.unwrap_err().to_string().contains("radial interval"));
    }

    #[test]
    fn the_shape_within_a_bin_integrates_exactly() {
        // moment() against a midpoint sum, for rising, falling and flat densities.
        for s in [-20.0, -1e-6, 0.0, 3e-5, 2.0] {
            let (a, x) = (0.3, 0.7);
            let n = 200_000;
            let h = x / n as f64;
            let sum: f64 = (0..n)
                .map(|i| {
                    let t = (i as f64 + 0.5) * h;
                    (a + t) * (s * t).exp() * h
                })
                .sum();
            let m = moment(a, s, x);
            assert!(
                (m - sum).abs() < 1e-8 * sum.abs().max(1e-12),
                "s = {s}: {m} vs {sum}"
            );
        }
    }

    #[test]
    fn bad_specifications_are_refused_naming_the_field() {
        let ok = TableSpec {
            g: 0.0,
            eta: 1.3,
            albedos: default_albedos(8, 0.99),
            photons: 1000,
            seed: 1,
            white: false,
        };
        ok.validate().unwrap();
        let field = |s: TableSpec| match s.validate() {
            Err(McError::InvalidValue { field, .. }) => field,
            other => panic!("{other:?}"),
        };
        assert_eq!(
            field(TableSpec {
                g: 1.0,
                ..ok.clone()
            }),
            "g"
        );
        assert_eq!(
            field(TableSpec {
                eta: 0.0,
                ..ok.clone()
            }),
            "eta"
        );
        let mut one = ok.clone();
        one.albedos[7] = 1.0;
        assert_eq!(field(one), "albedos[7]");
        let mut unordered = ok.clone();
        unordered.albedos.swap(2, 3);
        assert_eq!(field(unordered), "albedos[3]");
    }
}
