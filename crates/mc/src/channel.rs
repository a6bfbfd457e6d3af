//! The colour channels every material, profile and kernel carries, in order.

/// Channel names, in order.
pub const CHANNELS: [&str; 3] = ["R", "G", "B"];
