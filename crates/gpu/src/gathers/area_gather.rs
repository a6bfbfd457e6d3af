//! Subsurface scattering for large scattering distances (Maisch & Ropinski 2020): the
//! screen-space gather of area pre-integrated kernels over a layered sampling pattern.
//!
//! Per SSS pixel x_o the exitant light is (their eq. 6, with the constant c_o and the Fresnel terms
//! left to the scene pass's tables and the recombination, as for the separable path)
//!
//!   M(x_o) = Σ_cells E·A·R′(|x − x_o|, A) / ∫Rd,
//!
//! E the cell's mean irradiance × pre-scatter albedo, x its mean position, A its area on the
//! surface [cm²], and R′(r, A) the profile averaged over a disc of area A centred r from x_o (their
//! eq. 5; `fit::area_table`). Dividing by the profile's energy makes the weights of a flat, evenly
//! lit surface sum to one, so colour comes from the albedo as with the separable kernels.
//!
//! The passes: a surface pass (world position and the pixel's footprint area, `surface.wgsl`), the
//! area pyramid (level 0 from the G-buffer, then 2×2 sums: `level0`, `reduce`), and the gather
//! (`area_gather.wgsl`). Choices the paper leaves open, or where this departs from it:
//! - The pyramid stores sums per texel, not means: of A·E and A, and of the positions x and their
//!   count. A bilinear fetch then gives the area-weighted mean irradiance, the area per texel and
//!   the mean position at any level, so a cell's area is exact where the surface is seen whole,
//!   and nothing is counted twice at silhouettes.
//! - A cell of size c [px] reads level round(log₂ c) (their "≈ i·log₂(5/3)" for ring layer i) and
//!   takes the level's area per texel × (c/2^level)².
//! - Their §6.1 "brightening term" √i on the outer layers is optional ([`GatherPattern::brighten`])
//!   and off by default: on a flat, evenly lit surface the pattern's cells tile the plane and the
//!   gather already conserves energy, which √i would break (tested).
//! - Every pixel seen counts, with its footprint area bounded at grazing view: the frontal
//!   footprint over max(cos θ, [`GRAZING`]). The paper sets the area to 0 below cos θ = 0.2 (their
//!   §6.2, eq. 8) and leaves that band to the quarter-resolution splats, which blur a peaked
//!   kernel over 4 pixels: the silhouette's lit rim came out dark (marble sphere against Mitsuba,
//!   `images.py --quick`: 8.7 ± 1.0 % with 0.2; Skin1's rim at a tenth of its light).
//! - R′ is 0 beyond the table's r_max (where the source term α′σt′e^{−σt′r} has fallen to
//!   10⁻⁷ cm⁻¹), and cells whose disc exceeds the table's largest are read at its last row.

use crate::error::{GpuError, Result};
use crate::frame::context::{Gpu, bind, cleared_depth};
use crate::frame::pool::Alloc;
use crate::frame::recording::Recording;
use crate::frame::target::Target;
use crate::frame::timing::Timer;
use crate::passes::Pass;

/// The gather's shader with the shared kernel lookup prepended.
pub(crate) const AREA_GATHER_WGSL: &str = concat!(
    include_str!("../shaders/area_kernel.wgsl"),
    include_str!("../shaders/area_gather.wgsl")
);

/// The bound on cos θ (θ between the surface's normal and the view direction) below which a
/// pixel's footprint area is taken as its frontal footprint over this bound (20×), not over cos θ,
/// which grows without bound where a flat triangle stands in for a curved surface.
pub const GRAZING: f32 = 0.05;

/// Texels of a material's R′(r, A) table along each axis (the paper's 512).
pub const AREA_TABLE_SIZE: usize = 512;

/// The most pyramid levels (images up to 32768 px on a side).
const MAX_LEVELS: usize = 16;

/// An area pre-integrated kernel as the gather reads it: R′(r, A) of `fit::area_table` divided by
/// the profile's energy within r_max, per channel.
#[derive(Clone, Debug, PartialEq)]
pub struct AreaKernel {
    n_r: u32,
    n_a: u32,
    r_max_cm: f32,
    /// R′/energy [1/cm²] per texel (rgb; w unused), row-major: row j (disc radius
    /// (j + ½)·r_max/n_a) by column i (distance (i + ½)·r_max/n_r).
    values: Vec<[f32; 4]>,
}

