//! `report`: what people look at, built on the numerics of `mc`, `fit` and `gpu` — plots as PNG
//! bytes ([`plot`], [`pareto`]), Rd(θ) of `mc` beside the analytic models ([`incidence`]), the comparison sheet of rendered kernels against their ground
//! truth ([`sheet`]), the thesis's tables and claims regenerated with the HTML page
//! ([`reproduce`]) and the whole run of `sss reproduce` ([`reproduction`]), the rendered Tables
//! 6.4–6.5 ([`rendered`]), what a finished simulation writes and prints ([`simulation`]) and the
//! result types of the Mitsuba scripts' JSON ([`reproduce::MitsubaImages`]).
//!
//! Nothing here computes physics the libraries below do not: it arranges, compares and draws
//! their numbers. Every picture is returned as bytes; the caller decides where it goes.

#![deny(missing_docs)]
// Units are written in brackets as in the papers, [cm⁻¹]; rustdoc would take them for links.
#![allow(rustdoc::broken_intra_doc_links)]
// Per-channel loops index parallel [_; 3] arrays (profile, kernels, colours) by channel.
#![allow(clippy::needless_range_loop)]

mod error;
pub mod evaluation;
pub mod image;
pub mod incidence;
pub mod pareto;
pub mod plot;
pub mod profile_comparison;
pub mod render_checks;
pub mod rendered;
pub mod reproduce;
pub mod reproduction;
pub mod sheet;
pub mod simulation;
pub mod simulation_run;
pub mod tracer_bench;

pub use error::{ReportError, Result};
