//! `asperity demo [--out DIR]`: the main job on built-in inputs. For now it builds a torus
//! and an icosphere in code, round-trips them through OpenMesh, measures them with CGAL,
//! and writes the meshes under `DIR`; later stages (terrain, detail) extend it.

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;

use crate::error::{Error, Result};
use crate::ffi::{self, HalfEdgeMesh, HausdorffOptions};
use crate::io::{self, WriteOptions};
use crate::mesh::{Mesh, primitives};

#[derive(Debug, Args)]
pub struct DemoArgs {
    /// Output folder.
    #[arg(long, default_value_os_t = super::default_out())]
    out: PathBuf,
}

pub fn run(args: DemoArgs) -> Result<()> {
    std::fs::create_dir_all(&args.out).map_err(|e| Error::io(&args.out, e))?;
    let torus = primitives::torus(1.0, 0.35, 96, 48);
    let sphere = primitives::icosphere(1.0, 4);

    for (name, mesh) in [("torus", &torus), ("icosphere", &sphere)] {
        openmesh_round_trip(name, mesh)?;
    }

    let start = Instant::now();
    let coarse = primitives::icosphere(1.0, 2);
    let d = ffi::hausdorff_distance(&sphere, &coarse, HausdorffOptions::default())?;
    println!(
        "cgal: hausdorff(icosphere {} tris, icosphere {} tris) = {d:.5} ({:.2}% of the diameter) in {} ms",
        sphere.face_count(),
        coarse.face_count(),
        100.0 * d / 2.0,
        super::millis(start)
    );

    let start = Instant::now();
    let pairs = ffi::self_intersections(&torus)?;
    println!("cgal: torus self-intersections: {} face pairs in {} ms", pairs.len(), super::millis(start));

    let start = Instant::now();
    let quadrics = ffi::vertex_quadrics(&torus, 100.0)?;
    let lifted: Vec<_> = torus.positions.iter().map(|p| *p * 1.01).collect();
    let errors = ffi::quadric_errors(&quadrics, &lifted)?;
    let mean = errors.iter().sum::<f64>() / errors.len() as f64;
    println!(
        "cgal: garland-heckbert quadrics of {} vertices, mean error after 1% scaling {mean:.3e} in {} ms",
        quadrics.len(),
        super::millis(start)
    );

    write_result(&torus, &args.out.join("torus.ply"))?;
    write_result(&sphere, &args.out.join("icosphere.obj"))?;
    write_result(&coarse, &args.out.join("icosphere-coarse.off"))?;

    if let Some(fandisk) = shared_mesh("fandisk.off") {
        let start = Instant::now();
        let outcome = io::read(&fandisk)?;
        let report = outcome.mesh.validate();
        println!(
            "read: {} ({} vertices, {} tris, genus {}) in {} ms",
            fandisk.display(),
            report.vertices,
            report.faces,
            report.genus.map_or("n/a".into(), |g| g.to_string()),
            super::millis(start)
        );
        openmesh_round_trip("fandisk", &outcome.mesh)?;
        write_result(&outcome.mesh, &args.out.join("fandisk.ply"))?;
    }
    println!("demo: results in {}", args.out.display());
    Ok(())
}

fn openmesh_round_trip(name: &str, mesh: &Mesh) -> Result<()> {
    let start = Instant::now();
    let he = HalfEdgeMesh::from_mesh(mesh)?;
    let counts = he.counts()?;
    let back = he.export()?.mesh;
    if back.positions != mesh.positions || back.triangles != mesh.triangles {
        return Err(Error::Internal(format!("{name}: the OpenMesh round trip changed the mesh")));
    }
    println!(
        "openmesh: {name} {} vertices, {} edges, {} tris round trip exact in {} ms",
        counts.vertices,
        counts.edges,
        counts.faces,
        super::millis(start)
    );
    Ok(())
}

fn write_result(mesh: &Mesh, path: &Path) -> Result<()> {
    io::write(mesh, path, WriteOptions::default())?;
    println!("write: {} ({} tris)", path.display(), mesh.face_count());
    Ok(())
}

/// A mesh of `../shared/data/meshes` (next to the working directory or the executable's
/// checkout), when present.
fn shared_mesh(name: &str) -> Option<PathBuf> {
    let candidates = [
        PathBuf::from("../shared/data/meshes"),
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/data/meshes"),
    ];
    candidates.iter().map(|dir| dir.join(name)).find(|p| p.is_file())
}
