//! A large input through the hierarchy (#9): `elephant.off` after five Loop subdivision
//! steps (5.69 M triangles), simplified to 1 % of its vertices and refined back to full
//! resolution, with the peak resident memory of that stage (target: ≤ 8 GB).
//!
//! `cargo bench --bench large` (`-- --steps 4` for the 1.42 M-triangle mesh). Needs
//! `../shared/data/meshes`.

mod common;

use std::path::Path;
use std::time::Instant;

use asperity::hierarchy::{KeepFeatures, Refiner, SimplifyOptions, build};
use asperity::mesh::loop_subdivide;

fn main() {
    // As the asperity binary does: large freed buffers go back to the OS.
    asperity::memory::return_large_buffers_to_the_os();
    let args: Vec<String> = std::env::args().collect();
    let steps: usize =
        args.iter().position(|a| a == "--steps").and_then(|i| args.get(i + 1)?.parse().ok()).unwrap_or(5);
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/data/meshes/elephant.off");
    let Ok(read) = asperity::io::read(&path) else {
        println!("large: skipped ({} is absent)", path.display());
        return;
    };
    let start = Instant::now();
    let mut mesh = read.mesh;
    for _ in 0..steps {
        mesh = loop_subdivide(&mesh).expect("the elephant is a closed manifold");
    }
    let triangles = mesh.face_count();
    println!(
        "input: elephant.off after {steps} Loop steps: {} vertices, {triangles} tris (made in {:.1} s)",
        mesh.vertex_count(),
        start.elapsed().as_secs_f64()
    );
    let input_kib = common::peak_rss_kib().unwrap_or(0);
    let reset = common::reset_peak_rss();

    let start = Instant::now();
    let options = SimplifyOptions {
        target_vertices: Some(mesh.vertex_count() / 100),
        keep_features: KeepFeatures::Strong,
        ..Default::default()
    };
    let hierarchy = build(&mesh, &options).expect("hierarchy");
    let build_s = start.elapsed().as_secs_f64();
    let start = Instant::now();
    let mut refiner = Refiner::new(&hierarchy).expect("refiner");
    refiner.refine_all().expect("refine");
    let refined = refiner.mesh().expect("refined mesh");
    let refine_s = start.elapsed().as_secs_f64();
    assert!(refined.has_input_positions(&mesh), "the round trip moved a vertex");
    let peak = common::peak_rss_kib().unwrap_or(0);
    println!(
        "large: build {build_s:.1} s ({} levels, {} base vertices, {} feature vertices kept), refine {refine_s:.1} s, positions exact",
        hierarchy.steps(),
        hierarchy.base_vertex_count(),
        hierarchy.feature_vertices
    );
    println!(
        "large: peak RSS {:.2} GiB{} ({:.0} bytes per input triangle; target 8 GiB: {})",
        peak as f64 / 1048576.0,
        if reset { " during simplify + refine" } else { " of the whole run" },
        peak as f64 * 1024.0 / triangles as f64,
        if peak <= 8 * 1048576 { "met" } else { "MISSED" }
    );
    println!("large: (the input mesh alone peaked at {:.2} GiB while it was made)", input_kib as f64 / 1048576.0);
}
