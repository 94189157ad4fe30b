//! Fractal sums of a basis noise (thesis §3.3.1.1 and §4.7.3.1): fBm (eq. 3.15),
//! turbulence (eq. 4.10), marble (eq. 4.11), multifractal (eq. 4.12) and wood (eq. 4.13),
//! with octaves, lacunarity (frequency ratio) and gain (amplitude ratio).

use serde::{Deserialize, Serialize};

/// Which fractal sum.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum FractalKind {
    /// Σ gⁱ n(λⁱ p) (eq. 3.15).
    Fbm,
    /// Σ gⁱ |n(λⁱ p)| (eq. 4.10).
    Turbulence,
    /// (sin(pₓ + 4 + 4·T(p/2)) + 1) / 2 with T the turbulence (eq. 4.11).
    Marble,
    /// Weighted sum of (offset − |n|)² terms, each weighted by the previous one (eq. 4.12).
    Multifractal,
    /// frac(10·|F(p)|) with F the fBm sum: rings of wood (eq. 4.13).
    Wood,
}

/// Octave parameters. Thesis defaults: lacunarity 2.0, gain 0.5 (its inverse), offset 1.0.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Fractal {
    /// The sum to compute.
    pub kind: FractalKind,
    /// Number of octaves (at least 1).
    pub octaves: u32,
    /// Frequency ratio between octaves (1 to 3 keeps the sum fractal, §4.7.3.1).
    pub lacunarity: f64,
    /// Amplitude ratio between octaves.
    pub gain: f64,
    /// The offset `d` of the multifractal (eq. 4.12).
    pub offset: f64,
}

impl Default for Fractal {
    fn default() -> Self {
        Fractal { kind: FractalKind::Fbm, octaves: 6, lacunarity: 2.0, gain: 0.5, offset: 1.0 }
    }
}

impl Fractal {
    /// A sum of the given kind with the thesis' default parameters.
    pub fn new(kind: FractalKind) -> Self {
        Fractal { kind, ..Default::default() }
    }

    /// The thesis' level-modulated parameters (§4.7.3.1): at hierarchy level `l`,
    /// lacunarity 1.1 + (l + 1)/10 and gain 0.8/(l + 1).
    pub fn for_level(self, level: u32) -> Self {
        let l = f64::from(level);
        Fractal { lacunarity: 1.1 + (l + 1.0) / 10.0, gain: 0.8 / (l + 1.0), ..self }
    }

    /// Evaluates the sum. `basis(s)` must return the basis noise at the point scaled by
    /// `s`; `x` is the point's first coordinate (used by marble).
    #[inline]
    pub fn eval(&self, x: f64, basis: impl Fn(f64) -> f64) -> f64 {
        let octaves = self.octaves.max(1);
        match self.kind {
            FractalKind::Fbm => self.fbm(octaves, 1.0, &basis),
            FractalKind::Turbulence => self.turbulence(octaves, 1.0, &basis),
            FractalKind::Marble => (((x + 4.0 + 4.0 * self.turbulence(octaves, 0.5, &basis)).sin()) + 1.0) * 0.5,
            FractalKind::Multifractal => {
                let (mut sum, mut weight, mut frequency, mut amplitude) = (0.0, 1.0, 1.0, 1.0);
                for _ in 0..octaves {
                    let signal = (self.offset - basis(frequency)).abs();
                    let term = signal * signal * amplitude * weight;
                    sum += term;
                    weight = term.clamp(0.0, 1.0);
                    frequency *= self.lacunarity;
                    amplitude *= self.gain;
                }
                sum
            }
            FractalKind::Wood => {
                let v = self.fbm(octaves, 1.0, &basis).abs() * 10.0;
                v - v.trunc()
            }
        }
    }

    fn fbm(&self, octaves: u32, base: f64, basis: &impl Fn(f64) -> f64) -> f64 {
        let (mut sum, mut frequency, mut amplitude) = (0.0, base, 1.0);
        for _ in 0..octaves {
            sum += amplitude * basis(frequency);
            frequency *= self.lacunarity;
            amplitude *= self.gain;
        }
        sum
    }

    fn turbulence(&self, octaves: u32, base: f64, basis: &impl Fn(f64) -> f64) -> f64 {
        let (mut sum, mut frequency, mut amplitude) = (0.0, base, 1.0);
        for _ in 0..octaves {
            sum += amplitude * basis(frequency).abs();
            frequency *= self.lacunarity;
            amplitude *= self.gain;
        }
        sum
    }
}
