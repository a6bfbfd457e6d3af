//! Measurements of the photon tracer (`sss bench mc`), as plain data: throughput on one channel,
//! run time against error, and batch tracing against channel-by-channel runs. Each function runs
//! in the caller's rayon pool (one thread for throughput per core). A benchmark, not a test: it
//! asserts nothing.

use std::time::Instant;

use serde::Serialize;

use crate::batch::BatchSpec;
use crate::config::SimConfig;
use crate::error::Result;
use crate::layer::Sample;
use crate::material::{CHANNELS, Material};
use crate::output::Output;
use crate::simulate::{RunSpec, run, run_batch};
use crate::tally::TallySet;

/// One channel traced alone.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Throughput {
    /// The material.
    pub material: String,
    /// The channel (always R).
    pub channel: &'static str,
    /// `full (MCML, .mci)`, `full + A(r,z) SE` or `profile-only`.
    pub tallies: &'static str,
    /// Photon packets traced.
    pub photons: u64,
    /// Wall time [s].
    pub seconds: f64,
    /// Photon packets per second.
    pub photons_per_s: f64,
    /// Interactions per second.
    pub events_per_s: f64,
    /// Interactions per photon packet.
    pub events_per_photon: f64,
}

/// The tallies [`throughput`] compares: MCML's full set as `.mci` runs keep it (A(r, z) summed),
/// the full set with per-photon standard errors of A(r, z), and profile-only.
const THROUGHPUT_TALLIES: [(&str, TallySet); 3] = [
    (
        "full (MCML, .mci)",
        TallySet {
            absorption_rz: true,
            absorption_rz_se: false,
            surface_xy: 0,
        },
    ),
    (
        "full + A(r,z) SE",
        TallySet {
            absorption_rz: true,
            absorption_rz_se: true,
            surface_xy: 0,
        },
    ),
    (
        "profile-only",
        TallySet {
            absorption_rz: false,
            absorption_rz_se: false,
            surface_xy: 0,
        },
    ),
];

/// Channel R of each material on its thesis grid, with each of [`THROUGHPUT_TALLIES`],
/// `photons` packets each.
pub fn throughput(
    materials: &[(&str, &Material, u64)],
    config: &SimConfig,
) -> Result<Vec<Throughput>> {
    let mut rows = Vec::new();
    for &(name, m, photons) in materials {
        let grid = config.grid_for(m)?;
        for (label, tallies) in THROUGHPUT_TALLIES {
            let spec = RunSpec {
                sample: Sample {
                    n_above: config.n_above,
                    n_below: config.n_below,
                    layers: vec![m.layer(0, config.thickness_cm)],
                },
                grid,
                photons,
                seed: 1,
                tallies,
            };
            let t = Instant::now();
            let o = run(&spec, &|_| {})?;
            let s = t.elapsed().as_secs_f64();
            rows.push(Throughput {
                material: name.into(),
                channel: "R",
                tallies: label,
                photons,
                seconds: s,
                photons_per_s: photons as f64 / s,
                events_per_s: o.interactions as f64 / s,
                events_per_photon: o.interactions as f64 / photons as f64,
            });
        }
    }
    Ok(rows)
}

/// One channel of one run of [`time_vs_error`].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TimeVsError {
    /// The material.
    pub material: String,
    /// Photon packets per channel.
    pub photons: u64,
    /// Wall time of the material's run (three channels) [s].
    pub seconds: f64,
    /// The channel.
    pub channel: &'static str,
    /// Relative standard error of total Rd.
    pub rel_se_rd: f64,
    /// Relative standard error of Rd(r) one mean free path out.
    pub rel_se_rd_r_1mfp: f64,
    /// Relative standard error of Rd(r) three mean free paths out.
    pub rel_se_rd_r_3mfp: f64,
}

