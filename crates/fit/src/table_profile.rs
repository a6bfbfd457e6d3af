//! A material's Monte Carlo profile from tables (`mc::table`) instead of a simulation: each
//! channel's Rd(r) = σt²·R̂(σt·r; α) on the material's grid, interpolated in α within the table
//! of the channel's g and η. Between tables of neighbouring g or η values it blends linearly
//! (bilinearly when both lie between grid values), each table taken at the coefficients that
//! are similar to the material's for its g (the same σa and reduced scattering σs(1 − g)); a g
//! or η outside the tables' grid is refused.
//!
//! Units: r in cm, Rd in cm⁻² (MCML's `Rd_r`, specular reflection excluded), as `sss simulate`
//! writes; every value carries the table's standard error and the interpolation error estimate
//! in quadrature (`mc::table` documents both).

use mc::table::Table;
use mc::{Estimate, Grid, Material, McError};

use crate::error::{FitError, Result};
use crate::profile::Profile;

/// Two grid values this close count as the same g or η.
const SAME: f64 = 1e-9;

/// Tables of one or more (g, η), checked to hold each pair once.
#[derive(Clone, Debug)]
pub struct Tables {
    tables: Vec<(String, Table)>,
}

/// A material's profile from tables: what `sss simulate` would write, and each channel's total.
#[derive(Clone, Debug)]
pub struct TableProfile {
    /// Rd(r) with standard errors, MCML's overflow bin dropped.
    pub profile: Profile,
    /// Per channel, the overflow bin (everything beyond the grid over the last annulus) [cm⁻²].
    pub overflow: [Estimate; 3],
    /// Per channel, the total diffuse reflectance [-].
    pub rd: [Estimate; 3],
}

fn from_mc(e: McError) -> FitError {
    match e {
        McError::InvalidValue {
            field,
            value,
            reason,
        } => FitError::invalid(field, value, reason),
        other => FitError::invalid("table", other, "unusable"),
    }
}

impl Tables {
    /// Tables named for messages (file names). Refuses none, and two of the same (g, η).
    pub fn new(tables: Vec<(String, Table)>) -> Result<Tables> {
        if tables.is_empty() {
            return Err(FitError::invalid("tables", 0, "no table given"));
        }
        for (i, (a, ta)) in tables.iter().enumerate() {
            for (b, tb) in &tables[..i] {
                if (ta.g - tb.g).abs() <= SAME && (ta.eta - tb.eta).abs() <= SAME {
                    return Err(FitError::invalid(
                        "tables",
                        format!("{a} and {b}"),
                        format!("both hold g = {}, η = {}", ta.g, ta.eta),
                    ));
                }
            }
        }
        Ok(Tables { tables })
    }

    /// Sorted distinct values of a coordinate.
    fn axis(&self, f: fn(&Table) -> f64) -> Vec<f64> {
        let mut v: Vec<f64> = self.tables.iter().map(|(_, t)| f(t)).collect();
        v.sort_by(f64::total_cmp);
        v.dedup_by(|a, b| (*a - *b).abs() <= SAME);
        v
    }

    /// The table of (g, η), if there is one.
    fn find(&self, g: f64, eta: f64) -> Option<&Table> {
        self.tables
            .iter()
            .map(|(_, t)| t)
            .find(|t| (t.g - g).abs() <= SAME && (t.eta - eta).abs() <= SAME)
    }

    /// The tables and blend weights that stand for (g, η): one table on the grid, two or four
    /// around it.
    pub fn corners(&self, g: f64, eta: f64) -> Result<Vec<(&Table, f64)>> {
        let (gs, etas) = (self.axis(|t| t.g), self.axis(|t| t.eta));
        let outside = || {
            FitError::invalid(
                "g and η",
                format!("g = {g}, η = {eta}"),
                format!(
                    "outside the tables' grid (g ∈ {gs:?}, η ∈ {etas:?}): build a table for them \
                     (sss table --g {g} --eta {eta})"
                ),
            )
        };
        let bracket = |axis: &[f64], x: f64| -> Option<Vec<(f64, f64)>> {
            if let Some(&v) = axis.iter().find(|v| (*v - x).abs() <= SAME) {
                return Some(vec![(v, 1.0)]);
            }
            let hi = axis.iter().position(|&v| v > x)?;
            if hi == 0 {
                return None;
            }
            let (a, b) = (axis[hi - 1], axis[hi]);
            let t = (x - a) / (b - a);
            Some(vec![(a, 1.0 - t), (b, t)])
        };
        let (bg, be) = (
            bracket(&gs, g).ok_or_else(outside)?,
            bracket(&etas, eta).ok_or_else(outside)?,
        );
        let mut out = Vec::new();
        for &(gv, wg) in &bg {
            for &(ev, we) in &be {
                let t = self.find(gv, ev).ok_or_else(|| {
                    FitError::invalid(
                        "g and η",
                        format!("g = {g}, η = {eta}"),
                        format!(
                            "needs the table of g = {gv}, η = {ev} to interpolate, which is missing"
                        ),
                    )
                })?;
                out.push((t, wg * we));
            }
        }
        Ok(out)
    }

