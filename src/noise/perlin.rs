//! Perlin's improved noise (Perlin 2002; thesis §3.3.1.1, eq. 3.14): quintic fade
//! 6t⁵ − 15t⁴ + 10t³, the 12 cube-edge gradients (16 entries, four repeated), trilinear
//! blending of the eight corner contributions.
//!
//! Two lattices: Perlin's reference permutation (period 256, reproduces his Java
//! reference implementation) and a seeded counter-based hash of the integer corner
//! coordinates (no period: coordinates up to 1e6 and beyond stay non-repeating).

use glam::DVec3;

use super::hash::derive_seed;

/// Perlin's published permutation of 0..=255.
#[rustfmt::skip]
const REFERENCE_PERMUTATION: [u8; 256] = [
    151,160,137,91,90,15,131,13,201,95,96,53,194,233,7,225,140,36,103,30,69,142,8,99,37,240,21,10,23,
    190,6,148,247,120,234,75,0,26,197,62,94,252,219,203,117,35,11,32,57,177,33,88,237,149,56,87,174,
    20,125,136,171,168,68,175,74,165,71,134,139,48,27,166,77,146,158,231,83,111,229,122,60,211,133,
    230,220,105,92,41,55,46,245,40,244,102,143,54,65,25,63,161,1,216,80,73,209,76,132,187,208,89,18,
    169,200,196,135,130,116,188,159,86,164,100,109,198,173,186,3,64,52,217,226,250,124,123,5,202,38,
    147,118,126,255,82,85,212,207,206,59,227,47,16,58,17,182,189,28,42,223,183,170,213,119,248,152,2,
    44,154,163,70,221,153,101,155,167,43,172,9,129,22,39,253,19,98,108,110,79,113,224,232,178,185,112,
    104,218,246,97,228,251,34,242,193,238,210,144,12,191,179,162,241,81,51,145,235,249,14,239,107,49,
    192,214,31,181,199,106,157,184,84,204,176,115,121,50,45,127,4,150,254,138,236,205,93,222,114,67,
    29,24,72,243,141,128,195,78,66,215,61,156,180,
];

/// The gradients of Perlin's `grad(hash, x, y, z)` indexed by `hash & 15`: the 12 cube-edge
/// directions, with (1,1,0), (−1,1,0), (0,−1,1), (0,−1,−1) repeated to fill 16 slots.
#[rustfmt::skip]
const GRADIENTS: [[f64; 3]; 16] = [
    [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0], [1.0, -1.0, 0.0], [-1.0, -1.0, 0.0],
    [1.0, 0.0, 1.0], [-1.0, 0.0, 1.0], [1.0, 0.0, -1.0], [-1.0, 0.0, -1.0],
    [0.0, 1.0, 1.0], [0.0, -1.0, 1.0], [0.0, 1.0, -1.0], [0.0, -1.0, -1.0],
    [1.0, 1.0, 0.0], [0.0, -1.0, 1.0], [-1.0, 1.0, 0.0], [0.0, -1.0, -1.0],
];

/// Which hash selects the corner gradients.
#[derive(Clone)]
enum Lattice {
    /// Perlin's permutation, doubled to 512 entries.
    Reference(Box<[u8; 512]>),
    /// Counter-based hash of (seed, corner).
    Hashed(u64),
}

/// The largest |value| Perlin's improved noise can reach in 3D (and so on the 2D plane it
/// samples): 1.03636 rounded up.
///
/// Each corner's contribution is its fade weight times g·d, and the corners' gradients are
/// drawn independently, so the noise's supremum at a point of the cell is
/// Σ_c w_c · max_g g·d_c, where max over the 12 cube-edge gradients of g·d is the sum of
/// d's two largest absolute components. Maximised over the cell that sum is 1.036354
/// (near (0.355, 0.5, 0.519)); the unit test `peak_is_the_cell_supremum` computes it. It
/// is what an amplitude is divided by (#26 A4: amplitude is the peak displacement).
pub const PERLIN_PEAK: f64 = 1.03636;

