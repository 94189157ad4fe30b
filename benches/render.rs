//! Software rendering cost (#8): a 1 M-triangle torus and the 1.31 M-triangle icosphere at
//! 1024², in each mode. The target is ≤ 2 s per picture for a million triangles.
//!
//! `cargo bench --bench render`

use std::time::Instant;

use asperity::Mesh;
use asperity::mesh::primitives::{icosphere, torus};
use asperity::render::{Mode, RenderOptions, render};

fn time(name: &str, mesh: &Mesh, mode: Mode) {
    let options = RenderOptions { width: 1024, height: 1024, mode, ..RenderOptions::default() };
    render(mesh, &options).expect("warm-up render");
    let runs = 3;
    let start = Instant::now();
    for _ in 0..runs {
        render(mesh, &options).expect("render");
    }
    let seconds = start.elapsed().as_secs_f64() / runs as f64;
    println!(
        "render: {name} {} tris at 1024x1024 ({mode:?}, 2x2 samples) in {:.0} ms ({:.2}x the 2 s budget) on {} threads",
        mesh.face_count(),
        seconds * 1e3,
        seconds / 2.0,
        rayon::current_num_threads()
    );
}

fn main() {
    let ring = torus(1.0, 0.35, 1000, 500);
    let sphere = icosphere(1.0, 8);
    for mode in [Mode::Faces, Mode::Wireframe, Mode::Points] {
        time("torus", &ring, mode);
    }
    time("icosphere", &sphere, Mode::Faces);
    let single = rayon::ThreadPoolBuilder::new().num_threads(1).build().expect("pool");
    single.install(|| time("torus", &ring, Mode::Faces));
}
