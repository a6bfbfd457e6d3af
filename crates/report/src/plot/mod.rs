//! Comparison plots as PNG (plotters, bitmap backend, an embedded DejaVu Sans so output does not
//! depend on system fonts): profiles (thesis Fig. 6.1), kernel slices against the ground truth
//! (Fig. 6.2), singular-value decay (Fig. 5.1), convolution/difference sheets (Fig. 6.3–6.10),
//! guided optimization against pre-integration (Fig. 5.15, [`imitation`]), the manual model's w
//! sweep (Fig. 5.17, [`w_sweep`]) and total diffuse reflectance against the incidence angle
//! ([`incidence`]). Every plot is returned as PNG bytes: the caller decides where, and whether, it
//! is written.
//!
//! One file per figure family — `profiles` (Rd(r), against models and as a pixel grid gathers
//! it), `kernels` (slices and singular values), `convolutions` (test signals through each model),
//! `incidence`, `studies` (the thesis's chapter-5 model studies) and `sheets` (labelled picture
//! grids with colour bars) — built on the pieces here: the canvas and its PNG encoding, error
//! naming and the palette, and in `chart` the chart frame, labelled axes, legend and series marks.

pub(crate) mod chart;
mod convolutions;
mod incidence;
mod kernels;
mod profiles;
mod sheets;
mod studies;

use std::sync::Once;

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::{FontStyle, register_font};

use mc::CHANNELS;

use crate::error::{ReportError, Result};
use crate::image::png_8bit;

pub use convolutions::convolutions;
pub use incidence::{IncidenceCurve, IncidencePoint, incidence};
pub use kernels::{singular_values, slices};
pub use profiles::{area_effect, profile, profile_comparison};
pub use sheets::{ColourBar, Sheet, SheetCell, image_sheet};
pub use studies::{imitation, w_sweep};

static FONT: Once = Once::new();

/// Colours of the channels R, G, B.
const CHANNEL_COLORS: [RGBColor; 3] = [
    RGBColor(220, 40, 40),
    RGBColor(30, 160, 60),
    RGBColor(40, 80, 220),
];

/// Colours of compared models, through [`model_color`]; black, first, is the reference's.
const MODEL_COLORS: [RGBColor; 6] = [
    RGBColor(0, 0, 0),
    RGBColor(230, 120, 0),
    RGBColor(0, 150, 200),
    RGBColor(160, 0, 160),
    RGBColor(120, 120, 0),
    RGBColor(0, 160, 100),
];

/// Colour of the `m`-th compared model: the palette after the reference's black, cycling.
fn model_color(m: usize) -> RGBColor {
    MODEL_COLORS[(m + 1) % MODEL_COLORS.len()]
}

/// Legend name of channel `c`, e.g. "channel R".
fn channel_label(c: usize) -> String {
    format!("channel {}", CHANNELS[c])
}

/// Registers the embedded font as "sans-serif" (once).
pub(crate) fn font() {
    FONT.call_once(|| {
        let _ = register_font(
            "sans-serif",
            FontStyle::Normal,
            include_bytes!("../../../../assets/DejaVuSans.ttf"),
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

/// A plotting result whose error names the picture.
pub(crate) trait InPlot<T> {
    /// The value, or a [`ReportError::Plot`] naming `path`.
    fn in_plot(self, path: &str) -> Result<T>;
}

impl<T, E: std::fmt::Display> InPlot<T> for std::result::Result<T, E> {
    fn in_plot(self, path: &str) -> Result<T> {
        self.map_err(|e| err(path, e))
    }
}

/// A drawing area on an in-memory RGB picture.
pub(crate) type Area<'a> = DrawingArea<BitMapBackend<'a>, Shift>;

/// The part of `root` under `heading` (20 px); errors name `path`.
fn titled<'a>(root: &Area<'a>, path: &str, heading: &str) -> Result<Area<'a>> {
    root.titled(heading, ("sans-serif", 20)).in_plot(path)
}

/// The height of a figure's caption line [px].
pub(crate) const CAPTION_PX: u32 = 26;

/// The part of `root` above a one-line caption saying how to read the figure, drawn in its
/// bottom [`CAPTION_PX`]; errors name `path`.
fn captioned<'a>(root: &Area<'a>, path: &str, how_to_read: &str) -> Result<Area<'a>> {
    let h = root.dim_in_pixel().1;
    let (figure, caption) = root.split_vertically(h.saturating_sub(CAPTION_PX));
    let style = ("sans-serif", 15).into_font().color(&BLACK.mix(0.8));
    let text = Text::new(how_to_read.to_string(), (10, 4), style);
    caption.draw(&text).in_plot(path)?;
    Ok(figure)
}

