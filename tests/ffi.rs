//! The FFI spine: OpenMesh topology operations and CGAL measures.

use asperity::ffi::{self, CollapseOptions, HalfEdgeMesh, HausdorffOptions, OpStatus};
use asperity::mesh::primitives::{cube, grid, icosphere, torus};
use asperity::{Error, Mesh, VertexId};
use glam::DVec3;

fn all_vertices(mesh: &Mesh) -> Vec<VertexId> {
    (0..mesh.vertex_count() as u32).map(VertexId).collect()
}

#[test]
fn round_trip_through_openmesh_is_exact() {
    for mesh in [torus(2.0, 0.5, 24, 12), icosphere(1.0, 3), cube(DVec3::ZERO, DVec3::ONE, 3), grid(5)] {
        let he = HalfEdgeMesh::from_mesh(&mesh).unwrap();
        let counts = he.counts().unwrap();
        let report = mesh.validate();
        assert_eq!((counts.vertices, counts.edges, counts.faces), (report.vertices, report.edges, report.faces));
        let exported = he.export().unwrap();
        assert_eq!(exported.mesh.positions, mesh.positions);
        assert_eq!(exported.mesh.triangles, mesh.triangles);
        assert_eq!(exported.vertex_remap, (0..mesh.vertex_count() as u32).collect::<Vec<_>>());
    }
}

#[test]
fn non_manifold_faces_are_reported_not_dropped() {
    // Three triangles on one edge: the third cannot be added.
    let positions = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::NEG_Y, DVec3::Z];
    let mesh = Mesh::new(positions, vec![[0, 1, 2], [1, 0, 3], [0, 1, 4]]);
    match HalfEdgeMesh::from_mesh(&mesh) {
        Err(Error::Topology { faces, msg }) => {
            assert_eq!(faces, vec![asperity::FaceId(2)]);
            assert!(msg.contains("#2"), "{msg}");
        }
        other => panic!("expected a topology error, got {other:?}"),
    }
}

#[test]
fn one_rings_are_ccw_and_boundary_rings_open() {
    let mesh = grid(2); // 3x3 vertices, centre vertex 4
    let he = HalfEdgeMesh::from_mesh(&mesh).unwrap();
    let rings = he.one_rings(&all_vertices(&mesh)).unwrap();
    assert_eq!(rings.len(), 9);
    let valences = he.valences(&all_vertices(&mesh)).unwrap();
    let boundary = he.boundary_flags(&all_vertices(&mesh)).unwrap();
    for v in 0..9 {
        let ring = rings.row(v);
        assert_eq!(ring.len() as u32, valences[v]);
        assert_eq!(boundary[v], v != 4);
        // Consecutive neighbours share a face, turning counter-clockwise (+z normal).
        let p = mesh.positions[v];
        let closed = !boundary[v];
        let pairs = if closed { ring.len() } else { ring.len() - 1 };
        for k in 0..pairs {
            let (a, b) = (ring[k], ring[(k + 1) % ring.len()]);
            let shares = mesh.triangles.iter().any(|t| t.contains(&(v as u32)) && t.contains(&a) && t.contains(&b));
            assert!(shares, "vertex {v}: {a} and {b} share no face");
            let turn = (mesh.positions[a as usize] - p).cross(mesh.positions[b as usize] - p);
            assert!(turn.z > 0.0, "vertex {v} ring is not counter-clockwise");
        }
    }
    // Corner 0 of the grid: faces (0,1,4) and (0,4,3): ring 1, 4, 3.
    assert_eq!(rings.row(0), &[1, 4, 3]);
}

