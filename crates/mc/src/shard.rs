//! Shard files: the exact sums of a slice of a batch run's chunks, with the run's full
//! specification, so that `merge` can check shards belong together and rebuild exactly the
//! unsharded result. JSON; i128 sums are written as decimal strings, zero entries omitted.
//!
//! A shard file is untrusted input. [`Shard::from_json`] checks it against the specification it
//! carries before allocating anything: the specification validates (grids and tallies within
//! [`BatchSpec::validate`]'s limits), one label per channel, chunks within the run, one group per
//! walk of the specification, each with exactly the layout and photon count the specification and
//! chunks imply, and entries in range, in increasing order and non-negative. [`merge`] then checks
//! the shards against each other: one run (the same specification and labels), chunks that tile
//! the run exactly, and sums that fit their fixed-point type. Every refusal names the file, the
//! field and the value.

use std::ops::Range;

use serde::{Deserialize, Serialize};

use crate::batch::BatchSpec;
use crate::error::{McError, Result};
use crate::job::chunk_count;
use crate::rng::CHUNK_PHOTONS;
use crate::tally::{Accumulator, Layout};

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
pub(crate) struct ShardFile {
    format: String,
    spec: BatchSpec,
    labels: Vec<String>,
    chunks: [u64; 2],
    groups: Vec<GroupFile>,
}

#[derive(Serialize, Deserialize)]
pub(crate) struct GroupFile {
    layout: Layout,
    photons: u64,
    interactions: u64,
    /// (index, Σw, Σw²) in 2⁻⁶⁴ fixed point, non-zero entries only.
    entries: Vec<(usize, String, String)>,
}

const FORMAT: &str = "sss-shard-2";

/// The chunk range of shard `i` (0-based) of `n` for a run of `photons`.
pub fn shard_chunks(photons: u64, i: u64, n: u64) -> Range<u64> {
    let (total, i, n) = (chunk_count(photons) as u128, i as u128, n as u128);
    ((total * i / n) as u64)..((total * (i + 1) / n) as u64)
}

/// Photons traced by chunks `chunks` of a run of `photons` (the last chunk may be partial).
pub fn chunk_photons(photons: u64, chunks: &Range<u64>) -> u64 {
    let at = |c: u64| c.saturating_mul(CHUNK_PHOTONS).min(photons);
    at(chunks.end).saturating_sub(at(chunks.start))
}

/// The first field in which two layouts differ, with both values.
fn layout_difference(got: &Layout, want: &Layout) -> Option<(&'static str, String, String)> {
    let sizes = [
        ("nr", got.nr, want.nr),
        ("nz", got.nz, want.nz),
        ("na", got.na, want.na),
        ("layers", got.layers, want.layers),
        ("channels", got.channels, want.channels),
        ("xy", got.xy, want.xy),
        ("scores", got.scores, want.scores),
    ];
    sizes
        .into_iter()
        .find(|(_, a, b)| a != b)
        .map(|(f, a, b)| (f, a.to_string(), b.to_string()))
        .or_else(|| (got.rz != want.rz).then(|| ("rz", got.rz.to_string(), want.rz.to_string())))
}

/// Checks a shard's groups (layout and photon count of each) against what its specification and
/// chunks imply, before anything is sized by them.
fn check_groups(
    spec: &BatchSpec,
    chunks: &Range<u64>,
    groups: &[(Layout, u64)],
) -> std::result::Result<(), String> {
    let walks = spec.groups();
    if groups.len() != walks.len() {
        return Err(format!(
            "groups: {} where the spec has {} walk groups",
            groups.len(),
            walks.len()
        ));
    }
    let photons = chunk_photons(spec.photons, chunks);
    for (k, ((layout, n), walk)) in groups.iter().zip(&walks).enumerate() {
        if let Some((field, got, want)) = layout_difference(layout, &spec.layout(walk)) {
            return Err(format!(
                "group {k} layout {field} = {got}, but the spec implies {want}"
            ));
        }
        if *n != photons {
            return Err(format!(
                "group {k} photons = {n}, but chunks {chunks:?} hold {photons}"
            ));
        }
    }
    Ok(())
}

