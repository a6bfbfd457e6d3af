//! The thesis's chapter-5 model studies as figures: guided optimization imitating
//! pre-integration (Fig. 5.15, [`imitation`]) and the manual model's w sweep (Fig. 5.17,
//! [`w_sweep`]).

use plotters::prelude::*;

use fit::KernelModel;
use fit::imitation::Imitation;

use super::chart::{Frame, Mark, Ticks, axes, legend, line_with_dots, samples};
use super::{Area, CHANNEL_COLORS, channel_label, channel_row, model_color, png_of};
use crate::error::Result;
use mc::CHANNELS;

/// The models [`imitation`] draws as curves: the imitation, Fig. 5.15c–d, the thesis's default,
/// SVD rank-1.
const IMITATION_DRAWN: [KernelModel; 5] = [
    fit::imitation::IMITATION,
    KernelModel::Guided { k: 0.0, b: 50.0 },
    KernelModel::Guided { k: 2.0, b: 50.0 },
    KernelModel::Guided { k: 1.0, b: 0.0 },
    KernelModel::Svd {
        rank: 1,
        renormalize: false,
    },
];

/// Thesis Fig. 5.15 as a plot: top, per channel, the 1D function a(x) (log scale down to 10⁻⁴
/// of the peak) of pre-integration (dots),
/// of guided optimization with k = 1.55, b = 50, and of the other compared models; bottom, each
/// model's image-space distance to pre-integration on the shaded test signal (log scale, one
/// marker per channel). As PNG bytes.
pub fn imitation(im: &Imitation, title: &str) -> Result<Vec<u8>> {
    png_of(
        (1500, 960),
        &format!("{title} guided-vs-preint plot"),
        "Top: how closely each model's 1D function follows pre-integration's (dots); bottom: the \
         image distance between them, lower is closer.",
        |root, path| {
            let heading = format!(
                "{title}: guided optimization with k = 1.55, b = 50 imitates pre-integration (thesis Fig. 5.15)"
            );
            let (cells, bottom) = channel_row(root, path, &heading, 520)?;
            for (c, cell) in cells.iter().enumerate() {
                draw_imitation_a(cell, path, im, c)?;
            }
            draw_image_distances(&bottom, path, im)
        },
    )
}

/// a(x) of channel `c` per sample [-], log scale down to 10⁻⁴ of pre-integration's peak (the
/// centre and the falloff at once): pre-integration as dots, [`IMITATION_DRAWN`] as lines (the
/// imitation thick, the other guided ones with b > 0 dashed); the legend on the first channel.
fn draw_imitation_a(cell: &Area<'_>, path: &str, im: &Imitation, c: usize) -> Result<()> {
    let truth = &im.preint[c];
    let floor = 1e-4 * truth[0];
    let n = truth
        .iter()
        .position(|&v| v < floor)
        .unwrap_or(truth.len())
        .max(10)
        .min(truth.len());
    let max = IMITATION_DRAWN
        .iter()
        .filter_map(|&m| im.candidate(m))
        .map(|m| m.a[c][0])
        .fold(truth[0], f64::max)
        * 1.5;
    let caption = format!("channel {}: 1D function a(x) of A = a(x)a(y)", CHANNELS[c]);
    let y = (floor.max(1e-300)..max.max(2e-300)).log_scale();
    let mut ch = Frame::CELL.chart(cell, path, &caption, 0.0..n as f64 * im.h, y)?;
    let x = ("distance from the centre x [cm]", Ticks::Auto);
    axes(&mut ch, path, x, ("a(x) per sample [-]", Ticks::Exp(0)))?;
    let dots = samples(&truth[..n], im.h).step_by((n / 60).max(1));
    Mark::Dots(BLACK, 3, 3).labelled(&mut ch, path, dots, "pre-integration (eq. 5.18)")?;
    for (m, &model) in IMITATION_DRAWN.iter().enumerate() {
        let Some(cand) = im.candidate(model) else {
            continue;
        };
        let style = model_color(m).stroke_width(if m == 0 { 3 } else { 2 });
        let mark = if matches!(model, KernelModel::Guided { b, .. } if b > 0.0) && m > 0 {
            Mark::Dashed(style, 8, 5)
        } else {
            Mark::Line(style)
        };
        // Non-positive values (a fit's zero floor) have no place on the log axis.
        let line = samples(&cand.a[c][..n], im.h).map(|(x, v)| (x, v.max(floor * 0.5)));
        mark.labelled(&mut ch, path, line, model.title())?;
    }
    if c == 0 {
        legend(&mut ch, path, SeriesLabelPosition::UpperRight)?;
    }
    Ok(())
}

