//! How a half-space of the material reflects against the angles of entry and exit: the total
//! diffuse reflectance against the angle of incidence, ρ(θ)/ρ(0), and the radiance against the
//! exit angle for light that entered at each angle, h(θ_o; θ_i) (tables from `mc::incidence` and
//! `mc::exitance`, read by the scene pass and the surface gathers).

use crate::angles::{INCIDENCE_STEPS, incidence_ratio};
use crate::error::{Result, ShadingError};

/// An exit table h(θ_o; θ_i) per channel, [θ_i][θ_o] at 0°, 10°, …, 80°: the angular law of the
/// reflected light depends on the angle it entered at. For isotropic scattering behind a matched
/// boundary the radiance leaving at cosine μ is ∝ H(μ)/(μ + μ₀) for light entering at cosine μ₀
/// (Chandrasekhar 1960): towards the normal for normal entry and high albedo, flat or towards
/// grazing angles for oblique entry.
pub type ExitTable = [[[f32; 3]; INCIDENCE_STEPS]; INCIDENCE_STEPS];

/// A material's angle tables by `mc`: profile-only batch runs of its channels with
/// [`INCIDENCE_STEPS`] exit-angle bins of 10°.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct AngleTables {
    /// ρ(θ)/ρ(0) per channel at θ = 0°, 10°, …, 80° ([`Shading::incidence`]).
    pub incidence: [[f32; 3]; INCIDENCE_STEPS],
    /// The standard error of each `incidence` entry (the runs at each angle are independent;
    /// 0 at 0°, where the ratio is 1 by definition).
    pub incidence_se: [[f32; 3]; INCIDENCE_STEPS],
    /// h(θ_o; θ_i) per channel, [θ_i][θ_o] ([`Shading::exit`]).
    pub exit: ExitTable,
    /// The standard error of each `exit` entry.
    pub exit_se: ExitTable,
}

impl AngleTables {
    /// No angle dependence: plain Lambertian entry and exit.
    pub const ONES: AngleTables = AngleTables {
        incidence: [[1.0; 3]; INCIDENCE_STEPS],
        incidence_se: [[0.0; 3]; INCIDENCE_STEPS],
        exit: [[[1.0; 3]; INCIDENCE_STEPS]; INCIDENCE_STEPS],
        exit_se: [[[0.0; 3]; INCIDENCE_STEPS]; INCIDENCE_STEPS],
    };

    /// The beam angles [degrees] the tables need: every table angle for either table (the exit
    /// table has a row per angle of entry); none when neither is asked for.
    pub fn angles(incidence: bool, exit: bool) -> Vec<f64> {
        if incidence || exit {
            (0..INCIDENCE_STEPS).map(|k| 10.0 * k as f64).collect()
        } else {
            Vec::new()
        }
    }

    /// The tables of the three channels of `spec` (a profile-only batch of one material; its
    /// exit-angle bins are set to [`INCIDENCE_STEPS`] here), each run of `spec.photons` per
    /// channel and angle ([`AngleTables::angles`]); `progress` receives photon counts. The
    /// incidence table is ρ(θ)/ρ(0) (all ones unless `incidence`); the exit table h(θ_o; θ_i)
    /// (all ones unless `exit`) has the run at each θ_i as its row: at θ_o = 0° the first exit
    /// bin's, at 10°…80° the mean of the two bins around the angle. A channel that does not
    /// scatter (σs = 0) keeps ones: it returns no diffuse light to shape. Refuses a material
    /// that scatters but reflects nothing in some channel (at normal incidence, or for the exit
    /// table at any angle).
    pub fn from_mc(
        spec: &mc::BatchSpec,
        incidence: bool,
        exit: bool,
        progress: &(dyn Fn(u64) + Sync),
    ) -> Result<AngleTables> {
        let mut tables = AngleTables::ONES;
        let angles = AngleTables::angles(incidence, exit);
        if angles.is_empty() {
            return Ok(tables);
        }
        if spec.channels.len() != 3 {
            return Err(ShadingError::invalid(
                "angle tables: channels",
                spec.channels.len(),
                "one material (three channels) per table",
            ));
        }
        let mut spec = spec.clone();
        for ch in &mut spec.channels {
            ch.grid.na = INCIDENCE_STEPS;
        }
        let rows = mc::incidence::rd_table(&spec, &angles, progress)?;
        let rd0 = &rows[0].rd;
        // A channel that does not scatter (σs = 0: wine's green and blue) returns no diffuse
        // light at any angle: its diffuse term is 0, so its tables stay ones (nothing to shape).
        let dark = |c: usize| spec.channels[c].layer.mu_s == 0.0;
        if let Some(c) =
            (0..3).find(|&c| !dark(c) && (rd0[c].value.is_nan() || rd0[c].value <= 0.0))
        {
            return Err(ShadingError::invalid(
                format!("angle tables: diffuse reflectance at normal incidence of channel {c}"),
                rd0[c].value,
                "the material reflects nothing there",
            ));
        }
        if incidence {
            for (k, row) in rows.iter().enumerate().skip(1) {
                for (c, (r, r0)) in row
                    .rd
                    .iter()
                    .zip(rd0)
                    .enumerate()
                    .filter(|&(c, _)| !dark(c))
                {
                    let ratio = r.value / r0.value;
                    tables.incidence[k][c] = ratio as f32;
                    // (0 where nothing came back: NaN.max(0) is 0.)
                    tables.incidence_se[k][c] =
                        (ratio * (r.se / r.value).hypot(r0.se / r0.value)).max(0.0) as f32;
                }
            }
        }
        if exit {
            for (i, row) in rows.iter().enumerate() {
                for (c, channel) in row.exit.iter().enumerate().filter(|&(c, _)| !dark(c)) {
                    if channel.len() < INCIDENCE_STEPS {
                        return Err(ShadingError::invalid(
                            format!(
                                "exit table: light reflected at {}° incidence in channel {c}",
                                10 * i
                            ),
                            row.rd[c].value,
                            "the material reflects nothing there",
                        ));
                    }
                    for (k, (h, se)) in exit_angles(channel).into_iter().enumerate() {
                        tables.exit[i][k][c] = h;
                        tables.exit_se[i][k][c] = se;
                    }
                }
            }
        }
        Ok(tables)
    }
}

