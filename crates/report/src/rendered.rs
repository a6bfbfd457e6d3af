//! The thesis's rendered tables on our scenes: Table 6.4 (image RMS of rendered cut-outs per
//! scene and rank-1 model) and Table 6.5 rendered (SVD rank-N against d'Eon's N Gaussians at
//! equal pass count), with the thesis's materials, measured by [`gpu::compare_models`] against
//! the thesis's own ground truth (the full 2D convolution of the screen-space irradiance). Our
//! scenes are not the thesis's scans, so the claims are compared, not the values.

use std::time::Instant;

use crate::reproduce::{Claim, Published, Rendered, Rendered64Row, Rendered65, Table65};
use fit::taps::TapSpec;
use fit::{KernelModel, ManualParams, Profile};

use gpu::{Gpu, RenderParams, Scene};

use crate::error::{ReportError, Result};

/// (thesis scene, our scene, material): the thesis rendered its Head with Skin1, the Fruit with
/// Apple, Ketchup with Ketchup, Milk with Wholemilk and the Dragon with Marble.
pub const SCENES: [(&str, &str, &str); 6] = [
    ("head", "sphere", "skin1"),
    ("fruit", "sphere", "apple"),
    ("ketchup", "sphere", "ketchup"),
    ("milk", "sphere", "wholemilk"),
    ("dragon", "sphere", "marble"),
    ("head", "fin", "skin1"),
];

/// The rank-1 models of Table 6.4. SVD is rescaled to the kernel's energy (‖A‖₁ = ‖R_d‖₁), as
/// every image comparison here applies it (SSSS's convention).
pub const TABLE_6_4: [KernelModel; 4] = [
    KernelModel::Svd {
        rank: 1,
        renormalize: true,
    },
    KernelModel::Preint,
    KernelModel::Guided { k: 1.0, b: 0.0 },
    KernelModel::Manual(ManualParams::Auto),
];

/// Renders both tables with the profiles of [`SCENES`]' materials (`profiles`: slug and
/// profile), at 192×108 with ranks up to 3 when `quick`, else 960×540 up to 6.
pub fn rendered_tables(
    gpu: &Gpu,
    profiles: &[(&str, &Profile)],
    quick: bool,
    published: &Published,
) -> Result<Rendered> {
    let t = Instant::now();
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
    let mut t65 = (Vec::new(), Vec::new());
    for (i, &(_, scene_name, material)) in SCENES.iter().enumerate() {
        let p = profiles
            .iter()
            .find(|(slug, _)| *slug == material)
            .map(|(_, p)| *p)
            .ok_or_else(|| {
                ReportError::invalid("rendered tables: profiles", material, "no profile given")
            })?;
        let scene = Scene::named(scene_name)?;
        // The first scene (the Head's analogue) also holds Table 6.5's ranks.
        let mut models = TABLE_6_4.to_vec();
        if i == 0 {
            models.extend((2..=ranks).map(svd_n));
            models.extend((1..=ranks).map(|n| KernelModel::Deon { n }));
        }
        let cmp = gpu::compare_models(gpu, &scene, &base, p, material, &models, spec)?;
        let err = |m: KernelModel| {
            cmp.kernels[models.iter().position(|&x| x == m).expect("rendered")]
                .error
                .rms_rel
        };
        if i == 0 {
            t65 = (
                (1..=ranks).map(|n| err(svd_n(n))).collect(),
                (1..=ranks).map(|n| err(KernelModel::Deon { n })).collect(),
            );
        }
        measured.push((
            cmp.scale.cm_per_px,
            cmp.lambert.error.rms_rel,
            TABLE_6_4.map(err),
        ));
    }
    let (svd_raw, deon_raw): (Vec<[f64; 3]>, Vec<[f64; 3]>) = t65;

    // Normalized as the thesis does: the highest per-channel entry of each table is 1.
    let max64 = measured
        .iter()
        .flat_map(|m| m.2.iter().flatten())
        .fold(0.0f64, |a, &b| a.max(b));
    let max65 = svd_raw
        .iter()
        .chain(&deon_raw)
        .flatten()
        .fold(0.0f64, |a, &b| a.max(b));
    let norm = |v: &[[f64; 3]], max: f64| -> Vec<[f64; 3]> {
        v.iter().map(|r| r.map(|x| x / max)).collect()
    };
    let table_6_4: Vec<Rendered64Row> = SCENES
        .iter()
        .zip(&measured)
        .map(
            |(&(thesis, scene, material), &(cm_per_px, lambert, raw))| Rendered64Row {
                scene: scene.into(),
                material: material.into(),
                thesis_scene: thesis.into(),
                cm_per_px,
                raw: raw.to_vec(),
                normalized: norm(&raw, max64),
                published: published.table_6_4[thesis].rows().to_vec(),
                lambert_raw: lambert,
                lambert: lambert.map(|x| x / max64),
            },
        )
        .collect();
    let sum = |m: &[f64; 3]| m.iter().sum::<f64>();
    let sums: Vec<[f64; 4]> = table_6_4
        .iter()
        .map(|r| [0, 1, 2, 3].map(|j| sum(&r.normalized[j])))
        .collect();
    let pub_sums: Vec<[f64; 4]> = published
        .table_6_4
        .values()
        .map(|p| p.rows().map(|m| sum(&m)))
        .collect();
    let table_6_5 = Rendered65 {
        scene: SCENES[0].1.into(),
        material: SCENES[0].2.into(),
        n: (1..=ranks).collect(),
        rows: Table65 {
            svd: norm(&svd_raw, max65),
            deon: norm(&deon_raw, max65),
            svd_raw,
            deon_raw,
            published_svd: published.table_6_5.svd[..ranks].to_vec(),
            published_deon: published.table_6_5.deon[..ranks].to_vec(),
        },
    };
    let claims = claims(
        &sums,
        &pub_sums,
        (&table_6_5.rows.svd, &table_6_5.rows.deon),
        (&published.table_6_5.svd, &published.table_6_5.deon),
    );
    Ok(Rendered {
        adapter: gpu.adapter_name.clone(),
        width,
        height,
        taps: spec.taps,
        seconds: t.elapsed().as_secs_f64(),
        models: TABLE_6_4.map(Into::into).to_vec(),
        table_6_4,
        table_6_5,
        claims,
    })
}

