//! Radial diffuse reflectance profiles Rd(r): the input of every kernel model.
//!
//! Units: r in cm, Rd in cm⁻² (MCML's `Rd_r`), three channels (R, G, B). Radii are MCML's bin
//! coordinates: bin i covers [i·dr, (i+1)·dr). The last bin of an MC profile also collects every
//! photon beyond the grid, so it is not a sample of Rd(r) and is dropped on load.

use crate::error::{FitError, Result};

/// An RGB radial profile on a uniform radial grid.
#[derive(Clone, Debug, PartialEq)]
pub struct Profile {
    /// Radial bin width [cm].
    pub dr: f64,
    /// Sample radius of each bin [cm] (MCML's optimal coordinate, or the bin centre).
    pub r: Vec<f64>,
    /// Rd(r) per channel [cm⁻²].
    pub rd: [Vec<f64>; 3],
    /// Standard error of Rd(r) per channel [cm⁻²] (0 for analytic profiles).
    pub se: [Vec<f64>; 3],
}

impl Profile {
    /// Reads the CSV written by `sss simulate` (`r_cm,R,G,B,R_se,G_se,B_se`) and checks it can be
    /// fitted ([`Profile::validate`]). The last bin (MCML's overflow bin) is dropped.
    /// `source_name` is used in error messages.
    pub fn from_csv(text: &str, source_name: &str) -> Result<Self> {
        let p = Self::parse_csv(text, source_name)?;
        p.validate()?;
        Ok(p)
    }

    /// Reads the CSV without checking that every channel can be fitted (for plots of any
    /// profile, e.g. a channel that does not scatter at all). Each row must still be usable:
    /// radii positive, finite and increasing, Rd finite, standard errors finite and ≥ 0; the
    /// error names the line, column and value.
    pub fn parse_csv(text: &str, source_name: &str) -> Result<Self> {
        let perr = |line: usize, m: String| FitError::Parse {
            source_name: source_name.into(),
            line,
            message: m,
        };
        let mut lines = text.lines().enumerate();
        let header = lines.next().map(|(_, l)| l.trim()).unwrap_or("");
        if header != "r_cm,R,G,B,R_se,G_se,B_se" {
            return Err(perr(
                1,
                format!("expected header r_cm,R,G,B,R_se,G_se,B_se, found {header:?}"),
            ));
        }
        let mut r: Vec<f64> = Vec::new();
        let mut rd: [Vec<f64>; 3] = Default::default();
        let mut se: [Vec<f64>; 3] = Default::default();
        for (i, line) in lines {
            if line.trim().is_empty() {
                continue;
            }
            let v: Vec<f64> = line
                .split(',')
                .map(|f| f.trim().parse::<f64>())
                .collect::<std::result::Result<_, _>>()
                .map_err(|_| perr(i + 1, format!("not 7 numbers: {line:?}")))?;
            if v.len() != 7 {
                return Err(perr(
                    i + 1,
                    format!("expected 7 columns, found {}", v.len()),
                ));
            }
            // `parse` takes NaN and inf: refuse them here, with the column, so that no
            // plot or lookup meets a non-finite or unordered radius.
            let bad = |column: &str, x: f64, reason: &str| {
                perr(i + 1, format!("{column} = {x:?}: {reason}"))
            };
            if !(v[0].is_finite() && v[0] > 0.0) {
                return Err(bad("r_cm", v[0], "must be positive and finite"));
            }
            match r.last() {
                Some(&prev) if v[0] <= prev => {
                    return Err(bad(
                        "r_cm",
                        v[0],
                        &format!("radii must increase (previous row {prev:?})"),
                    ));
                }
                None if !(v[0] / (0.5 + 1.0 / 6.0)).is_finite() => {
                    return Err(bad("r_cm", v[0], "bin width r/(1/2 + 1/6) overflows"));
                }
                _ => {}
            }
            for (c, ch) in ["R", "G", "B"].iter().enumerate() {
                if !v[1 + c].is_finite() {
                    return Err(bad(ch, v[1 + c], "must be finite"));
                }
                if !(v[4 + c].is_finite() && v[4 + c] >= 0.0) {
                    return Err(bad(
                        &format!("{ch}_se"),
                        v[4 + c],
                        "must be non-negative and finite",
                    ));
                }
            }
            r.push(v[0]);
            for c in 0..3 {
                rd[c].push(v[1 + c]);
                se[c].push(v[4 + c]);
            }
        }
        if r.len() < 3 {
            return Err(FitError::invalid(
                "profile bins",
                r.len(),
                "need at least 3 radial bins",
            ));
        }
        // The bin width follows from MCML's optimal coordinate of bin 0: r₀ = (½ + 1/6)·dr.
        let dr = r[0] / (0.5 + 1.0 / 6.0);
        r.pop();
        for c in 0..3 {
            rd[c].pop();
            se[c].pop();
        }
        Ok(Profile { dr, r, rd, se })
    }

