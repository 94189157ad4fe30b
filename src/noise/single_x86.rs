//! The single-precision noise of [`super::single`] sixteen points at a time in AVX-512 F
//! vectors, or eight in AVX2 ones (whichever the CPU has, checked at run time): every lane
//! performs the scalar [`super::single::noise3`]'s operations in the same order — clamp,
//! floor, fade, the 32-bit hash's native products, the select-form gradient, the lerps —
//! with no fused multiply-add, so each value is the scalar one's bits (NaN coordinates give
//! NaN, whose sign the paths may differ in).

#![allow(unsafe_code)]

use std::arch::x86_64::*;

use super::single::{AXES, LIMIT, MIX};

/// Noise at the leading points (`xs[i]`, `ys[i]`, `zs[i]`) into `out`, by the widest path this
/// CPU has; returns how many were done (the rest, fewer than a vector, is the caller's).
pub(super) fn noise_if_available(seed: u32, xs: &[f32], ys: &[f32], zs: &[f32], out: &mut [f32]) -> usize {
    let n = out.len().min(xs.len()).min(ys.len()).min(zs.len());
    let mut done = 0;
    if is_x86_feature_detected!("avx512f") {
        // SAFETY: the CPU has AVX-512 F.
        done = unsafe { noise16(seed, &xs[..n], &ys[..n], &zs[..n], &mut out[..n]) };
    }
    if is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2.
        done += unsafe { noise8(seed, &xs[done..n], &ys[done..n], &zs[done..n], &mut out[done..n]) };
    }
    done
}

/// # Safety
/// The CPU must support AVX-512 F.
#[target_feature(enable = "avx512f")]
unsafe fn noise16(seed: u32, xs: &[f32], ys: &[f32], zs: &[f32], out: &mut [f32]) -> usize {
    let count = out.len().min(xs.len()).min(ys.len()).min(zs.len()) / 16 * 16;
    for i in (0..count).step_by(16) {
        // SAFETY: i + 16 <= the slices' common length.
        unsafe {
            let v = lanes16(
                seed,
                _mm512_loadu_ps(xs.as_ptr().add(i)),
                _mm512_loadu_ps(ys.as_ptr().add(i)),
                _mm512_loadu_ps(zs.as_ptr().add(i)),
            );
            _mm512_storeu_ps(out.as_mut_ptr().add(i), v);
        }
    }
    count
}

#[inline]
#[target_feature(enable = "avx512f")]
fn lanes16(seed: u32, x: __m512, y: __m512, z: __m512) -> __m512 {
    let (lo, hi) = (_mm512_set1_ps(-LIMIT), _mm512_set1_ps(LIMIT));
    // max(−L, v) then min(L, ·): a NaN lane keeps its NaN (the second operand wins).
    let clamp = |v: __m512| _mm512_min_ps(hi, _mm512_max_ps(lo, v));
    let (x, y, z) = (clamp(x), clamp(y), clamp(z));
    let floor = |v: __m512| _mm512_roundscale_ps::<{ _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC }>(v);
    let (fx, fy, fz) = (floor(x), floor(y), floor(z));
    let (x0, y0, z0) = (_mm512_sub_ps(x, fx), _mm512_sub_ps(y, fy), _mm512_sub_ps(z, fz));
    let one = _mm512_set1_ps(1.0);
    let (x1, y1, z1) = (_mm512_sub_ps(x0, one), _mm512_sub_ps(y0, one), _mm512_sub_ps(z0, one));
    let fade = |t: __m512| {
        let inner = _mm512_add_ps(
            _mm512_mul_ps(t, _mm512_sub_ps(_mm512_mul_ps(t, _mm512_set1_ps(6.0)), _mm512_set1_ps(15.0))),
            _mm512_set1_ps(10.0),
        );
        _mm512_mul_ps(_mm512_mul_ps(_mm512_mul_ps(t, t), t), inner)
    };
    let (u, v, w) = (fade(x0), fade(y0), fade(z0));
    let axis = |f: __m512, a: usize| {
        let c = _mm512_set1_epi32(AXES[a] as i32);
        let first = _mm512_mullo_epi32(_mm512_cvttps_epi32(f), c);
        [first, _mm512_add_epi32(first, c)]
    };
    let (hx, hy, hz) = (axis(fx, 0), axis(fy, 1), axis(fz, 2));
    let (seed, mix) = (_mm512_set1_epi32(seed as i32), _mm512_set1_epi32(MIX as i32));
    let grad = |h: __m512i, x: __m512, y: __m512, z: __m512| {
        let below = |n: i32| _mm512_cmplt_epu32_mask(h, _mm512_set1_epi32(n));
        let equal = |n: i32| _mm512_cmpeq_epi32_mask(h, _mm512_set1_epi32(n));
        let u = _mm512_mask_blend_ps(below(8), y, x);
        let w = _mm512_mask_blend_ps(equal(12) | equal(14), z, x);
        let v = _mm512_mask_blend_ps(below(4), w, y);
        // Sign flips as integer xors (the float xor is AVX-512 DQ's).
        let signed = |a: __m512, sign: __m512i| _mm512_castsi512_ps(_mm512_xor_si512(_mm512_castps_si512(a), sign));
        let sign_u = _mm512_slli_epi32::<31>(h);
        let sign_v = _mm512_slli_epi32::<31>(_mm512_srli_epi32::<1>(h));
        _mm512_add_ps(signed(u, sign_u), signed(v, sign_v))
    };
    let corner = |dx: usize, dy: usize, dz: usize| {
        let h = _mm512_xor_si512(_mm512_xor_si512(_mm512_xor_si512(seed, hx[dx]), hy[dy]), hz[dz]);
        grad(_mm512_srli_epi32::<28>(_mm512_mullo_epi32(h, mix)), [x0, x1][dx], [y0, y1][dy], [z0, z1][dz])
    };
    let lerp = |t: __m512, a: __m512, b: __m512| _mm512_add_ps(a, _mm512_mul_ps(t, _mm512_sub_ps(b, a)));
    let noise = lerp(
        w,
        lerp(v, lerp(u, corner(0, 0, 0), corner(1, 0, 0)), lerp(u, corner(0, 1, 0), corner(1, 1, 0))),
        lerp(v, lerp(u, corner(0, 0, 1), corner(1, 0, 1)), lerp(u, corner(0, 1, 1), corner(1, 1, 1))),
    );
    _mm512_add_ps(noise, _mm512_setzero_ps())
}

