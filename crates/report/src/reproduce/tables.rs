//! Tables 6.2, 6.3, 6.5 and 5.1 from the evaluations of the main materials, with their claims.

use serde::Serialize;

use super::{Claim, MAIN, ModelName, Published};
use fit::KernelModel;
use fit::evaluate::{Evaluation, RANK1, Row};

/// Table 6.2: one material's coefficients [cm⁻¹] with its derived albedo and mean free path.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MaterialRow {
    /// Its slug.
    pub material: String,
    /// Its display name.
    pub name: String,
    /// Relative refractive index.
    pub eta: f64,
    /// σa per channel [cm⁻¹].
    pub sigma_a: [f64; 3],
    /// σs per channel [cm⁻¹].
    pub sigma_s: [f64; 3],
    /// HG g per channel.
    pub g: [f64; 3],
    /// Single-scattering albedo per channel.
    pub albedo: [f64; 3],
    /// Mean free path per channel [cm].
    pub mfp_cm: [f64; 3],
    /// Where the coefficients come from.
    pub source: String,
}

/// Table 6.3: one main material's kernel-space RMS of the rank-1 models.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Table63Row {
    /// The material.
    pub material: String,
    /// The four rank-1 models ([`RANK1`]), in order.
    pub models: Vec<Table63Model>,
}

/// One model's entry of Table 6.3.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Table63Model {
    /// The model and its title.
    #[serde(flatten)]
    pub model: ModelName,
    /// Kernel-space RMS per channel.
    pub raw: [f64; 3],
    /// `raw` over the table's largest entry (the thesis's normalization).
    pub normalized: [f64; 3],
    /// The thesis's normalized values.
    pub published: [f64; 3],
}

/// Table 6.5: SVD rank-N against d'Eon's N Gaussians on Skin1, image-space RMS over the five
/// test signals (N = 1…6 per row, R, G, B).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Table65 {
    /// SVD rank-N, normalized (highest entry = 1).
    pub svd: Vec<[f64; 3]>,
    /// d'Eon N, normalized.
    pub deon: Vec<[f64; 3]>,
    /// SVD rank-N, raw.
    pub svd_raw: Vec<[f64; 3]>,
    /// d'Eon N, raw.
    pub deon_raw: Vec<[f64; 3]>,
    /// The thesis's SVD rows (Head scene).
    pub published_svd: Vec<[f64; 3]>,
    /// The thesis's d'Eon rows.
    pub published_deon: Vec<[f64; 3]>,
}

/// Table 5.1: a model family's properties (the thesis's) and our mean fit time.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Table51Row {
    /// The thesis's row name.
    pub model: String,
    /// The model timed for it.
    pub timed: KernelModel,
    /// Visual quality (the thesis's words).
    pub visual_quality: String,
    /// 1D convolutions per kernel.
    pub convolutions_1d: String,
    /// Separable.
    pub separable: bool,
    /// Fitted in closed form.
    pub closed_form: bool,
    /// Our mean fit time per channel over the five main materials [s].
    pub fit_seconds_per_channel: f64,
}

/// Tables 6.2, 6.3, 6.5 and 5.1 with their claims.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Tables {
    /// Table 6.2, every material.
    pub table_6_2: Vec<MaterialRow>,
    /// Table 6.3, the main materials.
    pub table_6_3: Vec<Table63Row>,
    /// Table 6.5 on Skin1.
    pub table_6_5: Table65,
    /// Table 5.1.
    pub table_5_1: Vec<Table51Row>,
    /// The claims of Tables 6.3 and 6.5.
    #[serde(skip)]
    pub claims: Vec<Claim>,
}

fn find(ev: &Evaluation, model: KernelModel, c: usize) -> &Row {
    ev.row(model, c)
        .expect("evaluate measures every model of fit::evaluate::MODELS on every channel")
}

/// RMS over the five test signals of a row's image-space errors.
fn image_rms(r: &Row) -> f64 {
    (r.image_rms.iter().map(|(_, e)| e * e).sum::<f64>() / r.image_rms.len() as f64).sqrt()
}

