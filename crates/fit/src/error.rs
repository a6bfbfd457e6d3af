//! Typed errors of the `fit` crate; each names the offending field or value.

/// What can go wrong while reading profiles or fitting kernels.
#[derive(Debug, thiserror::Error)]
pub enum FitError {
    /// A profile or parameter is unusable (too few bins, NaN, negative, all zero, …).
    #[error("invalid {field} = {value}: {reason}")]
    Invalid {
        /// The input's name, e.g. `sigma_a`.
        field: String,
        /// The offending value, as text.
        value: String,
        /// Why it was refused.
        reason: String,
    },

    /// A plot could not be drawn or written.
    #[error("plot {path}: {message}")]
    Plot {
        /// What the picture is, e.g. `skin1 Pareto plot` (plots are returned as bytes, so this
        /// names the picture, not a file).
        path: String,
        /// What went wrong.
        message: String,
    },

    /// A text input (profile CSV, kernel TOML, parameter table) could not be parsed.
    #[error("{source_name}:{line}: {message}")]
    Parse {
        /// File name (or other label) of the input.
        source_name: String,
        /// 1-based line, 0 when unknown.
        line: usize,
        /// What is wrong there.
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

/// Result with [`FitError`].
pub type Result<T> = std::result::Result<T, FitError>;
