//! The compute pass: [`Tracer`] compiles the walk once and traces runs of any size in dispatches
//! and rounds.
//!
//! A run of N photons is cut into dispatches of at most [`MAX_DISPATCH_PHOTONS`] (by default
//! sized on the fly to take about [`TARGET_DISPATCH_SECONDS`] each, so that no dispatch runs for
//! seconds on a software rasterizer or trips a desktop GPU's watchdog), grouped in rounds of
//! [`ROUND_PHOTONS`] after which the tallies are read back into the host's exact accumulator.
//! Photon k of the run draws from its own stream of (seed, k), and every sum is an integer, so
//! the dispatch size changes nothing in the result.

use std::time::Instant;

use bytemuck::{Pod, Zeroable};
use gpu::Gpu;
use mc::{Accumulator, Grid, Layout};

use crate::error::{McGpuError, Result};
use crate::medium::Walk;
use crate::tally::{ROUND_PHOTONS, add_round, words};

/// The walk's WGSL, its parts in order.
pub const TRACER_WGSL: &str = concat!(
    include_str!("rng.wgsl"),
    include_str!("fresnel.wgsl"),
    include_str!("phase.wgsl"),
    include_str!("tally.wgsl"),
    include_str!("tracer.wgsl"),
);

/// Invocations per workgroup (`tracer.wgsl`'s `@workgroup_size`).
const WORKGROUP: u32 = 64;
/// Most invocations of one dispatch: each traces photons one after another until the dispatch's
/// are done.
const MAX_INVOCATIONS: u32 = 1 << 16;
/// Most photons of one dispatch.
pub const MAX_DISPATCH_PHOTONS: u32 = 1 << 20;
/// Photons of the first dispatch when the size adapts.
const FIRST_DISPATCH_PHOTONS: u32 = 1 << 12;
/// The time one dispatch aims at when its size adapts [s].
pub const TARGET_DISPATCH_SECONDS: f64 = 0.1;

/// The run and one dispatch; `tracer.wgsl`'s `Params`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct Params {
    seed_lo: u32,
    seed_hi: u32,
    base_lo: u32,
    base_hi: u32,
    count: u32,
    layers: u32,
    first: u32,
    importance: u32,
    nr: u32,
    na: u32,
    /// 1/dr in walk units [1/unit].
    inv_dr: f32,
    /// 1/da [1/rad].
    inv_da: f32,
    w0: f32,
    tau_total: f32,
    pad: [f32; 2],
}

/// The photon tracer's compute pipeline on one device, built once and used for many runs.
pub struct Tracer {
    pipeline: wgpu::ComputePipeline,
    /// Photons per dispatch; `None`: adapted to [`TARGET_DISPATCH_SECONDS`].
    dispatch: Option<u32>,
}

/// The device's buffers of one run.
struct Buffers {
    params: wgpu::Buffer,
    tally: wgpu::Buffer,
    work: wgpu::Buffer,
    bind: wgpu::BindGroup,
    tally_bytes: u64,
}

