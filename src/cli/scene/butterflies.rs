//! `asperity butterflies --count N --steps S -o OUT.glb`: butterflies on pursuit curves,
//! as a glTF animation.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;

use crate::error::Result;
use crate::scene::butterflies::{ButterflyParams, fly};

/// The subcommand's flags.
#[derive(Debug, Args)]
pub struct ButterflyArgs {
    /// Butterflies.
    #[arg(long, default_value_t = ButterflyParams::default().count)]
    count: usize,
    /// Steps simulated (one keyframe each).
    #[arg(long, default_value_t = ButterflyParams::default().steps)]
    steps: usize,
    /// Seed.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// A butterfly's step length, in units of the unit cube they fly in.
    #[arg(long, default_value_t = ButterflyParams::default().speed)]
    speed: f64,
    /// The target's random-walk step length.
    #[arg(long, default_value_t = ButterflyParams::default().wander)]
    wander: f64,
    /// Distance at which a target counts as caught.
    #[arg(long, default_value_t = ButterflyParams::default().catch_radius)]
    catch_radius: f64,
    /// Wing turn per step, degrees.
    #[arg(long, default_value_t = ButterflyParams::default().flap_deg)]
    flap: f64,
    /// Wings turn between −limit and +limit, degrees.
    #[arg(long, default_value_t = ButterflyParams::default().flap_limit_deg)]
    flap_limit: f64,
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
    let params = ButterflyParams {
        seed: args.seed,
        count: args.count,
        steps: args.steps,
        speed: args.speed,
        wander: args.wander,
        catch_radius: args.catch_radius,
        flap_deg: args.flap,
        flap_limit_deg: args.flap_limit,
    };
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
                args.steps,
                catches,
                args.output.display(),
                super::super::millis(start)
            )
        },
        || {
            serde_json::json!({
                "output": args.output, "count": flights.len(), "steps": args.steps, "catches": catches,
                "colourings": colourings, "params": params, "seconds": start.elapsed().as_secs_f64(),
            })
        },
    );
    Ok(())
}