impl AreaKernel {
    /// The table normalized by its energy per channel; refuses tables under 2×2 texels, without
    /// a positive finite r_max, with negative or non-finite values, or without energy.
    pub fn new(table: &fit::area_table::AreaTable) -> Result<AreaKernel> {
        if table.n_r < 2 || table.n_a < 2 {
            return Err(GpuError::invalid(
                "area table size",
                format!("{}×{}", table.n_r, table.n_a),
                "needs at least 2×2 texels",
            ));
        }
        if !(table.r_max.is_finite() && table.r_max > 0.0) {
            return Err(GpuError::invalid(
                "area table r_max",
                table.r_max,
                "must be finite and > 0 [cm]",
            ));
        }
        for c in 0..3 {
            if !(table.energy[c].is_finite() && table.energy[c] > 0.0) {
                return Err(GpuError::invalid(
                    "area table energy",
                    table.energy[c],
                    format!("channel {c} must carry energy"),
                ));
            }
            if let Some(v) = table.values[c]
                .iter()
                .find(|v| !(v.is_finite() && **v >= 0.0))
            {
                return Err(GpuError::invalid(
                    "area table value",
                    v,
                    format!("channel {c}: every R′ must be finite and ≥ 0"),
                ));
            }
        }
        let n = table.n_r * table.n_a;
        let values = (0..n)
            .map(|k| {
                let v = |c: usize| (table.values[c][k] / table.energy[c]) as f32;
                [v(0), v(1), v(2), 0.0]
            })
            .collect();
        Ok(AreaKernel {
            n_r: table.n_r as u32,
            n_a: table.n_a as u32,
            r_max_cm: table.r_max as f32,
            values,
        })
    }

    /// The kernel of a material `name` with the three channels' `media` (Maisch & Ropinski 2020
    /// §7.1): its Monte Carlo profile
    /// `profile` averaged over discs ([`AREA_TABLE_SIZE`]² texels) out to r_max, where the
    /// source term α′σt′e^{−σt′r} of the slowest-decaying channel falls to 10⁻⁷ cm⁻¹. Refuses a
    /// material whose source term never reaches that (nothing scatters).
    pub fn for_material(
        name: &str,
        media: &[fit::analytic::Medium; 3],
        profile: &fit::Profile,
    ) -> Result<AreaKernel> {
        let r_max = media
            .iter()
            .map(|m| fit::area_table::cutoff_radius(m, 1e-7))
            .fold(0.0, f64::max);
        if r_max.is_nan() || r_max <= 0.0 {
            return Err(GpuError::invalid(
                format!("area gather: r_max of {name}"),
                r_max,
                "the source term never reaches 1e-7/cm (no scattering to gather)",
            ));
        }
        let rd = |c: usize| move |r: f64| profile.at(c, r);
        let (r0, r1, r2) = (rd(0), rd(1), rd(2));
        let table = fit::area_table::AreaTable::build(
            [&r0, &r1, &r2],
            r_max,
            AREA_TABLE_SIZE,
            AREA_TABLE_SIZE,
        );
        AreaKernel::new(&table)
    }

    /// area_kernel.wgsl's `AreaKernel` for width factor `scale`: scale and r_max as f32 bits,
    /// then the texels along r and A.
    pub(crate) fn uniform(&self, scale: f32) -> [u32; 4] {
        [scale.to_bits(), self.r_max_cm.to_bits(), self.n_r, self.n_a]
    }

    /// Where the kernel ends [cm] (before the width factor).
    pub fn r_max_cm(&self) -> f32 {
        self.r_max_cm
    }

