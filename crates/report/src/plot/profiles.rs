//! Rd(r) figures: one profile per channel (thesis Fig. 6.1), analytic profiles against Monte
//! Carlo, and the energy a pixel grid gathers from a profile against the pixel pitch (Maisch &
//! Ropinski's Fig. 2).

use plotters::prelude::*;

use fit::Profile;

use super::chart::{Axis, Frame, Mark, Ticks, axes, band, legend};
use super::{Area, CHANNEL_COLORS, channel_label, model_color, png_of};
use crate::error::Result;
use mc::CHANNELS;

/// Rd(r) per channel with ±1 standard-error bands: the light returned per unit radius, 2πr·Rd(r),
/// out to where 99 % of the widest channel's light has returned (left; its area is the total
/// reflectance), and Rd(r) on a logarithmic axis over the whole range (right), with a caption
/// saying how to read them. As PNG bytes.
pub fn profile(p: &Profile, title: &str) -> Result<Vec<u8>> {
    png_of(
        (1200, 480),
        &format!("{title} profile plot"),
        "Shaded: ±1 standard error. Left: where the light returns (each curve's area is that \
         channel's total reflectance); right: how fast Rd(r) falls off.",
        |root, path| draw_profile(root, path, p, title),
    )
}

fn draw_profile(root: &Area<'_>, path: &str, p: &Profile, title: &str) -> Result<()> {
    let (left, right) = root.split_horizontally(600);
    let r_end = *p.r.last().unwrap_or(&1.0);
    let near = (0..3)
        .map(|c| p.radius_holding(c, 0.99))
        .fold(0.0, f64::max)
        .min(r_end);
    let tau = 2.0 * std::f64::consts::PI;
    let weighted = |c: usize, k: f64| -> Vec<(f64, f64)> {
        (p.r.iter().zip(&p.rd[c]).zip(&p.se[c]))
            .filter(|((r, _), _)| **r <= near)
            .map(|((&r, &v), &e)| (r, tau * r * (v + k * e)))
            .collect()
    };
    let max = (0..3)
        .flat_map(|c| weighted(c, 1.0))
        .map(|(_, y)| y)
        .fold(0.0, f64::max);
    let caption = format!("{title}: 2πr·Rd(r), the light returned per cm of radius");
    let mut ch = Frame::PAGE.chart(&left, path, &caption, 0.0..near, 0.0..max * 1.05)?;
    axes(
        &mut ch,
        path,
        ("r [cm]", Ticks::Auto),
        ("2πr·Rd [1/cm]", Ticks::Auto),
    )?;
    for c in 0..3 {
        band(
            &mut ch,
            path,
            &weighted(c, -1.0),
            &weighted(c, 1.0),
            CHANNEL_COLORS[c],
        )?;
        Mark::line(CHANNEL_COLORS[c]).labelled(
            &mut ch,
            path,
            weighted(c, 0.0),
            channel_label(c),
        )?;
    }
    legend(&mut ch, path, SeriesLabelPosition::UpperRight)?;

    let values = || p.rd.iter().flatten().copied();
    let max = values().fold(0.0f64, f64::max);
    let min_pos = values().filter(|&v| v > 0.0).fold(f64::INFINITY, f64::min);
    let floor = min_pos.max(max * 1e-12);
    let caption = format!("{title}: Rd(r), log scale");
    let y = (floor..max * 2.0).log_scale();
    let mut ch = Frame::PAGE.chart(&right, path, &caption, 0.0..r_end, y)?;
    axes(
        &mut ch,
        path,
        ("r [cm]", Ticks::Auto),
        ("Rd [1/cm²]", Ticks::Exp(0)),
    )?;
    for c in 0..3 {
        let shown = |k: f64| -> Vec<(f64, f64)> {
            (p.r.iter().zip(&p.rd[c]).zip(&p.se[c]))
                .filter(|((_, v), _)| **v > 0.0)
                .map(|((&r, &v), &e)| (r, (v + k * e).max(floor)))
                .collect()
        };
        band(&mut ch, path, &shown(-1.0), &shown(1.0), CHANNEL_COLORS[c])?;
        Mark::line(CHANNEL_COLORS[c]).draw(&mut ch, path, shown(0.0))?;
    }
    Ok(())
}

/// How far [`profile_comparison`] reaches [transport mean free paths].
const X_MAX_MFP: f64 = 10.0;

/// [`profile_comparison`]'s x axis: r in transport mean free paths.
const R_MFP: Axis<'static, 'static> = ("r [transport MFP]", Ticks::Auto);

/// The frame of [`profile_comparison`]'s panels.
const COMPARISON: Frame = Frame {
    x_area: 30,
    y_area: 60,
    ..Frame::CELL
};

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
        "Top: r·Rd(r) of each analytic profile against Monte Carlo; bottom: model/MC − 1 (0 is \
         exact). Radii in transport mean free paths, so the channels compare.",
        |root, path| {
            let (top, bottom) = root.split_vertically(480);
            let (top, bottom) = (top.split_evenly((1, 3)), bottom.split_evenly((1, 3)));
            for c in 0..3 {
                let channel = Compared {
                    c,
                    mc,
                    models,
                    mfp: mfp[c],
                };
                channel.draw_weighted_profiles(&top[c], path, title)?;
                channel.draw_relative_errors(&bottom[c], path)?;
            }
            Ok(())
        },
    )
}

/// One channel `c` of [`profile_comparison`]: Monte Carlo's profile, the named models' and the
/// channel's transport mean free path `mfp` [cm], the unit of r.
struct Compared<'p> {
    c: usize,
    mc: &'p Profile,
    models: &'p [(&'p str, &'p Profile)],
    mfp: f64,
}

