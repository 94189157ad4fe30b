//! `asperity terrain`: classic diamond-square terrains as meshes or heightmaps, whole,
//! tiled or streamed.

use std::path::PathBuf;
use std::time::Instant;

use clap::{Args, ValueEnum};

use crate::analysis::{FaceGeometry, NormalWeighting, vertex_normals};
use crate::error::{Error, Result};
use crate::io::{self, WriteOptions, write_atomically};
use crate::mesh::Adjacency;
use crate::render::hillshade::{Relief, hillshade};
use crate::terrain::Grid;
use crate::terrain::stream::{StreamFormat, write_terrain_observed};
use crate::terrain::{
    Distribution, DualParams, Method, QuadSurface, Rect, TerrainParams, dual_midpoint_displacement, heights, mesh,
    ramp_color, tile_rect,
};

/// Generators.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum MethodArg {
    /// Midpoint displacement / diamond-square (seed 001).
    Classic,
    /// Seed 002: uniform within the parents' range, Gaussian-smoothed.
    Smooth,
    /// Janeczek's dual midpoint displacement over a 3D quadrilateral (seed 000).
    Dual,
}

#[derive(Debug, Args)]
pub struct TerrainArgs {
    /// Generator.
    #[arg(long, value_enum, default_value_t = MethodArg::Classic)]
    method: MethodArg,
    /// Points per side, 2^n + 1 (classic, smooth) [default: 257].
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
    #[arg(long, value_parser = super::parse::vector, allow_hyphen_values = true)]
    x: Option<[f64; 3]>,
    /// Dual: second side of the quadrilateral X,Y,Z [default: 0,1,0].
    #[arg(long, value_parser = super::parse::vector, allow_hyphen_values = true)]
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
    #[arg(long, value_parser = super::parse::four, allow_hyphen_values = true)]
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
    /// grid, so not with --tile or --stream; exclusive with --sigma and --corners, which
    /// set heights too).
    #[arg(long, conflicts_with_all = ["sigma", "corners"], allow_negative_numbers = true)]
    max_height: Option<f64>,
    /// Raise everything below this height to it.
    #[arg(long, allow_hyphen_values = true)]
    sea_level: Option<f64>,
    /// Ramp colours SEA;LOW;MID;HIGH;PEAK, each R,G,B.
    #[arg(long, value_parser = super::parse::palette)]
    colors: Option<crate::terrain::Palette>,
    /// Height above the sea that gets the peak colour (default: half the height scale).
    #[arg(long, allow_negative_numbers = true)]
    peak_height: Option<f64>,
    /// Grid type (classic, smooth) [default: square].
    #[arg(long, value_enum)]
    grid: Option<Grid>,
    /// Write rows as they are generated, in bounded memory (.ply, .obj, .png, .raw16, .f32).
    #[arg(long)]
    stream: bool,
    /// Rows per streamed band (with --stream) [default: 64].
    #[arg(long)]
    band: Option<usize>,
    /// Generate only tile I,J (needs --tile-size).
    #[arg(long, value_parser = super::parse::index_pair, requires = "tile_size")]
    tile: Option<(u64, u64)>,
    /// Points per tile side, 2^k + 1; tiles share their borders.
    #[arg(long)]
    tile_size: Option<u64>,
    /// Height range LO,HI mapped to 16 bits (.png, .raw16); default ± the height scale.
    #[arg(long, value_parser = super::parse::range, allow_hyphen_values = true)]
    range: Option<(f64, f64)>,
    /// Output: .ply / .obj mesh, .png 16-bit heightmap, .raw16, .f32.
    #[arg(short, long)]
    output: PathBuf,
    /// Also write a picture: a hillshaded colour map (classic, smooth; one pixel per point,
    /// or with --stream every k-th point of the streamed rows, at most 1024 a side) or a
    /// rendering of the surface (dual), as .png.
    #[arg(long)]
    preview: Option<PathBuf>,
    /// Output format when the file name has no telling extension (e.g. -o /dev/null):
    /// ply, obj, png, raw16 or f32.
    #[arg(long)]
    format: Option<String>,
}

/// Memory a whole-grid mesh takes per grid point: the heights and their coarser levels,
/// positions, normals, colours and two triangles (peak measured at 2049²: 99 bytes).
const MESH_BYTES_PER_POINT: u64 = 112;

