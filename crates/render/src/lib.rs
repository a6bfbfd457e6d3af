//! `render`: a render assembled as a whole. One [`Request`] (scene, materials, image, camera,
//! lights, method and every shading option) is checked at once, each refusal naming the field;
//! [`Plan::build`] turns it into the scene, the renderer's settings with each material's shading
//! tables (`shading`, simulated by `mc`), the kernels (`fit`) or a gather's set-up; and
//! [`Plan::render`] draws the frame (`gpu`); [`Package`] keeps what an engine needs of a plan
//! (the kernel, the tables, the lookups in WGSL, GLSL and HLSL). The command line (`sss render`) and Python
//! (`sss.render`) both map their arguments onto a [`Request`], so the same arguments give the same
//! image.
//!
//! The default request is the method the references measure closest to path tracing:
//! pre-integration with the incidence table, the exit law at the entry angle, the entry shift and
//! light through thin parts.

#![deny(missing_docs)]
// Units are written in brackets as in the papers, [cm⁻¹]; rustdoc would take them for links.
#![allow(rustdoc::broken_intra_doc_links)]

mod error;
pub mod folder;
pub mod options;
pub mod package;
pub mod parse;
pub mod plan;
pub mod profile_cache;
pub mod progress;
pub mod reference;
pub mod request;
pub mod summary;
pub mod tables;
pub mod view;

pub use error::{RenderError, Result};
pub use options::{Choice, DipoleEnergy, ExitLaw};
pub use package::Package;
pub use plan::{Gather, KernelChoice, Plan, Profiles, Simulated, describe};
pub use profile_cache::{Cached, ProfileCache};
pub use progress::Progress;
pub use reference::{Reference, SceneView};
pub use request::{
    GatherOptions, NamedMaterial, Request, ResolvedShading, ShadingOptions, TableSettings,
};
pub use tables::MaterialTables;
pub use view::{Site, SiteScene};
