//! Noise: Perlin's reference values, continuity, ranges, Gabor spectra and variance,
//! determinism across thread counts.

use std::f64::consts::PI;

use asperity::noise::{
    Fractal, FractalKind, Frame, Gabor, GaborParams, NoiseField, NoiseKind, NoiseSpec, Perlin, Profile, ScaledPerlin,
    hash::Stream, plane_point,
};
use glam::{DVec2, DVec3};
use rustfft::{FftPlanner, num_complex::Complex};

/// Values of Perlin's Java reference implementation (ImprovedNoise.noise), computed by
/// running it; pinned here. (3.14, 42, 7) is Perlin's own test point, not π.
#[allow(clippy::approx_constant)]
const REFERENCE: [([f64; 3], f64); 10] = [
    ([3.14, 42.0, 7.0], 0.13691995878400012),
    ([0.5, 0.5, 0.5], -0.25),
    ([1.25, -2.75, 3.5], 0.12009716033935547),
    ([-7.3, 0.01, 12.9], -0.3855792111813221),
    ([100.123, 200.456, -300.789], -0.16139695712834895),
    ([0.1, 0.2, 0.0], 0.04510399999999999),
    ([5.5, -1.25, 0.0], -0.185302734375),
    ([17.77, 3.3, 0.42], 0.17787886387614504),
    ([-0.999, -0.001, 0.333], -0.14144905553222412),
    ([255.5, 256.5, 257.5], 0.0),
];

#[test]
fn reference_permutation_reproduces_perlins_implementation() {
    let perlin = Perlin::reference();
    for ([x, y, z], expected) in REFERENCE {
        let got = perlin.sample3(DVec3::new(x, y, z));
        assert!((got - expected).abs() <= 1e-12, "noise({x}, {y}, {z}) = {got}, reference {expected}");
        assert_eq!(perlin.sample2(x, y), perlin.sample3(plane_point(x, y)), "2D is the oblique plane's slice");
    }
}

fn random_points(n: usize, scale: f64, seed: u64) -> Vec<DVec3> {
    let mut rng = Stream::new(seed);
    (0..n)
        .map(|_| DVec3::new(rng.uniform(-scale, scale), rng.uniform(-scale, scale), rng.uniform(-scale, scale)))
        .collect()
}

#[test]
fn seeded_perlin_is_bounded_aperiodic_and_seed_dependent() {
    let a = Perlin::new(7);
    let b = Perlin::new(8);
    let points = random_points(50_000, 100.0, 1);
    let mut differs = 0;
    for p in &points {
        let v = a.sample3(*p);
        assert!(v.abs() <= 1.1, "3D value {v} at {p}");
        assert!(a.sample2(p.x, p.y).abs() <= 1.05);
        if (v - b.sample3(*p)).abs() > 1e-3 {
            differs += 1;
        }
    }
    assert!(differs > points.len() * 9 / 10, "seeds must give different noise");
    // The reference lattice repeats every 256 units; the hashed one must not.
    let reference = Perlin::reference();
    let p = points[0];
    assert!((reference.sample3(p) - reference.sample3(p + DVec3::X * 256.0)).abs() < 1e-12);
    let period_matches =
        points.iter().filter(|p| (a.sample3(**p) - a.sample3(**p + DVec3::X * 256.0)).abs() < 1e-12).count();
    assert!(period_matches < points.len() / 100, "{period_matches} values repeat with period 256");
}

#[test]
fn far_coordinates_still_give_full_noise() {
    let perlin = Perlin::new(3);
    let values: Vec<f64> =
        random_points(20_000, 0.5, 2).iter().map(|p| perlin.sample3(*p * 200.0 + DVec3::splat(1e6))).collect();
    let mean = values.iter().sum::<f64>() / values.len() as f64;
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / values.len() as f64;
    assert!(var > 0.02, "variance {var} at 1e6");
}

#[test]
fn value_and_gradient_are_continuous_across_cells() {
    let perlin = Perlin::new(11);
    let eps = 1e-7;
    let h = 1e-4;
    let mut rng = Stream::new(5);
    for _ in 0..2000 {
        let axis = [DVec3::X, DVec3::Y, DVec3::Z][(rng.next_u64() % 3) as usize];
        let base = DVec3::new(rng.uniform(-50.0, 50.0), rng.uniform(-50.0, 50.0), rng.uniform(-50.0, 50.0));
        // Put the point on a lattice plane of the chosen axis.
        let on = base - axis * base.dot(axis) + axis * base.dot(axis).round();
        let left = perlin.sample3(on - axis * eps);
        let right = perlin.sample3(on + axis * eps);
        assert!((left - right).abs() < 1e-5, "value jump {} at {on}", (left - right).abs());
        // One-sided derivatives agree: the noise is C¹ (the quintic fade makes it C²).
        let d_left = (perlin.sample3(on) - perlin.sample3(on - axis * h)) / h;
        let d_right = (perlin.sample3(on + axis * h) - perlin.sample3(on)) / h;
        assert!((d_left - d_right).abs() < 1e-2, "derivative jump {d_left} vs {d_right} at {on}");
    }
}

