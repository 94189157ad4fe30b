//! #40's partitioned build against the one-piece build, side by side in one run: the
//! displaced 1.31M-triangle sphere and the bunny scan to 1 % of their vertices by
//! `hierarchy::partition::build_partitioned` with K = 8 parts (parts along the Morton
//! curve, built in parallel with their borders fenced, their bases joined and the build
//! continued) and by the one-piece build. Printed: Hausdorff of both (to the input, % of
//! its diagonal) and their ratio (target ≤ 1.1), the wall times and their ratio (target
//! ≤ 0.6 on 2 threads), and the one-piece build's time on one thread: the partitioned
//! build's time against it, and the one-piece build's own speed-up from its threads
//! (which bounds the ratio: parts that do the one-piece build's work between them take
//! about its one-thread time over the thread count).
//!
//! `-- --large [STEPS]`: the mesh plan's three stages as a job runner runs them, each a
//! process of its own (this bench run again with `--stage`, printing its VmHWM), the
//! chunks one after another: fandisk after STEPS Loop steps (6: 53.0M triangles; a smooth
//! surface, since Loop smooths the creases) written as binary PLY, `MeshPlan::make` with
//! K = 16 chunks, each chunk built (`run_chunk`), and the merge (`join_plan` and the report), to 0.1 % of
//! the vertices. Printed: each stage's peak (bytes per triangle it handles) and time, and
//! the same run at STEPS − 2 (1/16 of the triangles) for the time per triangle's ratio
//! (target ≤ 1.2).
//!
//! `cargo bench --bench hierarchy_scale` (`-- --quick`: the 327k-triangle sphere).

mod common;

use std::time::Instant;

use asperity::Mesh;
use asperity::hierarchy::BuildReport;
use asperity::hierarchy::compare::relative_hausdorff;
use asperity::hierarchy::partition::plan::{MeshPlan, join_plan, run_chunk};
use asperity::hierarchy::partition::{Partition, build_partitioned};
use asperity::hierarchy::{HierarchyRequest, KeepFeatures, SimplifyOptions, VertexTarget, build};

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
    let args: Vec<String> = std::env::args().collect();
    if let Some(i) = args.iter().position(|a| a == "--stage") {
        return run_stage(&args[i + 1..]);
    }
    if let Some(i) = args.iter().position(|a| a == "--large") {
        let steps: u32 = args.get(i + 1).and_then(|s| s.parse().ok()).unwrap_or(6);
        let small = planned_stages(steps.saturating_sub(2));
        let large = planned_stages(steps);
        println!(
            "  #40: time per triangle at {:.1}M / at {:.1}M triangles: {:.3}x (target: within 1.2x)",
            large.0 as f64 / 1e6,
            small.0 as f64 / 1e6,
            (large.1 / large.0 as f64) / (small.1 / small.0 as f64)
        );
        return;
    }
    let quick = args.iter().any(|a| a == "--quick");
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
    let single = rayon::ThreadPoolBuilder::new().num_threads(1).build().expect("a one-thread pool");
    let start = Instant::now();
    drop(single.install(|| build(mesh, &options(target, Vec::new())).expect("one-piece build on one thread")));
    let one_thread_s = start.elapsed().as_secs_f64();

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
    let threads = rayon::current_num_threads();
    println!(
        "  #40: hausdorff partitioned / one piece {:.3}x (target <= 1.1x); wall time {:.2}x on {threads} threads (target <= 0.6x)",
        parted_h / one_h,
        parted_s / one_s,
    );
    println!(
        "  one piece on one thread {one_thread_s:.2} s: its speed-up on {threads} threads {:.2}x, so parts doing its work take about {:.2}x its {threads}-thread time; partitioned on {threads} threads / one piece on one thread {:.2}x",
        one_thread_s / one_s,
        one_s.recip() * one_thread_s / threads as f64,
        parted_s / one_thread_s,
    );
}

/// Chunks of the large run.
const LARGE_CHUNKS: usize = 16;

/// One stage of the large run, in a process of its own (this bench run again with
/// `--stage plan DIR`, `--stage chunk DIR K` or `--stage merge DIR`), as a job runner would
/// run it: it prints its seconds and its peak resident memory (VmHWM, KiB) as its last line.
fn run_stage(args: &[String]) {
    asperity::memory::return_large_buffers_to_the_os();
    assert!(args.len() >= 2, "--stage plan DIR, --stage chunk DIR K or --stage merge DIR");
    let dir = std::path::PathBuf::from(&args[1]);
    let (input, plan_dir) = (dir.join("input.ply"), dir.join("plan"));
    let start = Instant::now();
    let detail = match args[0].as_str() {
        "plan" => {
            let request = HierarchyRequest {
                target_vertices: Some(VertexTarget::Percent(0.1)),
                chunks: Some(LARGE_CHUNKS),
                ..Default::default()
            };
            // As `asperity simplify plan` reads it: a binary PLY as a stream.
            let (read, streamed) = asperity::io::read_lean(&input).expect("the input read");
            assert!(streamed, "the bench's binary PLY is read as a stream");
            MeshPlan::make(&read.mesh, &input, false, &request, &plan_dir).expect("the plan");
            0
        }
        "chunk" => {
            let index = args.get(2).and_then(|k| k.parse().ok()).expect("--stage chunk DIR K");
            run_chunk(&plan_dir, index).expect("a chunk built");
            0
        }
        "merge" => {
            let plan = MeshPlan::read(&plan_dir).expect("the plan");
            let read = asperity::io::read_lean(&input).expect("the input read").0.mesh;
            // The merge keeps the input it is given: its positions and faces become the
            // hierarchy's. Then its report, as `simplify merge` gives it (the Hausdorff
            // distance to the input measured piece by piece).
            let merged = join_plan(&plan_dir, &plan, std::borrow::Cow::Owned(read)).expect("the merge");
            let base = merged.base_mesh().mesh;
            BuildReport::of_faces(&merged.positions, &merged.input_triangles, &merged, &base).expect("the report");
            base.vertex_count()
        }
        other => panic!("no stage {other}"),
    };
    let peak = common::peak_rss_kib().expect("VmHWM in /proc/self/status");
    println!("{} {peak} {detail}", start.elapsed().as_secs_f64());
}

