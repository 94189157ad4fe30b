//! The bodies of the fuzz targets (`fuzz/`, run by `make fuzz`), here so that the
//! regression test (`tests/io/fuzz_regressions.rs`) replays every saved input through exactly
//! the same code. Each function panics only when an invariant breaks; bad input must come
//! back as an error, never as a panic.

use std::path::Path;

use glam::DVec3;

use crate::analysis::{AnalysisOptions, analyze};
use crate::detail::Recipe;
use crate::hierarchy::{KeepFeatures, Refiner, SimplifyOptions, build};
use crate::io::{Format, read_bytes};
use crate::mesh::{Mesh, repair};

/// A reader on arbitrary bytes: an error is fine, and a mesh read must be consistent,
/// validate, and repair into a manifold.
pub fn read(format: Format, bytes: &[u8]) {
    let Ok(outcome) = read_bytes(bytes, format, Path::new("fuzz-input")) else { return };
    let mesh = outcome.mesh;
    mesh.check().expect("a mesh the reader returns passes check");
    let _ = mesh.validate();
    if mesh.face_count() <= 10_000 {
        assert_repairs_to_a_manifold(&mesh);
    }
}

/// The recipe parser on arbitrary text: an error names a line inside the text.
pub fn recipe(bytes: &[u8]) {
    let Ok(text) = std::str::from_utf8(bytes) else { return };
    if let Err((Some(line), _)) = Recipe::parse(text) {
        assert!(line >= 1 && line <= text.lines().count().max(1) + 1, "line {line} outside the text");
    }
}

/// Arbitrary bytes as a small mesh: a vertex count, then vertices on a coarse integer
/// lattice (so that coincident and collinear points are common), then triangles.
pub fn mesh_from_bytes(bytes: &[u8]) -> Mesh {
    let Some((&count, rest)) = bytes.split_first() else { return Mesh::default() };
    let n = usize::from(count % 24) + 3;
    let (coords, ids) = rest.split_at(rest.len().min(3 * n));
    let lattice = |b: u8| f64::from(b % 16) - 8.0;
    let mut positions: Vec<DVec3> =
        coords.chunks_exact(3).map(|c| DVec3::new(lattice(c[0]), lattice(c[1]), lattice(c[2]))).collect();
    while positions.len() < n {
        let k = positions.len() as f64;
        positions.push(DVec3::new(k, k * k % 7.0, (k * 3.0) % 5.0));
    }
    let triangles = ids.chunks_exact(3).map(|t| [t[0], t[1], t[2]].map(|v| u32::from(v) % n as u32)).collect();
    Mesh::new(positions, triangles)
}

/// The pipeline on a small mesh from `bytes`: repair, then (when the result is an
/// orientable manifold with faces) build the 4-k hierarchy, refine it all the way back with
/// bit-exact positions, and analyze the surface.
pub fn pipeline(bytes: &[u8]) {
    let mesh = mesh_from_bytes(bytes);
    let Some(repaired) = assert_repairs_to_a_manifold(&mesh) else { return };
    if repaired.face_count() == 0 {
        return;
    }
    let _ = analyze(&repaired, &AnalysisOptions::default());
    for keep in [KeepFeatures::Strong, KeepFeatures::None] {
        let options = SimplifyOptions { keep_features: keep, target_vertices: Some(4), ..Default::default() };
        let Ok(hierarchy) = build(&repaired, &options) else { continue };
        let mut refiner = Refiner::new(&hierarchy).expect("a built hierarchy refines");
        refiner.refine_all().expect("refinement of a built hierarchy succeeds");
        let out = refiner.mesh().expect("the refined mesh exports");
        assert!(out.has_input_positions(&repaired), "the round trip moved a vertex");
    }
}

/// Repairs `mesh` and checks the result; returns it when the surface is orientable.
fn assert_repairs_to_a_manifold(mesh: &Mesh) -> Option<Mesh> {
    let (out, report) = repair(mesh).expect("a checked mesh repairs");
    let r = out.validate();
    assert!(r.is_manifold(), "repair left a non-manifold mesh: {r:?}");
    assert_eq!((r.degenerate_faces, r.unreferenced_vertices), (0, 0), "{r:?}");
    assert_eq!(r.inconsistently_oriented_edges, report.non_orientable_edges, "{report:?}");
    (report.non_orientable_edges == 0).then_some(out)
}
