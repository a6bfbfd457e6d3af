//! One frame's recording: what every pass of [`crate::Renderer`] records into (the device, where
//! its buffers come from, the frame's one command encoder, its timestamp queries), handed to each
//! pass in turn, so that a pass's own arguments are only what it reads and writes.

use crate::frame::context::Gpu;
use crate::frame::pool::Alloc;
use crate::frame::timing::Timer;

/// The device, where the frame's buffers and textures come from, the frame's command encoder
/// and its timer (None where the adapter has no timestamp queries, or where nobody asked for
/// times).
pub(crate) struct Recording<'a> {
    pub gpu: &'a Gpu,
    pub alloc: Alloc<'a>,
    pub enc: wgpu::CommandEncoder,
    pub timer: Option<Timer>,
}

impl<'a> Recording<'a> {
    /// A new encoder on `alloc`'s device, timed where the adapter can.
    pub fn timed(alloc: Alloc<'a>, enc: wgpu::CommandEncoder) -> Self {
        Recording {
            gpu: alloc.gpu,
            alloc,
            enc,
            timer: Timer::new(alloc.gpu),
        }
    }

    /// A new encoder on `gpu`, untimed, with fresh buffers.
    pub fn untimed(gpu: &'a Gpu) -> Self {
        Recording {
            gpu,
            alloc: Alloc::fresh(gpu),
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
