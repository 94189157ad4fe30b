//! Noise throughput measured side by side with the `noise` crate in one run, printing
//! ratios (issue #3's targets: Perlin and 8-octave fBm ≥ 4× faster than `noise`, 2D Gabor
//! at 64 impulses per kernel ≥ 2 M samples/s per core, batches ≥ 1.8× faster on 2 threads;
//! issue #26's: the batch paths ≥ 10× `noise::Perlin` and ≥ 5× `noise::Fbm`, each row
//! naming the path it times, and the surface Gabor noise the operators evaluate).
//!
//! `cargo bench --bench noise`

mod common;

use std::hint::black_box;

use common::best_of;

use asperity::noise::{Fractal, FractalKind, NoiseField, NoiseKind, NoiseSpec, Perlin, ScaledPerlin, hash::Stream};
use glam::DVec3;
use noise::{Fbm, MultiFractal, NoiseFn};

fn single_thread<T: Send>(f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new().num_threads(1).build().expect("pool").install(f)
}

fn main() {
    // 16 Ki points (384 KiB, cache-resident) swept 64 times: per-sample compute cost, not
    // memory streaming, for both libraries alike.
    let mut rng = Stream::new(42);
    let distinct: Vec<DVec3> = (0..16_384)
        .map(|_| DVec3::new(rng.uniform(-100.0, 100.0), rng.uniform(-100.0, 100.0), rng.uniform(-100.0, 100.0)))
        .collect();
    let sweeps = 64;
    let points = || std::iter::repeat_n(&distinct, sweeps).flatten();
    let n = (distinct.len() * sweeps) as f64;

    let ours = Perlin::new(1);
    let theirs = noise::Perlin::new(1);
    let t_ours = best_of(|| {
        let mut s = 0.0;
        for p in points() {
            s += ours.sample3(*p);
        }
        black_box(s);
    });
    let t_theirs = best_of(|| {
        let mut s = 0.0;
        for p in points() {
            s += theirs.get([p.x, p.y, p.z]);
        }
        black_box(s);
    });
    println!(
        "perlin 3d, scalar (Perlin::sample3): {:.1} ns/sample | noise::Perlin {:.1} ns ({:.1}x)",
        t_ours / n * 1e9,
        t_theirs / n * 1e9,
        t_theirs / t_ours
    );
    let mut out = vec![0.0; distinct.len()];
    let t_batch = best_of(|| {
        for _ in 0..sweeps {
            ours.sample3_batch(black_box(&distinct), &mut out);
        }
        black_box(&out);
    });
    println!(
        "perlin 3d, batch (Perlin::sample3_batch, one core): {:.1} ns/sample | noise::Perlin {:.1} ns ({:.1}x; target >= 10x)",
        t_batch / n * 1e9,
        t_theirs / n * 1e9,
        t_theirs / t_batch
    );

    let fbm = Fractal { kind: FractalKind::Fbm, octaves: 8, ..Fractal::default() };
    let their_fbm = Fbm::<noise::Perlin>::new(1).set_octaves(8);
    let few: Vec<DVec3> = points().take(16_384 * 12).copied().collect();
    let t_ours = best_of(|| {
        let mut s = 0.0;
        for p in &few {
            let p = black_box(*p);
            s += fbm.eval(p.x, ScaledPerlin { perlin: &ours, point: p });
        }
        black_box(s);
    });
    let t_theirs = best_of(|| {
        let mut s = 0.0;
        for p in &few {
            s += their_fbm.get(black_box([p.x, p.y, p.z]));
        }
        black_box(s);
    });
    let m = few.len() as f64;
    println!(
        "fbm 3d, 8 octaves, scalar (Fractal::eval): {:.1} ns/sample | noise::Fbm<Perlin> {:.1} ns ({:.1}x)",
        t_ours / m * 1e9,
        t_theirs / m * 1e9,
        t_theirs / t_ours
    );
    let mut fbm_out = vec![0.0; few.len()];
    let t_batch = best_of(|| {
        fbm.fbm_batch(&ours, black_box(&few), &mut fbm_out);
        black_box(&fbm_out);
    });
    println!(
        "fbm 3d, 8 octaves, batch (Fractal::fbm_batch, one core): {:.1} ns/sample | noise::Fbm<Perlin> {:.1} ns ({:.1}x; target >= 5x)",
        t_batch / m * 1e9,
        t_theirs / m * 1e9,
        t_theirs / t_batch
    );

    // The path users' scattered points take (Python `noise`, C++ `noise`, detail steps):
    // NoiseField::sample3_batch, which routes Perlin and fBm through the batch forms (#42).
    for (kind, name) in [(NoiseKind::Perlin, "perlin"), (NoiseKind::Fbm, "fbm-8")] {
        let spec =
            NoiseSpec { kind, seed: 1, fractal: Fractal { octaves: 8, ..Fractal::default() }, ..NoiseSpec::default() };
        let field = NoiseField::new(&spec).expect("field");
        let t = single_thread(|| best_of(|| drop(black_box(field.sample3_batch(black_box(&few), &[])))));
        println!(
            "{name} 3d, scattered points (NoiseField::sample3_batch, the Python and C++ path, one core): {:.1} ns/sample",
            t / m * 1e9
        );
    }

    let gabor = NoiseField::new(&NoiseSpec { kind: NoiseKind::Gabor, ..NoiseSpec::default() }).expect("gabor");
    let side = 1024;
    let t = single_thread(|| best_of(|| drop(black_box(gabor.grid2(0.0, 0.0, 1.0, side, side)))));
    println!(
        "gabor 2d grid (NoiseField::grid2 -> Gabor::fill_grid2), 64 impulses/kernel, one core: {:.2} M samples/s ({:.0} ns/sample)",
        (side * side) as f64 / t / 1e6,
        t / (side * side) as f64 * 1e9
    );

    // The path the detail operators take: surface Gabor noise at mesh vertices, each with
    // its tangent frame (NoiseField::sample3_batch -> Gabor::sample3).
    let sphere = asperity::mesh::primitives::icosphere(1.0, 5);
    let frames: Vec<asperity::noise::Frame> = sphere
        .positions
        .iter()
        .map(|p| {
            let n = p.normalize();
            let tangent = n.any_orthonormal_vector();
            asperity::noise::Frame { tangent, bitangent: n.cross(tangent) }
        })
        .collect();
    let scaled: Vec<DVec3> = sphere.positions.iter().map(|p| *p * 20.0).collect();
    let t = single_thread(|| best_of(|| drop(black_box(gabor.sample3_batch(&scaled, &frames)))));
    println!(
        "gabor surface (NoiseField::sample3_batch -> Gabor::sample3, the operators' path), one core: {:.2} M samples/s ({:.0} ns/sample)",
        scaled.len() as f64 / t / 1e6,
        t / scaled.len() as f64 * 1e9
    );

    let turbulence =
        NoiseField::new(&NoiseSpec { kind: NoiseKind::Turbulence, ..NoiseSpec::default() }).expect("turbulence");
    for (name, field) in [("gabor", &gabor), ("turbulence", &turbulence)] {
        let one = single_thread(|| best_of(|| drop(black_box(field.grid2(0.0, 0.0, 0.7, side, side)))));
        let two = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .expect("pool")
            .install(|| best_of(|| drop(black_box(field.grid2(0.0, 0.0, 0.7, side, side)))));
        println!(
            "batch {name} {side}x{side}: 1 thread {:.1} ms | 2 threads {:.1} ms ({:.2}x)",
            one * 1e3,
            two * 1e3,
            one / two
        );
    }
}
