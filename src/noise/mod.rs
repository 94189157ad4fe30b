//! Procedural noise (thesis §3.3 and §4.7.3): Perlin's improved noise, its fractal sums
//! (fBm, turbulence, marble, multifractal, wood) and Gabor noise. Every function is a pure
//! function of (seed, coordinates) through counter-based hashing, so batch evaluation —
//! serial or parallel, at any thread count — equals scalar evaluation bit for bit.

mod fractal;
mod gabor;
pub mod hash;
mod perlin;
#[cfg(target_arch = "x86_64")]
mod perlin_avx2;
#[cfg(target_arch = "x86_64")]
mod perlin_avx512;
mod phasor;
mod request;
mod single;
#[cfg(target_arch = "x86_64")]
mod single_x86;

use glam::{DVec2, DVec3};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

pub use fractal::{Basis, Fractal, FractalKind, ScaledPerlin, WOOD_RING_FALL, wood_ring, wood_ring_falling_over};
pub use gabor::{Frame, Gabor, GaborParams, MAX_IMPULSES_PER_KERNEL};
pub use perlin::{PERLIN_PEAK, Perlin, plane_point};
pub use phasor::{Phasor, Profile};
pub use request::NoiseRequest;
pub use single::SinglePerlin;

use crate::error::Result;

/// Every kind of noise the command line and recipes can ask for.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum NoiseKind {
    /// Perlin improved noise, one octave.
    #[default]
    Perlin,
    /// Fractional Brownian motion (eq. 3.15).
    Fbm,
    /// Turbulence (eq. 4.10).
    Turbulence,
    /// Marble (eq. 4.11).
    Marble,
    /// Multifractal (eq. 4.12).
    Multifractal,
    /// Wood (eq. 4.13).
    Wood,
    /// Gabor noise (eq. 3.20–3.21).
    Gabor,
    /// Phasor noise (Tricard et al. 2019): Gabor's phase through a profile, constant
    /// contrast.
    Phasor,
}

impl NoiseKind {
    /// Whether the kind is made of Gabor kernels (Gabor and phasor noise), whose spectrum
    /// F0, ω0, a and the impulse density control.
    pub fn is_spectral(self) -> bool {
        matches!(self, NoiseKind::Gabor | NoiseKind::Phasor)
    }

    /// The octaves a kind shows its pattern with: wood is eq. 4.13's single noise f, whose
    /// contour bands are its rings (more octaves break them into static); the other
    /// fractal kinds take [`Fractal::default`]'s six.
    pub fn default_octaves(self) -> u32 {
        match self {
            NoiseKind::Wood => 1,
            _ => Fractal::default().octaves,
        }
    }
}

/// The arithmetic of Perlin noise and its fBm (#42).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum Precision {
    /// Double precision: the default, and the only one of the other kinds.
    #[default]
    F64,
    /// Single precision with a 32-bit lattice hash: a different noise (other values,
    /// coordinates clamped to ±2²⁴), about twice as fast on AVX-512.
    F32,
}

/// A fully specified noise: kind, parameters, seed.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct NoiseSpec {
    /// Which noise.
    pub kind: NoiseKind,
    /// Octave parameters for the fractal kinds (its `kind` is set from `kind`).
    pub fractal: Fractal,
    /// Gabor parameters (also phasor noise's).
    pub gabor: GaborParams,
    /// Phasor noise's profile.
    pub profile: Profile,
    /// Seed.
    pub seed: u64,
    /// The arithmetic: [`Precision::F32`] only for Perlin noise and fBm.
    #[serde(default)]
    pub precision: Precision,
}

impl Default for NoiseSpec {
    fn default() -> Self {
        NoiseSpec {
            kind: NoiseKind::Perlin,
            fractal: Fractal::default(),
            gabor: GaborParams::default(),
            profile: Profile::default(),
            seed: 0,
            precision: Precision::F64,
        }
    }
}

/// A ready-to-evaluate noise built from a [`NoiseSpec`].
#[derive(Debug, Clone)]
pub enum NoiseField {
    /// Perlin noise, possibly summed as a fractal.
    Perlin {
        /// The basis.
        basis: Perlin,
        /// `None` for plain Perlin noise.
        fractal: Option<Fractal>,
    },
    /// Gabor noise.
    Gabor(Gabor),
    /// Phasor noise.
    Phasor(Phasor),
    /// Single-precision Perlin noise or fBm, with the fractal it sums (`None`: one octave).
    Single(SinglePerlin, Option<Fractal>),
}

