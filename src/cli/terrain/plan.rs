//! `asperity terrain plan` and `asperity terrain --plan DIR`: a terrain cut into tiles that
//! existing job runners run, one process per tile ([`crate::terrain::plan`]: the manifest,
//! mosaics and completeness). This file parses, finds the tile index (the flag, or the job
//! runner's variable) and runs the tile's job.

use std::path::{Path, PathBuf};

use clap::Args;

use super::{Job, Setup};
use crate::error::{Error, Result};
use crate::terrain::plan::{Plan, tile_complete};
use crate::terrain::stream::StreamFormat;
use crate::terrain::{TerrainMethod, TerrainRequest};

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
    StreamFormat::from_extension(&format).filter(|f| f.is_heightmap()).ok_or_else(|| {
        Error::InvalidInput(format!("--format {format}: a plan's tiles are png, raw16, f32, exr or tif"))
    })?;
    // Tile 0's setup checks every parameter (sizes, preset, ranges) as each tile's will.
    let probe = tile_job(g, (0, 0), args.tile_size, args.output.join("tiles").join(format!("probe.{format}")), &format);
    let setup = Setup::of(&probe)?.terrain;
    let plan = Plan::new(g, &setup, args.tile_size, &format, &args.output)?;
    let manifest = plan.write(&args.output, &setup)?;
    let (count, tiles) = (plan.tiles.len(), plan.tiles_per_side);
    ctx.report(
        || {
            format!(
                "terrain plan: {count} tiles of {0}x{0} ({tiles}x{tiles}, {format}) for a {1}x{1} terrain => {2}, {3}{7} in {4} ms; run each with: asperity terrain --plan {5} --tile-index K (K = 0..{6})",
                args.tile_size,
                setup.extent,
                manifest.display(),
                args.output.join(&plan.mosaic).display(),
                crate::cli::millis(start),
                args.output.display(),
                count - 1,
                plan.layer_mosaics.values().map(|m| format!(", {}", args.output.join(m).display())).collect::<String>()
            )
        },
        || {
            serde_json::json!({
                "plan": manifest, "mosaic": args.output.join(&plan.mosaic), "tiles": count,
                "layer_mosaics": plan.layer_mosaics,
                "tiles_per_side": tiles, "tile_size": args.tile_size, "size": setup.extent, "format": format,
                "fingerprint": plan.fingerprint,
            })
        },
    );
    Ok(())
}

/// `asperity terrain --plan DIR`: makes one tile of the plan, unless it is complete.
pub(super) fn run_tile(dir: &Path, flag: Option<u64>, ctx: crate::cli::Context) -> Result<()> {
    let plan = Plan::read(dir)?;
    let index = crate::cli::job_index(flag, "tile")?;
    let (tile, fingerprint) = plan.tile(index, dir)?;
    let output = dir.join(&tile.output);
    if tile_complete(&output, &fingerprint) {
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
