//! Long calls release the GIL and can be interrupted with Ctrl-C. The work runs on a
//! worker thread while the calling thread, holding the GIL only between naps, checks for
//! signals; on Ctrl-C it raises a cancellation flag that the library's progress reports
//! (`asperity::progress`) turn into an unwind of the worker at its next report, so no
//! computation is left running. Progress is printed to stderr only when asked for.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use pyo3::prelude::*;

use crate::{InternalError, to_py};

/// Set by Ctrl-C during a call; the progress sink unwinds the worker when it sees it.
static CANCEL: AtomicBool = AtomicBool::new(false);

/// One call at a time: the progress sink is process-wide.
static CALL: Mutex<()> = Mutex::new(());

/// The panic payload of a cancelled worker.
struct Cancelled;

/// Keeps the default panic message for real panics and none for cancellations.
pub fn quiet_cancellation_panics() {
    let previous = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        if info.payload().downcast_ref::<Cancelled>().is_none() {
            previous(info);
        }
    }));
}

/// Runs `work` on a worker thread with the GIL released, interruptible by Ctrl-C at the
/// library's progress reports; `progress` prints them to stderr.
pub fn run<T: Send>(py: Python<'_>, progress: bool, work: impl FnOnce() -> asperity::Result<T> + Send) -> PyResult<T> {
    // Waiting for another thread's call, this thread holds the GIL only between naps: that
    // call's thread needs it to finish (#36: taking the lock with the GIL held deadlocked
    // two Python threads for good).
    let _one = loop {
        match CALL.try_lock() {
            Ok(guard) => break guard,
            Err(std::sync::TryLockError::Poisoned(poisoned)) => break poisoned.into_inner(),
            Err(std::sync::TryLockError::WouldBlock) => {
                py.detach(|| std::thread::sleep(Duration::from_millis(1)));
                py.check_signals()?;
            }
        }
    };
    CANCEL.store(false, Ordering::SeqCst);
    let last = Mutex::new((String::new(), u64::MAX));
    asperity::progress::install(Box::new(move |stage, done, total| {
        if CANCEL.load(Ordering::SeqCst) {
            std::panic::panic_any(Cancelled);
        }
        if progress {
            let percent = (done * 100).checked_div(total).unwrap_or(100);
            let mut last = last.lock().unwrap_or_else(|p| p.into_inner());
            if last.0 != stage || last.1 != percent {
                eprint!("\r{stage}: {percent:3}%{}", if done >= total { "\n" } else { "" });
                *last = (stage.to_string(), percent);
            }
        }
    }));
    let (outcome, interrupted) = std::thread::scope(|scope| {
        let worker = scope.spawn(move || catch_unwind(AssertUnwindSafe(work)));
        let mut interrupted = None;
        while !worker.is_finished() {
            py.detach(|| std::thread::sleep(Duration::from_millis(5)));
            if interrupted.is_none()
                && let Err(signal) = py.check_signals()
            {
                CANCEL.store(true, Ordering::SeqCst);
                interrupted = Some(signal);
            }
        }
        (worker.join(), interrupted)
    });
    asperity::progress::uninstall();
    CANCEL.store(false, Ordering::SeqCst);
    if let Some(signal) = interrupted {
        return Err(signal);
    }
    match outcome {
        Ok(Ok(Ok(value))) => Ok(value),
        Ok(Ok(Err(error))) => Err(to_py(error)),
        Ok(Err(panic)) | Err(panic) => {
            let message = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "a panic".into());
            Err(InternalError::new_err(format!("internal error (please report): {message}")))
        }
    }
}
