//! The shading model's lookups on the GPU against their CPU twins (`shading::check`): the WGSL
//! our renderer runs, and the GLSL and HLSL an exported package carries (translated from it by
//! naga, compiled to SPIR-V by glslangValidator), each at sampled inputs within 1e-5 of the
//! twins: relative, and for values near 0 relative to the largest of that output over the
//! samples (an entry shift of 0.001 cm is compared at 1e-5 of a tenth of the table's 0.2 cm).

mod common;

use shading::{
    CHECK_ENTRY, CHECK_OUTPUTS, CheckSample, EntryShift, HALF_SPACE_NODE, INCIDENCE_STEPS,
    PackedShading, SHAPE_CURVATURES, ShaderSources, Shading, ShapeTable, TRANSLUCENCY_STEPS,
    Translucency,
};
use wgpu::util::DeviceExt;

/// A deterministic value in [0, 1) from a counter (a 32-bit hash, so tests need no RNG crate).
fn hash01(k: u32) -> f32 {
    let mut x = k.wrapping_mul(0x9E37_79B9) ^ 0x85EB_CA6B;
    x ^= x >> 16;
    x = x.wrapping_mul(0x7FEB_352D);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846C_A68B);
    x ^= x >> 16;
    (x >> 8) as f32 / (1u32 << 24) as f32
}

/// Two materials with tables shaped as measured ones (smooth in angle and thickness: ρ(θ)/ρ(0)
/// falling towards grazing, h rising with θ_o, δ growing with θ, Tt(d)/ρ decaying with d), each
/// entry perturbed by a few per cent so that no two are equal; the second without translucency.
fn materials() -> Vec<Shading> {
    let mut k = 0;
    let mut jitter = || {
        k += 1;
        1.0 + 0.04 * (hash01(k) - 0.5)
    };
    let mut m = |translucent: bool, scale: f32| Shading {
        incidence: std::array::from_fn(|i| {
            std::array::from_fn(|c| {
                (1.0 - 0.5 * scale * (i as f32 / 8.0).powi(2) / (c + 1) as f32) * jitter()
            })
        }),
        exit: std::array::from_fn(|i| {
            std::array::from_fn(|o| {
                std::array::from_fn(|c| (0.8 + 0.05 * (i + o + c) as f32 * scale) * jitter())
            })
        }),
        translucency: translucent.then(|| Translucency {
            first_cm: 0.01,
            ratio: 1.6,
            table: std::array::from_fn(|d| {
                std::array::from_fn(|c| {
                    1.5 * (-0.01 * 1.6f32.powi(d as i32) * (c + 1) as f32).exp() * jitter()
                })
            }),
            exit: std::array::from_fn(|d| {
                std::array::from_fn(|o| {
                    std::array::from_fn(|c| {
                        (1.1 - 0.06 * o as f32 + 0.01 * (d + c) as f32) * jitter()
                    })
                })
            }),
        }),
        entry_shift: EntryShift {
            shift_cm: std::array::from_fn(|i| {
                std::array::from_fn(|c| 0.02 * scale * (i as f32 + 0.5) / (c + 1) as f32 * jitter())
            }),
            shift_se_cm: [[0.001; 3]; INCIDENCE_STEPS],
        },
        // E rising from concave to convex and with θ, ⟨x⟩ growing with θ, ⟨s⟩ with κ; slabs' E below 1.
        shape: translucent.then(|| {
            let mut t = ShapeTable::ones([2.7, 7.3, 14.6]);
            for (i, row) in t.curvature.iter_mut().enumerate() {
                for (k, entries) in row.iter_mut().enumerate() {
                    for (c, e) in entries.iter_mut().enumerate() {
                        let kappa = SHAPE_CURVATURES[i] as f64;
                        let v = (0.6 * kappa * (1.0 + 0.03 * k as f64)).exp() * (c + 1) as f64;
                        e.energy.value = if i == HALF_SPACE_NODE {
                            1.0
                        } else {
                            v * jitter() as f64
                        };
                        e.shift_cm.value = 0.01 * k as f64 * (2.5 + kappa) * jitter() as f64;
                        e.width_cm.value = 0.1 * (1.0 + 0.2 * kappa) / (c + 1) as f64
                            * (1.0 + 0.01 * k as f64)
                            * jitter() as f64;
                    }
                }
            }
            // Slabs keeping less the thinner they are, and less at grazing entry.
            for (i, row) in t.thickness.iter_mut().enumerate() {
                for (k, entries) in row.iter_mut().enumerate() {
                    for (c, e) in entries.iter_mut().enumerate() {
                        e.energy.value = (1.0 - 0.6 * 0.5f64.powi(i as i32) / (c + 1) as f64)
                            * (1.0 - 0.02 * k as f64)
                            * jitter() as f64;
                    }
                }
            }
            t
        }),
        eta: 1.4,
    };
    vec![m(true, 1.0), m(false, 0.6)]
}