#[test]
fn fractal_sums_have_their_ranges_and_identities() {
    let basis = Perlin::new(4);
    let points = random_points(5_000, 20.0, 9);
    let eval = |kind: FractalKind, octaves: u32, p: DVec3| {
        Fractal { kind, octaves, ..Fractal::default() }.eval(p.x, |s| basis.sample3(p * s))
    };
    for p in &points {
        assert_eq!(eval(FractalKind::Fbm, 1, *p), basis.sample3(*p));
        let fbm = eval(FractalKind::Fbm, 8, *p);
        assert!(fbm.abs() <= 2.2);
        let turbulence = eval(FractalKind::Turbulence, 8, *p);
        assert!((0.0..=2.2).contains(&turbulence));
        assert!((0.0..=1.0).contains(&eval(FractalKind::Marble, 6, *p)));
        assert!((0.0..1.0).contains(&eval(FractalKind::Wood, 4, *p)));
        assert!(eval(FractalKind::Multifractal, 6, *p) >= 0.0);
    }
    let level = Fractal::default().for_level(3);
    assert!((level.lacunarity - 1.5).abs() < 1e-15 && (level.gain - 0.2).abs() < 1e-15);
}

#[test]
fn paired_octaves_equal_octave_by_octave_evaluation() {
    // ScaledPerlin evaluates two octaves at once through Perlin::sample3_lanes; a closure
    // evaluates them one by one. Every kind and octave count must give the same bits,
    // on both lattices, including coordinates far from the origin.
    for basis in [Perlin::new(11), Perlin::reference()] {
        for p in random_points(300, 1e5, 12) {
            for kind in [
                FractalKind::Fbm,
                FractalKind::Turbulence,
                FractalKind::Marble,
                FractalKind::Multifractal,
                FractalKind::Wood,
            ] {
                for octaves in 1..=9 {
                    let fractal = Fractal { kind, octaves, lacunarity: 1.9, ..Fractal::default() };
                    let paired = fractal.eval(p.x, ScaledPerlin { perlin: &basis, point: p });
                    let single = fractal.eval(p.x, |s| basis.sample3(p * s));
                    assert_eq!(paired.to_bits(), single.to_bits(), "{kind:?}, {octaves} octaves at {p}");
                }
            }
            let lanes = basis.sample3_lanes([p, p * 0.5, -p]);
            assert_eq!(lanes, [basis.sample3(p), basis.sample3(p * 0.5), basis.sample3(-p)]);
        }
    }
}

/// Power spectrum of a square image (|FFT|², DC removed), indexed [row][col] with
/// frequencies centred: bin (u, v) is at fx = u/n, fy = v/n for u, v in −n/2..n/2.
fn power_spectrum(image: &[f64], n: usize) -> Vec<f64> {
    let mut data: Vec<Complex<f64>> = image.iter().map(|&v| Complex::new(v, 0.0)).collect();
    let fft = FftPlanner::new().plan_fft_forward(n);
    for row in data.chunks_mut(n) {
        fft.process(row);
    }
    let mut column = vec![Complex::new(0.0, 0.0); n];
    for c in 0..n {
        for r in 0..n {
            column[r] = data[r * n + c];
        }
        fft.process(&mut column);
        for r in 0..n {
            data[r * n + c] = column[r];
        }
    }
    let mut power: Vec<f64> = data.iter().map(|z| z.norm_sqr()).collect();
    power[0] = 0.0;
    power
}

fn frequency(bin: usize, n: usize) -> f64 {
    if bin < n / 2 { bin as f64 / n as f64 } else { bin as f64 / n as f64 - 1.0 }
}