    /// An analytic profile sampled at bin centres (i+½)·dr, i < n.
    pub fn from_fn(dr: f64, n: usize, f: impl Fn(usize, f64) -> f64) -> Self {
        let r: Vec<f64> = (0..n).map(|i| (i as f64 + 0.5) * dr).collect();
        let rd = [0, 1, 2].map(|c| r.iter().map(|&x| f(c, x)).collect());
        Profile {
            dr,
            r,
            rd,
            se: [vec![0.0; n], vec![0.0; n], vec![0.0; n]],
        }
    }

    /// The radius [cm] within which `share` of channel c's light returns, ∫₀^r 2πr'·Rd dr' over
    /// the whole integral (on the bins' radii; the last radius where it is never reached).
    pub fn radius_holding(&self, c: usize, share: f64) -> f64 {
        let total: f64 = self.r.iter().zip(&self.rd[c]).map(|(r, v)| r * v).sum();
        let mut acc = 0.0;
        for (r, v) in self.r.iter().zip(&self.rd[c]) {
            acc += r * v;
            if acc >= share * total {
                return *r;
            }
        }
        *self.r.last().unwrap_or(&0.0)
    }

    /// Refuses profiles no kernel can be built from: fewer than 2 bins, non-finite or negative
    /// values, or every channel zero everywhere. A single channel that is zero everywhere (one
    /// that does not scatter: wine's green and blue) is a profile: its kernel is the identity,
    /// with weight 0 ([`crate::kernel2d::cell_ground_truth`]).
    pub fn validate(&self) -> Result<()> {
        if !(self.dr.is_finite() && self.dr > 0.0) {
            return Err(FitError::invalid("dr", self.dr, "must be positive"));
        }
        if self.r.len() < 2 {
            return Err(FitError::invalid(
                "profile bins",
                self.r.len(),
                "need at least 2 radial bins",
            ));
        }
        for (c, ch) in ["R", "G", "B"].iter().enumerate() {
            if self.rd[c].len() != self.r.len() {
                return Err(FitError::invalid(
                    format!("Rd[{ch}] length"),
                    self.rd[c].len(),
                    "must match r",
                ));
            }
            if let Some((i, v)) = self.rd[c]
                .iter()
                .enumerate()
                .find(|(_, v)| !v.is_finite() || **v < 0.0)
            {
                return Err(FitError::invalid(
                    format!("Rd[{ch}] at r = {} cm", self.r[i]),
                    v,
                    "must be finite and non-negative",
                ));
            }
        }
        if self.rd.iter().all(|ch| ch.iter().all(|&v| v == 0.0)) {
            return Err(FitError::invalid(
                "Rd",
                0,
                "is zero everywhere in every channel: the material returns no diffuse light, no kernel to fit",
            ));
        }
        Ok(())
    }