/// The part of `root` under `heading` as a row of three cells, one per channel, `height` [px]
/// tall, and the area below it; errors name `path`.
fn channel_row<'a>(
    root: &Area<'a>,
    path: &str,
    heading: &str,
    height: u32,
) -> Result<(Vec<Area<'a>>, Area<'a>)> {
    let (top, bottom) = titled(root, path, heading)?.split_vertically(height);
    Ok((top.split_evenly((1, 3)), bottom))
}

/// Draws a figure of `size` [px] with `draw` on a white page, the font loaded, with a one-line
/// caption under it saying how to read it ([`CAPTION_PX`] more), and returns it as PNG bytes; `path`
/// names it in errors. Every chart is drawn through here, so none goes without its caption.
pub(crate) fn png_of(
    size: (u32, u32),
    path: &str,
    how_to_read: &str,
    draw: impl FnOnce(&Area<'_>, &str) -> Result<()>,
) -> Result<Vec<u8>> {
    png_picture((size.0, size.1 + CAPTION_PX), path, |root, path| {
        let figure = captioned(root, path, how_to_read)?;
        draw(&figure, path)
    })
}

/// Draws a picture of `size` [px] with `draw` on a white page, the font loaded, and returns it as
/// PNG bytes; `path` names it in errors (sheets, which carry their own title lines).
pub(crate) fn png_picture(
    size: (u32, u32),
    path: &str,
    draw: impl FnOnce(&Area<'_>, &str) -> Result<()>,
) -> Result<Vec<u8>> {
    font();
    let mut rgb = vec![0u8; (size.0 * size.1 * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area();
        root.fill(&WHITE).in_plot(path)?;
        draw(&root, path)?;
        root.present().in_plot(path)?;
    }
    png_8bit(png::ColorType::Rgb, size, &rgb, path)
}

/// A material's evaluation plots, each as (file name, PNG): the profile, the rank-1 and
/// multi-pass kernel slices, the singular values and the convolution sheets of the edge and
/// circles-and-squares signals (what `sss eval --plots` and `sss reproduce` write per material).
pub fn evaluation(
    p: &fit::Profile,
    ev: &fit::evaluate::Evaluation,
    slug: &str,
) -> crate::Result<Vec<(String, Vec<u8>)>> {
    use fit::KernelModel;
    use fit::evaluate::RANK1;
    use fit::signals::Signal;
    let multipass = [
        KernelModel::Svd {
            rank: 3,
            renormalize: false,
        },
        KernelModel::Deon { n: 3 },
        KernelModel::Burley { radial: true },
    ];
    let mut out = vec![
        (format!("{slug}.profile.png"), profile(p, slug)?),
        (
            format!("{slug}.slices_rank1.png"),
            slices(ev, &RANK1, slug)?,
        ),
        (
            format!("{slug}.slices_multipass.png"),
            slices(ev, &multipass, slug)?,
        ),
        (
            format!("{slug}.singular_values.png"),
            singular_values(ev, slug)?,
        ),
    ];
    for s in [Signal::Edge, Signal::CircleSquares] {
        out.push((
            format!("{slug}.conv_{}.png", s.name()),
            convolutions(ev, &RANK1, s, 10.0, slug)?,
        ));
    }
    Ok(out)
}
