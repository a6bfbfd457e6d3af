//! Comparison plots as PNG (plotters, bitmap backend, an embedded DejaVu Sans so output does not
//! depend on system fonts): profiles (thesis Fig. 6.1), kernel slices against the ground truth
//! (Fig. 6.2), singular-value decay (Fig. 5.1), convolution/difference sheets (Fig. 6.3–6.10), and
//! total diffuse reflectance against the incidence angle ([`incidence`], returned as PNG bytes).

use std::path::Path;
use std::sync::Once;

use plotters::prelude::*;
use plotters::style::{FontStyle, register_font};

use crate::error::{FitError, Result};
use crate::evaluate::Evaluation;
use crate::profile::Profile;
use crate::signals::Signal;

static FONT: Once = Once::new();
const CHANNEL_COLORS: [RGBColor; 3] = [
    RGBColor(220, 40, 40),
    RGBColor(30, 160, 60),
    RGBColor(40, 80, 220),
];
const MODEL_COLORS: [RGBColor; 6] = [
    RGBColor(0, 0, 0),
    RGBColor(230, 120, 0),
    RGBColor(0, 150, 200),
    RGBColor(160, 0, 160),
    RGBColor(120, 120, 0),
    RGBColor(0, 160, 100),
];

fn font() {
    FONT.call_once(|| {
        let _ = register_font(
            "sans-serif",
            FontStyle::Normal,
            include_bytes!("../../../assets/DejaVuSans.ttf"),
        );
    });
}

fn err(path: &Path, e: impl std::fmt::Display) -> FitError {
    FitError::Plot {
        path: path.display().to_string(),
        message: e.to_string(),
    }
}

/// Rd(r) per channel: linear near 0 (left) and logarithmic over the whole range (right).
pub fn profile(p: &Profile, title: &str, path: &Path) -> Result<()> {
    font();
    let root = BitMapBackend::new(path, (1200, 480)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(path, e))?;
    let (left, right) = root.split_horizontally(600);
    let r_end = *p.r.last().unwrap_or(&1.0);
    let near = r_end / 8.0;
    let max =
        p.rd.iter()
            .flat_map(|c| c.iter())
            .fold(0.0f64, |a, &b| a.max(b));
    {
        let mut ch = ChartBuilder::on(&left)
            .caption(format!("{title}: Rd(r) near 0"), ("sans-serif", 18))
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(70)
            .build_cartesian_2d(0.0..near, 0.0..max * 1.05)
            .map_err(|e| err(path, e))?;
        ch.configure_mesh()
            .x_desc("r [cm]")
            .y_desc("Rd [1/cm²]")
            .draw()
            .map_err(|e| err(path, e))?;
        for c in 0..3 {
            ch.draw_series(LineSeries::new(
                p.r.iter()
                    .zip(&p.rd[c])
                    .filter(|(r, _)| **r <= near)
                    .map(|(&r, &v)| (r, v)),
                CHANNEL_COLORS[c].stroke_width(2),
            ))
            .map_err(|e| err(path, e))?;
        }
    }
    let min_pos =
        p.rd.iter()
            .flat_map(|c| c.iter())
            .filter(|&&v| v > 0.0)
            .fold(f64::INFINITY, |a, &b| a.min(b));
    let mut ch = ChartBuilder::on(&right)
        .caption(format!("{title}: Rd(r), log scale"), ("sans-serif", 18))
        .margin(10)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(
            0.0..r_end,
            (min_pos.max(max * 1e-12)..max * 2.0).log_scale(),
        )
        .map_err(|e| err(path, e))?;
    ch.configure_mesh()
        .x_desc("r [cm]")
        .y_desc("Rd [1/cm²]")
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .draw()
        .map_err(|e| err(path, e))?;
    for c in 0..3 {
        ch.draw_series(LineSeries::new(
            p.r.iter()
                .zip(&p.rd[c])
                .filter(|(_, v)| **v > 0.0)
                .map(|(&r, &v)| (r, v)),
            CHANNEL_COLORS[c].stroke_width(2),
        ))
        .map_err(|e| err(path, e))?;
    }
    root.present().map_err(|e| err(path, e))
}