/// Runs one stage as a process of its own: (seconds, peak MB, the stage's figure).
fn stage(args: &[&str]) -> (f64, f64, usize) {
    let exe = std::env::current_exe().expect("this bench's path");
    let output = std::process::Command::new(exe).arg("--stage").args(args).output().expect("the stage ran");
    assert!(output.status.success(), "stage {args:?} failed: {}", String::from_utf8_lossy(&output.stderr));
    let text = String::from_utf8_lossy(&output.stdout);
    let fields: Vec<&str> = text.lines().last().unwrap_or("").split_whitespace().collect();
    let parse = |i: usize| fields.get(i).and_then(|f| f.parse::<f64>().ok()).expect("the stage's report");
    (parse(0), parse(1) / 1024.0, parse(2) as usize)
}

/// Fandisk after `steps` Loop steps through plan, chunks (one after another) and merge, each
/// a process of its own; prints each stage's peak and time and returns (triangles, seconds
/// of the three stages).
fn planned_stages(steps: u32) -> (usize, f64) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/data/meshes/fandisk.off");
    let mut mesh =
        asperity::io::read(&path).unwrap_or_else(|e| panic!("fandisk belongs at {}: {e}", path.display())).mesh;
    for _ in 0..steps {
        mesh = asperity::mesh::loop_subdivide(&mesh).expect("fandisk is a closed manifold");
    }
    let triangles = mesh.face_count();
    let dir = tempfile::tempdir_in(env!("CARGO_TARGET_TMPDIR")).expect("a folder for the plan");
    let input = dir.path().join("input.ply");
    asperity::io::write(&mesh, &input, Default::default()).expect("the input written");
    let input_mb = file_mb(&input);
    drop(mesh);
    println!(
        "fandisk after {steps} Loop steps: {triangles} triangles ({input_mb:.0} MB binary PLY); {LARGE_CHUNKS} chunks, to 0.1 %, each stage a process"
    );
    let per_triangle = |mb: f64, tris: usize| mb * 1024.0 * 1024.0 / tris.max(1) as f64;
    let dir_arg = dir.path().to_string_lossy().to_string();

    let (plan_s, plan_mb, _) = stage(&["plan", &dir_arg]);
    println!(
        "  plan: {plan_s:.1} s, peak {plan_mb:.0} MB ({:.0} B per input triangle; {:.2}x the input file)",
        per_triangle(plan_mb, triangles),
        plan_mb * 1.048_576 / input_mb
    );
    let plan = MeshPlan::read(&dir.path().join("plan")).expect("the plan");

    let (mut chunks_s, mut worst) = (0.0, (0.0f64, 0usize, 0.0f64));
    for (k, chunk) in plan.chunks.iter().enumerate() {
        let (seconds, mb, _) = stage(&["chunk", &dir_arg, &k.to_string()]);
        chunks_s += seconds;
        if mb > worst.0 {
            worst = (mb, chunk.faces, per_triangle(mb, chunk.faces));
        }
    }
    let built_mb: f64 = plan.chunks.iter().map(|c| file_mb(&dir.path().join("plan").join(&c.build))).sum();
    println!(
        "  chunks one after another: {chunks_s:.1} s; highest peak {:.0} MB for {} faces ({:.0} B per triangle of its share); the built chunks {built_mb:.0} MB",
        worst.0, worst.1, worst.2
    );

    let (merge_s, merge_mb, base) = stage(&["merge", &dir_arg]);
    println!(
        "  merge: {merge_s:.1} s, {base} base vertices (target {}), peak {merge_mb:.0} MB ({:.0} B per input triangle; {:.1}x the built chunks' bytes)",
        plan.options().expect("the plan's options").target_vertices.unwrap_or(0),
        per_triangle(merge_mb, triangles),
        merge_mb * 1.048_576 / built_mb.max(f64::MIN_POSITIVE)
    );
    let total = plan_s + chunks_s + merge_s;
    println!("  total {total:.1} s: {:.2} us per triangle", total * 1e6 / triangles as f64);
    (triangles, total)
}

/// A file's size in MB; a file the stages should have written and did not stops the bench
/// (counted as 0 MB it would make the merge's ratio to the chunks look better than it is).
fn file_mb(path: &std::path::Path) -> f64 {
    let meta = std::fs::metadata(path).unwrap_or_else(|e| panic!("{} should have been written: {e}", path.display()));
    meta.len() as f64 / 1e6
}