/// Memory a heightmap's rows take per point: the heights, the coarser levels that feed them
/// and the encoded output (peak measured at 2049²: 11 bytes; twice that with smoothing).
const HEIGHTS_BYTES_PER_POINT: u64 = 16;

pub fn run(args: TerrainArgs, ctx: super::Context) -> Result<()> {
    let start = Instant::now();
    let method = match args.method {
        MethodArg::Classic => Method::Classic,
        MethodArg::Smooth => Method::Smooth,
        MethodArg::Dual => return run_dual(&args, start, ctx),
    };
    refuse_other_modes_flags(&args)?;
    let hurst = hurst_of(&args, 0.8)?;
    let size = match args.iterations {
        Some(k @ 1..=31) => (1u64 << k) + 1,
        Some(k) => return Err(Error::InvalidInput(format!("--iterations {k} must be between 1 and 31"))),
        None => args.size.unwrap_or(257),
    };
    let grid = args.grid.unwrap_or_default();
    let band = args.band.unwrap_or(64);
    if grid == Grid::Hex && args.tile.is_some() {
        return Err(Error::InvalidInput(
            "a hexagonal tile is one terrain: --tile applies to square and triangle grids".into(),
        ));
    }
    let params = TerrainParams {
        method,
        grid,
        size,
        hurst,
        sigma: args.sigma,
        seed: args.seed,
        distribution: args.distribution.unwrap_or_default(),
        mean: args.mean.unwrap_or(0.0),
        variance: args.variance.unwrap_or(1.0),
        corners: args.corners,
        applet: args.applet,
        width: args.width.unwrap_or(10.0),
        depth: args.depth.unwrap_or(10.0),
        sea_level: args.sea_level,
        height_factor: 1.0,
        palette: args.colors.unwrap_or_default(),
        peak_height: args.peak_height,
    };
    params.generator()?;
    if let Some(preview) = &args.preview {
        super::require_extension(preview, &["png"])?;
    }
    let rect = match (args.tile, args.tile_size) {
        (Some((i, j)), Some(size)) => tile_rect(&params, i, j, size)?,
        _ => Rect { x0: 0, y0: 0, x1: size - 1, y1: size - 1 },
    };
    let ext = match &args.format {
        Some(format) => format.to_ascii_lowercase(),
        None => args.output.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase(),
    };
    let points = rect.width() as u64 * rect.height() as u64;
    let whole_mesh = matches!(ext.as_str(), "obj" | "ply") && !args.stream;
    let rows_at_once = if args.stream { band.max(1).min(rect.height()) } else { rect.height() } as u64;
    let bytes_per_point = if whole_mesh { MESH_BYTES_PER_POINT } else { HEIGHTS_BYTES_PER_POINT };
    let smoothing = if method == Method::Smooth { 2 } else { 1 };
    crate::memory::ensure_available(
        rows_at_once * rect.width() as u64 * bytes_per_point * smoothing,
        &format!("a {}x{} terrain built whole", rect.width(), rect.height()),
        "write a heightmap with --stream, or cut it into --tile pieces",
    )?;
    let params = match args.max_height {
        Some(top) => params.with_max_height(top)?,
        None => params,
    };
    let scale = params.height_scale();
    let range = args.range.unwrap_or((-scale, scale));
    let mut streamed_preview: Option<PreviewSampler> = None;
    if whole_mesh {
        let terrain = ctx.spin("terrain", "generating the mesh", || mesh(&params, rect))?;
        let format = if ext == "obj" { io::Format::Obj } else { io::Format::Ply };
        io::write_as(&terrain, &args.output, format, WriteOptions::default())?;
    } else {
        let format = StreamFormat::from_extension(&ext).ok_or_else(|| {
            Error::InvalidInput(format!(
                "{}: the output must end in .ply, .obj, .png, .raw16 or .f32",
                args.output.display()
            ))
        })?;
        if format == StreamFormat::Ply && points > i32::MAX as u64 {
            return Err(Error::InvalidInput(format!("{points} vertices exceed PLY's int indices: use --tile")));
        }
        let band = if args.stream { band } else { rect.height() };
        let mut failure = None;
        // A streamed terrain's preview is made from the streamed rows, at most
        // STREAMED_PREVIEW_SIDE pixels a side: one more band-sized pass would not be bounded.
        streamed_preview = (args.stream && args.preview.is_some()).then(|| PreviewSampler::new(rect));
        // I/O failures go back to `write_atomically`, which names the output file; other
        // errors keep their type.
        let message = format!("{}x{} points", rect.width(), rect.height());
        let sampler = &mut streamed_preview;
        ctx.spin("terrain", &message, || {
            write_atomically(&args.output, |w| {
                let mut observe = |field: &crate::terrain::Heightfield, y0: u64, y1: u64| {
                    if let Some(sampler) = sampler.as_mut() {
                        sampler.take(field, y0, y1);
                    }
                };
                write_terrain_observed(&params, rect, format, range, band, w, &mut observe).map_err(|e| match e {
                    Error::Io { source, .. } => source,
                    other => {
                        let message = other.to_string();
                        failure = Some(other);
                        std::io::Error::other(message)
                    }
                })
            })
        })
        .map_err(|e| failure.take().unwrap_or(e))?;
    }
    let seconds = start.elapsed().as_secs_f64();
    match (&args.preview, streamed_preview) {
        (Some(preview), Some(sampler)) => sampler.picture(&params).write_png(preview)?,
        (Some(preview), None) => write_preview(&params, rect, preview)?,
        _ => {}
    }
    let method = args.method.to_possible_value().map_or_else(String::new, |v| v.get_name().to_string());
    ctx.report(
        || {
            format!(
                "terrain: {method} {}x{} (H {}, seed {}) => {} in {} ms ({:.1} M points/s)",
                rect.width(),
                rect.height(),
                hurst,
                args.seed,
                args.output.display(),
                super::millis(start),
                points as f64 / seconds.max(1e-9) / 1e6
            )
        },
        || {
            serde_json::json!({
                "method": method, "output": args.output, "preview": args.preview, "columns": rect.width(),
                "rows": rect.height(), "hurst": hurst, "seed": args.seed, "points": points,
                "seconds": seconds, "points_per_second": points as f64 / seconds.max(1e-9),
            })
        },
    );
    Ok(())
}

