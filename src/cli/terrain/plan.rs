//! `asperity terrain plan` and `asperity terrain --plan DIR`: a terrain cut into tiles that
//! existing job runners run — Kubernetes Indexed Jobs, Slurm job arrays, GNU parallel,
//! `xargs -P` — one process per tile, each given its index. Tiles are computed from the
//! same parameters on their own rectangle (erosion with its halo), so together they equal
//! the whole grid bit for bit. A tile is complete when its sidecar exists and names the
//! plan's fingerprint and the tile's size in bytes: a rerun of a failed array skips the
//! complete ones.

use std::path::{Path, PathBuf};

use clap::Args;
use serde::{Deserialize, Serialize};

use super::{Job, Setup};
use crate::error::{Error, Result};
use crate::io::write_atomically;
use crate::terrain::mosaic::{MosaicTile, raw_descriptor, source_of, vrt};
use crate::terrain::sidecar::{Quantisation, Sidecar, WorldPlacement};
use crate::terrain::stream::{LAYER_RANGE, StreamFormat};
use crate::terrain::{TerrainMethod, TerrainRequest, tiles_per_side};

#[derive(Debug, Args)]
pub(crate) struct PlanArgs {
    #[command(flatten)]
    generation: TerrainRequest,
    /// Points per tile side, 2^k + 1 (with --preset, a size the engine imports); tiles
    /// share their borders.
    #[arg(long)]
    tile_size: u64,
    /// The tiles' format: png, raw16, f32, exr or tif [default: png; with --preset, the
    /// engine's].
    #[arg(long, conflicts_with = "preset")]
    format: Option<String>,
    /// The plan's folder: plan.json, mosaic.vrt and tiles/.
    #[arg(short, long, value_name = "DIR")]
    output: PathBuf,
}

/// The manifest: everything a tile's process needs, and what the mosaic is made of.
#[derive(Debug, Serialize, Deserialize)]
struct Plan {
    /// The manifest's layout version.
    version: u32,
    /// A hash of what the tiles are made from (parameters, sizes, format); tiles' sidecars
    /// record it.
    fingerprint: String,
    /// Points per side of the whole terrain.
    size: u64,
    /// Points per side of a tile.
    tile_size: u64,
    /// Tiles per side.
    tiles_per_side: u64,
    /// The tiles' file format (extension).
    format: String,
    /// The GDAL mosaic, relative to the plan's folder.
    mosaic: String,
    /// Each erosion layer's mosaic (`mosaic.LAYER.vrt`), by layer name.
    #[serde(default, skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    layer_mosaics: std::collections::BTreeMap<String, String>,
    /// Every tile, by index.
    tiles: Vec<PlannedTile>,
    /// The generation flags every tile is made with.
    parameters: TerrainRequest,
}

/// One tile of the plan.
#[derive(Debug, Serialize, Deserialize)]
struct PlannedTile {
    /// Its index: what --tile-index, $JOB_COMPLETION_INDEX or $SLURM_ARRAY_TASK_ID names.
    index: u64,
    /// Its column of tiles.
    x: u64,
    /// Its row of tiles.
    y: u64,
    /// Its rectangle on the grid, inclusive: x0, y0, x1, y1.
    rect: [u64; 4],
    /// Its file, relative to the plan's folder.
    output: String,
    /// The command that makes it.
    command: Vec<String>,
}

const PLAN_VERSION: u32 = 1;

/// FNV-1a, 64 bits: a fingerprint of text that does not change between builds.
fn fingerprint(text: &str) -> String {
    let hash = text.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3));
    format!("{hash:016x}")
}

/// The fingerprint of what a plan's tiles are made from.
fn plan_fingerprint(parameters: &TerrainRequest, size: u64, tile_size: u64, format: &str) -> Result<String> {
    let text =
        serde_json::to_string(&(parameters, size, tile_size, format)).map_err(|e| Error::Internal(e.to_string()))?;
    Ok(fingerprint(&format!("asperity terrain plan v{PLAN_VERSION} {text}")))
}

