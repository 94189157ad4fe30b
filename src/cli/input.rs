//! Reading a command's input mesh, repaired on request (`--repair`).

use std::path::Path;

use clap::Args;

use crate::error::Result;
use crate::io::{self, ReadOutcome};
use crate::mesh::{RepairReport, repair};

/// `--repair`, shared by every command that reads a mesh.
#[derive(Debug, Clone, Copy, Args)]
pub struct RepairArg {
    /// Repair the input first: remove degenerate and duplicate faces, split non-manifold
    /// vertices and edges, orient faces consistently, drop unreferenced vertices (prints
    /// what changed).
    #[arg(long)]
    pub repair: bool,
}

/// A read input: the reader's outcome (mesh repaired when asked) and what the repair did.
pub struct Input {
    /// The mesh, notes and triangulation count from the reader.
    pub read: ReadOutcome,
    /// What `--repair` changed (`None` without `--repair`).
    pub repair: Option<RepairReport>,
}

impl Input {
    /// The repair report as JSON (`null` without `--repair`).
    pub fn repair_json(&self) -> serde_json::Value {
        serde_json::to_value(self.repair).expect("a repair report serialises")
    }
}

/// Reads `path` and, with `--repair`, repairs the mesh and prints a `repair:` line.
/// Reader notes go to stderr.
///
/// # Errors
/// The reader's errors (naming the file, line or element).
pub fn read_input(path: &Path, arg: RepairArg, ctx: super::Context) -> Result<Input> {
    let mut read = io::read(path)?;
    for note in &read.notes {
        ctx.note(note);
    }
    let repair = if arg.repair {
        let (mesh, report) = repair(&read.mesh).map_err(|e| e.about_file(path))?;
        read.mesh = mesh;
        ctx.line(|| format!("repair: {}: {report}", path.display()));
        Some(report)
    } else {
        None
    };
    Ok(Input { read, repair })
}

/// Reads `path` as a partitioned build needs it: whole and repaired with `--repair`, else
/// keeping only what a build reads ([`io::read_lean`]: binary PLY and STL as a stream).
/// Also whether it was read as a stream.
///
/// # Errors
/// The reader's errors (naming the file, line or element).
pub fn read_for_build(path: &Path, arg: RepairArg, ctx: super::Context) -> Result<(Input, bool)> {
    if arg.repair {
        return Ok((read_input(path, arg, ctx)?, false));
    }
    let (read, streamed) = io::read_lean(path)?;
    for note in &read.notes {
        ctx.note(note);
    }
    Ok((Input { read, repair: None }, streamed))
}

/// An error about a mesh `--repair` already went over: its advice to run `--repair` is
/// replaced by what is true (the repair could not mend it).
pub fn after_repair(error: crate::Error, arg: RepairArg) -> crate::Error {
    match arg.repair {
        true => error.with_repair_advice(" (left after --repair)"),
        false => error,
    }
}
