//! Single-precision Perlin noise and its fBm (#42's f32 option): Perlin's improved noise
//! (Perlin 2002, thesis eq. 3.14 and 3.15) with f32 coordinates, arithmetic and a 32-bit
//! seeded lattice hash, so that a vector holds twice the lanes of the f64 path (16 per
//! AVX-512 vector, 8 per AVX2 one) and every integer product is native.
//!
//! A different noise from the f64 default (its own hash; f32 resolves a cell's fraction
//! to 2⁻²⁴ of the coordinate's magnitude), declared as such where it is chosen
//! (`--precision f32`). Coordinates are clamped to ±2²⁴, beyond which an f32 has no
//! fraction left. The scalar [`noise3`] is the definition; the vector paths
//! ([`super::single_x86`]) perform its operations lane by lane in the same order, so every
//! path gives the same bits.

use glam::{DVec2, DVec3};

use super::hash::derive_seed;

/// The per-axis multipliers of the 32-bit lattice hash (odd, from the golden ratio and
/// MurmurHash3's finaliser).
pub(super) const AXES: [u32; 3] = [0x9e37_79b9, 0x85eb_ca6b, 0xc2b2_ae35];
/// The corner hash's final multiplier; its top four bits pick the gradient.
pub(super) const MIX: u32 = 0x27d4_eb2f;
/// Coordinates are clamped to ±2²⁴: every f32 beyond is an integer.
pub(super) const LIMIT: f32 = 16_777_216.0;

/// The plane 2D noise samples, in f32: the f64 path's plane ([`super::plane_point`]).
const PLANE_U: [f32; 3] = [0.788_675_1, -0.577_350_26, -0.211_324_87];
const PLANE_V: [f32; 3] = [0.211_324_87, 0.577_350_26, -0.788_675_1];
const PLANE_OFFSET: f32 = 0.5 / 3.0;

/// `v` within ±[`LIMIT`]; NaN stays NaN (as the vector paths' max(−L, v), min(L, ·)).
#[inline(always)]
pub(super) fn clamp(v: f32) -> f32 {
    v.clamp(-LIMIT, LIMIT)
}

#[inline(always)]
fn fade(t: f32) -> f32 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

#[inline(always)]
fn lerp(t: f32, a: f32, b: f32) -> f32 {
    a + t * (b - a)
}

/// Perlin's select form of the gradient: u = x for h < 8 else y; v = y for h < 4, x for
/// 12 and 14, else z; u negated by bit 0 of h, v by bit 1.
#[inline(always)]
fn grad(h: u32, x: f32, y: f32, z: f32) -> f32 {
    let u = if h < 8 { x } else { y };
    let v = if h < 4 {
        y
    } else if h == 12 || h == 14 {
        x
    } else {
        z
    };
    (if h & 1 != 0 { -u } else { u }) + (if h & 2 != 0 { -v } else { v })
}

/// Single-precision seeded Perlin noise at (x, y, z).
#[inline(always)]
pub(super) fn noise3(seed: u32, x: f32, y: f32, z: f32) -> f32 {
    let (x, y, z) = (clamp(x), clamp(y), clamp(z));
    let (fx, fy, fz) = (x.floor(), y.floor(), z.floor());
    let (x0, y0, z0) = (x - fx, y - fy, z - fz);
    let (u, v, w) = (fade(x0), fade(y0), fade(z0));
    let axis = |f: f32, a: usize| {
        let first = (f as i32 as u32).wrapping_mul(AXES[a]);
        [first, first.wrapping_add(AXES[a])]
    };
    let (hx, hy, hz) = (axis(fx, 0), axis(fy, 1), axis(fz, 2));
    let c = |dx: usize, dy: usize, dz: usize| {
        let h = (seed ^ hx[dx] ^ hy[dy] ^ hz[dz]).wrapping_mul(MIX) >> 28;
        grad(h, [x0, x0 - 1.0][dx], [y0, y0 - 1.0][dy], [z0, z0 - 1.0][dz])
    };
    lerp(
        w,
        lerp(v, lerp(u, c(0, 0, 0), c(1, 0, 0)), lerp(u, c(0, 1, 0), c(1, 1, 0))),
        lerp(v, lerp(u, c(0, 0, 1), c(1, 0, 1)), lerp(u, c(0, 1, 1), c(1, 1, 1))),
    ) + 0.0
}

/// [`noise3`] at every point (`xs[i]`, `ys[i]`, `zs[i]`) into `out`: the widest vector path the
/// CPU has, then the scalar definition for the rest.
fn noise3_batch(seed: u32, xs: &[f32], ys: &[f32], zs: &[f32], out: &mut [f32]) {
    #[cfg(target_arch = "x86_64")]
    let done = super::single_x86::noise_if_available(seed, xs, ys, zs, out);
    #[cfg(not(target_arch = "x86_64"))]
    let done = 0;
    for i in done..out.len() {
        out[i] = noise3(seed, xs[i], ys[i], zs[i]);
    }
}

/// Single-precision Perlin noise, one octave or summed as fBm: Σ gainⁱ·n(p·fᵢ) in f32 over
/// the f64 path's frequencies rounded to f32.
#[derive(Debug, Clone, PartialEq)]
pub struct SinglePerlin {
    seed: u32,
    frequencies: Vec<f32>,
    gain: f32,
}

