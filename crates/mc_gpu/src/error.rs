//! Typed errors of the GPU tracer.

/// What can go wrong tracing photons on the GPU.
#[derive(Debug, thiserror::Error)]
pub enum McGpuError {
    /// The run's specification is invalid (the CPU tracer refuses it the same way).
    #[error(transparent)]
    Spec(#[from] mc::McError),
    /// Device creation or readback failed in the `gpu` crate.
    #[error(transparent)]
    Gpu(#[from] gpu::GpuError),
    /// The adapter cannot run the tracer's compute shader.
    #[error("the GPU adapter {adapter} cannot run the photon tracer: {reason}")]
    NoCompute {
        /// The adapter's name and backend.
        adapter: String,
        /// The limit it lacks.
        reason: String,
    },
    /// The tally buffer is larger than the adapter's storage buffers may be.
    #[error(
        "the tallies need a storage buffer of {needed} bytes, above the adapter's limit of {limit} bytes: use a coarser grid (fewer nr or na bins)"
    )]
    StorageTooSmall {
        /// Bytes the tallies need.
        needed: u64,
        /// The adapter's largest storage buffer binding [bytes].
        limit: u64,
    },
    /// A tally the GPU tracer does not record was asked for.
    #[error("the GPU tracer does not support {what}: {reason}")]
    Unsupported {
        /// The option or input.
        what: String,
        /// Why, and what to use instead.
        reason: String,
    },
    /// A fixed-point tally sum left its 64 bits within one round (see the crate's documentation
    /// for the bound): the results would be wrong, so none are returned.
    #[error(
        "a GPU tally overflowed its 64-bit fixed-point sum within a round of {round_photons} photons (photon weights far above 1 from the path-length roulette): run on the CPU"
    )]
    TallyOverflow {
        /// Photons per round (the tallies are read back and cleared after each).
        round_photons: u64,
    },
    /// The device reported an error (validation, out of memory, device lost).
    #[error("GPU device error: {0}")]
    Device(String),
}

/// Result with [`McGpuError`].
pub type Result<T> = std::result::Result<T, McGpuError>;
