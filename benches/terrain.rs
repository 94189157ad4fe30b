//! Classic terrain throughput (issue #4's targets: in-memory 8193² ≥ 100 M points/s on
//! 2 cores; streaming ≥ 50 % of in-memory), one line per stage. Peak memory of streaming
//! is measured on the command line: `scripts/bench-terrain.sh`.
//!
//! `cargo bench --bench terrain`

mod common;

use common::best_of;

use asperity::terrain::stream::{StreamFormat, write_terrain};
use asperity::terrain::{Rect, TerrainParams, whole};

fn main() {
    let p = TerrainParams { size: 8193, hurst: 0.8, seed: 1, ..TerrainParams::default() };
    let points = (p.size * p.size) as f64;
    let rect = Rect { x0: 0, y0: 0, x1: p.size - 1, y1: p.size - 1 };
    let in_memory = best_of(|| drop(whole(&p).expect("terrain")));
    println!(
        "classic 8193² in memory: {:.0} ms, {:.1} M points/s ({} threads)",
        in_memory * 1e3,
        points / in_memory / 1e6,
        rayon::current_num_threads()
    );
    let streamed = best_of(|| {
        write_terrain(&p, rect, StreamFormat::F32, (-1.0, 1.0), 64, &mut std::io::sink()).expect("stream");
    });
    println!(
        "classic 8193² streamed (f32, 64-row bands, to a sink): {:.0} ms, {:.1} M points/s ({:.0}% of in-memory)",
        streamed * 1e3,
        points / streamed / 1e6,
        100.0 * in_memory / streamed
    );
}
