//! Progress of long stages, as a facade in the manner of the `log` crate: library code
//! reports `(stage, done, total)` through [`report`] and pays almost nothing when no sink
//! is installed; the command line installs one that draws progress bars on a terminal.
//! Reports never change a result: the sink only watches.

use std::sync::RwLock;

/// Receives progress reports: `stage` has done `done` of `total` steps.
pub type Sink = Box<dyn Fn(&str, u64, u64) + Send + Sync>;

static SINK: RwLock<Option<Sink>> = RwLock::new(None);

/// Installs `sink` for every later report (replacing any earlier one).
pub fn install(sink: Sink) {
    if let Ok(mut slot) = SINK.write() {
        *slot = Some(sink);
    }
}

/// Removes the installed sink.
pub fn uninstall() {
    if let Ok(mut slot) = SINK.write() {
        *slot = None;
    }
}

/// Reports that `stage` has done `done` of `total` steps (to the installed sink, if any).
pub fn report(stage: &str, done: u64, total: u64) {
    if let Ok(slot) = SINK.read()
        && let Some(sink) = slot.as_ref() {
            sink(stage, done.min(total), total);
        }
}