/// Slices along the main axis (top row) and the diagonal (bottom row) of the models named in
/// `labels` against the ground truth (dotted), per channel, out to `extent` of the kernel.
pub fn slices(ev: &Evaluation, labels: &[&str], title: &str, path: &Path) -> Result<()> {
    font();
    let root = BitMapBackend::new(path, (1500, 800)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(path, e))?;
    let cells = root.split_evenly((2, 3));
    for (idx, cell) in cells.iter().enumerate() {
        let (row, c) = (idx / 3, idx % 3);
        let truth = if row == 0 {
            &ev.truth_axis[c]
        } else {
            &ev.truth_diagonal[c]
        };
        // Zoom on the central part: 4× the distance at which the ground truth falls to 1% of its peak.
        let fall = truth
            .iter()
            .position(|&v| v < 0.01 * truth[0])
            .unwrap_or(truth.len());
        let n = (4 * fall).clamp(10, truth.len());
        let step = if row == 0 {
            ev.h
        } else {
            ev.h * std::f64::consts::SQRT_2
        };
        let max = truth[0].max(1e-300) * 1.15;
        let mut ch = ChartBuilder::on(cell)
            .caption(
                format!(
                    "{title} {} {}",
                    ["R", "G", "B"][c],
                    if row == 0 { "axis" } else { "diagonal" }
                ),
                ("sans-serif", 16),
            )
            .margin(8)
            .x_label_area_size(30)
            .y_label_area_size(60)
            .build_cartesian_2d(0.0..n as f64 * step, 0.0..max)
            .map_err(|e| err(path, e))?;
        ch.configure_mesh()
            .x_desc("distance [cm]")
            .draw()
            .map_err(|e| err(path, e))?;
        ch.draw_series(
            truth[..n]
                .iter()
                .enumerate()
                .step_by((n / 60).max(1))
                .map(|(i, &v)| Circle::new((i as f64 * step, v), 2, BLACK.filled())),
        )
        .map_err(|e| err(path, e))?
        .label("ground truth")
        .legend(|(x, y)| Circle::new((x + 10, y), 3, BLACK.filled()));
        for (m, label) in labels.iter().enumerate() {
            if let Some(r) = ev
                .rows
                .iter()
                .find(|r| r.channel == c && r.label().starts_with(label))
            {
                let s = if row == 0 { &r.axis } else { &r.diagonal };
                let color = MODEL_COLORS[(m + 1) % MODEL_COLORS.len()];
                ch.draw_series(LineSeries::new(
                    s[..n]
                        .iter()
                        .enumerate()
                        .map(|(i, &v)| (i as f64 * step, v)),
                    color.stroke_width(2),
                ))
                .map_err(|e| err(path, e))?
                .label(label.to_string())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                });
            }
        }
        if idx == 0 {
            ch.configure_series_labels()
                .border_style(BLACK)
                .background_style(WHITE.mix(0.8))
                .draw()
                .map_err(|e| err(path, e))?;
        }
    }
    root.present().map_err(|e| err(path, e))
}

/// The first 30 singular values per channel, log scale (thesis Fig. 5.1).
pub fn singular_values(ev: &Evaluation, title: &str, path: &Path) -> Result<()> {
    font();
    let root = BitMapBackend::new(path, (700, 480)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(path, e))?;
    let all = ev
        .singular_values
        .iter()
        .flat_map(|v| v.iter())
        .filter(|&&x| x > 0.0);
    let (lo, hi) = all.fold((f64::INFINITY, 0.0f64), |(a, b), &x| (a.min(x), b.max(x)));
    let mut ch = ChartBuilder::on(&root)
        .caption(format!("{title}: singular values"), ("sans-serif", 18))
        .margin(10)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(0.5..30.5, (lo.max(hi * 1e-16)..hi * 2.0).log_scale())
        .map_err(|e| err(path, e))?;
    ch.configure_mesh()
        .x_desc("index")
        .y_desc("σ")
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .draw()
        .map_err(|e| err(path, e))?;
    for c in 0..3 {
        let pts: Vec<(f64, f64)> = ev.singular_values[c]
            .iter()
            .enumerate()
            .filter(|(_, v)| **v > 0.0)
            .map(|(i, &v)| ((i + 1) as f64, v))
            .collect();
        ch.draw_series(LineSeries::new(
            pts.clone(),
            CHANNEL_COLORS[c].stroke_width(2),
        ))
        .map_err(|e| err(path, e))?;
        ch.draw_series(
            pts.into_iter()
                .map(|p| Circle::new(p, 3, CHANNEL_COLORS[c].filled())),
        )
        .map_err(|e| err(path, e))?;
    }
    root.present().map_err(|e| err(path, e))
}

