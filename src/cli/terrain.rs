//! `asperity terrain`: classic diamond-square terrains as meshes or heightmaps, whole,
//! tiled or streamed.

use std::path::PathBuf;
use std::time::Instant;

use clap::{Args, ValueEnum};

use crate::error::{Error, Result};
use crate::io::{self, WriteOptions, write_atomically};
use crate::terrain::stream::{StreamFormat, write_terrain};
use crate::terrain::{Distribution, Method, Rect, TerrainParams, mesh, tile_rect};

/// Grid types.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum Grid {
    /// Two triangles per square cell.
    Square,
}

#[derive(Debug, Args)]
pub struct TerrainArgs {
    /// Generator (Janeczek's dual method of seed 000 is not built yet).
    #[arg(long, value_enum, default_value_t = Method::Classic)]
    method: Method,
    /// Points per side, 2^n + 1.
    #[arg(long, default_value_t = 257)]
    size: u64,
    /// Roughness H: the displacement scale falls by 2^-H per level.
    #[arg(long, default_value_t = 0.8)]
    hurst: f64,
    /// Displacement scale at the first level.
    #[arg(long, default_value_t = 1.0)]
    sigma: f64,
    /// Seed.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Displacement distribution.
    #[arg(long, value_enum, default_value_t = Distribution::Normal)]
    distribution: Distribution,
    /// Mean of the distribution.
    #[arg(long, default_value_t = 0.0)]
    mean: f64,
    /// Variance of the distribution.
    #[arg(long, default_value_t = 1.0)]
    variance: f64,
    /// Initial corner heights A,B,C,D.
    #[arg(long, value_parser = parse_corners)]
    corners: Option<[f64; 4]>,
    /// Seed 001's applet variant: constant scale, random sign.
    #[arg(long)]
    applet: bool,
    /// World width (x).
    #[arg(long, default_value_t = 10.0)]
    width: f64,
    /// World depth (y).
    #[arg(long, default_value_t = 10.0)]
    depth: f64,
    /// Raise everything below this height to it.
    #[arg(long)]
    sea_level: Option<f64>,
    /// Grid type.
    #[arg(long, value_enum, default_value_t = Grid::Square)]
    grid: Grid,
    /// Write rows as they are generated, in bounded memory (.ply, .png, .raw16, .f32).
    #[arg(long)]
    stream: bool,
    /// Rows per streamed band.
    #[arg(long, default_value_t = 64)]
    band: usize,
    /// Generate only tile I,J (needs --tile-size).
    #[arg(long, value_parser = parse_pair, requires = "tile_size")]
    tile: Option<(u64, u64)>,
    /// Points per tile side, 2^k + 1; tiles share their borders.
    #[arg(long)]
    tile_size: Option<u64>,
    /// Height range LO,HI mapped to 16 bits (.png, .raw16); default ± the height scale.
    #[arg(long, value_parser = parse_range, allow_hyphen_values = true)]
    range: Option<(f64, f64)>,
    /// Output: .ply / .obj mesh, .png 16-bit heightmap, .raw16, .f32.
    #[arg(short, long)]
    output: PathBuf,
    /// Output format when the file name has no telling extension (e.g. -o /dev/null):
    /// ply, obj, png, raw16 or f32.
    #[arg(long)]
    format: Option<String>,
}

fn parse_numbers<const N: usize>(s: &str) -> std::result::Result<[f64; N], String> {
    let values: Vec<f64> = s
        .split(',')
        .map(|t| t.trim().parse::<f64>().map_err(|_| format!("`{t}` is not a number")))
        .collect::<std::result::Result<_, _>>()?;
    values.try_into().map_err(|_| format!("expected {N} comma-separated numbers"))
}

fn parse_corners(s: &str) -> std::result::Result<[f64; 4], String> {
    parse_numbers::<4>(s)
}

fn parse_range(s: &str) -> std::result::Result<(f64, f64), String> {
    let [lo, hi] = parse_numbers::<2>(s)?;
    if hi > lo { Ok((lo, hi)) } else { Err("the range needs LO < HI".into()) }
}

fn parse_pair(s: &str) -> std::result::Result<(u64, u64), String> {
    let (a, b) = s.split_once(',').ok_or("expected I,J")?;
    let parse = |t: &str| t.trim().parse::<u64>().map_err(|_| format!("`{t}` is not a tile index"));
    Ok((parse(a)?, parse(b)?))
}

pub fn run(args: TerrainArgs) -> Result<()> {
    let start = Instant::now();
    let Grid::Square = args.grid;
    let params = TerrainParams {
        method: args.method,
        size: args.size,
        hurst: args.hurst,
        sigma: args.sigma,
        seed: args.seed,
        distribution: args.distribution,
        mean: args.mean,
        variance: args.variance,
        corners: args.corners.unwrap_or([0.0; 4]),
        applet: args.applet,
        width: args.width,
        depth: args.depth,
        sea_level: args.sea_level,
    };
    params.generator()?;
    let rect = match (args.tile, args.tile_size) {
        (Some((i, j)), Some(size)) => tile_rect(&params, i, j, size)?,
        _ => Rect { x0: 0, y0: 0, x1: args.size - 1, y1: args.size - 1 },
    };
    let ext = match &args.format {
        Some(format) => format.to_ascii_lowercase(),
        None => args.output.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase(),
    };
    let scale = params.height_scale();
    let range = args.range.unwrap_or((-scale, scale));
    let points = rect.width() as u64 * rect.height() as u64;
    if ext == "obj" || (ext == "ply" && !args.stream) {
        if args.stream && ext == "obj" {
            return Err(Error::InvalidInput("--stream writes .ply, .png, .raw16 or .f32, not .obj".into()));
        }
        let terrain = mesh(&params, rect)?;
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
        let band = if args.stream { args.band } else { rect.height() };
        let mut failure = None;
        write_atomically(&args.output, |w| {
            write_terrain(&params, rect, format, range, band, w).map_err(|e| {
                let message = e.to_string();
                failure = Some(e);
                std::io::Error::other(message)
            })
        })
        .map_err(|e| failure.take().unwrap_or(e))?;
    }
    let seconds = start.elapsed().as_secs_f64();
    println!(
        "terrain: {:?} {}x{} (H {}, seed {}) => {} in {} ms ({:.1} M points/s)",
        args.method,
        rect.width(),
        rect.height(),
        args.hurst,
        args.seed,
        args.output.display(),
        super::millis(start),
        points as f64 / seconds.max(1e-9) / 1e6
    );
    Ok(())
}
