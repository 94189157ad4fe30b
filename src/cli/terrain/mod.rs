//! `asperity terrain`: classic diamond-square terrains as meshes or heightmaps, whole,
//! tiled or streamed; engine presets, sidecars, thermal and hydraulic erosion; `terrain plan` and
//! `terrain --plan DIR` for tiles run by a job runner.

mod dual;
mod plan;
mod preview;
mod rules;

use std::path::PathBuf;
use std::time::Instant;

use clap::{Args, Subcommand, ValueEnum};
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::io::{self, WriteOptions, write_atomically};
use crate::terrain::sidecar::{HeightRange, Sidecar};
use crate::terrain::stream::{LAYER_RANGE, StreamFormat, default_band, write_layer, write_terrain_observed};
use crate::terrain::{
    Distribution, ErosionLayer, Grid, HydraulicErosion, Method, Preset, Rect, TerrainParams, ThermalErosion, mesh,
    presets, tile_rect_in,
};
use preview::{PreviewSampler, write_preview};

/// Generators.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
enum MethodArg {
    /// Midpoint displacement / diamond-square (seed 001).
    Classic,
    /// Seed 002: uniform within the parents' range, Gaussian-smoothed.
    Smooth,
    /// Janeczek's dual midpoint displacement over a 3D quadrilateral (seed 000).
    Dual,
}

/// A plan's `erode`: a list, or as plans before hydraulic erosion wrote it, one model or
/// null.
fn erosion_list<'de, D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Vec<ErodeArg>, D::Error> {
    #[derive(Deserialize)]
    #[serde(untagged)]
    enum Written {
        One(ErodeArg),
        Many(Vec<ErodeArg>),
    }
    Ok(match Option::<Written>::deserialize(d)? {
        None => Vec::new(),
        Some(Written::One(model)) => vec![model],
        Some(Written::Many(models)) => models,
    })
}

/// Erosion models.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
enum ErodeArg {
    /// Talus-angle thermal erosion (Musgrave et al. 1989): material slides downhill
    /// wherever the slope exceeds the talus angle; tiles equal the whole grid.
    Thermal,
    /// Hydraulic erosion by virtual pipes (Mei et al. 2007): rain, flow, dissolving,
    /// transport and deposition of sediment, evaporation; tiles equal the whole grid.
    Hydraulic,
}

/// `--layers`' values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub(crate) enum LayerArg {
    /// Water that ran through each point over the run: rivers and gullies.
    Flow,
    /// Sediment deposited by the run: fans and valley floors.
    Sediment,
    /// Water standing after the run: lakes.
    Water,
    /// Water depth over the run.
    Wetness,
}

impl LayerArg {
    fn layer(self) -> ErosionLayer {
        match self {
            LayerArg::Flow => ErosionLayer::Flow,
            LayerArg::Sediment => ErosionLayer::Sediment,
            LayerArg::Water => ErosionLayer::Water,
            LayerArg::Wetness => ErosionLayer::Wetness,
        }
    }
}

/// The file of `layer` beside the heightmap `output`: its name with `.LAYER` before the
/// extension (`terrain.png` → `terrain.flow.png`).
pub(crate) fn layer_path(output: &std::path::Path, layer: ErosionLayer) -> PathBuf {
    let stem = output.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let name = match output.extension() {
        Some(ext) => format!("{stem}.{}.{}", layer.name(), ext.to_string_lossy()),
        None => format!("{stem}.{}", layer.name()),
    };
    output.with_file_name(name)
}

