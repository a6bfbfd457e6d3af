//! Typed errors of the `shading` crate.

/// What can go wrong building or checking a shading table.
#[derive(Debug, thiserror::Error)]
pub enum ShadingError {
    /// An input or a table entry is unusable; names the field.
    #[error("invalid {field} = {value}: {reason}")]
    Invalid {
        /// The input's name, e.g. `exit table`.
        field: String,
        /// The offending value, as text.
        value: String,
        /// Why it was refused.
        reason: String,
    },
    /// A Monte Carlo run for a table failed.
    #[error(transparent)]
    Mc(#[from] mc::McError),
    /// A profile could not be read.
    #[error(transparent)]
    Fit(#[from] fit::FitError),
    /// The lookups' WGSL did not translate (a bug: the tests translate it).
    #[error("the lookups' shaders do not translate to {0}")]
    Shader(String),
}

impl ShadingError {
    pub(crate) fn invalid(
        field: impl Into<String>,
        value: impl ToString,
        reason: impl Into<String>,
    ) -> Self {
        ShadingError::Invalid {
            field: field.into(),
            value: value.to_string(),
            reason: reason.into(),
        }
    }
}

/// Result with [`ShadingError`].
pub type Result<T> = std::result::Result<T, ShadingError>;