/// A sheet for one test signal: the input and ground-truth convolution (RGB) on the first row;
/// each rank-1 model's convolution (second row) and its absolute difference to the ground truth,
/// scaled ×`gain` (third row), in the order svd1, preint, guided k=1, manual.
pub fn convolutions(ev: &Evaluation, signal: Signal, gain: f64, path: &Path) -> Result<()> {
    let size = ev.images[0].size;
    let labels: Vec<String> = ev
        .rank1
        .iter()
        .filter(|(_, c, _)| *c == 0)
        .map(|(l, _, _)| l.clone())
        .collect();
    let cols = labels.len().max(2);
    let root = BitMapBackend::new(
        path,
        ((cols * (size + 10)) as u32, (3 * (size + 10)) as u32),
    )
    .into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(path, e))?;
    let put = |x0: usize, y0: usize, rgb: &dyn Fn(usize, usize) -> [f64; 3]| -> Result<()> {
        for y in 0..size {
            for x in 0..size {
                let v = rgb(x, y).map(|c| (c.clamp(0.0, 1.0).powf(1.0 / 2.2) * 255.0) as u8);
                root.draw_pixel(
                    ((x0 + x) as i32, (y0 + y) as i32),
                    &RGBColor(v[0], v[1], v[2]),
                )
                .map_err(|e| err(path, e))?;
            }
        }
        Ok(())
    };
    let per_channel: Vec<_> = (0..3)
        .map(|c| {
            ev.images[c].images(
                signal,
                &ev.rank1
                    .iter()
                    .find(|(_, ch, _)| *ch == c)
                    .expect("a model per channel")
                    .2,
            )
        })
        .collect();
    put(0, 0, &|x, y| [0, 1, 2].map(|c| per_channel[c].0.at(x, y)))?;
    put(size + 10, 0, &|x, y| {
        [0, 1, 2].map(|c| per_channel[c].1.at(x, y))
    })?;
    for (i, label) in labels.iter().enumerate() {
        let imgs: Vec<_> = (0..3)
            .map(|c| {
                let model = &ev
                    .rank1
                    .iter()
                    .find(|(l, ch, _)| l == label && *ch == c)
                    .expect("each model on each channel")
                    .2;
                ev.images[c].images(signal, model)
            })
            .collect();
        put(i * (size + 10), size + 10, &|x, y| {
            [0, 1, 2].map(|c| imgs[c].2.at(x, y))
        })?;
        put(i * (size + 10), 2 * (size + 10), &|x, y| {
            [0, 1, 2].map(|c| gain * (imgs[c].2.at(x, y) - imgs[c].1.at(x, y)).abs())
        })?;
    }
    root.present().map_err(|e| err(path, e))
}

