//! One material's [`Shading`] as a renderer uploads it: [`PackedShading`], the bytes of WGSL's
//! `SssMaterial` (`wgsl/material.wgsl`), which `gpu`'s scene pass keeps in a uniform block and an
//! exported package writes as `tables.bin`; and the WGSL that reads it ([`LOOKUPS_WGSL`],
//! [`BINDINGS_WGSL`]).

use crate::angle_tables::{EXIT_WGSL, INCIDENCE_WGSL, incidence_hemispherical};
use crate::angles::{ANGLES_WGSL, INCIDENCE_STEPS};
use crate::entry_shift::{ENTRY_SHIFT_WGSL, EntryShift};
use crate::fresnel::FRESNEL_WGSL;
use crate::model::Shading;
use crate::shape::{
    CURVATURE_STEPS, SHAPE_CURVATURES, SHAPE_THICKNESSES, SHAPE_WGSL, THICKNESS_STEPS,
};
use crate::translucency::{TRANSLUCENCY_STEPS, TRANSLUCENCY_WGSL};

/// WGSL's `struct SssMaterial`, the layout of [`PackedShading`].
pub const MATERIAL_WGSL: &str = include_str!("wgsl/material.wgsl");

/// Every lookup a renderer does in the tables, in one WGSL source: `fresnel`, `angle_index`,
/// `sss_incidence`, `sss_exit`, `sss_entry_shift`, `sss_entry_offset`, `sss_translucency`,
/// `sss_translucency_exit`, `sss_back_face_entry`, `sss_shape_energy`, `sss_shape_shift`,
/// `sss_shape_width`, `sss_shape_thin` and `struct SssMaterial`. The lookups read the tables through eleven accessors the host defines
/// (`sss_incidence_entry(m, k)`, …): [`BINDINGS_WGSL`] over a storage buffer, or a renderer's own (`gpu`'s over its uniform block).
pub const LOOKUPS_WGSL: &str = const_format::concatcp!(
    FRESNEL_WGSL,
    "\n",
    ANGLES_WGSL,
    "\n",
    INCIDENCE_WGSL,
    "\n",
    EXIT_WGSL,
    "\n",
    ENTRY_SHIFT_WGSL,
    "\n",
    TRANSLUCENCY_WGSL,
    "\n",
    SHAPE_WGSL,
    "\n",
    MATERIAL_WGSL
);

/// The accessors over a storage buffer of [`PackedShading`]s at group 0, binding 0
/// (`wgsl/bindings.wgsl`): what an exported package binds.
pub const BINDINGS_WGSL: &str = include_str!("wgsl/bindings.wgsl");

/// One material's tables as WGSL's `SssMaterial` holds them: every member a `vec4<f32>` (rgb and
/// a spare), so the bytes are the same in uniform and storage buffers (std140 and std430).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct PackedShading {
    /// ρ(θ)/ρ(0) at θ = 0°, 10°, …, 80° (rgb).
    pub incidence: [[f32; 4]; INCIDENCE_STEPS],
    /// The ambient light's factor, the incidence table's cosine-weighted hemispherical mean
    /// (rgb).
    pub incidence_ambient: [f32; 4],
    /// Tt(d)/ρ at the thicknesses of [`crate::Translucency`] (rgb).
    pub translucency: [[f32; 4]; TRANSLUCENCY_STEPS],
    /// x: first thickness [cm], y: ln ratio, z: 1 on / 0 off, w: η ([`Shading::eta`]).
    pub translucency_params: [f32; 4],
    /// h_T(θ; d_k) at θ = 0°, 10°, …, 80° for each thickness d_k, [9·k + θ index] (rgb).
    pub translucency_exit: [[f32; 4]; TRANSLUCENCY_STEPS * INCIDENCE_STEPS],
    /// h(θ_o; θ_i) at 0°, 10°, …, 80°, [9·i + o] (rgb).
    pub exit: [[f32; 4]; INCIDENCE_STEPS * INCIDENCE_STEPS],
    /// The entry shift δ(θ) [cm] at 0°, 10°, …, 80° (rgb); w of the first: 1 on, 0 off.
    pub shift: [[f32; 4]; INCIDENCE_STEPS],
    /// The shape table ([`crate::ShapeTable`]): rgb σ_tr per channel [cm⁻¹], w: 1 on, 0 off.
    pub shape_params: [f32; 4],
    /// Its curvature nodes κ [-] ([`SHAPE_CURVATURES`]), four per vec4, the last slot 0.
    pub shape_grid: [[f32; 4]; SHAPE_GRID_VEC4],
    /// E, ⟨x⟩ [cm] and ⟨s⟩ [cm] (quantity q = 0, 1, 2) at node i and θ = 0°, 10°, …, 80°,
    /// [135·q + 9·i + θ index] (rgb; E ones, ⟨x⟩ and ⟨s⟩ zeros when off).
    pub shape: [[f32; 4]; 3 * CURVATURE_STEPS * INCIDENCE_STEPS],
    /// The slabs' thicknesses τ [-] ([`SHAPE_THICKNESSES`]), four per vec4, the last slots 0.
    pub shape_slab_grid: [[f32; 4]; SLAB_GRID_VEC4],
    /// E of the slab of node k at θ = 0°, 10°, …, 80°, [9·k + θ index] (rgb; ones when off).
    pub shape_slab: [[f32; 4]; THICKNESS_STEPS * INCIDENCE_STEPS],
}

