//! The text forms of points, boxes and lights that the command line's flags and Python's keyword
//! arguments take; each error quotes the text and says what was expected.

use glam::Vec3;
use gpu::Light;

/// A point or colour `X,Y,Z` (three finite numbers).
pub fn vec3(s: &str) -> Result<Vec3, String> {
    let v: Vec<f32> = s
        .split(',')
        .map(|x| {
            x.trim()
                .parse::<f32>()
                .map_err(|_| format!("{s:?}: expected X,Y,Z"))
        })
        .collect::<Result<_, _>>()?;
    match v[..] {
        [x, y, z] if v.iter().all(|c| c.is_finite()) => Ok(Vec3::new(x, y, z)),
        _ => Err(format!("{s:?}: expected three finite numbers X,Y,Z")),
    }
}

/// A box `MIN_X,MIN_Y,MIN_Z:MAX_X,MAX_Y,MAX_Z` [cm], every MIN below its MAX.
pub fn cuboid(s: &str) -> Result<(Vec3, Vec3), String> {
    let (a, b) = s.split_once(':').ok_or(format!(
        "{s:?}: expected MIN_X,MIN_Y,MIN_Z:MAX_X,MAX_Y,MAX_Z"
    ))?;
    let (lo, hi) = (vec3(a)?, vec3(b)?);
    if lo.cmplt(hi).all() {
        Ok((lo, hi))
    } else {
        Err(format!("{s:?}: every MIN must be below its MAX"))
    }
}

/// A light: `dir:X,Y,Z[:IRRADIANCE]` (towards the light; default 1.2), `point:X,Y,Z[:INTENSITY]`
/// (position [cm], intensity = irradiance × cm²; default 1200) or
/// `area:X,Y,Z:AX,AY,AZ:SIDE[:RADIANCE]` (a square of SIDE [cm] centred at X,Y,Z facing the point
/// AX,AY,AZ, in Mitsuba's look_at frame with +y up; radiance default 5). All cast shadows.
pub fn light(s: &str) -> Result<Light, String> {
    let parts: Vec<&str> = s.split(':').collect();
    let number = |t: &str, what: &str| -> Result<f32, String> {
        let v: f32 = t
            .parse()
            .map_err(|_| format!("{s:?}: {what} {t:?} is not a number"))?;
        if v.is_finite() && v >= 0.0 {
            Ok(v)
        } else {
            Err(format!("{s:?}: {what} must be finite and ≥ 0"))
        }
    };
    match parts[..] {
        ["area", at, aim, side, ref rest @ ..] if rest.len() <= 1 => {
            let radiance = match rest.first() {
                Some(t) => number(t, "radiance")?,
                None => 5.0,
            };
            let side = number(side, "side")?;
            Light::square(vec3(at)?, vec3(aim)?, side, Vec3::splat(radiance), true)
                .map_err(|e| format!("{s:?}: {e}"))
        }
        [kind @ ("dir" | "point"), v, ref rest @ ..] if rest.len() <= 1 => {
            let v = vec3(v)?;
            let i = match rest.first() {
                Some(t) => number(t, "intensity")?,
                None if kind == "dir" => 1.2,
                None => 1200.0,
            };
            if kind == "dir" {
                if v.length() == 0.0 {
                    return Err(format!("{s:?}: the direction must not be zero"));
                }
                Ok(Light::Directional {
                    towards: v.normalize(),
                    irradiance: Vec3::splat(i),
                    shadow: true,
                })
            } else {
                Ok(Light::Point {
                    position: v,
                    intensity: Vec3::splat(i),
                    shadow: true,
                })
            }
        }
        _ => Err(format!(
            "{s:?}: expected dir:X,Y,Z[:I], point:X,Y,Z[:I] or area:X,Y,Z:AX,AY,AZ:SIDE[:L]"
        )),
    }
}
