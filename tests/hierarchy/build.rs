//! The 4-k hierarchy (#6): topology kept at every level, features and boundaries kept,
//! the parametrization valid, and the round trip exact.

use std::collections::HashSet;

use asperity::ffi::{self, HalfEdgeMesh};
use asperity::hierarchy::{KeepFeatures, Refiner, Rings, SimplifyOptions, build, connectivity_match, face_key};
use asperity::mesh::primitives::{icosphere, torus};
use asperity::mesh::{Mesh, ValidationReport};
use asperity::{analysis, io};
use glam::DVec3;

use crate::common::shared_meshes;

fn shared(name: &str) -> Mesh {
    io::read(&shared_meshes().join(name)).expect("shared mesh reads").mesh
}

fn options() -> SimplifyOptions {
    SimplifyOptions { record_levels: true, ..SimplifyOptions::default() }
}

fn cyclic_equal(a: &[u32], b: &[u32]) -> bool {
    a.len() == b.len() && (a.is_empty() || (0..a.len()).any(|s| (0..a.len()).all(|i| a[(s + i) % a.len()] == b[i])))
}

#[test]
fn planning_rings_follow_openmesh_through_flips_splits_and_welds() {
    let mesh = torus(1.0, 0.4, 12, 8);
    let n = mesh.vertex_count();
    let mut grown = mesh.clone();
    grown.positions.push(glam::DVec3::new(0.0, 0.0, 5.0)); // an isolated vertex to insert
    let mut store = HalfEdgeMesh::from_mesh(&grown).unwrap();
    let live: Vec<u32> = (0..n as u32).collect();
    let mut rings = Rings::fetch(&store, &live, n + 1).unwrap();
    // A flip, a split with the isolated vertex, then spoke flips down to degree 4 and a weld.
    let (a, b) = (0, rings.ring(0)[0]);
    rings.flip(a, b).unwrap();
    assert_eq!(store.flip_edges(&[[a, b]]).unwrap(), vec![ffi::OpStatus::Done]);
    let (c, d) = (5, rings.ring(5)[2]);
    rings.split(c, d, n as u32).unwrap();
    assert_eq!(store.insert_on_edges(&[[c, d]], &[n as u32], &[glam::DVec3::ZERO]).unwrap(), vec![ffi::OpStatus::Done]);
    let v = 40;
    while rings.degree(v) > 4 {
        let apex = rings.ring(v)[0];
        rings.flip(v, apex).unwrap();
        assert_eq!(store.flip_edges(&[[v, apex]]).unwrap(), vec![ffi::OpStatus::Done]);
    }
    let to = rings.ring(v)[1];
    rings.weld(v, to).unwrap();
    let status =
        store.collapse_halfedges(&[[v, to]], ffi::CollapseOptions { required_degree: 4, check_normals: false });
    assert_eq!(status.unwrap(), vec![ffi::OpStatus::Done]);
    let now: Vec<u32> = (0..=n as u32).filter(|&x| x != v).collect();
    let fresh = Rings::fetch(&store, &now, n + 1).unwrap();
    for &x in &now {
        assert!(cyclic_equal(rings.ring(x), fresh.ring(x)), "vertex {x}: {:?} vs {:?}", rings.ring(x), fresh.ring(x));
    }
}

#[test]
fn rings_list_the_store_faces_and_roll_back_their_edits() {
    let mesh = torus(1.0, 0.4, 12, 8);
    let store = HalfEdgeMesh::from_mesh(&mesh).unwrap();
    let live: Vec<u32> = (0..mesh.vertex_count() as u32).collect();
    let mut rings = Rings::fetch(&store, &live, live.len()).unwrap();
    let sorted = |faces: &[[u32; 3]]| {
        let mut keys: Vec<[u32; 3]> = faces.iter().map(|&t| face_key(t)).collect();
        keys.sort_unstable();
        keys
    };
    let faces = rings.faces(&live);
    assert_eq!(faces.len(), mesh.face_count());
    assert_eq!(sorted(&faces), sorted(&mesh.triangles));
    rings.checkpoint();
    let (a, b) = (0, rings.ring(0)[0]);
    rings.flip(a, b).unwrap();
    let v = 40;
    while rings.degree(v) > 4 {
        let apex = rings.ring(v)[0];
        rings.flip(v, apex).unwrap();
    }
    rings.weld(v, rings.ring(v)[1]).unwrap();
    assert_ne!(sorted(&rings.faces(&live)), sorted(&mesh.triangles));
    rings.rollback();
    let fresh = Rings::fetch(&store, &live, live.len()).unwrap();
    for &x in &live {
        assert_eq!(rings.ring(x), fresh.ring(x), "vertex {x}");
    }
}