/// Analytic profiles against MC, per channel: r·Rd(r) on a log scale (top) and the relative error
/// model/MC − 1 (bottom), against r in transport mean free paths `mfp` [cm] of each channel.
pub fn profile_comparison(
    mc: &Profile,
    models: &[(&str, &Profile)],
    mfp: [f64; 3],
    title: &str,
    path: &Path,
) -> Result<()> {
    font();
    let root = BitMapBackend::new(path, (1500, 850)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(path, e))?;
    let (top, bottom) = root.split_vertically(480);
    let x_max = 10.0;
    for (c, (up, down)) in top
        .split_evenly((1, 3))
        .iter()
        .zip(bottom.split_evenly((1, 3)).iter())
        .enumerate()
    {
        let pts = |p: &Profile| -> Vec<(f64, f64)> {
            p.r.iter()
                .zip(&p.rd[c])
                .map(|(&r, &v)| (r / mfp[c], r * v))
                .filter(|&(x, v)| x <= x_max && v > 0.0)
                .collect()
        };
        let mc_pts = pts(mc);
        let hi = mc_pts.iter().fold(0.0f64, |a, p| a.max(p.1));
        let lo = mc_pts.iter().fold(f64::INFINITY, |a, p| a.min(p.1));
        let mut ch = ChartBuilder::on(up)
            .caption(
                format!("{title} {}: r·Rd(r)", ["R", "G", "B"][c]),
                ("sans-serif", 16),
            )
            .margin(8)
            .x_label_area_size(30)
            .y_label_area_size(60)
            .build_cartesian_2d(
                0.0..x_max,
                (lo.max(hi * 1e-8).max(1e-300)..hi * 3.0).log_scale(),
            )
            .map_err(|e| err(path, e))?;
        ch.configure_mesh()
            .x_desc("r [transport MFP]")
            .y_desc("r·Rd [1/cm]")
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .draw()
            .map_err(|e| err(path, e))?;
        ch.draw_series(
            mc_pts
                .iter()
                .step_by((mc_pts.len() / 80).max(1))
                .map(|&p| Circle::new(p, 2, BLACK.filled())),
        )
        .map_err(|e| err(path, e))?
        .label("Monte Carlo")
        .legend(|(x, y)| Circle::new((x + 10, y), 3, BLACK.filled()));
        for (m, (name, p)) in models.iter().enumerate() {
            let color = MODEL_COLORS[(m + 1) % MODEL_COLORS.len()];
            ch.draw_series(LineSeries::new(
                pts(p).into_iter().filter(|&(_, v)| v >= lo.max(hi * 1e-8)),
                color.stroke_width(2),
            ))
            .map_err(|e| err(path, e))?
            .label(name.to_string())
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
            });
        }
        if c == 0 {
            ch.configure_series_labels()
                .border_style(BLACK)
                .background_style(WHITE.mix(0.8))
                .draw()
                .map_err(|e| err(path, e))?;
        }
        let mut ch = ChartBuilder::on(down)
            .caption("model / MC − 1", ("sans-serif", 14))
            .margin(8)
            .x_label_area_size(30)
            .y_label_area_size(60)
            .build_cartesian_2d(0.0..x_max, -1.0..1.0)
            .map_err(|e| err(path, e))?;
        ch.configure_mesh()
            .x_desc("r [transport MFP]")
            .draw()
            .map_err(|e| err(path, e))?;
        ch.draw_series(LineSeries::new([(0.0, 0.0), (x_max, 0.0)], BLACK))
            .map_err(|e| err(path, e))?;
        for (m, (_, p)) in models.iter().enumerate() {
            let color = MODEL_COLORS[(m + 1) % MODEL_COLORS.len()];
            ch.draw_series(LineSeries::new(
                (0..mc.len().min(p.len()))
                    .filter(|&i| mc.rd[c][i] > 0.0 && mc.se[c][i] < 0.05 * mc.rd[c][i])
                    .map(|i| {
                        (
                            mc.r[i] / mfp[c],
                            (p.rd[c][i] / mc.rd[c][i] - 1.0).clamp(-1.0, 1.0),
                        )
                    })
                    .filter(|&(x, _)| x <= x_max),
                color.stroke_width(2),
            ))
            .map_err(|e| err(path, e))?;
        }
    }
    root.present().map_err(|e| err(path, e))
}

/// Maisch & Ropinski's Fig. 2 effect: the energy a screen-space gather collects from a beam's
/// profile, relative to the profile's total, against the pixel pitch [cm] (log-log). Point
/// sampling (thin, light) drifts with the pitch, differently per channel — a brightness and colour
/// shift when zooming; area pre-integration (thick) stays at 1. `curves[c]` holds (pitch, point, area) triples.
pub fn area_effect(curves: &[Vec<(f64, f64, f64)>; 3], title: &str, path: &Path) -> Result<()> {
    font();
    let root = BitMapBackend::new(path, (900, 560)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(path, e))?;
    let all = curves.iter().flatten();
    let (x0, x1) = all.clone().fold((f64::INFINITY, 0.0f64), |(a, b), p| {
        (a.min(p.0), b.max(p.0))
    });
    let y1 = all
        .clone()
        .fold(1.2f64, |a, p| a.max(p.1).max(p.2))
        .min(4.0);
    let y0 = all.fold(0.8f64, |a, p| a.min(p.1).min(p.2)).max(0.0);
    let mut ch = ChartBuilder::on(&root)
        .caption(
            format!("{title}: energy a pixel grid gathers / profile total"),
            ("sans-serif", 18),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
        .map_err(|e| err(path, e))?;
    ch.configure_mesh()
        .x_desc("pixel pitch [cm] (camera zooming out →)")
        .y_desc("gathered / total")
        .y_label_formatter(&|v| format!("{v:.2}"))
        .x_label_formatter(&|v| format!("{v:.0e}"))
        .draw()
        .map_err(|e| err(path, e))?;
    for c in 0..3 {
        let color = CHANNEL_COLORS[c];
        ch.draw_series(LineSeries::new(
            curves[c].iter().map(|p| (p.0, p.1)),
            color.mix(0.5).stroke_width(1),
        ))
        .map_err(|e| err(path, e))?
        .label(format!("{} point-sampled", ["R", "G", "B"][c]))
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color.mix(0.5)));
        ch.draw_series(LineSeries::new(
            curves[c].iter().map(|p| (p.0, p.2)),
            color.stroke_width(3),
        ))
        .map_err(|e| err(path, e))?
        .label(format!("{} area pre-integrated", ["R", "G", "B"][c]))
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(3)));
    }
    ch.configure_series_labels()
        .border_style(BLACK)
        .background_style(WHITE.mix(0.8))
        .draw()
        .map_err(|e| err(path, e))?;
    root.present().map_err(|e| err(path, e))
}

