//! Kernel cost against image error: which model to ship for a renderer's budget (issue 17).
//!
//! Cost is what a renderer pays per pixel at T taps per 1D pass (17 in the shaders, SSSS's
//! count): a separable model of R rank-1 terms runs 2R full-screen passes of T taps, 2R·T texture
//! reads per pixel; the radial Burley kernel is dense 2D, one pass of T² taps. Error is the
//! image-space RMS of [`crate::evaluate`] (each model against the CPU 2D ground-truth convolution
//! on the test signals, images in [0, 1]), averaged over the signals and the three channels; the
//! worst channel is kept beside it.
//!
//! A model is on the Pareto front when no other model is at least as cheap (taps per pixel) and
//! at least as accurate (mean image RMS) and strictly better in one of the two. The
//! recommendation for a pass budget is the separable model of lowest error that runs in at most
//! that many passes; dense kernels are not ranked in pass budgets (one pass of T² taps is not
//! comparable with 2R passes of T) and are reported on their own.
//!
//! Main types: [`Pareto`] (built from an [`Evaluation`] by [`Pareto::of`], or from any points by
//! [`Pareto::new`]), [`Point`], [`Cost`], [`Recommendation`]; the `report` crate draws it.
//!
//! ```
//! use fit::KernelModel;
//! use fit::pareto::{Cost, Pareto, Point};
//! let point = |model, terms, error| Point {
//!     model,
//!     label: format!("{model}"),
//!     cost: Cost::separable(terms, 17),
//!     mean_image_rms: error,
//!     channel_rms: [error; 3],
//!     worst_channel_rms: error,
//! };
//! let svd = |rank| KernelModel::Svd { rank, renormalize: false };
//! let p = Pareto::new(
//!     vec![point(svd(1), 1, 1e-2), point(svd(2), 2, 1e-3), point(KernelModel::Preint, 1, 5e-3)],
//!     17,
//! );
//! // svd1 costs what preint costs and is worse: dominated.
//! assert_eq!(p.front.iter().map(|q| q.label.as_str()).collect::<Vec<_>>(), ["preint", "svd2"]);
//! assert_eq!(p.recommended[0].best.as_ref().unwrap().model, KernelModel::Preint);
//! ```

use serde::Serialize;

use crate::error::{FitError, Result};
use crate::evaluate::Evaluation;
use crate::model::KernelModel;

/// The pass budgets recommendations are made for [full-screen 1D passes].
pub const BUDGETS: [usize; 5] = [2, 4, 6, 8, 12];

/// A model's GPU cost per pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Cost {
    /// Full-screen passes [-]: 2 per rank-1 term (horizontal + vertical), 1 for a dense kernel.
    pub passes: usize,
    /// Texture reads per pixel over all passes [taps/pixel]: 2R·T separable, T² dense.
    pub taps: usize,
    /// Whether the kernel is dense 2D (one pass of T × T taps) rather than separable.
    pub dense: bool,
}

impl Cost {
    /// `terms` rank-1 terms at `taps_per_pass` taps per 1D pass.
    pub fn separable(terms: usize, taps_per_pass: usize) -> Self {
        Cost {
            passes: 2 * terms,
            taps: 2 * terms * taps_per_pass,
            dense: false,
        }
    }

    /// A dense 2D kernel of `taps_per_pass` × `taps_per_pass` taps, in one pass.
    pub fn dense(taps_per_pass: usize) -> Self {
        Cost {
            passes: 1,
            taps: taps_per_pass * taps_per_pass,
            dense: true,
        }
    }
}

/// One model's cost and error on one material.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Point {
    /// The model, as keyed in the [`Evaluation`].
    pub model: KernelModel,
    /// The name for tables (`manual (table A.1)`: the model with its parameters' source).
    pub label: String,
    /// Its GPU cost at the given taps per pass.
    pub cost: Cost,
    /// Image RMS averaged over the test signals and the three channels [-, images in [0, 1]].
    pub mean_image_rms: f64,
    /// Image RMS averaged over the test signals, per channel (R, G, B) [-].
    pub channel_rms: [f64; 3],
    /// The largest of [`Point::channel_rms`] [-].
    pub worst_channel_rms: f64,
}

