//! Progress of long stages, as a facade in the manner of the `log` crate: library code
//! reports `(stage, done, total)` through [`report`] and pays almost nothing when no sink
//! is installed; the command line installs one that draws progress bars on a terminal.
//! Reports never change a result: the sink only watches. A caller that wants to watch
//! one call and maybe stop it (a GUI's progress bar with a cancel button, Python's and
//! C++'s progress callbacks) runs it through [`cancellable`].

use std::cell::RefCell;
use std::panic::AssertUnwindSafe;
use std::sync::RwLock;

use crate::error::{Error, Result};

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
    ask_callback(stage, done.min(total), total);
    if let Ok(slot) = SINK.read()
        && let Some(sink) = slot.as_ref() {
            sink(stage, done.min(total), total);
        }
}

/// A callback that watches one call's progress on the calling thread and may stop it: it
/// returns `false` to cancel.
pub type Callback = Box<dyn Fn(&str, u64, u64) -> bool>;

thread_local! {
    /// The callback of the [`cancellable`] call running on this thread, if any.
    static CALLBACK: RefCell<Option<Callback>> = const { RefCell::new(None) };
}

/// The unwind payload that carries a cancellation from a report to [`cancellable`].
struct CancelRequest {
    stage: String,
    done: u64,
    total: u64,
}

/// Runs `work` with `callback` receiving the progress reports made on this thread (before
/// the installed sink); when the callback returns `false`, the work stops at that report
/// (an unwind, so every object it was building is dropped) and this returns
/// [`Error::Cancelled`]. Reports made on other threads (rayon's) are not seen: a call is
/// cancelled at its next report on the calling thread. Calls nest: the inner callback
/// watches the inner call.
///
/// # Errors
/// [`Error::Cancelled`], or what `work` returns. A panic in `work` goes on unwinding.
pub fn cancellable<T>(callback: Callback, work: impl FnOnce() -> Result<T>) -> Result<T> {
    let outer = CALLBACK.with(|c| c.replace(Some(callback)));
    let outcome = std::panic::catch_unwind(AssertUnwindSafe(work));
    CALLBACK.with(|c| *c.borrow_mut() = outer);
    match outcome {
        Ok(result) => result,
        Err(payload) => match payload.downcast::<CancelRequest>() {
            Ok(request) => {
                Err(Error::Cancelled { stage: request.stage, done: request.done, total: request.total })
            }
            Err(other) => std::panic::resume_unwind(other),
        },
    }
}

/// Asks this thread's [`cancellable`] callback, if any; unwinds to it when it says stop.
/// The callback is out of its slot while it runs, so a call it makes (a report, or a
/// `cancellable` call of its own) finds no callback of this one's.
fn ask_callback(stage: &str, done: u64, total: u64) {
    let Some(callback) = CALLBACK.with(|c| c.borrow_mut().take()) else { return };
    /// Puts the callback back, also when it unwinds.
    struct Restore(Option<Callback>);
    impl Drop for Restore {
        fn drop(&mut self) {
            let callback = self.0.take();
            CALLBACK.with(|c| *c.borrow_mut() = callback);
        }
    }
    let restore = Restore(Some(callback));
    let go_on = restore.0.as_ref().is_none_or(|callback| callback(stage, done, total));
    drop(restore);
    if !go_on {
        // resume_unwind: a cancellation is not a panic, so no panic message is printed.
        std::panic::resume_unwind(Box::new(CancelRequest { stage: stage.to_string(), done, total }));
    }
}
