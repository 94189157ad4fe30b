//! `asperity noise`: a noise image as 16-bit greyscale PNG or raw f32.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;

use crate::error::{Error, Result};
use crate::io::image::{value_range, write_f32, write_png16};
use crate::noise::{Fractal, GaborParams, NoiseField, NoiseKind, NoiseSpec};

#[derive(Debug, Args)]
pub struct NoiseArgs {
    /// Which noise.
    #[arg(long, value_enum, default_value_t = NoiseKind::Perlin)]
    kind: NoiseKind,
    /// Octaves of the fractal kinds.
    #[arg(long, default_value_t = 6)]
    octaves: u32,
    /// Frequency ratio between octaves.
    #[arg(long, default_value_t = 2.0)]
    lacunarity: f64,
    /// Amplitude ratio between octaves.
    #[arg(long, default_value_t = 0.5)]
    gain: f64,
    /// Offset of the multifractal.
    #[arg(long, default_value_t = 1.0)]
    offset: f64,
    /// Gabor kernel magnitude K.
    #[arg(long, default_value_t = 1.0)]
    k: f64,
    /// Gabor bandwidth a.
    #[arg(long, default_value_t = 0.05)]
    a: f64,
    /// Gabor frequency F0 (cycles per unit).
    #[arg(long, default_value_t = 0.0625)]
    f0: f64,
    /// Gabor orientation ω0 (radians).
    #[arg(long, default_value_t = std::f64::consts::FRAC_PI_4)]
    omega: f64,
    /// Gabor impulses per kernel.
    #[arg(long, default_value_t = 64.0)]
    impulses: f64,
    /// Gabor: a random orientation per impulse.
    #[arg(long)]
    isotropic: bool,
    /// Image width and height in pixels.
    #[arg(long, default_value_t = 512)]
    size: usize,
    /// World units per pixel (default 1/32 for the Perlin kinds, 1 for Gabor).
    #[arg(long)]
    scale: Option<f64>,
    /// Seed.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// PNG grey range LO,HI (default: the image's own minimum and maximum).
    #[arg(long, value_parser = super::parse::range, allow_hyphen_values = true)]
    range: Option<(f64, f64)>,
    /// Output: .png (16-bit grey) or .f32 (raw little-endian, row-major).
    #[arg(short, long)]
    output: PathBuf,
}

pub fn run(args: NoiseArgs, ctx: super::Context) -> Result<()> {
    let start = Instant::now();
    super::require_extension(&args.output, &["png", "f32"])?;
    let ext = args.output.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    if args.size == 0 || args.size > 65_536 {
        return Err(Error::InvalidInput(format!("--size {} must be between 1 and 65536", args.size)));
    }
    let spec = NoiseSpec {
        kind: args.kind,
        fractal: Fractal {
            octaves: args.octaves,
            lacunarity: args.lacunarity,
            gain: args.gain,
            offset: args.offset,
            ..Fractal::default()
        },
        gabor: GaborParams {
            k: args.k,
            a: args.a,
            f0: args.f0,
            omega0: args.omega,
            impulses_per_kernel: args.impulses,
            isotropic: args.isotropic,
        },
        seed: args.seed,
    };
    let scale = args.scale.unwrap_or(if args.kind == NoiseKind::Gabor { 1.0 } else { 1.0 / 32.0 });
    if !(scale.is_finite() && scale > 0.0) {
        return Err(Error::InvalidInput(format!("--scale {scale} must be positive")));
    }
    let field = NoiseField::new(&spec)?;
    let values = field.grid2(0.0, 0.0, scale, args.size, args.size);
    let (lo, hi) = value_range(&values).ok_or_else(|| Error::Internal("noise produced no finite value".into()))?;
    if ext.as_deref() == Some("png") {
        let range = args.range.unwrap_or(if hi > lo { (lo, hi) } else { (lo - 1.0, lo + 1.0) });
        write_png16(&args.output, &values, args.size, range)?;
    } else {
        write_f32(&args.output, &values)?;
    }
    ctx.report(
        || {
            format!(
                "noise: {:?} {}x{} (values {lo:.4}..{hi:.4}) => {} in {} ms",
                args.kind,
                args.size,
                args.size,
                args.output.display(),
                super::millis(start)
            )
        },
        || {
            serde_json::json!({
                "output": args.output, "kind": format!("{:?}", args.kind).to_lowercase(), "size": args.size,
                "seed": args.seed, "min": lo, "max": hi, "seconds": start.elapsed().as_secs_f64(),
            })
        },
    );
    Ok(())
}
