//! Lights, and the emitters the shaders draw them as: a directional or point light is one
//! emitter; a square area light is [`AREA_CELLS`]² emitters, one per cell, each a point at the
//! cell's centre with the cell's power that emits ∝ cos θ off the light's normal (a Lambertian
//! emitter) and has its own shadow map. The cells' sum converges to the area integral of the
//! irradiance (the midpoint rule: its error falls as (cell side / distance)²) and their shadow
//! maps give the penumbra in steps (each blurred by the maps' 3×3 filter): across an edge parallel
//! to the cells' rows the staircase misses a smooth penumbra by up to half a step, 1/16 of the
//! light with 8 rows. Units are cm.

use glam::{Vec3, Vec4};

use crate::error::{GpuError, Result};

/// Cells per side of an area light.
pub const AREA_CELLS: usize = 8;

/// The most emitters a scene holds (the scene pass's uniform array and shadow maps): an area
/// light counts [`AREA_CELLS`]², any other light 1.
pub const MAX_EMITTERS: usize = 64;

/// A light, with a shadow map when `shadow` is set.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Light {
    /// Light from direction `towards` (pointing at the light) with `irradiance` at normal
    /// incidence, RGB.
    Directional {
        /// Direction towards the light (normalized when rendering).
        towards: Vec3,
        /// Irradiance on a surface facing the light, RGB.
        irradiance: Vec3,
        /// Whether the light casts shadows (has a shadow map).
        shadow: bool,
    },
    /// A point light at `position` [cm] with radiant `intensity` (irradiance × distance² [cm²]).
    Point {
        /// Position [cm].
        position: Vec3,
        /// Radiant intensity, RGB: the irradiance at normal incidence times distance² [cm²].
        intensity: Vec3,
        /// Whether the light casts shadows (has a shadow map).
        shadow: bool,
    },
    /// A rectangle of uniform `radiance` emitting from its front face, the side `half_u × half_v`
    /// points to (Mitsuba's `area` emitter on a `rectangle`); its edges are perpendicular. SSS surfaces
    /// reflect it in mirror with the Fresnel reflectance of their material's η
    /// (`shading::Shading::eta`), as a smooth dielectric boundary does.
    Area {
        /// Centre [cm].
        center: Vec3,
        /// Half of one edge [cm].
        half_u: Vec3,
        /// Half of the other edge [cm].
        half_v: Vec3,
        /// Emitted radiance, RGB (irradiance per steradian: a surface facing a large light of
        /// radiance L gets π·L).
        radiance: Vec3,
        /// Whether the light casts shadows (each cell has a shadow map).
        shadow: bool,
    },
}

impl Light {
    /// A square area light of side `side_cm` centred at `center` facing `aim`, in the frame
    /// Mitsuba's `look_at(center, aim, up = +y)` gives a `rectangle` scaled by side/2:
    /// n = (aim − center)/|aim − center|, u = (y × n)/|y × n|, v = n × u (+z instead of +y for
    /// a light facing straight up or down, where Mitsuba's frame degenerates), so both renderers
    /// put the same square in a scene.
    pub fn square(
        center: Vec3,
        aim: Vec3,
        side_cm: f32,
        radiance: Vec3,
        shadow: bool,
    ) -> Result<Light> {
        let n = (aim - center).normalize_or_zero();
        if n == Vec3::ZERO || !n.is_finite() {
            return Err(GpuError::invalid(
                "area light aim",
                format!("{aim}"),
                format!("must differ from its centre {center}"),
            ));
        }
        let up = if Vec3::Y.cross(n).length() < 1e-6 {
            Vec3::Z
        } else {
            Vec3::Y
        };
        let u = up.cross(n).normalize();
        let v = n.cross(u);
        let light = Light::Area {
            center,
            half_u: 0.5 * side_cm * u,
            half_v: 0.5 * side_cm * v,
            radiance,
            shadow,
        };
        light.validate()?;
        Ok(light)
    }

