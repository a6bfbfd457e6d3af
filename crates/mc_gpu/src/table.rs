//! Profile tables on the GPU (`sss table --device gpu`): mc's tables ([`mc::table`]) traced by the
//! compute pass, written and read as the CPU's.
//!
//! Each walk is the table's channel walk at σt = 1 (lengths in mean free paths), with the CPU's
//! roulettes. An exit through the top is scored once per albedo on the table's radial intervals
//! (between consecutive [`mc::table::radius_edges`]; [`TableSpec::table_from_intervals`] forms
//! the cumulative reflectance from them). A white table ([`TableSpec::white`]) traces its largest
//! albedo's walk once and scores an exit of weight w after n interactions w·(α/α_max)ⁿ for every
//! albedo α (mc's `white.rs`, Alerstam et al. 2008); otherwise each albedo traces its own walk.
//!
//! The cut: per exit, the albedos are scored from the largest down until a weight rounds to 0 in
//! the tallies' fixed point (below 2⁻³³ of the incident power); every smaller albedo's weight is
//! smaller still, so the cut drops only scores that would add nothing. Rounding each score to the
//! unit 2⁻³² biases a tally by at most 2⁻³³ per photon, below 10⁻⁵ of the smallest bin a table
//! reads with any precision.
//!
//! Photon k of a walk draws from its own stream of (the walk's seed, k); the walk's seed mixes the
//! table's seed with its medium, as a batch channel's does (`lib.rs`). The same seed gives the
//! same table on the same adapter; it is not the CPU's table bit for bit (other streams, f32),
//! but equal within noise (`tests/table.rs`).

use gpu::Gpu;
use mc::table::{IntervalSums, LEVELS, Table, TableSpec, radius_edges};

use crate::error::Result;
use crate::medium::Walk;
use crate::tracer::{Target, Tracer};

/// ln(α/α_walk) for the shader: finite (−10³⁰ for α = 0, whose weight after any interaction is 0).
fn ln_ratio(albedo: f64, walk: f64) -> f32 {
    ((albedo / walk).ln().max(-1e30)) as f32
}

/// Builds `specs`' tables on the GPU with one [`Tracer`] (see [`Tracer::table`]): the tables in
/// order and the interactions traced in all.
pub fn tables(
    gpu: &Gpu,
    specs: &[TableSpec],
    progress: &(dyn Fn(u64) + Sync),
) -> Result<(Vec<Table>, u64)> {
    let tracer = Tracer::new(gpu)?;
    let mut out = (Vec::with_capacity(specs.len()), 0);
    for spec in specs {
        let (table, interactions) = tracer.table(gpu, spec, progress)?;
        out.0.push(table);
        out.1 += interactions;
    }
    Ok(out)
}

impl Tracer {
    /// Builds `spec`'s table on the GPU (see the module documentation): the table, which names
    /// the adapter in [`Table::tracer`], and the interactions traced. `progress` is called with
    /// the photons each dispatch finished (a white table's walk once, else each albedo's).
    pub fn table(
        &self,
        gpu: &Gpu,
        spec: &TableSpec,
        progress: &(dyn Fn(u64) + Sync),
    ) -> Result<(Table, u64)> {
        spec.validate()?;
        let batch = spec.batch();
        let edges: Vec<f32> = radius_edges().iter().map(|&e| e as f32).collect();
        let intervals = edges.len() + 1;
        let n = spec.albedos.len();
        // (the walk's albedo, the albedos it scores), in the table's order.
        let walks: Vec<(usize, std::ops::Range<usize>)> = if spec.white {
            vec![(n - 1, 0..n)]
        } else {
            (0..n).map(|i| (i, i..i + 1)).collect()
        };
        let (mut rows, mut interactions) = (Vec::with_capacity(n), 0);
        for (w, scored) in walks {
            // The albedo's first channel: its medium (all its levels share it).
            let walk = Walk::of_channel(&batch, w * LEVELS)?;
            let ln: Vec<f32> = spec.albedos[scored.clone()]
                .iter()
                .map(|&a| ln_ratio(a, spec.albedos[w]))
                .collect();
            let target = Target::Table {
                ln_ratio: &ln,
                edges: &edges,
            };
            let seed = crate::channel_seed(&batch, w * LEVELS);
            let sums = self.trace(gpu, &walk, &target, spec.photons, seed, progress)?;
            interactions += sums.interactions;
            for k in 0..scored.len() {
                let block = k * intervals..(k + 1) * intervals;
                rows.push(IntervalSums {
                    sum: sums.sum[block.clone()].to_vec(),
                    sum_sq: sums.sum_sq[block].to_vec(),
                    photons: sums.photons,
                });
            }
        }
        let tracer = format!("gpu: {}", gpu.adapter_name);
        Ok((spec.table_from_intervals(&rows, &tracer)?, interactions))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ratios_are_finite_and_zero_for_the_walks_albedo() {
        assert_eq!(ln_ratio(0.9, 0.9), 0.0);
        assert_eq!(ln_ratio(0.0, 0.9), -1e30);
        assert!((ln_ratio(0.45, 0.9) - 0.5f32.ln()).abs() < 1e-7);
    }
}
