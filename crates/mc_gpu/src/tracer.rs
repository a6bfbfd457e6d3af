//! The compute pass: [`Tracer`] compiles the walk once and traces runs of any size in rounds
//! of dispatches.
//!
//! A run of N photons is cut into rounds of at most [`ROUND_PHOTONS`] ([`Dispatch::round`]),
//! after each of which the
//! tallies are read back into the host's exact accumulator. In a round, each of [`Dispatch::slots`]
//! invocations holds one photon in flight in a storage buffer and takes at most
//! [`Dispatch::steps`] steps per dispatch (by default sized on the fly so that a dispatch takes
//! about [`TARGET_DISPATCH_SECONDS`]: no dispatch runs for seconds on a software rasterizer or
//! trips a desktop GPU's watchdog, and none exceeds lavapipe's loop limit, see `tracer.wgsl`);
//! dispatches follow until the round's photons are all finished. Photon k of the run draws from
//! its own stream of (seed, k), its state is kept bit for bit between dispatches and every sum is
//! an integer, so neither the rounds, the slots nor the steps change the result.

use std::sync::Mutex;
use std::time::Instant;

use bytemuck::{Pod, Zeroable};
use gpu::Gpu;
use mc::{Grid, Layout};

use crate::error::{McGpuError, Result};
use crate::medium::{MAX_LAYERS, Walk};
use crate::tally::{ROUND_PHOTONS, Sums, words};

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
/// Photons in flight by default on a GPU: enough invocations to fill a large one.
pub const GPU_SLOTS: u32 = 1 << 16;
/// Photons in flight by default on a CPU adapter (lavapipe): a few per SIMD lane of its threads,
/// so that one step of every slot is short and a dispatch of the target time takes hundreds of
/// steps (with [`GPU_SLOTS`], measured on lavapipe with two cores, the steps adapted down to a
/// few per dispatch and the slots' loads and stores and the dispatches' readbacks took 3.3× the
/// run time).
pub const CPU_SLOTS: u32 = 1 << 11;
/// Loop iterations one invocation may run per dispatch, all loops together: below the 65,535 after
/// which Mesa 22's lavapipe silently ends a shader's loops. A step costs one, and a photon that
/// ends in it at most 4 + 3 per layer more (its deposits summed and its scores made,
/// `tracer.wgsl`'s `finish`), or in a table's walk 9 + one per albedo (the bisection of its
/// intervals and a score per albedo).
const LOOP_BUDGET: u32 = 60_000;
/// Steps per slot of the first dispatch when the steps adapt.
const FIRST_STEPS: u32 = 32;
/// The time one dispatch aims at when its steps adapt [s].
pub const TARGET_DISPATCH_SECONDS: f64 = 0.1;
/// Bytes of one slot (`tracer.wgsl`'s `Slot`): 16 words of photon state, then the deposits.
const SLOT_BYTES: u64 = 4 * (16 + MAX_LAYERS as u64);

/// How a run is cut into rounds and dispatches: photons per round, photons in flight and steps
/// per dispatch. None of them changes the result.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Dispatch {
    /// Photons in flight, one per invocation (at least 1).
    pub slots: u32,
    /// Steps per slot and dispatch; `None`: adapted to take about [`TARGET_DISPATCH_SECONDS`].
    /// Capped by the loop budget a driver allows (60,000 over 5 + 3 per layer).
    pub steps: Option<u32>,
    /// Photons per round, between two readbacks of the tallies (1..=[`ROUND_PHOTONS`]).
    pub round: u64,
}

impl Dispatch {
    /// The default for a device: [`CPU_SLOTS`] on a CPU adapter, else [`GPU_SLOTS`]; steps
    /// adapted; rounds of [`ROUND_PHOTONS`].
    pub fn for_device(device: &wgpu::Device) -> Dispatch {
        let cpu = device.adapter_info().device_type == wgpu::DeviceType::Cpu;
        Dispatch {
            slots: if cpu { CPU_SLOTS } else { GPU_SLOTS },
            steps: None,
            round: ROUND_PHOTONS,
        }
    }
}

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
    albedos: u32,
    nr: u32,
    na: u32,
    /// 1/dr in walk units [1/unit].
    inv_dr: f32,
    /// 1/da [1/rad].
    inv_da: f32,
    w0: f32,
    tau_total: f32,
    slots: u32,
    steps: u32,
}