/// Tile (x, y)'s file in the plan's folder: `tiles/terrain_x{x}_y{y}.{format}`, the
/// presets' tile naming.
fn tile_output(x: u64, y: u64, format: &str) -> String {
    crate::terrain::presets::tile_path(Path::new(&format!("tiles/terrain.{format}")), x, y)
        .to_string_lossy()
        .into_owned()
}

/// For headerless tiles (RAW16, F32): each tile's descriptor beside it in `dir`, which
/// the mosaic names ([`source_of`]).
fn write_raw_descriptors(dir: &Path, tiles: &[MosaicTile], format: StreamFormat) -> Result<()> {
    if !matches!(format, StreamFormat::Raw16 | StreamFormat::F32) {
        return Ok(());
    }
    for t in tiles {
        let name = Path::new(&t.file).file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        write_text(&dir.join(source_of(&t.file, format)), &raw_descriptor(&name, t.columns, t.rows, format))?;
    }
    Ok(())
}

/// A tile's file of `layer`, relative to the plan's folder (beside the tile, as
/// `terrain --layers` names it).
fn layer_file(tile_file: &str, layer: crate::terrain::ErosionLayer) -> String {
    super::layer_path(Path::new(tile_file), layer).to_string_lossy().into_owned()
}

/// The job of tile (i, j) of a plan in `dir`.
fn tile_job<'a>(
    generation: &'a TerrainRequest,
    tile: (u64, u64),
    tile_size: u64,
    output: PathBuf,
    format: &str,
) -> Job<'a> {
    Job { sidecar: true, ..Job::named(generation, output, format, Some(tile), Some(tile_size)) }
}