/// The most octaves a fractal noise may sum: at the default lacunarity of 2 the 32nd
/// octave's frequency is 2³¹ times the first's, past which a coordinate's f64 mantissa no
/// longer resolves a lattice cell (#36: `--octaves 1000000000` ran for good).
pub const MAX_OCTAVES: u32 = 32;

impl NoiseField {
    /// Builds the noise.
    ///
    /// # Errors
    /// [`crate::Error::InvalidInput`] for invalid Gabor parameters.
    pub fn new(spec: &NoiseSpec) -> Result<Self> {
        if spec.precision == Precision::F32 && !matches!(spec.kind, NoiseKind::Perlin | NoiseKind::Fbm) {
            return Err(crate::Error::InvalidInput(format!(
                "single precision (f32) is for Perlin noise and fBm, not {:?}",
                spec.kind
            )));
        }
        let fractal_kind = match spec.kind {
            NoiseKind::Perlin => None,
            NoiseKind::Fbm => Some(FractalKind::Fbm),
            NoiseKind::Turbulence => Some(FractalKind::Turbulence),
            NoiseKind::Marble => Some(FractalKind::Marble),
            NoiseKind::Multifractal => Some(FractalKind::Multifractal),
            NoiseKind::Wood => Some(FractalKind::Wood),
            NoiseKind::Gabor => return Ok(NoiseField::Gabor(Gabor::new(spec.gabor, spec.seed)?)),
            NoiseKind::Phasor => return Ok(NoiseField::Phasor(Phasor::new(spec.gabor, spec.profile, spec.seed)?)),
        };
        let fractal = fractal_kind.map(|kind| Fractal { kind, ..spec.fractal });
        if let Some(fractal) = &fractal {
            fractal.check()?;
        }
        if spec.precision == Precision::F32 {
            return match fractal {
                None => Ok(NoiseField::Single(SinglePerlin::new(spec.seed, &[1.0], 1.0)?, None)),
                Some(f) => Ok(NoiseField::Single(SinglePerlin::new(spec.seed, &f.octave_frequencies(), f.gain)?, Some(f))),
            };
        }
        Ok(NoiseField::Perlin { basis: Perlin::new(spec.seed), fractal })
    }

    /// 2D value at (x, y).
    pub fn sample2(&self, x: f64, y: f64) -> f64 {
        match self {
            NoiseField::Perlin { basis, fractal: None } => basis.sample2(x, y),
            NoiseField::Perlin { basis, fractal: Some(f) } => f.eval(x, |s| basis.sample2(x * s, y * s)),
            NoiseField::Gabor(g) => g.sample2(x, y),
            NoiseField::Phasor(p) => p.sample2(x, y),
            NoiseField::Single(s, _) => f64::from(s.sample2(x, y)),
        }
    }

    /// 3D value at `p`; Gabor noise uses `frame` for its orientation.
    pub fn sample3(&self, p: DVec3, frame: Frame) -> f64 {
        match self {
            NoiseField::Perlin { basis, fractal: None } => basis.sample3(p),
            NoiseField::Perlin { basis, fractal: Some(f) } => f.eval(p.x, ScaledPerlin { perlin: basis, point: p }),
            NoiseField::Gabor(g) => g.sample3(p, frame),
            NoiseField::Phasor(phasor) => phasor.sample3(p, frame),
            NoiseField::Single(s, _) => f64::from(s.sample3(p)),
        }
    }

    /// `value` (this field's) as a fraction of the largest value the kind can reach, so an
    /// amplitude times it is a peak displacement (#26 A4): in [−1, 1], and in [0, 1] for
    /// the one-sided kinds (turbulence, marble, multifractal, wood). Perlin and its fractal
    /// sums are divided by their bound ([`PERLIN_PEAK`], [`Fractal::peak`]). Gabor and
    /// phasor noise keep K as their magnitude, in [−K, K]: phasor noise is bounded by K
    /// already, and Gabor noise, a Gaussian sum with standard deviation K and no bound,
    /// goes through [`soft_limit`] at four standard deviations (unchanged up to two).
    pub fn unit(&self, value: f64) -> f64 {
        match self {
            NoiseField::Perlin { fractal: None, .. } | NoiseField::Single(_, None) => value / PERLIN_PEAK,
            NoiseField::Perlin { fractal: Some(f), .. } | NoiseField::Single(_, Some(f)) => value / f.peak(PERLIN_PEAK),
            NoiseField::Gabor(g) => {
                let k = g.params().k;
                k * soft_limit(value / (GABOR_PEAK_SIGMAS * k))
            }
            NoiseField::Phasor(_) => value,
        }
    }

