//! `sss reproduce`'s rendered tables: the thesis's Table 6.4 (image RMS of rendered cut-outs per
//! scene and rank-1 model) and Table 6.5 rendered (SVD rank-N against d'Eon's N Gaussians at
//! equal pass count), on our built-in scenes with the thesis's materials, measured by
//! `gpu::compare_models` against the thesis's own ground truth (the full 2D convolution of the
//! screen-space irradiance). Our scenes are not the thesis's scans, so the report compares its
//! claims, not its values. Without a GPU adapter the tables are skipped and the report says why.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::time::Instant;

use anyhow::Result;
use fit::taps::TapSpec;
use fit::{KernelModel, ManualParams, Profile};
use gpu::{Gpu, RenderParams, Scene};
use serde::Deserialize;
use serde_json::{Value, json};

use crate::library;

/// (thesis scene, our scene, material): the thesis rendered its Head with Skin1, the Fruit with
/// Apple, Ketchup with Ketchup, Milk with Wholemilk and the Dragon with Marble.
const SCENES: [(&str, &str, &str); 6] = [
    ("head", "sphere", "skin1"),
    ("fruit", "sphere", "apple"),
    ("ketchup", "sphere", "ketchup"),
    ("milk", "sphere", "wholemilk"),
    ("dragon", "sphere", "marble"),
    ("head", "fin", "skin1"),
];

/// The rank-1 models of Table 6.4. SVD is rescaled to the kernel's energy (‖A‖₁ = ‖R_d‖₁), as
/// every image comparison here applies it (SSSS's convention).
const TABLE_6_4: [KernelModel; 4] = [
    KernelModel::Svd {
        rank: 1,
        renormalize: true,
    },
    KernelModel::Preint,
    KernelModel::Guided { k: 1.0, b: 0.0 },
    KernelModel::Manual(ManualParams::Auto),
];

#[derive(Deserialize)]
struct Published {
    table_6_4: BTreeMap<String, Published64>,
    table_6_5: Published65,
}

/// The published Table 6.5 (Head, Skin1), rows N = 1…6, per channel R, G, B.
#[derive(Deserialize)]
struct Published65 {
    svd: Vec<[f64; 3]>,
    deon: Vec<[f64; 3]>,
}

/// One scene of the published Table 6.4, per channel R, G, B.
#[derive(Deserialize)]
struct Published64 {
    svd1: [f64; 3],
    preint: [f64; 3],
    guided_k1: [f64; 3],
    manual: [f64; 3],
}

impl Published64 {
    /// Rows in the order of [`TABLE_6_4`].
    fn rows(&self) -> [[f64; 3]; 4] {
        [self.svd1, self.preint, self.guided_k1, self.manual]
    }
}

const PUBLISHED: &str = include_str!("../../../configs/thesis_published.toml");

