//! Seeded Perlin noise eight points at a time in 512-bit AVX-512 vectors: the widest batch
//! path of [`super::Perlin::sample3_batch`] and [`super::Fractal::fbm_batch`], taken on
//! x86-64 CPUs with AVX-512 F and DQ (checked at run time) before the AVX2 path
//! ([`super::perlin_avx2`]) and the portable one.
//!
//! As on the AVX2 path, every lane performs the operations of the scalar `noise3` in the
//! same order, with no fused multiply-add, and the gradient is Perlin's select form, so
//! each value equals [`super::Perlin::sample3`]'s bit for bit. AVX-512 DQ multiplies 64-bit
//! integers natively (`vpmullq`: the low 64 bits of the product, as the scalar
//! `wrapping_mul`), and converts the floor to an integer exactly, where AVX2 needs three
//! 32-bit products and a magic-number conversion.

#![allow(unsafe_code)]

use std::arch::x86_64::*;

use glam::DVec3;

use super::perlin::{HASH_AXES, HASH_M, noise3_hashed};

/// Lanes with a coordinate this large (or not finite) take the scalar path: the AVX2
/// path's bound, so both vector paths split the same points off.
const LIMIT: f64 = 2_251_799_813_685_248.0; // 2⁵¹

/// Whether this CPU has the AVX-512 subsets the path uses.
fn available() -> bool {
    is_x86_feature_detected!("avx512f") && is_x86_feature_detected!("avx512dq")
}

/// fBm of seeded Perlin noise (Σ gainⁱ·n(p·fᵢ) over `frequencies`, summed in the order
/// [`super::Fractal::fbm_batch`] sums; one frequency of 1 and a gain of 1 give the noise
/// itself, 0 + 1·n = n) into `out`, eight points per step, when this CPU has AVX-512 F and
/// DQ. Returns how many leading points were done: a multiple of eight, or 0 without
/// AVX-512; the caller's paths do the rest.
pub(super) fn fbm_hashed_if_available(
    seed: u64,
    frequencies: &[f64],
    gain: f64,
    points: &[DVec3],
    out: &mut [f64],
) -> usize {
    if !available() {
        return 0;
    }
    // SAFETY: the CPU has AVX-512 F and DQ.
    unsafe { fbm_hashed(seed, frequencies, gain, points, out) }
}

/// # Safety
/// The CPU must support AVX-512 F and DQ.
#[target_feature(enable = "avx512f,avx512dq")]
unsafe fn fbm_hashed(seed: u64, frequencies: &[f64], gain: f64, points: &[DVec3], out: &mut [f64]) -> usize {
    // Gathers of x, y and z from the points' interleaved coordinates (stride 3 doubles).
    let index = _mm512_set_epi64(21, 18, 15, 12, 9, 6, 3, 0);
    for (p, o) in points.chunks_exact(8).zip(out.chunks_exact_mut(8)) {
        let base = p.as_ptr().cast::<f64>();
        // SAFETY: `p` holds eight DVec3 (24 contiguous f64, `glam`'s DVec3 is three f64 in
        // order); the largest index read is 21 + 2 = 23.
        let (x, y, z) = unsafe {
            (
                _mm512_i64gather_pd::<8>(index, base),
                _mm512_i64gather_pd::<8>(index, base.add(1)),
                _mm512_i64gather_pd::<8>(index, base.add(2)),
            )
        };
        let (mut sum, mut amplitude) = (_mm512_setzero_pd(), 1.0);
        for &f in frequencies {
            let s = _mm512_set1_pd(f);
            let (sx, sy, sz) = (_mm512_mul_pd(x, s), _mm512_mul_pd(y, s), _mm512_mul_pd(z, s));
            let n = if in_range(sx) && in_range(sy) && in_range(sz) {
                noise8(seed, sx, sy, sz)
            } else {
                let lanes: [f64; 8] = std::array::from_fn(|l| {
                    let q = p[l] * f;
                    noise3_hashed(seed, q.x, q.y, q.z)
                });
                // SAFETY: `lanes` holds eight f64.
                unsafe { _mm512_loadu_pd(lanes.as_ptr()) }
            };
            sum = _mm512_add_pd(sum, _mm512_mul_pd(_mm512_set1_pd(amplitude), n));
            amplitude *= gain;
        }
        // SAFETY: `o` holds eight f64.
        unsafe { _mm512_storeu_pd(o.as_mut_ptr(), sum) };
    }
    points.len().min(out.len()) / 8 * 8
}

/// Whether every lane is finite and below 2⁵¹ in magnitude.
#[inline]
#[target_feature(enable = "avx512f,avx512dq")]
fn in_range(v: __m512d) -> bool {
    _mm512_cmp_pd_mask::<_CMP_LT_OQ>(_mm512_abs_pd(v), _mm512_set1_pd(LIMIT)) == 0xff
}

/// The floor of each lane as an f64 and as an i64 (lanes below 2⁵¹ in magnitude). The f64
/// is the scalar path's `i as f64`: never −0 (adding +0 turns −0 into +0).
#[inline]
#[target_feature(enable = "avx512f,avx512dq")]
fn floor_parts(v: __m512d) -> (__m512d, __m512i) {
    let floor =
        _mm512_add_pd(_mm512_roundscale_pd::<{ _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC }>(v), _mm512_setzero_pd());
    (floor, _mm512_cvttpd_epi64(floor))
}

