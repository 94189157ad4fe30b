//! `asperity noise`: a noise image as 16-bit greyscale PNG or raw f32.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;

use crate::error::{Error, Result};
use crate::io::image::{value_range, write_f32, write_png16};
use crate::noise::{Fractal, GaborParams, NoiseField, NoiseKind, NoiseSpec, Profile};

/// The subcommand's flags (`NoiseArgs`).
#[derive(Debug, Args)]
pub struct NoiseArgs {
    /// Which noise.
    #[arg(long, value_enum, default_value_t = NoiseKind::Perlin)]
    kind: NoiseKind,
    /// Octaves of the fractal kinds, 1 to 32 [default: 6; wood 1, eq. 4.13's single noise,
    /// whose contour bands are the rings].
    #[arg(long)]
    octaves: Option<u32>,
    /// Frequency ratio between octaves (fractal kinds) [default: 2].
    #[arg(long, allow_negative_numbers = true)]
    lacunarity: Option<f64>,
    /// Amplitude ratio between octaves (fractal kinds) [default: 0.5].
    #[arg(long, allow_negative_numbers = true)]
    gain: Option<f64>,
    /// Offset d of the multifractal (eq. 4.12) [default: 1].
    #[arg(long, allow_hyphen_values = true)]
    offset: Option<f64>,
    /// Gabor kernel magnitude K: the noise's standard deviation (phasor: its amplitude)
    /// [default: 1].
    #[arg(long, allow_negative_numbers = true)]
    k: Option<f64>,
    /// Gabor bandwidth a [default: 0.05].
    #[arg(long, allow_negative_numbers = true)]
    a: Option<f64>,
    /// Gabor frequency F0, cycles per unit [default: 0.0625].
    #[arg(long, allow_negative_numbers = true)]
    f0: Option<f64>,
    /// Gabor orientation ω0, radians [default: π/4].
    #[arg(long, allow_hyphen_values = true)]
    omega: Option<f64>,
    /// Gabor impulses per kernel, at most 10000 [default: 64].
    #[arg(long, allow_negative_numbers = true)]
    impulses: Option<f64>,
    /// Gabor: a random orientation per impulse.
    #[arg(long)]
    isotropic: bool,
    /// Phasor noise's profile of the phase: sine, square or sawtooth [default: sine].
    #[arg(long, value_enum)]
    profile: Option<Profile>,
    /// Image width and height in pixels.
    #[arg(long, default_value_t = 512)]
    size: usize,
    /// World units per pixel [default: 1/32 for the Perlin kinds, 1/128 for wood, 1 for
    /// Gabor].
    #[arg(long, allow_negative_numbers = true)]
    scale: Option<f64>,
    /// Seed.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Arithmetic of Perlin noise and fBm: f64, or f32 — single precision with its own
    /// 32-bit lattice hash, a different noise (coordinates clamped to ±2^24), about twice as
    /// fast [default: f64].
    #[arg(long, value_enum)]
    precision: Option<crate::noise::Precision>,
    /// PNG grey range LO,HI [default: the image's own minimum and maximum; Gabor −3,3,
    /// three standard deviations at K = 1, and phasor −1,1, so K shows as contrast].
    #[arg(long, value_parser = super::parse::range, allow_hyphen_values = true)]
    range: Option<(f64, f64)>,
    /// Output: .png (16-bit grey) or .f32 (raw little-endian, row-major).
    #[arg(short, long)]
    output: PathBuf,
}

impl NoiseArgs {
    /// The noise the flags describe at `points` (the embeddings' batch evaluation): in
    /// the plane as `asperity noise` samples its pictures (x, y) when `planar`, else in
    /// space with the global frame.
    ///
    /// # Errors
    /// As [`NoiseArgs::field`].
    pub fn values_at(&self, points: &[glam::DVec3], planar: bool) -> Result<Vec<f64>> {
        let (field, _scale) = self.field()?;
        Ok(if planar {
            let plane: Vec<glam::DVec2> = points.iter().map(|p| p.truncate()).collect();
            field.sample2_batch(&plane)
        } else {
            let frames = vec![crate::noise::Frame { tangent: glam::DVec3::X, bitangent: glam::DVec3::Y }; points.len()];
            field.sample3_batch(points, &frames)
        })
    }

