//! Erosion on a 1025² classic terrain (#41), side by side in one run: thermal and hydraulic
//! erosion's time per point and iteration at one and two threads, and what hydraulic
//! erosion does to the land — the hypsometric integral (Strahler 1952) and the drainage
//! density (the share of points whose D8 flow accumulation exceeds 0.1 % of the grid) —
//! against the uneroded heights.
//!
//! Then #41's speed target on 4097² at two threads: one hydraulic iteration against one
//! thermal iteration over the same heights (target ≤ 4×), and what writing the four
//! layers (`--layers`) adds to a hydraulic run.
//!
//! `cargo bench --bench erosion`

mod common;

use std::time::Instant;

use asperity::terrain::drainage::drainage_density;
use asperity::terrain::{HydraulicErosion, Rect, TerrainParams, ThermalErosion, erosion, heights, hydraulic};

const SIZE: u64 = 1025;
const ITERATIONS: u32 = 50;

/// (mean − min) / (max − min).
fn hypsometric_integral(h: &[f64]) -> f64 {
    let (lo, hi) = h.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, u), &v| (l.min(v), u.max(v)));
    (h.iter().sum::<f64>() / h.len() as f64 - lo) / (hi - lo)
}

fn timed(params: &TerrainParams, threads: usize) -> (f64, Vec<f64>) {
    let rect = Rect { x0: 0, y0: 0, x1: SIZE - 1, y1: SIZE - 1 };
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("pool");
    let start = Instant::now();
    let field = pool.install(|| heights(params, rect).expect("heights"));
    (start.elapsed().as_secs_f64(), field.heights)
}

fn main() {
    let plain = TerrainParams { size: SIZE, hurst: 0.8, seed: 7, ..TerrainParams::default() };
    let thermal =
        TerrainParams { erosion: Some(ThermalErosion { iterations: ITERATIONS, talus_degrees: 30.0 }), ..plain };
    let hydraulic =
        TerrainParams { hydraulic: Some(HydraulicErosion { iterations: ITERATIONS, ..Default::default() }), ..plain };
    let (t_plain, before) = timed(&plain, 2);
    let work = (SIZE * SIZE) as f64 * f64::from(ITERATIONS);
    let mut after = Vec::new();
    for (name, params) in [("thermal", &thermal), ("hydraulic", &hydraulic)] {
        let (one, _) = timed(params, 1);
        let (two, heights) = timed(params, 2);
        println!(
            "{name} erosion, {SIZE}², {ITERATIONS} iterations: 1 thread {:.2} s ({:.1} M point-iterations/s), 2 threads {:.2} s ({:.2}x)",
            one - t_plain,
            work / (one - t_plain) / 1e6,
            two - t_plain,
            (one - t_plain) / (two - t_plain)
        );
        after = heights;
    }
    let n = SIZE as usize;
    println!(
        "hydraulic erosion: hypsometric integral {:.4} -> {:.4}, drainage density {:.4} -> {:.4} (uneroded -> eroded)",
        hypsometric_integral(&before),
        hypsometric_integral(&after),
        drainage_density(&before, n),
        drainage_density(&after, n)
    );
    layers_cost(&hydraulic);
    one_iteration_at_world_scale();
}

/// #41's target: one iteration of each erosion over 4097² on two threads, side by side,
/// from the same uneroded heights (best of three).
fn one_iteration_at_world_scale() {
    const BIG: u64 = 4097;
    let plain = TerrainParams { size: BIG, hurst: 0.8, seed: 7, ..TerrainParams::default() };
    let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().expect("pool");
    let field = pool.install(|| heights(&plain, Rect { x0: 0, y0: 0, x1: BIG - 1, y1: BIG - 1 }).expect("heights"));
    let best = |run: &(dyn Fn(&mut asperity::terrain::Heightfield) + Sync)| {
        (0..3)
            .map(|_| {
                let mut copy = field.clone();
                let start = Instant::now();
                pool.install(|| run(&mut copy));
                start.elapsed().as_secs_f64()
            })
            .fold(f64::INFINITY, f64::min)
    };
    let thermal = ThermalErosion { iterations: 1, talus_degrees: 30.0 };
    let rain = HydraulicErosion { iterations: 1, ..Default::default() };
    let t = best(&|f| erosion::erode(f, &plain, &thermal));
    let h = best(&|f| {
        hydraulic::erode(f, &plain, &rain);
    });
    let points = (BIG * BIG) as f64;
    println!(
        "{BIG}², one iteration on 2 threads: thermal {t:.3} s ({:.1} M points/s), hydraulic {h:.3} s ({:.1} M points/s): hydraulic/thermal {:.2}x (target <= 4x)",
        points / t / 1e6,
        points / h / 1e6,
        h / t,
    );
}

/// What the four layers (`--layers`) add to a hydraulic run of `params` on two threads.
fn layers_cost(params: &TerrainParams) {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().expect("pool");
    let rect = Rect { x0: 0, y0: 0, x1: SIZE - 1, y1: SIZE - 1 };
    let plain = TerrainParams { hydraulic: None, ..*params };
    let field = pool.install(|| heights(&plain, rect).expect("heights"));
    let rain = params.hydraulic.expect("hydraulic erosion");
    let time = |layers: bool| {
        let mut copy = field.clone();
        let start = Instant::now();
        pool.install(|| {
            if layers {
                hydraulic::erode_with_layers(&mut copy, params, &rain);
            } else {
                hydraulic::erode(&mut copy, params, &rain);
            }
        });
        start.elapsed().as_secs_f64()
    };
    let (without, with) = (time(false), time(true));
    println!(
        "hydraulic erosion, {SIZE}², {ITERATIONS} iterations, 2 threads: {without:.2} s, with the four layers {with:.2} s ({:.2}x)",
        with / without
    );
}
