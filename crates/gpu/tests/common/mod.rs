//! Shared by the GPU tests: the device, or a skip outside CI when there is none.

use gpu::Gpu;

/// The adapter wgpu finds; None (test skipped) without one, except under CI=true, where a
/// missing adapter is a failure.
pub fn gpu() -> Option<Gpu> {
    match Gpu::new() {
        Ok(g) => Some(g),
        Err(e) if std::env::var("CI").as_deref() == Ok("true") => panic!("CI=true and {e}"),
        Err(e) => {
            eprintln!("skipping GPU test: {e}");
            None
        }
    }
}
