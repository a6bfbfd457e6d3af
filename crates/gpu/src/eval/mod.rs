//! Evaluation beside the renderer's core: every kernel model against the CPU 2D ground truth
//! ([`compare`]) and the passes' timings ([`bench`]).

pub mod bench;
pub mod compare;