    /// R′_s(r, A)/energy [1/cm²] at distance `r` [cm] and area `a` [cm²] of the kernel widened by
    /// `s`: R′(r/s, A/s²)/s², bilinear between texel centres and clamped to them, 0 beyond s·r_max.
    /// The CPU twin of area_gather.wgsl's `area_kernel`, operation for operation.
    pub fn lookup(&self, r: f32, a: f32, s: f32) -> [f32; 3] {
        let rs = r / s;
        if rs.is_nan() || rs > self.r_max_cm {
            return [0.0; 3];
        }
        let ra = (a.max(0.0) / std::f32::consts::PI).sqrt() / s;
        let coord = |v: f32, n: u32| {
            let x = (v / self.r_max_cm * n as f32 - 0.5).clamp(0.0, (n - 1) as f32);
            let k = (x.floor() as u32).min(n - 2);
            (k, x - k as f32)
        };
        let (i, ti) = coord(rs, self.n_r);
        let (j, tj) = coord(ra, self.n_a);
        let at = |j: u32, i: u32, c: usize| {
            self.values[(j.min(self.n_a - 1) * self.n_r + i.min(self.n_r - 1)) as usize][c]
        };
        let mix = |x: f32, y: f32, t: f32| x * (1.0 - t) + y * t;
        [0, 1, 2].map(|c| {
            let lo = mix(at(j, i, c), at(j, i + 1, c), ti);
            let hi = mix(at(j + 1, i, c), at(j + 1, i + 1, c), ti);
            mix(lo, hi, tj) / (s * s)
        })
    }
}

/// The layered sampling pattern (Maisch & Ropinski 2020 §4.2, eq. 7): an inner block of
/// (2n+1)² taps at full resolution, then `layers` shells, each the outer ring of an n_l×n_l grid
/// (4(n_l − 1) taps) whose cells are n_l/(n_l − 2) times larger than the previous layer's, so that
/// the layers tile the plane without gaps or overlap.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GatherPattern {
    /// n: the inner block is (2n+1)² pixels.
    pub inner: u32,
    /// n_l: samples along a layer's side (odd, ≥ 3).
    pub ring: u32,
    /// Number of layers around the inner block.
    pub layers: u32,
    /// Their §6.1 brightening: each tap of ring layer i weighted by √i (compensating, they say,
    /// for curved geometry); off conserves energy on flat surfaces.
    pub brighten: bool,
}

impl Default for GatherPattern {
    /// The paper's choice: n = 2, n_l = 5, 10 layers (185 taps reaching ≈ 413 px).
    fn default() -> Self {
        GatherPattern {
            inner: 2,
            ring: 5,
            layers: 10,
            brighten: false,
        }
    }
}

/// One tap of a [`GatherPattern`].
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct GatherTap {
    /// Offset of the cell's centre from the pixel [px].
    pub offset_px: [f32; 2],
    /// The cell's side [px].
    pub cell_px: f32,
    /// The pyramid level read: round(log₂ cell).
    pub level: u32,
    /// The tap's weight (1, or √i with [`GatherPattern::brighten`]).
    pub weight: f32,
    _pad: f32,
}

/// The size of area_gather.wgsl's `Tap` (checked against naga's layout in a test).
pub(crate) const TAP_SIZE: usize = 24;
const _: () = assert!(std::mem::size_of::<GatherTap>() == TAP_SIZE);

impl GatherPattern {
    /// Only the inner block, of half-width `n` [px]: every pixel within n is a tap at full
    /// resolution (the brute-force screen-space 2D gather).
    pub fn dense(n: u32) -> GatherPattern {
        GatherPattern {
            inner: n,
            ring: 5,
            layers: 0,
            brighten: false,
        }
    }

    /// Refuses an even or too small ring, an inner block over 512 px and a reach over 65,536 px,
    /// naming the field.
    pub fn validate(&self) -> Result<()> {
        if self.ring < 3 || self.ring.is_multiple_of(2) {
            return Err(GpuError::invalid(
                "pattern ring",
                self.ring,
                "samples per layer side must be odd and ≥ 3",
            ));
        }
        if self.inner > 512 {
            return Err(GpuError::invalid(
                "pattern inner",
                self.inner,
                "the inner block's half-width is at most 512 px",
            ));
        }
        if self.reach_px() > 65536.0 {
            return Err(GpuError::invalid(
                "pattern layers",
                self.layers,
                format!(
                    "the pattern would reach {:.0} px (at most 65536)",
                    self.reach_px()
                ),
            ));
        }
        Ok(())
    }