/// Janeczek's dual method: a quad surface written as a mesh with normals and a height ramp.
fn run_dual(args: &TerrainArgs, start: Instant, ctx: super::Context) -> Result<()> {
    refuse_other_modes_flags(args)?;
    let format = io::Format::from_path(&args.output)?;
    if !matches!(format, io::Format::Ply | io::Format::Obj) {
        return Err(Error::InvalidInput(format!("{}: --method dual writes .ply or .obj", args.output.display())));
    }
    let params = DualParams {
        x: args.x.unwrap_or([1.0, 0.0, 0.0]).into(),
        y: args.y.unwrap_or([0.0, 1.0, 0.0]).into(),
        hurst: hurst_of(args, 1.5)?,
        levels: args.levels.unwrap_or(9),
        scale: args.sigma,
        seed: args.seed,
        deterministic: args.deterministic,
        cross_product: args.cross_product,
        mean_correction: !args.no_mean_correction,
    };
    if let Some(dir) = &args.steps {
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    }
    let mut step_error = None;
    let surface = dual_midpoint_displacement(&params, |level, surface| {
        if let (Some(dir), None) = (&args.steps, &step_error) {
            let path = dir.join(format!("level-{level:02}.ply"));
            if let Err(e) = io::write(&dual_mesh(surface, &params, args), &path, WriteOptions::default()) {
                step_error = Some(e);
            }
        }
    })?;
    if let Some(e) = step_error {
        return Err(e);
    }
    let mesh = dual_mesh(&surface, &params, args);
    io::write(&mesh, &args.output, WriteOptions::default())?;
    if let Some(preview) = &args.preview {
        super::require_extension(preview, &["png"])?;
        let up = crate::render::UpAxis::Z;
        let options = crate::render::RenderOptions { up, ..Default::default() };
        crate::render::render(&mesh, &options)?.write_png(preview)?;
    }
    ctx.report(
        || {
            format!(
                "terrain: dual {}x{} (H {}, {} divisions, seed {}) => {} in {} ms",
                surface.m,
                surface.n,
                params.hurst,
                params.levels,
                params.seed,
                args.output.display(),
                super::millis(start)
            )
        },
        || {
            serde_json::json!({
                "method": "dual", "output": args.output, "preview": args.preview, "columns": surface.m,
                "rows": surface.n, "hurst": params.hurst, "levels": params.levels, "seed": params.seed,
                "seconds": start.elapsed().as_secs_f64(),
            })
        },
    );
    Ok(())
}

