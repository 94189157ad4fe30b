//! Fractal sums of a basis noise (thesis §3.3.1.1 and §4.7.3.1): fBm (eq. 3.15),
//! turbulence (eq. 4.10), marble (eq. 4.11), multifractal (eq. 4.12) and wood (eq. 4.13),
//! with octaves, lacunarity (frequency ratio) and gain (amplitude ratio).

use glam::DVec3;
use serde::{Deserialize, Serialize};
use smallvec::SmallVec;

use super::Perlin;

/// Which fractal sum.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
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
    /// frac(10·|F(p)|) with F the fBm sum: rings of wood (eq. 4.13), each ring's drop
    /// spread over the last [`WOOD_RING_FALL`] of it ([`wood_ring`]).
    Wood,
}

/// The share of a wood ring over which eq. 4.13's fractional part falls back from 1 to 0.
pub const WOOD_RING_FALL: f64 = 0.25;

/// Eq. 4.13's ring profile frac(v), made continuous: it rises from 0 to 1 over the first
/// 1 − [`WOOD_RING_FALL`] of each unit of `v` and falls back to 0 over the rest. A
/// displacement by the bare fractional part jumps by its whole amplitude at every ring, and
/// a mesh samples each jump as a one-edge cliff whose outline follows the edges (the
/// "staircase of cliffs" of #26 B9); the fall keeps the rings' asymmetric grain.
pub fn wood_ring(v: f64) -> f64 {
    wood_ring_falling_over(v, WOOD_RING_FALL)
}