    /// The half-width of the outermost layer [px]: ½(2n+1)·(n_l/(n_l − 2))^layers.
    pub fn reach_px(&self) -> f32 {
        let q = self.ring as f32 / (self.ring as f32 - 2.0);
        0.5 * (2 * self.inner + 1) as f32 * q.powi(self.layers as i32)
    }

    /// Every tap: the inner block row by row, then each layer's ring.
    pub fn taps(&self) -> Vec<GatherTap> {
        let tap = |x: f32, y: f32, cell: f32, weight: f32| GatherTap {
            offset_px: [x, y],
            cell_px: cell,
            level: cell.log2().round().max(0.0) as u32,
            weight,
            _pad: 0.0,
        };
        let n = self.inner as i32;
        let mut taps: Vec<GatherTap> = (-n..=n)
            .flat_map(|y| (-n..=n).map(move |x| tap(x as f32, y as f32, 1.0, 1.0)))
            .collect();
        let nl = self.ring as f32;
        let q = nl / (nl - 2.0);
        for i in 1..=self.layers {
            // Eq. 7: p_i(s) = ½(2n+1)·q^(i−1)·((2s − 1)/(n_l − 2) − 1), s = 0, …, n_l − 1.
            let d = (2 * self.inner + 1) as f32 * q.powi(i as i32 - 1);
            let p = |s: u32| 0.5 * d * ((2.0 * s as f32 - 1.0) / (nl - 2.0) - 1.0);
            let cell = d / (nl - 2.0);
            let weight = if self.brighten {
                (i as f32).sqrt()
            } else {
                1.0
            };
            for sy in 0..self.ring {
                for sx in 0..self.ring {
                    if sx == 0 || sy == 0 || sx == self.ring - 1 || sy == self.ring - 1 {
                        taps.push(tap(p(sx), p(sy), cell, weight));
                    }
                }
            }
        }
        taps
    }
}

/// What [`crate::Scatter::AreaGather`] needs: the kernel, the pattern and how splats are read.
#[derive(Clone, Debug)]
pub struct AreaGatherSetup {
    /// The area pre-integrated kernel of the (one) SSS material.
    pub kernel: AreaKernel,
    /// The sampling pattern.
    pub pattern: GatherPattern,
    /// Move each splat's point towards the pixel by up to its disc's radius (their eq. 9) before
    /// reading R′; off reads R′ at the triangle's centre (see `splat.rs`).
    pub splat_clamp: bool,
}

impl AreaGatherSetup {
    /// `kernel` with the paper's pattern and splats read at their centres.
    pub fn new(kernel: AreaKernel) -> AreaGatherSetup {
        AreaGatherSetup {
            kernel,
            pattern: GatherPattern::default(),
            splat_clamp: false,
        }
    }
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Uniform {
    width: u32,
    height: u32,
    taps: u32,
    material: u32,
    kernel: [u32; 4],
    levels: u32,
    _pad: [u32; 3],
    level: [[u32; 4]; MAX_LEVELS],
}

/// The size of area_gather.wgsl's `Params` (checked against naga's layout in a test).
pub(crate) const GATHER_UNIFORM_SIZE: usize = 48 + 16 * MAX_LEVELS;
const _: () = assert!(std::mem::size_of::<Uniform>() == GATHER_UNIFORM_SIZE);

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct ReduceU {
    src: [u32; 4],
    dst: [u32; 4],
}

/// The size of area_gather.wgsl's `Reduce`.
pub(crate) const REDUCE_UNIFORM_SIZE: usize = 32;
const _: () = assert!(std::mem::size_of::<ReduceU>() == REDUCE_UNIFORM_SIZE);

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct ViewU {
    view_proj: [[f32; 4]; 4],
    camera_pos: [f32; 4],
}

/// The size of surface.wgsl's `View`.
pub(crate) const VIEW_UNIFORM_SIZE: usize = 80;
const _: () = assert!(std::mem::size_of::<ViewU>() == VIEW_UNIFORM_SIZE);

/// The pyramid's levels for a `w`×`h` image: (offset, width, height) in texels, down to 1×1.
fn levels((w, h): (u32, u32)) -> Vec<[u32; 4]> {
    let mut out = vec![[0, w, h, 0]];
    let mut offset = w * h;
    let (mut lw, mut lh) = (w, h);
    while (lw > 1 || lh > 1) && out.len() < MAX_LEVELS {
        lw = lw.div_ceil(2);
        lh = lh.div_ceil(2);
        out.push([offset, lw, lh, 0]);
        offset += lw * lh;
    }
    out
}

/// The compiled surface, pyramid, gather and lookup pipelines.
pub(crate) struct AreaGather {
    surface: wgpu::RenderPipeline,
    level0: wgpu::ComputePipeline,
    reduce: wgpu::ComputePipeline,
    gather: wgpu::ComputePipeline,
    lookup: wgpu::ComputePipeline,
}

/// What the gather leaves for the frame and the splats.
pub(crate) struct Gathered {
    /// Per pixel xyz world position [cm] and w the footprint area [cm²] that entered the gather
    /// (0 off the material or at grazing view).
    pub surface: wgpu::Buffer,
    /// The position pyramid: per texel Σx and the count of the material's pixels.
    pub pos: wgpu::Buffer,
    /// The kernel's texels.
    pub table: wgpu::Buffer,
    /// The pyramid's levels: offset, width, height.
    pub levels: Vec<[u32; 4]>,
}

impl Pass for AreaGather {
    /// The target, the gather's set-up and the width factor.
    type Input<'a> = (&'a Target<'a>, &'a AreaGatherSetup, f32);
    /// The surface buffer and pyramid the splats read.
    type Output = Gathered;

