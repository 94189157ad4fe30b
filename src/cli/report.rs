//! What every subcommand shares about output: one human line per stage in
//! meshoptimizer's style (`simplify: 75408 tris => 754 tris ... in 412 ms`), or one JSON
//! report on stdout with `--json`; progress bars on stderr for long stages, hidden with
//! `--quiet`, under `--json`, or when stderr is not a terminal.

use std::io::IsTerminal;
use std::time::Duration;

use std::collections::HashMap;
use std::sync::{Mutex, OnceLock};

use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};

/// Every bar and spinner of the process draws through one multi-bar, so they stack.
fn bars() -> &'static MultiProgress {
    static BARS: OnceLock<MultiProgress> = OnceLock::new();
    BARS.get_or_init(|| MultiProgress::with_draw_target(ProgressDrawTarget::stderr()))
}

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

    /// Installs the library's progress sink ([`crate::progress`]) as bars with position,
    /// rate and time left, when progress shows (a terminal, no `--quiet` or `--json`).
    pub fn install_progress_bars(&self) {
        if !self.shows_progress() {
            return;
        }
        let open: Mutex<HashMap<String, ProgressBar>> = Mutex::new(HashMap::new());
        crate::progress::install(Box::new(move |stage, done, total| {
            let Ok(mut open) = open.lock() else { return };
            if done >= total && !open.contains_key(stage) {
                return; // a stage that ended already (or ends as it begins): nothing to show
            }
            let bar = open.entry(stage.to_string()).or_insert_with(|| {
                let bar = bars().add(ProgressBar::new(total)).with_style(
                    ProgressStyle::with_template(
                        "{prefix:>10} [{bar:30}] {pos}/{len} {per_sec} {eta} left ({elapsed})",
                    )
                    .expect("a valid template")
                    .progress_chars("=> "),
                );
                bar.set_prefix(stage.to_string());
                bar.enable_steady_tick(Duration::from_millis(200));
                bar
            });
            bar.set_length(total);
            bar.set_position(done);
            if done >= total {
                bar.finish_and_clear();
                open.remove(stage);
            }
        }));
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
            Some(n) => ProgressBar::new(n).with_style(
                ProgressStyle::with_template("{prefix:>10} [{bar:30}] {pos}/{len} {msg} ({elapsed})")
                    .expect("a valid template")
                    .progress_chars("=> "),
            ),
            None => ProgressBar::new_spinner().with_style(
                ProgressStyle::with_template("{prefix:>10} {spinner} {msg} ({elapsed})").expect("a valid template"),
            ),
        };
        let bar = bars().add(bar);
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
