//! Chapter 5's figures that the tables do not cover, on Skin1 (the thesis's example material
//! throughout chapter 5): Fig. 5.14–5.15, guided optimization with k = 1.55, b = 50 imitating
//! pre-integration ([`fit::imitation`]), and Fig. 5.17, the manual model's w sweep with Table
//! A.1's Gaussians ([`fit::WSweep`]); their numbers, plots and claims.

use std::time::Instant;

use serde::Serialize;

use super::{Claim, ModelName};
use crate::error::{ReportError, Result};
use fit::imitation::{IMITATION, Imitation};
use fit::metrics::ImageSize;
use fit::{KernelModel, Profile, WSweep, ground_truth, table_a1};

/// The material of chapter 5's figures.
pub const MATERIAL: &str = "skin1";

/// Fig. 5.15's numbers.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Fig515 {
    /// The material.
    pub material: String,
    /// The test signal the images are compared on.
    pub signal: String,
    /// The kernels' extent, in largest mean free paths (the extent b = 50 is defined on).
    pub extent_mfp: f64,
    /// Half-width of the kernels [samples].
    pub half_samples: usize,
    /// Sample spacing [cm].
    pub h_cm: f64,
    /// Each compared model's distance to pre-integration.
    pub models: Vec<Fig515Model>,
    /// k's control with and without the axis term: image distance of k = 0 against k = 2.
    pub k_spread: Vec<KSpread>,
    /// Time to fit and measure [s].
    pub seconds: f64,
}

/// One model of Fig. 5.15.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Fig515Model {
    /// The model and its title.
    #[serde(flatten)]
    pub model: ModelName,
    /// Image distance to pre-integration's image, relative, per channel.
    pub image_distance: [f64; 3],
    /// ‖A − A_p‖_F / ‖A_p‖_F per channel.
    pub kernel_distance: [f64; 3],
    /// Fit time per channel [s].
    pub fit_seconds_per_channel: f64,
}

/// k = 0 against k = 2 at one b.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct KSpread {
    /// The axis term's b.
    pub b: f64,
    /// Relative image distance per channel.
    pub image_distance: [f64; 3],
}

/// Fig. 5.17's numbers.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Fig517 {
    /// The material.
    pub material: String,
    /// Table A.1's w.
    pub table_a1_w: f64,
    /// √τ_n per channel [cm].
    pub sqrt_tau_near_cm: [f64; 3],
    /// √τ_f per channel [cm].
    pub sqrt_tau_far_cm: [f64; 3],
    /// The swept w.
    pub w: Vec<f64>,
    /// Image-space RMS per w and channel.
    pub image_rms: Vec<[f64; 3]>,
    /// The edge's 10–90 % width per w and channel [cm].
    pub edge_width_cm: Vec<[f64; 3]>,
    /// The ground truth's edge width per channel [cm].
    pub truth_edge_width_cm: [f64; 3],
    /// The w of the lowest image-space RMS per channel.
    pub best_w: [f64; 3],
    /// Time to measure [s].
    pub seconds: f64,
}

/// Both figures, with what their plots are drawn from and their claims.
#[derive(Clone, Debug)]
pub struct Chapter5 {
    /// Fig. 5.15's measurement (for its plot).
    pub imitation: Imitation,
    /// Fig. 5.17's measurement (for its plot).
    pub sweep: WSweep,
    /// Fig. 5.15's numbers.
    pub fig_5_15: Fig515,
    /// Fig. 5.17's numbers.
    pub fig_5_17: Fig517,
    /// Their claims.
    pub claims: Vec<Claim>,
}

impl Chapter5 {
    /// The two figures' plots: (file name, PNG bytes).
    pub fn plots(&self) -> Result<Vec<(&'static str, Vec<u8>)>> {
        Ok(vec![
            (
                "fig5_15_guided_vs_preint.png",
                crate::plot::imitation(&self.imitation, "Skin1")?,
            ),
            (
                "fig5_17_manual_w_sweep.png",
                crate::plot::w_sweep(&self.sweep, "Skin1")?,
            ),
        ])
    }
}

