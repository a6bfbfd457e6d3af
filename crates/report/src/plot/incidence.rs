//! Total diffuse reflectance against the incidence angle: Monte Carlo with error bars, analytic
//! models as dashed curves, absolute and relative to normal incidence.

use plotters::coord::ranged1d::Ranged;
use plotters::prelude::*;

use super::chart::{Chart, Frame, Mark, Ticks, axes, legend, line_with_dots};
use super::{Area, CHANNEL_COLORS, InPlot, png_of, titled};
use crate::error::Result;
use mc::CHANNELS;

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

/// One panel of [`incidence`]: per channel the Monte Carlo points (θ [deg], value, 2 SE) and per
/// model its curve (θ [deg], value); what the y axis shows and the caption; whether y starts at 0.
struct Panel {
    points: [Vec<(f64, f64, f64)>; 3],
    models: Vec<[Vec<(f64, f64)>; 3]>,
    y_desc: &'static str,
    caption: &'static str,
    from_zero: bool,
}

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
    let mut pts = points.to_vec();
    pts.sort_by(|a, b| a.theta_deg.total_cmp(&b.theta_deg));
    let normal = pts.iter().find(|p| p.theta_deg == 0.0).copied();
    let heading = match normal {
        Some(_) => format!(
            "{title}: diffuse reflectance against incidence angle (Monte Carlo ±2 SE; dashed: models)"
        ),
        None => format!("{title}: Rd against incidence angle (±2 SE); no 0° angle, so no ratio"),
    };
    let mut panels: Vec<Panel> = normal.map(|n| ratio(&pts, n, curves)).into_iter().collect();
    panels.push(absolute(&pts, curves));
    let width = if normal.is_some() { 1200 } else { 640 };
    png_of(
        (width, 520),
        &format!("{title} incidence plot"),
        "Bars: Monte Carlo ±2 standard errors; dashed: diffusion models. Above 1 (left): more \
         light returns at that angle than at normal incidence.",
        |root, path| {
            let root = titled(root, path, &heading)?;
            let areas = root.split_evenly((1, panels.len()));
            for (area, panel) in areas.iter().zip(&panels) {
                draw_panel(area, path, panel, curves)?;
            }
            Ok(())
        },
    )
}

/// Only the points with a finite value and error: a channel without reflectance at 0° has no
/// ratio.
fn finite(v: impl Iterator<Item = (f64, f64, f64)>) -> Vec<(f64, f64, f64)> {
    v.filter(|p| p.1.is_finite() && p.2.is_finite()).collect()
}

/// Rd(θ)/Rd(0°) against `normal`; each model's ratio is to its own normal-incidence value.
fn ratio(pts: &[IncidencePoint], n: IncidencePoint, curves: &[IncidenceCurve]) -> Panel {
    let points = [0, 1, 2].map(|c| {
        finite(pts.iter().map(|p| {
            let r = p.rd[c] / n.rd[c];
            let rel = if p.theta_deg == 0.0 {
                0.0
            } else {
                (p.se[c] / p.rd[c]).hypot(n.se[c] / n.rd[c])
            };
            (p.theta_deg, r, 2.0 * r * rel)
        }))
    });
    let models = model_curves(curves, |m| {
        m.points.iter().find(|p| p.0 == 0.0).map(|p| p.1)
    });
    Panel {
        points,
        models,
        y_desc: "Rd(θ)/Rd(0°)",
        caption: "Rd(θ) / Rd(0°), per unit incident power",
        from_zero: false,
    }
}

/// Each model's curve per channel, divided by what `divisor` gives it per channel (nothing: no
/// curve); non-finite values are left out.
fn model_curves(
    curves: &[IncidenceCurve],
    divisor: impl Fn(&IncidenceCurve) -> Option<[f64; 3]>,
) -> Vec<[Vec<(f64, f64)>; 3]> {
    curves
        .iter()
        .map(|m| {
            let d = divisor(m);
            [0, 1, 2].map(|c| {
                m.points
                    .iter()
                    .filter_map(|p| d.map(|d| (p.0, p.1[c] / d[c])))
                    .filter(|p| p.1.is_finite())
                    .collect()
            })
        })
        .collect()
}