    fn new(gpu: &Gpu) -> AreaGather {
        let dev = &gpu.device;
        let surface = dev.create_shader_module(wgpu::include_wgsl!("../shaders/surface.wgsl"));
        let module = dev.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("area gather"),
            source: wgpu::ShaderSource::Wgsl(AREA_GATHER_WGSL.into()),
        });
        let pipeline =
            |entry: &str| crate::frame::context::entry_pipeline(dev, &module, entry, entry);
        AreaGather {
            surface: crate::mesh::pipeline(dev, &surface, "surface", &[SURFACE_FORMAT]),
            level0: pipeline("level0"),
            reduce: pipeline("reduce"),
            gather: pipeline("gather"),
            lookup: pipeline("lookup"),
        }
    }

    /// Records the surface pass, the pyramid and the gather of the target's SSS light into its
    /// scattered light (0 on pixels without SSS, as the separable passes leave them).
    fn encode(
        &self,
        rec: &mut Recording,
        (target, setup, sss_width): Self::Input<'_>,
    ) -> Result<Gathered> {
        let Target {
            camera_view_proj: view_proj,
            size: (w, h),
            mesh,
            gbuffer,
            scattered,
            ..
        } = *target;
        let camera_pos = target.scene.camera.position;
        let (alloc, enc, timer) = (rec.alloc, &mut rec.enc, &mut rec.timer.as_mut());
        let gpu = alloc.gpu;
        setup.pattern.validate()?;
        if !(sss_width.is_finite() && sss_width > 0.0) {
            return Err(GpuError::invalid(
                "sss width",
                sss_width,
                "the area gather needs a width factor > 0",
            ));
        }
        let dev = &gpu.device;
        // The surface pass.
        let view = ViewU {
            view_proj: view_proj.to_cols_array_2d(),
            camera_pos: camera_pos.extend(GRAZING).into(),
        };
        let vbuf = alloc.uniform("surface view", bytemuck::bytes_of(&view));
        let target = alloc.texture(
            "surface",
            (w, h, 1),
            SURFACE_FORMAT,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let target_view = target.create_view(&Default::default());
        let depth = alloc.texture(
            "surface depth",
            (w, h, 1),
            wgpu::TextureFormat::Depth32Float,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        );
        let depth_view = depth.create_view(&Default::default());
        {
            let bind = dev.create_bind_group(&wgpu::BindGroupDescriptor {
                label: None,
                layout: &self.surface.get_bind_group_layout(0),
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: vbuf.as_entire_binding(),
                }],
            });
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("surface"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &target_view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(cleared_depth(&depth_view)),
                timestamp_writes: timer.as_mut().map(|t| t.render_writes("surface")),
                ..Default::default()
            });
            pass.set_pipeline(&self.surface);
            pass.set_bind_group(0, &bind, &[]);
            mesh.draw(&mut pass);
        }
        // The pyramid.
        let taps = setup.pattern.taps();
        let params = Self::params(&setup.kernel, (w, h), taps.len() as u32, sss_width);
        let lv = levels((w, h));
        let texels = lv.iter().map(|l| (l[1] * l[2]) as usize).sum::<usize>();
        let ubuf = alloc.uniform("gather params", bytemuck::bytes_of(&params));
        let [light, pos] = ["light pyramid", "position pyramid"].map(|l| alloc.pixels(texels, l));
        let surface = alloc.pixels((w * h) as usize, "surface");
        let groups = |x: u32, y: u32| (x.div_ceil(8), y.div_ceil(8));
        Self::dispatch(
            gpu,
            enc,
            &self.level0,
            "area level 0",
            &[
                bind(0, &ubuf),
                bind(3, &light),
                bind(4, &pos),
                bind(5, &surface),
                bind(6, &gbuffer.geometry),
                bind(8, &gbuffer.diffuse),
                wgpu::BindGroupEntry {
                    binding: 9,
                    resource: wgpu::BindingResource::TextureView(&target_view),
                },
            ],
            groups(w, h),
            timer.as_deref_mut(),
        );
        for (k, pair) in lv.windows(2).enumerate() {
            let r = ReduceU {
                src: pair[0],
                dst: pair[1],
            };
            let rbuf = alloc.uniform("reduce", bytemuck::bytes_of(&r));
            Self::dispatch(
                gpu,
                enc,
                &self.reduce,
                "area pyramid",
                &[bind(3, &light), bind(4, &pos), bind(10, &rbuf)],
                groups(pair[1][1], pair[1][2]),
                if k == 0 { timer.as_deref_mut() } else { None },
            );
        }
        // The gather.
        let tbuf = alloc.storage("taps", bytemuck::cast_slice(&taps));
        let table = alloc.storage("area table", bytemuck::cast_slice(&setup.kernel.values));
        Self::dispatch(
            gpu,
            enc,
            &self.gather,
            "area gather",
            &[
                bind(0, &ubuf),
                bind(1, &tbuf),
                bind(2, &table),
                bind(3, &light),
                bind(4, &pos),
                bind(5, &surface),
                bind(6, &gbuffer.geometry),
                bind(7, scattered),
            ],
            groups(w, h),
            timer.as_deref_mut(),
        );
        Ok(Gathered {
            surface,
            pos,
            table,
            levels: lv,
        })
    }
}

