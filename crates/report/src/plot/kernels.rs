//! Kernel figures: slices of the fitted models against the 2D ground truth (thesis Fig. 6.2) and
//! the ground truth's singular values (Fig. 5.1).

use plotters::prelude::*;

use fit::KernelModel;
use fit::evaluate::Evaluation;

use super::chart::{Frame, Mark, Ticks, axes, legend, line_with_dots, samples};
use super::{Area, CHANNEL_COLORS, InPlot, channel_label, err, model_color, png_of, titled};
use crate::error::Result;
use mc::CHANNELS;

/// Slices along the main axis (top row) and the diagonal (bottom row) of `models` against the
/// ground truth (dots), per channel, zoomed to where the kernel lives, each with an inset of the
/// whole tail on a logarithmic axis, and a caption saying how to read them. Every model must
/// have been evaluated (an error names the one that was not). As PNG bytes.
pub fn slices(ev: &Evaluation, models: &[KernelModel], title: &str) -> Result<Vec<u8>> {
    png_of(
        (1500, 800),
        &format!("{title} slices plot"),
        "Dots: the exact 2D kernel; lines: the separable models. Each panel is zoomed to where the \
         kernel lives; its inset shows the whole tail on a log axis.",
        |root, path| {
            let heading = format!(
                "{title}: kernel slices against the 2D ground truth (normalized to Σ = 1 per channel)"
            );
            let cells = titled(root, path, &heading)?.split_evenly((2, 3));
            for (idx, cell) in cells.iter().enumerate() {
                draw_slice(cell, path, ev, models, idx / 3 == 1, idx % 3)?;
            }
            Ok(())
        },
    )
}

/// One slice of channel `c`: along the main axis A(x, 0), or the `diagonal` A(x, x), 3× as far
/// as the ground truth takes to fall to 5 % of its peak (at least 15 samples); an inset shows 4× as far as it
/// takes to fall to 1 %, on a log axis down to 10⁻⁴ of the peak; the legend on the first.
fn draw_slice(
    cell: &Area<'_>,
    path: &str,
    ev: &Evaluation,
    models: &[KernelModel],
    diagonal: bool,
    c: usize,
) -> Result<()> {
    let (truth, step, along) = if diagonal {
        let step = ev.h * std::f64::consts::SQRT_2;
        (&ev.truth_diagonal[c], step, "diagonal A(x, x)")
    } else {
        (&ev.truth_axis[c], ev.h, "main axis A(x, 0)")
    };
    let fall = |share: f64| {
        truth
            .iter()
            .position(|&v| v < share * truth[0])
            .unwrap_or(truth.len())
    };
    let n = (3 * fall(0.05)).clamp(15.min(truth.len()), truth.len());
    let tail = (4 * fall(0.01)).clamp(10, truth.len());
    let mut rows = Vec::new();
    for &model in models {
        let r = ev
            .row(model, c)
            .ok_or_else(|| err(path, format!("{model} was not evaluated")))?;
        rows.push((if diagonal { &r.diagonal } else { &r.axis }, r.title()));
    }
    let peak = rows
        .iter()
        .map(|(s, _)| s[..n].iter().fold(0.0f64, |a, &b| a.max(b)));
    let max = peak.fold(truth[0], f64::max).max(1e-300) * 1.1;
    let caption = format!("channel {}: {along}", CHANNELS[c]);
    let mut ch = Frame::CELL.chart(cell, path, &caption, 0.0..n as f64 * step, 0.0..max)?;
    let x = ("distance from the centre [cm]", Ticks::Auto);
    axes(&mut ch, path, x, ("weight per sample [-]", Ticks::Exp(1)))?;
    let dots = samples(&truth[..n], step).step_by((n / 40).max(1));
    Mark::Dots(BLACK, 2, 3).labelled(&mut ch, path, dots, "2D ground truth")?;
    for (m, (s, name)) in rows.iter().enumerate() {
        Mark::line(model_color(m)).labelled(&mut ch, path, samples(&s[..n], step), name.clone())?;
    }
    if !diagonal && c == 0 {
        legend(&mut ch, path, SeriesLabelPosition::LowerRight)?;
    }
    // The inset: the whole tail, log weights.
    let (w, h) = cell.dim_in_pixel();
    let inset = cell
        .clone()
        .shrink((w * 11 / 20, h / 7), (w * 2 / 5, h * 2 / 5));
    inset.fill(&WHITE.mix(0.9)).in_plot(path)?;
    let floor = truth[0].max(1e-300) * 1e-4;
    let y = (floor..max).log_scale();
    let mut tail_chart = ChartBuilder::on(&inset)
        .margin(4)
        .x_label_area_size(18)
        .y_label_area_size(44)
        .build_cartesian_2d(0.0..tail as f64 * step, y)
        .in_plot(path)?;
    tail_chart
        .configure_mesh()
        .disable_x_mesh()
        .disable_y_mesh()
        .x_labels(3)
        .y_labels(3)
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .label_style(("sans-serif", 11))
        .draw()
        .in_plot(path)?;
    let clamped = |s: &[f64]| -> Vec<(f64, f64)> {
        samples(&s[..tail], step)
            .map(|(x, v)| (x, v.max(floor)))
            .collect()
    };
    let dots = clamped(truth).into_iter().step_by((tail / 30).max(1));
    Mark::Dots(BLACK, 1, 1).draw(&mut tail_chart, path, dots)?;
    for (m, (s, _)) in rows.iter().enumerate() {
        Mark::line(model_color(m)).draw(&mut tail_chart, path, clamped(s))?;
    }
    Ok(())
}

/// The first 30 singular values per channel, log scale (thesis Fig. 5.1), as PNG bytes.
pub fn singular_values(ev: &Evaluation, title: &str) -> Result<Vec<u8>> {
    png_of(
        (700, 480),
        &format!("{title} singular values plot"),
        "The faster they fall, the closer a few separable passes come: rank N keeps the first N.",
        |root, path| draw_singular_values(root, path, ev, title),
    )
}

fn draw_singular_values(root: &Area<'_>, path: &str, ev: &Evaluation, title: &str) -> Result<()> {
    let all = ev.singular_values.iter().flatten().filter(|&&x| x > 0.0);
    let (lo, hi) = all.fold((f64::INFINITY, 0.0f64), |(a, b), &x| (a.min(x), b.max(x)));
    let caption = format!("{title}: singular values of the 2D ground truth (Σ = 1)");
    let y = (lo.max(hi * 1e-16)..hi * 2.0).log_scale();
    let mut ch = Frame::PAGE.chart(root, path, &caption, 0.5..30.5, y)?;
    axes(
        &mut ch,
        path,
        ("index i (rank)", Ticks::Auto),
        ("|σᵢ| [-]", Ticks::Exp(0)),
    )?;
    for c in 0..3 {
        let pts: Vec<(f64, f64)> = ev.singular_values[c]
            .iter()
            .enumerate()
            .filter(|(_, v)| **v > 0.0)
            .map(|(i, &v)| ((i + 1) as f64, v))
            .collect();
        line_with_dots(&mut ch, path, &pts, CHANNEL_COLORS[c], channel_label(c))?;
    }
    legend(&mut ch, path, SeriesLabelPosition::MiddleRight)
}
