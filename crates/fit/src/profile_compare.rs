//! Analytic profiles against a Monte Carlo profile on the same grid: how far each model is from
//! the transport ground truth, and where along r it fails.
//!
//! Distances are in transport mean free paths ℓ = 1/σt′ of each channel. Totals are the
//! reflectance held by the grid, Σ Rdᵢ·π((i+1)² − i²)dr², for both profiles alike.

use crate::analytic::{Medium, Model, profile};
use crate::error::Result;
use crate::profile::Profile;

/// Bands of r [MFP] in which the worst relative error is reported.
pub const BANDS: [(f64, f64); 3] = [(0.0, 0.5), (0.5, 3.0), (3.0, 10.0)];

/// One model's agreement with MC in one channel.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ChannelAgreement {
    /// MC total diffuse reflectance on the grid and its standard error [-]; the error treats bins
    /// as independent, an upper bound (a photon's weight leaves through one bin, so bins are
    /// anti-correlated); the exact one is in `simulate`'s summary.
    pub total_mc: f64,
    /// Its standard error [-].
    pub total_mc_se: f64,
    /// The model's total on the grid [-].
    pub total_model: f64,
    /// (model − MC)/MC of the total [-].
    pub total_rel_err: f64,
    /// RMS of r·Rd(r) differences over r ≤ 3 MFP, relative to the RMS of MC's r·Rd(r) [-].
    pub rms_r_rd_3mfp: f64,
    /// Worst |model/MC − 1| in each of [`BANDS`], over bins whose MC standard error is below 5%
    /// (None where no bin qualifies).
    pub band_max_rel_err: [Option<f64>; 3],
}

/// One model against MC: its profile on MC's grid and the agreement per channel.
#[derive(Clone, Debug)]
pub struct ModelAgreement {
    /// The analytic model.
    pub model: Model,
    /// Its profile on MC's grid (annulus averages; standard errors 0).
    pub profile: Profile,
    /// The agreement per channel (R, G, B).
    pub channels: [ChannelAgreement; 3],
}

/// Grid total of a channel and its standard error.
fn grid_total(p: &Profile, c: usize) -> (f64, f64) {
    let area = |i: usize| std::f64::consts::PI * (2 * i + 1) as f64 * p.dr * p.dr;
    let (mut t, mut v) = (0.0, 0.0);
    for i in 0..p.len() {
        t += p.rd[c][i] * area(i);
        v += (p.se[c][i] * area(i)).powi(2);
    }
    (t, v.sqrt())
}

/// The agreement of profile `model` with `mc` in channel `c`, distances scaled by `mfp` [cm].
pub fn agreement(mc: &Profile, model: &Profile, c: usize, mfp: f64) -> ChannelAgreement {
    let (total_mc, total_mc_se) = grid_total(mc, c);
    let (total_model, _) = grid_total(model, c);
    let (mut num, mut den) = (0.0, 0.0);
    let mut bands = [None; 3];
    for i in 0..mc.len().min(model.len()) {
        let (r, m, t, se) = (mc.r[i], model.rd[c][i], mc.rd[c][i], mc.se[c][i]);
        let x = r / mfp;
        if x <= 3.0 {
            num += (r * (m - t)).powi(2);
            den += (r * t).powi(2);
        }
        if t > 0.0 && se < 0.05 * t {
            let e = (m / t - 1.0).abs();
            for (b, &(lo, hi)) in BANDS.iter().enumerate() {
                if x >= lo && x < hi {
                    bands[b] = Some(bands[b].map_or(e, |w: f64| w.max(e)));
                }
            }
        }
    }
    ChannelAgreement {
        total_mc,
        total_mc_se,
        total_model,
        total_rel_err: (total_model - total_mc) / total_mc,
        rms_r_rd_3mfp: (num / den).sqrt(),
        band_max_rel_err: bands,
    }
}

/// Every analytic model of a material against its MC profile.
pub fn compare(mc: &Profile, material: &mc::Material) -> Result<Vec<ModelAgreement>> {
    let n = mc.len();
    Model::ALL
        .iter()
        .map(|&model| {
            let p = profile(model, material, mc.dr, n)?;
            let channels = [0, 1, 2]
                .map(|c| agreement(mc, &p, c, Medium::channel(material, c).transport_mfp()));
            Ok(ModelAgreement {
                model,
                profile: p,
                channels,
            })
        })
        .collect()
}
