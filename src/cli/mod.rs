//! The command line: one subcommand per capability, thin over the library. Errors are
//! one line on stderr; exit codes are 0 (success), 2 (bad input or usage), 1 (internal).

pub mod analyze;
pub mod clouds;
pub mod compare;
mod convert;
mod demo;
pub mod detail;
mod info;
pub mod input;
pub mod noise;
pub mod refine;
pub mod render;
mod report;
pub mod scene;
pub mod simplify;
mod simplify_plan;
pub mod terrain;

use std::path::PathBuf;

use clap::{Parser, Subcommand};

pub use report::Context;

use crate::error::{Error, Result};

/// asperity — procedural detail on 3D surfaces.
#[derive(Debug, Parser)]
#[command(name = "asperity", version, about, propagate_version = true)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Print one machine-readable JSON report on stdout instead of human lines.
    #[arg(long, global = true)]
    json: bool,
    /// Print nothing but errors (and the JSON report with --json); no progress bars.
    #[arg(short, long, global = true)]
    quiet: bool,
    /// Memory budget: work estimated to need more is refused before it starts (512M, 2G,
    /// 1.5GB; default: three quarters of the machine's memory).
    #[arg(long, global = true, value_name = "SIZE", value_parser = crate::memory::parse_size)]
    max_memory: Option<u64>,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Curvatures and feature classes of a mesh, written as PLY properties and colours.
    Analyze(analyze::AnalyzeArgs),
    /// Butterflies chasing targets on pursuit curves, as a glTF animation (seed 002).
    Butterflies(scene::butterflies::ButterflyArgs),
    /// A cloud image from a midpoint-displacement plasma, thresholded and coloured.
    Clouds(clouds::CloudArgs),
    /// Print a mesh's validation report (counts, boundaries, manifoldness, genus).
    Info(info::InfoArgs),
    /// Simplify with asperity, OpenMesh, CGAL and meshoptimizer: each at the target, then like with like.
    Compare(compare::CompareArgs),
    /// Convert a mesh between OBJ, PLY, OFF, STL and glTF, binary or text (format by extension).
    Convert(convert::ConvertArgs),
    /// Build the 4-k hierarchy and refine it back (the round trip; recipes add detail).
    Detail(detail::DetailArgs),
    /// Run the built-in demonstration, writing results under an output folder.
    Demo(demo::DemoArgs),
    /// A plant from a stochastic L-system: tapered branches and leaf clusters (seed 002).
    Flora(scene::flora::FloraArgs),
    /// The Menger sponge as one closed mesh of its outer and tunnel faces (seed 002).
    Menger(scene::menger::MengerArgs),
    /// Write a noise image (Perlin family or Gabor) as 16-bit PNG or raw f32.
    Noise(noise::NoiseArgs),
    /// Refine a region to full resolution and leave the rest at a coarser level (§4.6).
    Refine(refine::RefineArgs),
    /// Draw a mesh as a PNG: shaded faces, wireframe or points (software rasteriser).
    Render(render::RenderArgs),
    /// Seed 002's environment — terrain, water, trees, cabin, smoke, butterflies — as one
    /// animated glTF scene.
    Scene(scene::whole::SceneArgs),
    /// Simplify to the 4-k hierarchy's base domain (feature-sensitive four-face clusters).
    Simplify(simplify::SimplifyArgs),
    /// Smoke: particles, Blinn's metaballs and marching tetrahedra, one mesh per frame.
    Smoke(scene::smoke::SmokeArgs),
    /// Generate a fractal terrain: mesh or heightmap, whole, tiled or streamed.
    Terrain(Box<terrain::TerrainArgs>),
    /// A water surface with waves and a depth attribute over a terrain mesh, per frame.
    Water(scene::water::WaterArgs),
    /// Print this command-line reference as Markdown (docs/cli.md is its output).
    #[command(hide = true)]
    Reference,
}