    /// Checks the light's numbers; the error names the field.
    pub fn validate(&self) -> Result<()> {
        let finite = |field: &str, v: Vec3| {
            if v.is_finite() {
                Ok(())
            } else {
                Err(GpuError::invalid(field, format!("{v}"), "must be finite"))
            }
        };
        let power = |field: &str, v: Vec3| {
            finite(field, v)?;
            if v.min_element() < 0.0 {
                return Err(GpuError::invalid(field, format!("{v}"), "must be ≥ 0"));
            }
            Ok(())
        };
        match *self {
            Light::Directional {
                towards,
                irradiance,
                ..
            } => {
                finite("light direction", towards)?;
                if towards.length() == 0.0 {
                    return Err(GpuError::invalid(
                        "light direction",
                        "0",
                        "must not be zero",
                    ));
                }
                power("light irradiance", irradiance)
            }
            Light::Point {
                position,
                intensity,
                ..
            } => {
                finite("light position", position)?;
                power("light intensity", intensity)
            }
            Light::Area {
                center,
                half_u,
                half_v,
                radiance,
                ..
            } => {
                finite("area light centre", center)?;
                finite("area light edge", half_u)?;
                finite("area light edge", half_v)?;
                let area = 4.0 * half_u.cross(half_v).length();
                if !(area >= 1e-6 && area.is_finite()) {
                    return Err(GpuError::invalid(
                        "area light size",
                        format!("{area} cm²"),
                        "must be at least 1e-6 cm²",
                    ));
                }
                if half_u.dot(half_v).abs() > 1e-4 * half_u.length() * half_v.length() {
                    return Err(GpuError::invalid(
                        "area light edges",
                        format!("{half_u}, {half_v}"),
                        "must be perpendicular",
                    ));
                }
                power("area light radiance", radiance)
            }
        }
    }

    /// What the shaders draw this light as.
    pub fn emitters(&self) -> Vec<Emitter> {
        match *self {
            Light::Directional {
                towards,
                irradiance,
                shadow,
            } => vec![Emitter {
                pos_or_dir: towards.normalize().extend(0.0),
                power: irradiance,
                shadow,
                cell: None,
            }],
            Light::Point {
                position,
                intensity,
                shadow,
            } => vec![Emitter {
                pos_or_dir: position.extend(1.0),
                power: intensity,
                shadow,
                cell: None,
            }],
            Light::Area {
                center,
                half_u,
                half_v,
                radiance,
                shadow,
            } => {
                let n = AREA_CELLS as f32;
                let (cu, cv) = (half_u / n, half_v / n);
                // Each cell's intensity along the normal: L × its area (4|cu × cv|).
                let power = radiance * 4.0 * cu.cross(cv).length();
                let offset = |k: usize| 2.0 * k as f32 + 1.0 - n;
                (0..AREA_CELLS * AREA_CELLS)
                    .map(|k| Emitter {
                        pos_or_dir: (center
                            + offset(k % AREA_CELLS) * cu
                            + offset(k / AREA_CELLS) * cv)
                            .extend(1.0),
                        power,
                        shadow,
                        cell: Some([cu, cv]),
                    })
                    .collect()
            }
        }
    }
}

impl Light {
    /// A point of an area light at `(s, t)` ∈ [0, 1)² across its edges, carrying the whole
    /// light: intensity L·A along its normal, falling as the cosine off it (a Lambertian emitter;
    /// `cell` is the whole rectangle). The mean of such points' irradiance over (s, t) uniform
    /// in the square is the area light's irradiance, exactly: what the disc gather draws, a few
    /// points per frame. `None` for other lights.
    pub fn point_on(&self, (s, t): (f32, f32)) -> Option<Emitter> {
        let Light::Area {
            center,
            half_u,
            half_v,
            radiance,
            shadow,
        } = *self
        else {
            return None;
        };
        Some(Emitter {
            pos_or_dir: (center + (2.0 * s - 1.0) * half_u + (2.0 * t - 1.0) * half_v).extend(1.0),
            power: radiance * 4.0 * half_u.cross(half_v).length(),
            shadow,
            cell: Some([half_u, half_v]),
        })
    }
}

/// One light source as the shaders draw it (lighting.wgsl's `Light`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Emitter {
    /// Direction towards the light, normalized (w = 0), or its position [cm] (w = 1).
    pub pos_or_dir: Vec4,
    /// Irradiance at normal incidence (directional), radiant intensity [× cm²] (point), or for
    /// a cell of an area light its intensity along the light's normal, L × the cell's area.
    pub power: Vec3,
    /// Whether it has a shadow map.
    pub shadow: bool,
    /// For a cell of an area light, its half edges [cm]: the intensity falls as the cosine off
    /// their cross product (the emitting side), and a mirror ray that hits the cell sees
    /// radiance power / (4|u × v|).
    pub cell: Option<[Vec3; 2]>,
}

