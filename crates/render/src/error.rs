//! Typed errors of the `render` crate.

/// What can go wrong assembling or drawing a render.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// An option, or a combination of options, is refused; names the [`crate::Request`] field.
    #[error("invalid {field} {value}: {reason}")]
    Invalid {
        /// The request's field, e.g. `entry_shift`.
        field: String,
        /// The offending value, as text.
        value: String,
        /// Why it was refused.
        reason: String,
    },
    /// A material's profile could not be had (the caller's profile source failed).
    #[error("the profile of {material}: {reason}")]
    Profile {
        /// The material's short name.
        material: String,
        /// What the profile source said.
        reason: String,
    },
    /// A folder of profile tables holds none.
    #[error("no table in {0} (expected files *.table.json from `sss table`)")]
    NoTables(String),
    /// The renderer refused a setting or failed.
    #[error(transparent)]
    Gpu(#[from] gpu::GpuError),
    /// A shading table could not be built.
    #[error(transparent)]
    Shading(#[from] shading::ShadingError),
    /// A kernel could not be fitted.
    #[error(transparent)]
    Fit(#[from] fit::FitError),
    /// The run settings or a material were refused.
    #[error(transparent)]
    Mc(#[from] mc::McError),
}

impl RenderError {
    pub(crate) fn invalid(
        field: impl Into<String>,
        value: impl ToString,
        reason: impl Into<String>,
    ) -> Self {
        RenderError::Invalid {
            field: field.into(),
            value: value.to_string(),
            reason: reason.into(),
        }
    }

    /// The same error with a refusal's field renamed by `name` (e.g. to the command-line flag
    /// that set it); other errors unchanged. A [`gpu::GpuError::Invalid`] counts as a refusal.
    pub fn renamed(self, name: impl Fn(&str) -> Option<String>) -> Self {
        let (field, value, reason) = match self {
            RenderError::Invalid {
                field,
                value,
                reason,
            }
            | RenderError::Gpu(gpu::GpuError::Invalid {
                field,
                value,
                reason,
            }) => (field, value, reason),
            e => return e,
        };
        RenderError::Invalid {
            field: name(&field).unwrap_or(field),
            value,
            reason,
        }
    }
}

/// Result with [`RenderError`].
pub type Result<T> = std::result::Result<T, RenderError>;