/// The vec4 that hold the curvature nodes.
const SHAPE_GRID_VEC4: usize = CURVATURE_STEPS.div_ceil(4);

/// The vec4 that hold the slabs' thicknesses.
const SLAB_GRID_VEC4: usize = THICKNESS_STEPS.div_ceil(4);

/// The vec4 of [`PackedShading`] and of WGSL's `SssMaterial`: 718.
pub const PACKED_SHADING_VEC4: usize = 10
    + 17
    + 16 * 9
    + 9 * 9
    + 9
    + 1
    + SHAPE_GRID_VEC4
    + 3 * CURVATURE_STEPS * 9
    + SLAB_GRID_VEC4
    + THICKNESS_STEPS * 9;

/// The size of [`PackedShading`] and of WGSL's `SssMaterial` [bytes].
pub const PACKED_SHADING_SIZE: usize = PACKED_SHADING_VEC4 * 16;
const _: () = assert!(std::mem::size_of::<PackedShading>() == PACKED_SHADING_SIZE);

impl PackedShading {
    /// The tables of `s` as uploaded; a translucency that is off keeps zeros for Tt/ρ and ones
    /// for h_T (with grid 1 cm, ln ratio 1: finite lookups), a shape table that is off ones for E
    /// (curved bodies and slabs) and zeros for ⟨x⟩ and ⟨s⟩ (with σ_tr 1 cm⁻¹).
    pub fn new(s: &Shading) -> PackedShading {
        let rgb = |r: [f32; 3]| [r[0], r[1], r[2], 0.0];
        PackedShading {
            incidence: s.incidence.map(rgb),
            incidence_ambient: rgb(incidence_hemispherical(&s.incidence)),
            translucency: match &s.translucency {
                Some(t) => t.table.map(rgb),
                None => [[0.0; 4]; TRANSLUCENCY_STEPS],
            },
            translucency_params: match &s.translucency {
                Some(t) => [t.first_cm, t.ratio.ln(), 1.0, s.eta],
                None => [1.0, 1.0, 0.0, s.eta],
            },
            translucency_exit: match &s.translucency {
                Some(t) => {
                    std::array::from_fn(|i| rgb(t.exit[i / INCIDENCE_STEPS][i % INCIDENCE_STEPS]))
                }
                None => [[1.0; 4]; TRANSLUCENCY_STEPS * INCIDENCE_STEPS],
            },
            exit: std::array::from_fn(|i| rgb(s.exit[i / INCIDENCE_STEPS][i % INCIDENCE_STEPS])),
            shift: {
                let mut t = s.entry_shift.shift_cm.map(rgb);
                t[0][3] = (s.entry_shift != EntryShift::NONE) as u32 as f32;
                t
            },
            shape_params: match &s.shape {
                Some(t) => {
                    let [r, g, b] = t.sigma_tr.map(|v| v as f32);
                    [r, g, b, 1.0]
                }
                None => [1.0, 1.0, 1.0, 0.0],
            },
            shape_grid: std::array::from_fn(|j| {
                std::array::from_fn(|i| SHAPE_CURVATURES.get(4 * j + i).copied().unwrap_or(0.0))
            }),
            shape: std::array::from_fn(|j| {
                let per = CURVATURE_STEPS * INCIDENCE_STEPS;
                let (q, i, k) = (j / per, j % per / INCIDENCE_STEPS, j % INCIDENCE_STEPS);
                match &s.shape {
                    Some(t) => rgb(t.curvature[i][k]
                        .map(|e| [e.energy, e.shift_cm, e.width_cm][q].value as f32)),
                    None => [[1.0; 4], [0.0; 4], [0.0; 4]][q],
                }
            }),
            shape_slab_grid: std::array::from_fn(|j| {
                std::array::from_fn(|i| SHAPE_THICKNESSES.get(4 * j + i).copied().unwrap_or(0.0))
            }),
            shape_slab: std::array::from_fn(|j| {
                let (i, k) = (j / INCIDENCE_STEPS, j % INCIDENCE_STEPS);
                match &s.shape {
                    Some(t) => rgb(t.thickness[i][k].map(|e| e.energy.value as f32)),
                    None => [1.0; 4],
                }
            }),
        }
    }
}
