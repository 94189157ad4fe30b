//! Seeded Perlin noise four points at a time in 256-bit AVX2 vectors: the batch paths of
//! [`super::Perlin::sample3_batch`] and [`super::Fractal::fbm_batch`] on x86-64 CPUs that
//! have AVX2 (checked at run time), for the points the AVX-512 path
//! ([`super::perlin_avx512`]) leaves (all of them on CPUs without it).
//!
//! Every lane performs the operations of the scalar `noise3` on the hashed lattice in the
//! same order — floor, fade, the per-axis hash parts, the corner hash's 64-bit product,
//! the lerps — with no fused multiply-add; the gradient is Perlin's select form, equal to
//! the scalar table's product up to the sign of an exact zero, which both paths remove by
//! adding +0 to their result. So each value equals [`super::Perlin::sample3`]'s bit for
//! bit. AVX2 has no 64-bit multiply; [`mul_lo64`] forms the low 64 bits of the product
//! from three 32-bit ones, exactly.

#![allow(unsafe_code)]

use std::arch::x86_64::*;

use glam::DVec3;

use super::perlin::{HASH_AXES, HASH_M, noise3_hashed};

/// 2⁵² + 2⁵¹: added to an integral f64 below 2⁵¹ in magnitude, its low 52 bits become the
/// integer's two's complement (Hacker's Delight's conversion trick).
const MAGIC: f64 = 6_755_399_441_055_744.0;
/// Lanes with a coordinate this large (or not finite) take the scalar path.
const LIMIT: f64 = 2_251_799_813_685_248.0; // 2⁵¹

/// Seeded Perlin noise at the leading points into `out` when this CPU has AVX2: the
/// one-octave sum of [`fbm_hashed_if_available`], whose 0 + 1·n is n itself. Returns how
/// many points were done (see there).
pub(super) fn batch_hashed_if_available(seed: u64, points: &[DVec3], out: &mut [f64]) -> usize {
    fbm_hashed_if_available(seed, &[1.0], 1.0, points, out)
}

/// fBm of seeded Perlin noise (Σ gainⁱ·n(p·fᵢ) over `frequencies`, summed in the order
/// [`super::Fractal::fbm_batch`] sums) into `out`, four points per step, when this CPU has
/// AVX2; an octave whose scaled coordinates are beyond 2⁵¹ or not finite is evaluated by
/// the scalar path. The AVX-512 path ([`super::perlin_avx512`]) takes the leading points
/// where the CPU has it. Returns how many leading points were done: a multiple of four, or
/// 0 without AVX2 or AVX-512; the caller's own path does the rest.
pub(super) fn fbm_hashed_if_available(
    seed: u64,
    frequencies: &[f64],
    gain: f64,
    points: &[DVec3],
    out: &mut [f64],
) -> usize {
    // The AVX-512 path first, eight points at a time; this path takes the points it left.
    let wide = super::perlin_avx512::fbm_hashed_if_available(seed, frequencies, gain, points, out);
    if !is_x86_feature_detected!("avx2") {
        return wide;
    }
    // SAFETY: the CPU has AVX2.
    wide + unsafe { fbm_hashed(seed, frequencies, gain, &points[wide..], &mut out[wide..]) }
}

/// # Safety
/// The CPU must support AVX2.
#[target_feature(enable = "avx2")]
unsafe fn fbm_hashed(seed: u64, frequencies: &[f64], gain: f64, points: &[DVec3], out: &mut [f64]) -> usize {
    for (p, o) in points.chunks_exact(4).zip(out.chunks_exact_mut(4)) {
        let x = _mm256_set_pd(p[3].x, p[2].x, p[1].x, p[0].x);
        let y = _mm256_set_pd(p[3].y, p[2].y, p[1].y, p[0].y);
        let z = _mm256_set_pd(p[3].z, p[2].z, p[1].z, p[0].z);
        let (mut sum, mut amplitude) = (_mm256_setzero_pd(), 1.0);
        for &f in frequencies {
            let s = _mm256_set1_pd(f);
            let (sx, sy, sz) = (_mm256_mul_pd(x, s), _mm256_mul_pd(y, s), _mm256_mul_pd(z, s));
            let n = if in_range(sx) && in_range(sy) && in_range(sz) {
                noise4(seed, sx, sy, sz)
            } else {
                let mut lanes = [0.0; 4];
                for (l, q) in p.iter().enumerate() {
                    let q = *q * f;
                    lanes[l] = noise3_hashed(seed, q.x, q.y, q.z);
                }
                _mm256_set_pd(lanes[3], lanes[2], lanes[1], lanes[0])
            };
            sum = _mm256_add_pd(sum, _mm256_mul_pd(_mm256_set1_pd(amplitude), n));
            amplitude *= gain;
        }
        // SAFETY: `o` holds four f64.
        unsafe { _mm256_storeu_pd(o.as_mut_ptr(), sum) };
    }
    points.len().min(out.len()) / 4 * 4
}

