//! How a plan reports the Monte Carlo runs it makes, for a caller's progress bars, and what it
//! did for the user to know: `mc`'s [`Progress`], which every library above reports to.

pub use mc::progress::Progress;