/// Renders the tables (or records why not) into `report["rendered_tables"]` and appends their
/// claims to `report["claims"]`. `profiles` are those of `all`, in its order.
pub fn add(
    report: &mut Value,
    all: &[library::Named],
    profiles: &[Profile],
    quick: bool,
) -> Result<()> {
    let published: Published = toml::from_str(PUBLISHED).expect("published tables parse");
    let t = Instant::now();
    let gpu = match Gpu::new() {
        Ok(g) => g,
        Err(e) => {
            eprintln!("rendered Tables 6.4 and 6.5 skipped: {e}");
            report["rendered_tables"] = json!({ "status": "skipped", "reason": e.to_string() });
            return Ok(());
        }
    };
    let (width, height, ranks) = if quick { (192, 108, 3) } else { (960, 540, 6) };
    let base = RenderParams {
        width,
        height,
        ..RenderParams::default()
    };
    let spec = TapSpec::default();
    let svd_n = |rank| KernelModel::Svd {
        rank,
        renormalize: true,
    };
    // Per scene: (cm per pixel, Lambert's error, the errors of TABLE_6_4), R, G, B.
    let mut measured: Vec<(f64, [f64; 3], [[f64; 3]; 4])> = Vec::new();
    let mut t65 = None;
    for (i, &(_, scene_name, material)) in SCENES.iter().enumerate() {
        let p = &profiles[all
            .iter()
            .position(|n| n.slug == material)
            .expect("the scenes' materials are built in")];
        let scene = Scene::named(scene_name)?;
        // The first scene (the Head's analogue) also holds Table 6.5's ranks.
        let mut models = TABLE_6_4.to_vec();
        if i == 0 {
            models.extend((2..=ranks).map(svd_n));
            models.extend((1..=ranks).map(|n| KernelModel::Deon { n }));
        }
        eprintln!(
            "rendering {} model(s) for {material} on the {scene_name} scene at {width}×{height} …",
            models.len()
        );
        let cmp = gpu::compare_models(&gpu, &scene, &base, p, material, &models, spec)?;
        let err = |m: KernelModel| {
            cmp.kernels[models.iter().position(|&x| x == m).expect("rendered")]
                .error
                .rms_rel
        };
        if i == 0 {
            let svd: Vec<[f64; 3]> = (1..=ranks).map(|n| err(svd_n(n))).collect();
            let deon: Vec<[f64; 3]> = (1..=ranks).map(|n| err(KernelModel::Deon { n })).collect();
            t65 = Some((svd, deon));
        }
        measured.push((
            cmp.scale.cm_per_px,
            cmp.lambert.error.rms_rel,
            TABLE_6_4.map(err),
        ));
    }
    let (svd, deon) = t65.expect("the first scene holds Table 6.5");

    // Normalized as the thesis does: the highest per-channel entry of each table is 1.
    let max64 = measured
        .iter()
        .flat_map(|m| m.2.iter().flatten())
        .fold(0.0f64, |a, &b| a.max(b));
    let max65 = svd
        .iter()
        .chain(&deon)
        .flatten()
        .fold(0.0f64, |a, &b| a.max(b));
    let norm = |v: &[[f64; 3]], max: f64| -> Vec<[f64; 3]> {
        v.iter().map(|r| r.map(|x| x / max)).collect()
    };
    let rows: Vec<Value> = SCENES
        .iter()
        .zip(&measured)
        .map(|(&(thesis, scene, material), (cm_per_px, lambert, raw))| {
            json!({
                "scene": scene, "material": material, "thesis_scene": thesis, "cm_per_px": cm_per_px,
                "raw": raw, "normalized": norm(raw, max64), "published": published.table_6_4[thesis].rows(),
                "lambert_raw": lambert, "lambert": lambert.map(|x| x / max64),
            })
        })
        .collect();
    let sum = |m: &[f64; 3]| m.iter().sum::<f64>();
    let sums64: Vec<[f64; 4]> = measured
        .iter()
        .map(|m| m.2.map(|e| sum(&e) / max64))
        .collect();
    let pub_sums64: Vec<[f64; 4]> = published
        .table_6_4
        .values()
        .map(|p| p.rows().map(|m| sum(&m)))
        .collect();
    let (svd_raw, deon_raw) = (svd, deon);
    let (svd, deon) = (norm(&svd_raw, max65), norm(&deon_raw, max65));
    let claims = claims(
        &sums64,
        &pub_sums64,
        (&svd, &deon),
        (&published.table_6_5.svd, &published.table_6_5.deon),
    );
    let seconds = t.elapsed().as_secs_f64();
    eprintln!("rendered Tables 6.4 and 6.5 in {seconds:.1} s");
    report["rendered_tables"] = json!({
        "status": "rendered", "adapter": gpu.adapter_name, "width": width, "height": height,
        "taps": spec.taps, "seconds": seconds,
        "models": TABLE_6_4.map(|m| json!({ "model": m, "name": m.title() })),
        "table_6_4": rows,
        "table_6_5": { "scene": SCENES[0].1, "material": SCENES[0].2, "n": (1..=ranks).collect::<Vec<_>>(),
                       "svd": svd, "deon": deon, "svd_raw": svd_raw, "deon_raw": deon_raw,
                       "published_svd": published.table_6_5.svd[..ranks], "published_deon": published.table_6_5.deon[..ranks] },
    });
    if let Some(list) = report["claims"].as_array_mut() {
        list.extend(claims);
    }
    Ok(())
}

