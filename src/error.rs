//! Errors, tiered by whose fault they are: bad input (exit code 2), a failure inside the
//! native C++ layer or our own bug (exit code 1).

use std::fmt;
use std::path::PathBuf;

use crate::ids::FaceId;

/// Result alias used across asperity.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Where in an input file a problem was found.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Location {
    /// The file as a whole (empty file, unknown format, ...).
    File,
    /// A 1-based line of a text file.
    Line(usize),
    /// A byte offset in a binary file.
    Byte(u64),
    /// An element of the file: `vertex 12`, `face 7`.
    Element(&'static str, usize),
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Location::File => Ok(()),
            Location::Line(n) => write!(f, "line {n}: "),
            Location::Byte(n) => write!(f, "byte {n}: "),
            Location::Element(kind, n) => write!(f, "{kind} {n}: "),
        }
    }
}

/// Every error asperity reports.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A file could not be parsed; names the file and where.
    #[error("{}: {at}{msg}", path.display())]
    Parse {
        /// The file being read.
        path: PathBuf,
        /// Line, byte or element.
        at: Location,
        /// What is wrong.
        msg: String,
    },
    /// Input data (not from a file) is invalid: a vertex index out of range, a NaN coordinate.
    #[error("invalid input: {0}")]
    InvalidInput(String),
    /// The mesh's connectivity cannot be represented or the operation would break it.
    #[error("{msg}")]
    Topology {
        /// Description naming the elements.
        msg: String,
        /// The faces involved (input face indices).
        faces: Vec<FaceId>,
    },
    /// Reading or writing a file failed.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// The native C++ layer (OpenMesh, CGAL) reported a failure.
    #[error("native library: {0}")]
    Native(String),
    /// A bug in asperity.
    #[error("internal error (please report): {0}")]
    Internal(String),
    /// The caller's progress callback asked to stop ([`crate::progress::cancellable`]);
    /// nothing the call was making is left.
    #[error("cancelled by the progress callback at {stage} ({done} of {total})")]
    Cancelled {
        /// The stage reporting when the callback said stop.
        stage: String,
        /// Steps of that stage done.
        done: u64,
        /// Steps of that stage in all.
        total: u64,
    },
}

impl Error {
    /// Process exit code for this error: 2 for bad input or usage, 1 for internal failures,
    /// 130 (as for Ctrl-C) for a cancellation.
    pub fn exit_code(&self) -> i32 {
        match self {
            Error::Parse { .. } | Error::InvalidInput(_) | Error::Topology { .. } | Error::Io { .. } => 2,
            Error::Native(_) | Error::Internal(_) => 1,
            Error::Cancelled { .. } => 130,
        }
    }

    /// Shorthand for a parse error.
    pub fn parse(path: impl Into<PathBuf>, at: Location, msg: impl Into<String>) -> Self {
        Error::Parse { path: path.into(), at, msg: msg.into() }
    }

    /// A topology error whose advice to run `--repair` (its message from "; --repair" on)
    /// is replaced by `advice`, where that flag is not the remedy (the mesh was repaired
    /// already, or the flag belongs to another command); other errors as they are.
    pub fn with_repair_advice(self, advice: &str) -> Self {
        match self {
            Error::Topology { msg, faces } => {
                let msg = match msg.find("; --repair") {
                    Some(cut) => format!("{}{advice}", &msg[..cut]),
                    None => msg,
                };
                Error::Topology { msg, faces }
            }
            other => other,
        }
    }

    /// The error with `path` named in front, for input and topology errors about a mesh
    /// read from that file (other errors name their file already, or have none).
    pub fn about_file(self, path: &std::path::Path) -> Self {
        match self {
            Error::InvalidInput(msg) => Error::InvalidInput(format!("{}: {msg}", path.display())),
            Error::Topology { msg, faces } => Error::Topology { msg: format!("{}: {msg}", path.display()), faces },
            other => other,
        }
    }

    /// Shorthand for an I/O error on a path.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Error::Io { path: path.into(), source }
    }
}

impl From<cxx::Exception> for Error {
    fn from(e: cxx::Exception) -> Self {
        Error::Native(e.what().to_string())
    }
}
