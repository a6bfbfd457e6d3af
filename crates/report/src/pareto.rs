//! The Pareto plot of [`fit::pareto`]: taps per pixel against image error, every model labelled
//! and coloured by family, the front as a step line.

use plotters::prelude::*;

use fit::Family;
use fit::pareto::{Pareto, Point};

use crate::error::{ReportError, Result};
use crate::plot::{font, png_of};

/// One colour per model family.
fn family_color(family: Family) -> RGBColor {
    match family {
        Family::Svd => RGBColor(0, 0, 0),
        Family::Preint => RGBColor(230, 120, 0),
        Family::Guided => RGBColor(0, 150, 200),
        Family::Manual => RGBColor(160, 0, 160),
        Family::Deon => RGBColor(30, 160, 60),
        Family::Skin => RGBColor(120, 120, 0),
        Family::Burley => RGBColor(220, 40, 40),
    }
}

/// Label font size [px] and the least vertical distance between two labels [px].
const LABEL_FONT: u32 = 13;
const LABEL_PITCH: i32 = 14;

/// Taps per pixel (x, log, ticks at every model's cost) against mean image RMS (y, log) of every
/// model, each labelled and coloured by family (filled: on the front; squares: dense 2D kernels),
/// with the Pareto front as a step line; `title` names the material. Points whose error is not
/// positive and finite cannot sit on a log axis and are left out. As PNG bytes (1100 × 700).
pub fn plot(p: &Pareto, title: &str) -> Result<Vec<u8>> {
    let (width, height) = (1100u32, 700u32);
    let name = format!("{title} Pareto plot");
    let fail = |e: &dyn std::fmt::Display| ReportError::Plot {
        path: name.clone(),
        message: e.to_string(),
    };
    let plottable = |q: &&Point| q.mean_image_rms.is_finite() && q.mean_image_rms > 0.0;
    let shown: Vec<&Point> = p.points.iter().filter(plottable).collect();
    if shown.is_empty() {
        return Err(fail(&"no model has a positive, finite image RMS"));
    }
    let mut ticks: Vec<usize> = shown.iter().map(|q| q.cost.taps).collect();
    ticks.sort_unstable();
    ticks.dedup();
    let (e_lo, e_hi) = shown.iter().fold((f64::INFINITY, 0.0f64), |(a, b), q| {
        (a.min(q.mean_image_rms), b.max(q.mean_image_rms))
    });
    // Room for the labels right of the rightmost points and above the highest one.
    let x_range = (ticks[0].max(1) as f64 / 1.5)..(ticks[ticks.len() - 1] as f64 * 1.8);
    let y_range = (e_lo / 2.0)..(e_hi * 3.0);
    let on_front = |q: &Point| p.front.iter().any(|f| f.model == q.model);

    png_of((width, height), &name, |root, _| {
        font();
        root.fill(&WHITE).map_err(|e| fail(&e))?;
        let mut ch = ChartBuilder::on(&root)
            .caption(
                format!(
                    "{title}: GPU cost against image error (T = {} taps per 1D pass)",
                    p.taps_per_pass
                ),
                ("sans-serif", 18),
            )
            .margin(12)
            .x_label_area_size(44)
            .y_label_area_size(80)
            .build_cartesian_2d(
                x_range
                    .clone()
                    .log_scale()
                    .with_key_points(ticks.iter().map(|&t| t as f64).collect()),
                y_range.log_scale(),
            )
            .map_err(|e| fail(&e))?;
        ch.configure_mesh()
            .x_desc("texture taps per pixel [taps/pixel] (2R·T separable, T² dense), log scale")
            .y_desc("mean image RMS over signals and channels [-], log scale")
            .x_label_formatter(&|v| format!("{v:.0}"))
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .draw()
            .map_err(|e| fail(&e))?;

        // The front as a staircase: the error each number of taps buys, held until the next
        // front member, continued to the right edge.
        let mut stairs: Vec<(f64, f64)> = Vec::new();
        for q in p.front.iter().filter(plottable) {
            if let Some(&(_, e)) = stairs.last() {
                stairs.push((q.cost.taps as f64, e));
            }
            stairs.push((q.cost.taps as f64, q.mean_image_rms));
        }
        if let Some(&(_, e)) = stairs.last() {
            stairs.push((x_range.end, e));
        }
        let grey = RGBColor(90, 90, 90);
        ch.draw_series(LineSeries::new(stairs, grey.stroke_width(2)))
            .map_err(|e| fail(&e))?
            .label("Pareto front")
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], grey.stroke_width(2))
            });

        let at = |q: &Point| (q.cost.taps as f64, q.mean_image_rms);
        let style = |q: &Point| {
            let color = family_color(q.model.family());
            if on_front(q) {
                color.filled()
            } else {
                color.stroke_width(2)
            }
        };
        for family in Family::ALL {
            let color = family_color(family);
            let members = shown
                .iter()
                .filter(|q| q.model.family() == family && !q.cost.dense);
            if members.clone().next().is_none() {
                continue;
            }
            ch.draw_series(members.map(|q| Circle::new(at(q), 5, style(q))))
                .map_err(|e| fail(&e))?
                .label(family.name())
                .legend(move |(x, y)| Circle::new((x + 10, y), 5, color.filled()));
        }
        if shown.iter().any(|q| q.cost.dense) {
            let dense = shown.iter().filter(|q| q.cost.dense);
            ch.draw_series(
                dense.map(|q| {
                    EmptyElement::at(at(q)) + Rectangle::new([(-5, -5), (5, 5)], style(q))
                }),
            )
            .map_err(|e| fail(&e))?
            .label("dense 2D kernel (square)")
            .legend(move |(x, y)| {
                Rectangle::new([(x + 5, y - 5), (x + 15, y + 5)], grey.stroke_width(2))
            });
        }
        if shown.iter().any(|q| !on_front(q)) {
            ch.draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
                .map_err(|e| fail(&e))?
                .label("not on the front (hollow)")
                .legend(move |(x, y)| Circle::new((x + 10, y), 5, grey.stroke_width(2)));
        }

        // Labels above right of their points, clear of the front's horizontal steps. Where points
        // of one cost crowd, labels are stacked upwards from the lowest point, each at least a
        // line above the one below it, and tied to a point they left by a thin line.
        let mut labels: Vec<(usize, (i32, i32), &Point)> = shown
            .iter()
            .map(|q| (q.cost.taps, ch.backend_coord(&at(q)), *q))
            .collect();
        // Per cost, lowest point (largest pixel row) first.
        labels.sort_by_key(|&(taps, (_, y), _)| (taps, std::cmp::Reverse(y)));
        let mut below: Option<(usize, i32)> = None;
        for (taps, (x, y), q) in labels {
            // Bottom edge of the label [px].
            let bottom = match below {
                Some((t, top)) if t == taps => (y - 1).min(top),
                _ => y - 1,
            };
            below = Some((taps, bottom - LABEL_PITCH));
            let color = family_color(q.model.family());
            if bottom < y - LABEL_PITCH / 2 {
                root.draw(&PathElement::new(
                    vec![(x + 4, y - 4), (x + 9, bottom - LABEL_PITCH / 2)],
                    color.mix(0.6),
                ))
                .map_err(|e| fail(&e))?;
            }
            root.draw(&Text::new(
                q.label.clone(),
                (x + 10, bottom - LABEL_PITCH),
                ("sans-serif", LABEL_FONT).into_font().color(&color),
            ))
            .map_err(|e| fail(&e))?;
        }
        ch.configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .border_style(BLACK)
            .background_style(WHITE.mix(0.8))
            .draw()
            .map_err(|e| fail(&e))?;
        root.present().map_err(|e| fail(&e))?;
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use fit::KernelModel;
    use fit::pareto::Cost;

    #[test]
    fn the_plot_is_a_png_of_the_stated_size() {
        let point = |model: KernelModel, terms, error| Point {
            model,
            label: model.to_string(),
            cost: Cost::separable(terms, 17),
            mean_image_rms: error,
            channel_rms: [error; 3],
            worst_channel_rms: error,
        };
        let svd = |rank| KernelModel::Svd {
            rank,
            renormalize: false,
        };
        let points = vec![
            point(svd(1), 1, 1e-2),
            point(svd(2), 2, 1e-3),
            point(KernelModel::Preint, 1, 5e-3),
        ];
        let bytes = plot(&Pareto::new(points, 17), "test").unwrap();
        let info = png::Decoder::new(std::io::Cursor::new(bytes))
            .read_info()
            .unwrap()
            .info()
            .clone();
        assert_eq!((info.width, info.height), (1100, 700));
        let nothing = vec![point(svd(1), 1, 0.0)];
        assert!(plot(&Pareto::new(nothing, 17), "test").is_err());
    }
}
