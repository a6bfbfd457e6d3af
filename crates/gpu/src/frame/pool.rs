//! What a [`crate::Renderer`] keeps between frames: the buffers and textures its passes create
//! (frame-sized targets, the kernels' taps, tables, meshes, uniforms), handed out again to the
//! next frame that asks for the same thing, so that drawing many frames of one scene allocates
//! and uploads only what changed. Whatever a frame did not ask for is released when the next
//! one begins.
//!
//! Passes ask through [`Alloc`]; without a pool (one-off passes such as the area table's
//! lookup) it creates everything fresh, as wgpu would.

use std::sync::{Mutex, MutexGuard};

use wgpu::util::DeviceExt;

use crate::frame::context::{Gpu, pixels, texture};

/// The resources kept between frames, and the lock that gives one frame at a time the use of
/// them (a frame holds it from recording until its images are read back).
#[derive(Default)]
pub(crate) struct FramePool {
    frame: Mutex<()>,
    kept: Mutex<Kept>,
}

#[derive(Default)]
struct Kept {
    /// Pixel buffers (written by passes): a frame's k-th request of a label and size gets the
    /// k-th buffer kept for it, zeroed when the frame begins, as a new buffer is.
    targets: Vec<Slot<(&'static str, usize), wgpu::Buffer>>,
    /// Textures (every one is cleared or wholly written by the pass that creates it): matched
    /// as the targets are.
    textures: Vec<Slot<TextureKey, wgpu::Texture>>,
    /// Read-only buffers, matched by their content: any number of requests share one.
    constants: Vec<Slot<ConstantKey, wgpu::Buffer>>,
}

struct Slot<K, T> {
    key: K,
    item: T,
    /// Handed out in the current frame.
    used: bool,
}

#[derive(Clone, Copy, PartialEq)]
struct TextureKey {
    label: &'static str,
    size: (u32, u32, u32),
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
}

struct ConstantKey {
    label: &'static str,
    usage: wgpu::BufferUsages,
    bytes: Vec<u8>,
}

impl FramePool {
    /// Starts a frame: waits for the frame before it to be done with the pool, releases what it
    /// did not use, and records into `enc` the zeroing of the pixel buffers kept. The frame owns
    /// the pool until the guard is dropped.
    pub(crate) fn begin(&self, enc: &mut wgpu::CommandEncoder) -> MutexGuard<'_, ()> {
        let guard = self.frame.lock().unwrap_or_else(|e| e.into_inner());
        let mut kept = self.kept();
        kept.targets.retain(|s| s.used);
        kept.textures.retain(|s| s.used);
        kept.constants.retain(|s| s.used);
        for s in &mut kept.targets {
            s.used = false;
            enc.clear_buffer(&s.item, 0, None);
        }
        kept.textures.iter_mut().for_each(|s| s.used = false);
        kept.constants.iter_mut().for_each(|s| s.used = false);
        guard
    }

    fn kept(&self) -> MutexGuard<'_, Kept> {
        self.kept.lock().unwrap_or_else(|e| e.into_inner())
    }
}

/// The next unused slot under `key`, marked used, or a new one made by `make`.
fn take<K: PartialEq, T: Clone>(
    slots: &mut Vec<Slot<K, T>>,
    key: K,
    make: impl FnOnce() -> T,
) -> T {
    if let Some(s) = slots.iter_mut().find(|s| !s.used && s.key == key) {
        s.used = true;
        return s.item.clone();
    }
    let item = make();
    slots.push(Slot {
        key,
        item: item.clone(),
        used: true,
    });
    item
}

/// Where a pass gets its buffers and textures: the renderer's pool, or the device directly.
#[derive(Clone, Copy)]
pub(crate) struct Alloc<'a> {
    pub gpu: &'a Gpu,
    pool: Option<&'a FramePool>,
}

impl<'a> Alloc<'a> {
    /// Fresh resources from `gpu`, nothing kept.
    pub fn fresh(gpu: &'a Gpu) -> Self {
        Alloc { gpu, pool: None }
    }

    /// Resources from `pool` (which the caller's frame owns, [`FramePool::begin`]).
    pub fn pooled(gpu: &'a Gpu, pool: &'a FramePool) -> Self {
        Alloc {
            gpu,
            pool: Some(pool),
        }
    }

    /// A zeroed storage buffer of `n` RGBA f32 pixels ([`crate::frame::context::pixels`]).
    pub fn pixels(self, n: usize, label: &'static str) -> wgpu::Buffer {
        match self.pool {
            None => pixels(self.gpu, n, label),
            Some(p) => take(&mut p.kept().targets, (label, n), || {
                pixels(self.gpu, n, label)
            }),
        }
    }

    /// A 2D texture (array) ([`crate::frame::context::texture`]); its content is undefined, so the pass
    /// must clear it or write all of it.
    pub fn texture(
        self,
        label: &'static str,
        size: (u32, u32, u32),
        format: wgpu::TextureFormat,
        usage: wgpu::TextureUsages,
    ) -> wgpu::Texture {
        let make = || texture(&self.gpu.device, label, size, format, usage);
        match self.pool {
            None => make(),
            Some(p) => {
                let key = TextureKey {
                    label,
                    size,
                    format,
                    usage,
                };
                take(&mut p.kept().textures, key, make)
            }
        }
    }

    /// A buffer holding `bytes` that no pass writes (uniforms, taps, tables, meshes): the one
    /// kept with the same label, usage and content, else a new upload.
    pub fn constant(
        self,
        label: &'static str,
        usage: wgpu::BufferUsages,
        bytes: &[u8],
    ) -> wgpu::Buffer {
        let make = || {
            self.gpu
                .device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(label),
                    contents: bytes,
                    usage,
                })
        };
        let Some(p) = self.pool else {
            return make();
        };
        let mut kept = p.kept();
        if let Some(s) = kept
            .constants
            .iter_mut()
            .find(|s| s.key.label == label && s.key.usage == usage && s.key.bytes == bytes)
        {
            s.used = true;
            return s.item.clone();
        }
        let item = make();
        kept.constants.push(Slot {
            key: ConstantKey {
                label,
                usage,
                bytes: bytes.to_vec(),
            },
            item: item.clone(),
            used: true,
        });
        item
    }

    /// A uniform buffer holding `bytes` ([`Alloc::constant`]).
    pub fn uniform(self, label: &'static str, bytes: &[u8]) -> wgpu::Buffer {
        self.constant(label, wgpu::BufferUsages::UNIFORM, bytes)
    }

    /// A read-only storage buffer holding `bytes` ([`Alloc::constant`]).
    pub fn storage(self, label: &'static str, bytes: &[u8]) -> wgpu::Buffer {
        self.constant(label, wgpu::BufferUsages::STORAGE, bytes)
    }
}