/// The thesis's claims on its rendered scenes, checked on ours. `sums[scene]` is Σ over R, G, B
/// of the normalized Table 6.4 entries of [`TABLE_6_4`]'s models, `published` the thesis's;
/// `(svd[n], deon[n])` the normalized rendered Table 6.5 at N = n + 1, `(ps, pd)` the thesis's.
fn claims(
    sums: &[[f64; 4]],
    published: &[[f64; 4]],
    (svd, deon): (&[[f64; 3]], &[[f64; 3]]),
    (ps, pd): (&[[f64; 3]], &[[f64; 3]]),
) -> Vec<Value> {
    let svd_worst = |s: &[[f64; 4]]| {
        s.iter()
            .filter(|m| m[1..].iter().all(|&x| m[0] > x))
            .count()
    };
    let comparable = |s: &[[f64; 4]]| {
        s.iter()
            .filter(|m| {
                let (lo, hi) = m[1..]
                    .iter()
                    .fold((f64::MAX, 0.0f64), |(lo, hi), &x| (lo.min(x), hi.max(x)));
                hi <= 2.0 * lo
            })
            .count()
    };
    let sum = |v: &[f64; 3]| v.iter().sum::<f64>();
    let n = svd.len();
    let svd_wins = (0..n).filter(|&k| sum(&svd[k]) < sum(&deon[k])).count();
    let svd_wins_channels = (0..n)
        .flat_map(|k| (0..3).map(move |c| (k, c)))
        .filter(|&(k, c)| svd[k][c] < deon[k][c])
        .count();
    let saving = (0..n - 1)
        .filter(|&k| sum(&svd[k]) <= sum(&deon[k + 1]))
        .count();
    let pub_wins = (0..ps.len()).filter(|&k| sum(&ps[k]) < sum(&pd[k])).count();
    let pub_saving = (0..ps.len() - 1)
        .filter(|&k| sum(&ps[k]) <= sum(&pd[k + 1]))
        .count();
    let (s, p) = (sums.len(), published.len());
    vec![
        json!({ "claim": "Table 6.4 (rendered): SVD rank-1 has the highest image error (Σ R+G+B) of the four rank-1 models in most scenes",
                "ours": format!("{} of {s} scenes", svd_worst(sums)), "published": format!("{} of {p} scenes", svd_worst(published)), "holds": 2 * svd_worst(sums) > s,
                "why": "A rank-1 SVD matches the kernel's peak and loses its far falloff (the thesis: it \"underestimates the far-range scattering\"); renormalized to the kernel's energy, that energy goes to the centre instead, which a shadow edge shows. Our scenes are a sphere on a floor, not the thesis's scans." }),
        json!({ "claim": "Table 6.4 (rendered): pre-integration, guided k = 1 and manual are comparable (in each scene the largest Σ of the three is within 2× the smallest) in most scenes",
                "ours": format!("{} of {s} scenes", comparable(sums)), "published": format!("{} of {p} scenes", comparable(published)), "holds": 2 * comparable(sums) > s,
                "why": "All three keep the kernel's energy and approximate its falloff with one separable pass pair; they differ in how they trade the centre against the tail, which moves the image error by less than the rank-1 SVD's missing falloff." }),
        json!({ "claim": "Table 6.5 (rendered): at equal pass count SVD rank-N has a lower image error (Σ) than d'Eon with N Gaussians, on the sphere with Skin1",
                "ours": format!("{svd_wins} of {n} (per channel {svd_wins_channels} of {})", 3 * n), "published": format!("{pub_wins} of {} (Head)", ps.len()), "holds": svd_wins == n,
                "why": "A sum of N separable Gaussians is a rank-N kernel and the truncated SVD is the best rank-N kernel in kernel space; a rendered image weighs the kernel through its irradiance, so the ordering is expected but not guaranteed." }),
        json!({ "claim": "Table 6.5 (rendered): SVD saves about one rank: SVD rank-N (Σ) is at least as good as d'Eon N+1 in most steps",
                "ours": format!("{saving} of {}", n - 1), "published": format!("{pub_saving} of {} (Head)", ps.len() - 1), "holds": 2 * saving > n - 1,
                "why": "Same argument, with a margin." }),
    ]
}