/// `asperity terrain plan`: checks the parameters as a tile's process will, then writes
/// the manifest, the mosaic and the headerless tiles' descriptors.
pub(super) fn run(args: PlanArgs, ctx: crate::cli::Context) -> Result<()> {
    let start = std::time::Instant::now();
    let g = &args.generation;
    if g.method == TerrainMethod::Dual {
        return Err(Error::InvalidInput(
            "terrain plan tiles heightfields: --method classic or smooth (a dual surface is one quadrilateral)".into(),
        ));
    }
    let format = match (&args.format, g.preset) {
        (Some(f), _) => f.to_ascii_lowercase(),
        (None, Some(preset)) => preset.extensions()[0].to_string(),
        (None, None) => "png".to_string(),
    };
    let stream_format = StreamFormat::from_extension(&format).filter(|f| f.is_heightmap()).ok_or_else(|| {
        Error::InvalidInput(format!("--format {format}: a plan's tiles are png, raw16, f32, exr or tif"))
    })?;
    // Tile 0's setup checks every parameter (sizes, preset, ranges) as each tile's will.
    let probe = tile_job(g, (0, 0), args.tile_size, args.output.join("tiles").join(format!("probe.{format}")), &format);
    let setup = Setup::of(&probe)?;
    let tiles = tiles_per_side(setup.extent, args.tile_size)?;
    let fingerprint = plan_fingerprint(g, setup.extent, args.tile_size, &format)?;
    let dir_text = args.output.to_string_lossy().into_owned();
    let planned: Vec<PlannedTile> = (0..tiles * tiles)
        .map(|index| {
            let (x, y) = (index % tiles, index / tiles);
            let span = args.tile_size - 1;
            PlannedTile {
                index,
                x,
                y,
                rect: [x * span, y * span, (x + 1) * span, (y + 1) * span],
                output: tile_output(x, y, &format),
                command: ["asperity", "terrain", "--plan", &dir_text, "--tile-index", &index.to_string()]
                    .map(String::from)
                    .to_vec(),
            }
        })
        .collect();
    crate::io::create_output_dir(&args.output.join("tiles"))?;
    let world = WorldPlacement::of(&setup.params, 0, 0);
    let mosaic_tiles: Vec<MosaicTile> = planned
        .iter()
        .map(|t| MosaicTile {
            file: t.output.clone(),
            x: t.rect[0],
            y: t.rect[1],
            columns: args.tile_size as usize,
            rows: args.tile_size as usize,
        })
        .collect();
    write_raw_descriptors(&args.output, &mosaic_tiles, stream_format)?;
    let quantisation = stream_format.is_16_bit().then(|| Quantisation::of(setup.range));
    let mosaic = vrt(setup.extent, setup.extent, stream_format, quantisation, world, &mosaic_tiles);
    write_text(&args.output.join("mosaic.vrt"), &mosaic)?;
    // Each erosion layer's tiles lie beside the heights' and make a mosaic of their own.
    let mut layer_mosaics = std::collections::BTreeMap::new();
    for &layer in &setup.layers {
        let tiles: Vec<MosaicTile> =
            mosaic_tiles.iter().map(|t| MosaicTile { file: layer_file(&t.file, layer), ..t.clone() }).collect();
        write_raw_descriptors(&args.output, &tiles, stream_format)?;
        let quantisation = stream_format.is_16_bit().then(|| Quantisation::of(LAYER_RANGE));
        let name = format!("mosaic.{}.vrt", layer.name());
        write_text(
            &args.output.join(&name),
            &vrt(setup.extent, setup.extent, stream_format, quantisation, world, &tiles),
        )?;
        layer_mosaics.insert(layer.name().to_string(), name);
    }
    let count = planned.len();
    let plan = Plan {
        version: PLAN_VERSION,
        fingerprint,
        size: setup.extent,
        tile_size: args.tile_size,
        tiles_per_side: tiles,
        format: format.clone(),
        mosaic: "mosaic.vrt".into(),
        layer_mosaics,
        tiles: planned,
        parameters: args.generation.clone(),
    };
    let text = serde_json::to_string_pretty(&plan).map_err(|e| Error::Internal(e.to_string()))?;
    let manifest = args.output.join("plan.json");
    write_text(&manifest, &text)?;
    ctx.report(
        || {
            format!(
                "terrain plan: {count} tiles of {0}x{0} ({tiles}x{tiles}, {format}) for a {1}x{1} terrain => {2}, {3}{7} in {4} ms; run each with: asperity terrain --plan {5} --tile-index K (K = 0..{6})",
                args.tile_size,
                setup.extent,
                manifest.display(),
                args.output.join("mosaic.vrt").display(),
                crate::cli::millis(start),
                args.output.display(),
                count - 1,
                plan.layer_mosaics.values().map(|m| format!(", {}", args.output.join(m).display())).collect::<String>()
            )
        },
        || {
            serde_json::json!({
                "plan": manifest, "mosaic": args.output.join("mosaic.vrt"), "tiles": count,
                "layer_mosaics": plan.layer_mosaics,
                "tiles_per_side": tiles, "tile_size": args.tile_size, "size": setup.extent, "format": format,
                "fingerprint": plan.fingerprint,
            })
        },
    );
    Ok(())
}

fn write_text(path: &Path, text: &str) -> Result<()> {
    write_atomically(path, |w| w.write_all(text.as_bytes()))
}

/// The tile index: `--tile-index`, else $JOB_COMPLETION_INDEX, else $SLURM_ARRAY_TASK_ID.
fn tile_index(flag: Option<u64>) -> Result<u64> {
    if let Some(k) = flag {
        return Ok(k);
    }
    for variable in ["JOB_COMPLETION_INDEX", "SLURM_ARRAY_TASK_ID"] {
        if let Ok(value) = std::env::var(variable) {
            return value.trim().parse().map_err(|_| {
                Error::InvalidInput(format!("${variable} is {value:?}: a tile index must be a whole number from 0"))
            });
        }
    }
    Err(Error::InvalidInput(
        "--plan needs a tile index: --tile-index K, $JOB_COMPLETION_INDEX (Kubernetes) or $SLURM_ARRAY_TASK_ID (Slurm)"
            .into(),
    ))
}

