//! The README's `console` examples print what the commands print today (#24 item 16): every
//! `$ asperity …` line is run from the repository root (outputs under a temporary folder),
//! and its shown lines must appear in that order in what it printed, timings aside.

use std::path::Path;
use std::process::Command;

/// One example: the command's arguments and the lines the README shows.
struct Example {
    args: Vec<String>,
    shown: Vec<String>,
}

fn examples(readme: &str) -> Vec<Example> {
    let mut out: Vec<Example> = Vec::new();
    let mut inside = false;
    for line in readme.lines() {
        if line.starts_with("```") {
            inside = line.trim() == "```console";
            continue;
        }
        if !inside {
            continue;
        }
        if let Some(command) = line.strip_prefix("$ asperity ") {
            out.push(Example { args: command.split_whitespace().map(String::from).collect(), shown: Vec::new() });
        } else if let Some(example) = out.last_mut() {
            example.shown.push(line.to_string());
        }
    }
    out
}

/// "in 123 ms", "in 1.2 s" and "(4.5 M points/s)" become "in … ms" and "(… M points/s)":
/// timings vary from run to run.
fn without_timings(line: &str) -> String {
    let mut words: Vec<String> = line.split(' ').map(String::from).collect();
    for i in 1..words.len() {
        if words[i - 1] == "in" && words[i].parse::<f64>().is_ok() {
            words[i] = "…".into();
        }
        let rate = words.get(i + 1).is_some_and(|w| w.starts_with("points/s"));
        if words[i] == "M" && rate && words[i - 1].trim_start_matches('(').parse::<f64>().is_ok() {
            words[i - 1] = "(…".into();
        }
    }
    words.join(" ")
}

#[test]
fn readme_console_examples_print_what_the_commands_print() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let examples = examples(&readme);
    assert!(examples.len() >= 5, "{} console examples", examples.len());
    let meshes = crate::common::shared_meshes();
    let tmp = crate::common::temp_dir();
    for example in examples {
        let mut args = example.args.clone();
        for i in 1..args.len() {
            if args[i - 1] == "-o" || args[i - 1] == "--plan" || (args[i - 1] == "merge" && i == 2) {
                args[i] = tmp.path().join(&args[i]).display().to_string();
            }
        }
        // The README names the meshes where they sit beside a checkout; a fresh clone
        // elsewhere has them where scripts/fetch-test-meshes.sh put them.
        for arg in &mut args {
            if let Some(name) = arg.strip_prefix("../shared/data/meshes/") {
                *arg = meshes.join(name).display().to_string();
            }
        }
        let out = Command::new(env!("CARGO_BIN_EXE_asperity")).args(&args).current_dir(root).output().unwrap();
        let printed = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
        assert!(out.status.success(), "asperity {}: {printed}", example.args.join(" "));
        let fetched_prefix = format!("{}/", meshes.display());
        let outputs_prefix = format!("{}/", tmp.path().display());
        let printed: Vec<String> = printed
            .lines()
            .map(|l| {
                without_timings(&l.replace(&fetched_prefix, "../shared/data/meshes/").replace(&outputs_prefix, ""))
            })
            .collect();
        let mut at = 0;
        for shown in example.shown.iter().filter(|l| l.trim() != "...") {
            let shown = without_timings(shown);
            match printed[at..].iter().position(|p| *p == shown) {
                Some(k) => at += k + 1,
                None => panic!(
                    "README: `asperity {}` shows\n{shown}\nbut prints\n{}",
                    example.args.join(" "),
                    printed.join("\n")
                ),
            }
        }
    }
}

#[test]
fn the_figure_sheet_shows_every_shipped_recipe() {
    // docs/figures.md (scripts/figures.sh --docs) pairs each thesis figure with its recipe
    // (#37): a recipe added to recipes/ must be added to the sheet too.
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let sheet = std::fs::read_to_string(root.join("docs/figures.md")).unwrap();
    let script = std::fs::read_to_string(root.join("scripts/figures.sh")).unwrap();
    for entry in std::fs::read_dir(root.join("recipes")).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_stem().unwrap().to_string_lossy().to_string();
        assert!(sheet.contains(&format!("`recipes/{name}.toml`")), "docs/figures.md lacks {name}: run scripts/figures.sh --docs");
        assert!(script.contains(&format!("|{name}|")), "scripts/figures.sh lacks {name}");
    }
}
