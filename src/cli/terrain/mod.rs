//! `asperity terrain`: classic diamond-square terrains as meshes or heightmaps, whole,
//! tiled or streamed; engine presets, sidecars, thermal and hydraulic erosion; `terrain plan` and
//! `terrain --plan DIR` for tiles run by a job runner.

mod dual;
mod plan;

use std::path::PathBuf;
use std::time::Instant;

use clap::{Args, Subcommand};

use crate::error::{Error, Result};
use crate::request::Spelling;
use crate::terrain::files::TerrainFiles;
use crate::terrain::plan::layer_path;
use crate::terrain::preview::{PreviewSampler, preview};
use crate::terrain::stream::StreamFormat;
use crate::terrain::{TerrainMethod, TerrainOutput, TerrainRequest, TerrainSetup, TerrainTarget, presets};

/// The subcommand's flags (`TerrainArgs`).
#[derive(Debug, Args)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct TerrainArgs {
    #[command(subcommand)]
    command: Option<TerrainCommand>,
    #[command(flatten)]
    generation: TerrainRequest,
    /// Write rows as they are generated, in bounded memory (.ply, .obj, .png, .raw16, .f32).
    #[arg(long)]
    stream: bool,
    /// Rows per streamed band (with --stream) [default: as many as 2^22 points make, 64 to
    /// 1024].
    #[arg(long)]
    band: Option<usize>,
    /// Generate only tile I,J (needs --tile-size).
    #[arg(long, value_parser = crate::request::parse::index_pair, requires = "tile_size")]
    tile: Option<(u64, u64)>,
    /// Points per tile side, 2^k + 1; tiles share their borders.
    #[arg(long)]
    tile_size: Option<u64>,
    /// Output: .ply / .obj mesh, .png 16-bit heightmap, .raw16, .f32, .exr or .tif (32-bit
    /// float); with --preset and --tile, the tile's name is made from it (NAME_x{I}_y{J}).
    #[arg(short, long, required_unless_present = "plan")]
    output: Option<PathBuf>,
    /// Also write a picture: a hillshaded colour map (classic, smooth; one pixel per point,
    /// or with --stream every k-th point of the streamed rows, at most 1024 a side) or a
    /// rendering of the surface (dual), as .png.
    #[arg(long)]
    preview: Option<PathBuf>,
    /// Output format when the file name has no telling extension (e.g. -o /dev/null):
    /// ply, obj, png, raw16, f32, exr or tif.
    #[arg(long, conflicts_with = "preset")]
    format: Option<String>,
    /// Also write OUTPUT.json beside a heightmap: its place on the grid and in the world,
    /// its height range and how 16-bit values map to heights (always with --preset).
    #[arg(long)]
    sidecar: bool,
    /// Run one tile of the plan in DIR (made by `asperity terrain plan`): the tile given by
    /// --tile-index, else $JOB_COMPLETION_INDEX (Kubernetes Indexed Jobs), else
    /// $SLURM_ARRAY_TASK_ID (Slurm job arrays). A tile already complete is skipped.
    #[arg(
        long,
        value_name = "DIR",
        conflicts_with_all = [
            "method", "size", "iterations", "hurst", "roughness", "sigma", "x", "y", "levels", "deterministic",
            "cross_product", "no_mean_correction", "steps", "seed", "distribution", "mean", "variance", "corners",
            "applet", "width", "depth", "max_height", "sea_level", "colors", "peak_height", "grid", "range", "erode",
            "erode_iterations", "talus", "layers", "rain", "evaporation", "capacity", "dissolving", "deposition", "time_step", "preset", "stream", "band", "tile", "tile_size", "output", "preview", "format",
            "sidecar"
        ]
    )]
    plan: Option<PathBuf>,
    /// The plan's tile to run, 0-based (with --plan; wins over the job runners' variables).
    #[arg(long, requires = "plan")]
    tile_index: Option<u64>,
}

#[derive(Debug, Subcommand)]
enum TerrainCommand {
    /// Cut a terrain into tiles for a job runner: writes DIR/plan.json (every tile's index,
    /// rectangle, output and command), DIR/mosaic.vrt (a GDAL mosaic of the tiles) and, for
    /// headerless formats, a VRT per tile.
    Plan(Box<plan::PlanArgs>),
}