/// The rendered tables' section of the report page.
pub fn html(v: &Value) -> String {
    let mut h = String::from(
        "<h2>Table 6.4 — image-space RMS of rendered cut-outs, and Table 6.5 rendered</h2>",
    );
    if v["status"].as_str() != Some("rendered") {
        let _ = write!(
            h,
            "<p>Skipped: {}. These tables need a GPU adapter (software rendering: Mesa's lavapipe).</p>",
            v["reason"].as_str().unwrap_or("not run")
        );
        return h;
    }
    let f = |x: &Value| x.as_f64().unwrap_or(f64::NAN);
    let _ = write!(
        h,
        "<p>Our scenes (a 5 cm sphere on a floor with a hard shadow; <code>fin</code>: a sphere beside 3 mm and 1 mm fins), the thesis's materials, {}×{} pixels on {}, {} taps per pass, every kernel at one scale (the target's depth) without a depth test. Ground truth as in the thesis: the screen-space irradiance convolved per channel with the full 2D kernel of the profile binned to pixels. RMS of the scattered diffuse light against it on the SSS pixels, per channel, normalized so that the highest per-channel entry of the table is 1 (Σ = R + G + B); SVD rank-1 normalized to the kernel's energy, as SSSS normalizes every kernel before it convolves (thesis §5.1). Published values (grey) are of the thesis's scene rendered with the same material; the scenes differ, so compare the claims above, not the values. Rendered in {:.1} s.</p>",
        v["width"],
        v["height"],
        v["adapter"].as_str().unwrap_or("?"),
        v["taps"],
        f(&v["seconds"])
    );
    h += "<table><tr><th>scene · material (thesis scene)</th><th>cm/px</th>";
    for m in v["models"].as_array().into_iter().flatten() {
        let _ = write!(
            h,
            "<th colspan=3>{} R G B</th><th>Σ</th>",
            m["name"].as_str().unwrap_or("?")
        );
    }
    h += "<th>no SSS Σ</th></tr>";
    for r in v["table_6_4"].as_array().into_iter().flatten() {
        let _ = write!(
            h,
            "<tr><td style=\"text-align:left\">{} · {} ({})</td><td>{:.3}</td>",
            r["scene"].as_str().unwrap_or(""),
            r["material"].as_str().unwrap_or(""),
            r["thesis_scene"].as_str().unwrap_or(""),
            f(&r["cm_per_px"])
        );
        for j in 0..4 {
            let mut sum = (0.0, 0.0);
            for c in 0..3 {
                let (o, p) = (f(&r["normalized"][j][c]), f(&r["published"][j][c]));
                sum = (sum.0 + o, sum.1 + p);
                h += &crate::reproduce::cell(o, p);
            }
            h += &crate::reproduce::cell(sum.0, sum.1);
        }
        let lambert: f64 = (0..3).map(|c| f(&r["lambert"][c])).sum();
        let _ = write!(h, "<td>{lambert:.3}</td></tr>");
    }
    h += "</table>";
    let t = &v["table_6_5"];
    let _ = write!(
        h,
        "<p>Table 6.5 rendered: {} on the {} scene, SVD rank-N (renormalized) against d'Eon's N Gaussians, image RMS as above, normalized so that the highest entry is 1. The published values (grey) are the thesis's Head.</p><table><tr><th>N</th><th colspan=3>SVD R G B</th><th>Σ</th><th colspan=3>d'Eon R G B</th><th>Σ</th></tr>",
        t["material"].as_str().unwrap_or(""),
        t["scene"].as_str().unwrap_or("")
    );
    for (k, _) in t["n"].as_array().into_iter().flatten().enumerate() {
        let _ = write!(h, "<tr><td>{}</td>", k + 1);
        for (ours, theirs) in [("svd", "published_svd"), ("deon", "published_deon")] {
            let mut sum = (0.0, 0.0);
            for c in 0..3 {
                let (o, p) = (f(&t[ours][k][c]), f(&t[theirs][k][c]));
                sum = (sum.0 + o, sum.1 + p);
                h += &crate::reproduce::cell(o, p);
            }
            h += &crate::reproduce::cell(sum.0, sum.1);
        }
        h += "</tr>";
    }
    h += "</table>";
    h
}