    /// The profile of three `mc` runs on one grid (R, G, B): Rd(r) with its standard errors at
    /// MCML's optimal radii, without the grid's last bin (everything beyond it), as
    /// [`Profile::from_csv`] reads `sss simulate`'s CSV.
    pub fn from_mc(chans: [&mc::Output; 3]) -> Profile {
        let g = chans[0].grid;
        let n = g.nr - 1;
        let est = |c: usize, i: usize| chans[c].rd_r[i];
        Profile {
            dr: g.dr,
            r: (0..n).map(|i| g.r_optimal(i)).collect(),
            rd: [0, 1, 2].map(|c| (0..n).map(|i| est(c, i).value).collect()),
            se: [0, 1, 2].map(|c| (0..n).map(|i| est(c, i).se).collect()),
        }
    }

    /// The CSV of three `mc` runs on one grid (R, G, B): [`Profile::from_mc`], then the grid's
    /// last bin (everything beyond it) as the overflow row.
    pub fn csv_from_mc(chans: [&mc::Output; 3]) -> String {
        let n = chans[0].grid.nr - 1;
        Profile::from_mc(chans)
            .to_csv([0, 1, 2].map(|c| (chans[c].rd_r[n].value, chans[c].rd_r[n].se)))
    }

    /// The CSV `sss simulate` writes (`r_cm,R,G,B,R_se,G_se,B_se`): one row per bin, then the
    /// overflow bin with `overflow` (Rd [cm⁻²] of everything beyond the grid spread over the
    /// last annulus, as MCML does, standard error 0 when not known) at MCML's optimal coordinate
    /// [(n+½) + 1/(12(n+½))]·dr. [`Profile::parse_csv`] reads it back and drops that row.
    pub fn to_csv(&self, overflow: [(f64, f64); 3]) -> String {
        let mut s = String::from("r_cm,R,G,B,R_se,G_se,B_se\n");
        let row = |s: &mut String, r: f64, v: [(f64, f64); 3]| {
            *s += &format!(
                "{r},{},{},{},{},{},{}\n",
                v[0].0, v[1].0, v[2].0, v[0].1, v[1].1, v[2].1
            );
        };
        for i in 0..self.len() {
            row(
                &mut s,
                self.r[i],
                [0, 1, 2].map(|c| (self.rd[c][i], self.se[c][i])),
            );
        }
        let c = self.len() as f64 + 0.5;
        row(&mut s, (c + 1.0 / (12.0 * c)) * self.dr, overflow);
        s
    }

    /// Total diffuse reflectance of channel `c` within the grid [-]: Σ Rd_i·Aᵢ over the bins,
    /// Aᵢ = π((i+1)² − i²)dr² = 2π(i+½)dr² the area of bin i's annulus [i·dr, (i+1)·dr), the
    /// area MCML divides each bin's weight by. (Not 2π·rᵢ·dr: at MCML's optimal coordinate
    /// rᵢ = (i+½ + 1/(12(i+½)))·dr that overstates bin 0 by a third, Skin1's B total by 3 %.) The
    /// overflow bin, dropped on load, is not included.
    pub fn total(&self, c: usize) -> f64 {
        self.r
            .iter()
            .zip(&self.rd[c])
            .map(|(r, v)| {
                let centre = (r / self.dr).floor() + 0.5;
                v * 2.0 * std::f64::consts::PI * centre * self.dr * self.dr
            })
            .sum()
    }

    /// Number of radial bins.
    pub fn len(&self) -> usize {
        self.r.len()
    }

    /// Whether the profile has no bins.
    pub fn is_empty(&self) -> bool {
        self.r.is_empty()
    }