/// Samples over every branch: cosines across the grid, beyond 80° and from behind, exact grid
/// angles, thicknesses below, across and beyond the table, η from 1 to 2.5, light along the
/// normal (no shift) and at every angle.
fn samples() -> Vec<CheckSample> {
    let unit = |v: [f32; 3]| {
        let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        v.map(|c| c / n)
    };
    let first = 0.01f32;
    let last = first * 1.6f32.powi(TRANSLUCENCY_STEPS as i32 - 1);
    (0..1024u32)
        .map(|i| {
            let h = |j: u32| hash01(10_000 + 8 * i + j);
            let grid = |x: f32| {
                if i % 7 == 0 {
                    (10.0 * (x * 9.0).floor()).to_radians().cos()
                } else {
                    1.2 * x - 0.2
                }
            };
            let n = unit([h(0) - 0.5, h(1) - 0.5, h(2) - 0.5]);
            let l = if i % 11 == 0 {
                n
            } else {
                unit([h(3) - 0.5, h(4) - 0.5, h(5) - 0.5])
            };
            CheckSample {
                material: i % 2,
                cos_o: grid(h(6)),
                cos_i: grid(h(7)),
                d_cm: first * 0.3 * (last / first * 10.0).powf(hash01(20_000 + i)),
                n,
                eta: [1.0, 1.33, 1.4, 2.5][(i % 4) as usize],
                l,
                delta_cm: 0.3 * hash01(30_000 + i),
                // Both signs over 0.03–30 cm⁻¹ (κ beyond the table's ends in every channel),
                // and flat.
                curvature_per_cm: if i % 13 == 0 {
                    0.0
                } else {
                    (hash01(40_000 + i) - 0.5).signum() * 10f32.powf(3.0 * hash01(50_000 + i) - 1.5)
                },
            }
        })
        .collect()
}

/// Runs `module`'s `entry` over the samples with the materials' packed tables; its outputs.
fn run(
    gpu: &gpu::Gpu,
    module: &wgpu::ShaderModule,
    entry: &str,
    tables: &[Shading],
    s: &[CheckSample],
) -> Vec<[f32; 4]> {
    let d = &gpu.device;
    let packed: Vec<PackedShading> = tables.iter().map(PackedShading::new).collect();
    let input = CheckSample::buffer(s);
    let storage = wgpu::BufferUsages::STORAGE;
    let buf = |label, bytes: &[u8], usage| {
        d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytes,
            usage,
        })
    };
    let tables_buf = buf("tables", bytemuck::cast_slice(&packed), storage);
    let in_buf = buf("in", bytemuck::cast_slice(&input), storage);
    let size = (s.len() * CHECK_OUTPUTS * 16) as u64;
    let out_buf = d.create_buffer(&wgpu::BufferDescriptor {
        label: Some("out"),
        size,
        usage: storage | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let entry_of = |binding, read_only| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    };
    // Explicit: a module passed through as SPIR-V has no reflection to derive a layout from.
    let layout = d.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: None,
        entries: &[entry_of(0, true), entry_of(1, true), entry_of(2, false)],
    });
    let pipeline_layout = d.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: None,
        bind_group_layouts: &[Some(&layout)],
        immediate_size: 0,
    });
    let pipeline = d.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(entry),
        layout: Some(&pipeline_layout),
        module,
        entry_point: Some(entry),
        compilation_options: Default::default(),
        cache: None,
    });
    let bind = d.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &layout,
        entries: &[&tables_buf, &in_buf, &out_buf]
            .iter()
            .enumerate()
            .map(|(i, b)| wgpu::BindGroupEntry {
                binding: i as u32,
                resource: b.as_entire_binding(),
            })
            .collect::<Vec<_>>(),
    });
    let mut enc = d.create_command_encoder(&Default::default());
    {
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind, &[]);
        pass.dispatch_workgroups((s.len() as u32).div_ceil(64), 1, 1);
    }
    gpu.queue.submit([enc.finish()]);
    bytemuck::cast_slice(&gpu.read_buffer(&out_buf, size).unwrap()).to_vec()
}

/// Every output of every sample within 1e-5 of the CPU twins: relative to the larger of the
/// value and a tenth of its output's scale (f32 rounding of a lookup is ~10⁻⁷ of its table).
fn assert_twins(language: &str, got: &[[f32; 4]], tables: &[Shading], s: &[CheckSample]) {
    let names = [
        "incidence|fresnel",
        "exit|back face",
        "entry shift",
        "entry offset",
        "translucency",
        "translucency exit",
    ];
    let want: Vec<_> = s.iter().map(|x| x.expected(tables)).collect();
    let scale: Vec<[f32; 4]> = (0..CHECK_OUTPUTS)
        .map(|k| std::array::from_fn(|c| want.iter().map(|w| w[k][c].abs()).fold(0.0, f32::max)))
        .collect();
    let mut worst = 0.0f32;
    for (i, sample) in s.iter().enumerate() {
        for (k, w) in want[i].iter().enumerate() {
            let g = got[i * CHECK_OUTPUTS + k];
            for c in 0..4 {
                let err = (g[c] - w[c]).abs() / w[c].abs().max(0.1 * scale[k][c]).max(1e-30);
                worst = worst.max(err);
                assert!(
                    err <= 1e-5,
                    "{language}: {} [{c}] at {sample:?}: GPU {} CPU {} (relative {err:.2e}; all of \
                     this sample: GPU {:?} CPU {:?})",
                    names[k],
                    g[c],
                    w[c],
                    &got[i * CHECK_OUTPUTS..(i + 1) * CHECK_OUTPUTS],
                    want[i]
                );
            }
        }
    }
    eprintln!(
        "{language}: {} samples, worst relative difference {worst:.2e}",
        s.len()
    );
}

