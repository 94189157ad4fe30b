//! `asperity noise`: a noise image as 16-bit greyscale PNG or raw f32.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;

use crate::error::{Error, Result};
use crate::io::image::{value_range, write_f32, write_png16};
use crate::noise::{NoiseField, NoiseKind, NoiseRequest};
use crate::request::Spelling;

/// The subcommand's flags (`NoiseArgs`): the noise (the library's request) and its picture.
#[derive(Debug, Args)]
pub struct NoiseArgs {
    /// The noise.
    #[command(flatten)]
    pub noise: NoiseRequest,
    /// Image width and height in pixels.
    #[arg(long, default_value_t = 512)]
    size: usize,
    /// World units per pixel [default: 1/32 for the Perlin kinds, 1/128 for wood, 1 for
    /// Gabor].
    #[arg(long, allow_negative_numbers = true)]
    scale: Option<f64>,
    /// PNG grey range LO,HI [default: the image's own minimum and maximum; Gabor −3,3,
    /// three standard deviations at K = 1, and phasor −1,1, so K shows as contrast].
    #[arg(long, value_parser = crate::request::parse::range, allow_hyphen_values = true)]
    range: Option<(f64, f64)>,
    /// Output: .png (16-bit grey) or .f32 (raw little-endian, row-major).
    #[arg(short, long)]
    output: PathBuf,
}

impl NoiseArgs {
    /// The noise the flags describe, and the image's sample spacing (`--scale`).
    ///
    /// # Errors
    /// Flags of other kinds, or invalid parameters.
    fn field(&self) -> Result<(NoiseField, f64)> {
        let field = self.noise.field(Spelling::Flag)?;
        let scale = self.scale.unwrap_or(match self.noise.kind {
            NoiseKind::Gabor | NoiseKind::Phasor => 1.0,
            NoiseKind::Wood => 1.0 / 128.0,
            _ => 1.0 / 32.0,
        });
        if !(scale.is_finite() && scale > 0.0) {
            return Err(Error::InvalidInput(format!("--scale {scale} must be positive")));
        }
        Ok((field, scale))
    }
}

/// Runs the subcommand.
pub fn run(args: NoiseArgs, ctx: super::Context) -> Result<()> {
    let start = Instant::now();
    super::require_extension(&args.output, &["png", "f32"])?;
    let ext = args.output.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    if args.size == 0 || args.size > 65_536 {
        return Err(Error::InvalidInput(format!("--size {} must be between 1 and 65536", args.size)));
    }
    args.noise.check(Spelling::Flag)?;
    if args.range.is_some() && ext.as_deref() != Some("png") {
        return Err(Error::InvalidInput(format!(
            "{}: --range maps values to a PNG's 16-bit grey; raw .f32 keeps the values themselves",
            args.output.display()
        )));
    }
    let (field, scale) = args.field()?;
    // The values (f64) and the encoded picture (16-bit grey or f32), before allocating.
    let points = (args.size as u64).pow(2);
    crate::memory::ensure_available(
        points * (8 + 4),
        &format!("a {0}x{0} noise picture", args.size),
        "ask for a smaller --size",
    )?;
    let values = field.grid2(0.0, 0.0, scale, args.size, args.size);
    let (lo, hi) = value_range(&values).ok_or_else(|| Error::Internal("noise produced no finite value".into()))?;
    if ext.as_deref() == Some("png") {
        let own = if hi > lo { (lo, hi) } else { (lo - 1.0, lo + 1.0) };
        // Gabor's and phasor's magnitude K would cancel in the image's own range.
        let fixed = match args.noise.kind {
            NoiseKind::Gabor => Some((-3.0, 3.0)),
            NoiseKind::Phasor => Some((-1.0, 1.0)),
            _ => None,
        };
        let range = args.range.or(fixed).unwrap_or(own);
        write_png16(&args.output, &values, args.size, range)?;
    } else {
        write_f32(&args.output, &values)?;
    }
    ctx.report(
        || {
            format!(
                "noise: {:?} {}x{} (values {lo:.4}..{hi:.4}) => {} in {} ms",
                args.noise.kind,
                args.size,
                args.size,
                args.output.display(),
                super::millis(start)
            )
        },
        || {
            serde_json::json!({
                "output": args.output, "kind": format!("{:?}", args.noise.kind).to_lowercase(), "size": args.size,
                "seed": args.noise.seed, "min": lo, "max": hi, "seconds": start.elapsed().as_secs_f64(),
            })
        },
    );
    Ok(())
}
