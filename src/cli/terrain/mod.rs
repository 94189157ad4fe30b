//! `asperity terrain`: classic diamond-square terrains as meshes or heightmaps, whole,
//! tiled or streamed; engine presets, sidecars, thermal and hydraulic erosion; `terrain plan` and
//! `terrain --plan DIR` for tiles run by a job runner.

mod dual;
mod plan;
mod preview;

use std::path::PathBuf;
use std::time::Instant;

use clap::{Args, Subcommand};

use crate::error::{Error, Result};
use crate::io::{self, WriteOptions, write_atomically};
use crate::request::Spelling;
use crate::terrain::plan::layer_path;
use crate::terrain::sidecar::{HeightRange, Sidecar};
use crate::terrain::stream::{LAYER_RANGE, StreamFormat, default_band, write_layer, write_terrain_observed};
use crate::terrain::{
    ErosionLayer, Rect, TerrainMethod, TerrainOutput, TerrainRequest, TerrainSetup, TerrainTarget, mesh, presets,
};
use preview::{PreviewSampler, write_preview};

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
    /// The output file.
    output: PathBuf,
    /// A whole mesh (PLY, OBJ) or a streamable encoding.
    format: StreamFormat,
    whole_mesh: bool,
    sidecar: bool,
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
        Ok(Setup { terrain, output, format, whole_mesh, sidecar })
    }
}

/// Generates and writes the terrain `setup` describes, its preview and sidecar.
fn generate(job: &Job, setup: &Setup, start: Instant, ctx: crate::cli::Context) -> Result<()> {
    let (params, rect, output) = (&setup.terrain.params, setup.terrain.rect, &setup.output);
    let points = rect.width() as u64 * rect.height() as u64;
    let mut streamed_preview: Option<PreviewSampler> = None;
    let mut extremes = HeightRange { min: f64::INFINITY, max: f64::NEG_INFINITY };
    let mut layer_files: Vec<PathBuf> = Vec::new();
    if setup.whole_mesh {
        let terrain = ctx.spin("terrain", "generating the mesh", || mesh(params, rect))?;
        let format = if setup.format == StreamFormat::Obj { io::Format::Obj } else { io::Format::Ply };
        io::write_as(&terrain, output, format, WriteOptions::default())?;
    } else {
        let band = if job.stream { job.band.unwrap_or_else(|| default_band(rect.width())) } else { rect.height() };
        // A file written whole takes its heights and every layer from one erosion run; a
        // streamed one runs it again per file, band by band, in bounded memory.
        let known = match (setup.terrain.layers.is_empty(), job.stream) {
            (false, false) => Some(ctx.spin("terrain", "eroding", || {
                crate::terrain::heights_and_layers(params, rect, &setup.terrain.layers)
            })?),
            _ => None,
        };
        let mut failure = None;
        // A streamed terrain's preview is made from the streamed rows, at most
        // STREAMED_PREVIEW_SIDE pixels a side: one more band-sized pass would not be bounded.
        streamed_preview = (job.stream && job.preview.is_some()).then(|| PreviewSampler::new(rect));
        // I/O failures go back to `write_atomically`, which names the output file; other
        // errors keep their type.
        let message = format!("{}x{} points", rect.width(), rect.height());
        let sampler = &mut streamed_preview;
        let extremes = &mut extremes;
        ctx.spin("terrain", &message, || {
            write_atomically(output, |w| {
                let mut observe = |field: &crate::terrain::Heightfield, y0: u64, y1: u64| {
                    if let Some(sampler) = sampler.as_mut() {
                        sampler.take(field, y0, y1);
                    }
                    if setup.sidecar {
                        widen(extremes, field, rect, y0, y1);
                    }
                };
                let known = known.as_ref().map(|(field, _)| field);
                write_terrain_observed(params, rect, known, setup.format, setup.terrain.range, band, w, &mut observe)
                    .map_err(|e| io_or_kept(e, &mut failure))
            })
        })
        .map_err(|e| failure.take().unwrap_or(e))?;
        for (k, &layer) in setup.terrain.layers.iter().enumerate() {
            let values = known.as_ref().map(|(_, layers)| &layers[k]);
            layer_files.push(write_layer_file(job, setup, layer, values, band)?);
        }
    }
    let seconds = start.elapsed().as_secs_f64();
    match (&job.preview, streamed_preview) {
        (Some(preview), Some(sampler)) => sampler.picture(params).write_png(preview)?,
        (Some(preview), None) => write_preview(params, rect, preview)?,
        _ => {}
    }
    let sidecar_path = setup.sidecar.then(|| write_sidecar(job, setup, extremes)).transpose()?;
    let method = job.generation.method.name();
    ctx.report(
        || {
            let layers: String = layer_files.iter().map(|p| format!(", {}", p.display())).collect();
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
                "method": method, "output": output, "preview": job.preview, "sidecar": sidecar_path, "layers": layer_files,
                "columns": rect.width(), "rows": rect.height(), "hurst": setup.terrain.hurst, "seed": job.generation.seed,
                "points": points, "seconds": seconds, "points_per_second": points as f64 / seconds.max(1e-9),
            })
        },
    );
    Ok(())
}

