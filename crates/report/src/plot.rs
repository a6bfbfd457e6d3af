//! Comparison plots as PNG (plotters, bitmap backend, an embedded DejaVu Sans so output does not
//! depend on system fonts): profiles (thesis Fig. 6.1), kernel slices against the ground truth
//! (Fig. 6.2), singular-value decay (Fig. 5.1), convolution/difference sheets (Fig. 6.3–6.10),
//! guided optimization against pre-integration (Fig. 5.15, [`imitation`]), the manual model's w
//! sweep (Fig. 5.17, [`w_sweep`]) and total diffuse reflectance against the incidence angle
//! ([`incidence`]). Every plot is returned as PNG bytes: the caller decides where, and whether, it
//! is written.

use std::sync::Once;

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::{FontStyle, register_font};

use mc::CHANNELS;

use crate::error::{ReportError, Result};
use fit::KernelModel;
use fit::Profile;
use fit::evaluate::Evaluation;
use fit::signals::Signal;

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

pub(crate) fn font() {
    FONT.call_once(|| {
        let _ = register_font(
            "sans-serif",
            FontStyle::Normal,
            include_bytes!("../../../assets/DejaVuSans.ttf"),
        );
    });
}

/// `path` names the picture (e.g. "skin1 profile plot"): plots are returned as bytes, and the
/// caller decides where they go.
fn err(path: &str, e: impl std::fmt::Display) -> ReportError {
    ReportError::Plot {
        path: path.to_string(),
        message: e.to_string(),
    }
}

/// A drawing area on an in-memory RGB picture.
pub(crate) type Area<'a> = DrawingArea<BitMapBackend<'a>, Shift>;

/// A white page with `heading` above its drawing area, the font loaded; errors name `path`.
fn page<'a>(root: Area<'a>, path: &str, heading: &str) -> Result<Area<'a>> {
    font();
    root.fill(&WHITE).map_err(|e| err(path, e))?;
    root.titled(heading, ("sans-serif", 20))
        .map_err(|e| err(path, e))
}

/// Draws a picture of `size` with `draw` and returns it as PNG bytes; `path` names it in errors.
pub(crate) fn png_of(
    size: (u32, u32),
    path: &str,
    draw: impl FnOnce(Area<'_>, &str) -> Result<()>,
) -> Result<Vec<u8>> {
    let mut rgb = vec![0u8; (size.0 * size.1 * 3) as usize];
    draw(
        BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area(),
        path,
    )?;
    encode_png(&rgb, size, path)
}

/// RGB8 pixels, row-major, as PNG bytes.
fn encode_png(rgb: &[u8], (width, height): (u32, u32), path: &str) -> Result<Vec<u8>> {
    let mut bytes = Vec::new();
    let mut enc = png::Encoder::new(&mut bytes, width, height);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    enc.write_header()
        .and_then(|mut wr| wr.write_image_data(rgb))
        .map_err(|e| err(path, e))?;
    Ok(bytes)
}

/// Rd(r) per channel: linear near 0 (left) and logarithmic over the whole range (right), as PNG
/// bytes.
pub fn profile(p: &Profile, title: &str) -> Result<Vec<u8>> {
    png_of(
        (1200, 480),
        &format!("{title} profile plot"),
        |root, path| draw_profile(root, path, p, title),
    )
}

fn draw_profile(root: Area<'_>, path: &str, p: &Profile, title: &str) -> Result<()> {
    font();
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
            let color = CHANNEL_COLORS[c];
            ch.draw_series(LineSeries::new(
                p.r.iter()
                    .zip(&p.rd[c])
                    .filter(|(r, _)| **r <= near)
                    .map(|(&r, &v)| (r, v)),
                color.stroke_width(2),
            ))
            .map_err(|e| err(path, e))?
            .label(format!("channel {}", CHANNELS[c]))
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
            });
        }
        ch.configure_series_labels()
            .border_style(BLACK)
            .background_style(WHITE.mix(0.8))
            .draw()
            .map_err(|e| err(path, e))?;
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

/// Slices along the main axis (top row) and the diagonal (bottom row) of `models` against the
/// ground truth (dots), per channel, zoomed on the kernel's centre. Every model must have been
/// evaluated (an error names the one that was not). As PNG bytes.
pub fn slices(ev: &Evaluation, models: &[KernelModel], title: &str) -> Result<Vec<u8>> {
    png_of(
        (1500, 800),
        &format!("{title} slices plot"),
        |root, path| draw_slices(root, path, ev, models, title),
    )
}

