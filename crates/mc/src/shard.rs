//! Shard files: the exact sums of a slice of a batch run's chunks, with the run's full
//! specification, so that `merge` can check shards belong together and rebuild exactly the
//! unsharded result. JSON; i128 sums are written as decimal strings, zero entries omitted.

use std::ops::Range;

use serde::{Deserialize, Serialize};

use crate::batch::BatchSpec;
use crate::error::{McError, Result};
use crate::simulate::chunk_count;
use crate::tally::Accumulator;

/// A shard: which chunks, of which run, and their sums (one accumulator per batch group).
#[derive(Clone, Debug, PartialEq)]
pub struct Shard {
    /// The whole run's specification.
    pub spec: BatchSpec,
    /// Free-form labels for the channels (material and channel names), kept with the data.
    pub labels: Vec<String>,
    /// The chunks this shard traced.
    pub chunks: Range<u64>,
    /// Exact sums, one per walk group.
    pub groups: Vec<Accumulator>,
}

#[derive(Serialize, Deserialize)]
struct ShardFile {
    format: String,
    spec: BatchSpec,
    labels: Vec<String>,
    chunks: [u64; 2],
    groups: Vec<GroupFile>,
}

#[derive(Serialize, Deserialize)]
struct GroupFile {
    layout: crate::tally::Layout,
    photons: u64,
    interactions: u64,
    /// (index, Σw, Σw²) in 2⁻⁶⁴ fixed point, non-zero entries only.
    entries: Vec<(usize, String, String)>,
}

const FORMAT: &str = "sss-shard-1";

/// The chunk range of shard `i` (0-based) of `n` for a run of `photons`.
pub fn shard_chunks(photons: u64, i: u64, n: u64) -> Range<u64> {
    let total = chunk_count(photons);
    (total * i / n)..(total * (i + 1) / n)
}

impl Shard {
    /// The shard file's text.
    pub fn to_json(&self) -> String {
        let groups = self
            .groups
            .iter()
            .map(|a| GroupFile {
                layout: a.layout,
                photons: a.photons,
                interactions: a.interactions,
                entries: (0..a.sum.len())
                    .filter(|&i| a.sum[i] != 0 || a.sum_sq[i] != 0)
                    .map(|i| (i, a.sum[i].to_string(), a.sum_sq[i].to_string()))
                    .collect(),
            })
            .collect();
        let f = ShardFile {
            format: FORMAT.into(),
            spec: self.spec.clone(),
            labels: self.labels.clone(),
            chunks: [self.chunks.start, self.chunks.end],
            groups,
        };
        serde_json::to_string(&f).expect("shard data is always serializable")
    }

    /// Reads a shard file; `source_name` is used in error messages.
    pub fn from_json(text: &str, source_name: &str) -> Result<Self> {
        let bad = |m: String| McError::parse(source_name, 0, m);
        let f: ShardFile = serde_json::from_str(text)
            .map_err(|e| McError::parse(source_name, e.line(), e.to_string()))?;
        if f.format != FORMAT {
            return Err(bad(format!("format {:?} is not {FORMAT:?}", f.format)));
        }
        let mut groups = Vec::with_capacity(f.groups.len());
        for g in f.groups {
            let mut acc = Accumulator::new(g.layout);
            acc.photons = g.photons;
            acc.interactions = g.interactions;
            for (i, s, s2) in g.entries {
                if i >= acc.sum.len() {
                    return Err(bad(format!("entry index {i} beyond the tally")));
                }
                acc.sum[i] = s.parse().map_err(|_| bad(format!("bad sum {s:?}")))?;
                acc.sum_sq[i] = s2.parse().map_err(|_| bad(format!("bad sum {s2:?}")))?;
            }
            groups.push(acc);
        }
        Ok(Shard {
            spec: f.spec,
            labels: f.labels,
            chunks: f.chunks[0]..f.chunks[1],
            groups,
        })
    }
}

/// Merges shards of one run into the whole run's sums. Fails unless the shards share the same
/// specification and their chunk ranges tile the run exactly.
pub fn merge(shards: &[Shard]) -> Result<(BatchSpec, Vec<String>, Vec<Accumulator>)> {
    let first = shards
        .first()
        .ok_or_else(|| McError::ShardMismatch("no shards given".into()))?;
    let mut order: Vec<&Shard> = shards.iter().collect();
    order.sort_by_key(|s| s.chunks.start);
    let mut next = 0;
    for s in &order {
        if s.spec != first.spec || s.labels != first.labels {
            return Err(McError::ShardMismatch(
                "shards come from different runs (specifications differ)".into(),
            ));
        }
        if s.chunks.start != next {
            return Err(McError::ShardMismatch(format!(
                "chunks {next}..{} are missing or overlap",
                s.chunks.start
            )));
        }
        next = s.chunks.end;
    }
    let total = chunk_count(first.spec.photons);
    if next != total {
        return Err(McError::ShardMismatch(format!(
            "chunks {next}..{total} are missing"
        )));
    }
    let mut groups = order[0].groups.clone();
    for s in &order[1..] {
        if s.groups.len() != groups.len() {
            return Err(McError::ShardMismatch(
                "shards have different group counts".into(),
            ));
        }
        for (a, b) in groups.iter_mut().zip(&s.groups) {
            a.merge(b);
        }
    }
    Ok((first.spec.clone(), first.labels.clone(), groups))
}