#[test]
fn the_wgsl_lookups_equal_their_cpu_twins() {
    let Some(gpu) = common::gpu() else { return };
    let (tables, s) = (materials(), samples());
    let src = ShaderSources::new().unwrap();
    let module = gpu
        .device
        .create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("lookups"),
            source: wgpu::ShaderSource::Wgsl(src.wgsl.into()),
        });
    assert_twins(
        "WGSL",
        &run(&gpu, &module, CHECK_ENTRY, &tables, &s),
        &tables,
        &s,
    );
}

/// `glslangValidator`'s SPIR-V of `source` (GLSL or, with `hlsl`, HLSL); None (test skipped)
/// without the tool, except under CI=true.
fn spirv(source: &str, hlsl: bool) -> Option<Vec<u32>> {
    let dir = tempfile::tempdir().unwrap();
    let (name, extra): (&str, &[&str]) = if hlsl {
        ("sss.hlsl", &["-D", "-e", CHECK_ENTRY, "-S", "comp"])
    } else {
        ("sss.comp", &[])
    };
    let path = dir.path().join(name);
    std::fs::write(&path, source).unwrap();
    let out = dir.path().join("sss.spv");
    let run = std::process::Command::new("glslangValidator")
        .arg("-V")
        .args(extra)
        .arg(&path)
        .arg("-o")
        .arg(&out)
        .output();
    match run {
        Ok(o) => assert!(
            o.status.success(),
            "glslangValidator refused {name}: {}",
            String::from_utf8_lossy(&o.stdout)
        ),
        Err(e) if std::env::var("CI").as_deref() == Ok("true") => {
            panic!("CI=true and glslangValidator does not run: {e}")
        }
        Err(e) => {
            common::report_skip(&format!("glslangValidator does not run: {e}"));
            return None;
        }
    }
    Some(bytemuck::cast_slice(&std::fs::read(&out).unwrap()).to_vec())
}

/// The adapter with SPIR-V passthrough (the driver compiles glslang's SPIR-V itself, as an
/// engine's would); None (test skipped) without an adapter or the feature, except under CI=true.
fn passthrough_gpu() -> Option<gpu::Gpu> {
    let skip = |why: String| {
        if std::env::var("CI").as_deref() == Ok("true") {
            panic!("CI=true and {why}");
        }
        common::report_skip(&why);
        None
    };
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle());
    let adapter = match pollster::block_on(instance.request_adapter(&Default::default())) {
        Ok(a) => a,
        Err(e) => return skip(format!("no adapter: {e}")),
    };
    let feature = wgpu::Features::PASSTHROUGH_SHADERS;
    if !adapter.features().contains(feature) {
        return skip(format!(
            "{} has no SPIR-V passthrough",
            adapter.get_info().name
        ));
    }
    let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        required_features: feature,
        ..Default::default()
    }))
    .unwrap();
    Some(gpu::Gpu {
        device,
        queue,
        adapter_name: adapter.get_info().name,
        timestamps: false,
        float32_blend: false,
    })
}

#[test]
fn the_glsl_and_hlsl_lookups_equal_their_cpu_twins() {
    let Some(gpu) = passthrough_gpu() else { return };
    let (tables, s) = (materials(), samples());
    let src = ShaderSources::new().unwrap();
    for (language, code, hlsl) in [("GLSL", &src.glsl, false), ("HLSL", &src.hlsl, true)] {
        let Some(words) = spirv(code, hlsl) else {
            return;
        };
        // glslang names a GLSL module's entry point `main`, an HLSL one's by -e.
        let entry = if hlsl { CHECK_ENTRY } else { "main" };
        // SAFETY: the SPIR-V is glslangValidator's output for a compute shader whose bindings are
        // the three storage buffers of `run`'s explicit layout.
        let module = unsafe {
            gpu.device
                .create_shader_module_passthrough(wgpu::ShaderModuleDescriptorPassthrough {
                    label: Some(language),
                    entry_points: vec![wgpu::PassthroughShaderEntryPoint {
                        name: entry.into(),
                        workgroup_size: (64, 1, 1),
                    }]
                    .into(),
                    spirv: Some(words.into()),
                    ..Default::default()
                })
        };
        assert_twins(
            language,
            &run(&gpu, &module, entry, &tables, &s),
            &tables,
            &s,
        );
    }
}
