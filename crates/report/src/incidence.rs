//! Total diffuse reflectance against the angle of incidence, Rd(θ): `mc`'s runs beside the
//! analytic models' (`sss simulate --incidence-angles`), as a table, JSON rows and a plot.

use mc::incidence::IncidenceRow;
use serde_json::{Value, json};

use fit::analytic::{Medium, Model, total_at};

use crate::error::Result;
use crate::plot::{IncidenceCurve, IncidencePoint};

/// `mc`'s Rd(θ) rows of one material beside the analytic models' totals at the same angles.
#[derive(Clone, Debug, PartialEq)]
pub struct IncidenceComparison {
    /// The Monte Carlo rows, one per angle.
    pub rows: Vec<IncidenceRow>,
    /// Each analytic model's totals at those angles (models outside their domain left out).
    pub models: Vec<IncidenceCurve>,
}

impl IncidenceComparison {
    /// The rows of a material with channels `media`, and the models' totals beside them.
    pub fn new(media: &[Medium; 3], rows: Vec<IncidenceRow>) -> Self {
        let models = curves(media, &rows);
        IncidenceComparison { rows, models }
    }

    /// The table as CSV: `theta_deg,R,G,B,R_se,G_se,B_se,R_rsp,G_rsp,B_rsp`, then
    /// `MODEL_R,MODEL_G,MODEL_B` per model, one row per angle [degrees].
    pub fn csv(&self) -> String {
        csv(&self.rows, &self.models)
    }

    /// One JSON object per angle: θ, Rd, its standard error and Rsp per channel, and each
    /// model's totals.
    pub fn json(&self) -> Value {
        json(&self.rows, &self.models)
    }

    /// Rd(θ) and Rd(θ)/Rd(0°) with the models' curves, as PNG bytes titled `title`.
    pub fn png(&self, title: &str) -> Result<Vec<u8>> {
        png(&self.rows, &self.models, title)
    }
}

/// The analytic models drawn and tabulated beside Monte Carlo's Rd(θ).
const INCIDENCE_MODELS: [Model; 3] = [Model::DirectionalDipole, Model::Dipole, Model::BetterDipole];

/// Each of [`INCIDENCE_MODELS`]' total Rd at every angle of `rows`, per channel; a model is left
/// out where a channel is outside its domain (e.g. does not interact with light).
fn curves(media: &[Medium; 3], rows: &[IncidenceRow]) -> Vec<IncidenceCurve> {
    INCIDENCE_MODELS
        .iter()
        .filter_map(|&model| {
            let points = rows
                .iter()
                .map(|r| {
                    let v: Option<Vec<f64>> = (0..3)
                        .map(|c| total_at(model, &media[c], r.theta_deg).ok())
                        .collect();
                    v.map(|v| (r.theta_deg, [v[0], v[1], v[2]]))
                })
                .collect::<Option<Vec<_>>>()?;
            Some(IncidenceCurve {
                name: model.name().to_string(),
                points,
            })
        })
        .collect()
}

/// `theta_deg,R,G,B,R_se,G_se,B_se,R_rsp,G_rsp,B_rsp`, then `MODEL_R,MODEL_G,MODEL_B` per model:
/// total Rd per unit incident power (without Rsp) with standard errors, the specular reflectance
/// Rsp, and the analytic models' totals, per angle [degrees].
fn csv(rows: &[IncidenceRow], models: &[IncidenceCurve]) -> String {
    let mut s = String::from("theta_deg,R,G,B,R_se,G_se,B_se,R_rsp,G_rsp,B_rsp");
    for m in models {
        for c in ["R", "G", "B"] {
            s += &format!(",{}_{c}", m.name);
        }
    }
    s += "\n";
    for (i, r) in rows.iter().enumerate() {
        s += &format!(
            "{},{},{},{},{},{},{},{},{},{}",
            r.theta_deg,
            r.rd[0].value,
            r.rd[1].value,
            r.rd[2].value,
            r.rd[0].se,
            r.rd[1].se,
            r.rd[2].se,
            r.rsp[0],
            r.rsp[1],
            r.rsp[2]
        );
        for m in models {
            let v = m.points[i].1;
            s += &format!(",{},{},{}", v[0], v[1], v[2]);
        }
        s += "\n";
    }
    s
}

fn json(rows: &[IncidenceRow], models: &[IncidenceCurve]) -> Value {
    let rgb = |v: [f64; 3]| json!({ "R": v[0], "G": v[1], "B": v[2] });
    rows.iter()
        .enumerate()
        .map(|(i, r)| {
            let analytic: serde_json::Map<String, Value> = models
                .iter()
                .map(|m| (m.name.clone(), rgb(m.points[i].1)))
                .collect();
            json!({
                "theta_deg": r.theta_deg,
                "rd": rgb([0, 1, 2].map(|c| r.rd[c].value)),
                "rd_se": rgb([0, 1, 2].map(|c| r.rd[c].se)),
                "rsp": rgb([0, 1, 2].map(|c| r.rsp[c])),
                "models": analytic,
            })
        })
        .collect()
}

fn png(rows: &[IncidenceRow], models: &[IncidenceCurve], slug: &str) -> Result<Vec<u8>> {
    let points: Vec<IncidencePoint> = rows
        .iter()
        .map(|r| IncidencePoint {
            theta_deg: r.theta_deg,
            rd: [0, 1, 2].map(|c| r.rd[c].value),
            se: [0, 1, 2].map(|c| r.rd[c].se),
        })
        .collect();
    crate::plot::incidence(&points, models, slug)
}