/// The centroid of a power spectrum's lobe on the half-plane facing `omega` (the spectrum
/// is symmetric), as (radius, angle).
fn lobe_centroid(power: &[f64], n: usize, omega: f64) -> (f64, f64) {
    let dir = (omega.cos(), omega.sin());
    let (mut sx, mut sy, mut total) = (0.0, 0.0, 0.0);
    for r in 0..n {
        for c in 0..n {
            let (fx, fy) = (frequency(c, n), frequency(r, n));
            if fx * dir.0 + fy * dir.1 > 0.0 {
                let p = power[r * n + c];
                sx += p * fx;
                sy += p * fy;
                total += p;
            }
        }
    }
    let (cx, cy) = (sx / total, sy / total);
    (cx.hypot(cy), cy.atan2(cx))
}

fn gabor_image(params: GaborParams, seed: u64, n: usize) -> Vec<f64> {
    let spec = NoiseSpec { kind: NoiseKind::Gabor, gabor: params, seed, ..NoiseSpec::default() };
    NoiseField::new(&spec).unwrap().grid2(0.0, 0.0, 1.0, n, n)
}

#[test]
fn anisotropic_gabor_spectrum_peaks_at_f0_and_omega0() {
    let n = 512;
    let params = GaborParams::default();
    let power = power_spectrum(&gabor_image(params, 1, n), n);
    let (radius, angle) = lobe_centroid(&power, n, params.omega0);
    assert!((radius - params.f0).abs() <= 0.05 * params.f0, "peak radius {radius} vs F0 {}", params.f0);
    assert!((angle - params.omega0).abs() <= 3f64.to_radians(), "peak angle {}°", angle.to_degrees());
}

#[test]
fn isotropic_gabor_spectrum_is_a_ring() {
    let n = 512;
    let params = GaborParams { isotropic: true, ..GaborParams::default() };
    let power = power_spectrum(&gabor_image(params, 2, n), n);
    let sectors = 8;
    let mut energy = vec![0.0; sectors];
    let mut radial = (0.0, 0.0);
    for r in 0..n {
        for c in 0..n {
            let (fx, fy) = (frequency(c, n), frequency(r, n));
            let p = power[r * n + c];
            // Angles modulo 180°: the spectrum of a real image is symmetric.
            let theta = fy.atan2(fx).rem_euclid(PI);
            energy[((theta / PI * sectors as f64) as usize).min(sectors - 1)] += p;
            radial.0 += p * fx.hypot(fy);
            radial.1 += p;
        }
    }
    let mean = energy.iter().sum::<f64>() / sectors as f64;
    for (k, e) in energy.iter().enumerate() {
        assert!((e / mean - 1.0).abs() <= 0.2, "sector {k} holds {:.2} of the mean", e / mean);
    }
    let mean_radius = radial.0 / radial.1;
    assert!((mean_radius - params.f0).abs() <= 0.1 * params.f0, "ring radius {mean_radius}");
}

#[test]
fn gabor_is_centred_with_the_analytic_variance() {
    for isotropic in [false, true] {
        let params = GaborParams { isotropic, ..GaborParams::default() };
        let values: Vec<f64> = (0..8).flat_map(|seed| gabor_image(params, 100 + seed, 512)).collect();
        let mean = values.iter().sum::<f64>() / values.len() as f64;
        let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / values.len() as f64;
        assert!(mean.abs() < 0.05, "mean {mean}");
        assert!((var - 1.0).abs() < 0.1, "variance {var} (isotropic {isotropic}), analytic 1");
    }
}

#[test]
fn gabor_k_is_the_kernel_magnitude_and_scales_the_noise() {
    // Eq. 3.20: K multiplies every kernel, so the noise (2D and on surfaces) scales with it
    // and nothing normalises it away.
    for k in [0.25, 5.0] {
        let scaled = gabor_image(GaborParams { k, ..GaborParams::default() }, 3, 64);
        for (a, b) in gabor_image(GaborParams::default(), 3, 64).iter().zip(&scaled) {
            assert!((b - k * a).abs() <= 1e-9 * (1.0 + b.abs()), "K = {k}: {b} is not {k} × {a}");
        }
        let frame = Frame { tangent: DVec3::X, bitangent: DVec3::Y };
        let (one, many) = (
            Gabor::new(GaborParams::default(), 4).unwrap(),
            Gabor::new(GaborParams { k, ..GaborParams::default() }, 4).unwrap(),
        );
        for p in random_points(200, 50.0, 9) {
            let (a, b) = (one.sample3(p, frame), many.sample3(p, frame));
            assert!((b - k * a).abs() <= 1e-9 * (1.0 + b.abs()), "K = {k} at {p}: {b} is not {k} × {a}");
        }
    }
}

