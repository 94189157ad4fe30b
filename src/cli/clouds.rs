//! `asperity clouds`: a cloud image from a midpoint-displacement plasma (seed 001).

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;

use crate::error::Result;
use crate::io::image::write_png_rgb8;
use crate::terrain::{CloudParams, TerrainParams, clouds};

/// The subcommand's flags (`CloudArgs`).
#[derive(Debug, Args)]
pub struct CloudArgs {
    /// Pixels per side, 2^n + 1.
    #[arg(long, default_value_t = 513)]
    size: u64,
    /// Roughness H of the plasma.
    #[arg(long, default_value_t = 0.7, allow_negative_numbers = true)]
    hurst: f64,
    /// Seed.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Plasma values below this (0 to 1) are clear sky.
    #[arg(long, default_value_t = 0.45, allow_negative_numbers = true)]
    threshold: f64,
    /// Sky colour R,G,B.
    #[arg(long, value_parser = super::parse::rgb, default_value = "70,130,210")]
    sky: [u8; 3],
    /// Cloud colour R,G,B.
    #[arg(long, value_parser = super::parse::rgb, default_value = "255,255,255")]
    cloud: [u8; 3],
    /// Output .png (8-bit RGB).
    #[arg(short, long)]
    output: PathBuf,
}

impl CloudArgs {
    /// The library parameters the flags give.
    pub fn params(&self) -> CloudParams {
        CloudParams {
            plasma: TerrainParams { size: self.size, hurst: self.hurst, seed: self.seed, ..TerrainParams::default() },
            threshold: self.threshold,
            sky: self.sky,
            cloud: self.cloud,
        }
    }
}

/// Runs the subcommand.
pub fn run(args: CloudArgs, ctx: super::Context) -> Result<()> {
    let start = Instant::now();
    super::require_extension(&args.output, &["png"])?;
    let params = args.params();
    // The plasma's heights (f64, twice while smoothing) and the RGB picture, before allocating.
    let points = args.size.saturating_mul(args.size);
    crate::memory::ensure_available(
        points.saturating_mul(2 * 8 + 3),
        &format!("a {0}x{0} cloud picture", args.size),
        "ask for a smaller --size",
    )?;
    let (rgb, cover) = clouds(&params)?;
    write_png_rgb8(&args.output, &rgb, args.size as usize)?;
    ctx.report(
        || {
            format!(
                "clouds: {0}x{0} (H {1}, threshold {2}) => {3:.0}% cover => {4} in {5} ms",
                args.size,
                args.hurst,
                args.threshold,
                cover * 100.0,
                args.output.display(),
                super::millis(start)
            )
        },
        || {
            serde_json::json!({
                "output": args.output, "size": args.size, "hurst": args.hurst, "seed": args.seed,
                "threshold": args.threshold, "cover": cover, "seconds": start.elapsed().as_secs_f64(),
            })
        },
    );
    Ok(())
}