impl Emitter {
    /// For a cell or point of an area light, the unit normal of its emitting side (its
    /// intensity falls as the cosine off it); `None` for an isotropic point or a directional
    /// light.
    pub fn emitting_normal(&self) -> Option<Vec3> {
        self.cell.map(|[u, v]| u.cross(v).normalize())
    }

    /// The irradiance this emitter delivers unshadowed to a surface at `x` [cm] with unit normal
    /// `n`: what the scene shader computes before the incidence table.
    pub fn irradiance(&self, x: Vec3, n: Vec3) -> Vec3 {
        if self.pos_or_dir.w == 0.0 {
            return self.power * n.dot(self.pos_or_dir.truncate()).max(0.0);
        }
        let d = self.pos_or_dir.truncate() - x;
        let l = d.normalize();
        let emission = self
            .emitting_normal()
            .map_or(1.0, |normal| normal.dot(-l).max(0.0));
        self.power * emission * n.dot(l).max(0.0) / d.length_squared()
    }
}

/// Every emitter of `lights`, in order.
pub fn emitters(lights: &[Light]) -> Vec<Emitter> {
    lights.iter().flat_map(Light::emitters).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Irradiance at x (unit normal n) from a uniform Lambertian polygon of radiance 1 lying
    /// wholly above x's tangent plane, by Lambert's formula: E = ½ Σᵢ Θᵢ (n · γᵢ), Θᵢ the angle
    /// the edge (pᵢ, pᵢ₊₁) subtends at x and γᵢ the unit normal of the plane through x and the
    /// edge (Lambert 1760, as in Arvo 1995; the sign follows the winding, so the magnitude is
    /// taken).
    fn lambert_polygon(p: &[Vec3], x: Vec3, n: Vec3) -> f64 {
        let d = |v: Vec3| (v - x).as_dvec3().normalize();
        let n = n.as_dvec3();
        let sum: f64 = (0..p.len())
            .map(|i| {
                let (a, b) = (d(p[i]), d(p[(i + 1) % p.len()]));
                a.dot(b).clamp(-1.0, 1.0).acos() * n.dot(a.cross(b).normalize())
            })
            .sum();
        0.5 * sum.abs()
    }

    /// A square light of radiance 1 at `centre` facing `aim`, its half edges and its corners.
    fn square(centre: Vec3, aim: Vec3, side: f32) -> (Light, [Vec3; 2], [Vec3; 4]) {
        let light = Light::square(centre, aim, side, Vec3::ONE, true).unwrap();
        let Light::Area { half_u, half_v, .. } = light else {
            panic!()
        };
        let corners = [
            centre - half_u - half_v,
            centre + half_u - half_v,
            centre + half_u + half_v,
            centre - half_u + half_v,
        ];
        (light, [half_u, half_v], corners)
    }

    #[test]
    fn a_square_light_sums_to_lamberts_polygon_irradiance() {
        // A square like the references': side 16 cm, its centre 24 cm from the sphere's.
        let centre = Vec3::new(-12.0, 20.0, 14.0);
        let (light, [half_u, half_v], corners) = square(centre, Vec3::new(0.0, 5.0, 0.0), 16.0);
        // The frame: u ⊥ y (Mitsuba's look_at), u × v along the aim.
        assert!(half_u.y.abs() < 1e-6 && (half_u.length() - 8.0).abs() < 1e-5);
        let aim = (Vec3::new(0.0, 5.0, 0.0) - centre).normalize();
        assert!(half_u.cross(half_v).normalize().dot(aim) > 0.99999);
        let cells = light.emitters();
        assert_eq!(cells.len(), AREA_CELLS * AREA_CELLS);
        let power: f32 = cells.iter().map(|e| e.power.x).sum();
        assert!((power - 256.0).abs() < 1e-3, "Σ intensity = L·A: {power}");
        // Points of the sphere (centre (0, 5, 0), radius 5) and the floor the light sees.
        for (x, n) in [
            (Vec3::new(0.0, 10.0, 0.0), Vec3::Y),
            (Vec3::new(-3.0, 5.0, 4.0), Vec3::new(-3.0, 0.0, 4.0) / 5.0),
            (Vec3::new(-3.0, 9.0, 0.0), Vec3::new(-3.0, 4.0, 0.0) / 5.0),
            (Vec3::new(8.0, 0.0, -6.0), Vec3::Y),
        ] {
            let want = lambert_polygon(&corners, x, n);
            let got: f64 = cells.iter().map(|e| e.irradiance(x, n).x as f64).sum();
            assert!(
                (got - want).abs() < 0.01 * want,
                "at {x}: cells {got} against Lambert's formula {want}"
            );
        }
        // Far away the square is a point of intensity L·A·cos θ: 60° off its normal, a surface
        // facing it gets L·A·cos 60°/d².
        let off = (aim + 3f32.sqrt() * half_u.normalize()).normalize();
        let x = centre + 400.0 * off;
        let got: f32 = cells.iter().map(|e| e.irradiance(x, -off).x).sum();
        let want = 256.0 * 0.5 / 160_000.0;
        assert!((got - want).abs() < 1e-3 * want, "{got} vs {want}");
        // Behind the light, nothing.
        let x = centre - 400.0 * aim;
        assert_eq!(
            cells.iter().map(|e| e.irradiance(x, aim).x).sum::<f32>(),
            0.0
        );
    }

    #[test]
    fn points_on_a_square_light_average_to_lamberts_polygon_irradiance() {
        let centre = Vec3::new(-7.1, 13.8, 8.3);
        let (light, [half_u, half_v], corners) = square(centre, Vec3::new(0.0, 5.0, 0.0), 3.0);
        // A 64 × 64 grid of points, and points close to the light where the cells' midpoint
        // rule would be poor (the light 2 cm away, 3 cm wide).
        let aim = (Vec3::new(0.0, 5.0, 0.0) - centre).normalize();
        for (x, n) in [
            (
                Vec3::new(0.0, 8.0, 1.5),
                Vec3::new(-0.6, 0.6, 0.52).normalize(),
            ),
            (centre + 2.0 * aim + 0.5 * half_u, -aim),
            (
                centre + 1.0 * aim - 1.2 * half_v,
                (-aim + 0.5 * half_u).normalize(),
            ),
        ] {
            let want = lambert_polygon(&corners, x, n);
            let m = 64;
            let got: f64 = (0..m * m)
                .map(|k| {
                    let st = ((k % m) as f32 + 0.5, (k / m) as f32 + 0.5);
                    let e = light.point_on((st.0 / m as f32, st.1 / m as f32)).unwrap();
                    e.irradiance(x, n).x as f64
                })
                .sum::<f64>()
                / (m * m) as f64;
            assert!(
                (got - want).abs() < 2e-3 * want,
                "at {x}: points {got} against Lambert's formula {want}"
            );
        }
        let sun = Light::Directional {
            towards: Vec3::Y,
            irradiance: Vec3::ONE,
            shadow: true,
        };
        assert_eq!(sun.point_on((0.5, 0.5)), None);
    }

    #[test]
    fn bad_lights_are_refused_naming_the_field() {
        let err = |r: Result<Light>| r.unwrap_err().to_string();
        let e = err(Light::square(Vec3::ONE, Vec3::ONE, 1.0, Vec3::ONE, true));
        assert!(e.contains("area light aim"), "{e}");
        let e = err(Light::square(Vec3::ONE, Vec3::ZERO, 0.0, Vec3::ONE, true));
        assert!(e.contains("area light size"), "{e}");
        let e = err(Light::square(
            Vec3::ONE,
            Vec3::ZERO,
            f32::NAN,
            Vec3::ONE,
            true,
        ));
        assert!(e.contains("area light"), "{e}");
        let e = err(Light::square(Vec3::ONE, Vec3::ZERO, 2.0, -Vec3::ONE, true));
        assert!(e.contains("area light radiance"), "{e}");
        let e = err(Light::square(Vec3::ONE, Vec3::ZERO, 1e-20, Vec3::ONE, true));
        assert!(e.contains("area light size"), "{e}");
        let skewed = Light::Area {
            center: Vec3::ZERO,
            half_u: Vec3::X,
            half_v: Vec3::new(1.0, 1.0, 0.0),
            radiance: Vec3::ONE,
            shadow: true,
        };
        let e = skewed.validate().unwrap_err().to_string();
        assert!(e.contains("area light edges"), "{e}");
    }
}
