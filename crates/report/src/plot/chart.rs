//! What every chart is built of: a [`Frame`] (caption, margin, axis label areas), labelled axes
//! with units and tick formats ([`axes`], [`Ticks`]), the legend box ([`legend`]) and series
//! [`Mark`]s (lines, dashed lines, dots) with their legend glyphs. All sizes are in pixels.

use plotters::chart::SeriesAnno;
use plotters::coord::ranged1d::{AsRangedCoord, Ranged, ValueFormatter};
use plotters::prelude::*;

use super::{Area, InPlot};
use crate::error::Result;

/// A chart on an in-memory picture, with f64 axes of kinds `X` and `Y` (linear or logarithmic).
pub(crate) type Chart<'a, 'b, X, Y> = ChartContext<'a, BitMapBackend<'b>, Cartesian2d<X, Y>>;

/// A series as drawn, to be named in the legend.
pub(crate) type Drawn<'r, 'a, 'b> = &'r mut SeriesAnno<'a, BitMapBackend<'b>>;

/// A chart's frame [px]: caption font size, margin around the chart, and the label areas under
/// the x axis and left of the y axis.
#[derive(Clone, Copy)]
pub(crate) struct Frame {
    /// Caption font size [px].
    pub caption: u32,
    /// Margin around the chart [px].
    pub margin: u32,
    /// Height of the x axis's label area [px].
    pub x_area: u32,
    /// Width of the y axis's label area [px].
    pub y_area: u32,
}

impl Frame {
    /// A chart that fills its picture, or a half of it.
    pub const PAGE: Frame = Frame {
        caption: 18,
        margin: 10,
        x_area: 40,
        y_area: 70,
    };
    /// A cell in a row of panels.
    pub const CELL: Frame = Frame {
        caption: 16,
        margin: 8,
        x_area: 36,
        y_area: 70,
    };
    /// A wide panel, e.g. under a row of cells.
    pub const PANEL: Frame = Frame {
        caption: 16,
        margin: 12,
        x_area: 40,
        y_area: 70,
    };

    /// A chart in this frame on `area`, captioned `caption`, its axes spanning `x` and `y`
    /// (ranges, or `log_scale()` ranges); errors name `path`.
    pub fn chart<'a, 'b, X, Y>(
        self,
        area: &'a Area<'b>,
        path: &str,
        caption: &str,
        x: X,
        y: Y,
    ) -> Result<Chart<'a, 'b, X::CoordDescType, Y::CoordDescType>>
    where
        X: AsRangedCoord<Value = f64>,
        Y: AsRangedCoord<Value = f64>,
    {
        ChartBuilder::on(area)
            .caption(caption, ("sans-serif", self.caption))
            .margin(self.margin)
            .x_label_area_size(self.x_area)
            .y_label_area_size(self.y_area)
            .build_cartesian_2d(x, y)
            .in_plot(path)
    }
}

/// Tick labels of an axis.
#[derive(Clone, Copy)]
pub(crate) enum Ticks<'n> {
    /// plotters' own.
    Auto,
    /// Scientific notation with this many decimals (1e-3 for 0).
    Exp(usize),
    /// Fixed point with this many decimals.
    Fixed(usize),
    /// A categorical axis: one tick per name, at 0, 1, 2, ….
    Names(&'n [String]),
}

/// The label of the value at a tick.
type Formatter<'n> = Box<dyn Fn(&f64) -> String + 'n>;

impl<'n> Ticks<'n> {
    /// The label of the value at a tick, unless plotters labels it itself.
    fn formatter(self) -> Option<Formatter<'n>> {
        match self {
            Ticks::Auto => None,
            Ticks::Exp(d) => Some(Box::new(move |v| format!("{v:.d$e}"))),
            Ticks::Fixed(d) => Some(Box::new(move |v| format!("{v:.d$}"))),
            Ticks::Names(names) => Some(Box::new(move |&x| {
                let i = x.round();
                if (x - i).abs() < 1e-6 && i >= 0.0 {
                    names.get(i as usize).cloned().unwrap_or_default()
                } else {
                    String::new()
                }
            })),
        }
    }
}

/// An axis: what it shows, with its unit in brackets (e.g. "r [cm]"), and its tick labels.
pub(crate) type Axis<'d, 'n> = (&'d str, Ticks<'n>);

/// Draws `ch`'s grid with the axes `x` and `y` labelled; errors name `path`.
pub(crate) fn axes<X, Y>(
    ch: &mut Chart<'_, '_, X, Y>,
    path: &str,
    (x_desc, x_ticks): Axis<'_, '_>,
    (y_desc, y_ticks): Axis<'_, '_>,
) -> Result<()>
where
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let (x_format, y_format) = (x_ticks.formatter(), y_ticks.formatter());
    let mut mesh = ch.configure_mesh();
    mesh.x_desc(x_desc).y_desc(y_desc);
    if let Ticks::Names(names) = x_ticks {
        mesh.x_labels(names.len());
    }
    if let Some(f) = &x_format {
        mesh.x_label_formatter(f);
    }
    if let Some(f) = &y_format {
        mesh.y_label_formatter(f);
    }
    mesh.draw().in_plot(path)
}

