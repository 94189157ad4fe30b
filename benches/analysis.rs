//! Normals + curvatures + features on a 1M-vertex mesh (issue #5's target: ≤ 1 s on
//! 2 cores), one line per stage.
//!
//! `cargo bench --bench analysis`

use std::time::Instant;

use asperity::analysis::{
    AnalysisOptions, FaceGeometry, analyze, classify, curvatures, vertex_normals, voting_tensors,
};
use asperity::mesh::Adjacency;
use asperity::mesh::primitives::torus;

fn main() {
    let mesh = torus(2.0, 0.6, 1000, 1000);
    println!(
        "mesh: {} vertices, {} tris, {} threads",
        mesh.vertex_count(),
        mesh.face_count(),
        rayon::current_num_threads()
    );
    let stage = |label: &str, start: Instant| println!("{label}: {:.0} ms", start.elapsed().as_secs_f64() * 1e3);

    let start = Instant::now();
    let adjacency = Adjacency::of(&mesh);
    stage("adjacency", start);
    let start = Instant::now();
    let faces = FaceGeometry::of(&mesh);
    stage("face geometry", start);
    let start = Instant::now();
    let normals = vertex_normals(&mesh, &adjacency, &faces, Default::default());
    stage("normals", start);
    let start = Instant::now();
    let _ = curvatures(&mesh, &adjacency, &faces, &normals);
    stage("curvatures", start);
    let start = Instant::now();
    let tensors = voting_tensors(&mesh, &adjacency, &faces);
    stage("voting tensors", start);
    let start = Instant::now();
    let _ = classify(&mesh.positions, &adjacency, &tensors, &Default::default());
    stage("classes", start);

    let start = Instant::now();
    let analysis = analyze(&mesh, &AnalysisOptions::default()).expect("analysis");
    println!(
        "analyze: {} vertices => {:?} classes in {:.0} ms (target 1000 ms on 2 cores)",
        mesh.vertex_count(),
        analysis.class_counts(),
        start.elapsed().as_secs_f64() * 1e3
    );
}