impl Point {
    /// `self` is at least as cheap (taps per pixel) and as accurate (mean image RMS) as `other`,
    /// and strictly better in one. A point whose error is not finite dominates nothing and is
    /// dominated by every point whose error is finite.
    pub fn dominates(&self, other: &Point) -> bool {
        let (a, b) = (self.mean_image_rms, other.mean_image_rms);
        let (ta, tb) = (self.cost.taps, other.cost.taps);
        a.is_finite() && (!b.is_finite() || (ta <= tb && a <= b && (ta < tb || a < b)))
    }
}

/// The best separable model within a pass budget.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Recommendation {
    /// The budget [full-screen passes].
    pub budget: usize,
    /// The separable model of lowest mean image RMS with at most `budget` passes; `None` when
    /// none fits.
    pub best: Option<Point>,
}

/// Cost against error of every model on one material.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Pareto {
    /// Taps per 1D pass T the costs assume [taps].
    pub taps_per_pass: usize,
    /// Every model, in evaluation order.
    pub points: Vec<Point>,
    /// The points no other point dominates, by taps per pixel ascending (then error). Points
    /// whose error is not finite are never on it.
    pub front: Vec<Point>,
    /// The best separable model per budget of [`BUDGETS`].
    pub recommended: Vec<Recommendation>,
    /// The dense 2D kernels, lowest error first (outside the pass budgets).
    pub dense: Vec<Point>,
}

impl Pareto {
    /// The front, the recommendations and the dense kernels of `points` costed at
    /// `taps_per_pass` taps per 1D pass.
    pub fn new(points: Vec<Point>, taps_per_pass: usize) -> Self {
        let mut front: Vec<Point> = points
            .iter()
            .filter(|p| p.mean_image_rms.is_finite() && !points.iter().any(|q| q.dominates(p)))
            .cloned()
            .collect();
        front.sort_by(|a, b| {
            (a.cost.taps.cmp(&b.cost.taps)).then(a.mean_image_rms.total_cmp(&b.mean_image_rms))
        });
        let recommended = BUDGETS
            .iter()
            .map(|&budget| Recommendation {
                budget,
                best: recommend(&points, budget).cloned(),
            })
            .collect();
        let mut dense: Vec<Point> = points.iter().filter(|p| p.cost.dense).cloned().collect();
        dense.sort_by(|a, b| a.mean_image_rms.total_cmp(&b.mean_image_rms));
        Pareto {
            taps_per_pass,
            points,
            front,
            recommended,
            dense,
        }
    }

    /// Cost and error of every model of an evaluation at `taps_per_pass` taps per 1D pass
    /// (≥ 1). A separable model's terms are those of its fitted kernels (the most over the
    /// channels: SVD stops early on a kernel of lower rank), else the model's own count.
    pub fn of(ev: &Evaluation, taps_per_pass: usize) -> Result<Self> {
        if taps_per_pass == 0 {
            return Err(FitError::invalid("taps per pass", 0, "must be at least 1"));
        }
        let mut models: Vec<KernelModel> = Vec::new();
        for r in &ev.rows {
            if !models.contains(&r.model) {
                models.push(r.model);
            }
        }
        let points = models
            .into_iter()
            .map(|model| point(ev, model, taps_per_pass))
            .collect::<Result<_>>()?;
        Ok(Pareto::new(points, taps_per_pass))
    }
}

/// The separable point of lowest finite mean image RMS with at most `budget` passes.
pub fn recommend(points: &[Point], budget: usize) -> Option<&Point> {
    points
        .iter()
        .filter(|p| !p.cost.dense && p.cost.passes <= budget && p.mean_image_rms.is_finite())
        .min_by(|a, b| a.mean_image_rms.total_cmp(&b.mean_image_rms))
}