/// Widens `extremes` to the values of rows y0..=y1 of `field` over `rect`'s columns.
fn widen(extremes: &mut HeightRange, field: &crate::terrain::Heightfield, rect: Rect, y0: u64, y1: u64) {
    for y in y0..=y1 {
        for x in rect.x0..=rect.x1 {
            let v = field.at(x, y);
            extremes.min = extremes.min.min(v);
            extremes.max = extremes.max.max(v);
        }
    }
}

/// A writer's error as `write_atomically` takes it: an I/O error goes back to it (which
/// names the file); any other keeps its type in `failure` and returns its message.
fn io_or_kept(e: Error, failure: &mut Option<Error>) -> std::io::Error {
    match e {
        Error::Io { source, .. } => source,
        other => {
            let message = other.to_string();
            *failure = Some(other);
            std::io::Error::other(message)
        }
    }
}

/// Writes `layer` beside the heightmap (its values on the rectangle when known, else
/// streamed band by band) and, with the heightmap's, its sidecar; returns its path.
fn write_layer_file(
    job: &Job,
    setup: &Setup,
    layer: ErosionLayer,
    values: Option<&crate::terrain::Heightfield>,
    band: usize,
) -> Result<PathBuf> {
    let path = layer_path(&setup.output, layer);
    let mut extremes = HeightRange { min: f64::INFINITY, max: f64::NEG_INFINITY };
    let rect = setup.terrain.rect;
    let mut failure = None;
    write_atomically(&path, |w| {
        let mut observe =
            |field: &crate::terrain::Heightfield, y0: u64, y1: u64| widen(&mut extremes, field, rect, y0, y1);
        write_layer(&setup.terrain.params, rect, layer, values, setup.format, band, w, &mut observe)
            .map_err(|e| io_or_kept(e, &mut failure))
    })
    .map_err(|e| failure.take().unwrap_or(e))?;
    if setup.sidecar {
        let mut sidecar = Sidecar::new(&setup.terrain.params, rect, setup.format, LAYER_RANGE, extremes);
        sidecar.file = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        sidecar.bytes = io::written_size(&path)?;
        sidecar.plan = job.plan.clone();
        sidecar.layer = Some(layer.name().to_string());
        let text = serde_json::to_string_pretty(&sidecar).map_err(|e| Error::Internal(e.to_string()))?;
        write_atomically(&Sidecar::path_for(&path), |w| w.write_all(format!("{text}\n").as_bytes()))?;
    }
    Ok(path)
}

/// Writes OUTPUT.json beside the heightmap (after it: a sidecar means the file is complete).
fn write_sidecar(job: &Job, setup: &Setup, heights: HeightRange) -> Result<PathBuf> {
    let mut sidecar =
        Sidecar::new(&setup.terrain.params, setup.terrain.rect, setup.format, setup.terrain.range, heights);
    sidecar.file = setup.output.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    sidecar.bytes = io::written_size(&setup.output)?;
    sidecar.plan = job.plan.clone();
    let path = Sidecar::path_for(&setup.output);
    let text = serde_json::to_string_pretty(&sidecar).map_err(|e| Error::Internal(e.to_string()))?;
    write_atomically(&path, |w| w.write_all(format!("{text}\n").as_bytes()))?;
    Ok(path)
}