/// Whether every lane is finite and below 2⁵¹ in magnitude.
#[inline]
#[target_feature(enable = "avx2")]
fn in_range(v: __m256d) -> bool {
    let abs = _mm256_andnot_pd(_mm256_set1_pd(-0.0), v);
    _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_LT_OQ>(abs, _mm256_set1_pd(LIMIT))) == 0b1111
}

/// The low 64 bits of `a · c` in each lane, c given as its 32-bit halves.
#[inline]
#[target_feature(enable = "avx2")]
fn mul_lo64(a: __m256i, c_lo: __m256i, c_hi: __m256i) -> __m256i {
    let low = _mm256_mul_epu32(a, c_lo);
    let cross = _mm256_add_epi64(_mm256_mul_epu32(a, c_hi), _mm256_mul_epu32(_mm256_srli_epi64::<32>(a), c_lo));
    _mm256_add_epi64(low, _mm256_slli_epi64::<32>(cross))
}

/// A 64-bit constant as the two 32-bit halves [`mul_lo64`] takes.
#[inline]
#[target_feature(enable = "avx2")]
fn halves(c: u64) -> (__m256i, __m256i) {
    (_mm256_set1_epi64x((c & 0xffff_ffff) as i64), _mm256_set1_epi64x((c >> 32) as i64))
}

/// The floor of each lane as an f64 and as an i64 (lanes below 2⁵¹ in magnitude). The
/// f64 is the scalar path's `i as f64`: never −0 (adding +0 turns −0 into +0), so the
/// fraction of −0 is −0 − 0 = −0 on both paths.
#[inline]
#[target_feature(enable = "avx2")]
fn floor_parts(v: __m256d) -> (__m256d, __m256i) {
    let floor = _mm256_add_pd(_mm256_floor_pd(v), _mm256_setzero_pd());
    let magic = _mm256_set1_pd(MAGIC);
    let int = _mm256_sub_epi64(_mm256_castpd_si256(_mm256_add_pd(floor, magic)), _mm256_castpd_si256(magic));
    (floor, int)
}

/// 6t⁵ − 15t⁴ + 10t³ as the scalar `fade` forms it.
#[inline]
#[target_feature(enable = "avx2")]
fn fade(t: __m256d) -> __m256d {
    let inner = _mm256_add_pd(
        _mm256_mul_pd(t, _mm256_sub_pd(_mm256_mul_pd(t, _mm256_set1_pd(6.0)), _mm256_set1_pd(15.0))),
        _mm256_set1_pd(10.0),
    );
    _mm256_mul_pd(_mm256_mul_pd(_mm256_mul_pd(t, t), t), inner)
}

/// a + t·(b − a).
#[inline]
#[target_feature(enable = "avx2")]
fn lerp(t: __m256d, a: __m256d, b: __m256d) -> __m256d {
    _mm256_add_pd(a, _mm256_mul_pd(t, _mm256_sub_pd(b, a)))
}