#[test]
fn flips_splits_and_welds_keep_the_mesh_valid() {
    let mesh = icosphere(1.0, 2);
    let chi = mesh.validate().euler;
    let mut he = HalfEdgeMesh::from_mesh(&mesh).unwrap();

    // Flip an edge and flip it back: two flips, same edge count.
    let [a, b, _] = mesh.triangles[0];
    assert_eq!(he.flip_edges(&[[a, b], [0, 0]]).unwrap(), vec![OpStatus::Done, OpStatus::NotAnEdge]);

    // Split two edges at their midpoints.
    let t = mesh.triangles[10];
    let mid = |i: u32, j: u32| (mesh.positions[i as usize] + mesh.positions[j as usize]) / 2.0;
    let split = he.split_edges(&[[t[0], t[1]], [t[1], t[0]]], &[mid(t[0], t[1]), mid(t[1], t[0])]).unwrap();
    // The second pair no longer names an edge: the first split replaced it.
    assert_eq!(split[1], (OpStatus::NotAnEdge, None));
    assert_eq!(split[0].0, OpStatus::Done);
    let new_vertex = split[0].1.unwrap();
    assert_eq!(he.valences(&[new_vertex]).unwrap(), vec![4]);

    // The new vertex has degree 4: weld it back onto a neighbour.
    let ring = he.one_rings(&[new_vertex]).unwrap();
    let status = he.weld_degree_four(&[[new_vertex.0, ring.row(0)[0]]]).unwrap();
    assert_eq!(status, vec![OpStatus::Done]);
    // A degree-6 vertex is refused by a degree-4 weld.
    let ring0 = he.one_rings(&[VertexId(20)]).unwrap();
    let deg = he.valences(&[VertexId(20)]).unwrap()[0];
    let status = he.weld_degree_four(&[[20, ring0.row(0)[0]]]).unwrap();
    assert_eq!(status, vec![if deg == 4 { OpStatus::Done } else { OpStatus::WrongDegree }]);

    let remap = he.garbage_collect().unwrap();
    assert_eq!(remap[new_vertex.index()], ffi::INVALID_INDEX);
    let out = he.export().unwrap().mesh;
    let report = out.validate();
    assert_eq!(report.euler, chi);
    assert!(report.is_closed_manifold());
    assert_eq!(report.degenerate_faces, 0);
    assert_eq!(out.vertex_count(), mesh.vertex_count(), "one split, one weld");
}

#[test]
fn collapse_refuses_invalid_and_normal_flipping_collapses() {
    let mesh = torus(2.0, 0.5, 12, 8);
    let mut he = HalfEdgeMesh::from_mesh(&mesh).unwrap();
    let status = he
        .collapse_halfedges(&[[0, 5000], [0, 0]], CollapseOptions { required_degree: 0, check_normals: true })
        .unwrap();
    assert_eq!(status, vec![OpStatus::OutOfRange, OpStatus::NotAnEdge]);
    // Collapse many edges along one ring: topology is checked every time.
    let pairs: Vec<[u32; 2]> = (0..8).map(|j| [j, (j + 1) % 8]).collect();
    let status = he.collapse_halfedges(&pairs, CollapseOptions::default()).unwrap();
    assert!(status.contains(&OpStatus::Done));
    assert!(status.iter().any(|s| *s != OpStatus::Done), "collapsing a whole ring must be refused at some point");
    he.garbage_collect().unwrap();
    let report = he.export().unwrap().mesh.validate();
    assert_eq!(report.euler, 0);
    assert!(report.is_closed_manifold());
}

#[test]
fn hausdorff_to_itself_is_zero_and_to_a_translate_is_the_offset() {
    let mesh = icosphere(1.0, 3);
    let d0 = ffi::hausdorff_distance(&mesh, &mesh, HausdorffOptions::default()).unwrap();
    assert!(d0 < 1e-12, "self distance {d0}");
    let d = 0.05;
    let mut moved = mesh.clone();
    for p in &mut moved.positions {
        p.z += d;
    }
    let dh = ffi::hausdorff_distance(&mesh, &moved, HausdorffOptions::default()).unwrap();
    assert!((dh - d).abs() < 1e-3 * d, "hausdorff {dh} vs offset {d}");
    // Reproducible: same seed, same answer.
    assert_eq!(dh, ffi::hausdorff_distance(&mesh, &moved, HausdorffOptions::default()).unwrap());
}

#[test]
fn quadrics_vanish_on_the_surface_and_grow_off_it() {
    let mesh = cube(DVec3::ZERO, DVec3::ONE, 2);
    let q = ffi::vertex_quadrics(&mesh, 100.0).unwrap();
    assert_eq!(q.len(), mesh.vertex_count());
    let on = ffi::quadric_errors(&q, &mesh.positions).unwrap();
    assert!(on.iter().all(|e| e.abs() < 1e-12));
    // A cube corner's quadric sums the three face planes: moving by (d,d,d) outwards costs
    // (number of faces per plane) * d² per plane.
    let corner = mesh.positions.iter().position(|p| *p == DVec3::ONE).unwrap();
    let d = 0.1;
    let e = ffi::quadric_errors(&[q[corner]], &[DVec3::splat(1.0 + d)]).unwrap()[0];
    let faces_at_corner = mesh.triangles.iter().filter(|t| t.contains(&(corner as u32))).count() as f64;
    assert!((e - faces_at_corner * d * d).abs() < 1e-12, "error {e}");
    assert!(matches!(ffi::quadric_errors(&q[..2], &mesh.positions), Err(Error::InvalidInput(_))));
}

