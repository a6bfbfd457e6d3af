//! The methods that replace the separable kernel by a gather per pixel: over the lit surface
//! found through the lights' maps ([`disc_gather`]) with the directional dipole ([`dipole`]) or
//! the Monte Carlo BSSRDF ([`surface_gather`]), and Maisch & Ropinski's screen-space area
//! gather ([`area_gather`]).

pub mod area_gather;
pub mod dipole;
pub mod disc_gather;
pub mod surface_gather;