/// The photon tracer's compute pipeline on one device, built once and used for many runs.
pub struct Tracer {
    module: wgpu::ShaderModule,
    /// The pipelines built so far, one per variant of the walk.
    pipelines: Mutex<Vec<(Variant, wgpu::ComputePipeline)>>,
    dispatch: Dispatch,
}

/// What a walk needs of the shader: its pipeline-overridable constants (`tracer.wgsl`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Variant {
    /// Some layer is glass.
    glass: bool,
    /// More than one layer.
    layered: bool,
    /// The importance roulette is played.
    importance: bool,
    /// Some scattering layer has g = 0 / g ≠ 0.
    isotropic: bool,
    anisotropic: bool,
    /// A profile table's walk.
    table: bool,
}

impl Variant {
    fn of(walk: &Walk, target: &Target) -> Variant {
        Variant {
            table: matches!(target, Target::Table { .. }),
            glass: walk.slabs.iter().any(|s| s.is_glass()),
            layered: walk.slabs.len() > 1,
            importance: walk.importance,
            isotropic: walk.slabs.iter().any(|s| !s.is_glass() && s.g == 0.0),
            anisotropic: walk.slabs.iter().any(|s| !s.is_glass() && s.g != 0.0),
        }
    }
}

/// What a run tallies.
pub(crate) enum Target<'a> {
    /// Rd(r, α), Tt(r, α), A_l and A on a grid [cm].
    Grid(&'a Grid),
    /// A profile table's top exits per albedo and radial interval (`table.rs`): per albedo
    /// ln(α/α_walk), increasing, and the intervals' edges [walk units], increasing.
    Table {
        ln_ratio: &'a [f32],
        edges: &'a [f32],
    },
}

impl Target<'_> {
    /// The shader's tally entries.
    fn entries(&self, walk: &Walk) -> usize {
        match self {
            Target::Grid(grid) => grid_layout(walk, grid).entries(),
            Target::Table { ln_ratio, edges } => ln_ratio.len() * (edges.len() + 1),
        }
    }
}

/// The accumulator layout of a run of `walk` on `grid`.
pub(crate) fn grid_layout(walk: &Walk, grid: &Grid) -> Layout {
    Layout {
        nr: grid.nr,
        nz: grid.nz,
        na: grid.na,
        layers: walk.slabs.len(),
        rz: false,
        rz_se: false,
        channels: 1,
        xy: 0,
        scores: 0,
    }
}

/// The device's buffers of one run.
struct Buffers {
    pipeline: wgpu::ComputePipeline,
    params: wgpu::Buffer,
    tally: wgpu::Buffer,
    work: wgpu::Buffer,
    bind: wgpu::BindGroup,
    tally_bytes: u64,
}