/// Whether the tile at `output` is complete for the plan `fingerprint`: its sidecar names
/// the plan and the tile's size in bytes.
fn complete(output: &Path, fingerprint: &str) -> bool {
    let Ok(text) = std::fs::read_to_string(Sidecar::path_for(output)) else { return false };
    let Ok(sidecar) = serde_json::from_str::<Sidecar>(&text) else { return false };
    let size = std::fs::metadata(output).map(|m| m.len()).ok();
    sidecar.plan.as_deref() == Some(fingerprint) && size == Some(sidecar.bytes)
}

/// `asperity terrain --plan DIR`: makes one tile of the plan, unless it is complete.
pub(super) fn run_tile(dir: &Path, flag: Option<u64>, ctx: crate::cli::Context) -> Result<()> {
    let manifest = dir.join("plan.json");
    let text = std::fs::read_to_string(&manifest).map_err(|e| Error::io(&manifest, e))?;
    let plan: Plan = serde_json::from_str(&text)
        .map_err(|e| Error::InvalidInput(format!("{}: not an asperity terrain plan: {e}", manifest.display())))?;
    if plan.version != PLAN_VERSION {
        return Err(Error::InvalidInput(format!(
            "{}: plan version {} (this asperity reads version {PLAN_VERSION}): make the plan again",
            manifest.display(),
            plan.version
        )));
    }
    let index = tile_index(flag)?;
    let Some(tile) = plan.tiles.iter().find(|t| t.index == index) else {
        return Err(Error::InvalidInput(format!(
            "tile index {index} is outside the plan's {} tiles (0..{})",
            plan.tiles.len(),
            plan.tiles.len().saturating_sub(1)
        )));
    };
    // The tile's file is the plan's own name for it: an edited manifest cannot send a tile
    // outside the plan's folder.
    if tile.output != tile_output(tile.x, tile.y, &plan.format) {
        return Err(Error::InvalidInput(format!(
            "{}: tile {index}'s output {:?} is not the plan's name for tile {},{} ({:?}): make the plan again",
            manifest.display(),
            tile.output,
            tile.x,
            tile.y,
            tile_output(tile.x, tile.y, &plan.format)
        )));
    }
    // Recomputed, not read: an edited manifest makes new tiles, never skips stale ones.
    let fingerprint = plan_fingerprint(&plan.parameters, plan.size, plan.tile_size, &plan.format)?;
    let output = dir.join(&tile.output);
    if complete(&output, &fingerprint) {
        ctx.report(
            || format!("terrain: tile {index} ({},{}) is already complete: {}", tile.x, tile.y, output.display()),
            || serde_json::json!({ "tile": index, "output": output, "skipped": true }),
        );
        return Ok(());
    }
    if let Some(parent) = output.parent() {
        crate::io::create_output_dir(parent)?;
    }
    let mut job = tile_job(&plan.parameters, (tile.x, tile.y), plan.tile_size, output, &plan.format);
    job.plan = Some(fingerprint);
    super::run_job(&job, ctx)
}

#[cfg(test)]
mod tests {
    use clap::Args as _;

    /// `--plan DIR` takes every parameter from the plan: each other terrain flag is refused
    /// beside it (so one added to `terrain` must be added to --plan's conflicts).
    #[test]
    fn every_other_terrain_flag_conflicts_with_plan() {
        let mut command = super::super::TerrainArgs::augment_args(clap::Command::new("terrain"));
        command.build();
        let plan = command.get_arguments().find(|a| a.get_id() == "plan").expect("--plan").clone();
        let conflicts: Vec<String> =
            command.get_arg_conflicts_with(&plan).iter().map(|a| a.get_id().to_string()).collect();
        for arg in command.get_arguments().filter(|a| !["plan", "tile_index", "help"].contains(&a.get_id().as_str())) {
            assert!(conflicts.contains(&arg.get_id().to_string()), "--{} does not conflict with --plan", arg.get_id());
        }
    }
}