fn draw_slices(
    root: Area<'_>,
    path: &str,
    ev: &Evaluation,
    models: &[KernelModel],
    title: &str,
) -> Result<()> {
    let root = page(
        root,
        path,
        &format!(
            "{title}: kernel slices against the 2D ground truth (normalized to Σ = 1 per channel)"
        ),
    )?;
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
                    "channel {}: {}",
                    CHANNELS[c],
                    if row == 0 {
                        "main axis A(x, 0)"
                    } else {
                        "diagonal A(x, x)"
                    }
                ),
                ("sans-serif", 16),
            )
            .margin(8)
            .x_label_area_size(36)
            .y_label_area_size(70)
            .build_cartesian_2d(0.0..n as f64 * step, 0.0..max)
            .map_err(|e| err(path, e))?;
        ch.configure_mesh()
            .x_desc("distance from the centre [cm]")
            .y_desc("weight per sample [-]")
            .y_label_formatter(&|v| format!("{v:.1e}"))
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
        .label("2D ground truth")
        .legend(|(x, y)| Circle::new((x + 10, y), 3, BLACK.filled()));
        for (m, &model) in models.iter().enumerate() {
            let r = ev
                .row(model, c)
                .ok_or_else(|| err(path, format!("{model} was not evaluated")))?;
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
            .label(r.title())
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
            });
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

/// The first 30 singular values per channel, log scale (thesis Fig. 5.1), as PNG bytes.
pub fn singular_values(ev: &Evaluation, title: &str) -> Result<Vec<u8>> {
    png_of(
        (700, 480),
        &format!("{title} singular values plot"),
        |root, path| draw_singular_values(root, path, ev, title),
    )
}

fn draw_singular_values(root: Area<'_>, path: &str, ev: &Evaluation, title: &str) -> Result<()> {
    font();
    root.fill(&WHITE).map_err(|e| err(path, e))?;
    let all = ev
        .singular_values
        .iter()
        .flat_map(|v| v.iter())
        .filter(|&&x| x > 0.0);
    let (lo, hi) = all.fold((f64::INFINITY, 0.0f64), |(a, b), &x| (a.min(x), b.max(x)));
    let mut ch = ChartBuilder::on(&root)
        .caption(
            format!("{title}: singular values of the 2D ground truth (Σ = 1)"),
            ("sans-serif", 18),
        )
        .margin(10)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(0.5..30.5, (lo.max(hi * 1e-16)..hi * 2.0).log_scale())
        .map_err(|e| err(path, e))?;
    ch.configure_mesh()
        .x_desc("index i (rank)")
        .y_desc("|σᵢ| [-]")
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .draw()
        .map_err(|e| err(path, e))?;
    for c in 0..3 {
        let color = CHANNEL_COLORS[c];
        let pts: Vec<(f64, f64)> = ev.singular_values[c]
            .iter()
            .enumerate()
            .filter(|(_, v)| **v > 0.0)
            .map(|(i, &v)| ((i + 1) as f64, v))
            .collect();
        ch.draw_series(LineSeries::new(pts.clone(), color.stroke_width(2)))
            .map_err(|e| err(path, e))?
            .label(format!("channel {}", CHANNELS[c]))
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
            });
        ch.draw_series(pts.into_iter().map(|p| Circle::new(p, 3, color.filled())))
            .map_err(|e| err(path, e))?;
    }
    ch.configure_series_labels()
        .border_style(BLACK)
        .background_style(WHITE.mix(0.8))
        .draw()
        .map_err(|e| err(path, e))?;
    root.present().map_err(|e| err(path, e))
}

/// What a test signal shows, for panel labels.
fn signal_title(s: Signal) -> &'static str {
    match s {
        Signal::Edge => "white–black edge",
        Signal::CircleSquares => "circle and two squares",
        Signal::Dot => "single-pixel dot",
        Signal::Shaded => "shaded disc",
        Signal::Uniform => "textured patch",
    }
}

/// Linear value in [0, 1] → sRGB-like display byte (γ = 2.2), as every picture of a
/// [`convolutions`] sheet and its colour bars use.
fn display(v: f64) -> u8 {
    (v.clamp(0.0, 1.0).powf(1.0 / 2.2) * 255.0) as u8
}