/// Clap's message for a usage error, whole (its usage line and "did you mean" tips), with
/// its first paragraph — what is wrong, with the missing arguments or the possible values
/// — joined into one self-contained first line.
fn usage_error_message(rendered: &str) -> String {
    let (what, rest) = rendered.split_once("\n\n").unwrap_or((rendered, ""));
    let what: Vec<&str> = what.lines().map(str::trim).filter(|l| !l.is_empty()).collect();
    let mut what = what.join(" ");
    // `simplify --chunks 4 plan IN`: clap takes what follows a flag of the command above as
    // a subcommand's name.
    if what.contains("the subcommand '") && what.contains("cannot be used with") {
        what.push_str(" (a subcommand's flags go after its name, not before it)");
    }
    let mut message = format!("asperity: {}\n", what.trim_start_matches("error: "));
    if !rest.trim().is_empty() {
        message.push('\n');
        message.push_str(rest.trim_end());
        message.push('\n');
    }
    message
}

/// The command line, every subcommand taking negative numbers as values: `--size -5` is
/// then an invalid value of `--size`, not an unexpected argument `-5` (#36).
fn command_line() -> clap::Command {
    fn allow_negative_numbers(command: clap::Command) -> clap::Command {
        command.allow_negative_numbers(true).mut_subcommands(allow_negative_numbers)
    }
    allow_negative_numbers(<Cli as clap::CommandFactory>::command())
}

/// Parses the arguments, runs the subcommand and returns the process exit code.
/// Panics are caught and reported as internal errors: no panic text reaches the user.
pub fn run() -> i32 {
    let parsed = command_line().try_get_matches().and_then(|m| <Cli as clap::FromArgMatches>::from_arg_matches(&m));
    let cli = match parsed {
        Ok(cli) => cli,
        Err(e) => {
            use clap::error::ErrorKind;
            if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion) {
                let _ = e.print();
                return 0;
            }
            eprint!("{}", usage_error_message(&e.render().to_string()));
            return 2;
        }
    };
    std::panic::set_hook(Box::new(|_| {}));
    crate::memory::set_budget(cli.max_memory);
    remove_partial_outputs_on_signals();
    Context { json: cli.json, quiet: cli.quiet }.install_progress_bars();
    // Every output of the command, or none (#36): files are renamed into place when it ends well.
    let outcome = crate::io::OutputBatch::open().and_then(|batch| {
        let outcome = std::panic::catch_unwind(|| dispatch(cli)).unwrap_or_else(|payload| {
            let msg = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "panic".to_string());
            Err(Error::Internal(msg))
        });
        outcome.and_then(|()| batch.commit())
    });
    match outcome {
        Ok(()) => 0,
        Err(Error::Internal(msg)) if closed_stdout(&msg) => end_quietly_on_closed_stdout(),
        Err(e) => {
            eprintln!("asperity: {}", one_line(&e.to_string()));
            e.exit_code()
        }
    }
}

/// Whether a failure is standard output closed under us (`asperity … | head`): the
/// standard library's printing panics with this.
fn closed_stdout(msg: &str) -> bool {
    msg.starts_with("failed printing to stdout") && msg.contains("Broken pipe")
}

/// Standard output was closed by its reader: end as Unix tools do, quietly, by SIGPIPE's
/// default action (outputs still being written are removed first).
fn end_quietly_on_closed_stdout() -> i32 {
    crate::io::abandon_pending_outputs();
    let _ = signal_hook::low_level::emulate_default_handler(signal_hook::consts::SIGPIPE);
    128 + signal_hook::consts::SIGPIPE
}

/// On SIGINT, SIGTERM or SIGHUP: remove the temporary files of outputs being written, then
/// die by the signal as the default action would (so shells see the usual status). Files
/// already renamed into place are complete; no partial file is left.
fn remove_partial_outputs_on_signals() {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP]) else {
        return;
    };
    std::thread::spawn(move || {
        if let Some(signal) = signals.forever().next() {
            crate::io::abandon_pending_outputs();
            let _ = signal_hook::low_level::emulate_default_handler(signal);
            std::process::exit(128 + signal);
        }
    });
}