impl Compared<'_> {
    /// r·Rd(r) [1/cm], log scale: Monte Carlo as dots, the models as lines; the legend on the
    /// first channel.
    fn draw_weighted_profiles(&self, area: &Area<'_>, path: &str, title: &str) -> Result<()> {
        let Compared { c, mfp, .. } = *self;
        let pts = |p: &Profile| -> Vec<(f64, f64)> {
            p.r.iter()
                .zip(&p.rd[c])
                .map(|(&r, &v)| (r / mfp, r * v))
                .filter(|&(x, v)| x <= X_MAX_MFP && v > 0.0)
                .collect()
        };
        let mc_pts = pts(self.mc);
        let hi = mc_pts.iter().fold(0.0f64, |a, p| a.max(p.1));
        let lo = mc_pts.iter().fold(f64::INFINITY, |a, p| a.min(p.1));
        let floor = lo.max(hi * 1e-8);
        let caption = format!("{title}, channel {}: r·Rd(r)", CHANNELS[c]);
        let y = (floor.max(1e-300)..hi * 3.0).log_scale();
        let mut ch = COMPARISON.chart(area, path, &caption, 0.0..X_MAX_MFP, y)?;
        axes(&mut ch, path, R_MFP, ("r·Rd [1/cm]", Ticks::Exp(0)))?;
        let every = (mc_pts.len() / 80).max(1);
        let dots = mc_pts.iter().copied().step_by(every);
        Mark::Dots(BLACK, 2, 3).labelled(&mut ch, path, dots, "Monte Carlo")?;
        for (m, (name, p)) in self.models.iter().enumerate() {
            let line = pts(p).into_iter().filter(|&(_, v)| v >= floor);
            Mark::line(model_color(m)).labelled(&mut ch, path, line, *name)?;
        }
        if c == 0 {
            legend(&mut ch, path, SeriesLabelPosition::MiddleRight)?;
        }
        Ok(())
    }

    /// model / MC − 1 [-], clamped to ±1, where MC's standard error is under 5 %.
    fn draw_relative_errors(&self, area: &Area<'_>, path: &str) -> Result<()> {
        let Compared { c, mc, mfp, .. } = *self;
        let frame = Frame {
            caption: 14,
            ..COMPARISON
        };
        let caption = format!("channel {}: relative error of each model", CHANNELS[c]);
        let mut ch = frame.chart(area, path, &caption, 0.0..X_MAX_MFP, -1.0..1.0)?;
        axes(&mut ch, path, R_MFP, ("model / MC − 1 [-]", Ticks::Auto))?;
        let zero = [(0.0, 0.0), (X_MAX_MFP, 0.0)];
        Mark::Line(BLACK.into()).draw(&mut ch, path, zero)?;
        for (m, (_, p)) in self.models.iter().enumerate() {
            let line = (0..mc.len().min(p.len()))
                .filter(|&i| mc.rd[c][i] > 0.0 && mc.se[c][i] < 0.05 * mc.rd[c][i])
                .map(|i| {
                    let error = p.rd[c][i] / mc.rd[c][i] - 1.0;
                    (mc.r[i] / mfp, error.clamp(-1.0, 1.0))
                })
                .filter(|&(x, _)| x <= X_MAX_MFP);
            Mark::line(model_color(m)).draw(&mut ch, path, line)?;
        }
        Ok(())
    }
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
        "Thin: point sampling drifts with the pixel's size, per channel (a colour shift when \
         zooming); thick: area pre-integration stays at 1.",
        |root, path| draw_area_effect(root, path, curves, title),
    )
}

fn draw_area_effect(
    root: &Area<'_>,
    path: &str,
    curves: &[Vec<(f64, f64, f64)>; 3],
    title: &str,
) -> Result<()> {
    let all = curves.iter().flatten();
    let (x0, x1) = all.clone().fold((f64::INFINITY, 0.0f64), |(a, b), p| {
        (a.min(p.0), b.max(p.0))
    });
    let y1 = all
        .clone()
        .fold(1.2f64, |a, p| a.max(p.1).max(p.2))
        .min(4.0);
    let y0 = all.fold(0.8f64, |a, p| a.min(p.1).min(p.2)).max(0.0);
    let frame = Frame {
        margin: 12,
        y_area: 60,
        ..Frame::PAGE
    };
    let caption = format!("{title}: energy a pixel grid gathers / profile total");
    let (x, y) = ((x0..x1).log_scale(), (y0..y1).log_scale());
    let mut ch = frame.chart(root, path, &caption, x, y)?;
    let pitch = ("pixel pitch [cm] (camera zooming out →)", Ticks::Exp(0));
    axes(&mut ch, path, pitch, ("gathered / total", Ticks::Fixed(2)))?;
    for c in 0..3 {
        let color = CHANNEL_COLORS[c];
        let point = curves[c].iter().map(|p| (p.0, p.1));
        let area = curves[c].iter().map(|p| (p.0, p.2));
        let label = |what: &str| format!("{} {what}", CHANNELS[c]);
        let thin = Mark::Line(color.mix(0.5).stroke_width(1));
        thin.labelled(&mut ch, path, point, label("point-sampled"))?;
        let thick = Mark::Line(color.stroke_width(3));
        thick.labelled(&mut ch, path, area, label("area pre-integrated"))?;
    }
    legend(&mut ch, path, SeriesLabelPosition::MiddleRight)
}