impl AreaGather {
    fn params(kernel: &AreaKernel, size: (u32, u32), taps: u32, scale: f32) -> Uniform {
        let lv = levels(size);
        let mut level = [[0; 4]; MAX_LEVELS];
        level[..lv.len()].copy_from_slice(&lv);
        Uniform {
            width: size.0,
            height: size.1,
            taps,
            material: 0,
            kernel: kernel.uniform(scale),
            levels: lv.len() as u32,
            _pad: [0; 3],
            level,
        }
    }

    /// One compute pass of `pipeline` with `entries` as its bind group.
    fn dispatch(
        gpu: &Gpu,
        enc: &mut wgpu::CommandEncoder,
        pipeline: &wgpu::ComputePipeline,
        label: &str,
        entries: &[wgpu::BindGroupEntry],
        groups: (u32, u32),
        timer: Option<&mut Timer>,
    ) {
        let bind = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &pipeline.get_bind_group_layout(0),
            entries,
        });
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(label),
            timestamp_writes: timer.map(|t| t.writes(label)),
        });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &bind, &[]);
        pass.dispatch_workgroups(groups.0, groups.1, 1);
    }

    /// The GPU's R′_s/energy at each (distance [cm], area [cm²]) of `points`: what the gather
    /// reads, for checking against [`AreaKernel::lookup`].
    pub(crate) fn lookup(
        &self,
        gpu: &Gpu,
        kernel: &AreaKernel,
        scale: f32,
        points: &[[f32; 2]],
    ) -> Result<Vec<[f32; 3]>> {
        if points.is_empty() {
            return Ok(Vec::new());
        }
        let params = Self::params(kernel, (1, 1), 0, scale);
        let alloc = Alloc::fresh(gpu);
        let ubuf = alloc.uniform("lookup params", bytemuck::bytes_of(&params));
        let table = alloc.storage("area table", bytemuck::cast_slice(&kernel.values));
        let pbuf = alloc.storage("points", bytemuck::cast_slice(points));
        let out = alloc.pixels(points.len(), "values");
        let mut enc = gpu.device.create_command_encoder(&Default::default());
        let bind = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &self.lookup.get_bind_group_layout(0),
            entries: &[
                bind(0, &ubuf),
                bind(2, &table),
                bind(11, &pbuf),
                bind(12, &out),
            ],
        });
        {
            let mut pass = enc.begin_compute_pass(&Default::default());
            pass.set_pipeline(&self.lookup);
            pass.set_bind_group(0, &bind, &[]);
            pass.dispatch_workgroups((points.len() as u32).div_ceil(64), 1, 1);
        }
        gpu.queue.submit([enc.finish()]);
        let bytes = gpu.read_buffer(&out, (points.len() * 16) as u64)?;
        Ok(bytemuck::cast_slice::<u8, [f32; 4]>(&bytes)
            .iter()
            .map(|v| [v[0], v[1], v[2]])
            .collect())
    }
}