/// An exit table's entries at θ = 0°, 10°, …, 80° with their standard errors from `mc`'s
/// [`INCIDENCE_STEPS`] exit bins of 10°: at 0° the first bin's, at 10°…80° the mean of the two
/// bins around the angle.
pub(crate) fn exit_angles(bins: &[mc::exitance::ExitBin]) -> [(f32, f32); INCIDENCE_STEPS] {
    std::array::from_fn(|k| {
        let (a, b) = (&bins[k.saturating_sub(1)].h, &bins[k].h);
        (
            (0.5 * (a.value + b.value)) as f32,
            (0.5 * (a.se.powi(2) + b.se.powi(2)).sqrt()) as f32,
        )
    })
}

/// h(θ_o; θ_i) from an exit table at exit cosine `cos_o` and entry cosine `cos_i`: linear in θ_o
/// and in θ_i between entries, the 80° values beyond: the CPU twin of `sss_exit` ([`EXIT_WGSL`]).
pub fn exit_ratio(table: &ExitTable, cos_o: f32, cos_i: f32) -> [f32; 3] {
    let t = cos_i.clamp(0.0, 1.0).acos().to_degrees() / 10.0;
    let i = (t.floor() as usize).min(INCIDENCE_STEPS - 1);
    let j = (i + 1).min(INCIDENCE_STEPS - 1);
    let f = (t - i as f32).clamp(0.0, 1.0);
    let (a, b) = (
        incidence_ratio(&table[i], cos_o),
        incidence_ratio(&table[j], cos_o),
    );
    [0, 1, 2].map(|c| a[c] * (1.0 - f) + b[c] * f)
}

/// The WGSL of the incidence table's lookup, `sss_incidence(m, cos_i) -> vec3<f32>`
/// (`wgsl/incidence.wgsl`; reads the host's `sss_incidence_entry(m, k)`; its CPU twin is
/// [`incidence_ratio`]).
pub const INCIDENCE_WGSL: &str = include_str!("wgsl/incidence.wgsl");

/// The WGSL of the exit table's lookup, `sss_exit(m, cos_o, cos_i) -> vec3<f32>`
/// (`wgsl/exit.wgsl`; reads the host's `sss_exit_entry(m, k)`; its CPU twin is [`exit_ratio`]).
pub const EXIT_WGSL: &str = include_str!("wgsl/exit.wgsl");

/// The cosine-weighted hemispherical mean 2∫₀^{π/2} f(θ) cos θ sin θ dθ of an incidence table:
/// the factor for diffuse (ambient) light.
pub fn incidence_hemispherical(table: &[[f32; 3]; INCIDENCE_STEPS]) -> [f32; 3] {
    let n = 900;
    let mut acc = [0.0f64; 3];
    for k in 0..n {
        let theta = (k as f64 + 0.5) / n as f64 * std::f64::consts::FRAC_PI_2;
        let f = incidence_ratio(table, theta.cos() as f32);
        let w = 2.0 * theta.cos() * theta.sin() * std::f64::consts::FRAC_PI_2 / n as f64;
        for c in 0..3 {
            acc[c] += w * f[c] as f64;
        }
    }
    acc.map(|x| x as f32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn incidence_table_lookup_and_hemispherical_mean() {
        // A constant table is that constant everywhere; 2∫cos θ sin θ dθ = 1.
        let ones = [[1.0f32; 3]; INCIDENCE_STEPS];
        assert_eq!(incidence_ratio(&ones, 0.3), [1.0; 3]);
        for h in incidence_hemispherical(&ones) {
            assert!((h - 1.0).abs() < 1e-5, "{h}");
        }
        // A table linear in θ is reproduced between entries and held beyond 80°.
        let table: [[f32; 3]; INCIDENCE_STEPS] =
            std::array::from_fn(|k| [1.0 + 0.1 * k as f32, 1.0, 2.0 - 0.1 * k as f32]);
        let r = incidence_ratio(&table, 35f32.to_radians().cos());
        assert!(
            (r[0] - 1.35).abs() < 1e-4 && (r[2] - 1.65).abs() < 1e-4,
            "{r:?}"
        );
        assert_eq!(incidence_ratio(&table, 0.0), table[8]);
        // Hemispherical mean of f(θ) = 1 + θ/100 rad⁻¹… checked against direct quadrature of the
        // interpolant: for R, 2∫(1 + 0.01·θ°)cos θ sin θ dθ with θ° clamped at 80.
        let n = 20_000;
        let direct: f64 = (0..n)
            .map(|k| {
                let t = (k as f64 + 0.5) / n as f64 * std::f64::consts::FRAC_PI_2;
                let deg = t.to_degrees().min(80.0);
                (1.0 + 0.01 * deg) * 2.0 * t.cos() * t.sin() * std::f64::consts::FRAC_PI_2
                    / n as f64
            })
            .sum();
        let h = incidence_hemispherical(&table);
        assert!((h[0] as f64 - direct).abs() < 1e-4, "{} vs {direct}", h[0]);
    }
}