/// Perlin's select form of `grad` in each lane: u = x for h < 8 else y; v = y for h < 4,
/// x for 12 and 14, else z; signed by bits 0 and 1 of h; u + v. The scalar path's table
/// form gives the same value up to the sign of an exact zero, which the final + 0 of both
/// paths removes.
#[inline]
#[target_feature(enable = "avx2")]
fn grad(h: __m256i, x: __m256d, y: __m256d, z: __m256d) -> __m256d {
    let below = |n: i64| _mm256_castsi256_pd(_mm256_cmpgt_epi64(_mm256_set1_epi64x(n), h));
    let equal = |n: i64| _mm256_castsi256_pd(_mm256_cmpeq_epi64(h, _mm256_set1_epi64x(n)));
    let u = _mm256_blendv_pd(y, x, below(8));
    let w = _mm256_blendv_pd(z, x, _mm256_or_pd(equal(12), equal(14)));
    let v = _mm256_blendv_pd(w, y, below(4));
    let sign_u = _mm256_castsi256_pd(_mm256_slli_epi64::<63>(h));
    let sign_v = _mm256_castsi256_pd(_mm256_slli_epi64::<63>(_mm256_srli_epi64::<1>(h)));
    _mm256_add_pd(_mm256_xor_pd(u, sign_u), _mm256_xor_pd(v, sign_v))
}

/// Noise at four points (lanes in range).
#[inline]
#[target_feature(enable = "avx2")]
fn noise4(seed: u64, x: __m256d, y: __m256d, z: __m256d) -> __m256d {
    let one = _mm256_set1_pd(1.0);
    let (fx, ix) = floor_parts(x);
    let (fy, iy) = floor_parts(y);
    let (fz, iz) = floor_parts(z);
    let (x0, y0, z0) = (_mm256_sub_pd(x, fx), _mm256_sub_pd(y, fy), _mm256_sub_pd(z, fz));
    let (x1, y1, z1) = (_mm256_sub_pd(x0, one), _mm256_sub_pd(y0, one), _mm256_sub_pd(z0, one));
    let (u, v, w) = (fade(x0), fade(y0), fade(z0));
    let axis = |i: __m256i, a: usize| {
        let (lo, hi) = halves(HASH_AXES[a]);
        let first = mul_lo64(i, lo, hi);
        [first, _mm256_add_epi64(first, _mm256_set1_epi64x(HASH_AXES[a] as i64))]
    };
    let (hx, hy, hz) = (axis(ix, 0), axis(iy, 1), axis(iz, 2));
    let seed = _mm256_set1_epi64x(seed as i64);
    let (m_lo, m_hi) = halves(HASH_M);
    let corner = |dx: usize, dy: usize, dz: usize| {
        let h = _mm256_xor_si256(_mm256_xor_si256(_mm256_xor_si256(seed, hx[dx]), hy[dy]), hz[dz]);
        let g = _mm256_srli_epi64::<60>(mul_lo64(h, m_lo, m_hi));
        grad(g, [x0, x1][dx], [y0, y1][dy], [z0, z1][dz])
    };
    let noise = lerp(
        w,
        lerp(v, lerp(u, corner(0, 0, 0), corner(1, 0, 0)), lerp(u, corner(0, 1, 0), corner(1, 1, 0))),
        lerp(v, lerp(u, corner(0, 0, 1), corner(1, 0, 1)), lerp(u, corner(0, 1, 1), corner(1, 1, 1))),
    );
    _mm256_add_pd(noise, _mm256_setzero_pd())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The AVX2 kernel alone (a CPU with AVX-512 gives the batch to that path first), on
    /// points in range, past 2⁵¹ and not finite, against the scalar noise bit for bit.
    #[test]
    fn the_avx2_kernel_is_the_scalar_noise() {
        let points = super::super::test_points();
        let frequencies = [1.0, 1.9, 3.61];
        let mut out = vec![0.0; points.len()];
        if !is_x86_feature_detected!("avx2") {
            // Without AVX2 (so without AVX-512) the vector paths leave every point.
            assert_eq!(fbm_hashed_if_available(7, &frequencies, 0.5, &points, &mut out), 0);
            return;
        }
        // SAFETY: the CPU has AVX2.
        let done = unsafe { fbm_hashed(7, &frequencies, 0.5, &points, &mut out) };
        assert_eq!(done, points.len() / 4 * 4);
        for (p, v) in points.iter().zip(&out).take(done) {
            let expected = super::super::fbm_reference(7, &frequencies, 0.5, *p);
            assert_eq!(v.to_bits(), expected.to_bits(), "at {p}");
        }
    }
}