fn dispatch(cli: Cli) -> Result<()> {
    let ctx = Context { json: cli.json, quiet: cli.quiet };
    match cli.command {
        Command::Analyze(args) => analyze::run(args, ctx),
        Command::Butterflies(args) => scene::butterflies::run(args, ctx),
        Command::Clouds(args) => clouds::run(args, ctx),
        Command::Flora(args) => scene::flora::run(args, ctx),
        Command::Menger(args) => scene::menger::run(args, ctx),
        Command::Scene(args) => scene::whole::run(args, ctx),
        Command::Smoke(args) => scene::smoke::run(args, ctx),
        Command::Water(args) => scene::water::run(args, ctx),
        Command::Info(args) => info::run(args, ctx),
        Command::Compare(args) => compare::run(args, ctx),
        Command::Convert(args) => convert::run(args, ctx),
        Command::Demo(args) => demo::run(args, ctx),
        Command::Detail(args) => detail::run(args, ctx),
        Command::Refine(args) => refine::run(args, ctx),
        Command::Render(args) => render::run(args, ctx),
        Command::Simplify(args) => simplify::run(args, ctx),
        Command::Noise(args) => noise::run(args, ctx),
        Command::Terrain(args) => terrain::run(*args, ctx),
        Command::Reference => {
            print!("{}", reference());
            Ok(())
        }
    }
}

/// The command-line reference in Markdown, generated from the argument definitions: the
/// top-level help, then each subcommand's long help.
pub fn reference() -> String {
    use clap::CommandFactory;
    let mut cli = Cli::command();
    cli.build();
    let mut out = String::from(
        "# asperity command-line reference\n\n\
         Generated from the argument definitions by `asperity reference > docs/cli.md`; a test \
         fails when this file is stale.\n\n```text\n",
    );
    out += &cli.render_long_help().to_string();
    out += "```\n";
    fn subcommands(prefix: &str, command: &mut clap::Command, out: &mut String) {
        for sub in command.get_subcommands_mut().filter(|s| !s.is_hide_set() && s.get_name() != "help") {
            let name = format!("{prefix}{}", sub.get_name());
            *out += &format!("\n## asperity {name}\n\n```text\n{}```\n", sub.render_long_help());
            subcommands(&format!("{name} "), sub, out);
        }
    }
    subcommands("", &mut cli, &mut out);
    out
}

/// Every subcommand's long flags (without `--help` and the global `--json` and `--quiet`),
/// for the test that runs each one and checks it changes the output or is refused.
pub fn subcommand_flags() -> Vec<(String, Vec<String>)> {
    use clap::CommandFactory;
    fn visit(prefix: &str, command: &clap::Command, out: &mut Vec<(String, Vec<String>)>) {
        for s in command.get_subcommands().filter(|s| !s.is_hide_set() && s.get_name() != "help") {
            let name = if prefix.is_empty() { s.get_name().to_string() } else { format!("{prefix} {}", s.get_name()) };
            let flags = s
                .get_arguments()
                .filter_map(|a| a.get_long())
                // Global flags: `--max-memory` is checked by every estimate
                // (`cli::a_memory_budget_refuses_work_before_it_starts`).
                .filter(|l| !["help", "json", "quiet", "max-memory"].contains(l))
                .map(|l| format!("--{l}"))
                .collect();
            out.push((name.clone(), flags));
            visit(&name, s, out);
        }
    }
    let mut cli = Cli::command();
    cli.build();
    let mut out = Vec::new();
    visit("", &cli, &mut out);
    out
}

