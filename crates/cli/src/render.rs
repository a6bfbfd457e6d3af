//! `sss render`: a scene drawn in wgpu with the material's subsurface scattering, written as PNG
//! and linear PFM. The flags map onto a `render::Request` (defaults: pre-integration with the
//! incidence, exit and entry-shift tables and light through thin parts, the method closest to path
//! tracing); the library checks it, builds the plan and draws the frame. `--compare-models`
//! renders every kernel model beside the CPU 2D ground-truth convolution; `--bench` times the SSS
//! passes.

use anyhow::{Context, Result, bail};
use gpu::Gpu;
use render::{Gather, Plan};
use report::render_checks::{self, compare_models};
use serde_json::{Value, json};

use crate::files::Outputs;
use crate::library;

mod flags;
pub use flags::RenderArgs;
use flags::{flagged, request};

pub fn run(mut a: RenderArgs) -> Result<()> {
    let names: Vec<&str> = a.material.split(',').map(str::trim).collect();
    if names.len() > 1 && (a.compare_models || a.bench.is_some()) {
        bail!(
            "--compare-models and --bench take a scene of one SSS material (--material names {})",
            names.len()
        );
    }
    if a.method != gpu::Method::Separable && a.compare_models {
        bail!(
            "--compare-models compares the separable method's kernels: it takes --method separable"
        );
    }
    let materials = names
        .iter()
        .map(|n| library::material(n))
        .collect::<Result<Vec<_>>>()?;
    // Nothing is written outside --out unless --profiles says where.
    a.source.profiles.get_or_insert_with(|| a.out.clone());
    let request = request(&a, materials)?;
    request.check().map_err(flagged)?;
    let slugs: Vec<String> = request.materials.iter().map(|n| n.slug.clone()).collect();
    render::folder::claim(&a.out, &a.scene, &slugs, a.overwrite).map_err(flagged)?;
    let mut files = Outputs::checked(&a.out)?;
    let plan = (a.source)
        .build(&mut files, |p, bars| Plan::build(&request, p, bars))
        .map_err(flagged)?;
    for line in render::summary::plan_lines(&plan) {
        eprintln!("{line}");
    }
    let gpu = Gpu::new()?;
    eprintln!("GPU: {}", gpu.adapter_name);
    let named = &request.materials[0];
    if a.bench.is_some() {
        bench(&gpu, &plan, &a.source.profile(named, &mut files)?, &a)?;
        return Ok(files.commit()?);
    }
    let start = std::time::Instant::now();
    let frame = plan.render(&gpu)?;
    let seconds = start.elapsed().as_secs_f64();
    let png_path = a.out.join("render.png");
    files.add(
        &png_path,
        report::image::png_rgba(frame.width, frame.height, &frame.display)?,
    );
    files.add(
        a.out.join("render.pfm"),
        report::image::pfm(frame.width, frame.height, &frame.linear),
    );
    let what = render::describe(&plan);
    let mut summary = json!({
        "adapter": gpu.adapter_name, "scene": a.scene, "method": render::Choice::name(a.method),
        "materials": slugs, "width": a.width, "height": a.height,
        "seconds": seconds, "png": png_path, "pass_ms": frame.times.iter().map(|t| json!({"pass": t.label, "ms": t.ms})).collect::<Vec<_>>(),
    });
    if let (Some(m), Value::Object(extra)) = (
        summary.as_object_mut(),
        render::summary::settings_json(&plan),
    ) {
        m.extend(extra);
    }
    if a.compare_models {
        let p = a.source.profile(named, &mut files)?;
        summary["compare"] = compare(&gpu, &plan, &p, &a, &mut files)?;
    }
    let record = serde_json::to_vec_pretty(&summary)?;
    files.add(a.out.join(render::folder::RECORD), record);
    files.commit()?;
    let (scene, w, h, png) = (&a.scene, a.width, a.height, png_path.display());
    eprintln!("{what} on {scene} at {w}×{h} in {seconds:.2} s → {png}");
    let sheet = a.out.join("compare_sheet.png");
    if a.compare_models {
        eprintln!("comparison sheet → {}", sheet.display());
    }
    if a.json {
        crate::common::print_json(&summary)?;
    }
    Ok(())
}

/// `--compare-models`: every kernel model against the CPU 2D ground truth
/// (`report::render_checks`): the table on stdout (not with --json), each model's PNG, the sheet
/// and compare.json.
fn compare(
    gpu: &Gpu,
    plan: &Plan,
    p: &fit::Profile,
    a: &RenderArgs,
    files: &mut Outputs,
) -> Result<Value> {
    let m = &plan.materials[0];
    let media = fit::analytic::Medium::channels(&m.material);
    let (scene, params) = (&plan.scene, &plan.params);
    let c = compare_models(gpu, scene, &a.scene, params, p, (&m.slug, &media), a.taps)
        .with_context(|| format!("--compare-models: {}", m.slug))?;
    eprintln!("{}", c.scale);
    if !a.json {
        c.table.iter().for_each(|l| println!("{l}"));
    }
    Ok(c.add_files(&a.out, files))
}

/// `--bench` (`report::render_checks::bench`): this frame's time, the dipole's per frame, or the
/// separable passes' every configuration and skip, as a table (stdout, or stderr with --json)
/// and with --json as JSON on stdout.
fn bench(gpu: &Gpu, plan: &Plan, p: &fit::Profile, a: &RenderArgs) -> Result<()> {
    let slug = &plan.materials[0].slug;
    let gathers = Gather::timed(&plan.gather);
    let scene = (&plan.scene, a.scene.as_str(), a.width, a.height);
    let what = render::describe(plan);
    let surface = matches!(plan.gather, Some(Gather::Surface(_)));
    let frame = (surface || a.bench.as_deref() == Some("frame")).then(|| (plan.scatter(), &*what));
    let b = render_checks::bench(gpu, scene, (p, slug), &plan.params, gathers, frame)?;
    b.warnings.iter().for_each(|w| eprintln!("{w}"));
    for line in b.table {
        if a.json {
            eprintln!("{line}")
        } else {
            println!("{line}")
        }
    }
    if a.json {
        crate::common::print_json(&b.json)?;
    }
    Ok(())
}