/// The first field in which two runs' specifications differ, with both values.
fn spec_difference(a: &BatchSpec, b: &BatchSpec) -> Option<(String, String, String)> {
    let scalars = [
        ("seed", a.seed.to_string(), b.seed.to_string()),
        ("photons", a.photons.to_string(), b.photons.to_string()),
        ("n_above", a.n_above.to_string(), b.n_above.to_string()),
        ("n_below", a.n_below.to_string(), b.n_below.to_string()),
        (
            "tallies",
            format!("{:?}", a.tallies),
            format!("{:?}", b.tallies),
        ),
        (
            "channels",
            a.channels.len().to_string(),
            b.channels.len().to_string(),
        ),
    ];
    if let Some((f, x, y)) = scalars.into_iter().find(|(_, x, y)| x != y) {
        return Some((f.to_string(), x, y));
    }
    let i = a
        .channels
        .iter()
        .zip(&b.channels)
        .position(|(x, y)| x != y)?;
    Some((
        format!("channel {i}"),
        format!("{:?}", a.channels[i]),
        format!("{:?}", b.channels[i]),
    ))
}

impl Shard {
    /// The shard file's text.
    pub fn to_json(&self) -> String {
        serde_json::to_string(&self.to_file()).expect("shard data is always serializable")
    }

    /// The shard as its file's data (also embedded in table shard files).
    pub(crate) fn to_file(&self) -> ShardFile {
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
        ShardFile {
            format: FORMAT.into(),
            spec: self.spec.clone(),
            labels: self.labels.clone(),
            chunks: [self.chunks.start, self.chunks.end],
            groups,
        }
    }

    /// Reads a shard file and checks it against the specification it carries (see the module
    /// docs); `source_name` names the file in error messages.
    pub fn from_json(text: &str, source_name: &str) -> Result<Self> {
        let f: ShardFile = serde_json::from_str(text)
            .map_err(|e| McError::parse(source_name, e.line(), e.to_string()))?;
        Self::from_file(f, source_name)
    }

    /// A shard file's data, checked as [`Shard::from_json`] checks it.
    pub(crate) fn from_file(f: ShardFile, source_name: &str) -> Result<Self> {
        let bad = |m: String| McError::parse(source_name, 0, m);
        if f.format != FORMAT {
            return Err(bad(format!(
                "format {:?} is not {FORMAT:?} (shards of another version cannot be merged)",
                f.format
            )));
        }
        let spec = f.spec;
        spec.validate().map_err(|e| bad(format!("spec: {e}")))?;
        if f.labels.len() != spec.channels.len() {
            return Err(bad(format!(
                "labels: {} for {} channels",
                f.labels.len(),
                spec.channels.len()
            )));
        }
        let total = chunk_count(spec.photons);
        let [start, end] = f.chunks;
        if start > end || end > total {
            return Err(bad(format!(
                "chunks {start}..{end} are not within the run's 0..{total}"
            )));
        }
        let chunks = start..end;
        let sizes: Vec<(Layout, u64)> = f.groups.iter().map(|g| (g.layout, g.photons)).collect();
        check_groups(&spec, &chunks, &sizes).map_err(bad)?;
        let mut groups = Vec::with_capacity(f.groups.len());
        for (k, g) in f.groups.into_iter().enumerate() {
            // Checked above: the layout is the one the spec implies, within its limits.
            let layout = g.layout;
            let mut acc = Accumulator::new(layout);
            acc.photons = g.photons;
            acc.interactions = g.interactions;
            let mut next = 0;
            for (i, s, s2) in g.entries {
                if i < next || i >= acc.sum.len() {
                    return Err(bad(format!(
                        "group {k} entry index {i}: entries must be in increasing order below {}",
                        acc.sum.len()
                    )));
                }
                next = i + 1;
                let sum = |v: &str| match v.parse::<i128>() {
                    Ok(x) if x >= 0 => Ok(x),
                    _ => Err(bad(format!(
                        "group {k} entry {i}: sum {v:?} is not a non-negative integer"
                    ))),
                };
                acc.sum[i] = sum(&s)?;
                acc.sum_sq[i] = sum(&s2)?;
            }
            groups.push(acc);
        }
        Ok(Shard {
            spec,
            labels: f.labels,
            chunks,
            groups,
        })
    }
}