/// The flags that say which terrain is made: everything a plan stores and replays for
/// each tile.
#[derive(Debug, Clone, Args, Serialize, Deserialize)]
#[group(id = "generation", multiple = true)]
pub(crate) struct Generation {
    /// Generator.
    #[arg(long, value_enum, default_value_t = MethodArg::Classic)]
    method: MethodArg,
    /// Points per side, 2^n + 1 (classic, smooth; with --preset, a size the engine imports)
    /// [default: 257].
    #[arg(long)]
    size: Option<u64>,
    /// Seed 001's iterations k: a (2^k + 1)² grid, the same as --size 2^k+1.
    #[arg(long, conflicts_with = "size")]
    iterations: Option<u32>,
    /// Roughness H: the displacement scale falls by 2^-H per level (default 0.8; 1.5 for dual).
    #[arg(long, allow_negative_numbers = true)]
    hurst: Option<f64>,
    /// Seed 001's roughness: the factor by which the perturbations shrink per iteration,
    /// 2^H (2 is --hurst 1).
    #[arg(long, conflicts_with = "hurst", allow_negative_numbers = true)]
    roughness: Option<f64>,
    /// Displacement scale at the first level (dual: the factor applied to (|x| + |y|)/2).
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    sigma: f64,
    /// Dual: first side of the quadrilateral X,Y,Z [default: 1,0,0].
    #[arg(long, value_parser = crate::cli::parse::vector, allow_hyphen_values = true)]
    x: Option<[f64; 3]>,
    /// Dual: second side of the quadrilateral X,Y,Z [default: 0,1,0].
    #[arg(long, value_parser = crate::cli::parse::vector, allow_hyphen_values = true)]
    y: Option<[f64; 3]>,
    /// Dual: number of divisions n ((2^n + 1)² points) [default: 9].
    #[arg(long)]
    levels: Option<u32>,
    /// Dual: displace by σ itself instead of a random sample.
    #[arg(long)]
    deterministic: bool,
    /// Dual: one sample per point along the cross product of its two pairs.
    #[arg(long)]
    cross_product: bool,
    /// Dual: keep the original points where they are (shows his Fig. 2 artifacts).
    #[arg(long)]
    no_mean_correction: bool,
    /// Dual: also write each division's surface as DIR/level-NN.ply.
    #[arg(long)]
    steps: Option<PathBuf>,
    /// Seed.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Displacement distribution (classic, smooth's corners) [default: normal].
    #[arg(long, value_enum)]
    distribution: Option<Distribution>,
    /// Mean of the distribution (classic, smooth's corners) [default: 0].
    #[arg(long, allow_hyphen_values = true)]
    mean: Option<f64>,
    /// Variance of the distribution (classic, smooth's corners) [default: 1].
    #[arg(long, allow_negative_numbers = true)]
    variance: Option<f64>,
    /// Corner heights A,B,C,D (x0y0, xNy0, x0yN, xNyN), set exactly as in seed 001's
    /// applet [default: each a random draw around 0].
    #[arg(long, value_parser = crate::cli::parse::four, allow_hyphen_values = true)]
    corners: Option<[f64; 4]>,
    /// Seed 001's applet variant: constant scale, random sign.
    #[arg(long)]
    applet: bool,
    /// World width (x) (classic, smooth) [default: 10].
    #[arg(long, allow_negative_numbers = true)]
    width: Option<f64>,
    /// World depth (y) (classic, smooth) [default: 10].
    #[arg(long, allow_negative_numbers = true)]
    depth: Option<f64>,
    /// Seed 001's max height: the highest peak's height; every height is scaled so the
    /// whole grid's highest point is exactly this (classic, smooth; measured on the whole
    /// grid before erosion, so not with --stream or --tile; exclusive with --sigma and
    /// --corners, which set heights too).
    #[arg(long, conflicts_with_all = ["sigma", "corners"], allow_negative_numbers = true)]
    max_height: Option<f64>,
    /// Raise everything below this height to it.
    #[arg(long, allow_hyphen_values = true)]
    sea_level: Option<f64>,
    /// Ramp colours SEA;LOW;MID;HIGH;PEAK, each R,G,B.
    #[arg(long, value_parser = crate::cli::parse::palette)]
    colors: Option<crate::terrain::Palette>,
    /// Height above the sea that gets the peak colour (default: half the height scale).
    #[arg(long, allow_negative_numbers = true)]
    peak_height: Option<f64>,
    /// Grid type (classic, smooth) [default: square].
    #[arg(long, value_enum)]
    grid: Option<Grid>,
    /// Height range LO,HI mapped to 16 bits (.png, .raw16); default ± the height scale.
    #[arg(long, value_parser = crate::cli::parse::range, allow_hyphen_values = true)]
    range: Option<(f64, f64)>,
    /// Erode the generated heights (classic, smooth): thermal, hydraulic, or
    /// thermal,hydraulic (in that order); identical in tiles, which are computed with a halo
    /// of one point per thermal and two per hydraulic iteration.
    #[arg(long, value_enum, value_delimiter = ',')]
    #[serde(default, deserialize_with = "erosion_list")]
    erode: Vec<ErodeArg>,
    /// Erosion iterations, of each erosion (with --erode) [default: 50].
    #[arg(long)]
    erode_iterations: Option<u32>,
    /// Talus angle in degrees: the steepest slope erosion leaves in place (with --erode
    /// thermal) [default: 30].
    #[arg(long, allow_negative_numbers = true)]
    talus: Option<f64>,
    /// Rain Kr: water depth added per unit time, world height units (with --erode
    /// hydraulic) [default: 0.01].
    #[arg(long, allow_negative_numbers = true)]
    rain: Option<f64>,
    /// Evaporation Ke: share of the water evaporating per unit time, below 1/--time-step
    /// (with --erode hydraulic) [default: 0.5].
    #[arg(long, allow_negative_numbers = true)]
    evaporation: Option<f64>,
    /// Sediment capacity Kc: sediment the water carries per unit of speed and sin(tilt)
    /// (with --erode hydraulic) [default: 1].
    #[arg(long, allow_negative_numbers = true)]
    capacity: Option<f64>,
    /// Dissolving rate Ks in (0, 1]: share of the missing capacity dissolved per iteration
    /// (with --erode hydraulic) [default: 0.3].
    #[arg(long, allow_negative_numbers = true)]
    dissolving: Option<f64>,
    /// Deposition rate Kd in (0, 1]: share of the excess sediment deposited per iteration
    /// (with --erode hydraulic) [default: 0.3].
    #[arg(long, allow_negative_numbers = true)]
    deposition: Option<f64>,
    /// Time step Δt in (0, 1] (with --erode hydraulic) [default: 0.05].
    #[arg(long, allow_negative_numbers = true)]
    time_step: Option<f64>,
    /// Also write these layers of the hydraulic erosion beside a heightmap, in its format:
    /// flow, sediment, water, wetness (masks in [0, 1]: water that ran through, deposits,
    /// standing water, water over the run), as OUTPUT's name with .flow, .sediment, .water
    /// or .wetness before the extension (with --erode hydraulic).
    #[arg(long, value_enum, value_delimiter = ',')]
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    layers: Vec<LayerArg>,
    /// Write what a game engine imports: unity (RAW16 little-endian, 2^n + 1 from 33 to
    /// 4097 points a side) or unreal (PNG16, 127, 253, 505, 1009, 2017, 4033 or 8129);
    /// tiles named NAME_x{X}_y{Y}; a JSON sidecar with the height mapping.
    #[arg(long, value_enum)]
    preset: Option<Preset>,
}

