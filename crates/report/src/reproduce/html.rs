//! The report page: self-contained HTML (tables inline, the PNG plots beside it by name).

use std::fmt::Write as _;

use super::{MAIN, MitsubaImages, RenderedTables, Report};
use fit::evaluate::RANK1;

/// A table cell with our value above the published one (grey).
fn cell(ours: f64, published: f64) -> String {
    format!("<td>{ours:.3}<br><span class=\"pub\">{published:.3}</span></td>")
}

/// Cells of one R, G, B row against the published one, then their sums.
fn cells_with_sum(ours: [f64; 3], published: [f64; 3]) -> String {
    let mut h: String = (0..3).map(|c| cell(ours[c], published[c])).collect();
    h += &cell(ours.iter().sum(), published.iter().sum());
    h
}

/// Table 6.5's rows N = 1, 2, …: SVD then d'Eon, ours above the thesis's, with sums; then the
/// table's end.
fn table65_rows(t: &super::Table65, h: &mut String) {
    for n in 0..t.svd.len() {
        let _ = write!(h, "<tr><td>{}</td>", n + 1);
        *h += &cells_with_sum(t.svd[n], t.published_svd[n]);
        *h += &cells_with_sum(t.deon[n], t.published_deon[n]);
        *h += "</tr>";
    }
    *h += "</table>";
}

/// Values joined by " / " with `digits` decimals.
fn joined(v: &[f64], digits: usize) -> String {
    v.iter()
        .map(|x| format!("{x:.digits$}"))
        .collect::<Vec<_>>()
        .join(" / ")
}

impl Report {
    /// The report page. Plots are referenced by the names `sss reproduce` writes beside it.
    pub fn html(&self) -> String {
        let mut h = String::new();
        let _ = write!(
            h,
            "<!doctype html><html><head><meta charset=\"utf-8\"><title>sss reproduce</title><style>body{{font-family:sans-serif;max-width:1400px;margin:auto;padding:1em}}table{{border-collapse:collapse;margin:1em 0}}td,th{{border:1px solid #bbb;padding:3px 7px;text-align:right}}th{{background:#eee}}.pub{{color:#777}}.ok{{color:#070}}.bad{{color:#b00}}img{{max-width:100%}}</style></head><body>"
        );
        let photons = match self.photons_per_channel {
            Some(n) => format!("{} photons per channel", mc::provenance::count(n)),
            None => "profiles of unknown or differing photon counts".into(),
        };
        let _ = write!(
            h,
            "<h1>Separable SSS for arbitrary materials — reproduction</h1><p>Mode: <b>{}</b>, {photons} (library simulated or read in {:.0} s). Published values from Freude 2014 in <span class=\"pub\">grey</span>.</p>",
            self.mode, self.simulate_seconds
        );
        self.claims_html(&mut h);
        self.tables_html(&mut h);
        self.figures_html(&mut h);
        self.chapter5_html(&mut h);
        rendered_tables_html(&self.rendered_tables, &mut h);
        mitsuba_html(&self.rendered, &mut h);
        h += "</body></html>\n";
        h
    }

    fn claims_html(&self, h: &mut String) {
        *h += "<h2>What agrees, what differs and why</h2><table><tr><th>claim</th><th>ours</th><th>published</th><th>holds</th><th>why</th></tr>";
        for c in &self.claims {
            let _ = write!(
                h,
                "<tr><td style=\"text-align:left\">{}</td><td>{}</td><td class=\"pub\">{}</td><td class=\"{}\">{}</td><td style=\"text-align:left\">{}</td></tr>",
                c.claim,
                c.ours,
                c.published,
                if c.holds { "ok" } else { "bad" },
                if c.holds { "yes" } else { "no" },
                c.why
            );
        }
        *h += "</table>";
    }

