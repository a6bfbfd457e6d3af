//! `sss reproduce`'s chapter-5 figures that the tables do not cover, on Skin1 (the thesis's
//! example material throughout chapter 5): Fig. 5.14–5.15, guided optimization with k = 1.55,
//! b = 50 imitating pre-integration ([`fit::imitation`]), and Fig. 5.17, the manual model's w
//! sweep with Table A.1's Gaussians ([`fit::WSweep`]). Each adds a plot, a `report.json` field,
//! claims rows and an HTML section with its caption.

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use anyhow::{Context, Result};
use fit::evaluate::ImageSize;
use fit::imitation::{IMITATION, Imitation};
use fit::{KernelModel, Profile, WSweep, ground_truth, table_a1};
use serde_json::{Value, json};

use crate::files::Outputs;
use crate::library;

/// The material of chapter 5's figures.
const MATERIAL: &str = "skin1";

/// The swept w: 0, 0.05, …, 1.
fn swept() -> Vec<f64> {
    (0..=20).map(|i| f64::from(i) / 20.0).collect()
}

/// Measures both figures on Skin1's profile, adds their plots to `files` and their numbers and
/// claims to `report` (`fig_5_15`, `fig_5_17`, rows appended to `claims`).
pub fn add(
    report: &mut Value,
    all: &[library::Named],
    profiles: &[Profile],
    image: ImageSize,
    out: &Path,
    files: &mut Outputs,
) -> Result<()> {
    let i = all
        .iter()
        .position(|n| n.slug == MATERIAL)
        .context("skin1 is a built-in material")?;
    let (p, material) = (&profiles[i], &all[i].material);
    eprintln!(
        "guided k = 1.55, b = 50 against pre-integration, and the manual w sweep ({MATERIAL}) …"
    );

    // Fig. 5.15: b = 50 is defined on the kernel's extent, which in the thesis is 32 of the
    // largest MFP (Table 6.1, our thesis settings): a shorter profile (--quick) is padded with
    // zeros to it, so the axis band reaches the thesis's ≈ 32/√50 ≈ 4.5 MFP.
    let t = Instant::now();
    let reach_mfp = library::config(None)?.grid.r_max_mfp;
    let max_mfp = (0..3).map(|c| material.mfp(c)).fold(0.0, f64::max);
    let half = p.len().max((reach_mfp * max_mfp / p.dr).ceil() as usize);
    let padded: Vec<_> = (0..3).map(|c| ground_truth(p, c, Some(half))).collect();
    let imitation = Imitation::measure(&padded, image)?;
    let imitation_seconds = t.elapsed().as_secs_f64();
    files.add(
        out.join("fig5_15_guided_vs_preint.png"),
        fit::plot::imitation(&imitation, "Skin1")?,
    );

    // Fig. 5.17: Table A.1's τ_n, τ_f on the profile's own grid, as Table 6.3's manual kernel.
    let t = Instant::now();
    let params = table_a1(MATERIAL).context("Table A.1 has Skin1")?;
    let table_w = params[0].w;
    let truths: Vec<_> = (0..3).map(|c| ground_truth(p, c, None)).collect();
    let sweep = WSweep::measure(&truths, params, &swept(), &[0.1, table_w, 0.9], image)?;
    let sweep_seconds = t.elapsed().as_secs_f64();
    files.add(
        out.join("fig5_17_manual_w_sweep.png"),
        fit::plot::w_sweep(&sweep, "Skin1")?,
    );

    report["fig_5_15"] = json!({
        "material": MATERIAL,
        "signal": "shaded",
        "extent_mfp": reach_mfp,
        "half_samples": imitation.half,
        "h_cm": imitation.h,
        "models": imitation.candidates.iter().map(|c| json!({
            "model": c.model, "name": c.model.title(),
            "image_distance": c.image_distance, "kernel_distance": c.kernel_distance,
            "fit_seconds_per_channel": c.fit_seconds[0],
        })).collect::<Vec<_>>(),
        "k_spread": imitation.k_spread.iter().map(|(b, d)| json!({ "b": b, "image_distance": d })).collect::<Vec<_>>(),
        "seconds": imitation_seconds,
    });
    report["fig_5_17"] = json!({
        "material": MATERIAL,
        "table_a1_w": table_w,
        "sqrt_tau_near_cm": params.map(|m| m.tau_near.sqrt()),
        "sqrt_tau_far_cm": params.map(|m| m.tau_far.sqrt()),
        "w": sweep.w,
        "image_rms": sweep.image_rms,
        "edge_width_cm": sweep.edge_width,
        "truth_edge_width_cm": sweep.truth_edge_width,
        "best_w": sweep.best_w(),
        "seconds": sweep_seconds,
    });
    let rows = claims(&imitation, &sweep, table_w);
    match report["claims"].as_array_mut() {
        Some(c) => c.extend(rows),
        None => report["claims"] = Value::Array(rows),
    }
    Ok(())
}

