//! `shading`: the shading model a renderer reads around subsurface scattering, per material, as
//! plain data with standard errors, built from `mc` (Monte Carlo in the material itself) and
//! `fit` (its media), each table with the CPU twin of the lookup the shaders do and the WGSL
//! that does it:
//!
//! - [`AngleTables`]: ρ(θ)/ρ(0), the total diffuse reflectance against the angle of incidence,
//!   and h(θ_o; θ_i), the exit law for light that entered at each angle ([`angle_tables`]);
//! - [`EntryShift`]: δ(θ), where a half-space returns obliquely entering light on average
//!   ([`entry_shift`]);
//! - [`Translucency`]: a slab's transmittance against thickness and its exit law
//!   ([`translucency`]);
//! - [`ShapeTable`]: what a sphere, a cavity or a slab returns near the entry against the
//!   half-space, over curvature and thickness in diffusion lengths, with its shift and width
//!   ([`shape`]), and the curvature a mesh has at the scale light travels in it, per vertex
//!   ([`curvature`]: what a real-time pass reads the shape table at);
//! - [`DirectionalTable`]: `mc`'s Rd(x, y; θ) for the directional surface gather
//!   ([`directional`]);
//! - [`KernelTaps`]: a separable kernel's taps as uploaded ([`kernel`]);
//! - [`Shading`]: the set one material is shaded with ([`model`]), and [`PackedShading`], its
//!   bytes as a renderer uploads them ([`packed`]);
//! - [`SimulatedProfile`]: the radial profile Rd(r) its kernels and the surface gather read
//!   ([`profile`]).
//!
//! Angles are tabulated at θ = 0°, 10°, …, 80° ([`INCIDENCE_STEPS`], [`angles`]); lengths are cm,
//! reflectances per unit incident power. Each lookup's WGSL is one file beside its table
//! (`src/wgsl/`), all of them in [`LOOKUPS_WGSL`]: they read the tables through accessors the
//! host defines, so a renderer and an exported package run the same functions. Nothing here
//! needs a GPU: `gpu` uploads these tables and its tests compare the shaders against the twins
//! here.

#![deny(missing_docs)]
// Units are written in brackets as in the papers, [cm⁻¹]; rustdoc would take them for links.
#![allow(rustdoc::broken_intra_doc_links)]

pub mod angle_tables;
pub mod angles;
pub mod check;
pub mod curvature;
pub mod directional;
pub mod entry_shift;
mod error;
pub mod fresnel;
pub mod kernel;
pub mod model;
pub mod packed;
pub mod profile;
pub mod shaders;
pub mod shape;
pub mod translucency;

pub use angle_tables::{
    AngleTables, EXIT_WGSL, ExitTable, INCIDENCE_WGSL, exit_ratio, incidence_hemispherical,
};
pub use angles::{ANGLES_WGSL, INCIDENCE_STEPS, incidence_ratio};
pub use check::{CHECK_INPUTS, CHECK_OUTPUTS, CHECK_WGSL, CheckSample};
pub use curvature::{SurfaceMesh, light_scale_curvature};
pub use directional::{
    Bssrdf, DIRECTIONAL_ANGLES, DIRECTIONAL_HALF_WIDTH, DirectionalTable, GatherTables,
    gather_batch_runs, gather_tables,
};
pub use entry_shift::{
    ENTRY_SHIFT_WGSL, EntryShift, SHIFT_GRID_HALF_WIDTH, SHIFT_GRID_REACH_MFP, entry_offset,
};
pub use error::{Result, ShadingError};
pub use fresnel::{FRESNEL_WGSL, back_face_entry, fresnel};
pub use kernel::{KernelTaps, MAX_PASSES, MAX_TAPS};
/// The input types of this crate's builders, from `mc`: a material's coefficients, the run
/// settings, a batch of its channels, an estimate with its standard error.
pub use mc::{BatchSpec, Estimate, Material, SimConfig};
pub use model::Shading;
pub use packed::{
    BINDINGS_WGSL, LOOKUPS_WGSL, MATERIAL_WGSL, PACKED_SHADING_SIZE, PACKED_SHADING_VEC4,
    PackedShading,
};
pub use profile::SimulatedProfile;
pub use shaders::{CHECK_ENTRY, ShaderSources};
pub use shape::{
    CURVATURE_STEPS, HALF_SPACE_NODE, SHAPE_CURVATURES, SHAPE_PHOTONS, SHAPE_RUNS_PER_CHANNEL,
    SHAPE_THICKNESSES, SHAPE_WGSL, SHAPE_WINDOW, ShapeEntry, ShapeFactors, ShapeTable,
    THICKNESS_STEPS,
};
pub use translucency::{RHO_PHOTONS, TRANSLUCENCY_STEPS, TRANSLUCENCY_WGSL, Translucency};
