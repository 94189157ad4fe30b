//! The command line's flags, parsed by the command line's own argument definitions: a
//! Python keyword argument `target_vertices="5%"` arrives as `--target-vertices 5%` and
//! means exactly what the flag means, with the same checks and messages.

use pyo3::PyResult;

use crate::InputError;

/// Flags about files, pictures and streams, which the Python functions do not write: refused
/// by name rather than ignored.
const FILE_FLAGS: [&str; 12] = [
    "--output",
    "-o",
    "--ascii",
    "--force",
    "--preview",
    "--format",
    "--stream",
    "--band",
    "--sidecar",
    "--plan",
    "--tile-index",
    "--steps",
];

/// Parses `flags` (after the placeholder arguments `prefix`, e.g. an input path the arrays
/// stand for) as the arguments of subcommand `command`. `refused` names flags that make no
/// sense for this function (an image's size when sampling given points).
pub fn parse<A: clap::Args + clap::FromArgMatches>(
    command: &'static str,
    prefix: &[&str],
    flags: Vec<String>,
    refused: &[&str],
) -> PyResult<A> {
    let flag_of = |f: &String| f.split('=').next().unwrap_or_default().to_string();
    if let Some(flag) =
        flags.iter().map(flag_of).find(|f| FILE_FLAGS.contains(&f.as_str()) || refused.contains(&f.as_str()))
    {
        let name = flag.trim_start_matches('-').replace('-', "_");
        return Err(InputError::new_err(format!(
            "{flag} ({name}=) applies to the command line's asperity {command}, which writes files: here it would be ignored"
        )));
    }
    let definition = A::augment_args(clap::Command::new(command).no_binary_name(true).disable_help_flag(true));
    let argv = prefix.iter().map(|s| s.to_string()).chain(flags);
    let matches =
        definition.try_get_matches_from(argv).map_err(|e| InputError::new_err(one_line(&e.render().to_string())))?;
    A::from_arg_matches(&matches).map_err(|e| InputError::new_err(one_line(&e.render().to_string())))
}

/// Clap's message as one line: its first paragraph, without the "error: " prefix.
fn one_line(rendered: &str) -> String {
    let first = rendered.split("\n\n").next().unwrap_or(rendered);
    let words: Vec<&str> = first.split_whitespace().collect();
    words.join(" ").trim_start_matches("error: ").to_string()
}