/// The labelled sheet of one test signal (see [`convolutions`]).
fn convolution_sheet(
    ev: &Evaluation,
    models: &[KernelModel],
    signal: Signal,
    gain: f64,
    title: &str,
) -> Result<Sheet> {
    let missing = |m: &KernelModel| ReportError::Plot {
        path: format!("{title} convolution sheet"),
        message: format!("{m} was not evaluated"),
    };
    let size = ev.images[0].size;
    // Small test images are enlarged (nearest neighbour) so panels stay readable beside labels.
    let zoom = 200usize.div_ceil(size).max(1);
    let cell = |label: String, rgb: &dyn Fn(usize, usize) -> [f64; 3]| {
        let s = size * zoom;
        let mut px = Vec::with_capacity(s * s * 3);
        for y in 0..s {
            for x in 0..s {
                px.extend(rgb(x / zoom, y / zoom).map(display));
            }
        }
        SheetCell {
            label,
            width: s as u32,
            height: s as u32,
            rgb: px,
        }
    };
    let first = models.first().ok_or_else(|| ReportError::Plot {
        path: format!("{title} convolution sheet"),
        message: "no models to show".into(),
    })?;
    let reference: Vec<_> = (0..3)
        .map(|c| {
            let k = ev.kernel(*first, c).ok_or_else(|| missing(first))?;
            Ok(ev.images[c].images(signal, k))
        })
        .collect::<Result<_>>()?;
    let mut convolved = Vec::new();
    let mut differences = Vec::new();
    for m in models {
        let name = ev.row(*m, 0).ok_or_else(|| missing(m))?.title();
        let imgs = (0..3)
            .map(|c| {
                let k = ev.kernel(*m, c).ok_or_else(|| missing(m))?;
                Ok(ev.images[c].images(signal, k))
            })
            .collect::<Result<Vec<_>>>()?;
        convolved.push(cell(format!("{name} ⊛ input"), &|x, y| {
            [0, 1, 2].map(|c| imgs[c].2.at(x, y))
        }));
        differences.push(cell(format!("|{name} − truth| × {gain}"), &|x, y| {
            [0, 1, 2].map(|c| gain * (imgs[c].2.at(x, y) - imgs[c].1.at(x, y)).abs())
        }));
    }
    let ramp = |t: f64| [display(t); 3];
    // Five ticks from 0 to `top`; "≥" on the last where brighter values are clipped.
    let ticks = |top: f64, clipped: bool| {
        (0..=4)
            .map(|i| {
                let t = f64::from(i) / 4.0;
                let v = (t * top * 1e6).round() / 1e6;
                let label = if clipped && i == 4 {
                    format!("≥ {v}")
                } else {
                    format!("{v}")
                };
                (t, label)
            })
            .collect()
    };
    Ok(Sheet {
        title: vec![
            format!(
                "{title}: test signal “{}” convolved with each rank-1 model, channels R, G, B at once",
                signal_title(signal)
            ),
            format!(
                "rows: input and 2D ground truth; each model; |model − ground truth| × {gain} (one kernel per colour channel)"
            ),
        ],
        rows: vec![
            vec![
                cell(
                    format!("input: {}", signal_title(signal)),
                    &|x, y| [0, 1, 2].map(|c| reference[c].0.at(x, y)),
                ),
                cell("2D ground truth ⊛ input".into(), &|x, y| {
                    [0, 1, 2].map(|c| reference[c].1.at(x, y))
                }),
            ],
            convolved,
            differences,
        ],
        bars: vec![
            ColourBar {
                caption: "rows 1–2: reflected irradiance per channel, relative to the input's maximum [-]"
                    .into(),
                ramp,
                ticks: ticks(1.0, false),
            },
            ColourBar {
                caption: format!(
                    "row 3: |model − ground truth| per channel, relative to the input's maximum [-], drawn × {gain}"
                ),
                ramp,
                ticks: ticks(1.0 / gain, true),
            },
        ],
    })
}

/// A sheet for one test signal, all three channels at once (each colour channel convolved with
/// its own kernel): the input and its convolution with the 2D ground truth on the first row;
/// each of `models` convolved (second row) and its absolute difference to the ground truth,
/// scaled ×`gain` (third row); every panel labelled, with colour bars for both scales. As PNG
/// bytes.
pub fn convolutions(
    ev: &Evaluation,
    models: &[KernelModel],
    signal: Signal,
    gain: f64,
    title: &str,
) -> Result<Vec<u8>> {
    convolution_sheet(ev, models, signal, gain, title)?.png()
}

/// Analytic profiles against MC, per channel: r·Rd(r) on a log scale (top) and the relative error
/// model/MC − 1 (bottom), against r in transport mean free paths `mfp` [cm] of each channel. As
/// PNG bytes.
pub fn profile_comparison(
    mc: &Profile,
    models: &[(&str, &Profile)],
    mfp: [f64; 3],
    title: &str,
) -> Result<Vec<u8>> {
    png_of(
        (1500, 850),
        &format!("{title} profile comparison"),
        |root, path| draw_profile_comparison(root, path, mc, models, mfp, title),
    )
}

fn draw_profile_comparison(
    root: Area<'_>,
    path: &str,
    mc: &Profile,
    models: &[(&str, &Profile)],
    mfp: [f64; 3],
    title: &str,
) -> Result<()> {
    font();
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
                format!("{title}, channel {}: r·Rd(r)", CHANNELS[c]),
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
            .caption(
                format!("channel {}: relative error of each model", CHANNELS[c]),
                ("sans-serif", 14),
            )
            .margin(8)
            .x_label_area_size(30)
            .y_label_area_size(60)
            .build_cartesian_2d(0.0..x_max, -1.0..1.0)
            .map_err(|e| err(path, e))?;
        ch.configure_mesh()
            .x_desc("r [transport MFP]")
            .y_desc("model / MC − 1 [-]")
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
/// As PNG bytes.
pub fn area_effect(curves: &[Vec<(f64, f64, f64)>; 3], title: &str) -> Result<Vec<u8>> {
    png_of(
        (900, 560),
        &format!("{title} area effect plot"),
        |root, path| draw_area_effect(root, path, curves, title),
    )
}

fn draw_area_effect(
    root: Area<'_>,
    path: &str,
    curves: &[Vec<(f64, f64, f64)>; 3],
    title: &str,
) -> Result<()> {
    font();
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
        .label(format!("{} point-sampled", CHANNELS[c]))
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color.mix(0.5)));
        ch.draw_series(LineSeries::new(
            curves[c].iter().map(|p| (p.0, p.2)),
            color.stroke_width(3),
        ))
        .map_err(|e| err(path, e))?
        .label(format!("{} area pre-integrated", CHANNELS[c]))
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(3)));
    }
    ch.configure_series_labels()
        .border_style(BLACK)
        .background_style(WHITE.mix(0.8))
        .draw()
        .map_err(|e| err(path, e))?;
    root.present().map_err(|e| err(path, e))
}