/// Rd(θ) itself.
fn absolute(pts: &[IncidencePoint], curves: &[IncidenceCurve]) -> Panel {
    let points =
        [0, 1, 2].map(|c| finite(pts.iter().map(|p| (p.theta_deg, p.rd[c], 2.0 * p.se[c]))));
    let models = model_curves(curves, |_| Some([1.0; 3]));
    Panel {
        points,
        models,
        y_desc: "Rd [-]",
        caption: "Rd(θ), per unit incident power",
        from_zero: true,
    }
}

/// `panel` on `area`: the y range covers every point with its error bar and every model value.
fn draw_panel(area: &Area<'_>, path: &str, panel: &Panel, curves: &[IncidenceCurve]) -> Result<()> {
    let model_values = panel
        .models
        .iter()
        .flatten()
        .flatten()
        .map(|&(_, v)| (v, 0.0));
    let (lo, hi) = match panel
        .points
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
    let y = if panel.from_zero {
        0.0..hi + pad
    } else {
        lo - pad..hi + pad
    };
    let frame = Frame {
        x_area: 45,
        ..Frame::PANEL
    };
    let mut ch = frame.chart(area, path, panel.caption, 0.0..90.0, y)?;
    let y_ticks = if hi.abs() < 0.01 {
        Ticks::Exp(1)
    } else {
        Ticks::Fixed(3)
    };
    let theta = ("incidence angle θ [deg]", Ticks::Fixed(0));
    axes(&mut ch, path, theta, (panel.y_desc, y_ticks))?;
    for c in 0..3 {
        let color = CHANNEL_COLORS[c];
        let line: Vec<(f64, f64)> = panel.points[c].iter().map(|s| (s.0, s.1)).collect();
        line_with_dots(&mut ch, path, &line, color, CHANNELS[c])?;
        // Error bars: a vertical stroke with caps 0.6° wide.
        ch.draw_series(panel.points[c].iter().flat_map(|&(x, v, e)| {
            [
                PathElement::new(vec![(x, v - e), (x, v + e)], color.stroke_width(1)),
                PathElement::new(vec![(x - 0.6, v - e), (x + 0.6, v - e)], color),
                PathElement::new(vec![(x - 0.6, v + e), (x + 0.6, v + e)], color),
            ]
        }))
        .in_plot(path)?;
    }
    for (k, (curve, lines)) in curves.iter().zip(&panel.models).enumerate() {
        draw_model(&mut ch, path, k, &curve.name, lines)?;
    }
    legend(&mut ch, path, SeriesLabelPosition::UpperLeft)
}

/// The `k`-th model's curves, dashed in the channel colours, named once in the legend by a black
/// glyph of its dashes.
fn draw_model<'a, 'b: 'a, X, Y>(
    ch: &mut Chart<'a, 'b, X, Y>,
    path: &str,
    k: usize,
    name: &str,
    lines: &[Vec<(f64, f64)>; 3],
) -> Result<()>
where
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    let (dash, gap) = CURVE_DASHES[k % CURVE_DASHES.len()];
    for (c, line) in lines.iter().enumerate() {
        let mark = Mark::Dashed(CHANNEL_COLORS[c].stroke_width(2), dash, gap);
        let drawn = mark.draw(ch, path, line.iter().copied())?;
        if c == 0 {
            drawn.label(name).legend(move |(x, y)| {
                // The curve's first three dashes, clipped to the 20 px legend glyph, relative to
                // the anchor.
                let (d, g) = (dash as i32, gap as i32);
                let seg = |a: i32| {
                    let a = a.min(20);
                    PathElement::new(vec![(a, 0), ((a + d).min(20), 0)], BLACK.stroke_width(2))
                };
                EmptyElement::at((x, y)) + seg(0) + seg(d + g) + seg(2 * (d + g))
            });
        }
    }
    Ok(())
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