/// One labelled picture of a [`image_sheet`]: RGB8, row-major.
pub struct SheetCell {
    pub label: String,
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<u8>,
}

/// Pictures in a grid of `columns`, each with its label above it (comparison sheets of
/// renderings, cut-outs and difference images).
pub fn image_sheet(cells: &[SheetCell], columns: usize, path: &Path) -> Result<()> {
    font();
    let columns = columns.max(1);
    let (cw, ch) = cells
        .iter()
        .fold((1, 1), |(w, h), c| (w.max(c.width), h.max(c.height)));
    let rows = cells.len().div_ceil(columns) as u32;
    let (pad, label) = (8u32, 22u32);
    let size = (
        columns as u32 * (cw + pad) + pad,
        rows * (ch + label + pad) + pad,
    );
    let root = BitMapBackend::new(path, size).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(path, e))?;
    for (i, c) in cells.iter().enumerate() {
        let (col, row) = ((i % columns) as u32, (i / columns) as u32);
        let x = (pad + col * (cw + pad)) as i32;
        let y = (pad + row * (ch + label + pad)) as i32;
        root.draw(&Text::new(
            c.label.clone(),
            (x, y),
            ("sans-serif", 16).into_font(),
        ))
        .map_err(|e| err(path, e))?;
        let elem = BitMapElement::with_owned_buffer(
            (x, y + label as i32),
            (c.width, c.height),
            c.rgb.clone(),
        )
        .ok_or_else(|| {
            err(
                path,
                format!("cell {i}: buffer does not match {}×{}", c.width, c.height),
            )
        })?;
        root.draw(&elem).map_err(|e| err(path, e))?;
    }
    root.present().map_err(|e| err(path, e))
}

/// Total diffuse reflectance of the three channels at one incidence angle (plain data for
/// [`incidence`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IncidencePoint {
    /// Polar angle θ of the beam [degrees].
    pub theta_deg: f64,
    /// Rd per unit incident power, without Rsp, per channel (R, G, B) [-].
    pub rd: [f64; 3],
    /// Standard error of `rd` per channel [-].
    pub se: [f64; 3],
}

/// An analytic model's total Rd(θ) per channel at the measured angles, drawn beside the Monte
/// Carlo points of [`incidence`] (plain data).
#[derive(Clone, Debug, PartialEq)]
pub struct IncidenceCurve {
    /// Legend name.
    pub name: String,
    /// (θ [degrees], Rd per channel [-]).
    pub points: Vec<(f64, [f64; 3])>,
}

/// Line styles of the model curves: dash length and gap [px] (the first is dashed, the second
/// dotted, the third long-dashed).
const CURVE_DASHES: [(u32, u32); 3] = [(8, 5), (2, 4), (16, 6)];