/// Each model's image-space distance to pre-integration on the shaded test signal [-], log
/// scale, one marker per channel side by side.
fn draw_image_distances(area: &Area<'_>, path: &str, im: &Imitation) -> Result<()> {
    let shown = |v: f64| v > 0.0 && v.is_finite();
    let values = im.candidates.iter().flat_map(|m| m.image_distance);
    let (lo, hi) = values
        .filter(|&v| shown(v))
        .fold((f64::INFINITY, 0.0f64), |(a, b), v| (a.min(v), b.max(v)));
    let (lo, hi) = if lo <= hi { (lo, hi) } else { (1e-3, 1.0) };
    let count = im.candidates.len();
    let names: Vec<String> = im.candidates.iter().map(|m| m.model.title()).collect();
    let frame = Frame {
        x_area: 44,
        ..Frame::PANEL
    };
    let caption = "shaded test signal: ‖E∗A − E∗A_p‖ / ‖E∗A_p‖, distance of each model's image from pre-integration's (lower = closer)";
    let x = -0.5..count as f64 - 0.5;
    let mut ch = frame.chart(area, path, caption, x, (lo / 2.0..hi * 2.0).log_scale())?;
    let y = ("relative image distance [-]", Ticks::Exp(0));
    axes(&mut ch, path, ("model", Ticks::Names(&names)), y)?;
    for c in 0..3 {
        let offset = (c as f64 - 1.0) * 0.12;
        let dots = im.candidates.iter().enumerate().filter_map(|(i, m)| {
            let v = m.image_distance[c];
            shown(v).then_some((i as f64 + offset, v))
        });
        Mark::Dots(CHANNEL_COLORS[c], 6, 5).labelled(&mut ch, path, dots, channel_label(c))?;
    }
    legend(&mut ch, path, SeriesLabelPosition::UpperRight)
}

/// Thesis Fig. 5.17 as a plot: top, per channel, the light across a shadow edge for the shown w
/// against the ground truth (dots); bottom left, the image-space error against w per channel;
/// bottom right, the edge's 10–90 % width relative to the ground truth's against w. The w of
/// `sweep.params` (Table A.1's) is marked. As PNG bytes.
pub fn w_sweep(sweep: &fit::WSweep, title: &str) -> Result<Vec<u8>> {
    png_of(
        (1500, 960),
        &format!("{title} manual w sweep plot"),
        "Top: light across a shadow edge for several w against the truth (dots); bottom: the \
         image error and the edge's width against w, Table A.1's w marked.",
        |root, path| {
            let heading = format!(
                "{title}: the manual model's w moves it from far (w = 0) to near scattering (w = 1) (thesis Fig. 5.17)"
            );
            let (cells, bottom) = channel_row(root, path, &heading, 480)?;
            for (c, cell) in cells.iter().enumerate() {
                draw_edges(cell, path, sweep, c)?;
            }
            let (left, right) = bottom.split_horizontally(750);
            draw_against_w(&left, path, sweep, &ERROR_AGAINST_W, &sweep.image_rms)?;
            let ratio: Vec<[f64; 3]> = sweep
                .edge_width
                .iter()
                .map(|w| [0, 1, 2].map(|c| w[c] / sweep.truth_edge_width[c]))
                .collect();
            draw_against_w(&right, path, sweep, &WIDTH_AGAINST_W, &ratio)
        },
    )
}