/// 6t⁵ − 15t⁴ + 10t³ as the scalar `fade` forms it.
#[inline]
#[target_feature(enable = "avx512f,avx512dq")]
fn fade(t: __m512d) -> __m512d {
    let inner = _mm512_add_pd(
        _mm512_mul_pd(t, _mm512_sub_pd(_mm512_mul_pd(t, _mm512_set1_pd(6.0)), _mm512_set1_pd(15.0))),
        _mm512_set1_pd(10.0),
    );
    _mm512_mul_pd(_mm512_mul_pd(_mm512_mul_pd(t, t), t), inner)
}

/// a + t·(b − a).
#[inline]
#[target_feature(enable = "avx512f,avx512dq")]
fn lerp(t: __m512d, a: __m512d, b: __m512d) -> __m512d {
    _mm512_add_pd(a, _mm512_mul_pd(t, _mm512_sub_pd(b, a)))
}

/// Perlin's select form of `grad` in each lane (see the AVX2 path's `grad`): u = x for
/// h < 8 else y; v = y for h < 4, x for 12 and 14, else z; signed by bits 0 and 1 of h.
#[inline]
#[target_feature(enable = "avx512f,avx512dq")]
fn grad(h: __m512i, x: __m512d, y: __m512d, z: __m512d) -> __m512d {
    let below = |n: i64| _mm512_cmplt_epi64_mask(h, _mm512_set1_epi64(n));
    let equal = |n: i64| _mm512_cmpeq_epi64_mask(h, _mm512_set1_epi64(n));
    let u = _mm512_mask_blend_pd(below(8), y, x);
    let w = _mm512_mask_blend_pd(equal(12) | equal(14), z, x);
    let v = _mm512_mask_blend_pd(below(4), w, y);
    let sign_u = _mm512_castsi512_pd(_mm512_slli_epi64::<63>(h));
    let sign_v = _mm512_castsi512_pd(_mm512_slli_epi64::<63>(_mm512_srli_epi64::<1>(h)));
    _mm512_add_pd(_mm512_xor_pd(u, sign_u), _mm512_xor_pd(v, sign_v))
}

/// Noise at eight points (lanes in range).
#[inline]
#[target_feature(enable = "avx512f,avx512dq")]
fn noise8(seed: u64, x: __m512d, y: __m512d, z: __m512d) -> __m512d {
    let one = _mm512_set1_pd(1.0);
    let (fx, ix) = floor_parts(x);
    let (fy, iy) = floor_parts(y);
    let (fz, iz) = floor_parts(z);
    let (x0, y0, z0) = (_mm512_sub_pd(x, fx), _mm512_sub_pd(y, fy), _mm512_sub_pd(z, fz));
    let (x1, y1, z1) = (_mm512_sub_pd(x0, one), _mm512_sub_pd(y0, one), _mm512_sub_pd(z0, one));
    let (u, v, w) = (fade(x0), fade(y0), fade(z0));
    let axis = |i: __m512i, a: usize| {
        let c = _mm512_set1_epi64(HASH_AXES[a] as i64);
        let first = _mm512_mullo_epi64(i, c);
        [first, _mm512_add_epi64(first, c)]
    };
    let (hx, hy, hz) = (axis(ix, 0), axis(iy, 1), axis(iz, 2));
    let seed = _mm512_set1_epi64(seed as i64);
    let m = _mm512_set1_epi64(HASH_M as i64);
    let corner = |dx: usize, dy: usize, dz: usize| {
        let h = _mm512_xor_si512(_mm512_xor_si512(_mm512_xor_si512(seed, hx[dx]), hy[dy]), hz[dz]);
        let g = _mm512_srli_epi64::<60>(_mm512_mullo_epi64(h, m));
        grad(g, [x0, x1][dx], [y0, y1][dy], [z0, z1][dz])
    };
    let noise = lerp(
        w,
        lerp(v, lerp(u, corner(0, 0, 0), corner(1, 0, 0)), lerp(u, corner(0, 1, 0), corner(1, 1, 0))),
        lerp(v, lerp(u, corner(0, 0, 1), corner(1, 0, 1)), lerp(u, corner(0, 1, 1), corner(1, 1, 1))),
    );
    _mm512_add_pd(noise, _mm512_setzero_pd())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The AVX-512 kernel on points in range, past 2⁵¹ and not finite, against the scalar
    /// noise bit for bit.
    #[test]
    fn the_avx512_kernel_is_the_scalar_noise() {
        let points = super::super::test_points();
        let frequencies = [1.0, 1.9, 3.61];
        let mut out = vec![0.0; points.len()];
        if !available() {
            // Without AVX-512 F and DQ this path leaves every point to the others.
            assert_eq!(fbm_hashed_if_available(7, &frequencies, 0.5, &points, &mut out), 0);
            return;
        }
        // SAFETY: the CPU has AVX-512 F and DQ.
        let done = unsafe { fbm_hashed(7, &frequencies, 0.5, &points, &mut out) };
        assert_eq!(done, points.len() / 8 * 8);
        for (p, v) in points.iter().zip(&out).take(done) {
            let expected = super::super::fbm_reference(7, &frequencies, 0.5, *p);
            assert_eq!(v.to_bits(), expected.to_bits(), "at {p}");
        }
    }
}
