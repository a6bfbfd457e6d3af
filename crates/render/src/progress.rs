//! How a plan reports the Monte Carlo runs it makes, for a caller's progress bars.

/// Where a plan reports the Monte Carlo runs it makes: each run begins with a label and its
/// photon count, advances (from any thread) and ends. `()` reports nothing.
pub trait Progress: Sync {
    /// A run of `photons` photons in all begins.
    fn begin(&self, label: &str, photons: u64);
    /// `photons` more have been traced.
    fn advance(&self, photons: u64);
    /// The run has ended.
    fn end(&self);
}

impl Progress for () {
    fn begin(&self, _: &str, _: u64) {}
    fn advance(&self, _: u64) {}
    fn end(&self) {}
}
