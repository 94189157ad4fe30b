//! The validation report on meshes made in code, and against OpenMesh on the shared meshes.

use asperity::Mesh;
use asperity::ffi::HalfEdgeMesh;
use asperity::io;
use asperity::mesh::primitives::{cube, grid, icosphere, torus};
use glam::DVec3;

use crate::common::shared_mesh_files;

#[test]
fn closed_surfaces_have_their_genus() {
    let t = torus(2.0, 0.5, 16, 8).validate();
    assert_eq!((t.euler, t.genus, t.boundary_loops, t.components), (0, Some(1), 0, 1));
    assert_eq!((t.vertices, t.faces, t.edges), (128, 256, 384));
    let s = icosphere(1.0, 3).validate();
    assert_eq!((s.euler, s.genus, s.vertices), (2, Some(0), 642));
    let c = cube(DVec3::ZERO, DVec3::ONE, 3).validate();
    assert_eq!((c.euler, c.genus, c.vertices, c.faces), (2, Some(0), 6 * 9 + 2, 12 * 9));
    assert!(c.is_closed_manifold());
    assert_eq!(c.inconsistently_oriented_edges, 0);
}

#[test]
fn open_surfaces_count_their_boundary_loops() {
    let g = grid(4).validate();
    assert_eq!((g.boundary_loops, g.genus, g.euler), (1, Some(0), 1));
    // An annulus: the grid without its centre square has two boundary loops.
    let mut mesh = grid(3);
    let centre = mesh.triangles.len() / 2;
    mesh.triangles.drain(centre - 1..centre + 1);
    let r = mesh.validate();
    assert_eq!((r.boundary_loops, r.genus, r.euler), (2, Some(0), 0));
}

#[test]
fn defects_are_counted() {
    let p =
        vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::NEG_X, DVec3::NEG_Y, DVec3::Z, DVec3::splat(9.0), DVec3::X * 2.0];
    // Bowtie: two triangles sharing only vertex 0.
    let bowtie = Mesh::new(p.clone(), vec![[0, 1, 2], [0, 3, 4]]).validate();
    assert_eq!((bowtie.non_manifold_vertices, bowtie.non_manifold_edges, bowtie.genus), (1, 0, None));
    assert_eq!(bowtie.unreferenced_vertices, 3);
    // Three triangles on edge 0-1.
    let fin = Mesh::new(p.clone(), vec![[0, 1, 2], [1, 0, 4], [0, 1, 5]]).validate();
    assert_eq!(fin.non_manifold_edges, 1);
    // Two triangles traversing their shared edge the same way.
    let flipped = Mesh::new(p.clone(), vec![[0, 1, 2], [0, 1, 4]]).validate();
    assert_eq!(flipped.inconsistently_oriented_edges, 1);
    // A zero-area (collinear) triangle.
    let sliver = Mesh::new(p, vec![[0, 1, 7]]).validate();
    assert_eq!(sliver.degenerate_faces, 1);
}

#[test]
fn openmesh_agrees_with_the_report_on_shared_meshes() {
    for file in shared_mesh_files() {
        let mesh = io::read(&file).unwrap().mesh;
        let report = mesh.validate();
        let counts = HalfEdgeMesh::from_mesh(&mesh).unwrap().counts().unwrap();
        assert_eq!(
            (counts.vertices, counts.edges, counts.faces),
            (report.vertices, report.edges, report.faces),
            "{}",
            file.display()
        );
        assert!(report.is_manifold(), "{}", file.display());
    }
}

#[test]
fn shared_meshes_have_their_documented_topology() {
    let expected = [
        ("3torus.off", 3, 0),
        ("anchor.off", 4, 0),
        ("blade.off", 0, 2),
        ("bunny00.off", 0, 0),
        ("double-torus-3-holes.off", 2, 3),
        ("eight.off", 2, 0),
        ("elephant.off", 3, 0),
        ("fandisk.off", 0, 0),
        ("femur.off", 2, 0),
        ("mushroom.off", 0, 1),
    ];
    let files = shared_mesh_files();
    for (name, genus, loops) in expected {
        let Some(file) = files.iter().find(|f| f.ends_with(name)) else { continue };
        let outcome = io::read(file).unwrap();
        let r = outcome.mesh.validate();
        assert_eq!((r.genus, r.boundary_loops), (Some(genus), loops), "{name}");
        if name == "3torus.off" {
            assert_eq!(outcome.triangulated_polygons, 23);
        }
    }
}

#[test]
fn boundary_loops_follow_edges_whatever_the_orientation_and_twists_are_not_orientable() {
    // #24 item 9: two triangles sharing an edge in the same direction have one boundary
    // loop, not two; a Möbius strip has one loop and no orientation (no genus).
    let p = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::new(1.0, 1.0, 0.0)];
    let same_direction = Mesh::new(p, vec![[0, 1, 2], [1, 2, 3]]).validate();
    assert_eq!((same_direction.boundary_loops, same_direction.inconsistently_oriented_edges), (1, 1));
    assert!(same_direction.orientable, "flipping one face orients it");
    let mobius =
        io::read(&std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/bad/mobius.off")).unwrap().mesh;
    let r = mobius.validate();
    assert_eq!((r.boundary_loops, r.orientable, r.genus), (1, false, None));
    assert!(r.is_manifold());
    let torus = torus(1.0, 0.3, 12, 8).validate();
    assert_eq!((torus.orientable, torus.genus, torus.boundary_loops), (true, Some(1), 0));
}

/// A strip of `n` quads (two triangles each) around a circle, its last edge glued to the
/// first with a half twist or without; every `k`-th face written backwards.
fn band(n: u32, twisted: bool, flip_every: usize) -> Mesh {
    let mut positions = Vec::new();
    for i in 0..n {
        let a = std::f64::consts::TAU * f64::from(i) / f64::from(n);
        let radial = DVec3::new(a.cos(), a.sin(), 0.0);
        positions.push(radial * 3.0 + DVec3::Z * 0.5);
        positions.push(radial * 3.0 - DVec3::Z * 0.5);
    }
    let mut triangles = Vec::new();
    for i in 0..n {
        let (top, bottom) = (2 * i, 2 * i + 1);
        let (next_top, next_bottom) = match (i + 1 == n, twisted) {
            (true, true) => (1, 0),
            (true, false) => (0, 1),
            _ => (2 * i + 2, 2 * i + 3),
        };
        triangles.push([top, bottom, next_bottom]);
        triangles.push([top, next_bottom, next_top]);
    }
    for (f, t) in triangles.iter_mut().enumerate() {
        if flip_every > 0 && f % flip_every == 0 {
            t.swap(1, 2);
        }
    }
    Mesh::new(positions, triangles)
}

#[test]
fn orientability_holds_along_long_bands_whatever_faces_are_written_backwards() {
    // The union-find with parity joins faces far apart before the band closes: only the
    // half twist makes it non-orientable, however many faces are flipped.
    for flip_every in [0, 1, 3, 7] {
        let plain = band(400, false, flip_every).validate();
        assert!(plain.orientable && plain.is_manifold(), "plain band, every {flip_every}th face flipped");
        assert_eq!(plain.boundary_loops, 2);
        let twisted = band(400, true, flip_every).validate();
        assert!(!twisted.orientable && twisted.is_manifold(), "twisted band, every {flip_every}th face flipped");
        assert_eq!((twisted.boundary_loops, twisted.genus), (1, None));
    }
}
