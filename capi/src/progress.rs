//! A C++ progress function watching one call ([`asperity::progress::cancellable`]): false
//! from it, or an exception it throws (kept on the C++ side), stops the call with
//! `Error::Cancelled`, which C++ turns into `asperity::Cancelled` or the exception.

use crate::bridge::ProgressCallback;

/// Runs `work` watched by `progress` when a function is set.
pub fn watched<T>(progress: &ProgressCallback, work: impl FnOnce() -> asperity::Result<T>) -> asperity::Result<T> {
    if !progress.watching() {
        return work();
    }
    let callback: *const ProgressCallback = progress;
    asperity::progress::cancellable(
        Box::new(move |stage, done, total| {
            // SAFETY: `cancellable` drops this closure before returning, and `progress`
            // outlives this call.
            unsafe { (*callback).report(stage, done, total) }
        }),
        work,
    )
}
