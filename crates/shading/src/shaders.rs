//! The lookups in the three shading languages an engine takes: WGSL as written
//! ([`crate::LOOKUPS_WGSL`] with [`crate::BINDINGS_WGSL`] and the self-test [`crate::CHECK_WGSL`]),
//! GLSL 4.50 and HLSL (shader model 5.1) translated from it by naga. One source: the GLSL and
//! HLSL are what naga makes of the WGSL our renderer runs, and `gpu`'s tests run all three on a
//! GPU against the CPU twins.

use crate::check::CHECK_WGSL;
use crate::error::{Result, ShadingError};
use crate::packed::{BINDINGS_WGSL, LOOKUPS_WGSL};

/// The self-test's entry point in every language.
pub const CHECK_ENTRY: &str = "sss_check";

/// The lookups, the package's bindings and the self-test, in WGSL, GLSL and HLSL.
#[derive(Clone, Debug, PartialEq)]
pub struct ShaderSources {
    /// WGSL: the source.
    pub wgsl: String,
    /// GLSL 4.50 (Vulkan and OpenGL 4.5): the tables at binding 0, the self-test's input and
    /// output at 1 and 2 (std430 storage blocks).
    pub glsl: String,
    /// HLSL, shader model 5.1: the tables at register t0, the self-test's input at t1 and output
    /// at u2 (byte-address buffers), space 0.
    pub hlsl: String,
}

impl ShaderSources {
    /// Translates the WGSL with naga; an error names the language that failed.
    pub fn new() -> Result<ShaderSources> {
        let wgsl = format!("{LOOKUPS_WGSL}\n{BINDINGS_WGSL}\n{CHECK_WGSL}");
        let fail = |what: &str, e: String| ShadingError::Shader(format!("{what}: {e}"));
        let module = naga::front::wgsl::parse_str(&wgsl)
            .map_err(|e| fail("WGSL", e.emit_to_string(&wgsl)))?;
        let info = naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::default(),
        )
        .validate(&module)
        .map_err(|e| fail("WGSL", format!("{e:?}")))?;
        let bindings = 0..3u32;
        let group = |binding| naga::ResourceBinding { group: 0, binding };

        let mut glsl = String::new();
        let options = naga::back::glsl::Options {
            version: naga::back::glsl::Version::Desktop(450),
            writer_flags: naga::back::glsl::WriterFlags::empty(),
            binding_map: bindings.clone().map(|b| (group(b), b as u8)).collect(),
            zero_initialize_workgroup_memory: true,
        };
        let pipeline = naga::back::glsl::PipelineOptions {
            shader_stage: naga::ShaderStage::Compute,
            entry_point: CHECK_ENTRY.into(),
            multiview: None,
        };
        naga::back::glsl::Writer::new(
            &mut glsl,
            &module,
            &info,
            &options,
            &pipeline,
            naga::proc::BoundsCheckPolicies::default(),
        )
        .and_then(|mut w| w.write().map(|_| ()))
        .map_err(|e| fail("GLSL", e.to_string()))?;

        let mut hlsl = String::new();
        let options = naga::back::hlsl::Options {
            shader_model: naga::back::hlsl::ShaderModel::V5_1,
            binding_map: bindings
                .map(|b| {
                    let target = naga::back::hlsl::BindTarget {
                        space: 0,
                        register: b,
                        ..Default::default()
                    };
                    (group(b), target)
                })
                .collect(),
            ..Default::default()
        };
        let pipeline = naga::back::hlsl::PipelineOptions { entry_point: None };
        naga::back::hlsl::Writer::new(&mut hlsl, &options, &pipeline)
            .write(&module, &info, None)
            .map_err(|e| fail("HLSL", e.to_string()))?;
        Ok(ShaderSources { wgsl, glsl, hlsl })
    }
}