/// Draws the legend of `ch`'s named series at `at`: black border, translucent white box.
pub(crate) fn legend<'a, 'b: 'a, X: Ranged, Y: Ranged>(
    ch: &mut Chart<'a, 'b, X, Y>,
    path: &str,
    at: SeriesLabelPosition,
) -> Result<()> {
    ch.configure_series_labels()
        .position(at)
        .border_style(BLACK)
        .background_style(WHITE.mix(0.8))
        .draw()
        .in_plot(path)
}

/// How a series is drawn, and its legend glyph.
#[derive(Clone, Copy)]
pub(crate) enum Mark {
    /// A polyline; legend: a 20 px stroke of the same style.
    Line(ShapeStyle),
    /// A dashed polyline: style, dash and gap [px]; legend: a 20 px solid stroke.
    Dashed(ShapeStyle, u32, u32),
    /// Filled dots: colour, radius [px] and the legend dot's radius [px].
    Dots(RGBColor, u32, u32),
}

impl Mark {
    /// A 2 px line of `color`.
    pub fn line(color: RGBColor) -> Mark {
        Mark::Line(color.stroke_width(2))
    }

    /// Draws `points` (x, y in the chart's units) with this mark on `ch`, not yet named in the
    /// legend; errors name `path`.
    pub fn draw<'r, 'a, 'b: 'a, X, Y, P>(
        self,
        ch: &'r mut Chart<'a, 'b, X, Y>,
        path: &str,
        points: P,
    ) -> Result<Drawn<'r, 'a, 'b>>
    where
        X: Ranged<ValueType = f64>,
        Y: Ranged<ValueType = f64>,
        P: IntoIterator<Item = (f64, f64), IntoIter: Clone>,
    {
        match self {
            Mark::Line(style) => ch.draw_series(LineSeries::new(points, style)),
            Mark::Dashed(style, dash, gap) => {
                ch.draw_series(DashedLineSeries::new(points, dash, gap, style))
            }
            Mark::Dots(color, radius, _) => ch.draw_series(
                points
                    .into_iter()
                    .map(|p| Circle::new(p, radius, color.filled())),
            ),
        }
        .in_plot(path)
    }

    /// Draws `points` with this mark on `ch` and names them `label` in the legend, behind this
    /// mark's glyph; errors name `path`.
    pub fn labelled<'a, 'b: 'a, X, Y, P>(
        self,
        ch: &mut Chart<'a, 'b, X, Y>,
        path: &str,
        points: P,
        label: impl Into<String>,
    ) -> Result<()>
    where
        X: Ranged<ValueType = f64>,
        Y: Ranged<ValueType = f64>,
        P: IntoIterator<Item = (f64, f64), IntoIter: Clone>,
    {
        let drawn = self.draw(ch, path, points)?.label(label);
        match self {
            Mark::Line(style) | Mark::Dashed(style, ..) => {
                drawn.legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style))
            }
            Mark::Dots(color, _, radius) => {
                drawn.legend(move |(x, y)| Circle::new((x + 10, y), radius, color.filled()))
            }
        };
        Ok(())
    }
}

/// Shades the band between `lower` and `upper` (x, y in the chart's units, the same x in order)
/// in a light tint of `color`: a ±1 standard-error band behind a Monte Carlo curve; errors name
/// `path`.
pub(crate) fn band<'a, 'b: 'a, X, Y>(
    ch: &mut Chart<'a, 'b, X, Y>,
    path: &str,
    lower: &[(f64, f64)],
    upper: &[(f64, f64)],
    color: RGBColor,
) -> Result<()>
where
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    let outline: Vec<(f64, f64)> = upper.iter().chain(lower.iter().rev()).copied().collect();
    ch.draw_series(std::iter::once(Polygon::new(
        outline,
        color.mix(0.25).filled(),
    )))
    .in_plot(path)?;
    Ok(())
}

/// A 2 px line of `color` through `points` with a 3 px dot on each, named `label` in the legend
/// (as a line); errors name `path`.
pub(crate) fn line_with_dots<'a, 'b: 'a, X, Y>(
    ch: &mut Chart<'a, 'b, X, Y>,
    path: &str,
    points: &[(f64, f64)],
    color: RGBColor,
    label: impl Into<String>,
) -> Result<()>
where
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    Mark::line(color).labelled(ch, path, points.iter().copied(), label)?;
    Mark::Dots(color, 3, 3).draw(ch, path, points.iter().copied())?;
    Ok(())
}

/// (i · `step`, v) for the i-th of `values`: samples at a pitch of `step` in the x axis's unit.
pub(crate) fn samples(values: &[f64], step: f64) -> impl Iterator<Item = (f64, f64)> + Clone + '_ {
    values
        .iter()
        .enumerate()
        .map(move |(i, &v)| (i as f64 * step, v))
}
