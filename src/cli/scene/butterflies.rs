//! `asperity butterflies --count N --steps S -o OUT.glb`: butterflies on pursuit curves,
//! as a glTF animation.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;

use crate::error::Result;
use crate::scene::butterflies::{ButterflyParams, fly};

/// The subcommand's flags: the flight's parameters and the animation.
#[derive(Debug, Args)]
pub struct ButterflyArgs {
    #[command(flatten)]
    params: ButterflyParams,
    /// Steps per second of the animation.
    #[arg(long, default_value_t = 48.0)]
    fps: f64,
    /// Output .glb (an animation; the unit cube they fly in is 10 m wide).
    #[arg(short, long)]
    output: PathBuf,
}

/// Runs the subcommand.
pub fn run(args: ButterflyArgs, ctx: super::super::Context) -> Result<()> {
    let start = Instant::now();
    super::super::require_extension(&args.output, &["glb"])?;
    let fps = super::checked_fps(Some(args.fps))?;
    let params = args.params;
    let flights = fly(&params)?;
    let scene = crate::scene::compose::butterfly_scene(&flights, fps);
    crate::io::glb_scene::write_scene_glb(&scene, &args.output)?;
    let catches: usize = flights.iter().map(|f| f.catches).sum();
    let colourings: Vec<_> = flights.iter().map(|f| f.colouring).collect();
    ctx.report(
        || {
            format!(
                "butterflies: {} for {} steps, {} targets caught => {} in {} ms",
                flights.len(),
                params.steps,
                catches,
                args.output.display(),
                super::super::millis(start)
            )
        },
        || {
            serde_json::json!({
                "output": args.output, "count": flights.len(), "steps": params.steps, "catches": catches,
                "colourings": colourings, "params": params, "seconds": start.elapsed().as_secs_f64(),
            })
        },
    );
    Ok(())
}