    /// A row-major `width`×`height` grid of 2D values, sample (i, j) at
    /// (x0 + i·step, y0 + j·step); parallel, bit-identical to [`NoiseField::sample2`].
    /// Perlin noise and its fractal sums go through the batch forms (#42: the command
    /// line's pictures took the scalar path), Gabor noise through its cell cache.
    pub fn grid2(&self, x0: f64, y0: f64, step: f64, width: usize, height: usize) -> Vec<f64> {
        let mut out = vec![0.0; width * height];
        self.fill_grid2(x0, y0, step, width, &mut out);
        out
    }

    /// [`NoiseField::grid2`] into `out` (rows of `width`; `out.len() / width` of them), so
    /// a caller drawing many pictures reuses one buffer: a fresh one is faulted in page
    /// by page by the kernel, which does not run in parallel (about 0.6 ms per 8 MiB here).
    pub fn fill_grid2(&self, x0: f64, y0: f64, step: f64, width: usize, out: &mut [f64]) {
        if width == 0 {
            return;
        }
        match self {
            NoiseField::Gabor(g) => g.fill_grid2(x0, y0, step, width, out),
            _ => self.fill_plane(out, |start, run| {
                // Column and row of the run's first sample, then one step at a time (no
                // division per sample); each coordinate is formed as sample2's caller forms it.
                let (mut i, mut j) = (start % width, start / width);
                for xy in run {
                    *xy = DVec2::new(x0 + i as f64 * step, y0 + j as f64 * step);
                    i += 1;
                    if i == width {
                        (i, j) = (0, j + 1);
                    }
                }
            }),
        }
    }

    /// 2D values at many points (x, y), in parallel, bit-identical to
    /// [`NoiseField::sample2`]: Perlin noise and its fractal sums through the batch forms.
    pub fn sample2_batch(&self, points: &[DVec2]) -> Vec<f64> {
        let mut out = vec![0.0; points.len()];
        self.fill_plane(&mut out, |start, run| run.copy_from_slice(&points[start..start + run.len()]));
        out
    }

    /// `out[k]` = [`NoiseField::sample2`] at the k-th point (x, y), which `coordinates(start,
    /// run)` writes into `run` for the points from `start` on.
    fn fill_plane(&self, out: &mut [f64], coordinates: impl Fn(usize, &mut [DVec2]) + Sync) {
        // Runs of 256 points on the stack: a heap buffer per parallel chunk is large enough
        // to be mapped and unmapped each time, and the two threads then wait on the kernel.
        const RUN: usize = 256;
        fill_runs_parallel(out, |start, chunk| {
            let mut xy = [DVec2::ZERO; RUN];
            let mut points = [DVec3::ZERO; RUN];
            for (r, o) in chunk.chunks_mut(RUN).enumerate() {
                let xy = &mut xy[..o.len()];
                coordinates(start + r * RUN, xy);
                match self {
                    NoiseField::Perlin { basis, fractal: None } => {
                        for (p, q) in points.iter_mut().zip(xy.iter()) {
                            *p = plane_point(q.x, q.y);
                        }
                        basis.sample3_batch(&points[..o.len()], o);
                    }
                    // The scalar path's basis at frequency s: the plane point of (x·s, y·s).
                    NoiseField::Perlin { basis, fractal: Some(f) } => {
                        f.eval_batch(basis, |i, s| plane_point(xy[i].x * s, xy[i].y * s), |i| xy[i].x, o);
                    }
                    NoiseField::Single(single, _) => single.sample2_batch(xy, o),
                    _ => {
                        for (v, q) in o.iter_mut().zip(xy.iter()) {
                            *v = self.sample2(q.x, q.y);
                        }
                    }
                }
            }
        });
    }