    /// The material's profile on `grid` [cm] (its last bin MCML's overflow bin), as a half-space
    /// of relative index η = `material.eta / n_above`. Refuses a channel that does not interact,
    /// a layer thinner than a half-space, an albedo, g or η the tables do not cover, and a grid
    /// reaching beyond the tables' radii; errors name the channel and field.
    pub fn profile(
        &self,
        m: &Material,
        grid: &Grid,
        n_above: f64,
        thickness: f64,
    ) -> Result<TableProfile> {
        let n =
            grid.nr.checked_sub(1).filter(|&n| n >= 2).ok_or_else(|| {
                FitError::invalid("grid nr", grid.nr, "need at least 3 radial bins")
            })?;
        let eta = m.eta / n_above;
        let mut rd_bins: [Vec<Estimate>; 3] = Default::default();
        let mut overflow = [Estimate {
            value: 0.0,
            se: 0.0,
        }; 3];
        let mut totals = overflow;
        for c in 0..3 {
            let ch = mc::CHANNELS[c];
            let field = |f: &str| format!("material {} channel {ch} {f}", m.name);
            let sigma_t = m.sigma_a[c] + m.sigma_s[c];
            if sigma_t.is_nan() || sigma_t <= 0.0 {
                return Err(FitError::invalid(
                    field("sigma_a + sigma_s"),
                    sigma_t,
                    "does not interact: no table profile (simulate it)",
                ));
            }
            if sigma_t * thickness < mc::QUASI_INFINITE_MFP {
                return Err(FitError::invalid(
                    field("thickness"),
                    thickness,
                    "tables hold half-spaces: the layer is thinner than 10⁶ mean free paths",
                ));
            }
            let corners = self.corners(m.g[c], eta).map_err(|e| match e {
                FitError::Invalid {
                    field: f,
                    value,
                    reason,
                } => FitError::invalid(field(&f), value, reason),
                other => other,
            })?;
            let mut bins = vec![
                Estimate {
                    value: 0.0,
                    se: 0.0
                };
                n
            ];
            let zero = Estimate {
                value: 0.0,
                se: 0.0,
            };
            let (mut over, mut total) = (zero, zero);
            for (table, w) in corners {
                // Similarity (Wyman, Patterson & Wilson 1989): a medium of the corner's g with
                // the same σa and reduced scattering σs(1 − g) diffuses alike; blending those
                // corners leaves only the near field to the linear weights. On the grid, the
                // material's own coefficients.
                let g = m.g[c];
                let sigma_s = if (table.g - g).abs() <= SAME {
                    m.sigma_s[c]
                } else {
                    m.sigma_s[c] * (1.0 - g) / (1.0 - table.g)
                };
                let sigma_t = m.sigma_a[c] + sigma_s;
                let albedo = sigma_s / sigma_t;
                let at = table.at(albedo).map_err(|e| match from_mc(e) {
                    FitError::Invalid { value, reason, .. } => {
                        FitError::invalid(field("albedo"), value, reason)
                    }
                    other => other,
                })?;
                let last = sigma_t * grid.dr * n as f64;
                if last > at.reach() {
                    return Err(FitError::invalid(
                        field("grid radius"),
                        format!("{} cm", grid.dr * n as f64),
                        format!(
                            "reaches {last:.4e} mean free paths, beyond the table's {:.4e}",
                            at.reach()
                        ),
                    ));
                }
                let scale = sigma_t * sigma_t;
                let add = |e: &mut Estimate, v: Estimate, scale: f64| {
                    e.value += w * v.value * scale;
                    e.se = (e.se * e.se + (w * v.se * scale).powi(2)).sqrt();
                };
                for (i, b) in bins.iter_mut().enumerate() {
                    let r = |k: usize| sigma_t * grid.dr * k as f64;
                    add(b, at.annulus(r(i), r(i + 1)), scale);
                }
                // MCML's overflow bin: everything beyond the grid over the last annulus.
                let area = 2.0 * std::f64::consts::PI * (n as f64 + 0.5) * grid.dr * grid.dr;
                let beyond = Estimate {
                    value: (at.rd.value - at.cumulative(last)).max(0.0),
                    se: at.rd.se,
                };
                add(&mut over, beyond, 1.0 / area);
                add(&mut total, at.rd, 1.0);
            }
            rd_bins[c] = bins;
            overflow[c] = over;
            totals[c] = total;
        }
        let profile = Profile {
            dr: grid.dr,
            r: (0..n).map(|i| grid.r_optimal(i)).collect(),
            rd: [0, 1, 2].map(|c| rd_bins[c].iter().map(|e| e.value).collect()),
            se: [0, 1, 2].map(|c| rd_bins[c].iter().map(|e| e.se).collect()),
        };
        Ok(TableProfile {
            profile,
            overflow,
            rd: totals,
        })
    }
}

impl TableProfile {
    /// The CSV `sss simulate` writes for the same material.
    pub fn to_csv(&self) -> String {
        self.profile.to_csv(self.overflow.map(|e| (e.value, e.se)))
    }
}
