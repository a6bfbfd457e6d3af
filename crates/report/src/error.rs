//! Typed errors of the `report` crate; each names the offending picture, field or value.

use fit::FitError;
use gpu::GpuError;

/// What can go wrong while drawing a plot or building a report.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// A plot could not be drawn.
    #[error("plot {path}: {message}")]
    Plot {
        /// What the picture is, e.g. `skin1 Pareto plot` (plots are returned as bytes, so this
        /// names the picture, not a file).
        path: String,
        /// What went wrong.
        message: String,
    },

    /// An input of a report is unusable (a missing profile or table row).
    #[error("invalid {field} = {value}: {reason}")]
    Invalid {
        /// The input's name.
        field: String,
        /// The offending value, as text.
        value: String,
        /// Why it was refused.
        reason: String,
    },

    /// A profile of a folder the user named does not stand for what was asked.
    #[error("{0}")]
    Refused(String),

    /// The run settings, a material or a file were refused, or a run failed.
    #[error(transparent)]
    Mc(#[from] mc::McError),

    /// The numerics underneath failed.
    #[error(transparent)]
    Fit(#[from] FitError),

    /// The photon tracer on the GPU refused or failed.
    #[error(transparent)]
    McGpu(#[from] mc_gpu::McGpuError),

    /// A render underneath failed.
    #[error(transparent)]
    Gpu(#[from] GpuError),
}

impl ReportError {
    pub(crate) fn invalid(
        field: impl Into<String>,
        value: impl ToString,
        reason: impl Into<String>,
    ) -> Self {
        ReportError::Invalid {
            field: field.into(),
            value: value.to_string(),
            reason: reason.into(),
        }
    }
}

/// Result with [`ReportError`].
pub type Result<T> = std::result::Result<T, ReportError>;