/// Measures both figures on Skin1 (`material`, `profile`), test images of `image`, kernels of
/// Fig. 5.15 extended to `extent_mfp` of the largest mean free path (the thesis's 32, Table 6.1).
pub fn chapter5(
    material: &mc::Material,
    profile: &Profile,
    image: ImageSize,
    extent_mfp: f64,
) -> Result<Chapter5> {
    // Fig. 5.15: b = 50 is defined on the kernel's extent, which in the thesis is 32 of the
    // largest MFP (Table 6.1): a shorter profile (--quick) is padded with zeros to it, so the
    // axis band reaches the thesis's ≈ 32/√50 ≈ 4.5 MFP.
    let t = Instant::now();
    let max_mfp = (0..3).map(|c| material.mfp(c)).fold(0.0, f64::max);
    let half = profile
        .len()
        .max((extent_mfp * max_mfp / profile.dr).ceil() as usize);
    let padded: Vec<_> = (0..3)
        .map(|c| ground_truth(profile, c, Some(half)))
        .collect();
    let imitation = Imitation::measure(&padded, image)?;
    let fig_5_15 = Fig515 {
        material: MATERIAL.into(),
        signal: "shaded".into(),
        extent_mfp,
        half_samples: imitation.half,
        h_cm: imitation.h,
        models: imitation
            .candidates
            .iter()
            .map(|c| Fig515Model {
                model: c.model.into(),
                image_distance: c.image_distance,
                kernel_distance: c.kernel_distance,
                fit_seconds_per_channel: c.fit_seconds[0],
            })
            .collect(),
        k_spread: imitation
            .k_spread
            .iter()
            .map(|&(b, image_distance)| KSpread { b, image_distance })
            .collect(),
        seconds: t.elapsed().as_secs_f64(),
    };

    // Fig. 5.17: Table A.1's τ_n, τ_f on the profile's own grid, as Table 6.3's manual kernel.
    let t = Instant::now();
    let params = table_a1(MATERIAL).ok_or_else(|| {
        ReportError::invalid("Table A.1 material", MATERIAL, "Table A.1 has no such row")
    })?;
    let table_w = params[0].w;
    let truths: Vec<_> = fit::ground_truths(profile);
    let swept: Vec<f64> = (0..=20).map(|i| f64::from(i) / 20.0).collect();
    let sweep = WSweep::measure(&truths, params, &swept, &[0.1, table_w, 0.9], image)?;
    let fig_5_17 = Fig517 {
        material: MATERIAL.into(),
        table_a1_w: table_w,
        sqrt_tau_near_cm: params.map(|m| m.tau_near.sqrt()),
        sqrt_tau_far_cm: params.map(|m| m.tau_far.sqrt()),
        w: sweep.w.clone(),
        image_rms: sweep.image_rms.clone(),
        edge_width_cm: sweep.edge_width.clone(),
        truth_edge_width_cm: sweep.truth_edge_width,
        best_w: sweep.best_w(),
        seconds: t.elapsed().as_secs_f64(),
    };
    let claims = claims(&imitation, &sweep, table_w);
    Ok(Chapter5 {
        imitation,
        sweep,
        fig_5_15,
        fig_5_17,
        claims,
    })
}

/// R/G/B values with `digits` decimals.
fn rgb(v: [f64; 3], digits: usize) -> String {
    v.map(|x| format!("{x:.digits$}")).join(" / ")
}

