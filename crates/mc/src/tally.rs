//! Raw tallies: sums of weights and of squared per-photon weights, in MCML's bins, before any
//! normalization. Second moments are per photon, so standard errors are exact estimates of the
//! sampling error (no batch means):
//! - a photon escapes at most once, so the exit tallies `Rd(r, α)` and `Tt(r, α)` get w and w²
//!   directly, and every 1D/0D exit quantity's second moment is a sum of theirs;
//! - absorption happens many times per photon, so deposits are gathered in a per-photon scratch
//!   (`A(r,z)`, `A(z)`, `A_l`, `A`) and flushed as (Σw, (Σw)²) when the photon's history ends;
//!   without `TallySet::absorption_rz_se`, `A(r,z)` and `A(z)` are summed directly (no second
//!   moments: their standard errors are NaN).
//!
//! Chunk tallies are summed into an [`Accumulator`] in 2⁻⁶⁴ fixed point (i128), which makes the
//! merge associative: results are bit-identical whatever the thread count, chunk order or shards.

use crate::grid::{Grid, GridIndex};
use crate::photon::{Depth, Photon, Scorer};

/// Which optional tallies to record. Exit tallies and total/per-layer absorption are always on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct TallySet {
    /// Record absorption on the (r, z) grid (MCML's `A_rz` and `A_z`). Costs a write per
    /// interaction; turn it off when only profiles are needed.
    pub absorption_rz: bool,
    /// With `absorption_rz`: estimate the standard errors of A(r, z) and A(z) from per-photon
    /// second moments (each history's deposits gathered per cell before squaring: a scratch
    /// write per interaction and a flush per photon, and the photon walk stays scalar). Off,
    /// A(r, z) and A(z) are summed as MCML sums them (one write per interaction, several photons
    /// in flight) and their standard errors are NaN: not estimated. Totals (A, A_l, Rd, Tt) and
    /// every exit tally keep exact standard errors either way.
    #[serde(default = "yes")]
    pub absorption_rz_se: bool,
    /// Record diffuse reflectance on a square surface grid Rd(x, y) of 2n + 1 cells per side
    /// with the radial grid's spacing dr, centred on the beam (n = this value; 0 = off). Needed
    /// when the profile is not radially symmetric (oblique incidence).
    #[serde(default)]
    pub surface_xy: usize,
}

fn yes() -> bool {
    true
}

impl Default for TallySet {
    fn default() -> Self {
        TallySet {
            absorption_rz: true,
            absorption_rz_se: true,
            surface_xy: 0,
        }
    }
}

/// Offsets of each quantity in the flat tally vectors.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Layout {
    /// Radial bins (stride).
    pub nr: usize,
    /// Depth bins (stride).
    pub nz: usize,
    /// Exit-angle bins (stride).
    pub na: usize,
    /// Layers.
    pub layers: usize,
    /// Whether A(r, z) and A(z) are recorded.
    pub rz: bool,
    /// Whether A(r, z) and A(z) carry per-photon second moments (else only sums: their
    /// standard errors are not estimated).
    #[serde(default = "yes")]
    pub rz_se: bool,
    /// Number of channels tallied side by side (1 except for batch runs).
    pub channels: usize,
    /// Half-width n of the surface grid Rd(x, y), (2n + 1)² cells; 0 = not recorded.
    #[serde(default)]
    pub xy: usize,
    /// Entries a job lays out itself after the channel's MCML tallies, each a sum of per-photon
    /// scores and of their squares (a body run's surface tallies, [`crate::body`]); 0 for MCML
    /// runs.
    #[serde(default)]
    pub scores: usize,
}

impl Layout {
    /// Entries per channel: Rd(r,α), Tt(r,α), A_l, A, then A(r,z) and A(z) if recorded, the
    /// surface grid and the job's own scores.
    pub fn per_channel(&self) -> usize {
        2 * self.nr * self.na
            + self.layers
            + 1
            + if self.rz {
                self.nr * self.nz + self.nz
            } else {
                0
            }
            + self.xy_cells()
            + self.scores
    }
    /// Cells of the surface grid (0 when not recorded).
    pub fn xy_cells(&self) -> usize {
        if self.xy > 0 {
            (2 * self.xy + 1).pow(2)
        } else {
            0
        }
    }
    /// Total entries of the flat tally vectors.
    pub fn entries(&self) -> usize {
        self.per_channel() * self.channels
    }
    /// Offset of channel `c`'s Rd(r, α), stored [ir][ia].
    pub fn rd_ra(&self, c: usize) -> usize {
        c * self.per_channel()
    }
    /// Offset of channel `c`'s Tt(r, α), stored [ir][ia].
    pub fn tt_ra(&self, c: usize) -> usize {
        self.rd_ra(c) + self.nr * self.na
    }
    /// Offset of channel `c`'s absorption per layer.
    pub fn a_l(&self, c: usize) -> usize {
        self.tt_ra(c) + self.nr * self.na
    }
    /// Offset of channel `c`'s total absorption.
    pub fn a_total(&self, c: usize) -> usize {
        self.a_l(c) + self.layers
    }
    /// Offset of A(r,z), stored [ir][iz]; only when `rz`.
    pub fn a_rz(&self, c: usize) -> usize {
        self.a_total(c) + 1
    }
    /// Offset of channel `c`'s A(z); only when `rz`.
    pub fn a_z(&self, c: usize) -> usize {
        self.a_rz(c) + self.nr * self.nz
    }
    /// Offset of channel `c`'s surface grid Rd(x, y), stored [iy][ix]; only when `xy` > 0.
    pub fn rd_xy(&self, c: usize) -> usize {
        self.a_total(c)
            + 1
            + if self.rz {
                self.nr * self.nz + self.nz
            } else {
                0
            }
    }
    /// Offset of channel `c`'s own scores; only when `scores` > 0.
    pub fn scores_offset(&self, c: usize) -> usize {
        self.rd_xy(c) + self.xy_cells()
    }
}

