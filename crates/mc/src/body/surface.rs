//! The surface tally of a body run: each exit binned where it leaves the body's own surface and
//! how, with the per-photon sums that give every number a standard error.
//!
//! Per surface (the entry side — a sphere's or cavity's whole surface, a slab's entry face — and
//! a slab's far face), in the order they lie in the tally's scores:
//! - exits by (radius along the surface, azimuth), [ir][iφ]: Σw and Σw²;
//! - exits by exit angle to the local normal, in air: Σw and Σw²;
//! - the first moment along the plane of incidence: Σw·x and Σ(w·x)², then Σw²·x (the cross
//!   moment of w and w·x, for the standard error of the ratio Σw·x/Σw);
//! - the mean radius likewise: Σw·s, Σ(w·s)², then Σw²·s;
//! - the window, the exits within the grid's reach s < nr·dr: Σw and Σw², then its first
//!   moment (Σw·x, Σ(w·x)², Σw²·x) and mean radius (Σw·s, Σ(w·s)², Σw²·s) as above.
//!
//! A photon leaves once, so each sum of squares is one of per-photon scores. The absorbed weight
//! is gathered over a history and tallied as (Σ, Σ²) when it ends. Units: cm, rad.

use super::shape::Shape;
use super::spec::SurfaceGrid;
use crate::photon::{Depth, Photon, Scorer};
use crate::tally::{Layout, Tally};

/// Offsets of a body run's entries within the tally's scores.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SurfaceLayout {
    pub grid: SurfaceGrid,
}

impl SurfaceLayout {
    /// Radius × azimuth bins of one surface.
    pub fn cells(&self) -> usize {
        self.grid.nr * self.grid.n_azimuth
    }

    /// Offset of the exit-angle bins within a surface's block.
    pub fn exits(&self) -> usize {
        self.cells()
    }

    /// Offset of the moments (along: Σ w·x, Σ w²·x; radius: Σ w·s, Σ w²·s) within a block.
    pub fn moments(&self) -> usize {
        self.cells() + self.grid.n_exit
    }

    /// Offset of the window (Σw; Σw·x, Σw²·x; Σw·s, Σw²·s) within a block.
    pub fn window(&self) -> usize {
        self.moments() + 4
    }

    /// The window's reach nr·dr [cm]: exits nearer the entry along the surface are in it.
    pub fn reach(&self) -> f64 {
        self.grid.nr as f64 * self.grid.dr
    }

    /// Entries of one surface: cells, exit angles, the two moments' two entries each and the
    /// window's five.
    pub fn per_surface(&self) -> usize {
        self.window() + 5
    }

    /// Offset of a surface's block (entry side first, then the far face), after the total
    /// absorption entry.
    pub fn surface(&self, entry_side: bool) -> usize {
        self.tally_layout().scores_offset(0) + if entry_side { 0 } else { self.per_surface() }
    }

    /// The tally layout: the total absorption (A) and two surfaces' scores.
    pub fn tally_layout(&self) -> Layout {
        Layout {
            nr: 0,
            nz: 0,
            na: 0,
            layers: 0,
            rz: false,
            rz_se: false,
            channels: 1,
            xy: 0,
            scores: 2 * self.per_surface(),
        }
    }
}

/// Scores the walk's exits on the body's surface.
pub(crate) struct SurfaceScorer<'a> {
    tally: &'a mut Tally,
    shape: Shape,
    layout: SurfaceLayout,
    inv_dr: f64,
    inv_d_azimuth: f64,
    inv_d_exit: f64,
    /// The window's reach nr·dr [cm].
    reach: f64,
    /// Weight absorbed so far in this history.
    absorbed: f64,
}

impl<'a> SurfaceScorer<'a> {
    pub fn new(tally: &'a mut Tally, shape: Shape, grid: SurfaceGrid) -> Self {
        SurfaceScorer {
            tally,
            shape,
            layout: SurfaceLayout { grid },
            reach: SurfaceLayout { grid }.reach(),
            inv_dr: 1.0 / grid.dr,
            inv_d_azimuth: 1.0 / grid.d_azimuth(),
            inv_d_exit: 1.0 / grid.d_exit(),
            absorbed: 0.0,
        }
    }

    #[inline]
    fn add(&mut self, i: usize, v: f64) {
        self.tally.sum[i] += v;
        self.tally.sum_sq[i] += v * v;
    }
}

impl Scorer for SurfaceScorer<'_> {
    fn depth(&self) -> Depth {
        Depth::None
    }

    #[inline]
    fn absorb(&mut self, _: &Photon, dw: f64) {
        self.absorbed += dw;
    }

    // Never called: depth is `Depth::None`.
    fn deposit_summed(&mut self, _: f64, _: f64, _: f64) {}

    #[inline]
    fn absorb_total(&mut self, _: &Photon, dw: f64) {
        self.absorbed += dw;
    }

    fn escape(&mut self, p: &Photon, entry_side: bool, cos_exit: f64) {
        let g = self.layout.grid;
        let at = self.shape.surface_point([p.x, p.y, p.z]);
        let ir = ((at.radius * self.inv_dr) as usize).min(g.nr - 1);
        let iphi = ((at.azimuth * self.inv_d_azimuth) as usize).min(g.n_azimuth - 1);
        let ia = ((cos_exit.min(1.0).acos() * self.inv_d_exit) as usize).min(g.n_exit - 1);
        let o = self.layout.surface(entry_side);
        let w = p.w;
        self.add(o + ir * g.n_azimuth + iphi, w);
        self.add(o + self.layout.exits() + ia, w);
        let m = o + self.layout.moments();
        self.add(m, w * at.along);
        self.tally.sum[m + 1] += w * w * at.along;
        self.add(m + 2, w * at.radius);
        self.tally.sum[m + 3] += w * w * at.radius;
        if at.radius < self.reach {
            let k = o + self.layout.window();
            self.add(k, w);
            self.add(k + 1, w * at.along);
            self.tally.sum[k + 2] += w * w * at.along;
            self.add(k + 3, w * at.radius);
            self.tally.sum[k + 4] += w * w * at.radius;
        }
    }

    fn finish(&mut self, p: &Photon) {
        let a = std::mem::take(&mut self.absorbed);
        let i = self.tally.layout.a_total(0);
        self.add(i, a);
        self.tally.photons += 1;
        self.tally.interactions += p.interactions;
    }
}
