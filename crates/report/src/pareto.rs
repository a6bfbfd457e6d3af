//! The Pareto plot of [`fit::pareto`]: taps per pixel against image error, every model labelled
//! and coloured by family, the front as a step line.

use plotters::coord::ranged1d::Ranged;
use plotters::prelude::*;

use fit::Family;
use fit::pareto::{Pareto, Point};

use crate::error::{ReportError, Result};
use crate::plot::chart::{Chart, Frame, Mark, Ticks, axes, legend};
use crate::plot::{Area, InPlot, png_of};

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

/// Grey of the front and of the legend's glyphs for marker shapes.
const GREY: RGBColor = RGBColor(90, 90, 90);

/// The chart's frame [px].
const FRAME: Frame = Frame {
    caption: 18,
    margin: 12,
    x_area: 44,
    y_area: 80,
};

/// Whether a point can sit on the log error axis: its error is positive and finite.
fn plottable(q: &Point) -> bool {
    q.mean_image_rms.is_finite() && q.mean_image_rms > 0.0
}

/// Where a point sits: (taps per pixel, mean image RMS [-]).
fn at(q: &Point) -> (f64, f64) {
    (q.cost.taps as f64, q.mean_image_rms)
}

/// Taps per pixel (x, log, ticks at every model's cost) against mean image RMS (y, log) of every
/// model, each labelled and coloured by family (filled: on the front; squares: dense 2D kernels),
/// with the Pareto front as a step line; `title` names the material. Points whose error is not
/// positive and finite cannot sit on a log axis and are left out. As PNG bytes (1100 × 700, and its caption line).
pub fn plot(p: &Pareto, title: &str) -> Result<Vec<u8>> {
    let name = format!("{title} Pareto plot");
    let shown: Vec<&Point> = p.points.iter().filter(|q| plottable(q)).collect();
    if shown.is_empty() {
        return Err(ReportError::Plot {
            path: name,
            message: "no model has a positive, finite image RMS".into(),
        });
    }
    let mut ticks: Vec<usize> = shown.iter().map(|q| q.cost.taps).collect();
    ticks.sort_unstable();
    ticks.dedup();
    let (e_lo, e_hi) = shown.iter().fold((f64::INFINITY, 0.0f64), |(a, b), q| {
        (a.min(q.mean_image_rms), b.max(q.mean_image_rms))
    });
    // Room for the labels right of the rightmost points and above the highest one.
    let x_range = (ticks[0].max(1) as f64 / 1.5)..(ticks[ticks.len() - 1] as f64 * 1.8);
    let caption = format!(
        "{title}: GPU cost against image error (T = {} taps per 1D pass)",
        p.taps_per_pass
    );
    let how = "Lower left is better: each point a model at its cost; the line joins those that \
               no other beats on both.";
    png_of((1100, 700), &name, how, |root, path| {
        let key_points = ticks.iter().map(|&t| t as f64).collect();
        let x = x_range.clone().log_scale().with_key_points(key_points);
        let y = (e_lo / 2.0..e_hi * 3.0).log_scale();
        let mut ch = FRAME.chart(root, path, &caption, x, y)?;
        let taps = "texture taps per pixel [taps/pixel] (2R·T separable, T² dense), log scale";
        let error = "mean image RMS over signals and channels [-], log scale";
        axes(
            &mut ch,
            path,
            (taps, Ticks::Fixed(0)),
            (error, Ticks::Exp(0)),
        )?;
        let stairs = front_stairs(p, x_range.end);
        Mark::Line(GREY.stroke_width(2)).labelled(&mut ch, path, stairs, "Pareto front")?;
        draw_points(&mut ch, path, p, &shown)?;
        draw_labels(root, path, &ch, &shown)?;
        legend(&mut ch, path, SeriesLabelPosition::UpperRight)
    })
}

/// The front as a staircase: the error each number of taps buys, held until the next front
/// member, continued to `x_end`.
fn front_stairs(p: &Pareto, x_end: f64) -> Vec<(f64, f64)> {
    let mut stairs: Vec<(f64, f64)> = Vec::new();
    for q in p.front.iter().filter(|q| plottable(q)) {
        if let Some(&(_, e)) = stairs.last() {
            stairs.push((q.cost.taps as f64, e));
        }
        stairs.push(at(q));
    }
    if let Some(&(_, e)) = stairs.last() {
        stairs.push((x_end, e));
    }
    stairs
}

/// The `shown` points in their family's colour, filled where on the front: circles per family
/// (one legend entry each), squares for dense 2D kernels, and a legend entry for hollow markers.
fn draw_points<'a, 'b: 'a, X, Y>(
    ch: &mut Chart<'a, 'b, X, Y>,
    path: &str,
    p: &Pareto,
    shown: &[&Point],
) -> Result<()>
where
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    let on_front = |q: &Point| p.front.iter().any(|f| f.model == q.model);
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
            .in_plot(path)?
            .label(family.name())
            .legend(move |(x, y)| Circle::new((x + 10, y), 5, color.filled()));
    }
    if shown.iter().any(|q| q.cost.dense) {
        let dense = shown.iter().filter(|q| q.cost.dense);
        ch.draw_series(
            dense.map(|q| EmptyElement::at(at(q)) + Rectangle::new([(-5, -5), (5, 5)], style(q))),
        )
        .in_plot(path)?
        .label("dense 2D kernel (square)")
        .legend(move |(x, y)| {
            Rectangle::new([(x + 5, y - 5), (x + 15, y + 5)], GREY.stroke_width(2))
        });
    }
    if shown.iter().any(|q| !on_front(q)) {
        ch.draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
            .in_plot(path)?
            .label("not on the front (hollow)")
            .legend(move |(x, y)| Circle::new((x + 10, y), 5, GREY.stroke_width(2)));
    }
    Ok(())
}

/// Every shown point's label above right of it, clear of the front's horizontal steps. Where
/// points of one cost crowd, labels are stacked upwards from the lowest point, each at least a
/// line above the one below it, and tied to a point they left by a thin line.
fn draw_labels<X, Y>(
    root: &Area<'_>,
    path: &str,
    ch: &Chart<'_, '_, X, Y>,
    shown: &[&Point],
) -> Result<()>
where
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
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
            .in_plot(path)?;
        }
        root.draw(&Text::new(
            q.label.clone(),
            (x + 10, bottom - LABEL_PITCH),
            ("sans-serif", LABEL_FONT).into_font().color(&color),
        ))
        .in_plot(path)?;
    }
    Ok(())
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
        let caption = crate::plot::CAPTION_PX;
        assert_eq!((info.width, info.height), (1100, 700 + caption));
        let nothing = vec![point(svd(1), 1, 0.0)];
        assert!(plot(&Pareto::new(nothing, 17), "test").is_err());
    }
}