/// One labelled picture of a [`Sheet`]: RGB8, row-major.
#[derive(Clone)]
pub struct SheetCell {
    /// Caption shown with the picture.
    pub label: String,
    /// Width [px].
    pub width: u32,
    /// Height [px].
    pub height: u32,
    /// Pixels, `width × height × 3` bytes.
    pub rgb: Vec<u8>,
}

/// A colour scale under a [`Sheet`]: the ramp its pictures use, ticks and what it measures.
pub struct ColourBar {
    /// The quantity the colour shows, with units.
    pub caption: String,
    /// Colour at t ∈ [0, 1] along the bar.
    pub ramp: fn(f64) -> [u8; 3],
    /// (t ∈ [0, 1], value at t).
    pub ticks: Vec<(f64, String)>,
}

/// Labelled pictures in rows (a row may be shorter than the others) under title lines and above
/// colour bars.
pub struct Sheet {
    /// Title lines, drawn above the rows.
    pub title: Vec<String>,
    /// The pictures, row by row, top to bottom.
    pub rows: Vec<Vec<SheetCell>>,
    /// The colour bars, drawn under the rows.
    pub bars: Vec<ColourBar>,
}

// Sheet layout [px] and font sizes [pt].
const PAD: u32 = 8;
const TITLE_LINE: u32 = 24;
const LABEL_LINE: u32 = 22;
const BAR_HEIGHT: u32 = 16;
/// One colour bar: caption line, ramp, tick marks and values.
const BAR_BLOCK: u32 = LABEL_LINE + BAR_HEIGHT + 22;
const BAR_WIDTH: u32 = 480;
const TITLE_FONT: u32 = 18;
const LABEL_FONT: u32 = 15;
const TICK_FONT: u32 = 13;

/// Width of a text in the embedded font [px] (an estimate if the font cannot lay it out).
fn text_width(text: &str, size: u32) -> u32 {
    font();
    ("sans-serif", size)
        .into_font()
        .box_size(text)
        .map_or(text.chars().count() as u32 * size * 3 / 5, |(w, _)| w)
}

/// Where a [`Sheet`]'s parts go [px].
struct Layout {
    width: u32,
    height: u32,
    /// Column pitch without padding: the widest picture or label.
    column: u32,
    /// Top of each row's label line (its pictures start one label line lower).
    row_top: Vec<u32>,
    /// Top of the first colour bar's block.
    bars_top: u32,
}

impl Sheet {
    fn layout(&self) -> Layout {
        let column = self
            .rows
            .iter()
            .flatten()
            .map(|c| c.width.max(text_width(&c.label, LABEL_FONT) + 4))
            .max()
            .unwrap_or(1);
        let columns = self.rows.iter().map(Vec::len).max().unwrap_or(1) as u32;
        let mut y = PAD + TITLE_LINE * self.title.len() as u32;
        let row_top = self
            .rows
            .iter()
            .map(|r| {
                let top = y;
                y += LABEL_LINE + r.iter().map(|c| c.height).max().unwrap_or(0) + PAD;
                top
            })
            .collect();
        let texts = (self.title.iter().map(|t| text_width(t, TITLE_FONT)))
            .chain(self.bars.iter().map(|b| text_width(&b.caption, LABEL_FONT)));
        let bars = if self.bars.is_empty() {
            0
        } else {
            BAR_WIDTH + 4 * PAD
        };
        let width = (columns * (column + PAD) + PAD)
            .max(texts.max().unwrap_or(0) + 2 * PAD)
            .max(bars);
        Layout {
            width,
            height: y + BAR_BLOCK * self.bars.len() as u32,
            column,
            row_top,
            bars_top: y,
        }
    }