/// [`wood_ring`] with the fall spread over the share `fall` of each ring (in (0, 1)).
pub fn wood_ring_falling_over(v: f64, fall: f64) -> f64 {
    let t = v - v.trunc();
    let rise = 1.0 - fall;
    if t < rise { t / rise } else { (1.0 - t) / fall }
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

    /// The thesis' level-modulated parameters (§4.7.3.1): at hierarchy level `l`, counted
    /// from the base domain (0) towards the input as the thesis numbers K⁰ … Kᴸ (§4.4.1.2),
    /// lacunarity 1.1 + (l + 1)/10 and gain 0.8/(l + 1). The printed "1.1 + (l + 1/10)" is
    /// read as (l + 1)/10 with l from the base, because §5.1.1 says the lacunarity's
    /// influence is attenuated "while moving to coarser levels": it is then 1.2 on the base
    /// domain and grows towards the input, while the gain falls (finer levels get weaker
    /// high octaves). Counting l from the input instead would make it grow at coarser
    /// levels, against that sentence.
    pub fn for_level(self, level: u32) -> Self {
        let l = f64::from(level);
        Fractal { lacunarity: 1.1 + (l + 1.0) / 10.0, gain: 0.8 / (l + 1.0), ..self }
    }

    /// Whether the octaves are at most [`super::MAX_OCTAVES`] and every octave's frequency
    /// and amplitude, and their sum's bound, are finite numbers: a gain or lacunarity whose
    /// powers overflow over the octaves would make every value infinite or NaN (#36:
    /// `--gain 1e300` ended as an internal error).
    ///
    /// # Errors
    /// [`crate::Error::InvalidInput`] naming the parameter.
    pub fn check(&self) -> crate::Result<()> {
        if self.octaves > super::MAX_OCTAVES {
            return Err(crate::Error::InvalidInput(format!(
                "{} octaves: at most {} (beyond, an octave's frequency leaves the precision of the coordinates)",
                self.octaves,
                super::MAX_OCTAVES
            )));
        }
        let octaves = self.octaves.max(1);
        let last = (octaves - 1) as i32;
        for (name, value) in [("lacunarity", self.lacunarity), ("gain", self.gain), ("offset", self.offset)] {
            if !value.is_finite() {
                return Err(crate::Error::InvalidInput(format!(
                    "fractal {name} {} must be a finite number",
                    shown(value)
                )));
            }
        }
        if !(self.lacunarity.abs().powi(last).is_finite() && self.lacunarity != 0.0) {
            return Err(crate::Error::InvalidInput(format!(
                "fractal lacunarity {} over {octaves} octaves: the octaves' frequencies overflow (or vanish)",
                shown(self.lacunarity)
            )));
        }
        if !self.peak(1.0).is_finite() {
            return Err(crate::Error::InvalidInput(format!(
                "fractal gain {} over {octaves} octaves: the octaves' amplitudes overflow",
                shown(self.gain)
            )));
        }
        Ok(())
    }

    /// The largest |value| the sum can reach over a basis bounded by `basis_peak` (#26 A4:
    /// an amplitude is the peak displacement, so values are divided by this): fBm and
    /// turbulence Σ|g|ⁱ·B over the octaves; the multifractal (|d| + B)²·Σ|g|ⁱ, since each
    /// term is (d − n)² times the octave's amplitude times a weight clamped to [0, 1];
    /// marble and wood 1 (a sine mapped to [0, 1], a fractional part).
    pub fn peak(&self, basis_peak: f64) -> f64 {
        let weights: f64 = (0..self.octaves.max(1)).map(|i| self.gain.abs().powi(i as i32)).sum();
        match self.kind {
            FractalKind::Fbm | FractalKind::Turbulence => basis_peak * weights,
            FractalKind::Multifractal => (self.offset.abs() + basis_peak).powi(2) * weights,
            FractalKind::Marble | FractalKind::Wood => 1.0,
        }
    }

    /// Evaluates the sum. `basis.at(s)` must return the basis noise at the point scaled by
    /// `s` (a closure `|s| …` will do); `x` is the point's first coordinate (used by marble).
    #[inline(always)]
    pub fn eval(&self, x: f64, basis: impl Basis) -> f64 {
        let mut values: SmallVec<[f64; super::MAX_OCTAVES as usize]> = SmallVec::new();
        self.octave_values(self.octaves.max(1), self.base_frequency(), &basis, |n| values.push(n));
        self.combine(x, &values)
    }

    /// The frequency of the first octave: ½ for marble, whose turbulence is T(p/2)
    /// (eq. 4.11), else 1.
    fn base_frequency(&self) -> f64 {
        if self.kind == FractalKind::Marble { 0.5 } else { 1.0 }
    }

    /// The sum of the kind from its octaves' basis values `n` (at the frequencies
    /// [`Fractal::frequencies`] lists from [`Fractal::base_frequency`], in order) and the
    /// point's first coordinate `x`: the one combination [`Fractal::eval`] and
    /// [`Fractal::eval_batch`] share, so both give the same bits.
    #[inline(always)]
    fn combine(&self, x: f64, n: &[f64]) -> f64 {
        match self.kind {
            FractalKind::Fbm => self.weighted(n, |v| v),
            FractalKind::Turbulence => self.weighted(n, f64::abs),
            FractalKind::Marble => (((x + 4.0 + 4.0 * self.weighted(n, f64::abs)).sin()) + 1.0) * 0.5,
            FractalKind::Multifractal => {
                let (mut sum, mut weight, mut amplitude) = (0.0, 1.0, 1.0);
                for &v in n {
                    let signal = (self.offset - v).abs();
                    let term = signal * signal * amplitude * weight;
                    sum += term;
                    weight = term.clamp(0.0, 1.0);
                    amplitude *= self.gain;
                }
                sum
            }
            FractalKind::Wood => wood_ring(self.weighted(n, |v| v).abs() * 10.0),
        }
    }

    /// Σ gainⁱ·f(nᵢ), the amplitude a running product: fBm with the identity, turbulence
    /// with the absolute value.
    #[inline(always)]
    fn weighted(&self, n: &[f64], f: impl Fn(f64) -> f64) -> f64 {
        let (mut sum, mut amplitude) = (0.0, 1.0);
        for &v in n {
            sum += amplitude * f(v);
            amplitude *= self.gain;
        }
        sum
    }

    /// The sum (any kind) of Perlin noise at `out.len()` points into `out`, every octave of
    /// a run of points through [`Perlin::sample3_batch`] (AVX-512 or AVX2 where the CPU has it):
    /// `point_at(k, s)` is point k as the scalar path's basis sees it at frequency `s`
    /// (`p·s` in space; the plane point of (x·s, y·s) for 2D noise) and `x_of(k)` its
    /// first coordinate (marble's). Each value equals [`Fractal::eval`] with that basis
    /// bit for bit: the same frequencies, the same basis values, the same combination
    /// (`Fractal::combine`).
    pub fn eval_batch(
        &self,
        perlin: &Perlin,
        point_at: impl Fn(usize, f64) -> DVec3,
        x_of: impl Fn(usize) -> f64,
        out: &mut [f64],
    ) {
        const RUN: usize = 256;
        let frequencies = self.frequencies(self.octaves.max(1), self.base_frequency());
        let mut points = vec![DVec3::ZERO; RUN];
        let mut values = vec![0.0; frequencies.len() * RUN];
        let mut n: SmallVec<[f64; super::MAX_OCTAVES as usize]> = SmallVec::from_elem(0.0, frequencies.len());
        for (run, o) in out.chunks_mut(RUN).enumerate() {
            let (start, len) = (run * RUN, o.len());
            for (octave, &s) in frequencies.iter().enumerate() {
                for (i, p) in points[..len].iter_mut().enumerate() {
                    *p = point_at(start + i, s);
                }
                perlin.sample3_batch(&points[..len], &mut values[octave * RUN..octave * RUN + len]);
            }
            for (i, v) in o.iter_mut().enumerate() {
                for (octave, slot) in n.iter_mut().enumerate() {
                    *slot = values[octave * RUN + i];
                }
                *v = self.combine(x_of(start + i), &n);
            }
        }
    }

    /// fBm of 3D Perlin noise (the [`FractalKind::Fbm`] sum whatever `self.kind`) at every
    /// point of `points` into `out`: each octave evaluated on four points at a time through
    /// [`Perlin::sample3_lanes`], frequencies and sums formed in the order [`Fractal::eval`]
    /// forms them, so every value equals `eval` with a [`ScaledPerlin`] bit for bit.
    ///
    /// # Panics
    /// If `out` and `points` differ in length.
    pub fn fbm_batch(&self, perlin: &Perlin, points: &[DVec3], out: &mut [f64]) {
        assert_eq!(points.len(), out.len(), "one output per point");
        let octaves = self.octaves.max(1);
        let frequencies = self.frequencies(octaves, 1.0);
        let done = perlin.fbm_batch_vectorised(&frequencies, self.gain, points, out);
        let (points, out) = (&points[done..], &mut out[done..]);
        const L: usize = super::perlin::BATCH_LANES;
        let mut chunks = points.chunks_exact(L);
        let mut outs = out.chunks_exact_mut(L);
        for (p, o) in (&mut chunks).zip(&mut outs) {
            let (mut sum, mut amplitude) = ([0.0; L], 1.0);
            for &s in &frequencies {
                let n = perlin.sample3_lanes::<L>(std::array::from_fn(|l| p[l] * s));
                for l in 0..L {
                    sum[l] += amplitude * n[l];
                }
                amplitude *= self.gain;
            }
            o.copy_from_slice(&sum);
        }
        for (p, o) in chunks.remainder().iter().zip(outs.into_remainder()) {
            *o = Fractal { kind: FractalKind::Fbm, ..*self }.eval(p.x, ScaledPerlin { perlin, point: *p });
        }
    }

    /// The frequencies of the octaves [`Fractal::eval`] sums, in order (from 1, or ½ for
    /// marble).
    pub fn octave_frequencies(&self) -> Vec<f64> {
        self.frequencies(self.octaves.max(1), self.base_frequency())
    }

    /// The frequencies [`Fractal::octave_values`] visits, in order (the same running
    /// product).
    fn frequencies(&self, octaves: u32, base: f64) -> Vec<f64> {
        let mut out = Vec::with_capacity(octaves as usize);
        let mut frequency = base;
        for _ in 0..octaves / 2 {
            let pair = [frequency, frequency * self.lacunarity];
            frequency = pair[1] * self.lacunarity;
            out.extend(pair);
        }
        if octaves % 2 == 1 {
            out.push(frequency);
        }
        out
    }

    /// Calls `consume` with the basis at frequencies base·λⁱ, i = 0..octaves, in order.
    /// The frequencies are the running product (as a plain loop would compute them) and
    /// the basis is asked two octaves at a time, so the two evaluations overlap.
    #[inline(always)]
    fn octave_values(&self, octaves: u32, base: f64, basis: &impl Basis, mut consume: impl FnMut(f64)) {
        let mut frequency = base;
        for _ in 0..octaves / 2 {
            let pair = [frequency, frequency * self.lacunarity];
            frequency = pair[1] * self.lacunarity;
            let [a, b] = basis.at2(pair);
            consume(a);
            consume(b);
        }
        if octaves % 2 == 1 {
            consume(basis.at(frequency));
        }
    }
}

