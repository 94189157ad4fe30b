//! The 4-k hierarchy against the reference decimators, side by side in one run (#6): a
//! displaced icosphere of 1.31 M triangles made in code, simplified to 1 % of its vertices
//! by each method (ours without feature preservation: the relief makes thousands of
//! strong-edge vertices); then our refinement back to full resolution and peak memory.
//!
//! Then #20's speed ratios (build with and without the guard over meshoptimizer's time, each
//! stage's time on one thread and on all, the OpenMesh replay's cost), and #19's 1 % rows
//! on the shared meshes.
//!
//! `cargo bench --bench hierarchy` (`-- --quick` uses the 327 k-triangle sphere;
//! `-- --write-mesh PATH` writes the chosen sphere and stops, to profile the CLI on it).

mod common;

use std::time::Instant;

use asperity::Mesh;
use asperity::hierarchy::compare::compare;
use asperity::hierarchy::{KeepFeatures, Refiner, SimplifyOptions, build};

fn main() {
    // As the asperity binary does: large freed buffers go back to the OS.
    asperity::memory::return_large_buffers_to_the_os();
    let quick = std::env::args().any(|a| a == "--quick");
    let mesh = common::displaced_sphere(if quick { 7 } else { 8 });
    if std::env::args().any(|a| a == "--write-mesh") {
        let path = std::env::args().skip_while(|a| a != "--write-mesh").nth(1).expect("--write-mesh needs a path");
        asperity::io::write(&mesh, std::path::Path::new(&path), Default::default()).expect("write the sphere");
        println!("wrote {path}: {} vertices, {} tris", mesh.vertex_count(), mesh.face_count());
        return;
    }
    let target = mesh.vertex_count() / 100;
    println!("mesh: {} vertices, {} tris; target {} vertices", mesh.vertex_count(), mesh.face_count(), target);
    let before = common::peak_rss_kib().unwrap_or(0);

    let start = Instant::now();
    let options =
        SimplifyOptions { target_vertices: Some(target), keep_features: KeepFeatures::None, ..Default::default() };
    let hierarchy = build(&mesh, &options).expect("hierarchy");
    let build_s = start.elapsed().as_secs_f64();
    let start = Instant::now();
    let mut refiner = Refiner::new(&hierarchy).expect("refiner");
    refiner.refine_all().expect("refine");
    let refine_s = start.elapsed().as_secs_f64();
    let peak = common::peak_rss_kib().unwrap_or(0);
    println!(
        "asperity: build {:.2} s ({} levels, {} base vertices), refine {:.2} s (refine/build {:.2}); peak RSS {} MiB, {:.0} bytes per input triangle over the input",
        build_s,
        hierarchy.steps(),
        hierarchy.base_vertex_count(),
        refine_s,
        refine_s / build_s,
        peak / 1024,
        (peak.saturating_sub(before) * 1024) as f64 / mesh.face_count() as f64
    );
    println!("asperity build stages: {}", hierarchy.stages);
    drop(refiner);

    let rows = compare(&mesh, target, &["asperity", "openmesh", "cgal", "meshoptimizer"], &options).expect("compare");
    for r in &rows {
        println!(
            "{:<14} {:>7} vertices in {:>7.2} s, hausdorff {:.3} %, rms {:.4} %, min angle {:.2}°, slivers {:.2} %",
            r.method,
            r.vertices,
            r.seconds,
            r.hausdorff * 100.0,
            r.rms * 100.0,
            r.min_angle_deg,
            r.sliver_share * 100.0
        );
    }
    let ours = &rows[0];
    for r in &rows[1..] {
        println!(
            "ratio {}/asperity: time {:.2}x, hausdorff asperity/{} {:.2}x",
            r.method,
            r.seconds / ours.seconds,
            r.method,
            ours.hausdorff / r.hausdorff
        );
    }
    report_speed_targets(&mesh, &options, &rows);
    report_shared_meshes_at_one_percent();
}