/// Sums of w and of per-photon w² for one chunk, in f64.
#[derive(Clone, Debug)]
pub struct Tally {
    pub layout: Layout,
    pub sum: Vec<f64>,
    pub sum_sq: Vec<f64>,
    pub photons: u64,
    pub interactions: u64,
}

impl Tally {
    pub fn new(layout: Layout) -> Self {
        Tally {
            layout,
            sum: vec![0.0; layout.entries()],
            sum_sq: vec![0.0; layout.entries()],
            photons: 0,
            interactions: 0,
        }
    }

    /// Adds this chunk into `acc` in exact fixed point and resets it to zero for reuse.
    pub fn drain_into(&mut self, acc: &mut Accumulator) {
        debug_assert_eq!(self.layout, acc.layout);
        for (s, a) in self.sum.iter_mut().zip(acc.sum.iter_mut()) {
            if *s != 0.0 {
                *a += to_fixed(*s);
                *s = 0.0;
            }
        }
        for (s, a) in self.sum_sq.iter_mut().zip(acc.sum_sq.iter_mut()) {
            if *s != 0.0 {
                *a += to_fixed(*s);
                *s = 0.0;
            }
        }
        acc.photons += self.photons;
        acc.interactions += self.interactions;
        self.photons = 0;
        self.interactions = 0;
    }
}

const FIXED_ONE: f64 = 18_446_744_073_709_551_616.0; // 2⁶⁴

#[inline]
fn to_fixed(x: f64) -> i128 {
    (x * FIXED_ONE).round() as i128
}

/// Exact (fixed-point, 2⁻⁶⁴ resolution) sums over many chunks. Integer addition is associative,
/// so any merge order gives the same bits. Headroom: |sums| < 2⁶³, far above any tally
/// (a chunk's sums are bounded by its photon count times the largest weight).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Accumulator {
    /// What each entry is.
    pub layout: Layout,
    /// Σw per entry, in units of 2⁻⁶⁴.
    pub sum: Vec<i128>,
    /// Σ(per-photon w)² per entry, in units of 2⁻⁶⁴.
    pub sum_sq: Vec<i128>,
    /// Photons traced (u64: 10⁹ photons and far beyond fit).
    pub photons: u64,
    /// Interaction events (drops) over all photons.
    pub interactions: u64,
}

impl Accumulator {
    /// All zero.
    pub fn new(layout: Layout) -> Self {
        Accumulator {
            layout,
            sum: vec![0; layout.entries()],
            sum_sq: vec![0; layout.entries()],
            photons: 0,
            interactions: 0,
        }
    }

    /// Adds another accumulator of the same layout.
    pub fn merge(&mut self, other: &Accumulator) {
        debug_assert_eq!(self.layout, other.layout);
        for (a, b) in self.sum.iter_mut().zip(&other.sum) {
            *a += b;
        }
        for (a, b) in self.sum_sq.iter_mut().zip(&other.sum_sq) {
            *a += b;
        }
        self.photons += other.photons;
        self.interactions += other.interactions;
    }

    /// Σw of entry `i` as f64.
    pub fn s(&self, i: usize) -> f64 {
        self.sum[i] as f64 / FIXED_ONE
    }

    /// Σw² of entry `i` as f64.
    pub fn s2(&self, i: usize) -> f64 {
        self.sum_sq[i] as f64 / FIXED_ONE
    }
}

/// Gathers one photon's deposits in a dense array with a list of touched cells, then flushes
/// (Σw, (Σw)²) per cell. No allocation after construction. The list has room for every cell (4
/// bytes per cell beside the value's 8), so a deposit appends its cell unconditionally and counts
/// it only if the cell was empty: no branch on the deposit's value (a cell once touched stays
/// positive: deposits are > 0).
#[derive(Clone, Debug)]
pub(crate) struct Scratch {
    value: Vec<f64>,
    touched: Vec<u32>,
    /// Cells touched since the last flush (the first `len` entries of `touched`).
    len: usize,
}

impl Scratch {
    pub fn new(n: usize) -> Self {
        Scratch {
            value: vec![0.0; n],
            // One slot beyond the cells: the unconditional append after all n are touched.
            touched: vec![0; n + 1],
            len: 0,
        }
    }