    /// The noise the flags describe, and the image's sample spacing (`--scale`).
    ///
    /// # Errors
    /// Flags of other kinds, or invalid parameters.
    pub fn field(&self) -> Result<(NoiseField, f64)> {
        refuse_other_kinds_flags(self)?;
        if let Some(octaves) = self.octaves.filter(|&o| o == 0 || o > crate::noise::MAX_OCTAVES) {
            return Err(Error::InvalidInput(format!("--octaves {octaves} must be 1 to {}", crate::noise::MAX_OCTAVES)));
        }
        if let Some(impulses) = self.impulses.filter(|&i| i > crate::noise::MAX_IMPULSES_PER_KERNEL) {
            return Err(Error::InvalidInput(format!(
                "--impulses {impulses} must be at most {}",
                crate::noise::MAX_IMPULSES_PER_KERNEL
            )));
        }
        let fractal = Fractal::default();
        let gabor = GaborParams::default();
        let spec = NoiseSpec {
            kind: self.kind,
            fractal: Fractal {
                octaves: self.octaves.unwrap_or(self.kind.default_octaves()),
                lacunarity: self.lacunarity.unwrap_or(fractal.lacunarity),
                gain: self.gain.unwrap_or(fractal.gain),
                offset: self.offset.unwrap_or(fractal.offset),
                ..fractal
            },
            gabor: GaborParams {
                k: self.k.unwrap_or(gabor.k),
                a: self.a.unwrap_or(gabor.a),
                f0: self.f0.unwrap_or(gabor.f0),
                omega0: self.omega.unwrap_or(gabor.omega0),
                impulses_per_kernel: self.impulses.unwrap_or(gabor.impulses_per_kernel),
                isotropic: self.isotropic,
            },
            profile: self.profile.unwrap_or_default(),
            seed: self.seed,
            precision: self.precision.unwrap_or_default(),
        };
        let scale = self.scale.unwrap_or(match self.kind {
            NoiseKind::Gabor | NoiseKind::Phasor => 1.0,
            NoiseKind::Wood => 1.0 / 128.0,
            _ => 1.0 / 32.0,
        });
        if !(scale.is_finite() && scale > 0.0) {
            return Err(Error::InvalidInput(format!("--scale {scale} must be positive")));
        }
        Ok((NoiseField::new(&spec)?, scale))
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
    refuse_other_kinds_flags(&args)?;
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
        let fixed = match args.kind {
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

/// Every flag of a kind other than `--kind`'s is a usage error naming the kinds it belongs
/// to: a flag that would be ignored is refused.
fn refuse_other_kinds_flags(args: &NoiseArgs) -> Result<()> {
    let fractal = matches!(
        args.kind,
        NoiseKind::Fbm | NoiseKind::Turbulence | NoiseKind::Marble | NoiseKind::Multifractal | NoiseKind::Wood
    );
    let spectral = matches!(args.kind, NoiseKind::Gabor | NoiseKind::Phasor);
    let flags: [(&str, bool, bool, &str); 12] = [
        (
            "--octaves",
            args.octaves.is_some(),
            fractal,
            "the fractal kinds (fbm, turbulence, marble, multifractal, wood)",
        ),
        (
            "--lacunarity",
            args.lacunarity.is_some(),
            fractal,
            "the fractal kinds (fbm, turbulence, marble, multifractal, wood)",
        ),
        ("--gain", args.gain.is_some(), fractal, "the fractal kinds (fbm, turbulence, marble, multifractal, wood)"),
        ("--offset", args.offset.is_some(), args.kind == NoiseKind::Multifractal, "--kind multifractal"),
        ("--k", args.k.is_some(), spectral, "--kind gabor and phasor"),
        ("--a", args.a.is_some(), spectral, "--kind gabor and phasor"),
        ("--f0", args.f0.is_some(), spectral, "--kind gabor and phasor"),
        ("--omega", args.omega.is_some(), spectral, "--kind gabor and phasor"),
        ("--impulses", args.impulses.is_some(), spectral, "--kind gabor and phasor"),
        ("--isotropic", args.isotropic, spectral, "--kind gabor and phasor"),
        ("--profile", args.profile.is_some(), args.kind == NoiseKind::Phasor, "--kind phasor"),
        (
            "--precision",
            args.precision.is_some(),
            matches!(args.kind, NoiseKind::Perlin | NoiseKind::Fbm),
            "--kind perlin and fbm",
        ),
    ];
    match flags.iter().find(|&&(_, given, applies, _)| given && !applies) {
        Some((flag, _, _, kinds)) => Err(Error::InvalidInput(format!(
            "{flag} applies only to {kinds}, not to --kind {}",
            format!("{:?}", args.kind).to_lowercase()
        ))),
        None => Ok(()),
    }
}
