//! The sample as the shader reads it: MCML's layers with their bounds and derived coefficients
//! (mc's `Medium`, crates/mc/src/photon.rs), computed in f64 on the host and uploaded in f32.
//!
//! Units: the walk's lengths. A run of a [`mc::Sample`] walks in cm (coefficients in cm⁻¹); a
//! batch channel walks in its mean free paths 1/μt (μt = 1), as mc's batches do, and its tallies
//! are binned at r·[`Walk::scale`] on the channel's grid in cm. +z points into the sample.

use bytemuck::{Pod, Zeroable};
use mc::{BatchSpec, Layer, QUASI_INFINITE_MFP, Sample, cos_critical, specular};

use crate::error::{McGpuError, Result};

/// Most layers the shader walks (its per-history deposit array).
pub const MAX_LAYERS: usize = 16;

/// A layer prepared for transport; `tracer.wgsl`'s `Slab`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub(crate) struct Slab {
    /// Top and bottom [length unit].
    z0: f32,
    z1: f32,
    /// Refractive index [-].
    n: f32,
    /// μt = μa + μs [1/length unit].
    mu_t: f32,
    /// μa/μt [-].
    absorb: f32,
    /// Henyey–Greenstein anisotropy [-].
    pub g: f32,
    /// Cosines of the critical angles going up and down out of the layer.
    cos_crit_up: f32,
    cos_crit_down: f32,
    /// Indices above and below.
    n_up: f32,
    n_down: f32,
    /// μ_eff = √(3μa(μa + μs(1 − g))) [1/length unit] and ∫ μ_eff dz down to z0 [-].
    mu_eff: f32,
    tau0: f32,
}

impl Slab {
    /// Whether the layer neither absorbs nor scatters (MCML's glass).
    pub fn is_glass(&self) -> bool {
        self.mu_t == 0.0
    }
}

/// What one walk needs: the layers, where photons start and with what weight, and the length of
/// one walk unit.
#[derive(Clone, Debug)]
pub(crate) struct Walk {
    pub slabs: Vec<Slab>,
    /// Layer photons are launched into (1 under a glass top layer).
    pub first: u32,
    /// Specular reflectance at entry [-] (f64: the output's Rsp is the CPU's, exactly).
    pub rsp: f64,
    /// ∫ μ_eff dz over the whole sample [-].
    pub tau_total: f64,
    /// Whether photons play mc's importance roulette (runs that tally nothing below the surface).
    pub importance: bool,
    /// One walk length unit in cm.
    pub scale: f64,
}

impl Walk {
    /// The walk of `sample` in its own units (cm), one walk unit being `scale` cm, at normal
    /// incidence (MCML's launch: Rsp with a glass top layer's multiple reflections, eq. 3.1-3.3).
    pub fn new(sample: &Sample, importance: bool, scale: f64) -> Result<Walk> {
        let ls = &sample.layers;
        if ls.len() > MAX_LAYERS {
            return Err(McGpuError::Unsupported {
                what: format!("{} layers", ls.len()),
                reason: format!("at most {MAX_LAYERS}"),
            });
        }
        let (mut z, mut tau) = (0.0, 0.0);
        let mut slabs = Vec::with_capacity(ls.len());
        for (i, l) in ls.iter().enumerate() {
            let n_up = if i == 0 { sample.n_above } else { ls[i - 1].n };
            let n_down = ls.get(i + 1).map_or(sample.n_below, |b| b.n);
            let mu_eff = (3.0 * l.mu_a * (l.mu_a + l.mu_s * (1.0 - l.g))).sqrt();
            slabs.push(Slab {
                z0: z as f32,
                z1: (z + l.thickness) as f32,
                n: l.n as f32,
                mu_t: l.mu_t() as f32,
                absorb: if l.is_glass() {
                    0.0
                } else {
                    (l.mu_a / l.mu_t()) as f32
                },
                g: l.g as f32,
                cos_crit_up: cos_critical(l.n, n_up) as f32,
                cos_crit_down: cos_critical(l.n, n_down) as f32,
                n_up: n_up as f32,
                n_down: n_down as f32,
                mu_eff: mu_eff as f32,
                tau0: tau as f32,
            });
            z += l.thickness;
            tau += mu_eff * l.thickness;
        }
        let glass_first = ls[0].is_glass() && ls.len() > 1;
        Ok(Walk {
            slabs,
            first: u32::from(glass_first),
            rsp: specular(sample.n_above, ls[0].n, glass_first.then(|| ls[1].n)),
            tau_total: tau,
            importance,
            scale,
        })
    }

    /// The walk of a batch's channel `c`, as mc's batches trace it: the layer in its mean free
    /// paths (μt = 1, μa = 1 − albedo), at most [`QUASI_INFINITE_MFP`] thick; a layer that does
    /// not interact walks in cm.
    pub fn of_channel(spec: &BatchSpec, c: usize) -> Result<Walk> {
        let layer = spec.channels[c].layer;
        let (walk, scale) = channel_walk(&layer);
        let sample = Sample {
            n_above: spec.n_above,
            n_below: spec.n_below,
            layers: vec![walk],
        };
        Walk::new(&sample, !spec.tallies.absorption_rz, scale)
    }
}

/// A channel's layer in walk units and the length of one unit [cm] (mc's `batch::walk`).
pub(crate) fn channel_walk(layer: &Layer) -> (Layer, f64) {
    if layer.is_glass() {
        return (*layer, 1.0);
    }
    let mu_t = layer.mu_t();
    let absorb = layer.mu_a / mu_t;
    let walk = Layer {
        n: layer.n,
        mu_a: absorb,
        mu_s: 1.0 - absorb,
        g: layer.g,
        thickness: (mu_t * layer.thickness).min(QUASI_INFINITE_MFP),
    };
    (walk, 1.0 / mu_t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_glass_top_layer_launches_below_it_with_mcml_specular() {
        let glass = Layer {
            n: 1.5,
            mu_a: 0.0,
            mu_s: 0.0,
            g: 0.0,
            thickness: 0.1,
        };
        let tissue = Layer {
            n: 1.33,
            mu_a: 1.0,
            mu_s: 100.0,
            g: 0.9,
            thickness: 0.2,
        };
        let sample = Sample {
            n_above: 1.0,
            n_below: 1.0,
            layers: vec![glass, tissue],
        };
        let w = Walk::new(&sample, false, 1.0).unwrap();
        assert_eq!(w.first, 1);
        assert_eq!(w.rsp, specular(1.0, 1.5, Some(1.33)));
        assert_eq!((w.slabs[1].z0, w.slabs[1].z1), (0.1, 0.3f64 as f32));
        assert_eq!(w.slabs[0].cos_crit_down, cos_critical(1.5, 1.33) as f32);
    }

    #[test]
    fn a_channel_walks_in_mean_free_paths() {
        let l = Layer {
            n: 1.3,
            mu_a: 1.0,
            mu_s: 9.0,
            g: 0.5,
            thickness: 1e8,
        };
        let (w, scale) = channel_walk(&l);
        assert_eq!(
            (w.mu_a + w.mu_s, w.thickness, scale),
            (1.0, QUASI_INFINITE_MFP, 0.1)
        );
        assert!(
            Walk::new(
                &Sample {
                    n_above: 1.0,
                    n_below: 1.0,
                    layers: vec![l; 17]
                },
                true,
                1.0
            )
            .is_err()
        );
    }
}