/// The thesis's claims on its rendered scenes, checked on ours. `sums[scene]` is Σ over R, G, B
/// of the normalized Table 6.4 entries of [`TABLE_6_4`]'s models, `published` the thesis's;
/// `(svd[n], deon[n])` the normalized rendered Table 6.5 at N = n + 1, `(ps, pd)` the thesis's.
fn claims(
    sums: &[[f64; 4]],
    published: &[[f64; 4]],
    (svd, deon): (&[[f64; 3]], &[[f64; 3]]),
    (ps, pd): (&[[f64; 3]], &[[f64; 3]]),
) -> Vec<Claim> {
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
    let wins =
        |s: &[[f64; 3]], d: &[[f64; 3]]| (0..s.len()).filter(|&k| sum(&s[k]) < sum(&d[k])).count();
    let saving = |s: &[[f64; 3]], d: &[[f64; 3]]| {
        (0..s.len() - 1)
            .filter(|&k| sum(&s[k]) <= sum(&d[k + 1]))
            .count()
    };
    let n = svd.len();
    let svd_wins_channels = (0..n)
        .flat_map(|k| (0..3).map(move |c| (k, c)))
        .filter(|&(k, c)| svd[k][c] < deon[k][c])
        .count();
    let (s, p) = (sums.len(), published.len());
    vec![
        Claim {
            claim: "Table 6.4 (rendered): SVD rank-1 has the highest image error (Σ R+G+B) of the four rank-1 models in most scenes".into(),
            ours: format!("{} of {s} scenes", svd_worst(sums)),
            published: format!("{} of {p} scenes", svd_worst(published)),
            holds: 2 * svd_worst(sums) > s,
            why: "A rank-1 SVD matches the kernel's peak and loses its far falloff (the thesis: it \"underestimates the far-range scattering\"); renormalized to the kernel's energy, that energy goes to the centre instead, which a shadow edge shows. Our scenes are a sphere on a floor, not the thesis's scans.".into(),
        },
        Claim {
            claim: "Table 6.4 (rendered): pre-integration, guided k = 1 and manual are comparable (in each scene the largest Σ of the three is within 2× the smallest) in most scenes".into(),
            ours: format!("{} of {s} scenes", comparable(sums)),
            published: format!("{} of {p} scenes", comparable(published)),
            holds: 2 * comparable(sums) > s,
            why: "All three keep the kernel's energy and approximate its falloff with one separable pass pair; they differ in how they trade the centre against the tail, which moves the image error by less than the rank-1 SVD's missing falloff.".into(),
        },
        Claim {
            claim: "Table 6.5 (rendered): at equal pass count SVD rank-N has a lower image error (Σ) than d'Eon with N Gaussians, on the sphere with Skin1".into(),
            ours: format!("{} of {n} (per channel {svd_wins_channels} of {})", wins(svd, deon), 3 * n),
            published: format!("{} of {} (Head)", wins(ps, pd), ps.len()),
            holds: wins(svd, deon) == n,
            why: "A sum of N separable Gaussians is a rank-N kernel and the truncated SVD is the best rank-N kernel in kernel space; a rendered image weighs the kernel through its irradiance, so the ordering is expected but not guaranteed.".into(),
        },
        Claim {
            claim: "Table 6.5 (rendered): SVD saves about one rank: SVD rank-N (Σ) is at least as good as d'Eon N+1 in most steps".into(),
            ours: format!("{} of {}", saving(svd, deon), n - 1),
            published: format!("{} of {} (Head)", saving(ps, pd), ps.len() - 1),
            holds: 2 * saving(svd, deon) > n - 1,
            why: "Same argument, with a margin.".into(),
        },
    ]
}
