//! Throughput of the foundation: file formats, the OpenMesh round trip and CGAL measures
//! on a 327,680-triangle icosphere, one line per stage.
//!
//! `cargo bench --bench spine`

use std::time::Instant;

use asperity::ffi::{self, HalfEdgeMesh, HausdorffOptions};
use asperity::io::{self, WriteOptions};
use asperity::mesh::primitives::icosphere;

fn timed<T>(label: &str, f: impl FnOnce() -> T) -> T {
    let start = Instant::now();
    let out = f();
    println!("{label}: {:.1} ms", start.elapsed().as_secs_f64() * 1e3);
    out
}

fn main() {
    let mesh = timed("build icosphere level 7", || icosphere(1.0, 7));
    println!("mesh: {} vertices, {} tris", mesh.vertex_count(), mesh.face_count());
    let dir = tempfile::tempdir().expect("temp dir");
    for (file, ascii) in [("m.ply", false), ("m.ply", true), ("m.off", false), ("m.stl", false), ("m.obj", false)] {
        let path = dir.path().join(file);
        let kind = if ascii { "ascii" } else { "default" };
        timed(&format!("write {file} ({kind})"), || io::write(&mesh, &path, WriteOptions { ascii }).expect("write"));
        timed(&format!("read {file} ({kind})"), || io::read(&path).expect("read"));
    }
    timed("validate", || mesh.validate());
    let half_edge = timed("openmesh build", || HalfEdgeMesh::from_mesh(&mesh).expect("build"));
    timed("openmesh export", || half_edge.export().expect("export"));
    timed("cgal quadrics", || ffi::vertex_quadrics(&mesh, 100.0).expect("quadrics"));
    let coarse = icosphere(1.0, 5);
    timed("cgal hausdorff (327k vs 20k tris)", || {
        ffi::hausdorff_distance(&mesh, &coarse, HausdorffOptions::default()).expect("hausdorff")
    });
}