/// One terrain to write: the generation flags and where and how to write it.
#[derive(Debug)]
pub(super) struct Job<'a> {
    generation: &'a TerrainRequest,
    stream: bool,
    band: Option<usize>,
    tile: Option<(u64, u64)>,
    tile_size: Option<u64>,
    output: PathBuf,
    preview: Option<PathBuf>,
    format: Option<String>,
    sidecar: bool,
    /// The plan's fingerprint, recorded in the sidecar of a planned tile.
    plan: Option<String>,
    /// The output path is final: a preset's tile name is not made from it (planned tiles).
    named: bool,
}

impl<'a> Job<'a> {
    /// A job writing `generation`'s terrain (or its tile) to `output` under exactly that
    /// name, as `format`, whole, with nothing beside it.
    fn named(
        generation: &'a TerrainRequest,
        output: PathBuf,
        format: &str,
        tile: Option<(u64, u64)>,
        tile_size: Option<u64>,
    ) -> Self {
        Job {
            generation,
            stream: false,
            band: None,
            tile,
            tile_size,
            output,
            preview: None,
            format: Some(format.to_string()),
            sidecar: false,
            plan: None,
            named: true,
        }
    }

    /// The output's extension (lower case): --format's, the preset's or the file name's.
    fn extension(&self) -> String {
        match (&self.format, self.generation.preset) {
            (Some(format), _) => format.to_ascii_lowercase(),
            (None, Some(preset)) => preset.format().extension().to_string(),
            (None, None) => self.output.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase(),
        }
    }

    /// What the library's rules look at: the output's kind, the tile, how it is written.
    fn target(&self) -> TerrainTarget {
        TerrainTarget {
            output: TerrainOutput::of_extension(&self.extension()),
            tile: self.tile,
            tile_size: self.tile_size,
            stream: self.stream,
            band: self.band,
            preview: self.preview.is_some(),
            sidecar: self.sidecar,
        }
    }
}

/// Runs the subcommand.
pub fn run(args: TerrainArgs, ctx: crate::cli::Context) -> Result<()> {
    if let Some(TerrainCommand::Plan(plan)) = args.command {
        return plan::run(*plan, ctx);
    }
    if let Some(dir) = &args.plan {
        return plan::run_tile(dir, args.tile_index, ctx);
    }
    let output = args.output.clone().expect("clap requires --output without --plan");
    let job = Job {
        generation: &args.generation,
        stream: args.stream,
        band: args.band,
        tile: args.tile,
        tile_size: args.tile_size,
        output,
        preview: args.preview.clone(),
        format: args.format.clone(),
        sidecar: args.sidecar,
        plan: None,
        named: false,
    };
    run_job(&job, ctx)
}

/// Writes one terrain.
fn run_job(job: &Job, ctx: crate::cli::Context) -> Result<()> {
    let start = Instant::now();
    if job.generation.method == TerrainMethod::Dual {
        return dual::run(job, start, ctx);
    }
    let setup = Setup::of(job)?;
    generate(job, &setup, start, ctx)
}

/// What a heightfield job writes, checked before anything is generated: the library's
/// setup ([`TerrainRequest::layout`]) and the files.
#[derive(Debug)]
pub(super) struct Setup {
    /// What is generated: the parameters, region, range and layers.
    terrain: TerrainSetup,
    /// Where and how it is written.
    files: TerrainFiles,
}