fn assert_levels_keep_topology(name: &str, mesh: &Mesh, options: &SimplifyOptions) {
    let input = ValidationReport::of(mesh);
    let h = build(mesh, options).unwrap();
    assert!(h.steps() > 0, "{name}: nothing simplified");
    assert_eq!(h.levels.len(), h.steps() + 1);
    for (k, level) in h.levels.iter().enumerate() {
        let r = ValidationReport::of(&level.mesh);
        assert!(r.is_manifold() && r.inconsistently_oriented_edges == 0, "{name} level {k}: not an oriented manifold");
        assert_eq!(
            (r.genus, r.boundary_loops, r.components),
            (input.genus, input.boundary_loops, input.components),
            "{name} level {k}"
        );
        assert_eq!(r.degenerate_faces, 0, "{name} level {k}: degenerate faces");
    }
}

#[test]
fn every_level_keeps_genus_and_manifoldness() {
    assert_levels_keep_topology("torus", &torus(1.0, 0.35, 48, 24), &options());
    for name in ["eight.off", "elephant.off", "femur.off", "blade.off", "mushroom.off"] {
        let mesh = shared(name);
        assert_levels_keep_topology(name, &mesh, &options());
        assert_levels_keep_topology(name, &mesh, &SimplifyOptions { keep_features: KeepFeatures::None, ..options() });
    }
}

#[test]
fn boundaries_are_simplified_along_themselves_and_keep_their_loops() {
    for name in ["blade.off", "mushroom.off", "double-torus-3-holes.off"] {
        let mesh = shared(name);
        let input = ValidationReport::of(&mesh);
        let target = (mesh.vertex_count() * 5).div_ceil(100).max(25);
        let options = SimplifyOptions {
            target_vertices: Some(target),
            keep_features: KeepFeatures::None,
            record_levels: true,
            ..SimplifyOptions::default()
        };
        let h = build(&mesh, &options).unwrap();
        assert_eq!(h.base_vertex_count(), target, "{name}: the target is reached");
        let adjacency = asperity::mesh::Adjacency::of(&mesh);
        let boundary_removed = h.removals.iter().filter(|r| r.boundary).count();
        assert!(boundary_removed > 0, "{name}: no boundary vertex removed");
        for r in h.removals.iter().filter(|r| r.boundary) {
            assert!(adjacency.is_boundary(r.vertex as usize), "{name}: {} is not on the boundary", r.vertex);
        }
        for (k, level) in h.levels.iter().enumerate() {
            let report = ValidationReport::of(&level.mesh);
            assert_eq!(report.boundary_loops, input.boundary_loops, "{name} level {k}");
            // The level's boundary runs through input boundary vertices only.
            let level_adjacency = asperity::mesh::Adjacency::of(&level.mesh);
            for v in 0..level.mesh.vertex_count() {
                if level_adjacency.is_boundary(v) {
                    assert!(adjacency.is_boundary(level.ids[v] as usize), "{name} level {k}: vertex {v}");
                }
            }
        }
        assert_eq!(round_trip(&mesh, &options), 1.0, "{name}: round trip");
    }
}

#[test]
fn no_level_intersects_itself() {
    for name in ["eight.off", "elephant.off", "fandisk.off"] {
        let mesh = shared(name);
        assert!(ffi::self_intersections(&mesh).unwrap().is_empty(), "{name} input");
        let h = build(&mesh, &options()).unwrap();
        for (k, level) in h.levels.iter().enumerate() {
            let hits = ffi::self_intersections(&level.mesh).unwrap();
            assert!(hits.is_empty(), "{name} level {k}: {} intersecting face pairs", hits.len());
        }
    }
}

#[test]
fn the_guard_keeps_a_thin_pancake_from_cutting_itself() {
    assert_only_the_guard_keeps_apart(&crate::common::thin_pancake(), 20, "the pancake");
}