/// The tables from `materials` (slug and coefficients, every material of Table 6.2) and `evals`,
/// the evaluations of the [`MAIN`] materials in that order (panics on another count: a caller's
/// bug).
pub fn tables(
    materials: &[(&str, &mc::Material)],
    evals: &[Evaluation],
    published: &Published,
) -> Tables {
    assert_eq!(evals.len(), MAIN.len(), "one evaluation per main material");
    let table_6_2 = materials
        .iter()
        .map(|&(slug, m)| MaterialRow {
            material: slug.into(),
            name: m.name.clone(),
            eta: m.eta,
            sigma_a: m.sigma_a,
            sigma_s: m.sigma_s,
            g: m.g,
            albedo: [0, 1, 2].map(|c| m.albedo(c)),
            mfp_cm: [0, 1, 2].map(|c| m.mfp(c)),
            source: m.source.clone(),
        })
        .collect();

    // Table 6.3: raw kernel RMS, and normalized by the table's largest entry (the thesis's way).
    let raw: Vec<Vec<[f64; 3]>> = evals
        .iter()
        .map(|ev| {
            RANK1
                .iter()
                .map(|&m| [0, 1, 2].map(|c| find(ev, m, c).kernel_rms))
                .collect()
        })
        .collect();
    let max = raw
        .iter()
        .flatten()
        .flatten()
        .fold(0.0f64, |a, &b| a.max(b));
    let table_6_3 = MAIN
        .iter()
        .zip(&raw)
        .map(|(m, raw)| Table63Row {
            material: (*m).into(),
            models: RANK1
                .iter()
                .zip(raw)
                .zip(published.table_6_3[*m].rows())
                .map(|((&model, &raw), published)| Table63Model {
                    model: model.into(),
                    raw,
                    normalized: raw.map(|x| x / max),
                    published,
                })
                .collect(),
        })
        .collect();

    // Table 6.5: SVD rank-N vs d'Eon N, Skin1, image-space RMS over the five test signals.
    let skin = &evals[MAIN
        .iter()
        .position(|m| *m == "skin1")
        .expect("skin1 is a main material")];
    let svd_n = |rank| KernelModel::Svd {
        rank,
        renormalize: false,
    };
    let deon_n = |n| KernelModel::Deon { n };
    let ours = |model: &dyn Fn(usize) -> KernelModel| -> Vec<[f64; 3]> {
        (1..=6)
            .map(|n| [0, 1, 2].map(|c| image_rms(find(skin, model(n), c))))
            .collect()
    };
    let (svd, deon) = (ours(&svd_n), ours(&deon_n));
    let kernel_wins = (1..=6)
        .flat_map(|n| (0..3).map(move |c| (n, c)))
        .filter(|&(n, c)| find(skin, svd_n(n), c).kernel_rms < find(skin, deon_n(n), c).kernel_rms)
        .count();
    let max65 = svd
        .iter()
        .chain(&deon)
        .flatten()
        .fold(0.0f64, |a, &b| a.max(b));
    let norm =
        |v: &[[f64; 3]]| -> Vec<[f64; 3]> { v.iter().map(|r| r.map(|x| x / max65)).collect() };
    let table_6_5 = Table65 {
        svd: norm(&svd),
        deon: norm(&deon),
        svd_raw: svd,
        deon_raw: deon,
        published_svd: published.table_6_5.svd.clone(),
        published_deon: published.table_6_5.deon.clone(),
    };

    let table_5_1 = table_5_1(evals);
    let claims = claims(&raw, &table_6_5, kernel_wins, published);
    Tables {
        table_6_2,
        table_6_3,
        table_6_5,
        table_5_1,
        claims,
    }
}

