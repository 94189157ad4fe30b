//! Atomic output: write to a temporary file in the destination folder, then rename. Within
//! an [`OutputBatch`] (a command's whole output: levels, frames, tiles, scenes, sidecars) the
//! renames wait for the batch's commit, so a failure part way leaves no file, and no folder
//! the batch created.

use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard, PoisonError};

use crate::error::{Error, Result};

/// Temporary files being written, so that an interrupted run can remove them.
struct Pending {
    paths: Vec<PathBuf>,
    stopping: bool,
    /// Complete outputs waiting for their batch's commit, when a batch is open.
    batch: Option<Staged>,
}

/// A batch's complete temporary files, each with its destination, and the folders it made.
#[derive(Default)]
struct Staged {
    files: Vec<(tempfile::TempPath, PathBuf)>,
    folders: Vec<PathBuf>,
}

impl Staged {
    /// Deletes the temporary files (dropping them does) and then the folders made for them,
    /// deepest first, where nothing else went into them.
    fn discard(self) {
        drop(self.files);
        for folder in self.folders.iter().rev() {
            let _ = std::fs::remove_dir(folder);
        }
    }
}

static PENDING: Mutex<Pending> = Mutex::new(Pending { paths: Vec::new(), stopping: false, batch: None });

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
    if let Some(batch) = pending.batch.take() {
        batch.discard();
    }
}

/// All of a command's outputs, or none: while the batch is open, [`write_atomically`] keeps
/// each complete file under its temporary name, and [`OutputBatch::commit`] renames them all
/// into place. A batch dropped without its commit (an error, a panic) deletes them, and the
/// folders [`create_output_dir`] made. One batch at a time per process, and it holds every
/// thread's writes: the command line opens one around each command; a program embedding the
/// library opens one only where no other thread writes meanwhile. Outside a batch each file is
/// written at once. A rename that fails during the commit (rare: the files are in their
/// folders already) leaves the files renamed before it in place.
pub struct OutputBatch(());

impl OutputBatch {
    /// Opens the process's batch.
    ///
    /// # Errors
    /// [`Error::Internal`] if a batch is open already.
    pub fn open() -> Result<Self> {
        let mut pending = pending();
        if pending.batch.is_some() {
            return Err(Error::Internal("an output batch is open already".into()));
        }
        pending.batch = Some(Staged::default());
        Ok(OutputBatch(()))
    }

    /// Renames every staged file into place, in the order they were written.
    ///
    /// # Errors
    /// [`Error::Io`] naming the file whose rename failed (the ones before it are in place).
    pub fn commit(self) -> Result<()> {
        // Under the lock: a signal's handler waits for the renames rather than finding the
        // batch gone and leaving the temporary files of the ones not yet renamed.
        let mut pending = pending();
        let staged = pending.batch.take().unwrap_or_default();
        // A destination that became a folder meanwhile: nothing is renamed.
        if let Some(folder) = staged.files.iter().find_map(|(_, path)| refuse_folder(path).err()) {
            staged.discard();
            return Err(folder);
        }
        for (tmp, path) in staged.files {
            tmp.persist(&path).map_err(|e| Error::io(&path, e.error))?;
        }
        Ok(())
    }
}

impl Drop for OutputBatch {
    fn drop(&mut self) {
        let staged = pending().batch.take();
        if let Some(staged) = staged {
            staged.discard();
        }
    }
}

/// The size of the output just written at `path`: its staged file's while an
/// [`OutputBatch`] holds it, else the file's (sidecars record the size of what they describe).
///
/// # Errors
/// [`Error::Io`] naming `path` when neither exists.
pub fn written_size(path: &Path) -> Result<u64> {
    let staged = pending()
        .batch
        .as_ref()
        .and_then(|b| b.files.iter().find(|(_, dest)| dest == path).map(|(tmp, _)| tmp.to_path_buf()));
    let file = staged.as_deref().unwrap_or(path);
    std::fs::metadata(file).map(|m| m.len()).map_err(|e| Error::io(path, e))
}

/// Creates `dir` and its missing parents; inside an open [`OutputBatch`], the ones it made are
/// removed again if the batch is not committed.
///
/// # Errors
/// [`Error::Io`] naming the folder.
pub fn create_output_dir(dir: &Path) -> Result<()> {
    let mut missing = Vec::new();
    let mut at = Some(dir);
    while let Some(folder) = at.filter(|f| !f.as_os_str().is_empty() && !f.exists()) {
        missing.push(folder.to_path_buf());
        at = folder.parent();
    }
    let made = std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e));
    if let Some(batch) = pending().batch.as_mut() {
        // Even when the call failed part way, the folders it did make are the batch's.
        batch.folders.extend(missing.into_iter().rev().filter(|f| f.is_dir()));
    }
    made
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
    // A folder cannot be replaced by a file: refused before anything is written (in a
    // batch, its rename would fail only at the commit, after the command's report).
    refuse_folder(path)?;
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
        // tempfile's error names its own random path: keep the operating system's words.
        let tmp = builder
            .tempfile_in(dir)
            .map_err(|e| Error::io(path, e.raw_os_error().map_or(e, std::io::Error::from_raw_os_error)))?;
        pending.paths.push(tmp.path().to_path_buf());
        let registered = Registered(tmp.path().to_path_buf());
        (tmp, registered)
    };
    {
        let mut w = BufWriter::new(tmp.as_file());
        fill(&mut w).map_err(|e| Error::io(path, e))?;
        w.flush().map_err(|e| Error::io(path, e))?;
    }
    let tmp = tmp.into_temp_path();
    {
        let mut pending = pending();
        if let Some(batch) = pending.batch.as_mut() {
            // A second write to one path within the batch replaces the first.
            batch.files.retain(|(_, dest)| dest != path);
            batch.files.push((tmp, path.to_path_buf()));
            return Ok(());
        }
    }
    tmp.persist(path).map_err(|e| Error::io(path, e.error))?;
    Ok(())
}

/// [`Error::Io`] naming `path` when it is an existing folder (an output file's path).
///
/// # Errors
/// As said.
pub fn refuse_folder(path: &Path) -> Result<()> {
    match std::fs::metadata(path) {
        Ok(m) if m.is_dir() => Err(Error::io(path, std::io::Error::from(std::io::ErrorKind::IsADirectory))),
        _ => Ok(()),
    }
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
