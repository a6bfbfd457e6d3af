//! A slab of thickness t between two parallel faces: the entry face z = 0 and the far face z = t.
//!
//! Units: cm. Frame: the entry point is the origin and +z points into the slab, as in every `mc`
//! run (MCML's single layer, here with a far face a photon may leave by).

/// Which face of a slab a ray meets.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Face {
    /// The entry face (for a sphere or cavity: its whole surface).
    Entry,
    /// The slab's far face, z = t.
    Far,
}

/// A slab of thickness t [cm].
#[derive(Clone, Copy, Debug)]
pub(crate) struct Slab {
    /// Thickness t [cm].
    pub thickness: f64,
}

impl Slab {
    /// Distance [cm] from `p` along the unit direction `u` to the face it moves towards, and that
    /// face; `None` for a ray parallel to the faces. A point that rounding put a hair outside
    /// leaves at distance 0.
    #[inline]
    pub fn distance(&self, p: [f64; 3], u: [f64; 3]) -> Option<(f64, Face)> {
        if u[2] > 0.0 {
            Some((((self.thickness - p[2]) / u[2]).max(0.0), Face::Far))
        } else if u[2] < 0.0 {
            Some(((-p[2] / u[2]).max(0.0), Face::Entry))
        } else {
            None
        }
    }

    /// The unit normal of `face` pointing out of the slab.
    #[inline]
    pub fn outward_normal(face: Face) -> [f64; 3] {
        match face {
            Face::Entry => [0.0, 0.0, -1.0],
            Face::Far => [0.0, 0.0, 1.0],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rays_meet_the_face_they_move_towards() {
        let s = Slab { thickness: 2.0 };
        let c = 0.6f64;
        let u = [(1.0 - c * c).sqrt(), 0.0, c];
        assert_eq!(s.distance([0.0, 0.0, 0.5], u), Some((1.5 / c, Face::Far)));
        let down = [u[0], 0.0, -c];
        assert_eq!(
            s.distance([0.0, 0.0, 0.5], down),
            Some((0.5 / c, Face::Entry))
        );
        assert_eq!(s.distance([0.0, 0.0, 0.5], [1.0, 0.0, 0.0]), None);
        assert_eq!(
            s.distance([0.0, 0.0, -1e-17], down),
            Some((0.0, Face::Entry))
        );
    }
}