/// Perlin improved noise in 2D and 3D; values lie in [−`PERLIN_PEAK`, `PERLIN_PEAK`].
#[derive(Clone)]
pub struct Perlin {
    lattice: Lattice,
}

impl std::fmt::Debug for Perlin {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.lattice {
            Lattice::Reference(_) => write!(f, "Perlin(reference)"),
            Lattice::Hashed(seed) => write!(f, "Perlin(hashed {seed:#x})"),
        }
    }
}

#[inline(always)]
fn fade(t: f64) -> f64 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

#[inline(always)]
fn lerp(t: f64, a: f64, b: f64) -> f64 {
    a + t * (b - a)
}

/// g·(x, y, z) for gradient `hash & 15` of [`GRADIENTS`]: one table load and three
/// products, faster here than Perlin's select form (u and v chosen by the hash's bits,
/// signed, added), which the vector path ([`super::perlin_avx2`]) uses. Every gradient
/// has two components ±1 and one 0, so the two forms give the same value, up to the sign
/// of an exact zero; a zero's sign never changes a non-zero sum or product, so both
/// paths' results agree once they add +0, which turns −0 into +0 ([`noise3`]).
#[inline(always)]
fn grad(hash: usize, x: f64, y: f64, z: f64) -> f64 {
    let g = GRADIENTS[hash & 15];
    g[0] * x + g[1] * y + g[2] * z
}

/// Floor as an integer without calling libm (valid for |x| < 2⁶³).
#[inline(always)]
fn floor_i64(x: f64) -> i64 {
    let i = x as i64;
    if (i as f64) > x { i - 1 } else { i }
}

/// Gradient hashes of lattice corners, built axis by axis: per-axis values for the two
/// lattice planes of each axis, combined per corner.
trait CornerHash {
    /// Per-axis state of the two lattice coordinates `i` and `i + 1` along `axis`.
    fn axis(&self, axis: usize, i: i64) -> [u64; 2];
    /// Combines the x, then y, then z parts into a gradient index.
    fn combine_xy(&self, hx: u64, hy: u64) -> u64;
    fn corner(&self, hxy: u64, hz: u64) -> usize;
}

struct Permutation<'a>(&'a [u8; 512]);

impl CornerHash for Permutation<'_> {
    #[inline(always)]
    fn axis(&self, _: usize, i: i64) -> [u64; 2] {
        let i = (i & 255) as u64;
        [i, i + 1]
    }
    #[inline(always)]
    fn combine_xy(&self, hx: u64, hy: u64) -> u64 {
        self.0[hx as usize] as u64 + hy
    }
    #[inline(always)]
    fn corner(&self, hxy: u64, hz: u64) -> usize {
        self.0[self.0[hxy as usize] as usize + hz as usize] as usize
    }
}

/// Seeded lattice hash: per-axis odd multiples xor-combined, then one multiply;
/// the top four bits pick the gradient (the top bits of a product depend on all input bits).
struct Hashed(u64);

pub(super) const HASH_AXES: [u64; 3] = [0x9e37_79b9_7f4a_7c15, 0xc2b2_ae3d_27d4_eb4f, 0x1656_67b1_9e37_79f9];
pub(super) const HASH_M: u64 = 0xd6e8_feb8_6659_fd93;

impl CornerHash for Hashed {
    #[inline(always)]
    fn axis(&self, axis: usize, i: i64) -> [u64; 2] {
        let a = (i as u64).wrapping_mul(HASH_AXES[axis]);
        [a, a.wrapping_add(HASH_AXES[axis])]
    }
    #[inline(always)]
    fn combine_xy(&self, hx: u64, hy: u64) -> u64 {
        self.0 ^ hx ^ hy
    }
    #[inline(always)]
    fn corner(&self, hxy: u64, hz: u64) -> usize {
        let h = hxy ^ hz;
        (h.wrapping_mul(HASH_M) >> 60) as usize
    }
}