#[test]
fn self_intersections_are_found_between_crossing_faces_only() {
    let mesh = icosphere(1.0, 2);
    assert!(ffi::self_intersections(&mesh).unwrap().is_empty());
    // Two disjoint spheres overlapping in space.
    let mut a = icosphere(1.0, 1);
    let b = icosphere(1.0, 1);
    let offset = a.vertex_count() as u32;
    a.positions.extend(b.positions.iter().map(|p| *p + DVec3::new(1.0, 0.0, 0.0)));
    a.triangles.extend(b.triangles.iter().map(|t| t.map(|v| v + offset)));
    let pairs = ffi::self_intersections(&a).unwrap();
    assert!(!pairs.is_empty());
    let nf = b.triangles.len() as u32;
    assert!(pairs.iter().all(|[f, g]| f.0 < nf && g.0 >= nf && f < g));
}

/// `added_triangle_intersections` with the faces `f` where `is_added(f)` added and the rest
/// kept must report exactly the pairs of CGAL's `self_intersections` with an added member,
/// renumbered (kept faces first, then added ones, each in order).
fn assert_added_pairs_match(mesh: &Mesh, is_added: impl Fn(usize) -> bool) {
    let (mut kept, mut added, mut index) = (Vec::new(), Vec::new(), Vec::new());
    for (f, t) in mesh.triangles.iter().enumerate() {
        if is_added(f) {
            index.push((true, added.len()));
            added.push(*t);
        } else {
            index.push((false, kept.len()));
            kept.push(*t);
        }
    }
    let renumber = |f: u32| match index[f as usize] {
        (false, k) => k as u32,
        (true, a) => (kept.len() + a) as u32,
    };
    let mut expected: Vec<[u32; 2]> = ffi::self_intersections(mesh)
        .unwrap()
        .into_iter()
        .filter(|[f, g]| is_added(f.index()) || is_added(g.index()))
        .map(|[f, g]| {
            let (a, b) = (renumber(f.0), renumber(g.0));
            [a.min(b), a.max(b)]
        })
        .collect();
    expected.sort_unstable();
    assert_eq!(asperity::hierarchy::added_triangle_intersections(&mesh.positions, &kept, &added).unwrap(), expected);
}

