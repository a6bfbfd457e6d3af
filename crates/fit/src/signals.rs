//! Procedural test signals (irradiance images) of thesis §6.2 and supplement Figs. S.3/S.5, on a
//! square image of `size` pixels, values in [0, 1].

use crate::convolve::Image;

/// The test signals, by name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Signal {
    /// Vertical white–black edge through the centre (white on the left).
    Edge,
    /// A circle and two tilted, adjacent squares.
    CircleSquares,
    /// A single white pixel at the centre.
    Dot,
    /// A Lambert-shaded disc with a hard shadow terminator (pronounced shading).
    Shaded,
    /// A uniformly lit patch with fine surface detail.
    Uniform,
}

impl Signal {
    /// Every signal.
    pub const ALL: [Signal; 5] = [
        Signal::Edge,
        Signal::CircleSquares,
        Signal::Dot,
        Signal::Shaded,
        Signal::Uniform,
    ];

    /// The signal's name in reports and file names (`edge`, `circle_squares`, `dot`, `shaded`,
    /// `uniform`).
    pub fn name(self) -> &'static str {
        match self {
            Signal::Edge => "edge",
            Signal::CircleSquares => "circle_squares",
            Signal::Dot => "dot",
            Signal::Shaded => "shaded",
            Signal::Uniform => "uniform",
        }
    }

    /// The signal on a `size` × `size` image, values in [0, 1].
    pub fn image(self, size: usize) -> Image {
        let mut img = Image::new(size, size);
        let s = size as f64;
        for y in 0..size {
            for x in 0..size {
                // Pixel centre in [−1, 1]².
                let (u, v) = (
                    2.0 * (x as f64 + 0.5) / s - 1.0,
                    2.0 * (y as f64 + 0.5) / s - 1.0,
                );
                img.v[y * size + x] = match self {
                    Signal::Edge => f64::from(x < size / 2),
                    Signal::CircleSquares => {
                        let circle = (u + 0.45).powi(2) + v * v < 0.3f64.powi(2);
                        let square = |cx: f64, cy: f64| {
                            let (c, sn) = (0.5f64.cos(), 0.5f64.sin()); // tilted by 0.5 rad
                            let (dx, dy) = (u - cx, v - cy);
                            let (rx, ry) = (c * dx + sn * dy, -sn * dx + c * dy);
                            rx.abs() < 0.17 && ry.abs() < 0.17
                        };
                        f64::from(circle || square(0.35, -0.17) || square(0.5, 0.25))
                    }
                    Signal::Dot => f64::from(x == size / 2 && y == size / 2),
                    Signal::Shaded => {
                        let r2 = u * u + v * v;
                        if r2 < 0.8 * 0.8 {
                            let nz = (1.0 - r2 / 0.64).sqrt();
                            let (nx, ny) = (u / 0.8, v / 0.8);
                            // Light from the upper left; cos ≤ 0 is the shadowed side.
                            (0.7 * -nx + 0.3 * -ny + 0.65 * nz).max(0.0)
                        } else {
                            0.0
                        }
                    }
                    Signal::Uniform => {
                        if u.abs() < 0.7 && v.abs() < 0.7 {
                            0.8 + 0.2 * ((37.0 * u).sin() * (29.0 * v).sin()).signum()
                        } else {
                            0.0
                        }
                    }
                };
            }
        }
        img
    }
}
