//! The frame's plumbing: the device and its queue ([`context`]), the targets a frame draws
//! into ([`target`]), the buffers and textures kept between frames ([`pool`]), the command
//! recording with its timestamps ([`recording`], [`timing`]).

pub mod context;
pub(crate) mod pool;
pub(crate) mod recording;
pub(crate) mod target;
pub mod timing;
