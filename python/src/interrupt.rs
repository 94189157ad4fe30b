//! Long calls release the GIL and can be interrupted with Ctrl-C. The work runs on a
//! worker thread while the calling thread, holding the GIL only between naps, checks for
//! signals; on Ctrl-C it raises a cancellation flag that the library's progress reports
//! (`asperity::progress`) turn into an unwind of the worker at its next report, so no
//! computation is left running. Progress is printed to stderr only when asked for, or
//! handed to a Python callback (`progress=callable`): it runs on the worker thread under
//! the GIL, and returning False stops the call (`asperity.Cancelled`) through the
//! library's `progress::cancellable`; an exception it raises arrives unchanged.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use std::sync::Arc;

use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;

use crate::{InternalError, to_py};

/// What a call does with its progress reports: the Python `progress` argument.
pub enum Progress {
    /// Nothing (False).
    Off,
    /// Printed to stderr (True).
    Print,
    /// Handed to a callable `(stage, done, total)`; False from it cancels.
    Call(Py<PyAny>),
}

impl Progress {
    /// `progress=`: a bool or a callable.
    pub fn of(value: &Bound<'_, PyAny>) -> PyResult<Self> {
        if let Ok(on) = value.extract::<bool>() {
            return Ok(if on { Progress::Print } else { Progress::Off });
        }
        if value.is_callable() {
            return Ok(Progress::Call(value.clone().unbind()));
        }
        Err(PyTypeError::new_err(format!(
            "progress must be True, False or a function (stage, done, total), not {}",
            value.get_type().name()?
        )))
    }

    /// The callback's answer to one report (true: go on); an exception it raises is kept
    /// in `raised` and stops the call.
    pub fn ask(callback: &Py<PyAny>, raised: &Mutex<Option<PyErr>>, stage: &str, done: u64, total: u64) -> bool {
        Python::attach(|py| match callback.call1(py, (stage, done, total)) {
            Ok(answer) => !says_stop(answer.bind(py)),
            Err(error) => {
                *raised.lock().unwrap_or_else(|p| p.into_inner()) = Some(error);
                false
            }
        })
    }
}

/// The progress line `progress=True` prints on stderr: `stage: NN%`, redrawn in place,
/// ended when the stage is done.
pub fn print_progress(stage: &str, percent: u64, done: bool) {
    eprint!("\r{stage}: {percent:3}%{}", if done { "\n" } else { "" });
}

/// Whether a callback's answer means stop: a false bool (Python's or numpy's); None and
/// anything else mean go on.
pub fn says_stop(answer: &Bound<'_, PyAny>) -> bool {
    answer.extract::<bool>().is_ok_and(|go_on| !go_on)
}

thread_local! {
    /// Set on a call's worker thread: a progress callback runs there, and an asperity call
    /// it made would wait forever for the call it is part of.
    static IN_WORKER: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

impl From<bool> for Progress {
    fn from(on: bool) -> Self {
        if on { Progress::Print } else { Progress::Off }
    }
}

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
pub fn run<T: Send>(
    py: Python<'_>,
    progress: impl Into<Progress>,
    work: impl FnOnce() -> asperity::Result<T> + Send,
) -> PyResult<T> {
    if IN_WORKER.with(|w| w.get()) {
        return Err(pyo3::exceptions::PyRuntimeError::new_err(
            "asperity cannot be called from a progress callback (the call it watches holds the library); call it afterwards",
        ));
    }
    let progress = progress.into();
    let print = matches!(progress, Progress::Print);
    let callback = match progress {
        Progress::Call(callback) => Some(callback),
        _ => None,
    };
    let raised: Arc<Mutex<Option<PyErr>>> = Arc::default();
    let kept = Arc::clone(&raised);
    let work = move || match callback {
        None => work(),
        Some(callback) => asperity::progress::cancellable(
            Box::new(move |stage, done, total| Progress::ask(&callback, &kept, stage, done, total)),
            work,
        ),
    };
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
        if print {
            let percent = (done * 100).checked_div(total).unwrap_or(100);
            let mut last = last.lock().unwrap_or_else(|p| p.into_inner());
            if last.0 != stage || last.1 != percent {
                print_progress(stage, percent, done >= total);
                *last = (stage.to_string(), percent);
            }
        }
    }));
    let (outcome, interrupted) = std::thread::scope(|scope| {
        let worker = scope.spawn(move || {
            IN_WORKER.with(|w| w.set(true));
            catch_unwind(AssertUnwindSafe(work))
        });
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
    if let Some(error) = raised.lock().unwrap_or_else(|p| p.into_inner()).take() {
        return Err(error);
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
