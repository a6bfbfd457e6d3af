//! What `sss render --compare-models` and `--bench` report: every kernel model rendered against
//! the CPU 2D ground truth (its table, images and sheet), and the benchmarks' tables. Text and
//! bytes only; the caller prints and writes them.

use fit::analytic::Medium;
use fit::taps::TapSpec;
use fit::{KernelModel, Profile};
use gpu::eval::bench::{DipoleRow, SeparableBench};
use gpu::eval::compare::{ImageError, Shown};
use gpu::{AreaGatherSetup, DipoleSetup, Gpu, RenderParams, Scatter, Scene};
use mc::outputs::Outputs;
use serde_json::{Value, json};
use std::path::Path;

use crate::error::Result;

/// The kernels compared by --compare-models: (label, model). SVD is rescaled to the kernel's
/// energy (‖A‖₁ = ‖R_d‖₁) for images, as `eval` does.
pub const MODELS: [(&str, KernelModel); 8] = [
    ("preint", KernelModel::Preint),
    (
        "svd1",
        KernelModel::Svd {
            rank: 1,
            renormalize: true,
        },
    ),
    (
        "svd3",
        KernelModel::Svd {
            rank: 3,
            renormalize: true,
        },
    ),
    ("deon3", KernelModel::Deon { n: 3 }),
    ("guided", KernelModel::Guided { k: 1.0, b: 0.0 }),
    ("manual", KernelModel::Manual(fit::ManualParams::Auto)),
    (
        "skin",
        KernelModel::Skin(fit::SkinParams::Given(fit::skin::Skin::DEMO)),
    ),
    ("burley", KernelModel::Burley { radial: false }),
];

/// The comparison of every model in [`MODELS`] and the area gather with the paper's pattern.
pub struct ModelComparison {
    /// The scale the kernels were drawn at, a line.
    pub scale: String,
    /// The table of image RMS per model (relative to the SSS pixels' mean), lines.
    pub table: Vec<String>,
    /// Each model's rendered image as PNG, by label.
    pub images: Vec<(String, Vec<u8>)>,
    /// The sheet of cut-outs with difference images, PNG.
    pub sheet: Vec<u8>,
    /// One JSON row per model: `model`, `image_rms_rel`, `image_rms_rel_rgb`.
    pub rows: Vec<Value>,
    /// The image scale [cm per pixel].
    pub cm_per_px: f64,
}

/// Every model of [`MODELS`] fitted to `p` with `taps` taps, and the area gather of `media`,
/// rendered on `scene` (called `scene_name`) with `base`'s settings against the CPU 2D ground
/// truth ([`gpu::compare_models`]).
#[allow(clippy::too_many_arguments)]
pub fn compare_models(
    gpu: &Gpu,
    scene: &Scene,
    scene_name: &str,
    base: &RenderParams,
    p: &Profile,
    (slug, media): (&str, &[Medium; 3]),
    taps: usize,
) -> Result<ModelComparison> {
    let scale = gpu::eval::compare::kernel_scale(scene, base.height, p, base.sss_width);
    let scale_line = format!(
        "comparing models at {:.4} cm/px (profile bins of {:.4} cm × {}) …",
        scale.cm_per_px, p.dr, scale.bin
    );
    let models: Vec<KernelModel> = MODELS.iter().map(|(_, m)| *m).collect();
    let spec = TapSpec {
        taps,
        ..Default::default()
    };
    let cmp = gpu::compare_models(gpu, scene, base, p, slug, &models, spec)?;
    let mut table = vec![
        format!(
            "{slug} on {scene_name}: image RMS of the scattered diffuse against the 2D ground truth (SSS pixels, relative to their mean)"
        ),
        format!(
            "  {:<11} {:>9} {:>8} {:>8} {:>8}",
            "model", "RGB", "R", "G", "B"
        ),
    ];
    let line = |label: &str, e: &ImageError| {
        let pct = |x: f64| format!("{:.3}%", 100.0 * x);
        format!(
            "  {label:<11} {:>9} {:>8} {:>8} {:>8}",
            pct(e.rms_rel_all),
            pct(e.rms_rel[0]),
            pct(e.rms_rel[1]),
            pct(e.rms_rel[2])
        )
    };
    let l = &cmp.lambert;
    table.push(line("lambert", &l.error));
    let row = |label: &str, e: &ImageError| json!({"model": label, "image_rms_rel": e.rms_rel_all, "image_rms_rel_rgb": e.rms_rel});
    let mut rows = vec![row("lambert", &l.error)];
    // The area gather with the paper's pattern, at the pixels' true depths.
    let kernel = gpu::AreaKernel::for_material(slug, media, p)?;
    let area = cmp.area_gather(gpu, scene, base, &gpu::AreaGatherSetup::new(kernel))?;
    let labels = MODELS.iter().map(|(l, _)| *l).chain(["area-gather"]);
    let shown: Vec<(&str, &Shown)> = labels.zip(cmp.kernels.iter().chain([&area])).collect();
    let mut images = Vec::new();
    for &(label, k) in &shown {
        table.push(line(label, &k.error));
        rows.push(row(label, &k.error));
        let png = crate::image::png_rgba(base.width, base.height, &k.display)?;
        images.push((label.to_string(), png));
    }
    let title = vec![
        format!(
            "{slug} on {scene_name}: each kernel model against the CPU 2D ground truth (scattered diffuse light)"
        ),
        format!(
            "cut-out of {0}×{0} px around the strongest shadow edge; {1:.4} cm per pixel",
            cmp.crop.side, cmp.scale.cm_per_px
        ),
    ];
    let lambert = [("no SSS (Lambert)", l)];
    let all: Vec<_> = lambert.into_iter().chain(shown).collect();
    let sheet = crate::sheet::comparison_sheet(&cmp, title, &all, base.exposure)?;
    Ok(ModelComparison {
        scale: scale_line,
        table,
        images,
        sheet,
        rows,
        cm_per_px: cmp.scale.cm_per_px,
    })
}