/// `work` as read back after a dispatch (`tally.wgsl`).
struct Work {
    /// The round's next photon index (at least the round's photons once all are taken).
    next: u32,
    /// The overflow flag.
    overflow: bool,
    /// Slots still holding a photon.
    busy: u32,
    /// Photons finished in the dispatch.
    finished: u32,
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
        device_result(scope)?;
        Ok(Tracer {
            module,
            pipelines: Mutex::new(Vec::new()),
            dispatch: Dispatch::for_device(&gpu.device),
        })
    }

    /// The pipeline of `variant`, built on first use.
    fn pipeline(&self, gpu: &Gpu, variant: Variant) -> wgpu::ComputePipeline {
        let mut built = self.pipelines.lock().unwrap_or_else(|e| e.into_inner());
        if let Some((_, p)) = built.iter().find(|(v, _)| *v == variant) {
            return p.clone();
        }
        let flag = |b: bool| if b { 1.0 } else { 0.0 };
        let constants = [
            ("GLASS", flag(variant.glass)),
            ("LAYERED", flag(variant.layered)),
            ("IMPORTANCE", flag(variant.importance)),
            ("ISOTROPIC", flag(variant.isotropic)),
            ("ANISOTROPIC", flag(variant.anisotropic)),
            ("TABLE", flag(variant.table)),
        ];
        let p = gpu
            .device
            .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("mc_gpu tracer"),
                layout: None,
                module: &self.module,
                entry_point: Some("main"),
                compilation_options: wgpu::PipelineCompilationOptions {
                    constants: &constants,
                    ..Default::default()
                },
                cache: None,
            });
        built.push((variant, p.clone()));
        p
    }

    /// The same tracer cutting rounds into dispatches as `dispatch` says (the default:
    /// [`Dispatch::for_device`]). The result does not depend on it.
    pub fn with_dispatch(mut self, dispatch: Dispatch) -> Tracer {
        self.dispatch = dispatch;
        self
    }

    /// Traces `photons` photons of `walk` seeded with `seed`, tallied as `target` says, and
    /// returns the exact sums of the shader's entries. `progress` is called after each dispatch
    /// with the photons it finished.
    pub(crate) fn trace(
        &self,
        gpu: &Gpu,
        walk: &Walk,
        target: &Target,
        photons: u64,
        seed: u64,
        progress: &(dyn Fn(u64) + Sync),
    ) -> Result<Sums> {
        let scope = gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let round = self.dispatch.round.clamp(1, ROUND_PHOTONS);
        let slots = self.dispatch.slots.max(1).min(photons.min(round) as u32);
        let pipeline = self.pipeline(gpu, Variant::of(walk, target));
        let entries = target.entries(walk);
        let b = self.buffers(gpu, pipeline, walk, target, entries, slots)?;
        let (nr, na, inv_dr, inv_da, albedos, step_cost) = match target {
            Target::Grid(grid) => (
                grid.nr as u32,
                grid.na as u32,
                (walk.scale / grid.dr) as f32,
                (1.0 / grid.da()) as f32,
                0,
                5 + 3 * walk.slabs.len() as u32,
            ),
            Target::Table { ln_ratio, edges } => {
                let albedos = ln_ratio.len() as u32;
                (edges.len() as u32 + 1, 1, 1.0, 1.0, albedos, 10 + albedos)
            }
        };
        let max_steps = LOOP_BUDGET / step_cost;
        let mut params = Params {
            seed_lo: seed as u32,
            seed_hi: (seed >> 32) as u32,
            base_lo: 0,
            base_hi: 0,
            count: 0,
            layers: walk.slabs.len() as u32,
            first: walk.first,
            albedos,
            nr,
            na,
            inv_dr,
            inv_da,
            w0: (1.0 - walk.rsp) as f32,
            tau_total: walk.tau_total as f32,
            slots,
            steps: self
                .dispatch
                .steps
                .unwrap_or(FIRST_STEPS)
                .clamp(1, max_steps),
        };
        let mut sums = Sums::new(entries);
        let mut done = 0u64;
        while done < photons {
            let n = round.min(photons - done);
            (params.base_lo, params.base_hi) = (done as u32, (done >> 32) as u32);
            params.count = n as u32;
            // The round's photon counter restarts; the overflow flag stays raised.
            gpu.queue.write_buffer(&b.work, 0, &[0; 4]);
            loop {
                let start = Instant::now();
                let work = self.dispatch(gpu, &b, &params)?;
                progress(u64::from(work.finished));
                if self.dispatch.steps.is_none() {
                    params.steps = adapt(params.steps, max_steps, start.elapsed().as_secs_f64());
                }
                if u64::from(work.next) >= n && work.busy == 0 {
                    read_round(gpu, &b, &mut sums, n, work.overflow)?;
                    break;
                }
            }
            done += n;
        }
        device_result(scope)?;
        Ok(sums)
    }

    /// The run's buffers, after checking that the tallies fit the adapter's storage buffers.
    fn buffers(
        &self,
        gpu: &Gpu,
        pipeline: wgpu::ComputePipeline,
        walk: &Walk,
        target: &Target,
        entries: usize,
        slots: u32,
    ) -> Result<Buffers> {
        let tally_bytes = 4 * words(entries) as u64;
        let slot_bytes = SLOT_BYTES * u64::from(slots);
        let limits = gpu.device.limits();
        check_storage(&limits, tally_bytes.max(slot_bytes))?;
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
        let table_words: Vec<f32> = match target {
            Target::Grid(_) => vec![0.0],
            Target::Table { ln_ratio, edges } => [*ln_ratio, *edges].concat(),
        };
        let table = buffer(
            "mc_gpu table",
            size_of_val(table_words.as_slice()) as u64,
            U::STORAGE | U::COPY_DST,
        );
        gpu.queue
            .write_buffer(&table, 0, bytemuck::cast_slice(&table_words));
        let work = buffer("mc_gpu work", 16, U::STORAGE | U::COPY_SRC | U::COPY_DST);
        gpu.queue.write_buffer(&work, 0, &[0; 16]);
        // Zero: every slot starts without a photon.
        let slots = buffer("mc_gpu slots", slot_bytes, U::STORAGE);
        fn entry(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
            wgpu::BindGroupEntry {
                binding,
                resource: buffer.as_entire_binding(),
            }
        }
        let bind = dev.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("mc_gpu"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[
                entry(0, &params),
                entry(1, &slabs),
                entry(2, &tally),
                entry(3, &work),
                entry(4, &slots),
                entry(5, &table),
            ],
        });
        Ok(Buffers {
            pipeline,
            params,
            tally,
            work,
            bind,
            tally_bytes,
        })
    }

    /// Runs one dispatch of `params.steps` steps per slot, waits for it and reads `work`.
    fn dispatch(&self, gpu: &Gpu, b: &Buffers, params: &Params) -> Result<Work> {
        gpu.queue
            .write_buffer(&b.params, 0, bytemuck::bytes_of(params));
        // Busy slots and finished photons are counted per dispatch.
        gpu.queue.write_buffer(&b.work, 8, &[0; 8]);
        let mut enc = gpu.device.create_command_encoder(&Default::default());
        {
            let mut pass = enc.begin_compute_pass(&Default::default());
            pass.set_pipeline(&b.pipeline);
            pass.set_bind_group(0, &b.bind, &[]);
            pass.dispatch_workgroups(params.slots.div_ceil(WORKGROUP), 1, 1);
        }
        gpu.queue.submit([enc.finish()]);
        let w: Vec<u32> = bytemuck::pod_collect_to_vec(&gpu.read_buffer(&b.work, 16)?);
        Ok(Work {
            next: w[0],
            overflow: w[1] != 0,
            busy: w[2],
            finished: w[3],
        })
    }
}