/// An image's spectral power within 5° of the axes over its power within 5° of the
/// diagonals (sectors of equal size; the lowest frequencies, a few bins, left out). A Hann
/// window first, so the image's edges (it is not periodic) add no power on the axes.
fn axis_over_diagonal_power(image: &[f64], n: usize) -> f64 {
    let hann = |i: usize| 0.5 - 0.5 * (2.0 * PI * i as f64 / n as f64).cos();
    let windowed: Vec<f64> = image.iter().enumerate().map(|(k, v)| v * hann(k % n) * hann(k / n)).collect();
    let power = power_spectrum(&windowed, n);
    let (mut axes, mut diagonals) = (0.0, 0.0);
    for r in 0..n {
        for c in 0..n {
            let (u, v) = (frequency(c, n) * n as f64, frequency(r, n) * n as f64);
            if u.hypot(v) < 4.0 {
                continue;
            }
            // Angle from the nearest axis, 0..45°.
            let angle = v.abs().atan2(u.abs()).to_degrees();
            let from_axis = angle.min(90.0 - angle);
            if from_axis < 5.0 {
                axes += power[r * n + c];
            } else if from_axis > 40.0 {
                diagonals += power[r * n + c];
            }
        }
    }
    axes / diagonals
}

#[test]
fn perlin_images_have_no_axis_aligned_streaks() {
    // The z = 0 plane is a lattice plane: a lattice point at every integer (x, y), a zero
    // of the noise there, and gradients lying in the plane make straight streaks along the
    // axes. 2D noise samples an oblique plane that holds no lattice point.
    let n = 256;
    let step = 1.0 / 8.0;
    let at = |k: usize| ((k % n) as f64 * step, (k / n) as f64 * step);
    let (mut lattice_slice, mut image) = (Vec::new(), Vec::new());
    for seed in 0..4 {
        let perlin = Perlin::new(seed);
        lattice_slice.extend((0..n * n).map(|k| perlin.sample3(DVec3::new(at(k).0, at(k).1, 0.0))));
        image.extend((0..n * n).map(|k| perlin.sample2(at(k).0, at(k).1)));
    }
    let ratio = |values: &[f64]| values.chunks(n * n).map(|one| axis_over_diagonal_power(one, n)).sum::<f64>() / 4.0;
    let (control, ours) = (ratio(&lattice_slice), ratio(&image));
    assert!(control > 1.15, "the measure must see the lattice slice's streaks (axes/diagonals {control:.2})");
    assert!((ours - 1.0).abs() < 0.07, "axes/diagonals power {ours:.2} (the z = 0 slice: {control:.2})");
    let perlin = Perlin::new(1);
    let at_integers = (0..100).filter(|&i| perlin.sample2(f64::from(i % 10), f64::from(i / 10)) == 0.0).count();
    assert_eq!(at_integers, 0, "2D noise vanishes at integer points: it samples a lattice plane");
}

#[test]
fn gabor_3d_on_surfaces_has_unit_variance_and_follows_the_frame() {
    let gabor = Gabor::new(GaborParams::default(), 5).unwrap();
    let frame = Frame { tangent: DVec3::X, bitangent: DVec3::Y };
    let points: Vec<DVec3> =
        (0..40_000).map(|k| DVec3::new((k % 200) as f64 * 3.0, (k / 200) as f64 * 3.0, 0.5)).collect();
    let values: Vec<f64> = points.iter().map(|p| gabor.sample3(*p, frame)).collect();
    let mean = values.iter().sum::<f64>() / values.len() as f64;
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / values.len() as f64;
    assert!(mean.abs() < 0.1 && (var - 1.0).abs() < 0.15, "mean {mean}, variance {var}");
    // Along the stripes (perpendicular to ω0 in the frame) the noise varies slowly; across
    // them it oscillates with period 1/F0.
    let omega = GaborParams::default().omega0;
    let across = DVec3::new(omega.cos(), omega.sin(), 0.0);
    let along = DVec3::new(-omega.sin(), omega.cos(), 0.0);
    let step = 0.25 / 0.0625; // a quarter period
    let (mut d_across, mut d_along) = (0.0, 0.0);
    for p in points.iter().take(2000) {
        let v = gabor.sample3(*p, frame);
        d_across += (gabor.sample3(*p + across * step, frame) - v).abs();
        d_along += (gabor.sample3(*p + along * step, frame) - v).abs();
    }
    assert!(d_across > 2.0 * d_along, "across {d_across} vs along {d_along}");
}