/// #19's 1 % rows: every shared mesh simplified to 1 % of its vertices (at least 4) by
/// each method, without feature preservation, at one vertex count per mesh (`compare` runs
/// the methods again to the count of one that stops above it).
fn report_shared_meshes_at_one_percent() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/data/meshes");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("the shared meshes belong in {}: {e}", dir.display()))
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "off"))
        .collect();
    files.sort();
    let options = SimplifyOptions { keep_features: KeepFeatures::None, ..Default::default() };
    for path in files {
        let mesh = asperity::io::read(&path).expect("shared mesh").mesh;
        let target = (mesh.vertex_count() / 100).max(4);
        let rows =
            compare(&mesh, target, &["asperity", "openmesh", "cgal", "meshoptimizer"], &options).expect("compare");
        let row = |m: &str| rows.iter().find(|r| r.method == m).expect("row");
        let (ours, om, cgal, mo) = (row("asperity"), row("openmesh"), row("cgal"), row("meshoptimizer"));
        println!(
            "1 % {:<26} {:>5} vertices: hausdorff {:.3} % (asperity/meshoptimizer {:.2}x, asperity/cgal {:.2}x), slivers {:.1} % (openmesh {:.1} %), min angle {:.2}°; time asperity/meshoptimizer {:.1}x{}",
            path.file_name().expect("name").to_string_lossy(),
            ours.vertices,
            ours.hausdorff * 100.0,
            ours.hausdorff / mo.hausdorff.max(f64::MIN_POSITIVE),
            ours.hausdorff / cgal.hausdorff.max(f64::MIN_POSITIVE),
            ours.sliver_share * 100.0,
            om.sliver_share * 100.0,
            ours.min_angle_deg,
            ours.seconds / mo.seconds.max(f64::MIN_POSITIVE),
            // #35's budget for fandisk-size meshes (up to 20 k triangles; below a thousand the
            // build takes about a millisecond and meshoptimizer microseconds).
            if (1_000..=20_000).contains(&mesh.face_count()) { " (target <= 6x)" } else { "" }
        );
    }
}

/// The build-time budgets next to the least the build can cost with its topology in
/// OpenMesh (the design card's choice): OpenMesh itself carrying out the hierarchy's flips
/// and welds. That is the recorder's store stage, measured here without the guard and with
/// one worker thread, so the recorder has a core to itself.
fn report_speed_targets(mesh: &Mesh, options: &SimplifyOptions, rows: &[asperity::hierarchy::compare::CompareRow]) {
    let seconds = |method: &str| rows.iter().find(|r| r.method == method).map_or(f64::NAN, |r| r.seconds);
    let (ours, meshopt) = (seconds("asperity"), seconds("meshoptimizer"));
    let unguarded = SimplifyOptions { prevent_intersections: false, ..options.clone() };
    let start = Instant::now();
    let without = build(mesh, &unguarded).expect("hierarchy without the guard");
    let without_s = start.elapsed().as_secs_f64();
    println!(
        "#35: build with the guard / meshoptimizer {:.2}x (target <= 4x, stretch 2.5x); without the guard ({} base vertices) {:.2}x (target <= 3x)",
        ours / meshopt,
        without.base_vertex_count(),
        without_s / meshopt
    );
    for threads in [1, rayon::current_num_threads()] {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("pool");
        let start = Instant::now();
        let h = pool.install(|| build(mesh, options)).expect("hierarchy");
        println!("stages on {threads} thread(s), build {:.2} s: {}", start.elapsed().as_secs_f64(), h.stages);
        println!("  shares of the planning thread on {threads} thread(s): {}", stage_shares(&h.stages));
    }
    let start = Instant::now();
    let replayed = asperity::hierarchy::build_with_openmesh_replay(mesh, options).expect("replayed hierarchy");
    println!(
        "the OpenMesh replay (the build's check, off its critical path): {:.2} s on the recorder thread, {:.0} % of that build's {:.2} s",
        replayed.stages.store,
        100.0 * replayed.stages.store / start.elapsed().as_secs_f64(),
        start.elapsed().as_secs_f64()
    );
}

/// Each stage of the planning thread as a share of their sum (the recorder's run beside it).
fn stage_shares(s: &asperity::hierarchy::BuildStages) -> String {
    let stages = s.planning_thread();
    let total: f64 = stages.iter().map(|(_, t)| t).sum();
    stages.iter().map(|(name, t)| format!("{name} {:.0} %", 100.0 * t / total)).collect::<Vec<_>>().join(", ")
}
