//! Timing shared by the benchmarks.

use std::time::Instant;

/// The best of eleven runs of `f`, in seconds: this kind of machine is noisy, and the best
/// run is the one least disturbed by other work.
pub fn best_of(mut f: impl FnMut()) -> f64 {
    (0..11)
        .map(|_| {
            let start = Instant::now();
            f();
            start.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min)
}
