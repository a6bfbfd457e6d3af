//! MCML's output file (`.mco`, ASCII format "A1"): the same sections, order, comment lines and
//! number formats as MCML 1.2.2's `WriteResult`, so outputs can be diffed against MCML's.
//! Standard errors have no place in this format; they go to the CSV/JSON outputs.

use crate::cfmt::{c_e, c_g};
use crate::error::{McError, Result};
use crate::output::{Estimate, Output};
use crate::simulate::RunSpec;

/// The layer block of MCML's `InParm` (count, ambient indices, one line per layer), as MCML
/// writes it; `.mci` files use the same lines.
pub(crate) fn layers(smp: &crate::layer::Sample) -> String {
    let mut s = format!("{}\t\t\t\t\t# Number of layers\n", smp.layers.len());
    s += "#n\tmua\tmus\tg\td\t# One line for each layer\n";
    s += &format!("{}\t\t\t\t\t# n for medium above\n", c_g(smp.n_above, 6));
    for (i, l) in smp.layers.iter().enumerate() {
        s += &format!(
            "{}\t{}\t{}\t{}\t{}\t# layer {}\n",
            c_g(l.n, 6),
            c_g(l.mu_a, 6),
            c_g(l.mu_s, 6),
            c_g(l.g, 6),
            c_g(l.thickness, 6),
            i + 1
        );
    }
    s += &format!("{}\t\t\t\t\t# n for medium below\n\n", c_g(smp.n_below, 6));
    s
}

/// Renders a run as MCML would write it. Needs the (r, z) absorption tallies.
pub fn write(out_name: &str, spec: &RunSpec, out: &Output, seconds: f64) -> Result<String> {
    if out.a_rz.is_empty() {
        return Err(McError::invalid(
            "tallies",
            "absorption_rz = false",
            "an .mco file needs the A(r,z) tally",
        ));
    }
    let g = &out.grid;
    let (nr, nz, na) = (g.nr, g.nz, g.na);
    let mut s = String::with_capacity(16 * (nr * (nz + 2 * na) + 4 * nr));
    s += "A1 \t# Version number of the file format.\n\n";
    s += "####\n# Data categories include: \n# InParm, RAT, \n# A_l, A_z, Rd_r, Rd_a, Tt_r, Tt_a, \n# A_rz, Rd_ra, Tt_ra \n####\n\n";
    s += &format!(
        "# User time: {:8.0} sec = {:8.2} hr.  Simulation time of this run.\n\n",
        seconds,
        seconds / 3600.0
    );

    s += "InParm \t\t\t# Input parameters. cm is used.\n";
    s += &format!("{out_name} \tA\t\t# output file name, ASCII.\n");
    s += &format!("{} \t\t\t# No. of photons\n", out.photons);
    s += &format!("{}\t{}\t\t# dz, dr [cm]\n", c_g(g.dz, 6), c_g(g.dr, 6));
    s += &format!("{nz}\t{nr}\t{na}\t# No. of dz, dr, da.\n\n");
    s += &layers(&spec.sample);

    s += "RAT #Reflectance, absorption, transmission. \n";
    for (v, what) in [
        (out.rsp, "Specular reflectance"),
        (out.rd.value, "Diffuse reflectance"),
        (out.a.value, "Absorbed fraction"),
        (out.tt.value, "Transmittance"),
    ] {
        s += &format!("{:<14} \t#{what} [-]\n", c_g(v, 6));
    }
    s += "\n";

    s += "A_l #Absorption as a function of layer. [-]\n";
    for e in &out.a_l {
        s += &format!("{:>12}\n", c_g(e.value, 4));
    }
    s += "\n";
    column(&mut s, "A_z #A[0], [1],..A[nz-1]. [1/cm]", &out.a_z);
    column(&mut s, "Rd_r #Rd[0], [1],..Rd[nr-1]. [1/cm2]", &out.rd_r);
    column(&mut s, "Rd_a #Rd[0], [1],..Rd[na-1]. [sr-1]", &out.rd_a);
    column(&mut s, "Tt_r #Tt[0], [1],..Tt[nr-1]. [1/cm2]", &out.tt_r);
    column(&mut s, "Tt_a #Tt[0], [1],..Tt[na-1]. [sr-1]", &out.tt_a);
    table(
        &mut s,
        [
            "# A[r][z]. [1/cm3]",
            "# A[0][0], [0][1],..[0][nz-1]",
            "# A[1][0], [1][1],..[1][nz-1]",
            "# ...",
            "# A[nr-1][0], [nr-1][1],..[nr-1][nz-1]",
            "A_rz",
        ],
        &out.a_rz,
    );
    table(
        &mut s,
        [
            "# Rd[r][angle]. [1/(cm2sr)].",
            "# Rd[0][0], [0][1],..[0][na-1]",
            "# Rd[1][0], [1][1],..[1][na-1]",
            "# ...",
            "# Rd[nr-1][0], [nr-1][1],..[nr-1][na-1]",
            "Rd_ra",
        ],
        &out.rd_ra,
    );
    table(
        &mut s,
        [
            "# Tt[r][angle]. [1/(cm2sr)].",
            "# Tt[0][0], [0][1],..[0][na-1]",
            "# Tt[1][0], [1][1],..[1][na-1]",
            "# ...",
            "# Tt[nr-1][0], [nr-1][1],..[nr-1][na-1]",
            "Tt_ra",
        ],
        &out.tt_ra,
    );
    Ok(s)
}