#[test]
fn batches_equal_scalars_at_any_thread_count() {
    // Five octaves at lacunarity 1.9: an odd count (the last octave alone) and frequencies
    // that are no powers of two.
    let fractal = asperity::noise::Fractal { octaves: 5, lacunarity: 1.9, gain: 0.55, ..Default::default() };
    let mut specs: Vec<NoiseSpec> = [
        NoiseKind::Perlin,
        NoiseKind::Fbm,
        NoiseKind::Turbulence,
        NoiseKind::Marble,
        NoiseKind::Multifractal,
        NoiseKind::Wood,
        NoiseKind::Gabor,
        NoiseKind::Phasor,
    ]
    .into_iter()
    .enumerate()
    .map(|(seed, kind)| NoiseSpec { kind, seed: seed as u64 + 1, fractal, ..NoiseSpec::default() })
    .collect();
    specs.push(NoiseSpec {
        kind: NoiseKind::Gabor,
        seed: 3,
        gabor: GaborParams { isotropic: true, ..GaborParams::default() },
        ..NoiseSpec::default()
    });
    let pool = |threads| rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    let bits = |values: &[f64]| values.iter().map(|v| v.to_bits()).collect::<Vec<u64>>();
    for spec in specs {
        let field = NoiseField::new(&spec).unwrap();
        // 97 x 97 = 9409 values: more than one parallel chunk and a ragged last run.
        let (n, x0, y0, step) = (97, -31.5, 12.25, 0.7);
        let one = pool(1).install(|| field.grid2(x0, y0, step, n, n));
        let two = pool(2).install(|| field.grid2(x0, y0, step, n, n));
        assert_eq!(bits(&one), bits(&two), "{:?}", spec.kind);
        let plane: Vec<DVec2> =
            (0..n * n).map(|k| DVec2::new(x0 + (k % n) as f64 * step, y0 + (k / n) as f64 * step)).collect();
        assert_eq!(bits(&one), bits(&field.sample2_batch(&plane)), "{:?}: the picture and the 2D points", spec.kind);
        for (k, v) in one.iter().enumerate() {
            let (i, j) = (k % n, k / n);
            let scalar = field.sample2(x0 + i as f64 * step, y0 + j as f64 * step);
            assert_eq!(v.to_bits(), scalar.to_bits(), "{:?} at {i},{j}", spec.kind);
        }
        // A decreasing grid takes the point-by-point path with the same values.
        let reversed = field.grid2(x0, y0, -step, 7, 3);
        assert_eq!(reversed[8], field.sample2(x0 - step, y0 - step));
        // Points past the vector path's range (2^51) and not finite take its scalar lanes.
        let mut points = random_points(5000, 50.0, 4);
        points.extend([DVec3::new(3e15, -1.0, 2.0), DVec3::new(0.5, -7e16, 1e300), DVec3::new(f64::NAN, 1.0, 1.0)]);
        points.extend(random_points(5, 50.0, 5));
        let a = pool(1).install(|| field.sample3_batch(&points, &[]));
        let b = pool(2).install(|| field.sample3_batch(&points, &[]));
        assert_eq!(bits(&a), bits(&b), "{:?}", spec.kind);
        // The batch (AVX2 for the Perlin kinds, #42) is the point-by-point value bit for bit.
        let frame = asperity::noise::Frame { tangent: DVec3::X, bitangent: DVec3::Y };
        for (p, v) in points.iter().zip(&a) {
            assert_eq!(v.to_bits(), field.sample3(*p, frame).to_bits(), "{:?} at {p}", spec.kind);
        }
    }
}

#[test]
fn invalid_gabor_parameters_are_errors() {
    for params in [
        GaborParams { a: 0.0, ..GaborParams::default() },
        GaborParams { k: f64::NAN, ..GaborParams::default() },
        GaborParams { impulses_per_kernel: -1.0, ..GaborParams::default() },
        GaborParams { f0: f64::INFINITY, ..GaborParams::default() },
    ] {
        assert!(Gabor::new(params, 0).is_err(), "{params:?}");
    }
}

fn phasor_image(params: GaborParams, profile: Profile, seed: u64, n: usize) -> Vec<f64> {
    let spec = NoiseSpec { kind: NoiseKind::Phasor, gabor: params, profile, seed, ..NoiseSpec::default() };
    NoiseField::new(&spec).unwrap().grid2(0.0, 0.0, 1.0, n, n)
}