/// A time [ms] with three decimals, or "-" where there is none.
fn ms(v: Option<f64>) -> String {
    v.map_or("-".to_string(), |v| format!("{v:.3}"))
}

/// The directional dipole's benchmark ([`gpu::eval::bench::dipole`]) as a table, `adapter`, `slug` and
/// the `frames` per render in its title.
pub fn dipole_bench_table(
    rows: &[DipoleRow],
    adapter: &str,
    slug: &str,
    frames: u32,
) -> Vec<String> {
    let mut t = vec![
        format!(
            "directional dipole at 1920×1080 on {adapter} ({slug}, {frames} frames per render, median of 3 renders)"
        ),
        format!(
            "  {:>6} {:>8} {:>18} {:>18}",
            "lights", "samples", "dipole ms/frame", "render wall ms"
        ),
    ];
    for r in rows {
        t.push(format!(
            "  {:>6} {:>8} {:>18} {:>18.1}",
            r.lights,
            r.samples,
            ms(r.dipole_ms_per_frame),
            r.render_wall_ms
        ));
    }
    t
}

/// The separable passes' benchmark ([`gpu::eval::bench::separable`]) as a table: every configuration
/// and what each skip saves; `title` names the image, adapter, material and scene.
pub fn separable_bench_table(b: &SeparableBench, title: &str) -> Vec<String> {
    let mut t = vec![
        title.to_string(),
        format!(
            "  {:<12} {:>5} {:>5} {:>10} {:>6} {:>12} {:>10} {:>14}",
            "kernel", "taps", "rank", "resolution", "path", "SSS GPU ms", "frame ms", "÷ preint 17"
        ),
    ];
    for c in &b.configs {
        t.push(format!(
            "  {:<12} {:>5} {:>5} {:>10} {:>6} {:>12} {:>10.1} {:>14.2}",
            c.kernel,
            c.taps,
            c.rank.map_or("-".into(), |r| r.to_string()),
            c.resolution,
            c.path,
            ms(c.gpu_ms),
            c.frame_ms,
            c.frame_ratio_to_preint17
        ));
    }
    let s = &b.skips;
    let (e, f, r) = (&s.empty_pixels, &s.subpixel_kernels, &s.rank_target);
    t.push("skips (preint, 17 taps; SSS GPU ms on / off, frame ms on / off):".into());
    t.push(format!(
        "  pixels without SSS ({:.0} % of the image has SSS): {} / {}, {:.1} / {:.1}",
        100.0 * e.sss_pixel_fraction,
        ms(e.saving.gpu_ms_on),
        ms(e.saving.gpu_ms_off),
        e.saving.frame_ms_on,
        e.saving.frame_ms_off
    ));
    t.push(format!(
        "  sub-pixel kernels (the scene {:.1}× as far, footprint {:.1} → {:.2} px): {} / {}, {:.1} / {:.1}",
        f.distance_factor,
        f.near_footprint_px,
        f.footprint_px,
        ms(f.saving.gpu_ms_on),
        ms(f.saving.gpu_ms_off),
        f.saving.frame_ms_on,
        f.saving.frame_ms_off
    ));
    t.push(format!(
        "  ranks beyond an image-error target ({:.5}, 1.05 × the best of ranks 1–3): rank {} chosen, frame ms {:.1} / {:.1} (rank 3)",
        r.target_image_rms, r.rank_chosen, r.saving.frame_ms_on, r.saving.frame_ms_off
    ));
    t
}