/// R/G/B values with `digits` decimals.
fn rgb(v: [f64; 3], digits: usize) -> String {
    v.map(|x| format!("{x:.digits$}")).join(" / ")
}

fn claims(im: &Imitation, s: &WSweep, table_w: f64) -> Vec<Value> {
    let d = |m: KernelModel| {
        im.candidate(m)
            .expect("fit::imitation::COMPARED holds every model compared here")
    };
    let k1 = KernelModel::Guided { k: 1.0, b: 0.0 };
    let svd1 = KernelModel::Svd {
        rank: 1,
        renormalize: false,
    };
    let (ours, guided, svd) = (d(IMITATION), d(k1), d(svd1));
    let closer = (0..3).all(|c| {
        ours.image_distance[c] < guided.image_distance[c]
            && ours.image_distance[c] < svd.image_distance[c]
    });
    // The closest of all compared models per channel, named in the explanation.
    let closest = [0, 1, 2].map(|c| {
        im.candidates
            .iter()
            .min_by(|a, b| a.image_distance[c].total_cmp(&b.image_distance[c]))
            .map(|m| m.model.to_string())
            .unwrap_or_default()
    });
    let spread = |b: f64| {
        im.k_spread
            .iter()
            .find(|s| s.0 == b)
            .map(|s| s.1)
            .unwrap_or([f64::NAN; 3])
    };
    let (without, with) = (spread(0.0), spread(50.0));
    let weakened = (0..3).all(|c| with[c] < without[c]);
    let kernel_close = (0..3).all(|c| ours.kernel_distance[c] < guided.kernel_distance[c]);

    let first = |c: usize| s.edge_width.first().map_or(f64::NAN, |w| w[c]);
    let last = |c: usize| s.edge_width.last().map_or(f64::NAN, |w| w[c]);
    let monotone = (0..3).all(|c| s.edge_width.windows(2).all(|p| p[1][c] < p[0][c]));
    let best = s.best_w();
    let near_optimum = best.iter().all(|b| (b - table_w).abs() <= 0.2);
    vec![
        json!({ "claim": "Fig. 5.15: guided k = 1.55, b = 50 gives images closer to pre-integration's than guided k = 1 (b = 0) and SVD rank-1 (shaded test signal, every channel)",
                "ours": format!("relative image distance R / G / B: {} (k = 1: {}; SVD rank-1: {})", rgb(ours.image_distance, 4), rgb(guided.image_distance, 4), rgb(svd.image_distance, 4)),
                "published": "similar to pre-integration (Fig. 5.15a–b, by eye)", "holds": closer,
                "why": format!("The axis term (1 − e^(−b x̂²))(1 − e^(−b ŷ²)) lowers the weights on and near the main axes, as the guide Γ_p under which eq. 5.19's optimum is pre-integration does (Fig. 5.14). The kernels are fitted on the thesis's extent (32 of the largest MFP, Table 6.1), the one b = 50 is defined on. Closest of all compared models, R / G / B: {}.", closest.join(" / ")) }),
        json!({ "claim": "Fig. 5.15c–d: with b = 50, k no longer controls centre against falloff: the images of k = 0 and k = 2 differ less than without the axis term (every channel)",
                "ours": format!("k = 0 vs k = 2, relative image distance R / G / B: {} with b = 50, {} with b = 0", rgb(with, 4), rgb(without, 4)),
                "published": "Fig. 5.15c (k = 0) looks like Fig. 5.15d (k = 2)", "holds": weakened,
                "why": "With the axis term the weight vanishes near both axes and the centre (Γ ≈ b²x̂²ŷ²·r^k there) whatever k, so the centre, which k = 0 otherwise fits closely, is left to the L1 constraint in every case." }),
        json!({ "claim": "Fig. 5.15 (kernel space): the k = 1.55, b = 50 kernel itself is closer to pre-integration's than guided k = 1's (‖A − A_p‖_F / ‖A_p‖_F, every channel)",
                "ours": format!("R / G / B: {} (k = 1: {})", rgb(ours.kernel_distance, 3), rgb(guided.kernel_distance, 3)),
                "published": "not measured (the thesis compares images)", "holds": kernel_close,
                "why": "Our fit meets ‖a‖₁² = ‖R_d‖₁ exactly; with b > 0 the rows next to the axes carry almost no weight, so the constraint's multiplier piles mass there and the kernel has a narrow spike at the centre. Images, binned to the evaluation grid, barely see it; the Frobenius norm does. The thesis used a weakened soft constraint (up to 25 % off, §6.4), which would not." }),
        json!({ "claim": "Fig. 5.17: raising w moves the manual kernel from far scattering (pronounced falloff) to near scattering (sharper features): the edge's 10–90 % width falls monotonically with w (every channel)",
                "ours": format!("edge width R / G / B from w = 0 to w = 1: {} → {} cm (ground truth {} cm)", rgb([0, 1, 2].map(first), 3), rgb([0, 1, 2].map(last), 3), rgb(s.truth_edge_width, 3)),
                "published": "a seamless transition (Fig. 5.17c–e, by eye)", "holds": monotone,
                "why": "The light across an edge is the tail ∫ₓ^∞ a_m = w·Q_n(x) + (1 − w)·Q_f(x) of the two Gaussians' tails (eq. 5.15); the narrow Gaussian's tail is below the wide one's at every x > 0, so every point of the edge moves towards the narrow one as w grows." }),
        json!({ "claim": "Table A.1 (§5.4, parameters optimized by hand in image space): Skin1's w = 0.533 lies within 0.2 of the w with the lowest image-space error (every channel)",
                "ours": format!("lowest image-space RMS at w = {} (R / G / B)", rgb(best, 2)),
                "published": format!("w = {table_w}"), "holds": near_optimum,
                "why": format!("Table A.1's Gaussians are narrower than our Skin1 profile: even the far one alone (w = 0) crosses an edge in {} cm where the ground truth takes {} cm (R / G / B), so in the red and green channels more far weight keeps helping. The thesis tuned by eye on its Head scene at its kernel scale (‘highly adapted to the given scene’, §6.4); our test signals differ.", rgb([0, 1, 2].map(first), 3), rgb(s.truth_edge_width, 3)) }),
    ]
}

