//! Detail mapping's cost per stage (#7): the femur and a sphere of 1.31 M triangles through
//! hierarchy build, a three-step recipe (coarse variation, middle-level feature-guided
//! Gabor with Table 5.1 propagation, fine turbulence) applied during refinement, and the
//! self-intersection stage. The detail steps must cost less than the hierarchy build.
//!
//! `cargo bench --bench detail` (`-- --quick` uses the 327 k-triangle sphere).

use std::time::Instant;

use asperity::Mesh;
use asperity::detail::{DetailOptions, Recipe, apply_to};
use asperity::hierarchy::{SimplifyOptions, build};
use asperity::io;
use asperity::mesh::primitives::icosphere;

const RECIPE: &str = r#"
seed = 4

[[step]]
op = "variation"
level = 1
noise = { kind = "turbulence", amplitude = 0.05, frequency = 3.0 }

[[step]]
op = "noise"
level = -4
select = { independent = { exclusion = 3 } }
noise = { kind = "gabor", amplitude = 0.004, frequency = 30.0, rings = [
  { influence = 0.8, k = 1.0, a = 0.05 }, { influence = 0.5, k = 0.8, a = 0.04 },
  { influence = 0.25, k = 0.6, a = 0.03 }, { influence = 0.1, k = 0.4, a = 0.02 } ] }

[[step]]
op = "noise"
level = -1
noise = { kind = "turbulence", amplitude = 0.002, frequency = 40.0, octaves = 3, accumulate = true }
"#;

fn run(name: &str, mesh: &Mesh) {
    let recipe = Recipe::parse(RECIPE).expect("bench recipe parses");
    let simplify = SimplifyOptions { target_vertices: Some(mesh.vertex_count() / 100), ..Default::default() };
    let start = Instant::now();
    let hierarchy = build(mesh, &simplify).expect("hierarchy");
    let build_s = start.elapsed().as_secs_f64();
    let options = DetailOptions { simplify, ..Default::default() };
    let out = apply_to(&hierarchy, mesh, &recipe, &options).expect("detail");
    let s = out.seconds;
    println!(
        "{name}: {} tris, {} levels: hierarchy {build_s:.2} s, detail steps {:.3} s (steps/build {:.3}), refine {:.2} s, self-intersections {:.2} s ({} pairs)",
        mesh.face_count(),
        out.levels,
        s.detail,
        s.detail / build_s,
        s.refine,
        s.intersections,
        out.intersections.found
    );
    for step in &out.steps {
        println!(
            "  step {} {} at level {}: {} of {} vertices selected, {} touched, {:.3} s",
            step.step, step.op, step.level, step.selected, step.level_vertices, step.touched, step.seconds
        );
    }
}

fn main() {
    // As the asperity binary does: large freed buffers go back to the OS.
    asperity::memory::return_large_buffers_to_the_os();
    let quick = std::env::args().any(|a| a == "--quick");
    let femur = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/data/meshes/femur.off");
    if let Ok(read) = io::read(&femur) {
        run("femur", &read.mesh);
    }
    run("sphere", &icosphere(1.0, if quick { 7 } else { 8 }));
}
