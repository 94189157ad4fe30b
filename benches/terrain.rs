//! Classic terrain throughput (#23's targets on this machine's 2 cores: 8193² in memory
//! ≥ 100 M points/s; streaming ≥ 90 % of in-memory), measured side by side in one run with
//! a plain memory-bandwidth baseline: a parallel fill of the same 8193² buffer of f64, the
//! least any whole-grid generator must spend. Peak memory of streaming 65537² is measured on
//! the command line: `scripts/bench-terrain.sh`.
//!
//! `cargo bench --bench terrain`

mod common;

use common::best_of;
use rayon::prelude::*;

use asperity::terrain::stream::{StreamFormat, default_band, write_terrain};
use asperity::terrain::{Rect, TerrainParams, whole};

fn main() {
    let p = TerrainParams { size: 8193, hurst: 0.8, seed: 1, ..TerrainParams::default() };
    let points = (p.size * p.size) as f64;
    let rect = Rect { x0: 0, y0: 0, x1: p.size - 1, y1: p.size - 1 };
    let threads = rayon::current_num_threads();
    let fill = best_of(|| {
        let mut buffer: Vec<f64> = Vec::with_capacity(points as usize);
        buffer.spare_capacity_mut().par_chunks_mut(1 << 16).for_each(|c| {
            c.iter_mut().for_each(|v| {
                v.write(1.0);
            })
        });
        // SAFETY: every element was written above.
        unsafe { buffer.set_len(points as usize) };
        std::hint::black_box(&buffer);
    });
    println!(
        "baseline: parallel fill of 8193² f64: {:.0} ms, {:.1} M points/s ({threads} threads)",
        fill * 1e3,
        points / fill / 1e6
    );
    let in_memory = best_of(|| drop(whole(&p).expect("terrain")));
    println!(
        "classic 8193² in memory: {:.0} ms, {:.1} M points/s ({threads} threads): {:.2}x the fill's time [target: ≥ 100 M points/s]",
        in_memory * 1e3,
        points / in_memory / 1e6,
        in_memory / fill,
    );
    let band = default_band(rect.width());
    let streamed = best_of(|| {
        write_terrain(&p, rect, StreamFormat::F32, (-1.0, 1.0), band, &mut std::io::sink()).expect("stream");
    });
    println!(
        "classic 8193² streamed (f32, {band}-row bands, to a sink): {:.0} ms, {:.1} M points/s: {:.0}% of in-memory [target: ≥ 90%]",
        streamed * 1e3,
        points / streamed / 1e6,
        100.0 * in_memory / streamed
    );
}