/// Table 5.1: each model family's properties, and our mean fit time per channel over the
/// evaluations of the main materials.
fn table_5_1(evals: &[Evaluation]) -> Vec<Table51Row> {
    let svd_n = |rank| KernelModel::Svd {
        rank,
        renormalize: false,
    };
    let deon_n = |n| KernelModel::Deon { n };
    let fit_time = |model: KernelModel| {
        let v: Vec<f64> = evals
            .iter()
            .flat_map(|ev| (0..3).map(move |c| find(ev, model, c).fit_seconds))
            .collect();
        v.iter().sum::<f64>() / v.len() as f64
    };
    // The thesis's rows name families; each is timed on the model given beside it.
    let [svd1, preint, guided_k1, manual] = RANK1;
    [
        ("d'Eon 1 Gaussian", deon_n(1), "low", "2", true, false),
        (
            "d'Eon 2+ Gaussians",
            deon_n(6),
            "high",
            "2 per Gaussian",
            false,
            false,
        ),
        ("SVD rank-1", svd1, "low", "2", true, true),
        (
            "SVD rank-2+",
            svd_n(6),
            "excellent",
            "2 per rank",
            false,
            true,
        ),
        ("Kernel pre-integration", preint, "high", "2", true, true),
        (
            "Guided optimization",
            guided_k1,
            "controllable",
            "2",
            true,
            false,
        ),
        (
            "Manual approximation",
            manual,
            "controllable",
            "2",
            true,
            true,
        ),
    ]
    .iter()
    .map(
        |&(name, model, q, passes, separable, closed_form)| Table51Row {
            model: name.into(),
            timed: model,
            visual_quality: q.into(),
            convolutions_1d: passes.into(),
            separable,
            closed_form,
            fit_seconds_per_channel: fit_time(model),
        },
    )
    .collect()
}