/// The subcommand's flags (`TerrainArgs`).
#[derive(Debug, Args)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct TerrainArgs {
    #[command(subcommand)]
    command: Option<TerrainCommand>,
    #[command(flatten)]
    generation: Generation,
    /// Write rows as they are generated, in bounded memory (.ply, .obj, .png, .raw16, .f32).
    #[arg(long)]
    stream: bool,
    /// Rows per streamed band (with --stream) [default: as many as 2^22 points make, 64 to
    /// 1024].
    #[arg(long)]
    band: Option<usize>,
    /// Generate only tile I,J (needs --tile-size).
    #[arg(long, value_parser = crate::cli::parse::index_pair, requires = "tile_size")]
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
    generation: &'a Generation,
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
        generation: &'a Generation,
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
}

/// Memory a whole-grid mesh takes per grid point: the heights and their coarser levels,
/// positions, normals, colours and two triangles (peak measured at 2049²: 99 bytes).
const MESH_BYTES_PER_POINT: u64 = 112;

/// Memory a heightmap's rows take per point: the heights, the coarser levels that feed them
/// and the encoded output (peak measured at 2049²: 11 bytes; twice that with smoothing).
const HEIGHTS_BYTES_PER_POINT: u64 = 16;

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

/// The heights the flags of `args` describe (a heightfield method; `--tile` for a tile), as
/// the command would write them: the library call behind `asperity.terrain` in Python.
///
/// # Errors
/// As the command's, for the flags given; `--method dual`, which makes a surface.
pub fn heights_of(args: &TerrainArgs) -> Result<crate::terrain::Heightfield> {
    if args.generation.method == MethodArg::Dual {
        return Err(Error::InvalidInput(
            "--method dual makes a 3D surface, not a heightfield: use the command line's terrain --method dual".into(),
        ));
    }
    let job = in_memory_job(args, "f32");
    let setup = Setup::of(&job)?;
    crate::terrain::heights(&setup.params, setup.rect)
}