/// Light across a shadow edge in channel `c`, ±1.5 edge widths of the ground truth (at least 5
/// samples) around it: the ground truth as dots, each shown w as a line; the legend on the first
/// channel, lower left (lit, M ≈ 1, on the left and dark on the right leave it empty).
fn draw_edges(cell: &Area<'_>, path: &str, s: &fit::WSweep, c: usize) -> Result<()> {
    let reference_w = s.params[0].w;
    let truth = &s.truth_edge[c];
    let n = truth.len() / 2;
    let reach = ((1.5 * s.truth_edge_width[c] / s.h).ceil() as usize).clamp(5, n.max(5));
    let reach = reach.min(n);
    let x = |i: usize| (i as f64 - n as f64) * s.h;
    let span = n - reach..=n + reach;
    let frame = Frame {
        y_area: 60,
        ..Frame::CELL
    };
    let caption = format!("channel {}: light across a shadow edge", CHANNELS[c]);
    let mut ch = frame.chart(cell, path, &caption, x(n - reach)..x(n + reach), 0.0..1.05)?;
    let across = ("x [cm] (lit for x < 0, shadow beyond)", Ticks::Auto);
    axes(
        &mut ch,
        path,
        across,
        ("exitance / irradiance M(x) [-]", Ticks::Auto),
    )?;
    let step = (2 * reach / 50).max(1);
    let dots = span.clone().step_by(step).map(|i| (x(i), truth[i]));
    let name = "2D ground truth (= pre-integration, eq. 5.15)";
    Mark::Dots(BLACK, 3, 3).labelled(&mut ch, path, dots, name)?;
    for (k, (w, edges)) in s.edges.iter().enumerate() {
        let what = if (*w - reference_w).abs() < 1e-9 {
            "Table A.1"
        } else if *w < reference_w {
            "far"
        } else {
            "near"
        };
        let line = span.clone().map(|i| (x(i), edges[c][i]));
        let label = format!("manual, w = {w} ({what})");
        Mark::line(model_color(k)).labelled(&mut ch, path, line, label)?;
    }
    if c == 0 {
        legend(&mut ch, path, SeriesLabelPosition::LowerLeft)?;
    }
    Ok(())
}

/// A quantity [`w_sweep`] draws against w: caption, y axis and tick format, and whether it is
/// relative to the ground truth's (then y reaches 1 at least and the 1 is drawn dashed).
struct AgainstW {
    caption: &'static str,
    y: (&'static str, Ticks<'static>),
    relative: bool,
}

const ERROR_AGAINST_W: AgainstW = AgainstW {
    caption: "image-space error against the ground truth (five test signals)",
    y: ("RMS error [irradiance units]", Ticks::Exp(1)),
    relative: false,
};

const WIDTH_AGAINST_W: AgainstW = AgainstW {
    caption: "edge 10–90 % width / the ground truth's (1 = as wide)",
    y: ("width ratio [-]", Ticks::Fixed(2)),
    relative: true,
};

/// `values` per swept w and channel as `what` says, Table A.1's w marked by a dashed grey line.
fn draw_against_w(
    area: &Area<'_>,
    path: &str,
    s: &fit::WSweep,
    what: &AgainstW,
    values: &[[f64; 3]],
) -> Result<()> {
    let reference_w = s.params[0].w;
    let all = values.iter().flatten().filter(|v| v.is_finite());
    let least = if what.relative { 1.0f64 } else { 0.0 };
    let hi = all.fold(least, |a, &v| a.max(v)) * 1.1;
    let mut ch = Frame::PANEL.chart(area, path, what.caption, 0.0..1.0, 0.0..hi.max(1e-300))?;
    let w = ("w (weight of the near Gaussian) [-]", Ticks::Auto);
    axes(&mut ch, path, w, what.y)?;
    for c in 0..3 {
        let pts: Vec<(f64, f64)> = s.w.iter().zip(values).map(|(&w, v)| (w, v[c])).collect();
        line_with_dots(&mut ch, path, &pts, CHANNEL_COLORS[c], channel_label(c))?;
    }
    let grey = Mark::Dashed(RGBColor(120, 120, 120).stroke_width(2), 6, 4);
    let marker = [(reference_w, 0.0), (reference_w, hi)];
    grey.labelled(
        &mut ch,
        path,
        marker,
        format!("Table A.1: w = {reference_w}"),
    )?;
    if what.relative {
        let one = Mark::Dashed(BLACK.stroke_width(1), 10, 4);
        one.labelled(
            &mut ch,
            path,
            [(0.0, 1.0), (1.0, 1.0)],
            "ground truth's width",
        )?;
    }
    legend(&mut ch, path, SeriesLabelPosition::UpperRight)
}