    /// The sheet as PNG bytes.
    pub fn png(&self) -> Result<Vec<u8>> {
        font();
        let name = format!("sheet {:?}", self.title.first().map_or("", |t| t.as_str()));
        let fail = |e: &dyn std::fmt::Display| err(&name, e);
        let l = self.layout();
        let mut rgb = vec![0u8; (l.width * l.height * 3) as usize];
        {
            let root =
                BitMapBackend::with_buffer(&mut rgb, (l.width, l.height)).into_drawing_area();
            root.fill(&WHITE).map_err(|e| fail(&e))?;
            let text = |s: &str, (x, y): (u32, u32), size: u32| {
                root.draw(&Text::new(
                    s.to_string(),
                    (x as i32, y as i32),
                    ("sans-serif", size).into_font(),
                ))
                .map_err(|e| fail(&e))
            };
            for (i, t) in self.title.iter().enumerate() {
                text(t, (PAD, PAD + i as u32 * TITLE_LINE), TITLE_FONT)?;
            }
            for (row, top) in self.rows.iter().zip(&l.row_top) {
                for (i, c) in row.iter().enumerate() {
                    let x = PAD + i as u32 * (l.column + PAD);
                    text(&c.label, (x, *top), LABEL_FONT)?;
                    let elem = BitMapElement::with_owned_buffer(
                        (x as i32, (top + LABEL_LINE) as i32),
                        (c.width, c.height),
                        c.rgb.clone(),
                    )
                    .ok_or_else(|| {
                        fail(&format!(
                            "{:?}: buffer does not match {}×{}",
                            c.label, c.width, c.height
                        ))
                    })?;
                    root.draw(&elem).map_err(|e| fail(&e))?;
                    // A frame, so white parts of a picture do not melt into the page.
                    let (x, y) = (x as i32, (top + LABEL_LINE) as i32);
                    root.draw(&Rectangle::new(
                        [(x - 1, y - 1), (x + c.width as i32, y + c.height as i32)],
                        RGBColor(150, 150, 150),
                    ))
                    .map_err(|e| fail(&e))?;
                }
            }
            for (k, b) in self.bars.iter().enumerate() {
                let (x0, top) = (2 * PAD, l.bars_top + k as u32 * BAR_BLOCK);
                text(&b.caption, (PAD, top), LABEL_FONT)?;
                let y0 = (top + LABEL_LINE) as i32;
                for i in 0..BAR_WIDTH {
                    let [r, g, bl] = (b.ramp)(f64::from(i) / f64::from(BAR_WIDTH - 1));
                    let x = (x0 + i) as i32;
                    root.draw(&PathElement::new(
                        vec![(x, y0), (x, y0 + BAR_HEIGHT as i32 - 1)],
                        RGBColor(r, g, bl),
                    ))
                    .map_err(|e| fail(&e))?;
                }
                root.draw(&Rectangle::new(
                    [
                        (x0 as i32 - 1, y0 - 1),
                        ((x0 + BAR_WIDTH) as i32, y0 + BAR_HEIGHT as i32),
                    ],
                    BLACK,
                ))
                .map_err(|e| fail(&e))?;
                for (t, label) in &b.ticks {
                    let x = x0 + (t.clamp(0.0, 1.0) * f64::from(BAR_WIDTH - 1)).round() as u32;
                    let y = y0 + BAR_HEIGHT as i32;
                    root.draw(&PathElement::new(
                        vec![(x as i32, y), (x as i32, y + 4)],
                        BLACK,
                    ))
                    .map_err(|e| fail(&e))?;
                    let half = text_width(label, TICK_FONT) / 2;
                    text(label, (x.saturating_sub(half), (y + 5) as u32), TICK_FONT)?;
                }
            }
            root.present().map_err(|e| fail(&e))?;
        }
        encode_png(&rgb, (l.width, l.height), &name)
    }
}