/// `mesh` does not cut itself, nor do its levels down to `target` vertices with the guard;
/// without it they do: the check is the guard's doing, not the mesh's.
fn assert_only_the_guard_keeps_apart(mesh: &Mesh, target: usize, what: &str) {
    assert!(ffi::self_intersections(mesh).unwrap().is_empty(), "{what} cuts itself before any level");
    assert_eq!(crossings_over_levels(mesh, target, true), 0, "{what}: a level cuts itself with the guard");
    assert!(crossings_over_levels(mesh, target, false) > 0, "{what}: no level cuts itself even without the guard");
}

/// The intersecting face pairs summed over the levels of `mesh` simplified to `target`
/// vertices, with the guard or without.
fn crossings_over_levels(mesh: &Mesh, target: usize, guard: bool) -> usize {
    let options = SimplifyOptions {
        target_vertices: Some(target),
        keep_features: KeepFeatures::None,
        record_levels: true,
        prevent_intersections: guard,
        ..SimplifyOptions::default()
    };
    let h = build(mesh, &options).unwrap();
    assert_eq!(h.base_vertex_count(), target);
    h.levels.iter().map(|level| ffi::self_intersections(&level.mesh).unwrap().len()).sum()
}

/// A bumpy sheet over the unit square, `cells`×`cells`: `z = lift + 0.03·sin(9x)·cos(7y)`.
fn bumpy_sheet(cells: u32, lift: f64) -> Mesh {
    let mut sheet = asperity::mesh::primitives::grid(cells);
    for p in &mut sheet.positions {
        p.z = lift + 0.03 * (9.0 * p.x).sin() * (7.0 * p.y).cos();
    }
    sheet
}

#[test]
fn the_guard_keeps_two_sheets_closer_than_the_error_apart() {
    // Two bumpy sheets 0.005 apart, a twelfth of their bumps' height, on different grids
    // (so their levels differ): flattening a bump moves a sheet further than the gap.
    let (lower, upper) = (bumpy_sheet(24, 0.0), bumpy_sheet(19, 0.005));
    let n = lower.vertex_count() as u32;
    let positions = [lower.positions, upper.positions].concat();
    let triangles = [lower.triangles, upper.triangles.iter().map(|t| t.map(|v| v + n)).collect()].concat();
    assert_only_the_guard_keeps_apart(&Mesh::new(positions, triangles), 120, "two sheets");
}

