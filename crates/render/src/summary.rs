//! What a plan tells its caller's user: the lines to show before drawing (each material's
//! tables, each kernel's rank ladder, the plan's notes) and the JSON summary of the method's
//! settings.

use serde_json::{Value, json};

use crate::plan::{Gather, KernelChoice, Plan};

/// The lines to show before drawing: each material's tables, each kernel's rank ladder (with a
/// warning where no rank met the target) and the plan's notes.
pub fn plan_lines(plan: &Plan) -> Vec<String> {
    let mut lines: Vec<String> = plan.tables.iter().flat_map(|t| t.describe()).collect();
    for ((k, choice), t) in plan.kernels.iter().zip(&plan.tables) {
        if let KernelChoice::Ladder(tried, met) = choice {
            for (i, (rank, model, error)) in tried.iter().enumerate() {
                let chosen = *met && i + 1 == tried.len();
                let tail = if chosen { " ≤ target: chosen" } else { "" };
                lines.push(format!(
                    "{}: rank {rank} ({model}, {} taps) image RMS {error:.5}{tail}",
                    t.slug, k.taps
                ));
            }
            if !met {
                let max = fit::select::MAX_RANK;
                lines.push(format!(
                    "warning: {}: no rank up to {max} meets --error-target: using rank {max}",
                    t.slug
                ));
            }
        }
    }
    lines.extend(plan.notes.iter().cloned());
    lines
}

/// The JSON summary's settings of the method: the kernels, each gather's (null when not used)
/// and the materials' translucency tables.
pub fn settings_json(plan: &Plan) -> Value {
    let kernels = &plan.kernels;
    json!({
        "kernel": kernels.first().map(|(k, _)| k.model.to_string()),
        "kernels": kernels.iter().map(|(k, _)| json!({"model": k.model.to_string(), "passes": k.pass.len(), "taps": k.taps})).collect::<Vec<_>>(),
        "area_gather": match &plan.gather { Some(Gather::Area(s)) => json!({"inner": s.pattern.inner, "layers": s.pattern.layers, "taps": s.pattern.taps().len(), "reach_px": s.pattern.reach_px(), "brighten": s.pattern.brighten, "r_max_cm": s.kernel.r_max_cm(), "table": gpu::gathers::area_gather::AREA_TABLE_SIZE}), _ => Value::Null },
        "surface_gather": match &plan.gather { Some(Gather::Surface(s)) => json!({"bssrdf": crate::Choice::name(s.bssrdf), "samples": s.sampling.samples, "frames": s.sampling.frames, "radius_cm": s.sampling.radius_cm, "light_map": s.sampling.map_size, "seed": s.sampling.seed}), _ => Value::Null },
        "dipole": match &plan.gather { Some(Gather::Dipole(d)) => json!({"samples": d.sampling.samples, "frames": d.sampling.frames, "radius_cm": d.sampling.radius_cm, "light_map": d.sampling.map_size, "scale": d.scale}), _ => Value::Null },
        "translucency": plan.tables.iter().map(|t| t.translucency.as_ref().map(|(t, _)| json!({"first_cm": t.first_cm, "ratio": t.ratio, "tt_over_rho": t.table}))).collect::<Vec<_>>(),
    })
}