#[inline(always)]
fn noise3<H: CornerHash>(h: &H, x: f64, y: f64, z: f64) -> f64 {
    let (xi, yi, zi) = (floor_i64(x), floor_i64(y), floor_i64(z));
    let (x, y, z) = (x - xi as f64, y - yi as f64, z - zi as f64);
    let (u, v, w) = (fade(x), fade(y), fade(z));
    let (hx, hy, hz) = (h.axis(0, xi), h.axis(1, yi), h.axis(2, zi));
    let c = |dx: usize, dy: usize, dz: usize| {
        let corner = h.corner(h.combine_xy(hx[dx], hy[dy]), hz[dz]);
        grad(corner, x - dx as f64, y - dy as f64, z - dz as f64)
    };
    // + 0 turns an exact −0 into +0 (see [`grad`]).
    lerp(
        w,
        lerp(v, lerp(u, c(0, 0, 0), c(1, 0, 0)), lerp(u, c(0, 1, 0), c(1, 1, 0))),
        lerp(v, lerp(u, c(0, 0, 1), c(1, 0, 1)), lerp(u, c(0, 1, 1), c(1, 1, 1))),
    ) + 0.0
}

/// [`noise3`] on the seeded lattice `seed` (the vector path's scalar fallback).
#[cfg(target_arch = "x86_64")]
pub(super) fn noise3_hashed(seed: u64, x: f64, y: f64, z: f64) -> f64 {
    noise3(&Hashed(seed), x, y, z)
}

/// [`noise3`] at several points at once, written lane by lane so that the independent
/// evaluations interleave (and their float work vectorises): each lane performs exactly
/// the operations of [`noise3`], so it returns the same bits.
#[inline(always)]
fn noise3_lanes<H: CornerHash, const N: usize>(h: &H, p: [DVec3; N]) -> [f64; N] {
    let cell: [[i64; 3]; N] = std::array::from_fn(|l| [floor_i64(p[l].x), floor_i64(p[l].y), floor_i64(p[l].z)]);
    let f: [[f64; 3]; N] =
        std::array::from_fn(|l| [p[l].x - cell[l][0] as f64, p[l].y - cell[l][1] as f64, p[l].z - cell[l][2] as f64]);
    let fades: [[f64; 3]; N] = std::array::from_fn(|l| [fade(f[l][0]), fade(f[l][1]), fade(f[l][2])]);
    let axes: [[[u64; 2]; 3]; N] =
        std::array::from_fn(|l| [h.axis(0, cell[l][0]), h.axis(1, cell[l][1]), h.axis(2, cell[l][2])]);
    let corners: [[f64; 8]; N] = std::array::from_fn(|l| {
        let [hx, hy, hz] = axes[l];
        let [x, y, z] = f[l];
        std::array::from_fn(|c| {
            let (dx, dy, dz) = (c & 1, (c >> 1) & 1, c >> 2);
            grad(h.corner(h.combine_xy(hx[dx], hy[dy]), hz[dz]), x - dx as f64, y - dy as f64, z - dz as f64)
        })
    });
    std::array::from_fn(|l| {
        let [u, v, w] = fades[l];
        let c = &corners[l];
        lerp(w, lerp(v, lerp(u, c[0], c[1]), lerp(u, c[2], c[3])), lerp(v, lerp(u, c[4], c[5]), lerp(u, c[6], c[7])))
            + 0.0
    })
}

/// Batch evaluation, [`BATCH_LANES`] points at a time, the rest one by one.
#[inline(always)]
fn batch<H: CornerHash>(h: &H, points: &[DVec3], out: &mut [f64]) {
    let mut chunks = points.chunks_exact(BATCH_LANES);
    let mut outs = out.chunks_exact_mut(BATCH_LANES);
    for (p, o) in (&mut chunks).zip(&mut outs) {
        o.copy_from_slice(&noise3_lanes::<H, BATCH_LANES>(h, std::array::from_fn(|l| p[l])));
    }
    for (p, o) in chunks.remainder().iter().zip(outs.into_remainder()) {
        *o = noise3(h, p.x, p.y, p.z);
    }
}

/// Points per batch step: four interleaved evaluations fill two SSE2 (or one AVX) f64
/// vectors and hide the gradient lookups' latency.
pub const BATCH_LANES: usize = 4;

