//! `sss render`: a scene drawn in wgpu with the material's subsurface scattering, written as PNG
//! and linear PFM. The flags map onto a `render::Request` (defaults: pre-integration with the
//! incidence, exit and entry-shift tables and light through thin parts, the method closest to path
//! tracing); the library checks it, builds the plan and draws the frame. `--compare-models`
//! renders every kernel model beside the CPU 2D ground-truth convolution; `--bench` times the SSS
//! passes.

use anyhow::{Context, Result, bail};
use gpu::Gpu;
use render::{Gather, KernelChoice, Plan};
use serde_json::{Value, json};

use crate::cache::Cached;
use crate::common::Bars;
use crate::files::Outputs;
use crate::library;

mod flags;
pub use flags::RenderArgs;
use flags::{flagged, request};

/// The JSON summary's settings of the method: the kernels, each gather's (null when not used)
/// and the materials' translucency tables.
fn settings_json(plan: &Plan) -> Value {
    let kernels = &plan.kernels;
    json!({
        "kernel": kernels.first().map(|(k, _)| k.model.to_string()),
        "kernels": kernels.iter().map(|(k, _)| json!({"model": k.model.to_string(), "passes": k.pass.len(), "taps": k.taps})).collect::<Vec<_>>(),
        "area_gather": match &plan.gather { Some(Gather::Area(s)) => json!({"inner": s.pattern.inner, "layers": s.pattern.layers, "taps": s.pattern.taps().len(), "reach_px": s.pattern.reach_px(), "brighten": s.pattern.brighten, "r_max_cm": s.kernel.r_max_cm(), "table": gpu::gathers::area_gather::AREA_TABLE_SIZE}), _ => Value::Null },
        "surface_gather": match &plan.gather { Some(Gather::Surface(s)) => json!({"bssrdf": render::Choice::name(s.bssrdf), "samples": s.sampling.samples, "frames": s.sampling.frames, "radius_cm": s.sampling.radius_cm, "light_map": s.sampling.map_size, "seed": s.sampling.seed}), _ => Value::Null },
        "dipole": match &plan.gather { Some(Gather::Dipole(d)) => json!({"samples": d.sampling.samples, "frames": d.sampling.frames, "radius_cm": d.sampling.radius_cm, "light_map": d.sampling.map_size, "scale": d.scale}), _ => Value::Null },
        "translucency": plan.tables.iter().map(|t| t.translucency.as_ref().map(|(t, _)| json!({"first_cm": t.first_cm, "ratio": t.ratio, "tt_over_rho": t.table}))).collect::<Vec<_>>(),
    })
}

/// What the plan tells the user on stderr: its tables, each kernel's rank ladder, its notes.
fn report_plan(plan: &Plan) {
    for t in &plan.tables {
        for line in t.describe() {
            eprintln!("{line}");
        }
    }
    for ((k, choice), t) in plan.kernels.iter().zip(&plan.tables) {
        if let KernelChoice::Ladder(tried, met) = choice {
            for (i, (rank, model, error)) in tried.iter().enumerate() {
                let chosen = *met && i + 1 == tried.len();
                let tail = if chosen { " ≤ target: chosen" } else { "" };
                eprintln!(
                    "{}: rank {rank} ({model}, {} taps) image RMS {error:.5}{tail}",
                    t.slug, k.taps
                );
            }
            if !met {
                eprintln!(
                    "warning: {}: no rank up to {} meets --error-target: using rank {}",
                    t.slug,
                    fit::select::MAX_RANK,
                    fit::select::MAX_RANK
                );
            }
        }
    }
    for note in &plan.notes {
        eprintln!("{note}");
    }
}