/// The smallest, over `side`-pixel windows, of the largest |value| in the window, relative
/// to the image's largest |value|: near 1 when the contrast is the same everywhere.
fn weakest_window_peak(image: &[f64], n: usize, side: usize) -> f64 {
    let peak = image.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut weakest = f64::INFINITY;
    for wy in (0..n).step_by(side) {
        for wx in (0..n).step_by(side) {
            let mut local = 0.0f64;
            for y in wy..(wy + side).min(n) {
                for x in wx..(wx + side).min(n) {
                    local = local.max(image[y * n + x].abs());
                }
            }
            weakest = weakest.min(local / peak);
        }
    }
    weakest
}

#[test]
fn phasor_noise_has_constant_contrast_and_gabor_s_spectrum() {
    // Tricard et al. 2019: the phase of complex Gabor noise through a profile keeps the
    // spectral control (F0, ω0) with the same contrast everywhere (#26 A5).
    let n = 256;
    let params = GaborParams::default();
    let period = (1.0 / params.f0) as usize; // 16 pixels
    let phasor = phasor_image(params, Profile::Sine, 4, n);
    let gabor = gabor_image(params, 4, n);
    let (ours, control) = (weakest_window_peak(&phasor, n, 2 * period), weakest_window_peak(&gabor, n, 2 * period));
    assert!(ours > 0.9, "phasor noise's weakest window reaches {ours:.2} of its peak");
    assert!(control < 0.5, "the measure must see Gabor's fading contrast ({control:.2})");
    assert!(phasor.iter().all(|v| v.abs() <= 1.0), "sine profile within ±K");
    // The spectrum peaks where Gabor's does: at F0 along ω0.
    let (radius, angle) = lobe_centroid(&power_spectrum(&phasor, n), n, params.omega0);
    assert!((radius - params.f0).abs() <= 0.15 * params.f0, "peak radius {radius} vs F0 {}", params.f0);
    assert!((angle - params.omega0).abs() <= 5f64.to_radians(), "peak angle {}°", angle.to_degrees());
}

#[test]
fn phasor_profiles_and_k() {
    let params = GaborParams { k: 0.5, ..GaborParams::default() };
    let square = phasor_image(params, Profile::Square, 1, 64);
    assert!(square.iter().all(|&v| v == 0.5 || v == -0.5), "square profile: ±K only");
    let saw = phasor_image(params, Profile::Sawtooth, 1, 64);
    assert!(
        saw.iter().all(|v| v.abs() <= 0.5) && saw.iter().any(|v| v.abs() < 0.1) && saw.iter().any(|v| v.abs() > 0.4)
    );
    let sine = phasor_image(params, Profile::Sine, 1, 64);
    let unit = phasor_image(GaborParams::default(), Profile::Sine, 1, 64);
    for (a, b) in unit.iter().zip(&sine) {
        assert!((b - 0.5 * a).abs() < 1e-12, "K scales phasor noise: {b} vs {a}");
    }
}

#[test]
fn batch_perlin_and_fbm_equal_the_scalar_path_bit_for_bit() {
    let mut rng = Stream::new(9);
    // 1027 points: whole batches and a remainder; coordinates near and far from 0, on
    // lattice planes, and in batches with a coordinate past 2⁵¹ or not finite (the vector
    // path hands those batches to the scalar one).
    let mut points: Vec<DVec3> = (0..1027)
        .map(|i| {
            let r = if i % 3 == 0 { 1e5 } else { 50.0 };
            DVec3::new(rng.uniform(-r, r), rng.uniform(-r, r), rng.uniform(-r, r))
        })
        .collect();
    points[5] = DVec3::new(-3.0, 0.0, 7.0);
    points[6] = DVec3::new(-0.0, -1.0, 2.5);
    points[7] = DVec3::new(-0.0, -0.0, 0.0);
    points[8] = DVec3::new(-0.0, -0.0, -0.0);
    points[9] = DVec3::new(3e15, 1.5, -2.25);
    points[14] = DVec3::new(f64::NAN, 0.5, 0.5);
    points[19] = DVec3::new(0.5, f64::INFINITY, 0.5);
    for perlin in [Perlin::new(4), Perlin::reference()] {
        let mut out = vec![0.0; points.len()];
        perlin.sample3_batch(&points, &mut out);
        for (p, v) in points.iter().zip(&out) {
            let scalar = perlin.sample3(*p);
            assert!(v.to_bits() == scalar.to_bits() || (v.is_nan() && scalar.is_nan()), "{perlin:?} at {p}");
        }
        // The portable lanes (the batch path on CPUs without AVX2, and fBm's fallback).
        for group in points.chunks_exact(4) {
            let lanes = perlin.sample3_lanes::<4>([group[0], group[1], group[2], group[3]]);
            for (p, v) in group.iter().zip(lanes) {
                let scalar = perlin.sample3(*p);
                assert!(v.to_bits() == scalar.to_bits() || (v.is_nan() && scalar.is_nan()), "lanes at {p}");
            }
        }
        for octaves in [1, 7, 8] {
            let fbm = Fractal { kind: FractalKind::Fbm, octaves, ..Fractal::default() };
            fbm.fbm_batch(&perlin, &points, &mut out);
            for (p, v) in points.iter().zip(&out) {
                let scalar = fbm.eval(p.x, ScaledPerlin { perlin: &perlin, point: *p });
                if scalar.is_nan() {
                    assert!(v.is_nan(), "{octaves} octaves at {p}: {v}, not NaN");
                    continue;
                }
                assert_eq!(v.to_bits(), scalar.to_bits(), "{octaves} octaves at {p}");
            }
        }
    }
}