/// The plane 2D noise is sampled on: spanned by two unit vectors orthogonal to the
/// lattice diagonal (1, 1, 1) and offset along it so that no lattice point lies on it.
/// The z = 0 plane is a lattice plane: every lattice point on it is a zero of the noise
/// and half its gradients lie in it, which shows as straight axis-aligned streaks; on an
/// oblique plane the lattice's cells are cut in varied shapes. The in-plane basis is
/// turned so the lattice axes project at 15°, 75° and 135° to the image's x axis, none
/// along the image's axes: ((3+√3)/6, −1/√3, (√3−3)/6) and ((3−√3)/6, 1/√3, −(3+√3)/6).
const PLANE_U: DVec3 = DVec3::new(0.788_675_134_594_812_9, -0.577_350_269_189_625_7, -0.211_324_865_405_187_1);
const PLANE_V: DVec3 = DVec3::new(0.211_324_865_405_187_1, 0.577_350_269_189_625_7, -0.788_675_134_594_812_9);
/// The plane's offset: every point on it has x + y + z = 0.5, so no lattice point.
const PLANE_OFFSET: DVec3 = DVec3::new(0.5 / 3.0, 0.5 / 3.0, 0.5 / 3.0);

/// The 3D point at which 2D noise samples (x, y).
#[inline(always)]
pub fn plane_point(x: f64, y: f64) -> DVec3 {
    PLANE_OFFSET + PLANE_U * x + PLANE_V * y
}

impl Perlin {
    /// Seeded noise on the counter-based lattice.
    pub fn new(seed: u64) -> Self {
        Perlin { lattice: Lattice::Hashed(derive_seed(seed, "perlin")) }
    }

    /// Noise on Perlin's reference permutation: equal to his Java reference implementation.
    pub fn reference() -> Self {
        let mut p = [0u8; 512];
        p[..256].copy_from_slice(&REFERENCE_PERMUTATION);
        p[256..].copy_from_slice(&REFERENCE_PERMUTATION);
        Perlin { lattice: Lattice::Reference(Box::new(p)) }
    }

    /// 3D noise at `p`.
    #[inline(always)]
    pub fn sample3(&self, p: DVec3) -> f64 {
        match &self.lattice {
            Lattice::Reference(perm) => noise3(&Permutation(perm), p.x, p.y, p.z),
            Lattice::Hashed(seed) => noise3(&Hashed(*seed), p.x, p.y, p.z),
        }
    }

    /// 3D noise at several points at once: equal, lane by lane, to [`Perlin::sample3`].
    #[inline(always)]
    pub fn sample3_lanes<const N: usize>(&self, p: [DVec3; N]) -> [f64; N] {
        match &self.lattice {
            Lattice::Reference(perm) => noise3_lanes(&Permutation(perm), p),
            Lattice::Hashed(seed) => noise3_lanes(&Hashed(*seed), p),
        }
    }

    /// 3D noise at every point of `points` into `out` (the same length): four points at a
    /// time through [`Perlin::sample3_lanes`], so each value equals [`Perlin::sample3`]'s bit
    /// for bit.
    ///
    /// # Panics
    /// If `out` and `points` differ in length.
    pub fn sample3_batch(&self, points: &[DVec3], out: &mut [f64]) {
        assert_eq!(points.len(), out.len(), "one output per point");
        match &self.lattice {
            Lattice::Reference(perm) => batch(&Permutation(perm), points, out),
            Lattice::Hashed(seed) => {
                #[cfg(target_arch = "x86_64")]
                let done = super::perlin_avx2::batch_hashed_if_available(*seed, points, out);
                #[cfg(not(target_arch = "x86_64"))]
                let done = 0;
                batch(&Hashed(*seed), &points[done..], &mut out[done..])
            }
        }
    }