/// The quad surface as a mesh with angle-weighted normals and colours by height along the
/// quad's normal (the surface's own range).
fn dual_mesh(surface: &QuadSurface, params: &DualParams, args: &TerrainArgs) -> crate::mesh::Mesh {
    let mut m = surface.to_mesh();
    let adjacency = Adjacency::of(&m);
    m.normals = Some(vertex_normals(&m, &adjacency, &FaceGeometry::of(&m), NormalWeighting::Angle));
    let z = params.x.cross(params.y).normalize();
    let heights: Vec<f64> = m.positions.iter().map(|p| p.dot(z)).collect();
    let (lo, hi) = heights.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &h| (a.min(h), b.max(h)));
    let palette = args.colors.unwrap_or_default();
    m.colors = Some(heights.iter().map(|h| ramp_color(&palette, (h - lo) / (hi - lo).max(1e-12), false)).collect());
    m
}

/// The largest side of a streamed terrain's preview, pixels: every k-th point of every
/// k-th streamed row, k the smallest stride that fits.
const STREAMED_PREVIEW_SIDE: usize = 1024;

/// A streamed terrain's preview, gathered from the rows as they stream past: the heights
/// at every `stride`-th point of every `stride`-th row.
struct PreviewSampler {
    rect: Rect,
    stride: u64,
    columns: usize,
    heights: Vec<f64>,
}

impl PreviewSampler {
    fn new(rect: Rect) -> Self {
        let side = rect.width().max(rect.height());
        let stride = side.div_ceil(STREAMED_PREVIEW_SIDE).max(1) as u64;
        let columns = (rect.width() as u64).div_ceil(stride) as usize;
        let rows = (rect.height() as u64).div_ceil(stride) as usize;
        PreviewSampler { rect, stride, columns, heights: Vec::with_capacity(columns * rows) }
    }

    /// Takes the sampled points of rows y0..=y1 of `field`.
    fn take(&mut self, field: &crate::terrain::Heightfield, y0: u64, y1: u64) {
        for y in (y0..=y1).filter(|y| (y - self.rect.y0) % self.stride == 0) {
            self.heights.extend((0..self.columns as u64).map(|i| field.at(self.rect.x0 + i * self.stride, y)));
        }
    }

    /// The hillshaded picture, one pixel per sampled point.
    fn picture(&self, params: &TerrainParams) -> crate::render::Picture {
        let last = (params.size - 1).max(1) as f64;
        let k = self.stride as f64;
        let relief = Relief {
            heights: &self.heights,
            columns: self.columns,
            spacing: (params.width / last * k, params.depth / last * k),
            exaggeration: None,
        };
        hillshade(&relief, |h| params.color(h))
    }
}

/// The largest grid a preview pictures (one pixel per point).
const PREVIEW_MAX_SIDE: usize = 8193;

/// A hillshaded colour map of the heights on `rect`, one pixel per grid point.
fn write_preview(params: &TerrainParams, rect: Rect, path: &std::path::Path) -> Result<()> {
    if rect.width() > PREVIEW_MAX_SIDE || rect.height() > PREVIEW_MAX_SIDE {
        return Err(Error::InvalidInput(format!(
            "--preview pictures at most {PREVIEW_MAX_SIDE}x{PREVIEW_MAX_SIDE} points, one pixel each: preview a tile instead"
        )));
    }
    let field = heights(params, rect)?;
    let last = (params.size - 1).max(1) as f64;
    let relief = Relief {
        heights: &field.heights,
        columns: rect.width(),
        spacing: (params.width / last, params.depth / last),
        exaggeration: None,
    };
    hillshade(&relief, |h| params.color(h)).write_png(path)
}