fn column(s: &mut String, header: &str, v: &[Estimate]) {
    *s += header;
    *s += "\n";
    for e in v {
        *s += &format!("{:>12}\n", c_e(e.value, 4));
    }
    *s += "\n";
}

/// 2D arrays: five numbers per line, row-major, as MCML's `WriteA_rz`/`WriteRd_ra`.
fn table(s: &mut String, header: [&str; 6], v: &[Estimate]) {
    for h in header {
        *s += h;
        *s += "\n";
    }
    for (i, e) in v.iter().enumerate() {
        *s += &format!("{:>12} ", c_e(e.value, 4));
        if (i + 1) % 5 == 0 {
            *s += "\n";
        }
    }
    *s += "\n";
}

/// The totals and 1D arrays of an `.mco` file, as read back (values only).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct McoData {
    /// Photons traced.
    pub photons: u64,
    /// Depth bin width [cm].
    pub dz: f64,
    /// Radial bin width [cm].
    pub dr: f64,
    /// Specular reflectance [-].
    pub rsp: f64,
    /// Diffuse reflectance [-].
    pub rd: f64,
    /// Absorbed fraction [-].
    pub a: f64,
    /// Transmittance [-].
    pub tt: f64,
    /// Absorption per layer [-].
    pub a_l: Vec<f64>,
    /// Absorption per depth [cm⁻¹].
    pub a_z: Vec<f64>,
    /// Diffuse reflectance per area [cm⁻²].
    pub rd_r: Vec<f64>,
    /// Diffuse reflectance per solid angle [sr⁻¹].
    pub rd_a: Vec<f64>,
    /// Transmittance per area [cm⁻²].
    pub tt_r: Vec<f64>,
    /// Transmittance per solid angle [sr⁻¹].
    pub tt_a: Vec<f64>,
}

/// Reads an MCML `.mco` file (from MCML or from us): input header, RAT and the 1D arrays.
pub fn read(text: &str, source_name: &str) -> Result<McoData> {
    let err = |line: usize, m: String| McError::parse(source_name, line, m);
    let lines: Vec<&str> = text.lines().collect();
    let find = |tag: &str| {
        lines
            .iter()
            .position(|l| l.split_whitespace().next() == Some(tag))
    };
    let num = |i: usize| -> Result<f64> {
        let f = lines
            .get(i)
            .and_then(|l| l.split_whitespace().next())
            .ok_or_else(|| err(i + 1, "missing value".into()))?;
        f.parse()
            .map_err(|_| err(i + 1, format!("{f:?} is not a number")))
    };
    let inparm = find("InParm").ok_or_else(|| err(0, "no InParm section".into()))?;
    let rat = find("RAT").ok_or_else(|| err(0, "no RAT section".into()))?;
    let mut d = McoData {
        photons: num(inparm + 2)? as u64,
        ..Default::default()
    };
    let grid: Vec<f64> = lines[inparm + 3]
        .split_whitespace()
        .take(2)
        .filter_map(|f| f.parse().ok())
        .collect();
    if let [dz, dr] = grid[..] {
        d.dz = dz;
        d.dr = dr;
    }
    d.rsp = num(rat + 1)?;
    d.rd = num(rat + 2)?;
    d.a = num(rat + 3)?;
    d.tt = num(rat + 4)?;
    let array = |tag: &str| -> Result<Vec<f64>> {
        let start = find(tag).ok_or_else(|| err(0, format!("no {tag} section")))?;
        let mut v = Vec::new();
        for (i, l) in lines.iter().enumerate().skip(start + 1) {
            let Some(f) = l.split_whitespace().next() else {
                break;
            };
            v.push(
                f.parse()
                    .map_err(|_| err(i + 1, format!("{tag}: {f:?} is not a number")))?,
            );
        }
        Ok(v)
    };
    d.a_l = array("A_l")?;
    d.a_z = array("A_z")?;
    d.rd_r = array("Rd_r")?;
    d.rd_a = array("Rd_a")?;
    d.tt_r = array("Tt_r")?;
    d.tt_a = array("Tt_a")?;
    Ok(d)
}