/// The report's sections for both figures.
pub fn html(r: &Value) -> String {
    let mut h = String::new();
    let f = &r["fig_5_15"];
    if let Some(models) = f["models"].as_array() {
        let _ = write!(
            h,
            "<h2>Fig. 5.14–5.15 — guided optimization with k = 1.55, b = 50 imitates pre-integration</h2><img src=\"fig5_15_guided_vs_preint.png\"><p>Skin1. Top: the 1D function a(x) of each rank-1 kernel a(x)a(y) against pre-integration's (dots). Bottom: how far each model's convolution of the shaded test signal is from pre-integration's, relative to the RMS of pre-integration's image. Kernels fitted on the thesis's extent ({} largest MFP, {} samples either side, the extent b = 50 is defined on) in {:.1} s.</p>",
            f["extent_mfp"],
            f["half_samples"],
            f["seconds"].as_f64().unwrap_or(f64::NAN)
        );
        h += "<table><tr><th>model</th><th colspan=3>image distance to pre-integration R G B</th><th colspan=3>kernel distance ‖A − A_p‖_F / ‖A_p‖_F R G B</th></tr>";
        for m in models {
            let v = |k: &str, c: usize| m[k][c].as_f64().unwrap_or(f64::NAN);
            let _ = write!(
                h,
                "<tr><td style=\"text-align:left\">{}</td>",
                m["name"].as_str().unwrap_or("")
            );
            for c in 0..3 {
                let _ = write!(h, "<td>{:.4}</td>", v("image_distance", c));
            }
            for c in 0..3 {
                let _ = write!(h, "<td>{:.3}</td>", v("kernel_distance", c));
            }
            h += "</tr>";
        }
        h += "</table><p>Fig. 5.14's guide Γ_p (the weight under which eq. 5.19's optimum is pre-integration) is not reproduced: the thesis gives no formula for it.</p>";
    }
    let s = &r["fig_5_17"];
    if let Some(w) = s["w"].as_array() {
        let _ = write!(
            h,
            "<h2>Fig. 5.17 — the manual model's w sweep</h2><img src=\"fig5_17_manual_w_sweep.png\"><p>Skin1 with Table A.1's Gaussians (√τ_n = {} cm, √τ_f = {} cm, R / G / B) and w from 0 (far Gaussian only) to 1 (near only), {} values in {:.1} s. Top: the light across a shadow edge for a far-weighted, Table A.1's and a near-weighted w against the ground truth's. Bottom: the image-space error on the five test signals and the edge's 10–90 % width relative to the ground truth's. Lowest image-space error at w = {} (R / G / B); Table A.1: w = {}.</p>",
            fmt3(&s["sqrt_tau_near_cm"]),
            fmt3(&s["sqrt_tau_far_cm"]),
            w.len(),
            s["seconds"].as_f64().unwrap_or(f64::NAN),
            fmt3(&s["best_w"]),
            s["table_a1_w"]
        );
    }
    h
}

/// A JSON triple as `a / b / c`, 3 significant digits.
fn fmt3(v: &Value) -> String {
    v.as_array()
        .map(|a| {
            a.iter()
                .map(|x| format!("{:.3}", x.as_f64().unwrap_or(f64::NAN)))
                .collect::<Vec<_>>()
                .join(" / ")
        })
        .unwrap_or_default()
}
