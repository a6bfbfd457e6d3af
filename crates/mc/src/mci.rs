//! MCML's input file (`.mci`, format version 1.0): any number of runs, each with an output file
//! name, photon count, grid and layer stack. Data lines are read in order; blank lines and lines
//! starting with `#` are skipped, and anything after a `#` on a data line is a comment.
//!
//! ```text
//! 1.0                      # file version
//! 1                        # number of runs
//! out.mco  A               # output file name, ASCII
//! 100000                   # photons (an optional second number, MCML's time limit, is ignored)
//! 0.01 0.01                # dz, dr [cm]
//! 40 50 30                 # nz, nr, na
//! 1                        # number of layers
//! 1.0                      # n above
//! 1.37 1.0 100.0 0.9 0.1   # n mua mus g d [-, cm⁻¹, cm⁻¹, -, cm]
//! 1.0                      # n below
//! ```

use crate::error::{McError, Result};
use crate::grid::Grid;
use crate::layer::{Layer, Sample};
use crate::simulate::RunSpec;
use crate::tally::TallySet;

/// Largest count (bins, layers) read from a file: every integer up to 2^53 is exact in f64.
const MAX_COUNT: f64 = 9_007_199_254_740_992.0;

/// 2^64: photon counts must lie below it to fit a `u64`.
const U64_END: f64 = 18_446_744_073_709_551_616.0;

/// One run of an `.mci` file.
#[derive(Clone, Debug, PartialEq)]
pub struct MciRun {
    /// Output file name as written in the `.mci` (relative to the `.mci`'s folder).
    pub out_name: String,
    /// The run (sample, grid, photons, seed).
    pub spec: RunSpec,
}

/// Parses an `.mci` file's text; `source_name` is used in error messages. Every run gets `seed`.
pub fn parse(text: &str, source_name: &str, seed: u64) -> Result<Vec<MciRun>> {
    let mut lines = DataLines::new(text, source_name);
    let version = lines.next_line("file version")?;
    if version.fields.first().map(|v| v.trim()) != Some("1.0") {
        return Err(lines.error(
            version.number,
            format!(
                "unsupported file version {:?}, expected 1.0",
                version.fields.join(" ")
            ),
        ));
    }
    let n_runs: usize = lines.value("number of runs")?;
    if n_runs == 0 {
        return Err(McError::invalid("number of runs", 0, "must be at least 1"));
    }
    // Counts in the file size nothing up front: a run or layer is stored only once its lines
    // have been read, so a count of 10¹⁵ ends at the end of the file, not in the allocator.
    let mut runs = Vec::new();
    for run in 1..=n_runs {
        let ctx = |f: &str| format!("run {run} {f}");
        let name_line = lines.next_line(&format!("run {run} of {n_runs} output file name"))?;
        let out_name = name_line.fields[0].to_string();
        if let Some(fmt) = name_line.fields.get(1)
            && !fmt.eq_ignore_ascii_case("a")
        {
            return Err(lines.error(
                name_line.number,
                format!("output format {fmt:?} is not supported; use A (ASCII)"),
            ));
        }
        let photons_f: f64 = lines.value(&ctx("number of photons"))?;
        if !((1.0..U64_END).contains(&photons_f) && photons_f.fract() == 0.0) {
            return Err(McError::invalid(
                ctx("number of photons"),
                McError::number(photons_f),
                "must be a positive integer below 2^64",
            ));
        }
        let [dz, dr]: [f64; 2] = lines.values(&ctx("dz dr"))?;
        let [nz, nr, na]: [f64; 3] = lines.values(&ctx("nz nr na"))?;
        let count = |field: &str, v: f64| -> Result<usize> {
            if (1.0..=MAX_COUNT).contains(&v) && v.fract() == 0.0 {
                Ok(v as usize)
            } else {
                Err(McError::invalid(
                    ctx(field),
                    McError::number(v),
                    "must be a positive integer up to 2^53",
                ))
            }
        };
        let grid = Grid {
            dr,
            dz,
            nr: count("nr", nr)?,
            nz: count("nz", nz)?,
            na: count("na", na)?,
        };
        let n_layers: f64 = lines.value(&ctx("number of layers"))?;
        let n_layers = count("number of layers", n_layers)?;
        let n_above: f64 = lines.value(&ctx("n above"))?;
        let mut layers = Vec::new();
        for i in 1..=n_layers {
            let [n, mu_a, mu_s, g, thickness]: [f64; 5] =
                lines.values(&ctx(&format!("layer {i} of {n_layers}")))?;
            layers.push(Layer {
                n,
                mu_a,
                mu_s,
                g,
                thickness,
            });
        }
        let n_below: f64 = lines.value(&ctx("n below"))?;
        let spec = RunSpec {
            sample: Sample {
                n_above,
                n_below,
                layers,
            },
            grid,
            photons: photons_f as u64,
            seed,
            tallies: TallySet {
                absorption_rz: true,
                // MCML's .mco carries no standard errors of A(r, z): sum it as MCML does.
                absorption_rz_se: false,
                surface_xy: 0,
            },
        };
        spec.validate().map_err(|e| match e {
            McError::InvalidValue {
                field,
                value,
                reason,
            } => McError::InvalidValue {
                field: ctx(&field),
                value,
                reason,
            },
            other => other,
        })?;
        runs.push(MciRun { out_name, spec });
    }
    Ok(runs)
}

