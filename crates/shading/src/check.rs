//! The lookups' self-test: [`CHECK_WGSL`] evaluates every WGSL lookup of [`crate::LOOKUPS_WGSL`]
//! at sampled inputs on a GPU; [`CheckSample::expected`] gives what the CPU twins say there. `gpu`'s
//! tests run it on lavapipe for the WGSL and for the GLSL and HLSL an exported package carries.

use crate::angle_tables::exit_ratio;
use crate::angles::incidence_ratio;
use crate::entry_shift::entry_offset;
use crate::fresnel::{back_face_entry, fresnel};
use crate::model::Shading;

/// The compute entry point `sss_check` (workgroup size 64; inputs at binding 1, outputs at
/// binding 2, the tables at binding 0 through [`crate::BINDINGS_WGSL`]): `wgsl/check.wgsl`.
pub const CHECK_WGSL: &str = include_str!("wgsl/check.wgsl");

/// vec4 outputs per sample of [`CHECK_WGSL`].
pub const CHECK_OUTPUTS: usize = 10;

/// vec4 inputs per sample of [`CHECK_WGSL`].
pub const CHECK_INPUTS: usize = 4;

/// One set of inputs of every lookup.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CheckSample {
    /// The material's index in the tables.
    pub material: u32,
    /// cos θ_o, the exit (view) angle's cosine.
    pub cos_o: f32,
    /// cos θ_i, the entry angle's cosine.
    pub cos_i: f32,
    /// A thin part's thickness [cm] (translucency), and the body's chord along the light
    /// (`sss_shape_thin`).
    pub d_cm: f32,
    /// The unit normal.
    pub n: [f32; 3],
    /// The boundary's relative index η.
    pub eta: f32,
    /// The unit direction towards the light.
    pub l: [f32; 3],
    /// An entry shift δ [cm].
    pub delta_cm: f32,
    /// The surface's signed curvature [cm⁻¹] (±1/R, > 0 convex).
    pub curvature_per_cm: f32,
}

impl CheckSample {
    /// The input buffer of [`CHECK_WGSL`] for `samples`: their count, then each one's
    /// [`CheckSample::input`].
    pub fn buffer(samples: &[CheckSample]) -> Vec<[f32; 4]> {
        let mut b = vec![[samples.len() as f32, 0.0, 0.0, 0.0]];
        b.extend(samples.iter().flat_map(CheckSample::input));
        b
    }

    /// The [`CHECK_INPUTS`] vec4 [`CHECK_WGSL`] reads for this sample.
    pub fn input(&self) -> [[f32; 4]; CHECK_INPUTS] {
        let (n, l) = (self.n, self.l);
        [
            [self.material as f32, self.cos_o, self.cos_i, self.d_cm],
            [n[0], n[1], n[2], self.eta],
            [l[0], l[1], l[2], self.delta_cm],
            [self.curvature_per_cm, 0.0, 0.0, 0.0],
        ]
    }

    /// What the CPU twins give for this sample, in [`CHECK_WGSL`]'s order, for the materials
    /// `tables` (a translucency or shape table that is off reads as [`crate::PackedShading`]
    /// uploads it).
    pub fn expected(&self, tables: &[Shading]) -> [[f32; 4]; CHECK_OUTPUTS] {
        let s = &tables[self.material as usize];
        let v = |c: [f32; 3], w: f32| [c[0], c[1], c[2], w];
        let (eta, co, ci) = (self.eta as f64, self.cos_o as f64, self.cos_i as f64);
        let (transmitted, exit) = match &s.translucency {
            Some(t) => (t.at(self.d_cm), t.exit_at(self.d_cm, self.cos_o)),
            None => ([0.0; 3], [1.0; 3]),
        };
        let (k, cos) = (self.curvature_per_cm, self.cos_i);
        let (energy, shift, width, thin) = match &s.shape {
            Some(t) => {
                let f = t.at(k, cos);
                (
                    f.energy,
                    f.shift_cm,
                    t.width_ratio(k, cos),
                    t.thin_factor(k, self.d_cm, cos),
                )
            }
            None => ([1.0; 3], [0.0; 3], [1.0; 3], [1.0; 3]),
        };
        [
            v(
                incidence_ratio(&s.incidence, self.cos_i),
                fresnel(eta, co) as f32,
            ),
            v(
                exit_ratio(&s.exit, self.cos_o, self.cos_i),
                back_face_entry(eta, ci) as f32,
            ),
            v(s.entry_shift.at(self.cos_i), 0.0),
            v(entry_offset(self.n, self.l, self.delta_cm), 0.0),
            v(transmitted, 0.0),
            v(exit, 0.0),
            v(energy, 0.0),
            v(shift, 0.0),
            v(width, 0.0),
            v(thin, 0.0),
        ]
    }
}