/// Every kind's [`NoiseField::unit`] value over many points and parameter sets: within
/// [−1, 1] ([0, 1] for one-sided kinds; × K for Gabor and phasor noise), so an amplitude is
/// a peak displacement (#26 A4), and the bound is not loose: the largest value met reaches
/// `reach` of it.
#[test]
fn unit_values_stay_within_the_peak_and_come_near_it() {
    use clap::ValueEnum;
    let points = random_points(40_000, 40.0, 17);
    let frame = Frame { tangent: DVec3::X, bitangent: DVec3::Y };
    for &kind in NoiseKind::value_variants() {
        for (octaves, gain, offset) in [(1, 0.5, 1.0), (3, 0.5, 1.0), (6, 0.3, 0.5), (8, 0.8, 2.0)] {
            for k in [1.0, 2.5] {
                let spec = NoiseSpec {
                    kind,
                    fractal: Fractal { octaves, gain, offset, ..Fractal::default() },
                    gabor: GaborParams { k, ..GaborParams::default() },
                    seed: 3,
                    ..NoiseSpec::default()
                };
                let field = NoiseField::new(&spec).unwrap();
                let magnitude = if kind.is_spectral() { k } else { 1.0 };
                let one_sided = matches!(
                    kind,
                    NoiseKind::Turbulence | NoiseKind::Marble | NoiseKind::Multifractal | NoiseKind::Wood
                );
                let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
                for p in &points {
                    let u = field.unit(field.sample3(*p, frame)) / magnitude;
                    low = low.min(u);
                    high = high.max(u);
                }
                let what = format!("{kind:?} octaves {octaves} gain {gain} offset {offset} K {k}");
                assert!(high <= 1.0 && low >= if one_sided { 0.0 } else { -1.0 }, "{what}: range {low}..{high}");
                // The Perlin bound is reached only where all eight gradients line up, and a
                // fractal sum's only where every octave peaks at once: a quarter of it is met.
                let reach = match kind {
                    NoiseKind::Marble | NoiseKind::Wood | NoiseKind::Phasor => 0.95,
                    NoiseKind::Perlin | NoiseKind::Gabor => 0.6,
                    _ => 0.25,
                };
                assert!(high.max(-low) >= reach, "{what}: peak met {} below {reach}", high.max(-low));
            }
        }
    }
}

#[test]
fn soft_limit_is_the_identity_to_the_knee_then_bounded_and_smooth() {
    use asperity::noise::soft_limit;
    for x in [-0.5, -0.2, 0.0, 0.3, 0.5] {
        assert_eq!(soft_limit(x), x);
    }
    assert_eq!(soft_limit(1e9), 1.0, "bounded by 1");
    let mut previous = soft_limit(-5.0);
    for i in -499..=500 {
        let x = f64::from(i) / 100.0;
        let y = soft_limit(x);
        assert!(y > previous && y.abs() < 1.0, "increasing and below 1 at {x}");
        assert_eq!(soft_limit(-x), -y, "odd");
        previous = y;
    }
    let slope = (soft_limit(0.5 + 1e-7) - soft_limit(0.5)) / 1e-7;
    assert!((slope - 1.0).abs() < 1e-5, "slope at the knee {slope}");
}

