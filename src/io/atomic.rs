//! Atomic output: write to a temporary file in the destination folder, then rename.

use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard, PoisonError};

use crate::error::{Error, Result};

/// Temporary files being written, so that an interrupted run can remove them.
struct Pending {
    paths: Vec<PathBuf>,
    stopping: bool,
}

static PENDING: Mutex<Pending> = Mutex::new(Pending { paths: Vec::new(), stopping: false });

fn pending() -> MutexGuard<'static, Pending> {
    PENDING.lock().unwrap_or_else(PoisonError::into_inner)
}

/// Removes every temporary output file being written and refuses new ones: for a handler
/// of SIGINT/SIGTERM, which then ends the process, so that it leaves no partial file.
pub fn abandon_pending_outputs() {
    let mut pending = pending();
    pending.stopping = true;
    for path in pending.paths.drain(..) {
        let _ = std::fs::remove_file(path);
    }
}

/// Takes a temporary file's path off the pending list when the write ends, either way.
struct Registered(PathBuf);

impl Drop for Registered {
    fn drop(&mut self) {
        pending().paths.retain(|p| *p != self.0);
    }
}

/// Writes through `fill` into a temporary file beside `path` and renames it over `path`
/// once complete, so readers never see a partial file and a failure leaves nothing.
/// Devices and pipes (which cannot be renamed over) are written directly.
///
/// # Errors
/// [`Error::Io`] naming `path` if creating, writing or renaming fails.
pub fn write_atomically(path: &Path, fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>) -> Result<()> {
    // A device or pipe (/dev/null, /dev/stdout, a FIFO) cannot be replaced by a rename:
    // write to it directly.
    if std::fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir()) {
        let file = std::fs::OpenOptions::new().write(true).open(path).map_err(|e| Error::io(path, e))?;
        let mut w = BufWriter::new(file);
        fill(&mut w).map_err(|e| Error::io(path, e))?;
        return w.flush().map_err(|e| Error::io(path, e));
    }
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    // Temporary files are private (0600); the result gets the permissions of the file it
    // replaces, or the usual 0644 for a new one.
    let mut builder = tempfile::Builder::new();
    builder.prefix(".asperity-").suffix(".tmp");
    if let Some(permissions) = std::fs::metadata(path).ok().map(|m| m.permissions()).or_else(default_permissions) {
        builder.permissions(permissions);
    }
    // Created and registered under the lock, so an interrupt sees every temporary file.
    let (tmp, _registered) = {
        let mut pending = pending();
        if pending.stopping {
            return Err(Error::io(path, std::io::Error::new(std::io::ErrorKind::Interrupted, "interrupted")));
        }
        let tmp = builder.tempfile_in(dir).map_err(|e| Error::io(path, e))?;
        pending.paths.push(tmp.path().to_path_buf());
        let registered = Registered(tmp.path().to_path_buf());
        (tmp, registered)
    };
    {
        let mut w = BufWriter::new(tmp.as_file());
        fill(&mut w).map_err(|e| Error::io(path, e))?;
        w.flush().map_err(|e| Error::io(path, e))?;
    }
    tmp.persist(path).map_err(|e| Error::io(path, e.error))?;
    Ok(())
}

#[cfg(unix)]
fn default_permissions() -> Option<std::fs::Permissions> {
    use std::os::unix::fs::PermissionsExt;
    Some(std::fs::Permissions::from_mode(0o644))
}

#[cfg(not(unix))]
fn default_permissions() -> Option<std::fs::Permissions> {
    None
}