pub fn run(mut a: RenderArgs) -> Result<()> {
    let names: Vec<&str> = a.material.split(',').map(str::trim).collect();
    if names.len() > 1 && (a.compare_models || a.bench) {
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
    if a.method == gpu::Method::SurfaceGather && a.bench {
        bail!("--bench does not time the surface gather");
    }
    let materials = names
        .iter()
        .map(|n| {
            library::material(n).map(|n| render::NamedMaterial {
                slug: n.slug,
                material: n.material,
            })
        })
        .collect::<Result<Vec<_>>>()?;
    // Nothing is written outside --out unless --profiles says where.
    a.source.profiles.get_or_insert_with(|| a.out.clone());
    let request = request(&a, materials)?;
    request.check().map_err(flagged)?;
    let mut files = Outputs::default();
    let bars = Bars::default();
    let mut profiles = Cached {
        source: &a.source,
        files: &mut files,
    };
    let plan = Plan::build(&request, &mut profiles, &bars).map_err(flagged)?;
    report_plan(&plan);
    let gpu = Gpu::new()?;
    eprintln!("GPU: {}", gpu.adapter_name);
    let named = &request.materials[0];
    if a.bench {
        let p = render::Profiles::profile(&mut profiles, named)?;
        bench(&gpu, &plan, &p, &a)?;
        return files.commit();
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
        "materials": request.materials.iter().map(|n| &n.slug).collect::<Vec<_>>(), "width": a.width, "height": a.height,
        "seconds": seconds, "png": png_path, "pass_ms": frame.times.iter().map(|t| json!({"pass": t.label, "ms": t.ms})).collect::<Vec<_>>(),
    });
    if let (Some(m), Value::Object(extra)) = (summary.as_object_mut(), settings_json(&plan)) {
        m.extend(extra);
    }
    if a.compare_models {
        let mut profiles = Cached {
            source: &a.source,
            files: &mut files,
        };
        let p = render::Profiles::profile(&mut profiles, named)?;
        summary["compare"] = compare(&gpu, &plan, &p, &a, &mut files)?;
    }
    files.commit()?;
    eprintln!(
        "{what} on {} at {}×{} in {seconds:.2} s → {}",
        a.scene,
        a.width,
        a.height,
        png_path.display()
    );
    if a.compare_models {
        eprintln!(
            "comparison sheet → {}",
            a.out.join("compare_sheet.png").display()
        );
    }
    if a.json {
        println!("{}", serde_json::to_string_pretty(&summary)?);
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
    let c = report::render_checks::compare_models(
        gpu,
        &plan.scene,
        &a.scene,
        &plan.params,
        p,
        (&m.slug, &media),
        a.taps,
    )
    .with_context(|| format!("--compare-models: {}", m.slug))?;
    eprintln!("{}", c.scale);
    if !a.json {
        c.table.iter().for_each(|l| println!("{l}"));
    }
    let mut rows = c.rows;
    for ((label, png), row) in c.images.into_iter().zip(rows.iter_mut().skip(1)) {
        let path = a.out.join(format!("{label}.png"));
        row["png"] = json!(path);
        files.add(path, png);
    }
    let sheet = a.out.join("compare_sheet.png");
    files.add(&sheet, c.sheet);
    let v = json!({ "cm_per_px": c.cm_per_px, "models": rows, "sheet": sheet });
    files.add(
        a.out.join("compare.json"),
        serde_json::to_string_pretty(&v)?,
    );
    Ok(v)
}

/// `--bench`: the directional dipole's time per frame, or the separable passes' every
/// configuration and skip (`gpu::bench`), as a table (stdout, or stderr with --json) and with
/// --json as JSON on stdout.
fn bench(gpu: &Gpu, plan: &Plan, p: &fit::Profile, a: &RenderArgs) -> Result<()> {
    let slug = &plan.materials[0].slug;
    let (table, json) = match &plan.gather {
        Some(Gather::Dipole(setup)) => {
            if !gpu.timestamps {
                eprintln!(
                    "this adapter has no timestamp queries: reporting whole-render wall time instead"
                );
            }
            let rows = gpu::eval::bench::dipole(gpu, &plan.scene, setup)?;
            let table = report::render_checks::dipole_bench_table(
                &rows,
                &gpu.adapter_name,
                slug,
                setup.sampling.frames,
            );
            (table, json!({"adapter": gpu.adapter_name, "rows": rows}))
        }
        gather => {
            if !gpu.timestamps {
                eprintln!(
                    "this adapter has no timestamp queries: GPU times are null, frame times remain"
                );
            }
            let cpu_adapter = gpu.adapter_name.contains("Cpu");
            if cpu_adapter {
                eprintln!(
                    "{} runs on the CPU: its timestamps do not measure the work; compare the frame-time ratios",
                    gpu.adapter_name
                );
            }
            let area = match gather {
                Some(Gather::Area(s)) => Some(s.as_ref()),
                _ => None,
            };
            let b = gpu::eval::bench::separable(gpu, &plan.scene, (p, slug), &plan.params, area)?;
            let title = format!(
                "SSS passes at {}×{} on {} ({slug} on {}, renderer built once, median of 5 frames)",
                a.width, a.height, gpu.adapter_name, a.scene
            );
            let json = json!({
                "adapter": gpu.adapter_name, "width": a.width, "height": a.height,
                "scene": a.scene, "material": slug, "timestamps": gpu.timestamps,
                "cpu_adapter": cpu_adapter, "configs": b.configs, "skips": b.skips,
            });
            (
                report::render_checks::separable_bench_table(&b, &title),
                json,
            )
        }
    };
    for line in table {
        if a.json {
            eprintln!("{line}")
        } else {
            println!("{line}")
        }
    }
    if a.json {
        println!("{}", serde_json::to_string_pretty(&json)?);
    }
    Ok(())
}