/// The heights [`heights_of`] gives and the hydraulic erosion's layers `--layers` names
/// (all four when it names none), from one run, each a mask in [0, 1]
/// ([`crate::terrain::ErosionLayers`]).
///
/// # Errors
/// As [`heights_of`]; without `--erode hydraulic`.
pub fn layers_of(
    args: &TerrainArgs,
) -> Result<(crate::terrain::Heightfield, Vec<(ErosionLayer, crate::terrain::Heightfield)>)> {
    if args.generation.method == MethodArg::Dual {
        return Err(Error::InvalidInput("--method dual makes a 3D surface, not a heightfield with layers".into()));
    }
    if !args.generation.erode.contains(&ErodeArg::Hydraulic) {
        return Err(Error::InvalidInput("erosion layers need hydraulic erosion (--erode hydraulic)".into()));
    }
    let job = in_memory_job(args, "f32");
    let setup = Setup::of(&job)?;
    let layers = if setup.layers.is_empty() { ErosionLayer::ALL.to_vec() } else { setup.layers.clone() };
    let (heights, fields) = crate::terrain::heights_and_layers(&setup.params, setup.rect, &layers)?;
    Ok((heights, layers.into_iter().zip(fields).collect()))
}

/// The job of `args` made in memory rather than written: checked as if written as `format`.
fn in_memory_job<'a>(args: &'a TerrainArgs, format: &str) -> Job<'a> {
    let output = args.output.clone().unwrap_or_else(|| PathBuf::from(format!("terrain.{format}")));
    Job::named(&args.generation, output, format, args.tile, args.tile_size)
}

/// The mesh the flags of `args` describe, as the command writes it to `.ply`: a
/// heightfield's (positions, normals, height colours; `--tile` for a tile) or the dual
/// method's surface. The library call behind `asperity.terrain_mesh` in Python.
///
/// # Errors
/// As the command's, for the flags given.
pub fn mesh_of(args: &TerrainArgs) -> Result<crate::mesh::Mesh> {
    let job = in_memory_job(args, "ply");
    if args.generation.method == MethodArg::Dual {
        return dual::mesh_of(&job);
    }
    let setup = Setup::of(&job)?;
    mesh(&setup.params, setup.rect)
}

/// Writes one terrain.
fn run_job(job: &Job, ctx: crate::cli::Context) -> Result<()> {
    let start = Instant::now();
    if job.generation.method == MethodArg::Dual {
        return dual::run(job, start, ctx);
    }
    let setup = Setup::of(job)?;
    generate(job, &setup, start, ctx)
}

/// What a heightfield job writes, checked before anything is generated.
#[derive(Debug)]
pub(super) struct Setup {
    params: TerrainParams,
    /// The region written.
    rect: Rect,
    /// Points per side of the region the tiles are cut from (the grid, or a preset's window).
    extent: u64,
    /// The output file.
    output: PathBuf,
    /// A whole mesh (PLY, OBJ) or a streamable encoding.
    format: StreamFormat,
    whole_mesh: bool,
    /// Heights mapped to 16 bits.
    range: (f64, f64),
    hurst: f64,
    sidecar: bool,
    /// Erosion layers written beside the heightmap, each once, in the order asked.
    layers: Vec<ErosionLayer>,
}