impl Setup {
    /// Checks every flag of `job` and works out what it writes.
    fn of(job: &Job) -> Result<Setup> {
        let g = job.generation;
        let target = job.target();
        let layout = g.layout(&target, Spelling::Flag)?;
        if let Some(preview) = &job.preview {
            crate::cli::require_extension(preview, &["png"])?;
            crate::cli::distinct_outputs(&[("-o", job.output.as_path()), ("--preview", preview.as_path())])?;
        }
        let ext = job.extension();
        let output = match (g.preset, job.tile) {
            (Some(preset), _) if !job.named && job.format.is_none() => {
                crate::cli::require_extension(&job.output, preset.extensions())?;
                match job.tile {
                    Some((i, j)) => presets::tile_path(&job.output, i, j),
                    None => job.output.clone(),
                }
            }
            _ => job.output.clone(),
        };
        let whole_mesh = target.output == TerrainOutput::Mesh && !job.stream;
        let format = StreamFormat::from_extension(&ext).ok_or_else(|| {
            Error::InvalidInput(format!(
                "{}: the output must end in .ply, .obj, .png, .raw16, .f32, .exr or .tif",
                job.output.display()
            ))
        })?;
        if job.stream && !format.streams() {
            return Err(Error::InvalidInput(format!(
                "{}: .{} is written whole (its encoder seeks back): --stream writes .ply, .obj, .png, .raw16 or .f32; cut a large .{} terrain into --tile pieces",
                job.output.display(),
                format.extension(),
                format.extension()
            )));
        }
        if !layout.layers.is_empty() && !format.is_heightmap() {
            return Err(Error::InvalidInput(format!(
                "{}: --layers are heightmaps written beside a heightmap: write the terrain as .png, .raw16, .f32, .exr or .tif",
                job.output.display()
            )));
        }
        let mut named = vec![("-o", output.clone())];
        named.extend(layout.layers.iter().map(|&l| ("--layers", layer_path(&output, l))));
        if let Some(preview) = &job.preview {
            named.push(("--preview", preview.clone()));
        }
        crate::cli::distinct_outputs(&named.iter().map(|(flag, path)| (*flag, path.as_path())).collect::<Vec<_>>())?;
        let points = layout.rect.width() as u64 * layout.rect.height() as u64;
        if format == StreamFormat::Ply && points > i32::MAX as u64 {
            return Err(Error::InvalidInput(format!("{points} vertices exceed PLY's int indices: use --tile")));
        }
        let terrain = layout.ready(&target, Spelling::Flag)?;
        let sidecar = job.sidecar || g.preset.is_some();
        if sidecar && std::fs::metadata(&output).is_ok_and(|m| !m.is_file()) {
            return Err(Error::InvalidInput(format!(
                "{}: a sidecar (--sidecar, --preset) is written beside a file, and this is not one",
                output.display()
            )));
        }
        let band = target.streamed_band(terrain.rect.width());
        let files = TerrainFiles { output, format, whole_mesh, sidecar, band, plan: job.plan.clone() };
        Ok(Setup { terrain, files })
    }
}

/// Generates and writes the terrain `setup` describes, its preview and sidecar.
fn generate(job: &Job, setup: &Setup, start: Instant, ctx: crate::cli::Context) -> Result<()> {
    let (params, rect, output) = (&setup.terrain.params, setup.terrain.rect, &setup.files.output);
    let points = rect.width() as u64 * rect.height() as u64;
    // A streamed terrain's preview is made from the streamed rows (one more band-sized
    // pass would not be bounded).
    let mut sampler = (job.stream && job.preview.is_some()).then(|| PreviewSampler::new(rect));
    let message = format!("{}x{} points", rect.width(), rect.height());
    let written = ctx.spin("terrain", &message, || setup.files.write(&setup.terrain, sampler.as_mut()))?;
    let seconds = start.elapsed().as_secs_f64();
    match (&job.preview, sampler) {
        (Some(path), Some(sampler)) => sampler.picture(params).write_png(path)?,
        (Some(path), None) => preview(params, rect)?.write_png(path)?,
        _ => {}
    }
    let method = job.generation.method.name();
    ctx.report(
        || {
            let layers: String = written.layers.iter().map(|p| format!(", {}", p.display())).collect();
            format!(
                "terrain: {method} {}x{} (H {}, seed {}) => {}{layers} in {} ms ({:.1} M points/s)",
                rect.width(),
                rect.height(),
                setup.terrain.hurst,
                job.generation.seed,
                output.display(),
                crate::cli::millis(start),
                points as f64 / seconds.max(1e-9) / 1e6
            )
        },
        || {
            serde_json::json!({
                "method": method, "output": output, "preview": job.preview, "sidecar": written.sidecar, "layers": written.layers,
                "columns": rect.width(), "rows": rect.height(), "hurst": setup.terrain.hurst, "seed": job.generation.seed,
                "points": points, "seconds": seconds, "points_per_second": points as f64 / seconds.max(1e-9),
            })
        },
    );
    Ok(())
}