/// The qualitative claims of Tables 6.3 and 6.5, checked on our numbers and on the published ones.
/// `raw[material][j]` is the kernel RMS of `RANK1[j]`: 0 SVD rank-1, 1 pre-integration, 2 guided
/// k = 1, 3 manual.
fn claims(
    raw: &[Vec<[f64; 3]>],
    t65: &Table65,
    kernel_wins: usize,
    published: &Published,
) -> Vec<Claim> {
    let (svd, deon) = (&t65.svd_raw, &t65.deon_raw);
    let cases = |rows: &[Vec<[f64; 3]>], f: &dyn Fn(&[[f64; 3]]) -> [bool; 3]| -> usize {
        rows.iter()
            .map(|m| f(m).iter().filter(|&&b| b).count())
            .sum()
    };
    let pub_rows: Vec<Vec<[f64; 3]>> = MAIN
        .iter()
        .map(|m| published.table_6_3[*m].rows().to_vec())
        .collect();
    let agree = raw
        .iter()
        .zip(&pub_rows)
        .map(|(o, p)| {
            (0..3)
                .filter(|&c| (o[1][c] < o[2][c]) == (p[1][c] < p[2][c]))
                .count()
        })
        .sum::<usize>();
    let svd_lowest = |m: &[[f64; 3]]| {
        [0, 1, 2].map(|c| m[0][c] < m[1][c] && m[0][c] < m[2][c] && m[0][c] < m[3][c])
    };
    let preint_below_guided = |m: &[[f64; 3]]| [0, 1, 2].map(|c| m[1][c] < m[2][c]);
    let ratio = |rows: &[Vec<[f64; 3]>]| {
        let r: Vec<f64> = rows
            .iter()
            .flat_map(|m| (0..3).map(move |c| m[1][c] / m[0][c]))
            .collect();
        r.iter().sum::<f64>() / r.len() as f64
    };
    let n65 = |s: &[[f64; 3]], d: &[[f64; 3]], f: &dyn Fn(usize, usize) -> bool| {
        (0..6)
            .flat_map(|n| (0..3).map(move |c| (n, c)))
            .filter(|&(n, c)| f(n, c) && s[n][c].is_finite() && d[n][c].is_finite())
            .count()
    };
    let (ps, pd) = (&published.table_6_5.svd, &published.table_6_5.deon);
    let svd_wins = n65(svd, deon, &|n, c| svd[n][c] < deon[n][c]);
    let pub_svd_wins = n65(ps, pd, &|n, c| ps[n][c] < pd[n][c]);
    let saving = |s: &[[f64; 3]], d: &[[f64; 3]]| {
        (0..5)
            .flat_map(|n| (0..3).map(move |c| (n, c)))
            .filter(|&(n, c)| s[n][c] <= d[n + 1][c])
            .count()
    };
    let decreasing = |v: &[[f64; 3]]| {
        (0..3).all(|c| v.windows(2).all(|w| w[1][c] <= 1.01 * w[0][c]) && v[5][c] * 5.0 <= v[0][c])
    };
    let of15 = |n: usize| format!("{n} of 15");
    vec![
        Claim::new(
            "Table 6.3: SVD rank-1 (not renormalized) has the lowest kernel-space RMS of the four rank-1 models",
            of15(cases(raw, &svd_lowest)),
            of15(cases(&pub_rows, &svd_lowest)),
            cases(raw, &svd_lowest) == 15,
            "Eckart–Young: the truncated SVD is the best rank-1 approximation in the Frobenius norm, whatever the profile.",
        ),
        Claim::new(
            "Table 6.3: pre-integration's kernel RMS is roughly twice SVD rank-1's",
            format!("mean ratio {:.2}", ratio(raw)),
            format!("mean ratio {:.2}", ratio(&pub_rows)),
            (1.5..3.0).contains(&ratio(raw)),
            "Pre-integration matches projections, not point values: it spreads the peak, which costs kernel-space error but not edge fidelity.",
        ),
        Claim::new(
            "Table 6.3: which of pre-integration and guided k = 1 has the lower kernel RMS, case by case",
            format!("same as the thesis in {agree} of 15"),
            format!(
                "pre-integration lower in {} of 15",
                cases(&pub_rows, &preint_below_guided)
            ),
            agree >= 12,
            "Guided k = 1 weights errors by radius, trading the centre for the falloff; which wins in plain kernel RMS depends on the profile (the thesis's Ketchup G/B are exceptions). Our guided fit meets its L1 constraint exactly; the thesis's was off by up to 25%.",
        ),
        Claim::new(
            "Table 6.5 (kernel space): at equal pass count SVD rank-N has lower kernel-space RMS than d'Eon with N Gaussians",
            format!("{kernel_wins} of 18"),
            "not tabulated".into(),
            kernel_wins == 18,
            "Eckart–Young: a sum of N separable Gaussians is a rank-N kernel, and the truncated SVD is the best rank-N kernel in the Frobenius norm.",
        ),
        Claim::new(
            "Table 6.5 (image space): at equal pass count SVD rank-N has lower image-space RMS than d'Eon with N Gaussians",
            format!("{svd_wins} of 18"),
            format!("{pub_svd_wins} of 18"),
            svd_wins == 18,
            "A sum of N separable Gaussians is itself a rank-N kernel, and SVD's rank-N is the best one in kernel space. Image space need not follow: every SVD term of a radially symmetric kernel is even, and some have Σa = 0, so their pass adds nothing to an edge's image and little to other near-symmetric signals; SVD then plateaus for one rank while d'Eon keeps improving.",
        ),
        Claim::new(
            "Table 6.5: SVD saves about one rank: SVD rank-N is at least as good as d'Eon N+1",
            of15(saving(svd, deon)),
            of15(saving(ps, pd)),
            saving(svd, deon) >= 10,
            "Same argument, with a margin.",
        ),
        Claim::new(
            "Table 6.5: both converge to the ground truth as N grows (no step increases the error by more than 1%, and N = 6 is at least 5× better than N = 1)",
            format!("SVD {}, d'Eon {}", decreasing(svd), decreasing(deon)),
            format!("SVD {}, d'Eon {}", decreasing(ps), decreasing(pd)),
            decreasing(svd) && decreasing(deon),
            "Each added term can only reduce the best achievable kernel-space error (nested fits); image-space error follows up to plateaus (see above).",
        ),
    ]
}
