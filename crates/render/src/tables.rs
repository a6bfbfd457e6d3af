//! The shading model's tables of one material as a render asks for them, each simulated by
//! `shading` with the request's run settings and seed.

use shading::{AngleTables, EntryShift, INCIDENCE_STEPS, ShapeTable, Translucency};

use crate::error::Result;
use crate::options::ExitLaw;
use crate::progress::Progress;
use crate::request::{NamedMaterial, ResolvedShading, TableSettings};

/// One material's tables, as built (for the renderer and for a caller that prints or exports
/// them).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MaterialTables {
    /// The material's short name.
    pub slug: String,
    /// ρ(θ)/ρ(0) and h(θ_o; θ_i), where asked for (ones where not).
    pub angles: AngleTables,
    /// Whether `angles` holds the incidence table, the exit table.
    pub simulated: (bool, bool),
    /// δ(θ), where asked for.
    pub entry_shift: Option<EntryShift>,
    /// Tt(d)/ρ and the ρ it is relative to, where asked for.
    pub translucency: Option<(Translucency, [shading::Estimate; 3])>,
    /// What curved and thin bodies return against the half-space, where asked for (absent from
    /// tables kept before it existed).
    #[serde(default)]
    pub shape: Option<ShapeTable>,
}

/// Photons per run of the shape table: a third of an angle run's (33 333 at the default 10⁵,
/// [`shading::SHAPE_PHOTONS`]), because the table is [`shading::SHAPE_RUNS_PER_CHANNEL`] = 180
/// runs per channel where an angle table is 9.
fn shape_photons(settings: &TableSettings) -> u64 {
    (settings.incidence_photons / 3).max(1)
}

impl MaterialTables {
    /// What the tables of `m` under `shading` and `settings` are made of, as text: the tables
    /// asked for and each run's provenance (every channel's layer and grid, the ambient indices,
    /// photons and seed). Tables kept for an equal key are the same numbers.
    pub fn key(
        m: &NamedMaterial,
        shading: &ResolvedShading,
        settings: &TableSettings,
    ) -> Result<String> {
        let run = |photons| -> Result<serde_json::Value> {
            let spec = settings
                .config
                .batch(&[&m.material], photons, settings.seed, true)?;
            let json = mc::provenance::Provenance::of(&spec, 0, &m.slug, None).to_json();
            Ok(serde_json::from_str(&json).expect("a provenance is JSON"))
        };
        let mut key = serde_json::json!({
            "format": "sss-tables-1",
            "incidence": shading.incidence,
            "exit": shading.exit != ExitLaw::Lambertian,
            "entry_shift": shading.entry_shift,
            "translucency": shading.translucency,
            "angle_runs": run(settings.incidence_photons)?,
            "slab_runs": run(settings.translucency_photons)?,
        });
        // Only where asked for, so that tables kept without it keep their key.
        if shading.shape {
            key["shape"] = serde_json::json!({
                "runs": run(shape_photons(settings))?,
                "curvatures": shading::SHAPE_CURVATURES,
                "thicknesses": shading::SHAPE_THICKNESSES,
                "window": shading::SHAPE_WINDOW,
                "half_space": shading::shape::HALF_SPACE_DIFFUSION_LENGTHS,
            });
        }
        Ok(key.to_string())
    }

