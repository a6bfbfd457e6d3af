//! What the crates' tests share, as a dev-dependency instead of files included by `#[path]`:
//! Chandrasekhar's H-function and Gauss–Legendre nodes ([`chandrasekhar`]), hostile text for
//! parser property tests ([`hostile`]) and the one χ² judgement of the statistical tests
//! ([`chi2::reduced_limit`]). It depends on no workspace crate.

pub mod chandrasekhar;
pub mod chi2;
pub mod hostile;