    fn tables_html(&self, h: &mut String) {
        let t = &self.tables;
        *h += "<h2>Table 6.2 — materials (cm⁻¹) with derived albedo and MFP</h2><table><tr><th>material</th><th>σa R G B</th><th>σs R G B</th><th>g</th><th>η</th><th>albedo R G B</th><th>MFP [cm] R G B</th></tr>";
        for m in &t.table_6_2 {
            let v3 = |v: [f64; 3], p: usize| v.map(|x| format!("{x:.p$}")).join(" ");
            let _ = write!(
                h,
                "<tr><td style=\"text-align:left\">{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
                m.material,
                v3(m.sigma_a, 4),
                v3(m.sigma_s, 3),
                v3(m.g, 3),
                m.eta,
                v3(m.albedo, 5),
                v3(m.mfp_cm, 4)
            );
        }
        *h += "</table>";

        *h += "<h2>Table 6.3 — kernel-space RMS of the rank-1 models (normalized: largest entry = 1)</h2><table><tr><th>material</th>";
        for m in RANK1 {
            let _ = write!(h, "<th colspan=3>{} R G B</th><th>Σ</th>", m.title());
        }
        *h += "</tr>";
        for row in &t.table_6_3 {
            let _ = write!(h, "<tr><td style=\"text-align:left\">{}</td>", row.material);
            for m in &row.models {
                *h += &cells_with_sum(m.normalized, m.published);
            }
            *h += "</tr>";
        }
        *h += "</table><p>Raw (unnormalized) values:</p><table><tr><th>material</th>";
        for m in RANK1 {
            let _ = write!(h, "<th colspan=3>{}</th>", m.title());
        }
        *h += "</tr>";
        for row in &t.table_6_3 {
            let _ = write!(h, "<tr><td style=\"text-align:left\">{}</td>", row.material);
            for m in &row.models {
                for x in m.raw {
                    let _ = write!(h, "<td>{x:.3e}</td>");
                }
            }
            *h += "</tr>";
        }
        *h += "</table>";

        *h += "<h2>Table 6.5 — image-space RMS, Skin1, SVD rank-N vs d'Eon N Gaussians (normalized: max = 1)</h2><p>Ours: RMS over our five test signals; published: the Head scene.</p><table><tr><th>N</th><th colspan=3>SVD R G B</th><th>Σ</th><th colspan=3>d'Eon R G B</th><th>Σ</th></tr>";
        let t65 = &t.table_6_5;
        table65_rows(t65, h);

        *h += "<h2>Table 5.1 — model properties, with our measured fit time</h2><table><tr><th>model</th><th>visual quality (thesis)</th><th>1D convolutions</th><th>separable</th><th>closed form</th><th>our fit time per channel [s]</th></tr>";
        for m in &t.table_5_1 {
            let yn = |b: bool| if b { "✓" } else { "✗" };
            let _ = write!(
                h,
                "<tr><td style=\"text-align:left\">{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{:.3}</td></tr>",
                m.model,
                m.visual_quality,
                m.convolutions_1d,
                yn(m.separable),
                yn(m.closed_form),
                m.fit_seconds_per_channel
            );
        }
        *h += "</table>";
    }

    fn figures_html(&self, h: &mut String) {
        *h += "<h2>Fig. 5.1 — singular values of the main materials</h2>";
        for m in MAIN {
            let _ = write!(h, "<img src=\"{m}.singular_values.png\" width=\"45%\">");
        }
        *h += "<h2>Fig. 6.2 / A.12–A.64 — kernel slices (main axis, diagonal) against the ground truth</h2>";
        for m in MAIN {
            let _ = write!(
                h,
                "<h3>{m}</h3><img src=\"{m}.slices_rank1.png\"><img src=\"{m}.slices_multipass.png\">"
            );
        }
        *h += "<h2>Fig. 6.3–6.10 — test-signal convolutions of the rank-1 models (every panel labelled, with colour scales)</h2>";
        for m in MAIN {
            let _ = write!(
                h,
                "<h3>{m}</h3><img src=\"{m}.conv_edge.png\" width=\"49%\"> <img src=\"{m}.conv_circle_squares.png\" width=\"49%\">"
            );
        }
        *h += "<h2>Fig. 6.1 / A.1–A.11 — simulated profiles</h2>";
        for m in &self.tables.table_6_2 {
            let _ = write!(h, "<img src=\"{}.profile.png\" width=\"49%\">", m.material);
        }
    }

