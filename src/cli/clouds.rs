//! `asperity clouds`: a cloud image from a midpoint-displacement plasma (seed 001).

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;

use crate::error::Result;
use crate::io::image::write_png_rgb8;
use crate::request::Spelling;
use crate::terrain::CloudRequest;

/// The subcommand's flags (`CloudArgs`): the library's request and the output.
#[derive(Debug, Args)]
pub struct CloudArgs {
    #[command(flatten)]
    clouds: CloudRequest,
    /// Output .png (8-bit RGB).
    #[arg(short, long)]
    output: PathBuf,
}

/// Runs the subcommand.
pub fn run(args: CloudArgs, ctx: super::Context) -> Result<()> {
    let start = Instant::now();
    super::require_extension(&args.output, &["png"])?;
    let (rgb, cover) = args.clouds.picture(Spelling::Flag)?;
    write_png_rgb8(&args.output, &rgb, args.clouds.size as usize)?;
    ctx.report(
        || {
            format!(
                "clouds: {0}x{0} (H {1}, threshold {2}) => {3:.0}% cover => {4} in {5} ms",
                args.clouds.size,
                args.clouds.hurst,
                args.clouds.threshold,
                cover * 100.0,
                args.output.display(),
                super::millis(start)
            )
        },
        || {
            serde_json::json!({
                "output": args.output, "size": args.clouds.size, "hurst": args.clouds.hurst,
                "seed": args.clouds.seed, "threshold": args.clouds.threshold, "cover": cover, "seconds": start.elapsed().as_secs_f64(),
            })
        },
    );
    Ok(())
}