/// The three channels of each material in one profile-only walk at 10⁴, 10⁵, … up to
/// `max_photons`: run time against the standard errors of Rd and Rd(r).
pub fn time_vs_error(
    materials: &[(&str, &Material)],
    config: &SimConfig,
    max_photons: u64,
) -> Result<Vec<TimeVsError>> {
    let mut rows = Vec::new();
    for &(name, m) in materials {
        let mut photons = 10_000u64;
        while photons <= max_photons {
            let spec = config.batch(&[m], photons, 1, true)?;
            let t = Instant::now();
            let out = run_batch(&spec, &|_| {})?;
            let s = t.elapsed().as_secs_f64();
            for (c, o) in out.iter().enumerate() {
                rows.push(TimeVsError {
                    material: name.into(),
                    photons,
                    seconds: s,
                    channel: CHANNELS[c],
                    rel_se_rd: o.rd.se / o.rd.value,
                    rel_se_rd_r_1mfp: rel_at(o, m.mfp(c)),
                    rel_se_rd_r_3mfp: rel_at(o, 3.0 * m.mfp(c)),
                });
            }
            photons *= 10;
        }
    }
    Ok(rows)
}

/// Relative standard error of Rd(r) in the bin containing radius `r` [cm] (∞ where it is 0).
fn rel_at(o: &Output, r: f64) -> f64 {
    let i = ((r / o.grid.dr) as usize).min(o.grid.nr - 1);
    if o.rd_r[i].value > 0.0 {
        o.rd_r[i].se / o.rd_r[i].value
    } else {
        f64::INFINITY
    }
}

/// Batch tracing against one walk per channel.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Batching {
    /// Photon packets per channel.
    pub photons: u64,
    /// Channels.
    pub channels: usize,
    /// Walk groups of the batch (channels that are the same walk share one).
    pub groups: usize,
    /// Wall time of the batch [s].
    pub batched_seconds: f64,
    /// Wall time of the channels run one by one [s].
    pub separate_seconds: f64,
}

/// Every channel of `materials`, profile-only, `photons` each: one batch against one run per
/// channel.
pub fn batching(materials: &[&Material], config: &SimConfig, photons: u64) -> Result<Batching> {
    let spec = config.batch(materials, photons, 1, true)?;
    let t = Instant::now();
    run_batch(&spec, &|_| {})?;
    let batched_seconds = t.elapsed().as_secs_f64();
    let t = Instant::now();
    for c in &spec.channels {
        let one = BatchSpec {
            channels: vec![*c],
            ..spec.clone()
        };
        run_batch(&one, &|_| {})?;
    }
    Ok(Batching {
        photons,
        channels: spec.channels.len(),
        groups: spec.groups().len(),
        batched_seconds,
        separate_seconds: t.elapsed().as_secs_f64(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each measurement has its rows with finite numbers; the batch of two materials with the
    /// same walks in mean free paths shares them.
    #[test]
    fn measurements_are_complete() {
        let config = SimConfig::thesis().unwrap();
        let m = Material {
            name: "m".into(),
            source: String::new(),
            sigma_a: [0.5, 1.0, 2.0],
            sigma_s: [10.0, 10.0, 10.0],
            g: [0.0; 3],
            eta: 1.3,
            thickness: None,
        };
        // The same medium at twice the density: every channel is the same walk as m's.
        let dense = Material {
            sigma_a: m.sigma_a.map(|x| 2.0 * x),
            sigma_s: m.sigma_s.map(|x| 2.0 * x),
            ..m.clone()
        };
        let t = throughput(&[("m", &m, 500)], &config).unwrap();
        assert_eq!(t.len(), THROUGHPUT_TALLIES.len());
        assert!(
            t.iter()
                .all(|r| r.photons_per_s > 0.0 && r.events_per_photon > 0.0)
        );
        let e = time_vs_error(&[("m", &m)], &config, 10_000).unwrap();
        assert_eq!(e.len(), 3);
        assert!(
            e.iter()
                .all(|r| r.rel_se_rd.is_finite() && r.rel_se_rd > 0.0)
        );
        let b = batching(&[&m, &dense], &config, 1000).unwrap();
        assert_eq!((b.channels, b.groups), (6, 3));
        assert!(b.batched_seconds > 0.0 && b.separate_seconds > 0.0);
    }
}