    fn chapter5_html(&self, h: &mut String) {
        let f = &self.fig_5_15;
        let _ = write!(
            h,
            "<h2>Fig. 5.14–5.15 — guided optimization with k = 1.55, b = 50 imitates pre-integration</h2><img src=\"fig5_15_guided_vs_preint.png\"><p>Skin1. Top: the 1D function a(x) of each rank-1 kernel a(x)a(y) against pre-integration's (dots). Bottom: how far each model's convolution of the shaded test signal is from pre-integration's, relative to the RMS of pre-integration's image. Kernels fitted on the thesis's extent ({} largest MFP, {} samples either side, the extent b = 50 is defined on) in {:.1} s.</p>",
            f.extent_mfp, f.half_samples, f.seconds
        );
        *h += "<table><tr><th>model</th><th colspan=3>image distance to pre-integration R G B</th><th colspan=3>kernel distance ‖A − A_p‖_F / ‖A_p‖_F R G B</th></tr>";
        for m in &f.models {
            let _ = write!(h, "<tr><td style=\"text-align:left\">{}</td>", m.model.name);
            for x in m.image_distance {
                let _ = write!(h, "<td>{x:.4}</td>");
            }
            for x in m.kernel_distance {
                let _ = write!(h, "<td>{x:.3}</td>");
            }
            *h += "</tr>";
        }
        *h += "</table><p>Fig. 5.14's guide Γ_p (the weight under which eq. 5.19's optimum is pre-integration) is not reproduced: the thesis gives no formula for it.</p>";
        let s = &self.fig_5_17;
        let _ = write!(
            h,
            "<h2>Fig. 5.17 — the manual model's w sweep</h2><img src=\"fig5_17_manual_w_sweep.png\"><p>Skin1 with Table A.1's Gaussians (√τ_n = {} cm, √τ_f = {} cm, R / G / B) and w from 0 (far Gaussian only) to 1 (near only), {} values in {:.1} s. Top: the light across a shadow edge for a far-weighted, Table A.1's and a near-weighted w against the ground truth's. Bottom: the image-space error on the five test signals and the edge's 10–90 % width relative to the ground truth's. Lowest image-space error at w = {} (R / G / B); Table A.1: w = {}.</p>",
            joined(&s.sqrt_tau_near_cm, 3),
            joined(&s.sqrt_tau_far_cm, 3),
            s.w.len(),
            s.seconds,
            joined(&s.best_w, 3),
            s.table_a1_w
        );
    }
}

/// The rendered tables' section.
fn rendered_tables_html(t: &RenderedTables, h: &mut String) {
    *h += "<h2>Table 6.4 — image-space RMS of rendered cut-outs, and Table 6.5 rendered</h2>";
    let v = match t {
        RenderedTables::Skipped { reason } => {
            let _ = write!(
                h,
                "<p>Skipped: {reason}. These tables need a GPU adapter (software rendering: Mesa's lavapipe).</p>"
            );
            return;
        }
        RenderedTables::Rendered(v) => v,
    };
    let _ = write!(
        h,
        "<p>Our scenes (a 5 cm sphere on a floor with a hard shadow; <code>fin</code>: a sphere beside 3 mm and 1 mm fins), the thesis's materials, {}×{} pixels on {}, {} taps per pass, every kernel at one scale (the target's depth) without a depth test. Ground truth as in the thesis: the screen-space irradiance convolved per channel with the full 2D kernel of the profile binned to pixels. RMS of the scattered diffuse light against it on the SSS pixels, per channel, normalized so that the highest per-channel entry of the table is 1 (Σ = R + G + B); SVD rank-1 normalized to the kernel's energy, as SSSS normalizes every kernel before it convolves (thesis §5.1). Published values (grey) are of the thesis's scene rendered with the same material; the scenes differ, so compare the claims above, not the values. Rendered in {:.1} s.</p>",
        v.width, v.height, v.adapter, v.taps, v.seconds
    );
    *h += "<table><tr><th>scene · material (thesis scene)</th><th>cm/px</th>";
    for m in &v.models {
        let _ = write!(h, "<th colspan=3>{} R G B</th><th>Σ</th>", m.name);
    }
    *h += "<th>no SSS Σ</th></tr>";
    for r in &v.table_6_4 {
        let _ = write!(
            h,
            "<tr><td style=\"text-align:left\">{} · {} ({})</td><td>{:.3}</td>",
            r.scene, r.material, r.thesis_scene, r.cm_per_px
        );
        for (o, p) in r.normalized.iter().zip(&r.published) {
            *h += &cells_with_sum(*o, *p);
        }
        let _ = write!(h, "<td>{:.3}</td></tr>", r.lambert.iter().sum::<f64>());
    }
    *h += "</table>";
    let t = &v.table_6_5;
    let _ = write!(
        h,
        "<p>Table 6.5 rendered: {} on the {} scene, SVD rank-N (renormalized) against d'Eon's N Gaussians, image RMS as above, normalized so that the highest entry is 1. The published values (grey) are the thesis's Head.</p><table><tr><th>N</th><th colspan=3>SVD R G B</th><th>Σ</th><th colspan=3>d'Eon R G B</th><th>Σ</th></tr>",
        t.material, t.scene
    );
    table65_rows(&t.rows, h);
}