    /// The tables `shading` asks for of material `m`, each reported to `progress` as it runs.
    pub fn build(
        m: &NamedMaterial,
        shading: &ResolvedShading,
        settings: &TableSettings,
        progress: &dyn Progress,
    ) -> Result<MaterialTables> {
        let spec = |photons| {
            settings
                .config
                .batch(&[&m.material], photons, settings.seed, true)
        };
        let (incidence, exit) = (shading.incidence, shading.exit != ExitLaw::Lambertian);
        let runs = AngleTables::angles(incidence, exit).len() as u64;
        let angles = if runs == 0 {
            AngleTables::ONES
        } else {
            let spec = spec(settings.incidence_photons)?;
            let total = settings.incidence_photons * spec.groups().len() as u64 * runs;
            progress.begin("angle tables", total);
            let t = AngleTables::from_mc(&spec, incidence, exit, &|k| progress.advance(k));
            progress.end();
            t?
        };
        let entry_shift = if shading.entry_shift {
            let spec = spec(settings.incidence_photons)?;
            let groups = spec.groups().len() as u64;
            progress.begin(
                "entry shift",
                settings.incidence_photons * groups * INCIDENCE_STEPS as u64,
            );
            let t = EntryShift::from_mc(&spec, &|k| progress.advance(k));
            progress.end();
            Some(t?)
        } else {
            None
        };
        let translucency = if shading.translucency {
            let spec = spec(settings.translucency_photons)?;
            let groups = spec.groups().len() as u64;
            let per_group =
                shading::RHO_PHOTONS + spec.photons * shading::TRANSLUCENCY_STEPS as u64;
            progress.begin("translucency table", per_group * groups);
            let t = Translucency::rho_of(&spec, &|k| progress.advance(k)).and_then(|rho| {
                Translucency::from_mc(&spec, rho.map(|r| r.value), &|k| progress.advance(k))
                    .map(|t| (t, rho))
            });
            progress.end();
            Some(t?)
        } else {
            None
        };
        let shape = if shading.shape {
            let spec = spec(shape_photons(settings))?;
            let scattering = m.material.sigma_s.iter().filter(|&&s| s > 0.0).count() as u64;
            progress.begin(
                "shape table",
                spec.photons * shading::SHAPE_RUNS_PER_CHANNEL * scattering,
            );
            let t = ShapeTable::from_mc(&spec, &|k| progress.advance(k));
            progress.end();
            Some(t?)
        } else {
            None
        };
        Ok(MaterialTables {
            slug: m.slug.clone(),
            angles,
            simulated: (incidence, exit),
            entry_shift,
            translucency,
            shape,
        })
    }

    /// What the renderer reads: the tables with the exit law applied (`Normal`: every row the
    /// normal-entry one, whatever angle the light enters at) and the boundary's η.
    pub fn shading(&self, exit: ExitLaw, eta: f64) -> shading::Shading {
        shading::Shading {
            incidence: self.angles.incidence,
            entry_shift: self.entry_shift.unwrap_or(EntryShift::NONE),
            exit: match exit {
                ExitLaw::Entry => self.angles.exit,
                _ => [self.angles.exit[0]; INCIDENCE_STEPS],
            },
            translucency: self.translucency.map(|(t, _)| t),
            shape: self.shape,
            eta: eta as f32,
        }
    }

