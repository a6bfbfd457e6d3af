//! The separable method's passes: one kernel per SSS material blurred over the scene pass's
//! diffuse light ([`crate::passes::blur`]), at full resolution or between a depth-aware down- and
//! upsampling at half ([`crate::passes::half`]), each kernel replaced by a single tap where it
//! reaches less than [`SUBPIXEL_PX`] on screen.

use shading::KernelTaps;

use crate::error::Result;
use crate::frame::context::Gpu;
use crate::frame::recording::Recording;
use crate::frame::target::Target;
use crate::params::RenderParams;
use crate::passes::Pass;
use crate::passes::blur::{Blur, BlurIo, BlurParams};
use crate::passes::half::{HalfRes, half_size};
use crate::scene::Scene;

/// The largest kernel footprint [px] (its farthest tap from the pixel) that
/// [`RenderParams::skip_subpixel`] treats as below a pixel: taps within half a pixel interpolate
/// between the pixel and a neighbour, so the light moves by less than half a pixel.
pub const SUBPIXEL_PX: f32 = 0.5;

/// The largest distance [px] kernel `k` of `material` reaches on screen: its range × width ×
/// the material's largest SSS strength (with jitter, the outermost tap cell's bound instead of the
/// range), at the material's nearest vertex
/// (or the fixed depth). Vertices at or behind the near plane count as at it.
pub fn kernel_footprint_px(
    scene: &Scene,
    material: u32,
    k: &KernelTaps,
    params: &RenderParams,
) -> f32 {
    let view = scene.camera.view();
    let (depth, strength) = scene
        .mesh
        .vertices
        .iter()
        .filter(|v| v.strength > 0.0 && v.material == material)
        .fold((f32::MAX, 0.0f32), |(d, s), v| {
            let z = -(view * glam::Vec3::from(v.pos).extend(1.0)).z;
            (
                d.min(z.max(crate::passes::gbuffer::NEAR)),
                s.max(v.strength),
            )
        });
    let depth = params.fixed_depth.unwrap_or(depth);
    k.reach_cm(params.jitter)
        * params.sss_width
        * strength
        * scene.camera.px_per_cm_at_unit_depth(params.height)
        / depth
}

/// The kernels as the blur applies them (each replaced by a single tap where it reaches less than
/// [`SUBPIXEL_PX`], with `params.skip_subpixel`) and the blur's settings, for `scene` at
/// `params`' size and resolution.
pub(crate) fn blur_setup(
    scene: &Scene,
    given: &[KernelTaps],
    params: &RenderParams,
) -> (Vec<KernelTaps>, BlurParams) {
    // Half resolution: the blur's pixels are 2×2 of the image's.
    let px = if params.half_res { 0.5 } else { 1.0 };
    let kernels: Vec<KernelTaps> = given
        .iter()
        .enumerate()
        .map(|(m, k)| {
            let footprint = px * kernel_footprint_px(scene, m as u32, k, params);
            if params.skip_subpixel && footprint < SUBPIXEL_PX {
                k.point()
            } else {
                k.clone()
            }
        })
        .collect();
    let blur_params = BlurParams {
        px_per_cm_at_unit_depth: px * scene.camera.px_per_cm_at_unit_depth(params.height),
        sss_width: params.sss_width,
        depth_mode: params.depth_mode,
        tolerance_cm: params.tolerance_cm,
        jitter: params.jitter,
        fixed_depth: params.fixed_depth,
        skip_empty: params.skip_empty,
        fast: params.fast,
    };
    (kernels, blur_params)
}

/// The blur and the half-resolution resampling, compiled.
pub(crate) struct Separable {
    blur: Blur,
    half: HalfRes,
}

impl Pass for Separable {
    /// The target, one kernel per SSS material and the frame's settings.
    type Input<'a> = (&'a Target<'a>, &'a [KernelTaps], &'a RenderParams);
    /// Nothing: the kernels write the target's scattered light.
    type Output = ();

    fn new(gpu: &Gpu) -> Separable {
        Separable {
            blur: Blur::new(gpu),
            half: HalfRes::new(gpu),
        }
    }

    /// Records the kernels' passes on the target: one kernel per material, each replaced by a
    /// single tap where it reaches less than [`SUBPIXEL_PX`] (with `params.skip_subpixel`); at
    /// half resolution between a depth-aware down- and upsampling.
    fn encode(&self, rec: &mut Recording, (target, given, params): Self::Input<'_>) -> Result<()> {
        let (scene, (w, h)) = (target.scene, target.size);
        let alloc = rec.alloc;
        let (kernels, blur_params) = blur_setup(scene, given, params);
        let full = (&target.gbuffer.diffuse, &target.gbuffer.geometry);
        if !params.half_res {
            let tmp = alloc.pixels((w * h) as usize, "tmp");
            let io = BlurIo {
                size: (w, h),
                src: full.0,
                geometry: full.1,
                tmp: &tmp,
                dst: target.scattered,
            };
            return self.blur.encode(rec, &kernels, &blur_params, &io);
        }
        let size = half_size((w, h));
        let m = (size.0 * size.1) as usize;
        let [hd, hg, hs, tmp] =
            ["half diffuse", "half geometry", "half scattered", "tmp"].map(|l| alloc.pixels(m, l));
        // Upsampling weights fall by e over the largest kernel's range.
        let tolerance = params
            .tolerance_cm
            .unwrap_or(params.sss_width * given.iter().map(|k| k.range_cm).fold(0.0, f32::max));
        let u = self.half.down(rec, (w, h), tolerance, full, (&hd, &hg));
        let io = BlurIo {
            size,
            src: &hd,
            geometry: &hg,
            tmp: &tmp,
            dst: &hs,
        };
        self.blur.encode(rec, &kernels, &blur_params, &io)?;
        self.half
            .up(rec, (w, h), &u, full, (&hs, &hg), target.scattered);
        Ok(())
    }
}