/// # Safety
/// The CPU must support AVX2.
#[target_feature(enable = "avx2")]
unsafe fn noise8(seed: u32, xs: &[f32], ys: &[f32], zs: &[f32], out: &mut [f32]) -> usize {
    let count = out.len().min(xs.len()).min(ys.len()).min(zs.len()) / 8 * 8;
    for i in (0..count).step_by(8) {
        // SAFETY: i + 8 <= the slices' common length.
        unsafe {
            let v = lanes8(
                seed,
                _mm256_loadu_ps(xs.as_ptr().add(i)),
                _mm256_loadu_ps(ys.as_ptr().add(i)),
                _mm256_loadu_ps(zs.as_ptr().add(i)),
            );
            _mm256_storeu_ps(out.as_mut_ptr().add(i), v);
        }
    }
    count
}

#[inline]
#[target_feature(enable = "avx2")]
fn lanes8(seed: u32, x: __m256, y: __m256, z: __m256) -> __m256 {
    let (lo, hi) = (_mm256_set1_ps(-LIMIT), _mm256_set1_ps(LIMIT));
    let clamp = |v: __m256| _mm256_min_ps(hi, _mm256_max_ps(lo, v));
    let (x, y, z) = (clamp(x), clamp(y), clamp(z));
    let (fx, fy, fz) = (_mm256_floor_ps(x), _mm256_floor_ps(y), _mm256_floor_ps(z));
    let (x0, y0, z0) = (_mm256_sub_ps(x, fx), _mm256_sub_ps(y, fy), _mm256_sub_ps(z, fz));
    let one = _mm256_set1_ps(1.0);
    let (x1, y1, z1) = (_mm256_sub_ps(x0, one), _mm256_sub_ps(y0, one), _mm256_sub_ps(z0, one));
    let fade = |t: __m256| {
        let inner = _mm256_add_ps(
            _mm256_mul_ps(t, _mm256_sub_ps(_mm256_mul_ps(t, _mm256_set1_ps(6.0)), _mm256_set1_ps(15.0))),
            _mm256_set1_ps(10.0),
        );
        _mm256_mul_ps(_mm256_mul_ps(_mm256_mul_ps(t, t), t), inner)
    };
    let (u, v, w) = (fade(x0), fade(y0), fade(z0));
    let axis = |f: __m256, a: usize| {
        let c = _mm256_set1_epi32(AXES[a] as i32);
        let first = _mm256_mullo_epi32(_mm256_cvttps_epi32(f), c);
        [first, _mm256_add_epi32(first, c)]
    };
    let (hx, hy, hz) = (axis(fx, 0), axis(fy, 1), axis(fz, 2));
    let (seed, mix) = (_mm256_set1_epi32(seed as i32), _mm256_set1_epi32(MIX as i32));
    let grad = |h: __m256i, x: __m256, y: __m256, z: __m256| {
        // h is below 16, so signed comparisons order it as unsigned ones would.
        let below = |n: i32| _mm256_castsi256_ps(_mm256_cmpgt_epi32(_mm256_set1_epi32(n), h));
        let equal = |n: i32| _mm256_castsi256_ps(_mm256_cmpeq_epi32(h, _mm256_set1_epi32(n)));
        let u = _mm256_blendv_ps(y, x, below(8));
        let w = _mm256_blendv_ps(z, x, _mm256_or_ps(equal(12), equal(14)));
        let v = _mm256_blendv_ps(w, y, below(4));
        let sign_u = _mm256_castsi256_ps(_mm256_slli_epi32::<31>(h));
        let sign_v = _mm256_castsi256_ps(_mm256_slli_epi32::<31>(_mm256_srli_epi32::<1>(h)));
        _mm256_add_ps(_mm256_xor_ps(u, sign_u), _mm256_xor_ps(v, sign_v))
    };
    let corner = |dx: usize, dy: usize, dz: usize| {
        let h = _mm256_xor_si256(_mm256_xor_si256(_mm256_xor_si256(seed, hx[dx]), hy[dy]), hz[dz]);
        grad(_mm256_srli_epi32::<28>(_mm256_mullo_epi32(h, mix)), [x0, x1][dx], [y0, y1][dy], [z0, z1][dz])
    };
    let lerp = |t: __m256, a: __m256, b: __m256| _mm256_add_ps(a, _mm256_mul_ps(t, _mm256_sub_ps(b, a)));
    let noise = lerp(
        w,
        lerp(v, lerp(u, corner(0, 0, 0), corner(1, 0, 0)), lerp(u, corner(0, 1, 0), corner(1, 1, 0))),
        lerp(v, lerp(u, corner(0, 0, 1), corner(1, 0, 1)), lerp(u, corner(0, 1, 1), corner(1, 1, 1))),
    );
    _mm256_add_ps(noise, _mm256_setzero_ps())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Both kernels alone against the scalar definition, on points in range, beyond 2²⁴,
    /// infinite and NaN.
    #[test]
    fn the_vector_kernels_are_the_scalar_noise() {
        let mut rng = super::super::hash::Stream::new(5);
        let mut coordinates: Vec<[f32; 3]> = (0..1003)
            .map(|_| std::array::from_fn(|a| rng.uniform(-400.0, 400.0) as f32 * if a == 2 { 0.01 } else { 1.0 }))
            .collect();
        coordinates[10] = [3e7, 0.5, -0.25];
        coordinates[21] = [0.5, f32::INFINITY, 2.0];
        coordinates[32] = [f32::NAN, 0.5, 2.0];
        coordinates[43] = [-0.0, 0.0, -7.0];
        coordinates[54] = [-3e9, 1.5, 2.25];
        let xs: Vec<f32> = coordinates.iter().map(|c| c[0]).collect();
        let ys: Vec<f32> = coordinates.iter().map(|c| c[1]).collect();
        let zs: Vec<f32> = coordinates.iter().map(|c| c[2]).collect();
        let same = |a: f32, b: f32| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan());
        let mut checked = 0;
        type Kernel = unsafe fn(u32, &[f32], &[f32], &[f32], &mut [f32]) -> usize;
        let kernels: [(&str, bool, Kernel); 2] = [
            ("AVX-512", is_x86_feature_detected!("avx512f"), noise16),
            ("AVX2", is_x86_feature_detected!("avx2"), noise8),
        ];
        for (name, available, kernel) in kernels {
            if !available {
                continue;
            }
            let mut out = vec![0.0f32; xs.len()];
            // SAFETY: the CPU has the kernel's instructions.
            let done = unsafe { kernel(9, &xs, &ys, &zs, &mut out) };
            for i in 0..done {
                let expected = super::super::single::noise3(9, xs[i], ys[i], zs[i]);
                assert!(same(out[i], expected), "{name} at {:?}: {} vs {expected}", coordinates[i], out[i]);
            }
            checked += done;
        }
        // Without either kernel the dispatcher leaves every point to the scalar path.
        let mut out = vec![0.0f32; xs.len()];
        let done = noise_if_available(9, &xs, &ys, &zs, &mut out);
        assert_eq!(done == 0, checked == 0);
    }
}