/// Writes runs as an `.mci` file that MCML itself can read.
pub fn write(runs: &[MciRun]) -> String {
    use crate::cfmt::c_g;
    let mut s = format!(
        "1.0\t\t\t\t\t\t# file version\n{}\t\t\t\t\t\t# number of runs\n\n",
        runs.len()
    );
    for (k, r) in runs.iter().enumerate() {
        let g = &r.spec.grid;
        let smp = &r.spec.sample;
        s += &format!("#### SPECIFY DATA FOR RUN {}\n", k + 1);
        s += &format!("{}\tA\t\t\t\t# output file name, ASCII.\n", r.out_name);
        s += &format!("{}\t\t\t\t\t# No. of photons\n", r.spec.photons);
        s += &format!("{}\t{}\t\t\t\t# dz, dr [cm]\n", c_g(g.dz, 6), c_g(g.dr, 6));
        s += &format!("{}\t{}\t{}\t\t\t# No. of dz, dr, da.\n\n", g.nz, g.nr, g.na);
        s += &crate::mco::layers(smp);
    }
    s
}

struct Line<'a> {
    number: usize,
    fields: Vec<&'a str>,
}

struct DataLines<'a> {
    iter: std::iter::Enumerate<std::str::Lines<'a>>,
    source: &'a str,
}

impl<'a> DataLines<'a> {
    fn new(text: &'a str, source: &'a str) -> Self {
        DataLines {
            iter: text.lines().enumerate(),
            source,
        }
    }

    fn error(&self, line: usize, message: String) -> McError {
        McError::parse(self.source, line, message)
    }

    fn next_line(&mut self, what: &str) -> Result<Line<'a>> {
        for (i, raw) in self.iter.by_ref() {
            let data = raw.split('#').next().unwrap_or("").trim();
            if !data.is_empty() {
                return Ok(Line {
                    number: i + 1,
                    fields: data.split_whitespace().collect(),
                });
            }
        }
        Err(McError::parse(
            self.source,
            0,
            format!("unexpected end of file: expected {what}"),
        ))
    }

    fn values<const N: usize>(&mut self, what: &str) -> Result<[f64; N]> {
        let line = self.next_line(what)?;
        if line.fields.len() < N {
            return Err(self.error(
                line.number,
                format!(
                    "{what}: expected {N} number(s), found {:?}",
                    line.fields.join(" ")
                ),
            ));
        }
        let mut out = [0.0; N];
        for (o, f) in out.iter_mut().zip(&line.fields) {
            *o = f
                .parse()
                .map_err(|_| self.error(line.number, format!("{what}: {f:?} is not a number")))?;
        }
        Ok(out)
    }

    fn value<T: std::str::FromStr>(&mut self, what: &str) -> Result<T> {
        let line = self.next_line(what)?;
        let f = line.fields[0];
        f.parse()
            .map_err(|_| self.error(line.number, format!("{what}: {f:?} is not a valid number")))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SAMPLE: &str = "1.0 # version\n\n2 # runs\n\n# run 1\na.mco A\n1000\n0.01 0.02\n10 20 5\n2\n1.0\n1.37 1 100 0.9 0.1 # layer 1\n1.4 2 10 0 0.2\n1.0\n\nb.mco\tA\n50 1\n0.1 0.1\n1 2 3\n1\n1\n1.5 10 90 0.75 0.02\n1\n";

    #[test]
    fn parses_multi_run_multi_layer_files_and_round_trips() {
        let runs = parse(SAMPLE, "t.mci", 7).unwrap();
        assert_eq!(runs.len(), 2);
        assert_eq!(runs[0].out_name, "a.mco");
        assert_eq!(
            runs[0].spec.grid,
            Grid {
                dz: 0.01,
                dr: 0.02,
                nz: 10,
                nr: 20,
                na: 5
            }
        );
        assert_eq!(
            runs[0].spec.sample.layers[1],
            Layer {
                n: 1.4,
                mu_a: 2.0,
                mu_s: 10.0,
                g: 0.0,
                thickness: 0.2
            }
        );
        assert_eq!(runs[1].spec.photons, 50);
        let again = parse(&write(&runs), "w.mci", 7).unwrap();
        assert_eq!(again, runs);
    }

    #[test]
    fn errors_name_the_field() {
        let bad = SAMPLE.replace("1.37 1 100 0.9 0.1", "1.37 -1 100 0.9 0.1");
        let e = parse(&bad, "t.mci", 1).unwrap_err().to_string();
        assert!(e.contains("run 1 layer 1 mu_a") && e.contains("-1"), "{e}");
        let e = parse(&SAMPLE.replace("0.01 0.02", "0.01 x"), "t.mci", 1)
            .unwrap_err()
            .to_string();
        assert!(e.contains("t.mci:8") && e.contains("\"x\""), "{e}");
        assert!(
            parse("1.0\n1\na A\n", "t.mci", 1)
                .unwrap_err()
                .to_string()
                .contains("end of file")
        );
        assert!(
            parse(&SAMPLE.replace("1000\n", "0\n"), "t.mci", 1)
                .unwrap_err()
                .to_string()
                .contains("photons")
        );
    }
}