impl Tracer {
    /// Compiles the walk on `gpu`'s device; refuses an adapter without compute shaders
    /// ([`McGpuError::NoCompute`]).
    pub fn new(gpu: &Gpu) -> Result<Tracer> {
        check_compute(&gpu.device.limits(), &gpu.adapter_name)?;
        let scope = gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let module = gpu
            .device
            .create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("mc_gpu tracer"),
                source: wgpu::ShaderSource::Wgsl(TRACER_WGSL.into()),
            });
        let pipeline = gpu
            .device
            .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("mc_gpu tracer"),
                layout: None,
                module: &module,
                entry_point: Some("main"),
                compilation_options: Default::default(),
                cache: None,
            });
        device_result(scope)?;
        Ok(Tracer {
            pipeline,
            dispatch: None,
        })
    }

    /// The same tracer with `photons` per dispatch (clamped to 1..=[`MAX_DISPATCH_PHOTONS`]), or
    /// adapted to the device's speed (`None`, the default). The result does not depend on it.
    pub fn with_dispatch(mut self, photons: Option<u32>) -> Tracer {
        self.dispatch = photons.map(|n| n.clamp(1, MAX_DISPATCH_PHOTONS));
        self
    }

    /// Traces `photons` photons of `walk` seeded with `seed`, tallied on `grid` [cm], and returns
    /// the exact sums. `progress` is called after each dispatch with its photons.
    pub(crate) fn trace(
        &self,
        gpu: &Gpu,
        walk: &Walk,
        grid: &Grid,
        photons: u64,
        seed: u64,
        progress: &(dyn Fn(u64) + Sync),
    ) -> Result<Accumulator> {
        let layout = Layout {
            nr: grid.nr,
            nz: grid.nz,
            na: grid.na,
            layers: walk.slabs.len(),
            rz: false,
            rz_se: false,
            channels: 1,
            xy: 0,
        };
        let scope = gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let b = self.buffers(gpu, walk, &layout)?;
        let mut params = Params {
            seed_lo: seed as u32,
            seed_hi: (seed >> 32) as u32,
            base_lo: 0,
            base_hi: 0,
            count: 0,
            layers: walk.slabs.len() as u32,
            first: walk.first,
            importance: u32::from(walk.importance),
            nr: grid.nr as u32,
            na: grid.na as u32,
            inv_dr: (walk.scale / grid.dr) as f32,
            inv_da: (1.0 / grid.da()) as f32,
            w0: (1.0 - walk.rsp) as f32,
            tau_total: walk.tau_total as f32,
            pad: [0.0; 2],
        };
        let mut acc = Accumulator::new(layout);
        let (mut done, mut in_round) = (0u64, 0u64);
        let mut size = self.dispatch.unwrap_or(FIRST_DISPATCH_PHOTONS);
        while done < photons {
            let n = u64::from(size)
                .min(photons - done)
                .min(ROUND_PHOTONS - in_round);
            (params.base_lo, params.base_hi) = (done as u32, (done >> 32) as u32);
            params.count = n as u32;
            let start = Instant::now();
            self.dispatch(gpu, &b, &params)?;
            progress(n);
            if self.dispatch.is_none() {
                size = adapt(size, n, start.elapsed().as_secs_f64());
            }
            done += n;
            in_round += n;
            if in_round == ROUND_PHOTONS || done == photons {
                read_round(gpu, &b, &mut acc, in_round)?;
                in_round = 0;
            }
        }
        device_result(scope)?;
        Ok(acc)
    }

    /// The run's buffers, after checking that the tallies fit the adapter's storage buffers.
    fn buffers(&self, gpu: &Gpu, walk: &Walk, layout: &Layout) -> Result<Buffers> {
        let tally_bytes = 4 * words(layout) as u64;
        let limits = gpu.device.limits();
        check_storage(&limits, tally_bytes)?;
        let dev = &gpu.device;
        let buffer = |label: &str, size: u64, usage: wgpu::BufferUsages| {
            dev.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage,
                mapped_at_creation: false,
            })
        };
        use wgpu::BufferUsages as U;
        let params = buffer(
            "mc_gpu params",
            size_of::<Params>() as u64,
            U::UNIFORM | U::COPY_DST,
        );
        let slabs = buffer(
            "mc_gpu slabs",
            size_of_val(walk.slabs.as_slice()) as u64,
            U::STORAGE | U::COPY_DST,
        );
        gpu.queue
            .write_buffer(&slabs, 0, bytemuck::cast_slice(&walk.slabs));
        let tally = buffer(
            "mc_gpu tally",
            tally_bytes,
            U::STORAGE | U::COPY_SRC | U::COPY_DST,
        );
        let work = buffer("mc_gpu work", 8, U::STORAGE | U::COPY_SRC | U::COPY_DST);
        gpu.queue.write_buffer(&work, 0, &[0; 8]);
        fn entry(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
            wgpu::BindGroupEntry {
                binding,
                resource: buffer.as_entire_binding(),
            }
        }
        let bind = dev.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("mc_gpu"),
            layout: &self.pipeline.get_bind_group_layout(0),
            entries: &[
                entry(0, &params),
                entry(1, &slabs),
                entry(2, &tally),
                entry(3, &work),
            ],
        });
        Ok(Buffers {
            params,
            tally,
            work,
            bind,
            tally_bytes,
        })
    }

    /// Runs one dispatch of `params.count` photons and waits for it.
    fn dispatch(&self, gpu: &Gpu, b: &Buffers, params: &Params) -> Result<()> {
        gpu.queue
            .write_buffer(&b.params, 0, bytemuck::bytes_of(params));
        // The next photon's counter restarts; the overflow flag (word 1) stays raised.
        gpu.queue.write_buffer(&b.work, 0, &[0; 4]);
        let invocations = params.count.min(MAX_INVOCATIONS);
        let mut enc = gpu.device.create_command_encoder(&Default::default());
        {
            let mut pass = enc.begin_compute_pass(&Default::default());
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &b.bind, &[]);
            pass.dispatch_workgroups(invocations.div_ceil(WORKGROUP), 1, 1);
        }
        gpu.queue.submit([enc.finish()]);
        gpu.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| McGpuError::Device(e.to_string()))?;
        Ok(())
    }
}