fn claims(im: &Imitation, s: &WSweep, table_w: f64) -> Vec<Claim> {
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
        Claim {
            claim: "Fig. 5.15: guided k = 1.55, b = 50 gives images closer to pre-integration's than guided k = 1 (b = 0) and SVD rank-1 (shaded test signal, every channel)".into(),
            ours: format!(
                "relative image distance R / G / B: {} (k = 1: {}; SVD rank-1: {})",
                rgb(ours.image_distance, 4),
                rgb(guided.image_distance, 4),
                rgb(svd.image_distance, 4)
            ),
            published: "similar to pre-integration (Fig. 5.15a–b, by eye)".into(),
            holds: closer,
            why: format!(
                "The axis term (1 − e^(−b x̂²))(1 − e^(−b ŷ²)) lowers the weights on and near the main axes, as the guide Γ_p under which eq. 5.19's optimum is pre-integration does (Fig. 5.14). The kernels are fitted on the thesis's extent (32 of the largest MFP, Table 6.1), the one b = 50 is defined on. Closest of all compared models, R / G / B: {}.",
                closest.join(" / ")
            ),
        },
        Claim::new(
            "Fig. 5.15c–d: with b = 50, k no longer controls centre against falloff: the images of k = 0 and k = 2 differ less than without the axis term (every channel)",
            format!(
                "k = 0 vs k = 2, relative image distance R / G / B: {} with b = 50, {} with b = 0",
                rgb(with, 4),
                rgb(without, 4)
            ),
            "Fig. 5.15c (k = 0) looks like Fig. 5.15d (k = 2)".into(),
            weakened,
            "With the axis term the weight vanishes near both axes and the centre (Γ ≈ b²x̂²ŷ²·r^k there) whatever k, so the centre, which k = 0 otherwise fits closely, is left to the L1 constraint in every case.",
        ),
        Claim::new(
            "Fig. 5.15 (kernel space): the k = 1.55, b = 50 kernel itself is closer to pre-integration's than guided k = 1's (‖A − A_p‖_F / ‖A_p‖_F, every channel)",
            format!(
                "R / G / B: {} (k = 1: {})",
                rgb(ours.kernel_distance, 3),
                rgb(guided.kernel_distance, 3)
            ),
            "not measured (the thesis compares images)".into(),
            kernel_close,
            "Our fit meets ‖a‖₁² = ‖R_d‖₁ exactly; with b > 0 the rows next to the axes carry almost no weight, so the constraint's multiplier piles mass there and the kernel has a narrow spike at the centre. Images, binned to the evaluation grid, barely see it; the Frobenius norm does. The thesis used a weakened soft constraint (up to 25 % off, §6.4), which would not.",
        ),
        Claim::new(
            "Fig. 5.17: raising w moves the manual kernel from far scattering (pronounced falloff) to near scattering (sharper features): the edge's 10–90 % width falls monotonically with w (every channel)",
            format!(
                "edge width R / G / B from w = 0 to w = 1: {} → {} cm (ground truth {} cm)",
                rgb([0, 1, 2].map(first), 3),
                rgb([0, 1, 2].map(last), 3),
                rgb(s.truth_edge_width, 3)
            ),
            "a seamless transition (Fig. 5.17c–e, by eye)".into(),
            monotone,
            "The light across an edge is the tail ∫ₓ^∞ a_m = w·Q_n(x) + (1 − w)·Q_f(x) of the two Gaussians' tails (eq. 5.15); the narrow Gaussian's tail is below the wide one's at every x > 0, so every point of the edge moves towards the narrow one as w grows.",
        ),
        Claim {
            claim: "Table A.1 (§5.4, parameters optimized by hand in image space): Skin1's w = 0.533 lies within 0.2 of the w with the lowest image-space error (every channel)".into(),
            ours: format!("lowest image-space RMS at w = {} (R / G / B)", rgb(best, 2)),
            published: format!("w = {table_w}"),
            holds: near_optimum,
            why: format!(
                "Table A.1's Gaussians are narrower than our Skin1 profile: even the far one alone (w = 0) crosses an edge in {} cm where the ground truth takes {} cm (R / G / B), so in the red and green channels more far weight keeps helping. The thesis tuned by eye on its Head scene at its kernel scale (‘highly adapted to the given scene’, §6.4); our test signals differ.",
                rgb([0, 1, 2].map(first), 3),
                rgb(s.truth_edge_width, 3)
            ),
        },
    ]
}
