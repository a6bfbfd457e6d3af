//! How a library reports the Monte Carlo runs it makes, for a caller's progress bars, and what
//! it did for the user to know (a profile reused, simulated or interpolated; a step begun).

/// Where a library reports the Monte Carlo runs it makes: each run begins with a label and its
/// photon count, advances (from any thread) and ends; and lines for the user. `()` reports
/// nothing.
pub trait Progress: Sync {
    /// A run of `photons` photons in all begins.
    fn begin(&self, label: &str, photons: u64);
    /// `photons` more have been traced.
    fn advance(&self, photons: u64);
    /// The run has ended.
    fn end(&self);
    /// A line for the user, e.g. that a cached profile is reused (by default dropped).
    fn note(&self, line: &str) {
        let _ = line;
    }
}

impl Progress for () {
    fn begin(&self, _: &str, _: u64) {}
    fn advance(&self, _: u64) {}
    fn end(&self) {}
}