/// Reads a round's tallies and the overflow flag into `acc` and clears the tallies.
fn read_round(gpu: &Gpu, b: &Buffers, acc: &mut Accumulator, photons: u64) -> Result<()> {
    let bytes = gpu.read_buffer(&b.tally, b.tally_bytes)?;
    let flag = gpu.read_buffer(&b.work, 8)?;
    let words: Vec<u32> = bytemuck::pod_collect_to_vec(&bytes);
    add_round(acc, &words, photons, flag[4..8] != [0; 4])?;
    let mut enc = gpu.device.create_command_encoder(&Default::default());
    enc.clear_buffer(&b.tally, 0, None);
    gpu.queue.submit([enc.finish()]);
    Ok(())
}

/// The next dispatch's size after one of `n` photons took `seconds`: doubled while it takes
/// under half the target, halved while it takes over twice (never below a workgroup's worth).
fn adapt(size: u32, n: u64, seconds: f64) -> u32 {
    if n < u64::from(size) {
        size
    } else if seconds < 0.5 * TARGET_DISPATCH_SECONDS {
        (size * 2).min(MAX_DISPATCH_PHOTONS)
    } else if seconds > 2.0 * TARGET_DISPATCH_SECONDS {
        (size / 2).max(WORKGROUP)
    } else {
        size
    }
}

/// Refuses a device without compute shaders of one 64-wide workgroup and three storage buffers.
pub(crate) fn check_compute(limits: &wgpu::Limits, adapter: &str) -> Result<()> {
    let reason = if limits.max_compute_workgroups_per_dimension == 0 {
        "no compute shaders".to_string()
    } else if limits.max_compute_invocations_per_workgroup < WORKGROUP
        || limits.max_compute_workgroup_size_x < WORKGROUP
    {
        format!("workgroups of fewer than {WORKGROUP} invocations")
    } else if limits.max_storage_buffers_per_shader_stage < 3 {
        "fewer than 3 storage buffers per compute shader".to_string()
    } else {
        return Ok(());
    };
    Err(McGpuError::NoCompute {
        adapter: adapter.to_string(),
        reason,
    })
}

/// Refuses tallies of `bytes` that exceed a storage binding or a buffer of the device.
pub(crate) fn check_storage(limits: &wgpu::Limits, bytes: u64) -> Result<()> {
    let limit = u64::from(limits.max_storage_buffer_binding_size).min(limits.max_buffer_size);
    if bytes > limit {
        return Err(McGpuError::StorageTooSmall {
            needed: bytes,
            limit,
        });
    }
    Ok(())
}

/// The first validation error caught by `scope`, as a [`McGpuError::Device`].
fn device_result(scope: wgpu::ErrorScopeGuard) -> Result<()> {
    match pollster::block_on(scope.pop()) {
        Some(e) => Err(McGpuError::Device(e.to_string())),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shader_validates_and_its_params_match_rust() {
        let module = naga::front::wgsl::parse_str(TRACER_WGSL).expect("WGSL parses");
        naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::empty(),
        )
        .validate(&module)
        .expect("WGSL validates");
        let params = module
            .types
            .iter()
            .find(|(_, t)| t.name.as_deref() == Some("Params"))
            .expect("Params");
        assert_eq!(
            params.1.inner.size(module.to_ctx()) as usize,
            size_of::<Params>()
        );
        let slab = module
            .types
            .iter()
            .find(|(_, t)| t.name.as_deref() == Some("Slab"))
            .expect("Slab");
        assert_eq!(
            slab.1.inner.size(module.to_ctx()) as usize,
            size_of::<crate::medium::Slab>()
        );
    }

    #[test]
    fn adapters_without_compute_or_storage_are_refused_by_name() {
        let mut l = wgpu::Limits::downlevel_webgl2_defaults();
        assert!(matches!(
            check_compute(&l, "webgl"),
            Err(McGpuError::NoCompute { .. })
        ));
        l = wgpu::Limits::default();
        assert!(check_compute(&l, "any").is_ok());
        let e = check_storage(&l, 1 << 40).unwrap_err();
        assert!(matches!(e, McGpuError::StorageTooSmall { needed, .. } if needed == 1 << 40));
        assert!(e.to_string().contains("coarser grid"), "{e}");
    }

    #[test]
    fn dispatches_grow_on_a_fast_device_and_shrink_on_a_slow_one() {
        assert_eq!(adapt(4096, 4096, 0.001), 8192);
        assert_eq!(adapt(4096, 4096, 1.0), 2048);
        assert_eq!(adapt(4096, 4096, 0.1), 4096);
        assert_eq!(adapt(4096, 100, 0.0), 4096);
        assert_eq!(
            adapt(MAX_DISPATCH_PHOTONS, 1 << 20, 0.0),
            MAX_DISPATCH_PHOTONS
        );
    }
}