/// Merges the shards of one run into the whole run's sums. Each shard comes with the name of
/// its file, for error messages. Fails unless the shards share the same specification and labels,
/// their chunk ranges tile the run exactly, and the sums fit their fixed-point type.
pub fn merge(shards: &[(String, Shard)]) -> Result<(BatchSpec, Vec<String>, Vec<Accumulator>)> {
    let mismatch = |m: String| McError::ShardMismatch(m);
    let (first_name, first) = shards
        .first()
        .ok_or_else(|| mismatch("no shards given".into()))?;
    for (name, s) in shards {
        let sizes: Vec<(Layout, u64)> = s.groups.iter().map(|a| (a.layout, a.photons)).collect();
        check_groups(&s.spec, &s.chunks, &sizes).map_err(|m| mismatch(format!("{name}: {m}")))?;
        if s.spec != first.spec {
            let (field, a, b) = spec_difference(&s.spec, &first.spec).unwrap_or_else(|| {
                (
                    "spec".into(),
                    format!("{:?}", s.spec),
                    format!("{:?}", first.spec),
                )
            });
            return Err(mismatch(format!(
                "{name} has {field} = {a} but {first_name} has {field} = {b}: shards of different runs"
            )));
        }
        if s.labels != first.labels {
            let i = (0..s.labels.len())
                .find(|&i| s.labels.get(i) != first.labels.get(i))
                .unwrap_or(s.labels.len());
            return Err(mismatch(format!(
                "{name} labels channel {i} {:?} but {first_name} labels it {:?}: shards of different runs",
                s.labels.get(i),
                first.labels.get(i)
            )));
        }
    }
    let mut order: Vec<&(String, Shard)> = shards.iter().collect();
    order.sort_by_key(|(_, s)| (s.chunks.start, s.chunks.end));
    let total = chunk_count(first.spec.photons);
    let mut next = 0;
    let mut previous = "the start of the run";
    for (name, s) in &order {
        if s.chunks.start > next {
            return Err(mismatch(format!(
                "chunks {next}..{} are missing (between {previous} and {name})",
                s.chunks.start
            )));
        }
        if s.chunks.start < next {
            return Err(mismatch(format!(
                "{name} has chunks {:?}, which overlap {previous}'s (up to chunk {next})",
                s.chunks
            )));
        }
        next = s.chunks.end;
        previous = name;
    }
    if next < total {
        return Err(mismatch(format!(
            "chunks {next}..{total} are missing (after {previous})"
        )));
    }
    if next > total {
        return Err(mismatch(format!(
            "{previous} has chunks up to {next}, beyond the run's {total}"
        )));
    }
    // Not `Accumulator::merge`: these sums come from files, so overflow is an error, not a panic.
    let mut groups = order[0].1.groups.clone();
    for (name, s) in &order[1..] {
        for (k, (a, b)) in groups.iter_mut().zip(&s.groups).enumerate() {
            let overflow = |field: &str| {
                mismatch(format!(
                    "{name} group {k} {field}: the merged sum overflows"
                ))
            };
            for (x, y) in a.sum.iter_mut().zip(&b.sum) {
                *x = x.checked_add(*y).ok_or_else(|| overflow("Σw"))?;
            }
            for (x, y) in a.sum_sq.iter_mut().zip(&b.sum_sq) {
                *x = x.checked_add(*y).ok_or_else(|| overflow("Σw²"))?;
            }
            a.photons += b.photons; // the chunks tile the run: at most its photon count
            a.interactions = a
                .interactions
                .checked_add(b.interactions)
                .ok_or_else(|| overflow("interactions"))?;
        }
    }
    Ok((first.spec.clone(), first.labels.clone(), groups))
}

/// Checks that shard labels are what `sss simulate` writes, since output files are named after
/// them: one `SLUG:R`, `SLUG:G`, `SLUG:B` triple per material, the slug a plain file name (not
/// empty, `.` or `..`, without a path separator or control character).
pub fn check_labels(labels: &[String]) -> Result<()> {
    if !labels.len().is_multiple_of(3) {
        return Err(McError::ShardLabelCount(labels.len()));
    }
    for m in labels.chunks(3) {
        let slug = m[0].split(':').next().unwrap_or_default();
        let plain = !slug.is_empty()
            && slug != "."
            && slug != ".."
            && !slug.contains(['/', '\\'])
            && !slug.chars().any(char::is_control);
        for (label, channel) in m.iter().zip(crate::CHANNELS) {
            if !plain || *label != format!("{slug}:{channel}") {
                return Err(McError::ShardLabel {
                    label: label.clone(),
                    channel,
                });
            }
        }
    }
    Ok(())
}