/// Pictures in a grid of `columns`, each with its label above it (comparison sheets of
/// renderings, cut-outs and difference images), as PNG bytes.
pub fn image_sheet(cells: &[SheetCell], columns: usize) -> Result<Vec<u8>> {
    Sheet {
        title: Vec::new(),
        rows: cells.chunks(columns.max(1)).map(<[_]>::to_vec).collect(),
        bars: Vec::new(),
    }
    .png()
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
    let fail = |e: &dyn std::fmt::Display| ReportError::Plot {
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
    encode_png(&rgb, (w, h), &format!("{title} incidence plot"))
}

/// Thesis Fig. 5.15 as a plot: top, per channel, the 1D function a(x) (log scale down to 10⁻⁴
/// of the peak) of pre-integration (dots),
/// of guided optimization with k = 1.55, b = 50, and of the other compared models; bottom, each
/// model's image-space distance to pre-integration on the shaded test signal (log scale, one
/// marker per channel). As PNG bytes.
pub fn imitation(im: &fit::imitation::Imitation, title: &str) -> Result<Vec<u8>> {
    png_of(
        (1500, 960),
        &format!("{title} guided-vs-preint plot"),
        |root, path| draw_imitation(root, path, im, title),
    )
}

fn draw_imitation(
    root: Area<'_>,
    path: &str,
    im: &fit::imitation::Imitation,
    title: &str,
) -> Result<()> {
    let root = page(
        root,
        path,
        &format!(
            "{title}: guided optimization with k = 1.55, b = 50 imitates pre-integration (thesis Fig. 5.15)"
        ),
    )?;
    let (top, bottom) = root.split_vertically(520);
    // The models drawn as curves: the imitation, Fig. 5.15c–d, the thesis's default, SVD rank-1.
    let drawn = [
        fit::imitation::IMITATION,
        KernelModel::Guided { k: 0.0, b: 50.0 },
        KernelModel::Guided { k: 2.0, b: 50.0 },
        KernelModel::Guided { k: 1.0, b: 0.0 },
        KernelModel::Svd {
            rank: 1,
            renormalize: false,
        },
    ];
    for (c, cell) in top.split_evenly((1, 3)).iter().enumerate() {
        let truth = &im.preint[c];
        // Log scale, down to 10⁻⁴ of pre-integration's peak: the centre and the falloff at once.
        let floor = 1e-4 * truth[0];
        let n = truth
            .iter()
            .position(|&v| v < floor)
            .unwrap_or(truth.len())
            .max(10)
            .min(truth.len());
        let max = drawn
            .iter()
            .filter_map(|&m| im.candidate(m))
            .map(|m| m.a[c][0])
            .fold(truth[0], f64::max)
            * 1.5;
        let mut ch = ChartBuilder::on(cell)
            .caption(
                format!("channel {}: 1D function a(x) of A = a(x)a(y)", CHANNELS[c]),
                ("sans-serif", 16),
            )
            .margin(8)
            .x_label_area_size(36)
            .y_label_area_size(70)
            .build_cartesian_2d(
                0.0..n as f64 * im.h,
                (floor.max(1e-300)..max.max(2e-300)).log_scale(),
            )
            .map_err(|e| err(path, e))?;
        ch.configure_mesh()
            .x_desc("distance from the centre x [cm]")
            .y_desc("a(x) per sample [-]")
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .draw()
            .map_err(|e| err(path, e))?;
        ch.draw_series(
            truth[..n]
                .iter()
                .enumerate()
                .step_by((n / 60).max(1))
                .map(|(i, &v)| Circle::new((i as f64 * im.h, v), 3, BLACK.filled())),
        )
        .map_err(|e| err(path, e))?
        .label("pre-integration (eq. 5.18)")
        .legend(|(x, y)| Circle::new((x + 10, y), 3, BLACK.filled()));
        for (m, &model) in drawn.iter().enumerate() {
            let Some(cand) = im.candidate(model) else {
                continue;
            };
            let color = MODEL_COLORS[(m + 1) % MODEL_COLORS.len()];
            let width = if m == 0 { 3 } else { 2 };
            // Non-positive values (a fit's zero floor) have no place on the log axis.
            let line: Vec<(f64, f64)> = cand.a[c][..n]
                .iter()
                .enumerate()
                .map(|(i, &v)| (i as f64 * im.h, v.max(floor * 0.5)))
                .collect();
            let style = color.stroke_width(width);
            if matches!(model, KernelModel::Guided { b, .. } if b > 0.0) && m > 0 {
                ch.draw_series(DashedLineSeries::new(line, 8, 5, style))
            } else {
                ch.draw_series(LineSeries::new(line, style))
            }
            .map_err(|e| err(path, e))?
            .label(model.title())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style));
        }
        if c == 0 {
            ch.configure_series_labels()
                .position(SeriesLabelPosition::UpperRight)
                .border_style(BLACK)
                .background_style(WHITE.mix(0.8))
                .draw()
                .map_err(|e| err(path, e))?;
        }
    }

    // Bottom: image-space distance to pre-integration per model and channel.
    let values = im
        .candidates
        .iter()
        .flat_map(|m| m.image_distance)
        .filter(|v| *v > 0.0 && v.is_finite());
    let (lo, hi) = values.fold((f64::INFINITY, 0.0f64), |(a, b), v| (a.min(v), b.max(v)));
    let (lo, hi) = if lo <= hi { (lo, hi) } else { (1e-3, 1.0) };
    let count = im.candidates.len();
    let names: Vec<String> = im.candidates.iter().map(|m| m.model.title()).collect();
    let mut ch = ChartBuilder::on(&bottom)
        .caption(
            "shaded test signal: ‖E∗A − E∗A_p‖ / ‖E∗A_p‖, distance of each model's image from pre-integration's (lower = closer)",
            ("sans-serif", 16),
        )
        .margin(12)
        .x_label_area_size(44)
        .y_label_area_size(70)
        .build_cartesian_2d(-0.5..count as f64 - 0.5, (lo / 2.0..hi * 2.0).log_scale())
        .map_err(|e| err(path, e))?;
    ch.configure_mesh()
        .x_labels(count)
        .x_label_formatter(&|x| {
            let i = x.round();
            if (x - i).abs() < 1e-6 && i >= 0.0 {
                names.get(i as usize).cloned().unwrap_or_default()
            } else {
                String::new()
            }
        })
        .x_desc("model")
        .y_desc("relative image distance [-]")
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .draw()
        .map_err(|e| err(path, e))?;
    for c in 0..3 {
        let color = CHANNEL_COLORS[c];
        let offset = (c as f64 - 1.0) * 0.12;
        ch.draw_series(im.candidates.iter().enumerate().filter_map(|(i, m)| {
            let v = m.image_distance[c];
            (v > 0.0 && v.is_finite())
                .then(|| Circle::new((i as f64 + offset, v), 6, color.filled()))
        }))
        .map_err(|e| err(path, e))?
        .label(format!("channel {}", CHANNELS[c]))
        .legend(move |(x, y)| Circle::new((x + 10, y), 5, color.filled()));
    }
    ch.configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .border_style(BLACK)
        .background_style(WHITE.mix(0.8))
        .draw()
        .map_err(|e| err(path, e))?;
    root.present().map_err(|e| err(path, e))
}

