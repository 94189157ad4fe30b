//! Terrain randomness: every displacement is a pure function of (seed, level, x, y), drawn
//! from a counter-based stream, so any region of the grid — whole, tile or streamed band —
//! gets the same values.

use rand_distr::{Distribution as _, Exp1, StandardNormal};
use serde::{Deserialize, Serialize};

use crate::noise::hash::{Stream, derive_seed, mix64};

/// The distribution of the random displacements (seed 001), before scaling by the level's σ;
/// each is standardised, then given the requested mean and variance.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum Distribution {
    /// Normal (Gaussian), the default.
    #[default]
    Normal,
    /// Uniform, with the same mean and variance.
    Uniform,
    /// Exponential, shifted and scaled to the mean and variance (skewed: rare tall peaks).
    Exponential,
    /// Laplace (two-sided exponential), with the mean and variance (heavier tails).
    Laplace,
}

/// `rand_core` adapter over a borrowed [`Stream`], so `rand_distr`'s samplers (ziggurat for
/// the normal distribution) draw from counter-based bits.
pub(crate) struct CounterRng<'a>(pub &'a mut Stream);

impl rand_core::RngCore for CounterRng<'_> {
    fn next_u32(&mut self) -> u32 {
        (self.0.next_u64() >> 32) as u32
    }
    fn next_u64(&mut self) -> u64 {
        self.0.next_u64()
    }
    fn fill_bytes(&mut self, dest: &mut [u8]) {
        for chunk in dest.chunks_mut(8) {
            chunk.copy_from_slice(&self.0.next_u64().to_le_bytes()[..chunk.len()]);
        }
    }
    fn try_fill_bytes(&mut self, dest: &mut [u8]) -> Result<(), rand_core::Error> {
        self.fill_bytes(dest);
        Ok(())
    }
}

/// Random displacements of one terrain.
#[derive(Debug, Clone, Copy)]
pub struct Displacements {
    seed: u64,
    distribution: Distribution,
    mean: f64,
    deviation: f64,
}

impl Displacements {
    /// Displacements with the given seed, distribution, mean and variance.
    pub fn new(seed: u64, distribution: Distribution, mean: f64, variance: f64) -> Self {
        Displacements { seed: derive_seed(seed, "terrain"), distribution, mean, deviation: variance.max(0.0).sqrt() }
    }

    /// The seed and the point's coordinates combined by odd multipliers; the sampler's
    /// stream applies the one full mix (fmix64) before any bit is used.
    #[inline(always)]
    fn point_hash(&self, level: u32, x: u64, y: u64) -> u64 {
        self.seed
            ^ u64::from(level).wrapping_mul(0x9e37_79b9_7f4a_7c15)
            ^ x.wrapping_mul(0xc2b2_ae3d_27d4_eb4f)
            ^ y.rotate_left(32).wrapping_mul(0x1656_67b1_9e37_79f9)
    }

    /// The random value of grid point (x, y) at `level`.
    #[inline(always)]
    pub fn sample(&self, level: u32, x: u64, y: u64) -> f64 {
        let mut stream = Stream::new(self.point_hash(level, x, y));
        let z: f64 = match self.distribution {
            Distribution::Normal => StandardNormal.sample(&mut CounterRng(&mut stream)),
            Distribution::Uniform => (stream.unit() * 2.0 - 1.0) * 3f64.sqrt(),
            other => skewed_sample(other, stream),
        };
        self.mean + self.deviation * z
    }

    /// A uniform value in [0, 1) of (x, y) at `level` (seed 002's rule).
    #[inline]
    pub fn unit(&self, level: u32, x: u64, y: u64) -> f64 {
        Stream::new(self.point_hash(level, x, y)).unit()
    }

    /// A second, independent value of (x, y) at `level` (the applet's random sign).
    #[inline]
    pub fn sign(&self, level: u32, x: u64, y: u64) -> f64 {
        if mix64(self.point_hash(level, x, y) ^ 0x5167_4e20_7369_676e) >> 63 == 0 { 1.0 } else { -1.0 }
    }
}

/// The exponential and Laplace draws, kept out of line so the common normal path stays small.
#[cold]
#[inline(never)]
fn skewed_sample(distribution: Distribution, mut stream: Stream) -> f64 {
    // Exp(1) has mean 1 and variance 1; a random sign on it has variance 2.
    let magnitude: f64 = Exp1.sample(&mut CounterRng(&mut stream));
    match distribution {
        Distribution::Laplace => {
            let sign = if stream.next_u64() >> 63 == 0 { 1.0 } else { -1.0 };
            sign * magnitude * std::f64::consts::FRAC_1_SQRT_2
        }
        _ => magnitude - 1.0,
    }
}