/// The rendered-scene section: `images.py`'s comparisons against Mitsuba 3, one per scene and
/// material, or how to make them.
fn mitsuba_html(all: &[MitsubaImages], h: &mut String) {
    *h += "<h2>Rendered scenes against Mitsuba 3</h2>";
    if all.is_empty() {
        *h += "<p>Not included: run <code>python3 scripts/references/run.py --quick</code> and pass its <code>out/references/summary.json</code> (or one <code>images.json</code>) with <code>--references</code>.</p>";
        return;
    }
    for v in all {
        let _ = write!(
            h,
            "<h3>{} / {}</h3><p>The {} scene, {}×{} pixels, Mitsuba with {} samples per pixel (mean of two seeds; its noise {:.1} % of the mean on 2×2 blocks; silhouettes, {:.1} % of the lit blocks, excluded on both sides). Errors relative to the reference's mean; noise-corrected = √(MSE − var(reference)) ± standard error; spatial = what remains once each channel is scaled by its best global factor.</p>",
            v.scene,
            v.material,
            v.scene,
            v.width,
            v.height,
            v.spp,
            100.0 * v.reference_noise_rel,
            100.0 * v.silhouette_fraction
        );
        if let Some(pass) = v.calibration_pass {
            let pct = |x: Option<f64>| 100.0 * x.unwrap_or(f64::NAN);
            let _ = write!(
                h,
                "<p>Calibration (<code>--no-sss</code> against Mitsuba's direct light on the same opaque Lambertian surfaces): noise-corrected RMSE {:.2} ± {:.2} %, energy {}: {}. A deliberately wrong render (albedo × 0.8) is {}.</p>",
                pct(v.calibration_rmse_rel),
                pct(v.calibration_rmse_se),
                joined(&v.calibration_energy_ratio.unwrap_or([f64::NAN; 3]), 4),
                if pass {
                    "<span class=\"ok\">passes</span>"
                } else {
                    "<span class=\"bad\">fails: the scene ranks nothing</span>"
                },
                if v.negative_control.as_ref().is_some_and(|n| n.rejected) {
                    "rejected"
                } else {
                    "<span class=\"bad\">not rejected</span>"
                }
            );
        }
        *h += "<table><tr><th>model</th><th>RMSE</th><th>noise-corrected RMSE</th><th>spatial</th><th>SSIM</th><th>DSSIM</th><th>energy R / G / B</th></tr>";
        for m in &v.models {
            let _ = write!(
                h,
                "<tr><td style=\"text-align:left\">{}</td><td>{:.2} %</td><td>{:.2} ± {:.2} %</td><td>{:.2} %</td><td>{:.4}</td><td>{:.4}</td><td>{}</td></tr>",
                m.model,
                100.0 * m.rmse_rel,
                100.0 * m.rmse_noise_corrected,
                100.0 * m.rmse_noise_corrected_se,
                100.0 * m.rmse_spatial,
                m.ssim,
                (1.0 - m.ssim) / 2.0,
                joined(&m.energy_ratio, 3)
            );
        }
        *h += "</table>";
        if let Some(b) = &v.error_budget {
            let _ = write!(
                h,
                "<p>Where the error comes from, against {} (noise-corrected RMSE ± standard error, % of that reference's mean; resolved: more than 3 standard errors above 0). The best real-time method is <code>{}</code>, {:.2} ± {:.2} % from the full reference. Self-interreflection of opaque Lambertian surfaces of the same albedo: {} % of the direct light.</p><table><tr><th>term</th><th>noise-corrected RMSE</th><th></th><th>energy R / G / B</th></tr>",
                b.reference,
                b.best_realtime,
                100.0 * b.best_realtime_full_reference.rmse_noise_corrected,
                100.0 * b.best_realtime_full_reference.rmse_noise_corrected_se,
                joined(&b.self_interreflection_lambert.map(|x| 100.0 * x), 2)
            );
            for (name, t) in b.terms.named() {
                let _ = write!(
                    h,
                    "<tr><td style=\"text-align:left\">{name}</td><td>{:.2} ± {:.2} %</td><td>{}</td><td>{}</td></tr>",
                    100.0 * t.rmse_noise_corrected,
                    100.0 * t.rmse_noise_corrected_se,
                    if t.resolved { "resolved" } else { "undecided" },
                    joined(&t.energy_ratio, 3)
                );
            }
            *h += "</table>";
        }
        if !v.rankings.is_empty() {
            *h += "<p>Rankings (paired over blocks, resolved at 3 standard errors):</p><ul>";
            for (k, r) in &v.rankings {
                let verdict = match r {
                    Some(true) => "<span class=\"ok\">yes</span>",
                    Some(false) => "<span class=\"bad\">no</span>",
                    None => "undecided",
                };
                let _ = write!(h, "<li>{k}: {verdict}</li>");
            }
            *h += "</ul>";
        }
    }
}
