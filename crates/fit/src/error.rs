//! Typed errors of the `fit` crate; each names the offending field or value.

/// What can go wrong while reading profiles or fitting kernels.
#[derive(Debug, thiserror::Error)]
pub enum FitError {
    /// A profile or parameter is unusable (too few bins, NaN, negative, all zero, …).
    #[error("invalid {field} = {value}: {reason}")]
    Invalid {
        field: String,
        value: String,
        reason: String,
    },

    /// A plot could not be drawn or written.
    #[error("plot {path}: {message}")]
    Plot { path: String, message: String },

    /// A text input (profile CSV, kernel TOML, parameter table) could not be parsed.
    #[error("{source_name}:{line}: {message}")]
    Parse {
        source_name: String,
        line: usize,
        message: String,
    },
}

impl FitError {
    pub(crate) fn invalid(
        field: impl Into<String>,
        value: impl ToString,
        reason: impl Into<String>,
    ) -> Self {
        FitError::Invalid {
            field: field.into(),
            value: value.to_string(),
            reason: reason.into(),
        }
    }
}

pub type Result<T> = std::result::Result<T, FitError>;