/// The surface pass's target: world position and footprint area.
const SURFACE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

#[cfg(test)]
mod tests {
    use super::*;

    /// The default pattern is the paper's: 25 + 10 × 16 taps reaching ≈ 827 px across.
    #[test]
    fn the_default_pattern_is_the_papers() {
        let p = GatherPattern::default();
        assert_eq!(p.taps().len(), 25 + 10 * 16);
        assert!((2.0 * p.reach_px() - 827.0).abs() < 1.0, "{}", p.reach_px());
    }

    /// Eq. 7's layers tile the square of the pattern's reach: the cells' areas add up to it and
    /// no two cells overlap.
    #[test]
    fn the_layers_tile_the_plane() {
        for p in [
            GatherPattern::default(),
            GatherPattern {
                inner: 1,
                ring: 7,
                layers: 4,
                brighten: false,
            },
        ] {
            let taps = p.taps();
            let total: f64 = taps.iter().map(|t| (t.cell_px as f64).powi(2)).sum();
            let side = 2.0 * p.reach_px() as f64;
            assert!((total / (side * side) - 1.0).abs() < 1e-5, "{p:?}");
            for (k, a) in taps.iter().enumerate() {
                for b in &taps[k + 1..] {
                    let gap = |d: usize| {
                        (a.offset_px[d] - b.offset_px[d]).abs() - 0.5 * (a.cell_px + b.cell_px)
                    };
                    assert!(gap(0) > -1e-3 || gap(1) > -1e-3, "{a:?} overlaps {b:?}");
                }
            }
        }
    }

    /// The pyramid's levels halve (rounding up) down to one texel and follow each other.
    #[test]
    fn the_pyramid_reaches_one_texel() {
        let lv = levels((13, 5));
        assert_eq!(
            lv.iter().map(|l| (l[1], l[2])).collect::<Vec<_>>(),
            [(13, 5), (7, 3), (4, 2), (2, 1), (1, 1)]
        );
        assert_eq!(lv[4][0], 65 + 21 + 8 + 2);
    }

    /// The storage structs' sizes agree with area_gather.wgsl's (stride of `Tap` included).
    #[test]
    fn the_tap_and_reduce_structs_match_the_shader() {
        let src = AREA_GATHER_WGSL;
        let module = naga::front::wgsl::parse_str(src).unwrap();
        let mut layouter = naga::proc::Layouter::default();
        layouter.update(module.to_ctx()).unwrap();
        for (ty, size) in [("Tap", TAP_SIZE), ("Reduce", REDUCE_UNIFORM_SIZE)] {
            let (handle, _) = module
                .types
                .iter()
                .find(|(_, t)| t.name.as_deref() == Some(ty))
                .unwrap();
            assert_eq!(layouter[handle].size as usize, size, "{ty}");
        }
    }
}