fn one_line(msg: &str) -> String {
    msg.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// Refuses to overwrite an input file unless forced.
pub(crate) fn guard_overwrite(input: &std::path::Path, output: &std::path::Path, force: bool) -> Result<()> {
    let same = match (std::fs::canonicalize(input), std::fs::canonicalize(output)) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    };
    if same && !force {
        return Err(Error::InvalidInput(format!(
            "{} is both input and output; pass --force to overwrite it",
            output.display()
        )));
    }
    Ok(())
}

/// Refuses one path given to two outputs of a command (flag, path): one file would
/// silently overwrite the other (#36: `terrain -o t.png --preview t.png`). Paths are
/// compared made absolute, `.` and `..` resolved where the folder exists.
pub(crate) fn distinct_outputs(outputs: &[(&str, &std::path::Path)]) -> Result<()> {
    let resolved = |p: &std::path::Path| {
        let absolute = std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf());
        match (absolute.parent().and_then(|d| std::fs::canonicalize(d).ok()), absolute.file_name()) {
            (Some(dir), Some(name)) => dir.join(name),
            _ => absolute,
        }
    };
    let paths: Vec<PathBuf> = outputs.iter().map(|(_, p)| resolved(p)).collect();
    for (i, a) in paths.iter().enumerate() {
        if let Some(j) = paths[..i].iter().position(|b| b == a) {
            return Err(Error::InvalidInput(format!(
                "{} and {} both name {}: give each output its own path",
                outputs[j].0,
                outputs[i].0,
                outputs[i].1.display()
            )));
        }
    }
    Ok(())
}

/// Milliseconds since `start`, for stage reports.
pub(crate) fn millis(start: std::time::Instant) -> u128 {
    start.elapsed().as_millis()
}

/// The default output folder of commands that write several files.
pub(crate) fn default_out() -> PathBuf {
    PathBuf::from("out")
}

/// Checks that `output` ends in one of `extensions` (lower case, without the dot).
/// `--ascii` chooses between text and binary PLY or STL; OBJ and OFF are always text and
/// glTF always binary, so there it would be ignored: refused.
pub(crate) fn refuse_ascii_for(output: &std::path::Path, ascii: bool) -> Result<()> {
    let format = crate::io::Format::from_path(output)?;
    if ascii && !matches!(format, crate::io::Format::Ply | crate::io::Format::Stl) {
        return Err(Error::InvalidInput(format!(
            "{}: --ascii applies only to .ply and .stl outputs (OBJ and OFF are always text, .glb always binary)",
            output.display()
        )));
    }
    Ok(())
}

pub(crate) fn require_extension(output: &std::path::Path, extensions: &[&str]) -> Result<()> {
    let ext = output.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    if ext.as_deref().is_some_and(|e| extensions.contains(&e)) {
        return Ok(());
    }
    let list: Vec<String> = extensions.iter().map(|e| format!(".{e}")).collect();
    Err(Error::InvalidInput(format!("{}: the output must end in {}", output.display(), list.join(" or "))))
}

/// A planned job's index (`what`: "tile", "chunk"): its flag `--WHAT-index`, else
/// $JOB_COMPLETION_INDEX (Kubernetes Indexed Jobs), else $SLURM_ARRAY_TASK_ID (Slurm job
/// arrays).
fn job_index(flag: Option<u64>, what: &str) -> Result<u64> {
    if let Some(k) = flag {
        return Ok(k);
    }
    for variable in ["JOB_COMPLETION_INDEX", "SLURM_ARRAY_TASK_ID"] {
        if let Ok(value) = std::env::var(variable) {
            return value.trim().parse().map_err(|_| {
                Error::InvalidInput(format!("${variable} is {value:?}: a {what} index must be a whole number from 0"))
            });
        }
    }
    Err(Error::InvalidInput(format!(
        "--plan needs a {what} index: --{what}-index K, $JOB_COMPLETION_INDEX (Kubernetes) or $SLURM_ARRAY_TASK_ID (Slurm)"
    )))
}
