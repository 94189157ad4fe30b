//! Reads a mesh, prints its validation report, and round-trips it through OpenMesh.
//!
//! `cargo run --example mesh_report -- ../shared/data/meshes/fandisk.off`

use asperity::ffi::HalfEdgeMesh;
use asperity::io;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = std::env::args().nth(1).ok_or("usage: mesh_report MESH")?;
    let outcome = io::read(path.as_ref())?;
    let report = outcome.mesh.validate();
    println!("{path}: {report:#?}");
    let half_edge = HalfEdgeMesh::from_mesh(&outcome.mesh)?;
    println!("openmesh: {half_edge:?}");
    Ok(())
}