impl Setup {
    /// Checks every flag of `job` and works out what it writes.
    fn of(job: &Job) -> Result<Setup> {
        let g = job.generation;
        rules::refuse_other_modes_flags(job)?;
        let method = if g.method == MethodArg::Smooth { Method::Smooth } else { Method::Classic };
        let hurst = hurst_of(g, 0.8)?;
        let size = match g.iterations {
            Some(k @ 1..=31) => (1u64 << k) + 1,
            Some(k) => return Err(Error::InvalidInput(format!("--iterations {k} must be between 1 and 31"))),
            None => g.size.unwrap_or(257),
        };
        let grid = g.grid.unwrap_or_default();
        if grid == Grid::Hex && job.tile.is_some() {
            return Err(Error::InvalidInput(
                "a hexagonal tile is one terrain: --tile applies to square and triangle grids".into(),
            ));
        }
        // A preset's size is what the engine imports; the grid is the next 2^n + 1.
        let (extent, grid_size) = match g.preset {
            Some(preset) => {
                if grid != Grid::Square {
                    return Err(Error::InvalidInput(format!(
                        "--preset {}: game engines import square grids, not --grid {grid:?}",
                        preset.engine().to_lowercase()
                    )));
                }
                match (job.tile, job.tile_size) {
                    (Some(_), Some(t)) => preset.check_size(t, "--tile-size")?,
                    _ => preset.check_size(size, "--size")?,
                }
                (size, Preset::generation_size(size))
            }
            None => (size, size),
        };
        let width = g.width.unwrap_or(10.0);
        let depth = g.depth.unwrap_or(10.0);
        // A window of a larger grid keeps the world extent on the window.
        let stretch = (grid_size - 1) as f64 / (extent.max(2) - 1) as f64;
        let iterations = g.erode_iterations.unwrap_or(50);
        use ErodeArg::{Hydraulic, Thermal};
        if !matches!(g.erode.as_slice(), [] | [Thermal] | [Hydraulic] | [Thermal, Hydraulic]) {
            return Err(Error::InvalidInput(
                "--erode runs thermal, hydraulic or thermal,hydraulic (each once, thermal first)".into(),
            ));
        }
        let erosion = g
            .erode
            .contains(&ErodeArg::Thermal)
            .then(|| ThermalErosion { iterations, talus_degrees: g.talus.unwrap_or(30.0) });
        let hydraulic = g.erode.contains(&ErodeArg::Hydraulic).then(|| {
            let d = HydraulicErosion::default();
            HydraulicErosion {
                iterations,
                rain: g.rain.unwrap_or(d.rain),
                evaporation: g.evaporation.unwrap_or(d.evaporation),
                capacity: g.capacity.unwrap_or(d.capacity),
                dissolving: g.dissolving.unwrap_or(d.dissolving),
                deposition: g.deposition.unwrap_or(d.deposition),
                time_step: g.time_step.unwrap_or(d.time_step),
            }
        });
        let params = TerrainParams {
            method,
            grid,
            size: grid_size,
            hurst,
            sigma: g.sigma,
            seed: g.seed,
            distribution: g.distribution.unwrap_or_default(),
            mean: g.mean.unwrap_or(0.0),
            variance: g.variance.unwrap_or(1.0),
            corners: g.corners,
            applet: g.applet,
            width: width * stretch,
            depth: depth * stretch,
            sea_level: g.sea_level,
            height_factor: 1.0,
            palette: g.colors.unwrap_or_default(),
            peak_height: g.peak_height,
            erosion,
            hydraulic,
        };
        params.generator()?;
        if let Some(preview) = &job.preview {
            crate::cli::require_extension(preview, &["png"])?;
            crate::cli::distinct_outputs(&[("-o", job.output.as_path()), ("--preview", preview.as_path())])?;
        }
        let rect = match (job.tile, job.tile_size) {
            (Some((i, j)), Some(tile_size)) => tile_rect_in(extent, i, j, tile_size)?,
            _ => Rect { x0: 0, y0: 0, x1: extent - 1, y1: extent - 1 },
        };
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
        let whole_mesh = matches!(ext.as_str(), "obj" | "ply") && !job.stream;
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
        let mut layers: Vec<ErosionLayer> = Vec::new();
        for layer in g.layers.iter().map(|l| l.layer()) {
            if !layers.contains(&layer) {
                layers.push(layer);
            }
        }
        if !layers.is_empty() && !format.is_heightmap() {
            return Err(Error::InvalidInput(format!(
                "{}: --layers are heightmaps written beside a heightmap: write the terrain as .png, .raw16, .f32, .exr or .tif",
                job.output.display()
            )));
        }
        let mut named = vec![("-o", output.clone())];
        named.extend(layers.iter().map(|&l| ("--layers", layer_path(&output, l))));
        if let Some(preview) = &job.preview {
            named.push(("--preview", preview.clone()));
        }
        crate::cli::distinct_outputs(&named.iter().map(|(flag, path)| (*flag, path.as_path())).collect::<Vec<_>>())?;
        let points = rect.width() as u64 * rect.height() as u64;
        if format == StreamFormat::Ply && points > i32::MAX as u64 {
            return Err(Error::InvalidInput(format!("{points} vertices exceed PLY's int indices: use --tile")));
        }
        let halo = 2 * params.erosion_halo();
        let band = job.band.unwrap_or_else(|| default_band(rect.width())).max(1);
        let rows_at_once = if job.stream { band.min(rect.height()) } else { rect.height() };
        let bytes_per_point = if whole_mesh { MESH_BYTES_PER_POINT } else { HEIGHTS_BYTES_PER_POINT };
        let smoothing = if method == Method::Smooth || erosion.is_some() || hydraulic.is_some() { 2 } else { 1 };
        // Hydraulic erosion's state: water, sediment and the pipes' flux, each twice.
        let hydraulic_bytes = hydraulic.map_or(0, |_| crate::terrain::hydraulic::BYTES_PER_POINT)
            + if layers.is_empty() {
                0
            } else {
                crate::terrain::hydraulic::LAYER_BYTES_PER_POINT + 8 * layers.len() as u64
            };
        // A halo never reaches past the grid: 100000 erosion iterations on a whole 257² grid
        // were refused as needing 8965.8 GB (#36).
        let (rows, columns) =
            ((rows_at_once as u64 + halo).min(grid_size), (rect.width() as u64 + halo).min(grid_size));
        crate::memory::ensure_available(
            rows * columns * (bytes_per_point * smoothing + hydraulic_bytes),
            &format!("a {}x{} terrain built whole", rect.width(), rect.height()),
            "write a heightmap with --stream, or cut it into --tile pieces",
        )?;
        let params = match g.max_height {
            Some(top) => params.with_max_height(top)?,
            None => params,
        };
        let scale = params.height_scale();
        let range = g.range.unwrap_or((-scale, scale));
        let sidecar = job.sidecar || g.preset.is_some();
        if sidecar && std::fs::metadata(&output).is_ok_and(|m| !m.is_file()) {
            return Err(Error::InvalidInput(format!(
                "{}: a sidecar (--sidecar, --preset) is written beside a file, and this is not one",
                output.display()
            )));
        }
        Ok(Setup { params, rect, extent, output, format, whole_mesh, range, hurst, sidecar, layers })
    }
}

