//! One frame's recording: what every pass of [`crate::Renderer`] records into (the device, the
//! frame's one command encoder, its timestamp queries), handed to each pass in turn, so that a
//! pass's own arguments are only what it reads and writes.

use crate::context::Gpu;
use crate::timing::Timer;

/// The device, the frame's command encoder and its timer (None where the adapter has no
/// timestamp queries, or where nobody asked for times).
pub(crate) struct Recording<'a> {
    pub gpu: &'a Gpu,
    pub enc: wgpu::CommandEncoder,
    pub timer: Option<Timer>,
}

impl<'a> Recording<'a> {
    /// A new encoder on `gpu`, timed where the adapter can.
    pub fn timed(gpu: &'a Gpu) -> Self {
        Recording {
            gpu,
            enc: gpu.device.create_command_encoder(&Default::default()),
            timer: Timer::new(gpu),
        }
    }

    /// A new encoder on `gpu`, untimed.
    pub fn untimed(gpu: &'a Gpu) -> Self {
        Recording {
            gpu,
            enc: gpu.device.create_command_encoder(&Default::default()),
            timer: None,
        }
    }

    /// Submits what was recorded; returns the timer to read back.
    pub fn submit(self) -> Option<Timer> {
        self.gpu.queue.submit([self.enc.finish()]);
        self.timer
    }
}