/// H from `--hurst`, or from `--roughness` (2^H), or `default`.
fn hurst_of(args: &TerrainArgs, default: f64) -> Result<f64> {
    match (args.hurst, args.roughness) {
        (_, Some(r)) if !(r.is_finite() && r > 0.0) => {
            Err(Error::InvalidInput(format!("--roughness {r} must be positive (it is 2^H)")))
        }
        (_, Some(r)) => Ok(r.log2()),
        (h, None) => Ok(h.unwrap_or(default)),
    }
}

/// Every flag another mode would use is refused where it would be ignored, with the mode
/// it belongs to in the message: dual's quadrilateral flags with the heightfield methods,
/// the grid's flags with dual, `--band` without `--stream`, `--range` without a 16-bit
/// output, colours without a coloured output.
fn refuse_other_modes_flags(args: &TerrainArgs) -> Result<()> {
    let dual = args.method == MethodArg::Dual;
    let method = args.method.to_possible_value().map_or_else(String::new, |v| v.get_name().to_string());
    let ext = match &args.format {
        Some(format) => format.to_ascii_lowercase(),
        None => args.output.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase(),
    };
    let mesh_output = matches!(ext.as_str(), "ply" | "obj");
    let coloured = mesh_output || args.preview.is_some();
    let heightfield = "--method classic and smooth";
    let rules: [(&str, bool, bool, &str); 27] = [
        ("--iterations", args.iterations.is_some(), !dual, heightfield),
        (
            "--max-height",
            args.max_height.is_some(),
            !dual && !args.stream && args.tile.is_none(),
            "whole grids of --method classic and smooth (the highest peak is measured on the whole grid: not with --stream or --tile)",
        ),
        (
            "--roughness",
            args.roughness.is_some(),
            args.method != MethodArg::Smooth,
            "--method classic and dual (smooth's points are uniform within their parents' range)",
        ),
        ("--x", args.x.is_some(), dual, "--method dual"),
        ("--y", args.y.is_some(), dual, "--method dual"),
        ("--levels", args.levels.is_some(), dual, "--method dual"),
        ("--deterministic", args.deterministic, dual, "--method dual"),
        ("--cross-product", args.cross_product, dual, "--method dual"),
        ("--no-mean-correction", args.no_mean_correction, dual, "--method dual"),
        ("--steps", args.steps.is_some(), dual, "--method dual"),
        ("--size", args.size.is_some(), !dual, heightfield),
        ("--distribution", args.distribution.is_some(), !dual, heightfield),
        ("--mean", args.mean.is_some(), !dual, heightfield),
        ("--variance", args.variance.is_some(), !dual, heightfield),
        ("--corners", args.corners.is_some(), !dual, heightfield),
        ("--width", args.width.is_some(), !dual, heightfield),
        ("--depth", args.depth.is_some(), !dual, heightfield),
        ("--sea-level", args.sea_level.is_some(), !dual, heightfield),
        ("--grid", args.grid.is_some(), !dual, heightfield),
        ("--stream", args.stream, !dual, heightfield),
        ("--tile", args.tile.is_some(), !dual, heightfield),
        ("--applet", args.applet, args.method == MethodArg::Classic, "--method classic (seed 001's applet)"),
        (
            "--hurst",
            args.hurst.is_some(),
            args.method != MethodArg::Smooth,
            "--method classic and dual (smooth's points are uniform within their parents' range)",
        ),
        ("--band", args.band.is_some(), args.stream, "--stream"),
        ("--tile-size", args.tile_size.is_some(), args.tile.is_some(), "--tile"),
        (
            "--range",
            args.range.is_some(),
            !dual && matches!(ext.as_str(), "png" | "raw16"),
            "16-bit outputs (.png, .raw16) of --method classic and smooth",
        ),
        (
            "--peak-height",
            args.peak_height.is_some(),
            !dual && coloured,
            "coloured outputs (a .ply or .obj mesh, or --preview) of --method classic and smooth",
        ),
    ];
    match rules.iter().find(|&&(_, given, applies, _)| given && !applies) {
        Some((flag, _, _, belongs)) => Err(Error::InvalidInput(format!(
            "{flag} applies only to {belongs}: with --method {method} and this output it would be ignored"
        ))),
        None => match (args.colors.is_some(), coloured) {
            (true, false) => Err(Error::InvalidInput(
                "--colors applies only to coloured outputs (a .ply or .obj mesh, or --preview)".into(),
            )),
            _ => Ok(()),
        },
    }
}
