//! GPU timestamps per pass, where the adapter has timestamp queries.

use crate::error::Result;
use crate::frame::context::Gpu;

/// GPU time of one pass [ms] (timestamp queries).
#[derive(Clone, Debug, PartialEq)]
pub struct PassTime {
    /// The pass's label, e.g. `pass 1 horizontal`.
    pub label: String,
    /// Its GPU time [ms].
    pub ms: f64,
}

/// Timestamp bookkeeping: two queries per timed pass.
pub(crate) struct Timer {
    set: wgpu::QuerySet,
    labels: Vec<String>,
}

/// Enough for 4 materials × 12 terms × 2 passes and the other passes of a frame.
const MAX_TIMED: u32 = 128;

impl Timer {
    pub(crate) fn new(gpu: &Gpu) -> Option<Timer> {
        gpu.timestamps.then(|| Timer {
            set: gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count: 2 * MAX_TIMED,
            }),
            labels: Vec::new(),
        })
    }

    pub(crate) fn writes(&mut self, label: &str) -> wgpu::ComputePassTimestampWrites<'_> {
        let k = (self.labels.len() as u32).min(MAX_TIMED - 1);
        self.labels.push(label.to_string());
        wgpu::ComputePassTimestampWrites {
            query_set: &self.set,
            beginning_of_pass_write_index: Some(2 * k),
            end_of_pass_write_index: Some(2 * k + 1),
        }
    }

    /// The timestamp writes of a render pass labelled `label`.
    pub(crate) fn render_writes(&mut self, label: &str) -> wgpu::RenderPassTimestampWrites<'_> {
        let k = (self.labels.len() as u32).min(MAX_TIMED - 1);
        self.labels.push(label.to_string());
        wgpu::RenderPassTimestampWrites {
            query_set: &self.set,
            beginning_of_pass_write_index: Some(2 * k),
            end_of_pass_write_index: Some(2 * k + 1),
        }
    }

    /// Reserves one timed span over several consecutive passes; see [`Timer::span_writes`].
    pub(crate) fn span(&mut self, label: &str) -> u32 {
        let k = (self.labels.len() as u32).min(MAX_TIMED - 1);
        self.labels.push(label.to_string());
        k
    }

    /// The timestamp writes of a pass inside span `k`: its start on the `first` pass, its end on
    /// the `last`.
    pub(crate) fn span_writes(
        &self,
        k: u32,
        first: bool,
        last: bool,
    ) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        (first || last).then_some(wgpu::ComputePassTimestampWrites {
            query_set: &self.set,
            beginning_of_pass_write_index: first.then_some(2 * k),
            end_of_pass_write_index: last.then_some(2 * k + 1),
        })
    }

    pub(crate) fn read(&self, gpu: &Gpu) -> Result<Vec<PassTime>> {
        let n = (self.labels.len() as u32).min(MAX_TIMED);
        if n == 0 {
            return Ok(Vec::new());
        }
        let buf = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("timestamps"),
            size: 16 * n as u64,
            usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let mut enc = gpu.device.create_command_encoder(&Default::default());
        enc.resolve_query_set(&self.set, 0..2 * n, &buf, 0);
        gpu.queue.submit([enc.finish()]);
        let bytes = gpu.read_buffer(&buf, 16 * n as u64)?;
        let ticks: &[u64] = bytemuck::cast_slice(&bytes);
        let period = gpu.queue.get_timestamp_period() as f64;
        Ok(self
            .labels
            .iter()
            .zip(ticks.chunks(2))
            .map(|(l, t)| PassTime {
                label: l.clone(),
                ms: t[1].wrapping_sub(t[0]) as f64 * period * 1e-6,
            })
            .collect())
    }
}
