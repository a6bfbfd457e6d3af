//! Convolution sheets (thesis Figs. 6.3–6.10): a test signal convolved with the 2D ground truth
//! and with each model, and each model's difference from the ground truth, all three channels at
//! once.

use fit::KernelModel;
use fit::convolve::Image;
use fit::evaluate::Evaluation;
use fit::signals::Signal;

use super::err;
use super::sheets::{ColourBar, Sheet, SheetCell};
use crate::error::Result;

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

/// A grey ramp in display values.
fn grey(t: f64) -> [u8; 3] {
    [display(t); 3]
}

/// The signal, its convolution with the ground truth and with a model, per channel.
type Convolved = Vec<(Image, Image, Image)>;

/// A sheet panel: `rgb(x, y)` linear per channel, in display values, enlarged to ≥ 200 px.
fn panel(label: String, size: usize, rgb: &dyn Fn(usize, usize) -> [f64; 3]) -> SheetCell {
    SheetCell::magnified(label, size, 200, &|x, y| rgb(x, y).map(display))
}

/// Five ticks from 0 to `top`; "≥" on the last where brighter values are clipped.
fn ticks(top: f64, clipped: bool) -> Vec<(f64, String)> {
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
}

/// The labelled sheet of one test signal (see [`convolutions`]).
fn convolution_sheet(
    ev: &Evaluation,
    models: &[KernelModel],
    signal: Signal,
    gain: f64,
    title: &str,
) -> Result<Sheet> {
    let path = format!("{title} convolution sheet");
    let convolved = |m: &KernelModel| -> Result<Convolved> {
        (0..3)
            .map(|c| {
                let k = ev
                    .kernel(*m, c)
                    .ok_or_else(|| err(&path, format!("{m} was not evaluated")))?;
                Ok(ev.images[c].images(signal, k))
            })
            .collect()
    };
    let size = ev.images[0].size;
    let first = models
        .first()
        .ok_or_else(|| err(&path, "no models to show"))?;
    let reference = convolved(first)?;
    let mut rows = vec![vec![
        panel(format!("input: {}", signal_title(signal)), size, &|x, y| {
            [0, 1, 2].map(|c| reference[c].0.at(x, y))
        }),
        panel("2D ground truth ⊛ input".into(), size, &|x, y| {
            [0, 1, 2].map(|c| reference[c].1.at(x, y))
        }),
    ]];
    let (mut products, mut differences) = (Vec::new(), Vec::new());
    for m in models {
        let name = ev
            .row(*m, 0)
            .ok_or_else(|| err(&path, format!("{m} was not evaluated")))?
            .title();
        let imgs = convolved(m)?;
        products.push(panel(format!("{name} ⊛ input"), size, &|x, y| {
            [0, 1, 2].map(|c| imgs[c].2.at(x, y))
        }));
        differences.push(panel(
            format!("|{name} − truth| × {gain}"),
            size,
            &|x, y| [0, 1, 2].map(|c| gain * (imgs[c].2.at(x, y) - imgs[c].1.at(x, y)).abs()),
        ));
    }
    rows.extend([products, differences]);
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
        rows,
        bars: vec![
            ColourBar {
                caption: "rows 1–2: reflected irradiance per channel, relative to the input's maximum [-]"
                    .into(),
                ramp: grey,
                ticks: ticks(1.0, false),
            },
            ColourBar {
                caption: format!(
                    "row 3: |model − ground truth| per channel, relative to the input's maximum [-], drawn × {gain}"
                ),
                ramp: grey,
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plot::sheets::{BAR_BLOCK, BAR_HEIGHT, BAR_WIDTH, LABEL_LINE, PAD, TITLE_LINE};
    use fit::Profile;
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
}