    /// 3D values at many points (Gabor with each point's frame), in parallel. Perlin noise
    /// and its fractal sums go through their batch forms ([`Perlin::sample3_batch`],
    /// [`Fractal::fbm_batch`], [`Fractal::eval_batch`]: eight points at a time on AVX-512, four on AVX2, where
    /// the CPU has it), which give [`NoiseField::sample3`]'s values bit for bit; Gabor and
    /// phasor noise point by point (#42: the Python and C++ scattered points took the
    /// scalar path).
    pub fn sample3_batch(&self, points: &[DVec3], frames: &[Frame]) -> Vec<f64> {
        let mut out = vec![0.0; points.len()];
        match self {
            NoiseField::Perlin { basis, fractal: None } => {
                fill_runs_parallel(&mut out, |start, o| basis.sample3_batch(&points[start..start + o.len()], o));
            }
            NoiseField::Perlin { basis, fractal: Some(f) } if f.kind == FractalKind::Fbm => {
                fill_runs_parallel(&mut out, |start, o| f.fbm_batch(basis, &points[start..start + o.len()], o));
            }
            NoiseField::Perlin { basis, fractal: Some(f) } => fill_runs_parallel(&mut out, |start, o| {
                f.eval_batch(basis, |i, s| points[start + i] * s, |i| points[start + i].x, o);
            }),
            NoiseField::Single(single, _) => {
                fill_runs_parallel(&mut out, |start, o| single.sample3_batch(&points[start..start + o.len()], o));
            }
            _ => fill_parallel(&mut out, |k| {
                let frame = frames.get(k).copied().unwrap_or(Frame { tangent: DVec3::X, bitangent: DVec3::Y });
                self.sample3(points[k], frame)
            }),
        }
        out
    }
}

/// Standard deviations of Gabor noise that [`NoiseField::unit`] maps to its peak.
pub const GABOR_PEAK_SIGMAS: f64 = 4.0;

/// The identity on [−½, ½], and beyond it ½ + ½·tanh(2(|x| − ½)) with x's sign: continuous
/// with its first derivative, odd, increasing, and bounded by 1.
pub fn soft_limit(x: f64) -> f64 {
    const KNEE: f64 = 0.5;
    if x.abs() <= KNEE {
        x
    } else {
        x.signum() * (KNEE + (1.0 - KNEE) * ((x.abs() - KNEE) / (1.0 - KNEE)).tanh())
    }
}

/// Fills `out` by `run(start, chunk)` over parallel chunks (`start` the chunk's first
/// index); each value depends only on its index, so the result is the same at any thread
/// count.
fn fill_runs_parallel(out: &mut [f64], run: impl Fn(usize, &mut [f64]) + Sync) {
    const CHUNK: usize = 4096;
    out.par_chunks_mut(CHUNK).enumerate().for_each(|(c, o)| run(c * CHUNK, o));
}

/// Fills `out[k] = f(k)` in parallel chunks; each value depends only on `k`, so the result
/// is the same at any thread count.
pub fn fill_parallel(out: &mut [f64], f: impl Fn(usize) -> f64 + Sync) {
    const CHUNK: usize = 4096;
    out.par_chunks_mut(CHUNK).enumerate().for_each(|(c, chunk)| {
        for (i, v) in chunk.iter_mut().enumerate() {
            *v = f(c * CHUNK + i);
        }
    });
}

/// Points for the vector kernels' tests: random ones, some past 2⁵¹, infinite and NaN.
#[cfg(all(test, target_arch = "x86_64"))]
fn test_points() -> Vec<DVec3> {
    let mut rng = hash::Stream::new(11);
    let mut points: Vec<DVec3> = (0..997)
        .map(|_| DVec3::new(rng.uniform(-300.0, 300.0), rng.uniform(-300.0, 300.0), rng.uniform(-1.0, 1.0)))
        .collect();
    points[100] = DVec3::new(3e15, 0.5, -0.25);
    points[201] = DVec3::new(0.5, f64::INFINITY, 2.0);
    points[302] = DVec3::new(f64::NAN, 0.5, 2.0);
    points[403] = DVec3::new(-0.0, 0.0, -7.0);
    points
}

/// The scalar fBm the vector kernels must equal: Σ gainⁱ·n(p·fᵢ), summed from 0.
#[cfg(all(test, target_arch = "x86_64"))]
fn fbm_reference(seed: u64, frequencies: &[f64], gain: f64, p: DVec3) -> f64 {
    let (mut sum, mut amplitude) = (0.0, 1.0);
    for &f in frequencies {
        let q = p * f;
        sum += amplitude * perlin::noise3_hashed(seed, q.x, q.y, q.z);
        amplitude *= gain;
    }
    sum
}