impl ModelComparison {
    /// Its files in `out` (each model's `LABEL.png`, `compare_sheet.png` and `compare.json`),
    /// added to `files`; and `compare.json`'s value (each row with its PNG's path).
    pub fn add_files(self, out: &Path, files: &mut Outputs) -> Value {
        let mut rows = self.rows;
        for ((label, png), row) in self.images.into_iter().zip(rows.iter_mut().skip(1)) {
            let path = out.join(format!("{label}.png"));
            row["png"] = json!(path);
            files.add(path, png);
        }
        let sheet = out.join("compare_sheet.png");
        files.add(&sheet, self.sheet);
        let v = json!({ "cm_per_px": self.cm_per_px, "models": rows, "sheet": sheet });
        files.add(out.join("compare.json"), format!("{v:#}"));
        v
    }
}

/// What `--bench` measured: lines for stderr (what the adapter cannot measure), the table, and
/// the JSON.
pub struct Bench {
    /// Warnings about the adapter's timestamps.
    pub warnings: Vec<String>,
    /// The table, lines.
    pub table: Vec<String>,
    /// The measurements.
    pub json: Value,
}

/// The scene `scene_name` at `width` × `height` timed (`gpu::eval::bench`): with `frame` (the
/// frame's scattering and what it is) that frame alone, else the directional dipole's time per
/// frame when `dipole` is given, else the separable passes' every configuration and skip of `p`
/// (with the area gather's set-up `area`, if any).
pub fn bench(
    gpu: &Gpu,
    (scene, scene_name, width, height): (&Scene, &str, u32, u32),
    (p, slug): (&Profile, &str),
    params: &RenderParams,
    (dipole, area): (Option<&DipoleSetup>, Option<&AreaGatherSetup>),
    frame: Option<(Scatter, &str)>,
) -> Result<Bench> {
    let mut warnings = Vec::new();
    if let Some((scatter, what)) = frame {
        let b = gpu::eval::bench::frame(gpu, scene, scatter, params)?;
        let gpu_ms = b
            .gpu_ms
            .map_or(String::new(), |g| format!(", passes {g:.1} ms on the GPU"));
        let table = vec![format!(
            "{what} on {scene_name} at {width}×{height} on {}: {:.1} ms a frame{gpu_ms} (median of {} frames on a renderer built once, after one that compiles)",
            gpu.adapter_name, b.frame_ms, b.frames
        )];
        let json = json!({
            "adapter": gpu.adapter_name, "width": width, "height": height, "scene": scene_name,
            "material": slug, "method": what, "frame_ms": b.frame_ms, "gpu_ms": b.gpu_ms,
            "frames": b.frames,
        });
        return Ok(Bench {
            warnings,
            table,
            json,
        });
    }
    if let Some(setup) = dipole {
        if !gpu.timestamps {
            warnings.push(
                "this adapter has no timestamp queries: reporting whole-render wall time instead"
                    .to_string(),
            );
        }
        let rows = gpu::eval::bench::dipole(gpu, scene, setup)?;
        let frames = setup.sampling.frames;
        let table = dipole_bench_table(&rows, &gpu.adapter_name, slug, frames);
        let json = json!({"adapter": gpu.adapter_name, "rows": rows});
        return Ok(Bench {
            warnings,
            table,
            json,
        });
    }
    if !gpu.timestamps {
        warnings.push(
            "this adapter has no timestamp queries: GPU times are null, frame times remain".into(),
        );
    }
    let cpu_adapter = gpu.adapter_name.contains("Cpu");
    if cpu_adapter {
        warnings.push(format!(
            "{} runs on the CPU: its timestamps do not measure the work; compare the frame-time ratios",
            gpu.adapter_name
        ));
    }
    let b = gpu::eval::bench::separable(gpu, scene, (p, slug), params, area)?;
    let title = format!(
        "SSS passes at {width}×{height} on {} ({slug} on {scene_name}, renderer built once, median of 5 frames)",
        gpu.adapter_name
    );
    let json = json!({
        "adapter": gpu.adapter_name, "width": width, "height": height,
        "scene": scene_name, "material": slug, "timestamps": gpu.timestamps,
        "cpu_adapter": cpu_adapter, "configs": b.configs, "skips": b.skips,
    });
    Ok(Bench {
        warnings,
        table: separable_bench_table(&b, &title),
        json,
    })
}