/// Reads a round's tallies of `photons` into `sums` and clears them.
fn read_round(gpu: &Gpu, b: &Buffers, sums: &mut Sums, photons: u64, overflow: bool) -> Result<()> {
    let words: Vec<u32> = bytemuck::pod_collect_to_vec(&gpu.read_buffer(&b.tally, b.tally_bytes)?);
    sums.add_round(&words, photons, overflow)?;
    let mut enc = gpu.device.create_command_encoder(&Default::default());
    enc.clear_buffer(&b.tally, 0, None);
    gpu.queue.submit([enc.finish()]);
    Ok(())
}

/// The next dispatch's steps after one took `seconds`: doubled while it takes under half the
/// target, halved while it takes over twice, within 1..=`max`.
fn adapt(steps: u32, max: u32, seconds: f64) -> u32 {
    if seconds < 0.5 * TARGET_DISPATCH_SECONDS {
        (steps * 2).min(max)
    } else if seconds > 2.0 * TARGET_DISPATCH_SECONDS {
        (steps / 2).max(1)
    } else {
        steps
    }
}

/// Refuses a device without compute shaders of one 64-wide workgroup and five storage buffers.
pub(crate) fn check_compute(limits: &wgpu::Limits, adapter: &str) -> Result<()> {
    let reason = if limits.max_compute_workgroups_per_dimension == 0 {
        "no compute shaders".to_string()
    } else if limits.max_compute_invocations_per_workgroup < WORKGROUP
        || limits.max_compute_workgroup_size_x < WORKGROUP
    {
        format!("workgroups of fewer than {WORKGROUP} invocations")
    } else if limits.max_storage_buffers_per_shader_stage < 5 {
        "fewer than 5 storage buffers per compute shader".to_string()
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
    let limit = limits
        .max_storage_buffer_binding_size
        .min(limits.max_buffer_size);
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
        let slot = module
            .types
            .iter()
            .find(|(_, t)| t.name.as_deref() == Some("Slot"))
            .expect("Slot");
        assert_eq!(slot.1.inner.size(module.to_ctx()) as u64, SLOT_BYTES);
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
    fn steps_grow_on_a_fast_device_and_shrink_on_a_slow_one() {
        assert_eq!(adapt(32, 1000, 0.001), 64);
        assert_eq!(adapt(32, 1000, 1.0), 16);
        assert_eq!(adapt(32, 1000, 0.1), 32);
        assert_eq!(adapt(800, 1000, 0.0), 1000);
        assert_eq!(adapt(1, 1000, 9.0), 1);
    }
}
