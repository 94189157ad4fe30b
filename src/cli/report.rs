//! What every subcommand shares about output: one human line per stage in
//! meshoptimizer's style (`simplify: 75408 tris => 754 tris ... in 412 ms`), or one JSON
//! report on stdout with `--json`; progress bars on stderr for long stages, hidden with
//! `--quiet`, under `--json`, or when stderr is not a terminal.

use std::io::IsTerminal;
use std::time::Duration;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// Output settings from the global flags.
#[derive(Debug, Clone, Copy, Default)]
pub struct Context {
    /// Print one JSON report on stdout instead of human lines.
    pub json: bool,
    /// No human lines, notes or progress bars (errors are still printed).
    pub quiet: bool,
}

impl Context {
    /// Prints a stage's human line (not under `--json` or `--quiet`).
    pub fn line(&self, line: impl FnOnce() -> String) {
        if !self.json && !self.quiet {
            println!("{}", line());
        }
    }

    /// Prints the command's report: the JSON value under `--json`, else the human line.
    pub fn report(&self, line: impl FnOnce() -> String, json: impl FnOnce() -> serde_json::Value) {
        if self.json {
            println!("{}", serde_json::to_string_pretty(&json()).expect("a JSON value serialises"));
        } else {
            self.line(line);
        }
    }

    /// A note on stderr about something the input made us change or ignore.
    pub fn note(&self, note: &str) {
        if !self.quiet {
            eprintln!("note: {note}");
        }
    }

    fn shows_progress(&self) -> bool {
        !self.json && !self.quiet && std::io::stderr().is_terminal()
    }

    /// A progress bar over `total` steps (a spinner when `None`), ticking by itself.
    pub fn progress(&self, stage: &str, total: Option<u64>) -> ProgressBar {
        if !self.shows_progress() {
            return ProgressBar::hidden();
        }
        let bar = match total {
            Some(n) => ProgressBar::with_draw_target(Some(n), ProgressDrawTarget::stderr()).with_style(
                ProgressStyle::with_template("{prefix:>10} [{bar:30}] {pos}/{len} {msg} ({elapsed})")
                    .expect("a valid template")
                    .progress_chars("=> "),
            ),
            None => ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr()).with_style(
                ProgressStyle::with_template("{prefix:>10} {spinner} {msg} ({elapsed})").expect("a valid template"),
            ),
        };
        bar.set_prefix(stage.to_string());
        bar.enable_steady_tick(Duration::from_millis(120));
        bar
    }

    /// Runs `work` under a spinner named `stage` (for stages that report no steps).
    pub fn spin<T>(&self, stage: &str, message: &str, work: impl FnOnce() -> T) -> T {
        let bar = self.progress(stage, None);
        bar.set_message(message.to_string());
        let out = work();
        bar.finish_and_clear();
        out
    }
}