/// One model's point: its rows on channels R, G, B and, if separable, its kernels' terms.
fn point(ev: &Evaluation, model: KernelModel, taps_per_pass: usize) -> Result<Point> {
    let mut channel_rms = [0.0; 3];
    let mut label = String::new();
    for (c, rms) in channel_rms.iter_mut().enumerate() {
        let row = ev.row(model, c).ok_or_else(|| {
            FitError::invalid(
                "evaluation",
                model,
                format!("has no row for channel {}", mc::CHANNELS[c]),
            )
        })?;
        if row.image_rms.is_empty() {
            return Err(FitError::invalid(
                "evaluation",
                model,
                "has no image RMS (no test signals)",
            ));
        }
        *rms = row.image_rms.iter().map(|(_, e)| e).sum::<f64>() / row.image_rms.len() as f64;
        label = row.label();
    }
    let cost = match model.terms() {
        None => Cost::dense(taps_per_pass),
        Some(own) => Cost::separable(
            (0..3)
                .filter_map(|c| ev.kernel(model, c).map(|k| k.terms.len()))
                .max()
                .unwrap_or(own),
            taps_per_pass,
        ),
    };
    Ok(Point {
        model,
        label,
        cost,
        mean_image_rms: channel_rms.iter().sum::<f64>() / 3.0,
        channel_rms,
        worst_channel_rms: channel_rms
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::evaluate::Row;
    use crate::separable::{Separable, Term};
    use crate::signals::Signal;

    fn svd(rank: usize) -> KernelModel {
        KernelModel::Svd {
            rank,
            renormalize: false,
        }
    }

    fn deon(n: usize) -> KernelModel {
        KernelModel::Deon { n }
    }

    const RADIAL: KernelModel = KernelModel::Burley { radial: true };

    fn point(model: KernelModel, cost: Cost, error: f64) -> Point {
        Point {
            model,
            label: model.to_string(),
            cost,
            mean_image_rms: error,
            channel_rms: [error; 3],
            worst_channel_rms: error,
        }
    }

    fn labels(points: &[Point]) -> Vec<&str> {
        points.iter().map(|p| p.label.as_str()).collect()
    }

    /// Seven points whose front is known by construction: at 34 taps preint (4e-3) beats svd1
    /// (1e-2) and guided (5e-3); svd2 halves the error at 68 taps, deon2 costs the same and is
    /// worse; deon3 (102 taps) is worse than svd2 and so dominated; svd3 is best of the
    /// separable ones; the dense kernel (289 taps) is more accurate still.
    fn constructed() -> Vec<Point> {
        let s = |terms| Cost::separable(terms, 17);
        vec![
            point(svd(1), s(1), 1e-2),
            point(KernelModel::Preint, s(1), 4e-3),
            point(KernelModel::Guided { k: 1.0, b: 0.0 }, s(1), 5e-3),
            point(svd(2), s(2), 2e-3),
            point(deon(2), s(2), 3e-3),
            point(deon(3), s(3), 2.5e-3),
            point(svd(3), s(3), 1e-3),
            point(RADIAL, Cost::dense(17), 1e-4),
        ]
    }

    #[test]
    fn costs_follow_passes_and_taps() {
        assert_eq!(
            Cost::separable(3, 17),
            Cost {
                passes: 6,
                taps: 102,
                dense: false
            }
        );
        assert_eq!(
            Cost::dense(17),
            Cost {
                passes: 1,
                taps: 289,
                dense: true
            }
        );
    }

    #[test]
    fn the_front_is_the_constructed_one() {
        let p = Pareto::new(constructed(), 17);
        assert_eq!(
            labels(&p.front),
            ["preint", "svd2", "svd3", "burley-radial"]
        );
    }

    #[test]
    fn a_dominated_model_is_never_on_the_front() {
        let points = constructed();
        let p = Pareto::new(points.clone(), 17);
        for q in &points {
            let dominated = points.iter().any(|o| o.dominates(q));
            let on_front = p.front.iter().any(|f| f.model == q.model);
            assert_eq!(on_front, !dominated, "{}", q.label);
        }
        // Along the front, more taps buy strictly less error.
        for w in p.front.windows(2) {
            assert!(w[0].cost.taps < w[1].cost.taps, "{}", w[1].label);
            assert!(w[0].mean_image_rms > w[1].mean_image_rms, "{}", w[1].label);
        }
    }

    #[test]
    fn equal_points_do_not_dominate_each_other() {
        let a = point(svd(1), Cost::separable(1, 17), 1e-3);
        let b = point(KernelModel::Preint, Cost::separable(1, 17), 1e-3);
        assert!(!a.dominates(&b) && !b.dominates(&a));
        assert_eq!(Pareto::new(vec![a, b], 17).front.len(), 2);
    }

    #[test]
    fn a_model_without_a_finite_error_is_never_on_the_front_nor_recommended() {
        let mut points = constructed();
        points.push(point(svd(4), Cost::separable(4, 17), f64::NAN));
        let p = Pareto::new(points, 17);
        assert!(!p.front.iter().any(|q| q.model == svd(4)));
        assert_eq!(
            labels(&p.front),
            ["preint", "svd2", "svd3", "burley-radial"]
        );
        let eight = p.recommended.iter().find(|r| r.budget == 8).unwrap();
        assert_eq!(eight.best.as_ref().unwrap().model, svd(3));
    }

    #[test]
    fn recommendations_respect_the_budget() {
        let p = Pareto::new(constructed(), 17);
        let best: Vec<(usize, KernelModel)> = p
            .recommended
            .iter()
            .map(|r| (r.budget, r.best.as_ref().unwrap().model))
            .collect();
        assert_eq!(
            best,
            [
                (2, KernelModel::Preint),
                (4, svd(2)),
                (6, svd(3)),
                (8, svd(3)),
                (12, svd(3))
            ]
        );
        for r in &p.recommended {
            let b = r.best.as_ref().unwrap();
            assert!(b.cost.passes <= r.budget && !b.cost.dense);
            // Nothing within the budget is more accurate.
            assert!(
                p.points
                    .iter()
                    .filter(|q| !q.cost.dense && q.cost.passes <= r.budget)
                    .all(|q| q.mean_image_rms >= b.mean_image_rms)
            );
        }
        // The dense kernel is reported apart, never as a pass-budget pick.
        assert_eq!(labels(&p.dense), ["burley-radial"]);
        // A budget nothing fits recommends nothing.
        assert!(recommend(&p.points, 1).is_none());
    }

    /// A two-model evaluation: svd3 whose kernels kept 2 terms on channel R and 3 on G and B, and
    /// the dense Burley kernel; errors chosen per channel and signal.
    fn evaluation() -> Evaluation {
        let row = |model, channel, rms: [f64; 2]| Row {
            model,
            variant: None,
            channel,
            kernel_rms: 0.0,
            kernel_rms_normalized: 0.0,
            l1_error: 0.0,
            image_rms: vec![(Signal::Edge, rms[0]), (Signal::Dot, rms[1])],
            fit_seconds: 0.0,
            axis: vec![],
            diagonal: vec![],
        };
        let kernel = |terms| Separable {
            h: 0.01,
            terms: vec![
                Term {
                    sign: 1.0,
                    a: vec![0.0, 1.0, 0.0]
                };
                terms
            ],
        };
        Evaluation {
            rows: (0..3)
                .flat_map(|c| {
                    let c_f = c as f64;
                    [
                        row(svd(3), c, [1e-3 * (c_f + 1.0), 3e-3 * (c_f + 1.0)]),
                        row(RADIAL, c, [1e-4, 1e-4]),
                    ]
                })
                .collect(),
            singular_values: Default::default(),
            truth_axis: Default::default(),
            truth_diagonal: Default::default(),
            h: 0.01,
            kernels: vec![(svd(3), vec![kernel(2), kernel(3), kernel(3)])],
            images: vec![],
        }
    }

    #[test]
    fn an_evaluation_is_costed_from_its_kernels_and_averaged_over_signals_and_channels() {
        let p = Pareto::of(&evaluation(), 17).unwrap();
        assert_eq!(labels(&p.points), ["svd3", "burley-radial"]);
        let s = &p.points[0];
        assert_eq!(s.cost, Cost::separable(3, 17));
        // Channel c: mean of 1e-3·(c+1) and 3e-3·(c+1) = 2e-3·(c+1).
        for c in 0..3 {
            assert!((s.channel_rms[c] - 2e-3 * (c as f64 + 1.0)).abs() < 1e-15);
        }
        assert!((s.mean_image_rms - 4e-3).abs() < 1e-15);
        assert!((s.worst_channel_rms - 6e-3).abs() < 1e-15);
        assert_eq!(p.points[1].cost, Cost::dense(17));
        assert!(Pareto::of(&evaluation(), 0).is_err());
    }

    #[test]
    fn a_missing_channel_is_an_error_naming_the_model() {
        let mut ev = evaluation();
        ev.rows.retain(|r| !(r.model == RADIAL && r.channel == 2));
        let e = Pareto::of(&ev, 17).unwrap_err().to_string();
        assert!(e.contains("burley-radial") && e.contains("channel"), "{e}");
    }
}