#[test]
fn single_precision_batches_equal_its_scalars_and_differ_from_f64() {
    use asperity::noise::Precision;
    let pool = |threads| rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    for kind in [NoiseKind::Perlin, NoiseKind::Fbm] {
        let spec = NoiseSpec { kind, seed: 4, precision: Precision::F32, ..NoiseSpec::default() };
        let single = NoiseField::new(&spec).unwrap();
        let double = NoiseField::new(&NoiseSpec { precision: Precision::F64, ..spec }).unwrap();
        let (n, x0, y0, step) = (67, -20.5, 3.25, 0.37);
        let one = pool(1).install(|| single.grid2(x0, y0, step, n, n));
        let two = pool(2).install(|| single.grid2(x0, y0, step, n, n));
        assert_eq!(one, two, "{kind:?}");
        for (k, v) in one.iter().enumerate() {
            let (x, y) = (x0 + (k % n) as f64 * step, y0 + (k / n) as f64 * step);
            assert_eq!(v.to_bits(), single.sample2(x, y).to_bits(), "{kind:?} at {x}, {y}");
        }
        let points = random_points(4099, 60.0, 8);
        let a = pool(1).install(|| single.sample3_batch(&points, &[]));
        let b = pool(2).install(|| single.sample3_batch(&points, &[]));
        assert_eq!(a, b, "{kind:?}");
        let frame = asperity::noise::Frame { tangent: DVec3::X, bitangent: DVec3::Y };
        for (p, v) in points.iter().zip(&a) {
            assert_eq!(v.to_bits(), single.sample3(*p, frame).to_bits(), "{kind:?} at {p}");
            // Values are f32's, and within the kind's bound.
            assert_eq!(*v, f64::from(*v as f32));
            assert!(single.unit(*v).abs() <= 1.0 + 1e-6, "{kind:?}: {v}");
        }
        // A different noise from the f64 default, with the same statistics.
        let d = double.sample3_batch(&points, &[]);
        assert!(a.iter().zip(&d).filter(|(s, d)| s != d).count() > points.len() * 9 / 10, "{kind:?}");
        let spread = |v: &[f64]| (v.iter().map(|x| x * x).sum::<f64>() / v.len() as f64).sqrt();
        let (s, t) = (spread(&a), spread(&d));
        assert!((s / t - 1.0).abs() < 0.1, "{kind:?}: rms {s} (f32) vs {t} (f64)");
    }
    // Only Perlin noise and fBm have it, and only where f32 holds the octaves.
    for kind in [NoiseKind::Turbulence, NoiseKind::Gabor, NoiseKind::Phasor] {
        let spec = NoiseSpec { kind, precision: Precision::F32, ..NoiseSpec::default() };
        assert!(NoiseField::new(&spec).is_err(), "{kind:?}");
    }
    let fractal = asperity::noise::Fractal { octaves: 3, gain: 1e30, ..Default::default() };
    let spec = NoiseSpec { kind: NoiseKind::Fbm, precision: Precision::F32, fractal, ..NoiseSpec::default() };
    assert!(NoiseField::new(&spec).is_err(), "a gain whose square overflows f32");
    assert!(NoiseField::new(&NoiseSpec { precision: Precision::F64, ..spec }).is_ok());
}

/// Largest change between consecutive samples of `value` at `steps` points 10⁻³ apart,
/// counting those above 0.05 (a continuous field of slope ~0.4 per unit changes by ~4·10⁻⁴).
fn jumps(steps: usize, value: impl Fn(usize) -> f64) -> usize {
    let mut previous = value(0);
    (1..steps)
        .filter(|&k| {
            let v = value(k);
            let jump = (v - previous).abs() > 0.05;
            previous = v;
            jump
        })
        .count()
}

/// Phasor noise is continuous away from the isolated zeros of its complex sum: its kernels
/// fall to zero at their truncation radius. With the plain truncated Gaussian (5 % of the
/// peak at the radius) the phase jumped wherever a kernel left the support and the sum was
/// small: arcs where the stripes break off (4 jumps here in the plane and 13 on the
/// sphere; none now).
#[test]
fn phasor_noise_has_no_jumps_where_kernels_end() {
    let phasor = asperity::noise::Phasor::new(GaborParams::default(), Profile::Sine, 7).unwrap();
    let plane = jumps(100_000, |k| phasor.sample2(k as f64 * 1e-3, 11.1));
    assert_eq!(plane, 0, "phasor noise jumps {plane} times along a line of the plane");
    let reference = DVec3::new(1.0, 2.0, 3.0).normalize();
    let on_sphere = jumps(100_000, |k| {
        let angle = k as f64 * 1e-3 / 20.0;
        let n = DVec3::new(angle.cos() * 0.8, angle.sin() * 0.8, 0.6);
        let tangent = (reference - n * n.dot(reference)).normalize();
        phasor.sample3(n * 20.0, Frame { tangent, bitangent: n.cross(tangent) })
    });
    assert_eq!(on_sphere, 0, "phasor noise jumps {on_sphere} times along a circle on a sphere");
}