/// Generates and writes the terrain `setup` describes, its preview and sidecar.
fn generate(job: &Job, setup: &Setup, start: Instant, ctx: crate::cli::Context) -> Result<()> {
    let (params, rect, output) = (&setup.params, setup.rect, &setup.output);
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
        let known = match (setup.layers.is_empty(), job.stream) {
            (false, false) => Some(
                ctx.spin("terrain", "eroding", || crate::terrain::heights_and_layers(params, rect, &setup.layers))?,
            ),
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
                write_terrain_observed(params, rect, known, setup.format, setup.range, band, w, &mut observe)
                    .map_err(|e| io_or_kept(e, &mut failure))
            })
        })
        .map_err(|e| failure.take().unwrap_or(e))?;
        for (k, &layer) in setup.layers.iter().enumerate() {
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
    let method = job.generation.method.to_possible_value().map_or_else(String::new, |v| v.get_name().to_string());
    ctx.report(
        || {
            let layers: String = layer_files.iter().map(|p| format!(", {}", p.display())).collect();
            format!(
                "terrain: {method} {}x{} (H {}, seed {}) => {}{layers} in {} ms ({:.1} M points/s)",
                rect.width(),
                rect.height(),
                setup.hurst,
                job.generation.seed,
                output.display(),
                crate::cli::millis(start),
                points as f64 / seconds.max(1e-9) / 1e6
            )
        },
        || {
            serde_json::json!({
                "method": method, "output": output, "preview": job.preview, "sidecar": sidecar_path, "layers": layer_files,
                "columns": rect.width(), "rows": rect.height(), "hurst": setup.hurst, "seed": job.generation.seed,
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
    let rect = setup.rect;
    let mut failure = None;
    write_atomically(&path, |w| {
        let mut observe =
            |field: &crate::terrain::Heightfield, y0: u64, y1: u64| widen(&mut extremes, field, rect, y0, y1);
        write_layer(&setup.params, rect, layer, values, setup.format, band, w, &mut observe)
            .map_err(|e| io_or_kept(e, &mut failure))
    })
    .map_err(|e| failure.take().unwrap_or(e))?;
    if setup.sidecar {
        let mut sidecar = Sidecar::new(&setup.params, rect, setup.format, LAYER_RANGE, extremes);
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
    let mut sidecar = Sidecar::new(&setup.params, setup.rect, setup.format, setup.range, heights);
    sidecar.file = setup.output.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    sidecar.bytes = io::written_size(&setup.output)?;
    sidecar.plan = job.plan.clone();
    let path = Sidecar::path_for(&setup.output);
    let text = serde_json::to_string_pretty(&sidecar).map_err(|e| Error::Internal(e.to_string()))?;
    write_atomically(&path, |w| w.write_all(format!("{text}\n").as_bytes()))?;
    Ok(path)
}

/// H from `--hurst`, or from `--roughness` (2^H), or `default`.
pub(super) fn hurst_of(args: &Generation, default: f64) -> Result<f64> {
    match (args.hurst, args.roughness) {
        (_, Some(r)) if !(r.is_finite() && r > 0.0) => {
            Err(Error::InvalidInput(format!("--roughness {r} must be positive (it is 2^H)")))
        }
        (_, Some(r)) => Ok(r.log2()),
        (h, None) => Ok(h.unwrap_or(default)),
    }
}