/// Rd(θ)/Rd(0°) per channel (left) and absolute Rd(θ) (right) against the incidence angle θ
/// [degrees], with ±2 standard-error bars, as PNG bytes; `curves` (at most 3) are drawn as dashed
/// or dotted lines in the channel colours, named in a second legend. The ratio's error combines
/// both rows' standard errors (every angle is an independent run). Without a 0° point only the
/// absolute panel is drawn, and the title says so.
pub fn incidence(
    points: &[IncidencePoint],
    curves: &[IncidenceCurve],
    title: &str,
) -> Result<Vec<u8>> {
    font();
    let fail = |e: &dyn std::fmt::Display| FitError::Plot {
        path: format!("{title} incidence plot"),
        message: e.to_string(),
    };
    let mut pts = points.to_vec();
    pts.sort_by(|a, b| a.theta_deg.total_cmp(&b.theta_deg));
    let normal = pts.iter().find(|p| p.theta_deg == 0.0).copied();
    let (w, h) = (if normal.is_some() { 1200 } else { 640 }, 520u32);
    let mut rgb = vec![0u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| fail(&e))?;
        let heading = match normal {
            Some(_) => format!(
                "{title}: diffuse reflectance against incidence angle (Monte Carlo ±2 SE; dashed: models)"
            ),
            None => {
                format!("{title}: Rd against incidence angle (±2 SE); no 0° angle, so no ratio")
            }
        };
        let root = root
            .titled(&heading, ("sans-serif", 20))
            .map_err(|e| fail(&e))?;
        // One panel per series: (θ, value, 2 SE) per channel, y label, caption, y axis from 0.
        // A channel without reflectance at 0° has no ratio: its non-finite points are left out.
        let finite = |v: Vec<(f64, f64, f64)>| -> Vec<(f64, f64, f64)> {
            v.into_iter()
                .filter(|p| p.1.is_finite() && p.2.is_finite())
                .collect()
        };
        let absolute = [0, 1, 2].map(|c| {
            finite(
                pts.iter()
                    .map(|p| (p.theta_deg, p.rd[c], 2.0 * p.se[c]))
                    .collect(),
            )
        });
        let mut panels = Vec::new();
        if let Some(n) = normal {
            let ratio = [0, 1, 2].map(|c| {
                finite(
                    pts.iter()
                        .map(|p| {
                            let r = p.rd[c] / n.rd[c];
                            let rel = if p.theta_deg == 0.0 {
                                0.0
                            } else {
                                (p.se[c] / p.rd[c]).hypot(n.se[c] / n.rd[c])
                            };
                            (p.theta_deg, r, 2.0 * r * rel)
                        })
                        .collect(),
                )
            });
            // A model's ratio is to its own normal-incidence value.
            let model_ratio: Vec<[Vec<(f64, f64)>; 3]> = curves
                .iter()
                .map(|m| {
                    let zero = m.points.iter().find(|p| p.0 == 0.0).map(|p| p.1);
                    [0, 1, 2].map(|c| {
                        m.points
                            .iter()
                            .filter_map(|p| zero.map(|z| (p.0, p.1[c] / z[c])))
                            .filter(|p| p.1.is_finite())
                            .collect()
                    })
                })
                .collect();
            panels.push((
                ratio,
                model_ratio,
                "Rd(θ)/Rd(0°)",
                "Rd(θ) / Rd(0°), per unit incident power",
                false,
            ));
        }
        let model_absolute: Vec<[Vec<(f64, f64)>; 3]> = curves
            .iter()
            .map(|m| {
                [0, 1, 2].map(|c| {
                    m.points
                        .iter()
                        .map(|p| (p.0, p.1[c]))
                        .filter(|p| p.1.is_finite())
                        .collect()
                })
            })
            .collect();
        panels.push((
            absolute,
            model_absolute,
            "Rd [-]",
            "Rd(θ), per unit incident power",
            true,
        ));
        let areas = root.split_evenly((1, panels.len()));
        for (area, (series, model, y_desc, caption, from_zero)) in areas.iter().zip(&panels) {
            let model_values = model.iter().flatten().flatten().map(|&(_, v)| (v, 0.0));
            let (lo, hi) = match series
                .iter()
                .flatten()
                .map(|&(_, v, e)| (v, e))
                .chain(model_values)
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), (v, e)| {
                    (a.min(v - e), b.max(v + e))
                }) {
                (lo, hi) if lo <= hi => (lo, hi),
                _ => (0.0, 1.0),
            };
            let pad = (0.08 * (hi - lo)).max(0.02 * hi.abs()).max(1e-12);
            let y = if *from_zero {
                0.0..hi + pad
            } else {
                lo - pad..hi + pad
            };
            let mut ch = ChartBuilder::on(area)
                .caption(*caption, ("sans-serif", 16))
                .margin(12)
                .x_label_area_size(45)
                .y_label_area_size(70)
                .build_cartesian_2d(0.0..90.0, y)
                .map_err(|e| fail(&e))?;
            ch.configure_mesh()
                .x_desc("incidence angle θ [deg]")
                .y_desc(*y_desc)
                .x_label_formatter(&|v| format!("{v:.0}"))
                .y_label_formatter(&|v| {
                    if hi.abs() < 0.01 {
                        format!("{v:.1e}")
                    } else {
                        format!("{v:.3}")
                    }
                })
                .draw()
                .map_err(|e| fail(&e))?;
            for c in 0..3 {
                let color = CHANNEL_COLORS[c];
                let line: Vec<(f64, f64)> = series[c].iter().map(|s| (s.0, s.1)).collect();
                ch.draw_series(LineSeries::new(line.clone(), color.stroke_width(2)))
                    .map_err(|e| fail(&e))?
                    .label(["R", "G", "B"][c])
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                    });
                ch.draw_series(line.iter().map(|&p| Circle::new(p, 3, color.filled())))
                    .map_err(|e| fail(&e))?;
                // Error bars: a vertical stroke with caps 0.6° wide.
                ch.draw_series(series[c].iter().flat_map(|&(x, v, e)| {
                    [
                        PathElement::new(vec![(x, v - e), (x, v + e)], color.stroke_width(1)),
                        PathElement::new(vec![(x - 0.6, v - e), (x + 0.6, v - e)], color),
                        PathElement::new(vec![(x - 0.6, v + e), (x + 0.6, v + e)], color),
                    ]
                }))
                .map_err(|e| fail(&e))?;
            }
            for (k, (curve, lines)) in curves.iter().zip(model).enumerate() {
                let (dash, gap) = CURVE_DASHES[k % CURVE_DASHES.len()];
                for (c, line) in lines.iter().enumerate() {
                    let style = CHANNEL_COLORS[c].stroke_width(2);
                    let drawn = ch
                        .draw_series(DashedLineSeries::new(line.clone(), dash, gap, style))
                        .map_err(|e| fail(&e))?;
                    // One legend entry per model, in black.
                    if c == 0 {
                        drawn.label(curve.name.clone()).legend(move |(x, y)| {
                            // The curve's first three dashes, clipped to the 20 px
                            // legend glyph, relative to the anchor.
                            let (d, g) = (dash as i32, gap as i32);
                            let seg = |a: i32| {
                                let a = a.min(20);
                                PathElement::new(
                                    vec![(a, 0), ((a + d).min(20), 0)],
                                    BLACK.stroke_width(2),
                                )
                            };
                            EmptyElement::at((x, y)) + seg(0) + seg(d + g) + seg(2 * (d + g))
                        });
                    }
                }
            }
            ch.configure_series_labels()
                .position(SeriesLabelPosition::UpperLeft)
                .border_style(BLACK)
                .background_style(WHITE.mix(0.8))
                .draw()
                .map_err(|e| fail(&e))?;
        }
        root.present().map_err(|e| fail(&e))?;
    }
    let mut png_bytes = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut png_bytes, w, h);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        enc.write_header()
            .and_then(|mut wr| wr.write_image_data(&rgb))
            .map_err(|e| fail(&e))?;
    }
    Ok(png_bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn incidence_plot_is_a_png() {
        let row = |theta_deg: f64, k: f64| IncidencePoint {
            theta_deg,
            rd: [0.45 * k, 0.28 * k, 0.18 * k],
            se: [0.002, 0.002, 0.001],
        };
        let pts = [row(0.0, 1.0), row(45.0, 1.05), row(80.0, 1.4)];
        let png = incidence(&pts, &[], "test").unwrap();
        assert!(png.starts_with(b"\x89PNG\r\n\x1a\n"));
        // Model curves change the picture.
        let curve = IncidenceCurve {
            name: "model".into(),
            points: pts
                .iter()
                .map(|p| (p.theta_deg, p.rd.map(|v| 0.9 * v)))
                .collect(),
        };
        let with = incidence(&pts, std::slice::from_ref(&curve), "test").unwrap();
        assert!(with.starts_with(b"\x89PNG") && with != png);
        // Without 0° there is no ratio panel, but still a picture.
        assert!(
            incidence(&pts[1..], &[curve], "test")
                .unwrap()
                .starts_with(b"\x89PNG")
        );
        // A channel with no reflectance at 0° has no ratio, and the plot still draws.
        let mut dark = pts;
        dark[0].rd[2] = 0.0;
        assert!(
            incidence(&dark, &[], "test")
                .unwrap()
                .starts_with(b"\x89PNG")
        );
    }
}
