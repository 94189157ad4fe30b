//! The command line's flags for the embeddings (the Python package, the C++ package): an
//! option such as Python's `target_vertices="5%"` or C++'s `options.target_vertices`
//! arrives as `--target-vertices 5%` and is parsed by the subcommand's own argument
//! definitions, so it means exactly what the flag means, with the same checks and messages.

use crate::error::{Error, Result};

/// Flags about files, pictures and streams, which the embeddings do not write: refused by
/// name rather than ignored.
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
/// sense for the calling function (an image's size when sampling given points); `name_of`
/// says how the embedding spells a flag's option (`target_vertices=` in Python), for the
/// message that refuses it.
///
/// # Errors
/// [`Error::InvalidInput`] with clap's message on one line, or naming a refused flag.
pub fn parse_flags<A: clap::Args + clap::FromArgMatches>(
    command: &'static str,
    prefix: &[&str],
    flags: Vec<String>,
    refused: &[&str],
    name_of: impl Fn(&str) -> String,
) -> Result<A> {
    let flag_of = |f: &String| f.split('=').next().unwrap_or_default().to_string();
    if let Some(flag) =
        flags.iter().map(flag_of).find(|f| FILE_FLAGS.contains(&f.as_str()) || refused.contains(&f.as_str()))
    {
        let name = name_of(&flag.trim_start_matches('-').replace('-', "_"));
        return Err(Error::InvalidInput(format!(
            "{flag} ({name}) applies to the command line's asperity {command}, which writes files: here it would be ignored"
        )));
    }
    let definition = A::augment_args(clap::Command::new(command).no_binary_name(true).disable_help_flag(true));
    let argv = prefix.iter().map(|s| s.to_string()).chain(flags);
    let matches = definition.try_get_matches_from(argv).map_err(|e| Error::InvalidInput(one_line(&e)))?;
    A::from_arg_matches(&matches).map_err(|e| Error::InvalidInput(one_line(&e)))
}

/// Clap's message as one line: its first paragraph, without the "error: " prefix.
fn one_line(error: &clap::Error) -> String {
    let rendered = error.render().to_string();
    let first = rendered.split("\n\n").next().unwrap_or(&rendered);
    let words: Vec<&str> = first.split_whitespace().collect();
    words.join(" ").trim_start_matches("error: ").to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flags_parse_as_the_subcommand_and_file_flags_are_refused() {
        let args: crate::cli::noise::NoiseArgs =
            parse_flags("noise", &["-o", "x.f32"], vec!["--kind".into(), "gabor".into()], &[], |n| n.to_string())
                .expect("valid flags");
        assert!(format!("{args:?}").contains("Gabor"));
        let refused = parse_flags::<crate::cli::noise::NoiseArgs>(
            "noise",
            &["-o", "x.f32"],
            vec!["--size=64".into()],
            &["--size"],
            |n| format!(".{n}"),
        )
        .unwrap_err()
        .to_string();
        assert!(refused.contains("--size (.size) applies to the command line's asperity noise"), "{refused}");
        let bad = parse_flags::<crate::cli::noise::NoiseArgs>(
            "noise",
            &["-o", "x.f32"],
            vec!["--kind".into(), "plaid".into()],
            &[],
            |n| n.to_string(),
        )
        .unwrap_err()
        .to_string();
        assert!(bad.contains("plaid") && !bad.contains('\n'), "{bad}");
    }
}
