//! The command line's flags, parsed by the command line's own argument definitions
//! ([`asperity::cli::parse_flags`]): a Python keyword argument `target_vertices="5%"`
//! arrives as `--target-vertices 5%` and means exactly what the flag means, with the same
//! checks and messages.

use pyo3::PyResult;

use crate::to_py;

/// Parses `flags` as the arguments of subcommand `command` (see
/// [`asperity::cli::parse_flags`]); a refused flag is named as its keyword argument.
pub fn parse<A: clap::Args + clap::FromArgMatches>(
    command: &'static str,
    prefix: &[&str],
    flags: Vec<String>,
    refused: &[&str],
) -> PyResult<A> {
    asperity::cli::parse_flags(command, prefix, flags, refused, |name| format!("{name}=")).map_err(to_py)
}