/// The basis noise of a fractal sum as a function of the frequency: the point scaled by
/// `s`. Every `Fn(f64) -> f64` is one; [`ScaledPerlin`] also evaluates two frequencies
/// at once.
pub trait Basis {
    /// The basis at frequency `s`.
    fn at(&self, s: f64) -> f64;
    /// The basis at two frequencies; must equal `[self.at(s[0]), self.at(s[1])]` bit for bit.
    #[inline(always)]
    fn at2(&self, s: [f64; 2]) -> [f64; 2] {
        [self.at(s[0]), self.at(s[1])]
    }
}

impl<F: Fn(f64) -> f64> Basis for F {
    #[inline(always)]
    fn at(&self, s: f64) -> f64 {
        self(s)
    }
}

/// 3D Perlin noise at a point scaled by the frequency, two frequencies per evaluation
/// through [`Perlin::sample3_lanes`].
#[derive(Debug, Clone, Copy)]
pub struct ScaledPerlin<'a> {
    /// The basis noise.
    pub perlin: &'a Perlin,
    /// The point.
    pub point: DVec3,
}

impl Basis for ScaledPerlin<'_> {
    #[inline(always)]
    fn at(&self, s: f64) -> f64 {
        self.perlin.sample3(self.point * s)
    }
    #[inline(always)]
    fn at2(&self, s: [f64; 2]) -> [f64; 2] {
        self.perlin.sample3_lanes([self.point * s[0], self.point * s[1]])
    }
}

/// `value` as a message shows it: in exponent form when very large or small.
fn shown(value: f64) -> String {
    if value != 0.0 && !(1e-4..1e6).contains(&value.abs()) { format!("{value:e}") } else { format!("{value}") }
}
