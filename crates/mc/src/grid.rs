//! The tally grid in MCML's conventions: radial bins of width `dr` [cm], depth bins of width
//! `dz` [cm] and exit-angle bins of width `da` = π/(2·na) [rad]. Indices are truncated
//! coordinates (`ir = ⌊r/dr⌋`), and the last bin of each axis also collects everything beyond.

use crate::error::{McError, Result};

/// Grid sizes and spacings (MCML's `dz dr` / `nz nr na` input lines).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Grid {
    /// Radial bin width [cm].
    pub dr: f64,
    /// Depth bin width [cm].
    pub dz: f64,
    /// Number of radial bins.
    pub nr: usize,
    /// Number of depth bins.
    pub nz: usize,
    /// Number of exit-angle bins over [0, π/2].
    pub na: usize,
}

impl Grid {
    /// Exit-angle bin width [rad].
    pub fn da(&self) -> f64 {
        std::f64::consts::FRAC_PI_2 / self.na as f64
    }

    /// MCML's "optimal" radial coordinate of bin `ir` [cm]: r = [(i+½) + 1/(12(i+½))]·dr, the
    /// point at which a linearly varying profile equals its bin average over the annulus.
    pub fn r_optimal(&self, ir: usize) -> f64 {
        let c = ir as f64 + 0.5;
        (c + 1.0 / (12.0 * c)) * self.dr
    }

    /// Checks sizes and spacings; the error names the offending field.
    pub fn validate(&self) -> Result<()> {
        for (field, v) in [("dr", self.dr), ("dz", self.dz)] {
            if !(v.is_finite() && v > 0.0) {
                return Err(McError::invalid(
                    field,
                    v,
                    "grid spacing must be positive and finite",
                ));
            }
        }
        for (field, n) in [("nr", self.nr), ("nz", self.nz), ("na", self.na)] {
            if n == 0 || n > 1_000_000 {
                return Err(McError::invalid(
                    field,
                    n,
                    "number of bins must be in 1..=1000000",
                ));
            }
        }
        if self.nr.saturating_mul(self.nz) > 50_000_000
            || self.nr.saturating_mul(self.na) > 50_000_000
        {
            return Err(McError::invalid(
                "nr",
                self.nr,
                "2D tally would exceed 5e7 bins",
            ));
        }
        Ok(())
    }
}

/// Bin lookup for the photon loop: reciprocal spacings precomputed so indexing multiplies.
#[derive(Clone, Copy, Debug)]
pub(crate) struct GridIndex {
    inv_dr: f64,
    inv_dz: f64,
    inv_da: f64,
    nr: usize,
    nz: usize,
    na: usize,
}

impl GridIndex {
    pub fn new(g: &Grid) -> Self {
        GridIndex {
            inv_dr: 1.0 / g.dr,
            inv_dz: 1.0 / g.dz,
            inv_da: 1.0 / g.da(),
            nr: g.nr,
            nz: g.nz,
            na: g.na,
        }
    }

    /// Radial bin of radius `r` [cm], clamped to the last bin.
    #[inline]
    pub fn ir(&self, r: f64) -> usize {
        ((r * self.inv_dr) as usize).min(self.nr - 1)
    }

    /// Cell of the surface grid Rd(x, y) (2n + 1 cells of side dr per axis, centred on the beam)
    /// holding (x, y) [cm], row-major [iy][ix]; `None` outside it.
    #[inline]
    pub fn ixy(&self, x: f64, y: f64, n: usize) -> Option<usize> {
        let side = 2 * n + 1;
        let cell = |v: f64| {
            let i = (v * self.inv_dr + n as f64 + 0.5).floor();
            (i >= 0.0 && i < side as f64).then_some(i as usize)
        };
        Some(cell(y)? * side + cell(x)?)
    }

    /// Depth bin of depth `z` [cm], clamped to the last bin.
    #[inline]
    pub fn iz(&self, z: f64) -> usize {
        ((z * self.inv_dz) as usize).min(self.nz - 1)
    }

    /// Exit-angle bin of an exit direction with |cos α| = `cos_a`, clamped to the last bin.
    #[inline]
    pub fn ia(&self, cos_a: f64) -> usize {
        ((cos_a.min(1.0).acos() * self.inv_da) as usize).min(self.na - 1)
    }
}