    /// The tables as lines of text, for a caller to show: the incidence table, the exit table
    /// at three entry angles, the entry shift [mm], the translucency table and the shape table's
    /// energy ratios at normal incidence, each where built.
    pub fn describe(&self) -> Vec<String> {
        let rgb = |v: [f32; 3]| format!("{:.3} {:.3} {:.3}", v[0], v[1], v[2]);
        let mut lines = Vec::new();
        let (incidence, exit) = self.simulated;
        if incidence {
            lines.push(format!(
                "incidence table of {} (ρ(θ)/ρ(0), R G B):",
                self.slug
            ));
            for (k, row) in self.angles.incidence.iter().enumerate() {
                lines.push(format!("  {:>4}°  {}", 10 * k, rgb(*row)));
            }
        }
        if exit {
            lines.push(format!(
                "exit table of {} (h(θ_o; θ_i): radiance over a Lambertian surface's, R G B, ± SE; \
                 entering at 0°, 40° and 80° of the 0°…80° it holds):",
                self.slug
            ));
            let t = &self.angles;
            for k in 0..INCIDENCE_STEPS {
                let row = |i: usize| format!("{}  ± {}", rgb(t.exit[i][k]), rgb(t.exit_se[i][k]));
                lines.push(format!(
                    "  {:>4}°  {}  |  {}  |  {}",
                    10 * k,
                    row(0),
                    row(4),
                    row(8)
                ));
            }
        }
        if let Some(t) = &self.entry_shift {
            lines.push(format!(
                "entry shift of {} (centroid of the returned light ahead of the entry, δ(θ) [mm], R G B ± SE):",
                self.slug
            ));
            let mm =
                |v: [f32; 3]| format!("{:.3} {:.3} {:.3}", 10.0 * v[0], 10.0 * v[1], 10.0 * v[2]);
            for k in 0..INCIDENCE_STEPS {
                lines.push(format!(
                    "  {:>4}°  {}  ± {}",
                    10 * k,
                    mm(t.shift_cm[k]),
                    mm(t.shift_se_cm[k])
                ));
            }
        }
        if let Some((t, rho)) = &self.translucency {
            lines.push(format!(
                "translucency table of {} (slab Tt(d) / ρ; ρ = {:.3} {:.3} {:.3} ± {:.3} {:.3} {:.3}):",
                self.slug, rho[0].value, rho[1].value, rho[2].value, rho[0].se, rho[1].se, rho[2].se
            ));
            for (k, row) in t.table.iter().enumerate() {
                let d = t.thickness_cm(k);
                lines.push(format!(
                    "  {d:>8.4} cm  {:.4} {:.4} {:.4}",
                    row[0], row[1], row[2]
                ));
            }
        }
        if let Some(t) = &self.shape {
            lines.push(format!(
                "shape table of {} (energy within {}/σ_tr of the entry over the half-space's, \
                 at 0°, R G B ± SE; κ = 1/(σ_tr·R), > 0 convex; τ = σ_tr·t of a slab):",
                self.slug,
                shading::SHAPE_WINDOW
            ));
            let nodes = (shading::SHAPE_CURVATURES
                .iter()
                .map(|k| format!("κ {k:>5}")))
            .zip(&t.curvature)
            .chain(
                (shading::SHAPE_THICKNESSES
                    .iter()
                    .map(|k| format!("τ {k:>5}")))
                .zip(&t.thickness),
            );
            for (name, row) in nodes {
                let e = row[0].map(|e| e.energy);
                lines.push(format!(
                    "  {name}  {:.3} {:.3} {:.3}  ± {:.3} {:.3} {:.3}",
                    e[0].value, e[1].value, e[2].value, e[0].se, e[1].se, e[2].se
                ));
            }
        }
        lines
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn only_shape(shape: bool) -> ResolvedShading {
        ResolvedShading {
            incidence: false,
            exit: ExitLaw::Lambertian,
            entry_shift: false,
            translucency: false,
            shape,
        }
    }

    /// The shape table is built where asked for and is part of the key then; a key without it is
    /// the key tables had before it existed (no "shape" in it), and tables kept then still read,
    /// without one.
    #[test]
    fn the_shape_table_is_built_and_keyed_where_asked_for() {
        let m = NamedMaterial::builtin("skin1").unwrap();
        let settings = TableSettings {
            incidence_photons: 300,
            ..TableSettings::default()
        };
        let (off, on) = (only_shape(false), only_shape(true));
        let key_off = MaterialTables::key(&m, &off, &settings).unwrap();
        let key_on = MaterialTables::key(&m, &on, &settings).unwrap();
        assert!(!key_off.contains("\"shape\"") && key_on.contains("\"shape\""));
        let t = MaterialTables::build(&m, &on, &settings, &()).unwrap();
        let shape = t.shape.as_ref().unwrap();
        shape.validate().unwrap();
        assert!(
            MaterialTables::build(&m, &off, &settings, &())
                .unwrap()
                .shape
                .is_none()
        );
        assert!(
            t.describe()
                .iter()
                .any(|l| l.starts_with("shape table of skin1"))
        );
        let mut old = serde_json::to_value(&t).unwrap();
        old.as_object_mut().unwrap().remove("shape");
        let kept: MaterialTables = serde_json::from_value(old).unwrap();
        assert_eq!(kept.shape, None);
    }
}