    /// Rd of channel `c` at radius `r` [cm]: linear interpolation between sample radii, constant
    /// below the first, zero beyond the last.
    pub fn at(&self, c: usize, r: f64) -> f64 {
        let (rs, v) = (&self.r, &self.rd[c]);
        if r <= rs[0] {
            return v[0];
        }
        if r > *rs.last().expect("validated non-empty") {
            return 0.0;
        }
        // The first sample radius ≥ r (at least the second): near r/dr on a grid of bins, where
        // a short walk finds it; a binary search otherwise.
        let above = |i: usize| rs[i] >= r && (i == 1 || rs[i - 1] < r);
        let guess = ((r / self.dr) as usize).clamp(1, rs.len() - 1);
        let i = (guess.saturating_sub(1).max(1)..=(guess + 1).min(rs.len() - 1))
            .find(|&i| above(i))
            .unwrap_or_else(|| rs.partition_point(|&x| x < r).max(1));
        let t = (r - rs[i - 1]) / (rs[i] - rs[i - 1]);
        v[i - 1] + t * (v[i] - v[i - 1])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A profile uniform out to R holds a share s of its light within R·√s (the disc's area),
    /// to within one bin.
    #[test]
    fn a_uniform_disc_holds_a_share_within_r_root_share() {
        let (n, dr) = (1000, 1e-3);
        let r: Vec<f64> = (0..n).map(|i| (i as f64 + 0.5) * dr).collect();
        let p = Profile {
            dr,
            r,
            rd: [vec![1.0; n], vec![2.0; n], vec![0.5; n]],
            se: [vec![0.0; n], vec![0.0; n], vec![0.0; n]],
        };
        for (c, share) in [(0, 0.25f64), (1, 0.5), (2, 0.99)] {
            let expected = n as f64 * dr * share.sqrt();
            assert!(
                (p.radius_holding(c, share) - expected).abs() <= dr,
                "{c} {share}"
            );
        }
    }

    /// The lookup near r/dr finds the same interval as a binary search, on bins' centres, on
    /// MCML's optimal coordinates and on radii that follow no grid.
    #[test]
    fn at_interpolates_between_the_right_samples() {
        let dr = 0.01;
        let grids: [Vec<f64>; 3] = [
            (0..50).map(|i| (i as f64 + 0.5) * dr).collect(),
            (0..50)
                .map(|i| (i as f64 + 0.5 + 1.0 / (12.0 * (i as f64 + 0.5))) * dr)
                .collect(),
            (0..50).map(|i| 1e-3 * 1.2f64.powi(i)).collect(),
        ];
        for r in grids {
            let v: Vec<f64> = r.iter().map(|x| (-x).exp() * (1.0 + x.sin())).collect();
            let p = Profile {
                dr,
                rd: [v.clone(), v.clone(), v],
                se: [vec![0.0; 50], vec![0.0; 50], vec![0.0; 50]],
                r,
            };
            for k in 0..2000 {
                let x = k as f64 * 0.0007 * p.r[49];
                let i = p.r.partition_point(|&y| y < x).clamp(1, 49);
                let want = if x <= p.r[0] {
                    p.rd[0][0]
                } else if x > p.r[49] {
                    0.0
                } else {
                    let t = (x - p.r[i - 1]) / (p.r[i] - p.r[i - 1]);
                    p.rd[0][i - 1] + t * (p.rd[0][i] - p.rd[0][i - 1])
                };
                assert_eq!(p.at(0, x), want, "r = {x}");
            }
        }
    }

    /// The profile's total plus its overflow bin is `mc`'s total diffuse reflectance exactly:
    /// both sum the same photon weights over MCML's annuli.
    #[test]
    fn the_total_is_the_sum_over_mcmls_annuli() {
        let layer = mc::Layer {
            n: 1.3,
            mu_a: 4.8,
            mu_s: 10.1,
            g: 0.0,
            thickness: 1e8,
        };
        let spec = mc::RunSpec {
            sample: mc::Sample {
                n_above: 1.0,
                n_below: 1.0,
                layers: vec![layer],
            },
            grid: mc::Grid {
                dr: 0.01,
                dz: 0.01,
                nr: 40,
                nz: 1,
                na: 1,
            },
            photons: 20_000,
            seed: 3,
            tallies: mc::TallySet::default(),
        };
        let out = mc::run(&spec, &|_| {}).unwrap();
        let p = Profile::parse_csv(&Profile::csv_from_mc([&out, &out, &out]), "t").unwrap();
        let last = spec.grid.nr - 1;
        let overflow =
            out.rd_r[last].value * 2.0 * std::f64::consts::PI * (last as f64 + 0.5) * 1e-4;
        let total = p.total(0) + overflow;
        assert!(
            (total / out.rd.value - 1.0).abs() < 1e-9,
            "{total} against {}",
            out.rd.value
        );
    }
}