    /// Adds `w` > 0 to cell `i`.
    #[inline]
    pub fn add(&mut self, i: usize, w: f64) {
        let v = self.value[i];
        self.touched[self.len] = i as u32;
        self.len += usize::from(v == 0.0);
        self.value[i] = v + w;
    }

    /// Σ of the deposits since the last flush.
    pub fn total(&self) -> f64 {
        self.touched[..self.len]
            .iter()
            .map(|&i| self.value[i as usize])
            .sum()
    }

    /// Hands each touched cell and its value to `f`, and empties the scratch.
    #[inline]
    pub fn drain(&mut self, mut f: impl FnMut(usize, f64)) {
        for &i in &self.touched[..self.len] {
            let i = i as usize;
            f(i, std::mem::take(&mut self.value[i]));
        }
        self.len = 0;
    }

    /// Adds each touched cell's value v to `sum[offset + cell]` and v² to `sum_sq[…]`, and
    /// empties the scratch.
    pub fn flush(&mut self, offset: usize, sum: &mut [f64], sum_sq: &mut [f64]) {
        self.drain(|i, v| {
            sum[offset + i] += v;
            sum_sq[offset + i] += v * v;
        });
    }
}

/// The MCML tallies of one channel, fed by the walk.
pub(crate) struct McmlScorer<'a> {
    tally: &'a mut Tally,
    grid: GridIndex,
    /// A(r, z) and A(z) of the current history, when their per-photon moments are tallied.
    rz: Option<(Scratch, Scratch)>,
    a_l: Scratch,
    /// Offsets of A(r, z) and A(z) in the tally.
    offsets_rz: (usize, usize),
}

impl<'a> McmlScorer<'a> {
    pub fn new(tally: &'a mut Tally, grid: Grid) -> Self {
        let l = tally.layout;
        let rz = (l.rz && l.rz_se).then(|| (Scratch::new(l.nr * l.nz), Scratch::new(l.nz)));
        McmlScorer {
            tally,
            grid: GridIndex::new(&grid),
            rz,
            a_l: Scratch::new(l.layers),
            offsets_rz: (l.a_rz(0), l.a_z(0)),
        }
    }
}

impl Scorer for McmlScorer<'_> {
    fn depth(&self) -> Depth {
        depth_of(&self.tally.layout)
    }

    #[inline]
    fn absorb(&mut self, p: &Photon, dw: f64) {
        if dw == 0.0 {
            return;
        }
        self.absorb_total(p, dw);
        if let Some((a_rz, a_z)) = &mut self.rz {
            let iz = self.grid.iz(p.z);
            a_rz.add(self.grid.ir(p.r()) * self.tally.layout.nz + iz, dw);
            a_z.add(iz, dw);
        } else if self.tally.layout.rz {
            self.deposit_summed(p.r(), p.z, dw);
        }
    }

    #[inline]
    fn deposit_summed(&mut self, r: f64, z: f64, dw: f64) {
        let (o_rz, o_z) = self.offsets_rz;
        let iz = self.grid.iz(z);
        self.tally.sum[o_rz + self.grid.ir(r) * self.tally.layout.nz + iz] += dw;
        self.tally.sum[o_z + iz] += dw;
    }

    #[inline]
    fn absorb_total(&mut self, p: &Photon, dw: f64) {
        if dw != 0.0 {
            self.a_l.add(p.layer, dw);
        }
    }

    #[inline]
    fn escape(&mut self, p: &Photon, top: bool, cos_exit: f64) {
        let l = self.tally.layout;
        let i = self.grid.ir(p.r()) * l.na + self.grid.ia(cos_exit);
        let o = if top { l.rd_ra(0) } else { l.tt_ra(0) };
        self.tally.sum[o + i] += p.w;
        self.tally.sum_sq[o + i] += p.w * p.w;
        if top
            && l.xy > 0
            && let Some(j) = self.grid.ixy(p.x, p.y, l.xy)
        {
            self.tally.sum[l.rd_xy(0) + j] += p.w;
            self.tally.sum_sq[l.rd_xy(0) + j] += p.w * p.w;
        }
    }

    fn finish(&mut self, p: &Photon) {
        let l = self.tally.layout;
        let t = &mut *self.tally;
        let a = self.a_l.total();
        t.sum[l.a_total(0)] += a;
        t.sum_sq[l.a_total(0)] += a * a;
        self.a_l.flush(l.a_l(0), &mut t.sum, &mut t.sum_sq);
        if let Some((a_rz, a_z)) = &mut self.rz {
            a_rz.flush(l.a_rz(0), &mut t.sum, &mut t.sum_sq);
            a_z.flush(l.a_z(0), &mut t.sum, &mut t.sum_sq);
        }
        t.photons += 1;
        t.interactions += p.interactions;
    }
}

/// What a scorer with this layout keeps of deposits besides each history's total.
pub(crate) fn depth_of(l: &Layout) -> Depth {
    match (l.rz, l.rz_se) {
        (false, _) => Depth::None,
        (true, false) => Depth::Summed,
        (true, true) => Depth::PerPhoton,
    }
}