/// Points per run of the batch paths (their f32 buffers stay on the stack).
const RUN: usize = 256;

impl SinglePerlin {
    /// The noise of `seed` at `frequencies` (one frequency 1 for plain noise) with `gain`.
    ///
    /// # Errors
    /// [`crate::Error::InvalidInput`] where a frequency or an octave's amplitude, finite in
    /// f64, overflows f32 (the f64 checks pass a gain of 1e39).
    pub fn new(seed: u64, frequencies: &[f64], gain: f64) -> crate::Result<Self> {
        let frequencies: Vec<f32> = frequencies.iter().map(|&f| f as f32).collect();
        let gain = gain as f32;
        let amplitudes = std::iter::successors(Some(1.0f32), |a| Some(a * gain)).take(frequencies.len());
        if frequencies.iter().chain(amplitudes.collect::<Vec<_>>().iter()).any(|v| !v.is_finite()) {
            return Err(crate::Error::InvalidInput(
                "single precision (f32): the octaves' frequencies or amplitudes overflow f32; use --precision f64 or a smaller gain or lacunarity".into(),
            ));
        }
        Ok(SinglePerlin { seed: derive_seed(seed, "perlin-f32") as u32, frequencies, gain })
    }

    /// The sum over the octaves of [`noise3`] at `at(s)` for each frequency s.
    #[inline(always)]
    fn sum(&self, at: impl Fn(f32) -> [f32; 3]) -> f32 {
        let (mut sum, mut amplitude) = (0.0f32, 1.0f32);
        for &s in &self.frequencies {
            let [x, y, z] = at(s);
            sum += amplitude * noise3(self.seed, x, y, z);
            amplitude *= self.gain;
        }
        sum
    }

    /// The value at the 3D point `p` (its coordinates rounded to f32).
    pub fn sample3(&self, p: DVec3) -> f32 {
        let q = p.as_vec3();
        self.sum(|s| [q.x * s, q.y * s, q.z * s])
    }

    /// The value at the 2D point (x, y): the 3D noise on the f64 path's oblique plane,
    /// formed in f32.
    pub fn sample2(&self, x: f64, y: f64) -> f32 {
        let (x, y) = (x as f32, y as f32);
        self.sum(|s| plane(x * s, y * s))
    }

    /// [`SinglePerlin::sample3`] at every point of `points` into `out`, bit for bit.
    pub fn sample3_batch(&self, points: &[DVec3], out: &mut [f64]) {
        self.batch(out, false, |start, xyz| {
            for (i, q) in points[start..start + xyz[0].len()].iter().enumerate() {
                let q = q.as_vec3();
                (xyz[0][i], xyz[1][i], xyz[2][i]) = (q.x, q.y, q.z);
            }
        });
    }

    /// [`SinglePerlin::sample2`] at every point (x, y) of `points` into `out`, bit for bit.
    pub fn sample2_batch(&self, points: &[DVec2], out: &mut [f64]) {
        self.batch(out, true, |start, xyz| {
            for (i, q) in points[start..start + xyz[0].len()].iter().enumerate() {
                (xyz[0][i], xyz[1][i]) = (q.x as f32, q.y as f32);
            }
        });
    }

    /// Runs of [`RUN`] points: `load(start, [xs, ys, zs])` writes the run's coordinates
    /// (x and y only when `planar`: 2D points, which sample the plane), every octave goes
    /// through [`noise3_batch`], and the sum is formed as [`SinglePerlin::sum`] forms it.
    fn batch(&self, out: &mut [f64], planar: bool, load: impl Fn(usize, [&mut [f32]; 3])) {
        let (mut xs, mut ys, mut zs) = ([0.0f32; RUN], [0.0f32; RUN], [0.0f32; RUN]);
        let (mut qx, mut qy, mut qz) = ([0.0f32; RUN], [0.0f32; RUN], [0.0f32; RUN]);
        let mut n = [0.0f32; RUN];
        for (r, o) in out.chunks_mut(RUN).enumerate() {
            let len = o.len();
            load(r * RUN, [&mut xs[..len], &mut ys[..len], &mut zs[..len]]);
            let mut sum = [0.0f32; RUN];
            let mut amplitude = 1.0f32;
            for &s in &self.frequencies {
                for i in 0..len {
                    [qx[i], qy[i], qz[i]] =
                        if planar { plane(xs[i] * s, ys[i] * s) } else { [xs[i] * s, ys[i] * s, zs[i] * s] };
                }
                noise3_batch(self.seed, &qx[..len], &qy[..len], &qz[..len], &mut n[..len]);
                for i in 0..len {
                    sum[i] += amplitude * n[i];
                }
                amplitude *= self.gain;
            }
            for (v, s) in o.iter_mut().zip(sum) {
                *v = f64::from(s);
            }
        }
    }
}

/// The plane point of (x, y) in f32: offset + U·x + V·y, summed in that order.
#[inline(always)]
fn plane(x: f32, y: f32) -> [f32; 3] {
    std::array::from_fn(|a| PLANE_OFFSET + PLANE_U[a] * x + PLANE_V[a] * y)
}