/// Thesis Fig. 5.17 as a plot: top, per channel, the light across a shadow edge for the shown w
/// against the ground truth (dots); bottom left, the image-space error against w per channel;
/// bottom right, the edge's 10–90 % width relative to the ground truth's against w. The w of
/// `sweep.params` (Table A.1's) is marked. As PNG bytes.
pub fn w_sweep(sweep: &fit::WSweep, title: &str) -> Result<Vec<u8>> {
    png_of(
        (1500, 960),
        &format!("{title} manual w sweep plot"),
        |root, path| draw_w_sweep(root, path, sweep, title),
    )
}

fn draw_w_sweep(root: Area<'_>, path: &str, s: &fit::WSweep, title: &str) -> Result<()> {
    let root = page(
        root,
        path,
        &format!(
            "{title}: the manual model's w moves it from far (w = 0) to near scattering (w = 1) (thesis Fig. 5.17)"
        ),
    )?;
    let reference_w = s.params[0].w;
    let (top, bottom) = root.split_vertically(480);
    for (c, cell) in top.split_evenly((1, 3)).iter().enumerate() {
        let truth = &s.truth_edge[c];
        let n = truth.len() / 2;
        // ±1.5 edge widths of the ground truth (at least 5 samples) around the edge.
        let reach = ((1.5 * s.truth_edge_width[c] / s.h).ceil() as usize).clamp(5, n.max(5));
        let reach = reach.min(n);
        let x = |i: usize| (i as f64 - n as f64) * s.h;
        let span = n - reach..=n + reach;
        let mut ch = ChartBuilder::on(cell)
            .caption(
                format!("channel {}: light across a shadow edge", CHANNELS[c]),
                ("sans-serif", 16),
            )
            .margin(8)
            .x_label_area_size(36)
            .y_label_area_size(60)
            .build_cartesian_2d(x(n - reach)..x(n + reach), 0.0..1.05)
            .map_err(|e| err(path, e))?;
        ch.configure_mesh()
            .x_desc("x [cm] (lit for x < 0, shadow beyond)")
            .y_desc("exitance / irradiance M(x) [-]")
            .draw()
            .map_err(|e| err(path, e))?;
        let step = (2 * reach / 50).max(1);
        ch.draw_series(
            span.clone()
                .step_by(step)
                .map(|i| Circle::new((x(i), truth[i]), 3, BLACK.filled())),
        )
        .map_err(|e| err(path, e))?
        .label("2D ground truth (= pre-integration, eq. 5.15)")
        .legend(|(x, y)| Circle::new((x + 10, y), 3, BLACK.filled()));
        for (k, (w, edges)) in s.edges.iter().enumerate() {
            let color = MODEL_COLORS[(k + 1) % MODEL_COLORS.len()];
            let what = if (*w - reference_w).abs() < 1e-9 {
                "Table A.1"
            } else if *w < reference_w {
                "far"
            } else {
                "near"
            };
            ch.draw_series(LineSeries::new(
                span.clone().map(|i| (x(i), edges[c][i])),
                color.stroke_width(2),
            ))
            .map_err(|e| err(path, e))?
            .label(format!("manual, w = {w} ({what})"))
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
            });
        }
        if c == 0 {
            // Lit (M ≈ 1) on the left, dark on the right: the lower left is empty.
            ch.configure_series_labels()
                .position(SeriesLabelPosition::LowerLeft)
                .border_style(BLACK)
                .background_style(WHITE.mix(0.8))
                .draw()
                .map_err(|e| err(path, e))?;
        }
    }

    let (left, right) = bottom.split_horizontally(750);
    let panels: [(&Area<'_>, &str, &str, Vec<[f64; 3]>); 2] = [
        (
            &left,
            "image-space error against the ground truth (five test signals)",
            "RMS error [irradiance units]",
            s.image_rms.clone(),
        ),
        (
            &right,
            "edge 10–90 % width / the ground truth's (1 = as wide)",
            "width ratio [-]",
            s.edge_width
                .iter()
                .map(|w| [0, 1, 2].map(|c| w[c] / s.truth_edge_width[c]))
                .collect(),
        ),
    ];
    for (p, (area, caption, y_desc, values)) in panels.iter().enumerate() {
        let all = values.iter().flatten().filter(|v| v.is_finite());
        let hi = all.fold(if p == 1 { 1.0f64 } else { 0.0 }, |a, &v| a.max(v)) * 1.1;
        let mut ch = ChartBuilder::on(*area)
            .caption(*caption, ("sans-serif", 16))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(70)
            .build_cartesian_2d(0.0..1.0, 0.0..hi.max(1e-300))
            .map_err(|e| err(path, e))?;
        ch.configure_mesh()
            .x_desc("w (weight of the near Gaussian) [-]")
            .y_desc(*y_desc)
            .y_label_formatter(&|v| {
                if p == 1 {
                    format!("{v:.2}")
                } else {
                    format!("{v:.1e}")
                }
            })
            .draw()
            .map_err(|e| err(path, e))?;
        for c in 0..3 {
            let color = CHANNEL_COLORS[c];
            let pts: Vec<(f64, f64)> = s.w.iter().zip(values).map(|(&w, v)| (w, v[c])).collect();
            ch.draw_series(LineSeries::new(pts.clone(), color.stroke_width(2)))
                .map_err(|e| err(path, e))?
                .label(format!("channel {}", CHANNELS[c]))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                });
            ch.draw_series(pts.into_iter().map(|q| Circle::new(q, 3, color.filled())))
                .map_err(|e| err(path, e))?;
        }
        let grey = RGBColor(120, 120, 120);
        ch.draw_series(DashedLineSeries::new(
            vec![(reference_w, 0.0), (reference_w, hi)],
            6,
            4,
            grey.stroke_width(2),
        ))
        .map_err(|e| err(path, e))?
        .label(format!("Table A.1: w = {reference_w}"))
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], grey.stroke_width(2)));
        if p == 1 {
            ch.draw_series(DashedLineSeries::new(
                vec![(0.0, 1.0), (1.0, 1.0)],
                10,
                4,
                BLACK.stroke_width(1),
            ))
            .map_err(|e| err(path, e))?
            .label("ground truth's width")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK));
        }
        ch.configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .border_style(BLACK)
            .background_style(WHITE.mix(0.8))
            .draw()
            .map_err(|e| err(path, e))?;
    }
    root.present().map_err(|e| err(path, e))
}

