//! The comparison sheet of a [`gpu::Comparison`]: the ground truth's cut-out, then each rendered
//! image beside its difference from the truth, with a colour bar.

use gpu::Comparison;
use gpu::eval::compare::{Crop, Shown, tone_map};

use crate::error::Result;
use crate::plot::{ColourBar, Sheet, SheetCell};

/// What a comparison sheet's difference images show at full colour: ±10 % of the truth's mean.
const DIFF_RANGE: f32 = 0.1;

/// The comparison sheet of `cmp` as PNG bytes: under `title`, the ground truth's cut-out ([`Crop`],
/// magnified to at least 240 px), then one row per image of `rows` (its label and error,
/// then its difference from the truth, red where brighter and blue where darker, full colour
/// at ±10 % of the truth's mean, with the colour bar underneath). Cut-outs are tone-mapped as
/// the renderer's recombination does ([`tone_map`], `exposure`).
pub fn comparison_sheet(
    cmp: &Comparison,
    title: Vec<String>,
    rows: &[(&str, &Shown)],
    exposure: f32,
) -> Result<Vec<u8>> {
    let Crop { x0, y0, side } = cmp.crop;
    let cell = |label: String, pixel: &dyn Fn(usize) -> [u8; 3]| {
        SheetCell::magnified(label, side, 240, &|x, y| {
            pixel((y0 + y) * cmp.width + x0 + x)
        })
    };
    let picture = |label: String, img: &[[f32; 4]]| {
        cell(label, &|i| {
            tone_map([img[i][0], img[i][1], img[i][2]], exposure)
        })
    };
    let gain = 1.0 / (DIFF_RANGE * cmp.mean.max(1e-12) as f32);
    let difference = |label: String, img: &[[f32; 4]]| {
        cell(label, &|i| {
            let d = (0..3).map(|c| img[i][c] - cmp.truth[i][c]).sum::<f32>() / 3.0 * gain;
            diverging(0.5 + 0.5 * f64::from(d.clamp(-1.0, 1.0)))
        })
    };
    let mut cells = vec![vec![picture("2D ground truth (CPU)".into(), &cmp.truth)]];
    for (label, k) in rows {
        cells.push(vec![
            picture(
                format!(
                    "{label}: RMS {:.2} % of the mean",
                    100.0 * k.error.rms_rel_all
                ),
                &k.shown,
            ),
            difference(format!("{label} − truth"), &k.shown),
        ]);
    }
    let pct = 100.0 * DIFF_RANGE as f64;
    Sheet {
        title,
        rows: cells,
        bars: vec![ColourBar {
            caption: "difference from the truth, mean of R, G, B [% of the truth's mean]".into(),
            ramp: diverging,
            ticks: [-1.0, -0.5, 0.0, 0.5, 1.0]
                .map(|v: f64| (0.5 + 0.5 * v, format!("{:+.0}", v * pct)))
                .to_vec(),
        }],
    }
    .png()
}

/// Blue (t = 0) through white (½) to red (1).
fn diverging(t: f64) -> [u8; 3] {
    let m = ((2.0 * t - 1.0).abs().min(1.0) * 255.0) as u8;
    if t >= 0.5 {
        [255, 255 - m, 255 - m]
    } else {
        [255 - m, 255 - m, 255]
    }
}