#[test]
fn the_guard_keeps_a_folded_strip_from_cutting_itself() {
    // One bumpy strip folded in two: 24 columns of cells from x = 0 to 2 at z = -0.004, a
    // column standing at x = 2 (the fold), 24 back from x = 2 to 0 at z = +0.004, each leg
    // 12 cells wide, both carrying the bumps 0.06·sin(5x)·cos(4y). The legs' cells are
    // split along opposite diagonals, so their levels differ; the gap is a fifteenth of the
    // bumps' height.
    let (m, rows) = (24_u32, 12_u32);
    let bump = |x: f64, y: f64| 0.06 * (5.0 * x).sin() * (4.0 * y).cos();
    let mut positions = Vec::new();
    for j in 0..=rows {
        let y = f64::from(j) / f64::from(rows);
        for i in 0..=2 * m + 1 {
            let (x, z) = if i <= m {
                (2.0 * f64::from(i) / f64::from(m), -0.004)
            } else {
                (2.0 * f64::from(2 * m + 1 - i) / f64::from(m), 0.004)
            };
            positions.push(DVec3::new(x, y, z + bump(x, y)));
        }
    }
    let id = |i: u32, j: u32| j * (2 * m + 2) + i;
    let mut triangles = Vec::new();
    for j in 0..rows {
        for i in 0..=2 * m {
            triangles.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            triangles.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    assert_only_the_guard_keeps_apart(&Mesh::new(positions, triangles), 60, "the folded strip");
}

#[test]
fn fandisk_corners_reach_the_base_domain() {
    let mesh = shared("fandisk.off");
    let analysis = analysis::analyze(&mesh, &Default::default()).unwrap();
    let h = build(&mesh, &SimplifyOptions::default()).unwrap();
    let base: HashSet<u32> = h.base_mesh().ids.into_iter().collect();
    let corners: Vec<usize> =
        (0..mesh.vertex_count()).filter(|&v| analysis.classes[v] == analysis::FeatureClass::Corner).collect();
    assert!(!corners.is_empty());
    for v in corners {
        assert!(base.contains(&(v as u32)), "corner {v} was removed");
    }
    assert!(h.feature_vertices > 0 && base.len() < mesh.vertex_count() / 4);
}

#[test]
fn bunny_reaches_one_percent_of_its_vertices() {
    let mesh = shared("bunny00.off");
    let target = mesh.vertex_count() / 100;
    let h = build(&mesh, &SimplifyOptions { target_vertices: Some(target), ..SimplifyOptions::default() }).unwrap();
    assert!(h.base_vertex_count() <= target, "{} vertices left", h.base_vertex_count());
}

fn assert_parameter_points_valid(name: &str, mesh: &Mesh) {
    let h = build(mesh, &SimplifyOptions::default()).unwrap();
    let base_faces: HashSet<[u32; 3]> = h.base_triangles.iter().map(|&t| face_key(t)).collect();
    let points = h.base_parametrization();
    for (v, p) in points.iter().enumerate() {
        let p = p.unwrap_or_else(|| panic!("{name}: vertex {v} has no parameter point"));
        assert!(base_faces.contains(&face_key(p.point.face)), "{name}: vertex {v} on a face not in the base domain");
        assert!(p.point.bary.iter().all(|&b| b >= -1e-9), "{name}: vertex {v} bary {:?}", p.point.bary);
        assert!((p.point.bary.iter().sum::<f64>() - 1.0).abs() <= 1e-12, "{name}: vertex {v} bary sum");
        assert!(p.level as usize <= h.steps());
    }
    for r in &h.removals {
        assert!(r.local.bary.iter().all(|&b| b >= -1e-9) && (r.local.bary.iter().sum::<f64>() - 1.0).abs() <= 1e-12);
    }
    // The indexed form (what the Python and C++ packages hand out) is the same point: the
    // barycentric combination of the indexed triangle's corners equals the keyed face's.
    let indexed = h.indexed_parametrization().unwrap();
    for (v, (p, q)) in points.iter().zip(&indexed).enumerate() {
        let (p, q) = (p.unwrap(), q.unwrap());
        let t = h.base_triangles[q.face];
        assert_eq!(face_key(t), face_key(p.point.face), "{name}: vertex {v}'s indexed face");
        assert_eq!(q.level, p.level);
        let at = |face: [u32; 3], bary: [f64; 3]| -> glam::DVec3 {
            (0..3).map(|k| h.positions[face[k] as usize] * bary[k]).sum()
        };
        let d = at(t, q.barycentric).distance(at(p.point.face, p.point.bary));
        assert!(d <= 1e-12 * (1.0 + h.positions[v].length()), "{name}: vertex {v} moved {d}");
    }
}

#[test]
fn options_no_build_can_use_are_refused_naming_the_field() {
    let mesh = torus(1.0, 0.35, 16, 8);
    for (options, field) in [
        (SimplifyOptions { max_error: Some(-0.1), ..options() }, "max_error"),
        (SimplifyOptions { removal_weight: f64::NAN, ..options() }, "removal_weight"),
        (SimplifyOptions { swap_weight: -1.0, ..options() }, "swap_weight"),
        (SimplifyOptions { fix_threshold_degrees: 0.0, ..options() }, "fix_threshold_degrees"),
        (SimplifyOptions { fix_threshold_degrees: 200.0, ..options() }, "fix_threshold_degrees"),
    ] {
        let e = build(&mesh, &options).unwrap_err();
        assert_eq!(e.exit_code(), 2, "{e}");
        assert!(e.to_string().contains(field), "{e}");
    }
    assert!(build(&mesh, &SimplifyOptions { fix_threshold_degrees: 180.0, ..options() }).is_ok());
}

#[test]
fn every_vertex_has_a_valid_base_domain_point() {
    assert_parameter_points_valid("torus", &torus(1.0, 0.35, 48, 24));
    for name in ["fandisk.off", "femur.off", "mushroom.off"] {
        let mesh = shared(name);
        assert_parameter_points_valid(name, &mesh);
    }
}

/// Builds, refines all the way and checks positions bit for bit; returns the share of
/// input faces restored.
fn round_trip(mesh: &Mesh, options: &SimplifyOptions) -> f64 {
    let h = build(mesh, options).unwrap();
    let mut refiner = Refiner::new(&h).unwrap();
    refiner.refine_all().unwrap();
    let out = refiner.mesh().unwrap();
    assert_eq!(out.ids, (0..mesh.vertex_count() as u32).collect::<Vec<_>>());
    for (v, (a, b)) in out.mesh.positions.iter().zip(&mesh.positions).enumerate() {
        assert_eq!(a.to_array().map(f64::to_bits), b.to_array().map(f64::to_bits), "vertex {v}");
    }
    connectivity_match(&mesh.triangles, &out.triangles_in_ids())
}

#[test]
fn round_trip_restores_positions_and_connectivity() {
    assert_eq!(round_trip(&torus(1.0, 0.35, 48, 24), &SimplifyOptions::default()), 1.0);
    assert_eq!(
        round_trip(&icosphere(1.0, 3), &SimplifyOptions { keep_features: KeepFeatures::None, ..Default::default() }),
        1.0
    );
    for path in crate::common::shared_mesh_files() {
        let mesh = io::read(&path).unwrap().mesh;
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        for keep in [KeepFeatures::Strong, KeepFeatures::None] {
            let matched = round_trip(&mesh, &SimplifyOptions { keep_features: keep, ..Default::default() });
            eprintln!("round trip {name} ({keep:?}): {:.3}% of faces restored", matched * 100.0);
            assert!(matched >= 0.95, "{name}: only {:.2}% of faces restored", matched * 100.0);
        }
    }
}

#[test]
fn refining_a_region_only_inserts_vertices_there() {
    let mesh = torus(1.0, 0.35, 48, 24);
    let h = build(&mesh, &SimplifyOptions::default()).unwrap();
    let mut refiner = Refiner::new(&h).unwrap();
    let positions = mesh.positions.clone();
    let inside = |v: u32| positions[v as usize].x > 0.0;
    while !refiner.is_finished() {
        refiner.refine_level(&inside).unwrap();
    }
    let out = refiner.mesh().unwrap();
    let r = ValidationReport::of(&out.mesh);
    assert!(r.is_manifold() && r.genus == Some(1), "{r:?}");
    let base: HashSet<u32> = h.base_mesh().ids.into_iter().collect();
    let right = (0..mesh.vertex_count() as u32).filter(|&v| inside(v)).count();
    let present_right = out.ids.iter().filter(|&&v| inside(v)).count();
    let present_left_fine = out.ids.iter().filter(|&&v| !inside(v) && !base.contains(&v)).count();
    assert!(present_right * 10 >= right * 9, "{present_right} of {right} selected vertices inserted");
    assert_eq!(present_left_fine, 0, "unselected vertices were inserted");
}

#[test]
fn building_twice_gives_the_same_hierarchy() {
    let mesh = shared("elephant.off");
    let a = build(&mesh, &SimplifyOptions::default()).unwrap();
    let b = build(&mesh, &SimplifyOptions::default()).unwrap();
    assert_eq!(a.removals, b.removals);
    assert_eq!(a.base_triangles, b.base_triangles);
}

#[test]
fn non_manifold_input_is_refused_with_the_reason() {
    let mut mesh = icosphere(1.0, 1);
    let t = mesh.triangles[0];
    mesh.positions.push(glam::DVec3::new(3.0, 0.0, 0.0));
    mesh.triangles.push([t[0], t[1], mesh.positions.len() as u32 - 1]);
    let err = build(&mesh, &SimplifyOptions::default()).unwrap_err();
    assert!(
        err.to_string().contains("not an oriented manifold") && err.to_string().contains("1 non-manifold edges"),
        "{err}"
    );
}

#[test]
fn openmesh_replaying_the_plans_ends_with_the_rings_base_domain() {
    // #20: the build plans on the Rust rings alone; replayed on OpenMesh (flips, welds,
    // boundary welds), the same plans must leave the same base domain, and the hierarchy
    // must not depend on whether they were replayed. A closed surface, a CAD part with
    // feature lines, and a scan with boundary loops.
    let bunny = shared("bunny00.off");
    let mut open_torus = torus(1.0, 0.4, 40, 20);
    open_torus.triangles.truncate(open_torus.triangles.len() - 80);
    asperity::mesh::drop_unreferenced_vertices(&mut open_torus);
    let cases = [
        ("torus", torus(1.0, 0.35, 48, 24), options()),
        ("fandisk", shared("fandisk.off"), SimplifyOptions { keep_features: KeepFeatures::Strong, ..options() }),
        ("bunny00", bunny, options()),
        ("open torus", open_torus, options()),
    ];
    for (name, mesh, opts) in cases {
        let replayed = asperity::hierarchy::build_with_openmesh_replay(&mesh, &opts)
            .unwrap_or_else(|e| panic!("{name}: OpenMesh disagrees with the plans: {e}"));
        let planned = build(&mesh, &opts).unwrap();
        assert_eq!(replayed.base_triangles, planned.base_triangles, "{name}: base domain");
        assert_eq!(replayed.removals, planned.removals, "{name}: removals");
        assert_eq!(replayed.restore, planned.restore, "{name}: restore flips");
        assert!(replayed.steps() > 3, "{name}: {} levels", replayed.steps());
    }
}

#[test]
fn no_level_of_a_menger_sponge_lets_coplanar_faces_touch() {
    // The guard decides on the model's own positions: in the unit frame, rounding parts
    // faces that touch in the model (a vertex exactly on another face's edge), and the
    // corpus' Menger sponge came out cutting itself at 21 face pairs.
    let mesh = crate::common::menger_sponge(1.0);
    let report = mesh.validate();
    assert!(report.is_manifold() && report.inconsistently_oriented_edges == 0, "the sponge is a manifold: {report:?}");
    assert!(ffi::self_intersections(&mesh).unwrap().is_empty(), "the sponge's faces meet only where they share");
    let options = SimplifyOptions { target_vertices: Some(mesh.vertex_count() / 10), record_levels: true, ..options() };
    let h = build(&mesh, &options).unwrap();
    assert!(h.steps() > 3, "the sponge simplifies ({} levels)", h.steps());
    for (k, level) in h.levels.iter().enumerate() {
        let hits = ffi::self_intersections(&level.mesh).unwrap();
        assert!(hits.is_empty(), "level {k}: {} intersecting face pairs", hits.len());
    }
}

#[test]
fn corners_only_features_keep_the_corners_and_let_the_edges_go() {
    // #37, thesis Fig. 5.15: features by corners alone. On a subdivided box the eight
    // corners reach the base; the edges' vertices are removed like any other (with
    // `strong`, they are feature vertices kept on their lines).
    let mesh = asperity::mesh::primitives::cube(glam::DVec3::ZERO, glam::DVec3::ONE, 8);
    let analysis = analysis::analyze(&mesh, &Default::default()).unwrap();
    let corners: Vec<u32> = (0..mesh.vertex_count() as u32)
        .filter(|&v| analysis.classes[v as usize] == analysis::FeatureClass::Corner)
        .collect();
    assert_eq!(corners.len(), 8, "the box's corners");
    let build_with = |keep| {
        build(&mesh, &SimplifyOptions { keep_features: keep, target_vertices: Some(40), ..Default::default() }).unwrap()
    };
    let only_corners = build_with(KeepFeatures::Corners);
    let base: HashSet<u32> = only_corners.base_mesh().ids.into_iter().collect();
    assert!(corners.iter().all(|v| base.contains(v)), "a corner was removed");
    assert_eq!(only_corners.feature_vertices, 8, "only the corners are feature vertices");
    assert!(build_with(KeepFeatures::Strong).feature_vertices > 8, "strong keeps edge vertices too");
}

#[test]
fn build_stages_print_the_planning_thread_then_the_recorder_thread() {
    let stages = asperity::hierarchy::BuildStages {
        prepare: 1.0,
        ranking: 2.0,
        planning: 3.0,
        guard: 4.0,
        parametrization: 5.0,
        handoff: 6.0,
        store: 7.0,
        records: 8.0,
        export: 9.0,
    };
    assert_eq!(
        stages.to_string(),
        "prepare 1.00 s, ranking 2.00 s, planning 3.00 s, guard 4.00 s, parametrization 5.00 s, handoff 6.00 s; recorder thread: store 7.00 s, records 8.00 s, export 9.00 s"
    );
    assert_eq!(stages.planning_thread().iter().map(|(_, t)| t).sum::<f64>(), 21.0);
}
