//! #40's partitioned build against the one-piece build, side by side in one run: the
//! displaced 1.31M-triangle sphere and the bunny scan to 1 % of their vertices by
//! `hierarchy::partition::build_partitioned` with K = 8 parts (parts along the Morton
//! curve, built in parallel with their borders fenced, their bases joined and the build
//! continued) and by the one-piece build. Printed: Hausdorff of both (to the input, % of
//! its diagonal) and their ratio (target ≤ 1.1), the wall times and their ratio (target
//! ≤ 0.6 on 2 threads).
//!
//! Not measured yet (#40 continues): parts as separate processes and their peaks, 50M
//! triangles.
//!
//! `cargo bench --bench hierarchy_scale` (`-- --quick`: the 327k-triangle sphere).

mod common;

use std::time::Instant;

use asperity::Mesh;
use asperity::hierarchy::compare::relative_hausdorff;
use asperity::hierarchy::partition::{Partition, build_partitioned};
use asperity::hierarchy::{KeepFeatures, SimplifyOptions, build};

/// Parts of the partitioned build.
const PARTS: usize = 8;

fn options(target: usize, border: Vec<u32>) -> SimplifyOptions {
    SimplifyOptions {
        target_vertices: Some(target),
        keep_features: KeepFeatures::None,
        border_vertices: border,
        ..Default::default()
    }
}

fn main() {
    asperity::memory::return_large_buffers_to_the_os();
    let quick = std::env::args().any(|a| a == "--quick");
    let shared = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/data/meshes/bunny00.off");
    let scan = asperity::io::read(&shared)
        .unwrap_or_else(|e| panic!("the bunny scan belongs at {}: {e}", shared.display()))
        .mesh;
    for (name, mesh) in
        [("displaced sphere", common::displaced_sphere(if quick { 7 } else { 8 })), ("bunny00 scan", scan)]
    {
        compare(name, &mesh);
    }
}

fn compare(name: &str, mesh: &Mesh) {
    let target = mesh.vertex_count() / 100;
    println!(
        "{name}: {} vertices, {} triangles; target {target} vertices, {PARTS} parts",
        mesh.vertex_count(),
        mesh.face_count()
    );
    let start = Instant::now();
    let one = build(mesh, &options(target, Vec::new())).expect("one-piece build");
    let one_s = start.elapsed().as_secs_f64();
    let one_h = relative_hausdorff(mesh, &one.base_mesh().mesh).expect("hausdorff");
    let one_vertices = one.base_vertex_count();
    drop(one);

    let start = Instant::now();
    let parted = build_partitioned(mesh, PARTS, &options(target, Vec::new())).expect("partitioned build");
    let parted_s = start.elapsed().as_secs_f64();
    let parted_h = relative_hausdorff(mesh, &parted.base_mesh().mesh).expect("hausdorff");
    let border = Partition::of(mesh, PARTS).expect("partition").border_count();
    println!("  one piece: {one_vertices} vertices in {one_s:.2} s, hausdorff {:.4} %", one_h * 100.0);
    println!(
        "  partitioned: {} vertices in {parted_s:.2} s ({} levels, the parts' and the joined bases'), hausdorff {:.4} %; {border} border vertices ({:.1} %)",
        parted.base_vertex_count(),
        parted.steps(),
        parted_h * 100.0,
        100.0 * border as f64 / mesh.vertex_count() as f64
    );
    println!(
        "  #40: hausdorff partitioned / one piece {:.3}x (target <= 1.1x); wall time {:.2}x on {} threads (target <= 0.6x)",
        parted_h / one_h,
        parted_s / one_s,
        rayon::current_num_threads()
    );
}