#[cfg(test)]
mod tests {
    use super::*;
    use fit::evaluate::{ImageSize, RANK1, evaluate};

    /// Decoded RGB8 pixels of a PNG and its size.
    fn decode(png_bytes: &[u8]) -> (u32, u32, Vec<u8>) {
        let mut reader = png::Decoder::new(std::io::Cursor::new(png_bytes))
            .read_info()
            .unwrap();
        let mut px = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut px).unwrap();
        assert_eq!(info.color_type, png::ColorType::Rgb);
        (info.width, info.height, px)
    }

    #[test]
    fn convolution_sheets_label_every_panel_and_scale_the_differences() {
        let p = Profile::from_fn(0.01, 30, |c, r| {
            (-r / (0.03 * (c + 1) as f64)).exp() / r.max(0.005)
        });
        let size = ImageSize {
            size: 48,
            max_half: 12,
        };
        let ev = evaluate(&p, "no such material", size).unwrap();
        let sheet = convolution_sheet(&ev, &RANK1, Signal::Edge, 10.0, "test").unwrap();

        // Every panel says what it shows: input, ground truth, each model twice (its
        // convolution and its difference).
        let labels: Vec<&str> = sheet
            .rows
            .iter()
            .flatten()
            .map(|c| c.label.as_str())
            .collect();
        assert_eq!(labels.len(), 2 + 2 * RANK1.len(), "{labels:?}");
        assert!(labels[0].contains("input") && labels[0].contains("edge"));
        assert!(labels[1].contains("ground truth"));
        for m in RANK1 {
            let named: Vec<_> = labels.iter().filter(|l| l.contains(&m.title())).collect();
            assert_eq!(named.len(), 2, "{m}: {labels:?}");
            assert!(named[1].contains("× 10"), "{named:?}");
        }
        // The difference scale says what it measures and ends where ×10 saturates.
        let diff = &sheet.bars[1];
        assert!(
            diff.caption.contains("relative to the input's maximum")
                && diff.caption.contains("× 10")
        );
        assert_eq!(diff.ticks.last().unwrap().1, "≥ 0.1");

        // And it is drawn: text in the title lines, in every label line and in every colour bar's
        // caption; each bar runs from black to white.
        let (w, h, px) = decode(&sheet.png().unwrap());
        let l = sheet.layout();
        assert_eq!((w, h), (l.width, l.height));
        let at = |x: u32, y: u32| {
            let i = 3 * (y * w + x) as usize;
            [px[i], px[i + 1], px[i + 2]]
        };
        let dark = |x0: u32, y0: u32, x1: u32, y1: u32| {
            (y0..y1)
                .flat_map(|y| (x0..x1).map(move |x| (x, y)))
                .filter(|&(x, y)| at(x, y).iter().all(|&v| v < 100))
                .count()
        };
        assert_eq!(sheet.title.len(), 2);
        for i in 0..2 {
            let y = PAD + i * TITLE_LINE;
            assert!(
                dark(0, y, w, y + TITLE_LINE) > 100,
                "title line {i} is blank"
            );
        }
        for (row, &top) in sheet.rows.iter().zip(&l.row_top) {
            for (i, c) in row.iter().enumerate() {
                let x = PAD + i as u32 * (l.column + PAD);
                assert!(
                    dark(x, top, x + l.column, top + LABEL_LINE) > 20,
                    "no label drawn above {:?}",
                    c.label
                );
            }
        }
        for k in 0..sheet.bars.len() as u32 {
            let top = l.bars_top + k * BAR_BLOCK;
            assert!(
                dark(0, top, w, top + LABEL_LINE) > 100,
                "bar {k} has no caption"
            );
            let y = top + LABEL_LINE + BAR_HEIGHT / 2;
            let ramp: Vec<u8> = (0..BAR_WIDTH).map(|i| at(2 * PAD + i, y)[0]).collect();
            assert!(
                ramp[0] < 10 && ramp[ramp.len() - 1] > 245,
                "bar {k}: {ramp:?}"
            );
            assert!(
                ramp.windows(2).all(|p| p[0] <= p[1]),
                "bar {k} is not monotone"
            );
        }
    }

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