    /// fBm over `frequencies` with `gain` at the leading points into `out` by the vector
    /// paths (AVX-512, then AVX2), when the lattice is the seeded one and the CPU has
    /// them; returns how many
    /// points were done (0 otherwise), leaving the rest to the portable path. The sum is
    /// formed as [`super::Fractal::fbm_batch`] forms it, so the values are the same bits.
    pub(super) fn fbm_batch_vectorised(&self, frequencies: &[f64], gain: f64, points: &[DVec3], out: &mut [f64]) -> usize {
        match &self.lattice {
            #[cfg(target_arch = "x86_64")]
            Lattice::Hashed(seed) => {
                super::perlin_avx2::fbm_hashed_if_available(*seed, frequencies, gain, points, out)
            }
            _ => 0,
        }
    }

    /// 2D noise at (x, y): the 3D noise on an oblique plane ([`plane_point`]), so the
    /// image has the 3D noise's statistics in every direction.
    #[inline(always)]
    pub fn sample2(&self, x: f64, y: f64) -> f64 {
        self.sample3(plane_point(x, y))
    }
}

#[cfg(test)]
mod tests {
    use super::{GRADIENTS, PERLIN_PEAK, fade, grad};

    #[test]
    fn the_table_and_the_select_form_agree_up_to_the_sign_of_zero() {
        // The vector path's gradient (Perlin's select form) against the table's product.
        let select = |h: usize, x: f64, y: f64, z: f64| {
            let u = if h < 8 { x } else { y };
            let v = if h < 4 {
                y
            } else if h == 12 || h == 14 {
                x
            } else {
                z
            };
            (if h & 1 == 0 { u } else { -u }) + (if h & 2 == 0 { v } else { -v })
        };
        let values = [0.0, -0.0, 0.3, -0.7, 0.45, -1.0, 1.0, 0.999_999_9];
        for (h, gradient) in GRADIENTS.iter().enumerate() {
            let zeros = gradient.iter().filter(|&&c| c == 0.0).count();
            assert!(zeros == 1 && gradient.iter().all(|&c| c == 0.0 || c.abs() == 1.0), "gradient {h}");
            for &x in &values {
                for &y in &values {
                    for &z in &values {
                        assert_eq!(grad(h + 48, x, y, z), select(h, x, y, z), "gradient {h} at ({x}, {y}, {z})");
                    }
                }
            }
        }
    }

    /// The supremum of Σ_c w_c · (sum of d_c's two largest |components|) over the cell.
    fn corner_bound(p: [f64; 3]) -> f64 {
        let mut total = 0.0;
        for corner in 0..8 {
            let mut weight = 1.0;
            let mut d = [0.0; 3];
            for axis in 0..3 {
                let c = f64::from((corner >> axis) & 1);
                let f = fade(p[axis]);
                weight *= if c > 0.0 { f } else { 1.0 - f };
                d[axis] = (p[axis] - c).abs();
            }
            d.sort_by(f64::total_cmp);
            total += weight * (d[1] + d[2]);
        }
        total
    }

    #[test]
    fn peak_is_the_cell_supremum() {
        let n = 48;
        let mut best = (0.0, [0.0; 3]);
        for i in 0..=n {
            for j in 0..=n {
                for k in 0..=n {
                    let p = [i, j, k].map(|c| f64::from(c) / f64::from(n));
                    let b = corner_bound(p);
                    if b > best.0 {
                        best = (b, p);
                    }
                }
            }
        }
        // Coordinate refinement around the grid's best point.
        let mut step = 1.0 / f64::from(n);
        while step > 1e-7 {
            let mut improved = false;
            for axis in 0..3 {
                for sign in [-1.0, 1.0] {
                    let mut q = best.1;
                    q[axis] = (q[axis] + sign * step).clamp(0.0, 1.0);
                    let b = corner_bound(q);
                    if b > best.0 {
                        best = (b, q);
                        improved = true;
                    }
                }
            }
            if !improved {
                step /= 2.0;
            }
        }
        assert!(best.0 <= PERLIN_PEAK, "supremum {} above PERLIN_PEAK", best.0);
        assert!(best.0 > PERLIN_PEAK - 1e-4, "supremum {} well below PERLIN_PEAK", best.0);
    }
}
