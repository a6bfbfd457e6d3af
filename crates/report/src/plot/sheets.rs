//! Labelled picture sheets: pictures in rows, each with its label above it, under title lines and
//! above colour bars (the convolution sheets, the renderer's comparison sheets, [`image_sheet`]).

use plotters::prelude::*;

use super::{Area, InPlot, font, png_picture};
use crate::error::Result;

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

impl SheetCell {
    /// A square picture of `side` × `side` samples, `pixel(x, y)` each, enlarged (nearest
    /// neighbour, a whole factor) to at least `min_side` [px] so it stays readable beside its
    /// `label`.
    pub(crate) fn magnified(
        label: String,
        side: usize,
        min_side: usize,
        pixel: &dyn Fn(usize, usize) -> [u8; 3],
    ) -> SheetCell {
        let zoom = min_side.div_ceil(side).max(1);
        let s = side * zoom;
        let mut rgb = Vec::with_capacity(s * s * 3);
        for y in 0..s {
            for x in 0..s {
                rgb.extend(pixel(x / zoom, y / zoom));
            }
        }
        SheetCell {
            label,
            width: s as u32,
            height: s as u32,
            rgb,
        }
    }
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
pub(super) const PAD: u32 = 8;
pub(super) const TITLE_LINE: u32 = 24;
pub(super) const LABEL_LINE: u32 = 22;
pub(super) const BAR_HEIGHT: u32 = 16;
/// One colour bar: caption line, ramp, tick marks and values.
pub(super) const BAR_BLOCK: u32 = LABEL_LINE + BAR_HEIGHT + 22;
pub(super) const BAR_WIDTH: u32 = 480;
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

/// Draws `s` with its top left at (x, y) [px] in the embedded font of `size`.
fn text(root: &Area<'_>, path: &str, s: &str, (x, y): (u32, u32), size: u32) -> Result<()> {
    root.draw(&Text::new(
        s.to_string(),
        (x as i32, y as i32),
        ("sans-serif", size).into_font(),
    ))
    .in_plot(path)
}

/// Where a [`Sheet`]'s parts go [px].
pub(super) struct Layout {
    pub(super) width: u32,
    pub(super) height: u32,
    /// Column pitch without padding: the widest picture or label.
    pub(super) column: u32,
    /// Top of each row's label line (its pictures start one label line lower).
    pub(super) row_top: Vec<u32>,
    /// Top of the first colour bar's block.
    pub(super) bars_top: u32,
}

impl Sheet {
    pub(super) fn layout(&self) -> Layout {
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
        let name = format!("sheet {:?}", self.title.first().map_or("", |t| t.as_str()));
        let l = self.layout();
        png_picture((l.width, l.height), &name, |root, path| {
            for (i, t) in self.title.iter().enumerate() {
                text(
                    root,
                    path,
                    t,
                    (PAD, PAD + i as u32 * TITLE_LINE),
                    TITLE_FONT,
                )?;
            }
            for (row, &top) in self.rows.iter().zip(&l.row_top) {
                for (i, c) in row.iter().enumerate() {
                    let x = PAD + i as u32 * (l.column + PAD);
                    draw_cell(root, path, c, (x, top))?;
                }
            }
            for (k, b) in self.bars.iter().enumerate() {
                draw_bar(root, path, b, l.bars_top + k as u32 * BAR_BLOCK)?;
            }
            Ok(())
        })
    }
}

/// `c`'s label with its top left at (x, top) [px], its picture under it, framed so white parts
/// of a picture do not melt into the page.
fn draw_cell(root: &Area<'_>, path: &str, c: &SheetCell, (x, top): (u32, u32)) -> Result<()> {
    text(root, path, &c.label, (x, top), LABEL_FONT)?;
    let (x, y) = (x as i32, (top + LABEL_LINE) as i32);
    let elem = BitMapElement::with_owned_buffer((x, y), (c.width, c.height), c.rgb.clone())
        .ok_or_else(|| {
            format!(
                "{:?}: buffer does not match {}×{}",
                c.label, c.width, c.height
            )
        })
        .in_plot(path)?;
    root.draw(&elem).in_plot(path)?;
    root.draw(&Rectangle::new(
        [(x - 1, y - 1), (x + c.width as i32, y + c.height as i32)],
        RGBColor(150, 150, 150),
    ))
    .in_plot(path)
}

/// Colour bar `b` in its block from `top` [px]: caption, framed ramp, ticks with their values.
fn draw_bar(root: &Area<'_>, path: &str, b: &ColourBar, top: u32) -> Result<()> {
    let x0 = 2 * PAD;
    text(root, path, &b.caption, (PAD, top), LABEL_FONT)?;
    let y0 = (top + LABEL_LINE) as i32;
    for i in 0..BAR_WIDTH {
        let [r, g, bl] = (b.ramp)(f64::from(i) / f64::from(BAR_WIDTH - 1));
        let x = (x0 + i) as i32;
        root.draw(&PathElement::new(
            vec![(x, y0), (x, y0 + BAR_HEIGHT as i32 - 1)],
            RGBColor(r, g, bl),
        ))
        .in_plot(path)?;
    }
    root.draw(&Rectangle::new(
        [
            (x0 as i32 - 1, y0 - 1),
            ((x0 + BAR_WIDTH) as i32, y0 + BAR_HEIGHT as i32),
        ],
        BLACK,
    ))
    .in_plot(path)?;
    for (t, label) in &b.ticks {
        let x = x0 + (t.clamp(0.0, 1.0) * f64::from(BAR_WIDTH - 1)).round() as u32;
        let y = y0 + BAR_HEIGHT as i32;
        root.draw(&PathElement::new(
            vec![(x as i32, y), (x as i32, y + 4)],
            BLACK,
        ))
        .in_plot(path)?;
        let half = text_width(label, TICK_FONT) / 2;
        text(
            root,
            path,
            label,
            (x.saturating_sub(half), (y + 5) as u32),
            TICK_FONT,
        )?;
    }
    Ok(())
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
