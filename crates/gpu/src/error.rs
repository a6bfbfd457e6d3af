//! Typed errors of the `gpu` crate.

/// What can go wrong on the GPU side.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    /// No adapter (hardware or software) could be found.
    #[error(
        "no GPU adapter found (install a Vulkan driver; for software rendering Mesa's lavapipe: apt-get install mesa-vulkan-drivers): {0}"
    )]
    NoAdapter(String),
    /// The adapter refused the device.
    #[error("GPU device request failed: {0}")]
    Device(String),
    /// An input is unusable; names the field.
    #[error("invalid {field} = {value}: {reason}")]
    Invalid {
        /// The input's name, e.g. `image size`.
        field: String,
        /// The offending value, as text.
        value: String,
        /// Why it was refused.
        reason: String,
    },
    /// A mesh file could not be read.
    #[error("mesh {path}: {message}")]
    Mesh {
        /// The file's path.
        path: String,
        /// What went wrong: the I/O or parse error, or why the mesh was refused.
        message: String,
    },
    /// Reading results back failed.
    #[error("GPU readback failed: {0}")]
    Readback(String),
    /// Fitting a kernel model for a comparison failed.
    #[error(transparent)]
    Fit(#[from] fit::FitError),
    /// A shading table is unusable.
    #[error(transparent)]
    Shading(#[from] shading::ShadingError),
}

impl GpuError {
    pub(crate) fn invalid(
        field: impl Into<String>,
        value: impl ToString,
        reason: impl Into<String>,
    ) -> Self {
        GpuError::Invalid {
            field: field.into(),
            value: value.to_string(),
            reason: reason.into(),
        }
    }
}

/// Result with [`GpuError`].
pub type Result<T> = std::result::Result<T, GpuError>;