#[test]
fn added_triangle_intersections_agree_with_cgal_self_intersections() {
    // Two spheres crossing: many pairs with no shared vertex.
    let mut spheres = icosphere(1.0, 2);
    let small = icosphere(0.7, 2);
    let offset = spheres.vertex_count() as u32;
    spheres.positions.extend(small.positions.iter().map(|p| *p + DVec3::new(0.9, 0.1, 0.05)));
    spheres.triangles.extend(small.triangles.iter().map(|t| t.map(|v| v + offset)));
    // A sphere with one vertex pushed through to the far side: its fan crosses faces it
    // shares a vertex with and faces it shares nothing with.
    let mut pierced = icosphere(1.0, 2);
    pierced.positions[0] = -pierced.positions[0] * 1.3;
    // A flat grid with an interior vertex moved across its neighbours in the plane:
    // coplanar overlaps across shared edges and around shared vertices.
    let mut folded = grid(4);
    let centre = folded.positions.iter().position(|p| (p.x - 0.5).abs() < 1e-9 && (p.y - 0.5).abs() < 1e-9);
    let centre = centre.expect("a grid vertex at the centre");
    folded.positions[centre] += DVec3::new(0.4, 0.3, 0.0);
    // A small sphere cut by one huge triangle: a query box far larger than the grid cells
    // (the huge triangle kept) and a grid sized by one huge box (the huge triangle added).
    let mut sliced = icosphere(0.5, 3);
    let first = sliced.vertex_count() as u32;
    sliced.positions.extend([
        DVec3::new(-50.0, -50.0, 0.01),
        DVec3::new(50.0, -50.0, 0.02),
        DVec3::new(0.0, 80.0, 0.0),
    ]);
    sliced.triangles.push([first, first + 1, first + 2]);
    let huge = sliced.face_count() - 1;
    assert_added_pairs_match(&sliced, |f| f != huge);
    assert_added_pairs_match(&sliced, |f| f == huge);
    for mesh in [&spheres, &pierced, &folded] {
        assert!(!ffi::self_intersections(mesh).unwrap().is_empty());
        assert_added_pairs_match(mesh, |f| f % 3 == 0);
        assert_added_pairs_match(mesh, |f| f % 2 == 1);
        assert_added_pairs_match(mesh, |_| true);
        assert!(asperity::hierarchy::added_triangle_intersections(&mesh.positions, &mesh.triangles, &[]).unwrap().is_empty());
    }
    // More kept faces than one call takes (the kept side is split across threads).
    let mut large = icosphere(1.0, 6);
    let offset = large.vertex_count() as u32;
    large.positions.extend(small.positions.iter().map(|p| *p * 0.5 + DVec3::new(0.95, 0.0, 0.0)));
    large.triangles.extend(small.triangles.iter().map(|t| t.map(|v| v + offset)));
    let first_small = large.face_count() - small.face_count();
    assert_added_pairs_match(&large, |f| f >= first_small);
    // Bad indices and coordinates are errors, not aborts.
    assert!(matches!(
        asperity::hierarchy::added_triangle_intersections(&[DVec3::ZERO], &[], &[[0, 0, 7]]),
        Err(Error::InvalidInput(_))
    ));
    let nan = [DVec3::ZERO, DVec3::X, DVec3::NAN];
    assert!(matches!(asperity::hierarchy::added_triangle_intersections(&nan, &[[0, 1, 2]], &[]), Err(Error::InvalidInput(_))));
}

#[test]
fn native_errors_are_results_not_aborts() {
    // A face CGAL refuses (repeated vertex) surfaces as an error.
    let mesh = Mesh::new(vec![DVec3::ZERO, DVec3::X, DVec3::Y], vec![[0, 1, 1]]);
    assert!(matches!(ffi::vertex_quadrics(&mesh, 100.0), Err(Error::Native(_))));
    let empty = Mesh::new(vec![DVec3::ZERO], vec![]);
    assert!(matches!(ffi::hausdorff_distance(&empty, &empty, HausdorffOptions::default()), Err(Error::Native(_))));
    // Out-of-range queries are errors from the C++ side too.
    let he = HalfEdgeMesh::from_mesh(&grid(1)).unwrap();
    assert!(matches!(he.valences(&[VertexId(99)]), Err(Error::Native(_))));
}

#[test]
fn the_plane_side_filter_never_separates_what_cgal_finds_intersecting() {
    // Small integer coordinates make exactly coplanar, touching and piercing pairs common.
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut next = move |n: i64| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state % n as u64) as i64
    };
    let mut point = || DVec3::new((next(5) - 2) as f64, (next(5) - 2) as f64, (next(5) - 2) as f64);
    let (mut intersecting, mut certified) = (0, 0);
    for case in 0..3000 {
        let positions: Vec<DVec3> = (0..6).map(|_| point()).collect();
        let s = [0u32, 1, 2];
        let t = match case % 3 {
            0 => [3, 4, 5],
            1 => [0, 4, 5],
            _ => [1, 0, 5],
        };
        let area = |t: [u32; 3]| {
            let [a, b, c] = t.map(|v| positions[v as usize]);
            (b - a).cross(c - a)
        };
        if area(s) == DVec3::ZERO || area(t) == DVec3::ZERO {
            continue;
        }
        let mesh = Mesh::new(positions.clone(), vec![s, t]);
        let cgal = !ffi::self_intersections(&mesh).unwrap().is_empty();
        let ours = !asperity::hierarchy::added_triangle_intersections(&positions, &[s], &[t]).unwrap().is_empty();
        assert_eq!(ours, cgal, "case {case}: {s:?} {t:?} over {positions:?}");
        let apart = asperity::mesh::certainly_apart(&positions, s, t);
        assert!(!(apart && cgal), "case {case}: the filter separated an intersecting pair");
        intersecting += usize::from(cgal);
        certified += usize::from(apart);
    }
    // The cases must exercise both sides.
    assert!(intersecting > 100 && certified > 500, "{intersecting} intersecting, {certified} certified apart");
}
