//! Partitioned builds (#40): parts along the Morton curve, fenced borders, and the parts'
//! bases joined into a manifold that a build continues to the target.

use asperity::hierarchy::partition::{Partition, build_partitioned};
use asperity::hierarchy::{KeepFeatures, LevelMesh, Refiner, SimplifyOptions, build, connectivity_match, face_key};
use asperity::mesh::primitives::{grid, icosphere, torus};
use asperity::mesh::{Mesh, ValidationReport};
use asperity::noise::{Frame, NoiseField, NoiseKind, NoiseSpec};
use glam::DVec3;

use crate::common::shared_meshes;

fn shared(name: &str) -> Mesh {
    asperity::io::read(&shared_meshes().join(name)).expect("shared mesh reads").mesh
}

fn to(target: usize, border: Vec<u32>) -> SimplifyOptions {
    SimplifyOptions {
        target_vertices: Some(target),
        keep_features: KeepFeatures::None,
        border_vertices: border,
        ..Default::default()
    }
}

#[test]
fn parts_cover_every_face_once_in_equal_runs_and_name_their_border() {
    let mesh = torus(1.0, 0.35, 120, 48);
    let partition = Partition::of(&mesh, 7).unwrap();
    let mut counts = [0usize; 7];
    for f in 0..mesh.face_count() {
        counts[partition.owner(f) as usize] += 1;
    }
    let (lo, hi) = (counts.iter().min().unwrap(), counts.iter().max().unwrap());
    assert!(hi - lo <= 1, "part sizes {counts:?}");
    // A border vertex is one on faces of two parts or more, found here by brute force.
    let mut parts_of = vec![std::collections::BTreeSet::new(); mesh.vertex_count()];
    for (f, t) in mesh.triangles.iter().enumerate() {
        for &v in t {
            parts_of[v as usize].insert(partition.owner(f));
        }
    }
    for (v, parts) in parts_of.iter().enumerate() {
        assert_eq!(partition.is_border(v as u32), parts.len() > 1, "vertex {v} on parts {parts:?}");
    }
    // Compact runs: a small share of the vertices on a border (a run of the curve is a
    // block of the torus, not a scatter of faces: faces dealt out in turn put every vertex
    // on one).
    let share = partition.border_count() as f64 / mesh.vertex_count() as f64;
    assert!(share < 0.2, "{:.1} % of the vertices on a border", 100.0 * share);
    // Each part as a mesh of its own: its faces, in input ids, are the faces it owns.
    let mut seen = 0;
    for k in 0..7 {
        let part = partition.part(&mesh, k).unwrap();
        let faces = part.input_triangles(&part.mesh.triangles);
        let owned: Vec<[u32; 3]> =
            (0..mesh.face_count()).filter(|&f| partition.owner(f) as usize == k).map(|f| mesh.triangles[f]).collect();
        assert_eq!(faces, owned, "part {k}");
        assert!(part.border.iter().all(|&v| partition.is_border(part.ids[v as usize])));
        assert!(ValidationReport::of(&part.mesh).is_manifold(), "part {k} is split where it pinches");
        seen += faces.len();
    }
    assert_eq!(seen, mesh.face_count());
    assert_eq!(Partition::of(&mesh, 7).unwrap().border_count(), partition.border_count(), "deterministic");
    for bad in [0, mesh.face_count() + 1] {
        let e = Partition::of(&mesh, bad).unwrap_err().to_string();
        assert!(e.contains("parts of a mesh of"), "{e}");
    }
    assert!(partition.part(&mesh, 7).is_err());
}

#[test]
fn a_part_pinched_at_a_vertex_is_split_into_one_copy_per_fan() {
    // A 2 x 2 grid's two triangles that meet at the centre only (opposite corners of the
    // fan around it) in part 0: its mesh has a copy of the centre per fan, both naming
    // the centre, and both on the border.
    let mesh = grid(2);
    let centre = mesh.positions.iter().position(|p| (p.x - 0.5).abs() < 1e-12 && (p.y - 0.5).abs() < 1e-12).unwrap();
    let around: Vec<usize> = (0..mesh.face_count()).filter(|&f| mesh.triangles[f].contains(&(centre as u32))).collect();
    let shares_edge =
        |f: usize, g: usize| mesh.triangles[f].iter().filter(|v| mesh.triangles[g].contains(v)).count() > 1;
    let b = around[1..].iter().copied().find(|&g| !shares_edge(around[0], g)).expect("a face opposite the first");
    let a = around[0];
    let owner: Vec<u32> = (0..mesh.face_count()).map(|f| u32::from(f != a && f != b)).collect();
    let partition = Partition::with_owners(&mesh, owner, 2).unwrap();
    let part = partition.part(&mesh, 0).unwrap();
    assert_eq!(part.mesh.face_count(), 2);
    assert!(ValidationReport::of(&part.mesh).is_manifold());
    assert_eq!(part.ids.iter().filter(|&&v| v as usize == centre).count(), 2, "ids {:?}", part.ids);
    assert_eq!(part.mesh.vertex_count(), 6);
    assert_eq!(part.input_triangles(&part.mesh.triangles), vec![mesh.triangles[a], mesh.triangles[b]]);
    let centre_copies: Vec<u32> = (0..6).filter(|&v| part.ids[v as usize] as usize == centre).collect();
    assert!(centre_copies.iter().all(|v| part.border.contains(v)), "border {:?}", part.border);
    assert!(Partition::with_owners(&mesh, vec![0; 3], 2).is_err());
    assert!(Partition::with_owners(&mesh, vec![2; mesh.face_count()], 2).is_err());
}

/// Each part's own share of its vertices' quadrics, in input ids: the input's quadrics
/// over the part's faces in the input's frame, its border vertices' taken from the part.
fn own_shares(part: &asperity::hierarchy::partition::Part) -> Vec<(u32, asperity::analysis::Quadric)> {
    let in_frame = part.input_frame.apply(&part.mesh);
    let mut quadrics = asperity::ffi::vertex_quadrics(&in_frame, asperity::hierarchy::BOUNDARY_WEIGHT).unwrap();
    for (&b, &own) in part.border.iter().zip(&part.border_quadrics) {
        quadrics[b as usize] = own;
    }
    part.ids.iter().copied().zip(quadrics).collect()
}

#[test]
fn the_parts_shares_of_the_quadrics_sum_to_the_input_s() {
    // What the continuation of a partitioned build starts from: every vertex's quadric
    // (faces' planes, and boundary planes where the input has a boundary) split between
    // the parts. A part alone would see a boundary plane on every cut edge, and a border
    // vertex's star cut in two.
    use asperity::mesh::UnitFrame;
    let pinched = {
        let mesh = grid(2);
        let owner: Vec<u32> = (0..mesh.face_count() as u32).map(|f| u32::from(f % 3 == 0)).collect();
        (mesh, Some(owner))
    };
    for (name, (mesh, owner)) in
        [("open grid", (grid(12), None)), ("torus", (torus(1.0, 0.35, 40, 18), None)), ("pinched", pinched)]
    {
        let partition = match owner {
            Some(owner) => Partition::with_owners(&mesh, owner, 2).unwrap(),
            None => Partition::of(&mesh, 4).unwrap(),
        };
        let input = asperity::ffi::vertex_quadrics(&UnitFrame::of(&mesh).unwrap().apply(&mesh), 100.0).unwrap();
        let mut summed = vec![asperity::analysis::Quadric::default(); mesh.vertex_count()];
        for k in 0..partition.parts() {
            for (v, q) in own_shares(&partition.part(&mesh, k).unwrap()) {
                summed[v as usize].add_scaled(&q, 1.0);
            }
        }
        for (v, (a, b)) in input.iter().zip(&summed).enumerate() {
            let scale = a.0.iter().fold(1.0f64, |m, x| m.max(x.abs()));
            let apart = a.0.iter().zip(b.0).fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
            assert!(apart <= 1e-12 * scale, "{name}: vertex {v}: {:?} against the input's {:?}", b.0, a.0);
        }
        assert!(partition.border_count() > 0, "{name} has a border");
    }
}

#[test]
fn fenced_parts_join_into_a_manifold_that_a_build_continues_to_the_target() {
    // The bunny scan (genus 0), a torus (genus 1) and a displaced sphere in 8 parts, each
    // simplified to a 25th of its inside with its border fenced: the joined bases are a
    // manifold of the input's genus, and a build of them reaches 1 % of the input. (With
    // the borders only kept, not fenced, the sphere's joined bases have 8 edges of four
    // faces: two parts joined the same two border vertices.)
    let sphere = {
        let mut mesh = icosphere(1.0, 6);
        let spec = NoiseSpec { kind: NoiseKind::Fbm, seed: 7, ..NoiseSpec::default() };
        let field = NoiseField::new(&spec).unwrap();
        let frame = Frame { tangent: DVec3::X, bitangent: DVec3::Y };
        for p in &mut mesh.positions {
            let n = p.normalize();
            *p = n * (1.0 + 0.08 * field.sample3(n * 4.0, frame));
        }
        mesh
    };
    for (name, mesh) in
        [("bunny00", shared("bunny00.off")), ("torus", torus(1.0, 0.35, 120, 48)), ("displaced sphere", sphere)]
    {
        let input = ValidationReport::of(&mesh);
        let partition = Partition::of(&mesh, 8).unwrap();
        let bases: Vec<Vec<[u32; 3]>> = (0..8)
            .map(|k| {
                let part = partition.part(&mesh, k).unwrap();
                let inside = part.mesh.vertex_count() - part.border.len();
                let target = part.border.len() + inside / 25;
                let h = build(&part.mesh, &to(target, part.border.clone())).unwrap();
                // The border is kept: every border vertex is in the part's base.
                let base: std::collections::HashSet<u32> = h.base_triangles.iter().flatten().copied().collect();
                assert!(part.border.iter().all(|v| base.contains(v)), "{name} part {k}: a border vertex was removed");
                part.input_triangles(&h.base_triangles)
            })
            .collect();
        let joined = LevelMesh::compact(&mesh.positions, &bases.concat());
        let report = ValidationReport::of(&joined.mesh);
        assert!(report.is_manifold() && report.inconsistently_oriented_edges == 0, "{name}: joined bases {report:?}");
        assert_eq!(report.genus, input.genus, "{name}: genus");
        assert_eq!(report.boundary_loops, input.boundary_loops, "{name}: boundary loops");
        assert!(
            joined.mesh.vertex_count() < mesh.vertex_count() / 4,
            "{name}: {} vertices",
            joined.mesh.vertex_count()
        );
        let target = mesh.vertex_count() / 100;
        let h = build(&joined.mesh, &to(target, Vec::new())).unwrap();
        assert_eq!(h.base_vertex_count(), target, "{name}");
    }
}

#[test]
fn a_partitioned_build_is_one_hierarchy_whose_refinement_restores_the_input() {
    // The parts' levels, then the continuation's: one hierarchy of the input, reaching the
    // target, every removed vertex parametrized on the base domain, and refinement back to
    // the input's every face at its own positions.
    for (name, mesh, parts) in [("bunny00", shared("bunny00.off"), 6), ("torus", torus(1.0, 0.35, 96, 40), 5)] {
        let target = mesh.vertex_count() / 100;
        let h = build_partitioned(&mesh, parts, &to(target, Vec::new())).unwrap();
        assert_eq!(h.base_vertex_count(), target, "{name}");
        assert!(h.target.reached, "{name}");
        assert!(h.step_starts.windows(2).all(|w| w[0] <= w[1]) && *h.step_starts.last().unwrap() == h.removals.len());
        let removed = h.removals.len();
        assert_eq!(removed, mesh.vertex_count() - target, "{name}: every vertex but the base's removed once");
        let points = h.base_parametrization();
        assert!(points.iter().all(Option::is_some), "{name}: a vertex without a base point");
        // Every removed vertex's point lies on a face of the base domain, close to it.
        let base: std::collections::HashSet<[u32; 3]> = h.base_triangles.iter().map(|&t| face_key(t)).collect();
        for (v, point) in h.params.iter().enumerate() {
            if let Some(p) = point {
                assert!(base.contains(&face_key(p.face)), "{name}: vertex {v} on {:?}, no base face", p.face);
            }
        }
        let mut refiner = Refiner::new(&h).unwrap();
        refiner.refine_all().unwrap();
        let out = refiner.mesh().unwrap();
        assert_eq!(out.ids, (0..mesh.vertex_count() as u32).collect::<Vec<_>>(), "{name}");
        assert_eq!(out.mesh.positions, mesh.positions, "{name}");
        assert_eq!(connectivity_match(&mesh.triangles, &out.triangles_in_ids()), 1.0, "{name}: round trip");
    }
    // Feature classes come from the input, not from the joined bases' coarser faces (which
    // made 57 feature vertices of the bunny at 1 %, where a one-piece build finds none).
    let bunny = shared("bunny00.off");
    let strong = SimplifyOptions { target_vertices: Some(377), ..Default::default() };
    let parted = build_partitioned(&bunny, 8, &strong).unwrap();
    assert_eq!(parted.feature_vertices, build(&bunny, &strong).unwrap().feature_vertices);
    // What this first version refuses, by name, and a faulty input as a one-piece build
    // names it.
    let mut stray = torus(1.0, 0.35, 48, 24);
    stray.positions.push(DVec3::ZERO);
    let e = build_partitioned(&stray, 4, &to(100, Vec::new())).unwrap_err().to_string();
    assert!(e.contains("belong to no face, first vertex 1152"), "{e}");
    let mesh = torus(1.0, 0.35, 48, 24);
    let e = build_partitioned(&mesh, 4, &SimplifyOptions { levels: Some(3), ..Default::default() }).unwrap_err();
    assert!(e.to_string().contains("needs a vertex target or an error bound"), "{e}");
    let e = build_partitioned(&mesh, 4, &SimplifyOptions { levels: Some(3), ..to(100, Vec::new()) }).unwrap_err();
    assert!(e.to_string().contains("no level limit"), "{e}");
}

#[test]
fn a_part_and_its_build_read_back_from_their_files_bit_for_bit() {
    // Parts built in other processes (#40): a part's file reads back as the part, a
    // build's as the build, and the builds joined from files are the threaded build's.
    use asperity::hierarchy::partition::files::{read_build, read_part, write_build, write_part};
    use asperity::hierarchy::partition::{build_part, join_parts};
    let tmp = crate::common::temp_dir();
    let mesh = torus(1.0, 0.35, 72, 30);
    let options = to(60, Vec::new());
    let partition = Partition::of(&mesh, 3).unwrap();
    let mut builds = Vec::new();
    for k in 0..3 {
        let part = partition.part(&mesh, k).unwrap();
        let (part_file, build_file) = (tmp.path().join(format!("{k}.part")), tmp.path().join(format!("{k}.built")));
        write_part(&part, &part_file).unwrap();
        let read = read_part(&part_file, mesh.vertex_count()).unwrap();
        assert_eq!(
            (
                &read.mesh.positions,
                &read.mesh.triangles,
                &read.ids,
                &read.border,
                read.input_frame,
                &read.border_quadrics
            ),
            (
                &part.mesh.positions,
                &part.mesh.triangles,
                &part.ids,
                &part.border,
                part.input_frame,
                &part.border_quadrics
            )
        );
        let built = build_part(&read, &options, mesh.vertex_count()).unwrap();
        write_build(&built, &build_file).unwrap();
        assert_eq!(read_build(&build_file, mesh.vertex_count()).unwrap(), built, "part {k}");
        builds.push(built);
    }
    // An input given to keep (its positions and faces become the hierarchy's) and one lent
    // (copied) join alike.
    let join = |input: std::borrow::Cow<'_, Mesh>, builds| {
        join_parts(input, builds, |k| partition.part(&mesh, k), &options, std::time::Instant::now()).unwrap()
    };
    let owned = join(std::borrow::Cow::Owned(mesh.clone()), builds.clone());
    let joined = join(std::borrow::Cow::Borrowed(&mesh), builds);
    let threaded = build_partitioned(&mesh, 3, &options).unwrap();
    for other in [&owned, &threaded] {
        assert_eq!(joined.base_triangles, other.base_triangles);
        assert_eq!(joined.removals, other.removals);
        assert_eq!(joined.params, other.params);
        assert_eq!((&joined.positions, &joined.input_triangles), (&other.positions, &other.input_triangles));
        assert_eq!((&joined.restore, &joined.step_starts, &joined.kept), (&other.restore, &other.step_starts, &other.kept));
    }
}

#[test]
fn a_broken_part_file_is_refused_by_name_and_byte() {
    use asperity::hierarchy::partition::build_part;
    use asperity::hierarchy::partition::files::{read_build, read_part, write_build, write_part};
    let tmp = crate::common::temp_dir();
    let mesh = torus(1.0, 0.35, 48, 24);
    let part = Partition::of(&mesh, 2).unwrap().part(&mesh, 1).unwrap();
    let (part_file, build_file) = (tmp.path().join("p.part"), tmp.path().join("p.built"));
    write_part(&part, &part_file).unwrap();
    write_build(&build_part(&part, &to(50, Vec::new()), mesh.vertex_count()).unwrap(), &build_file).unwrap();
    let good = std::fs::read(&build_file).unwrap();
    let broken = tmp.path().join("broken.built");
    let refused = |bytes: &[u8], phrase: &str| {
        std::fs::write(&broken, bytes).unwrap();
        let e = read_build(&broken, mesh.vertex_count()).unwrap_err();
        assert_eq!(e.exit_code(), 2);
        let text = e.to_string();
        assert!(text.contains("broken.built: byte ") && text.contains(phrase), "{text}");
    };
    refused(&good[..good.len() / 2], "hash does not match");
    let mut flipped = good.clone();
    flipped[40] ^= 1;
    refused(&flipped, "hash does not match");
    refused(b"", "not a part's build");
    refused(&std::fs::read(&part_file).unwrap(), "not a part's build");
    // A file whose hash matches but whose ids do not fit the input: refused, not a panic.
    assert!(read_build(&build_file, 10).unwrap_err().to_string().contains("out of range"));
    assert!(read_part(&part_file, 10).unwrap_err().to_string().contains("out of range"));
    // Counts larger than the file are refused before anything is allocated.
    let mut huge = b"asperity-built2\n".to_vec();
    huge.extend(u64::MAX.to_le_bytes());
    let hash = asperity::io::manifest::fnv1a(asperity::io::manifest::FNV_OFFSET, &huge);
    huge.extend(hash.to_le_bytes());
    refused(&huge, "elements of 12 bytes");
}

#[test]
fn levels_made_by_refinement_are_the_levels_a_build_records() {
    // A partitioned build records no levels (#40); refinement makes them. Checked against
    // a one-piece build's recorded levels, then on a partitioned hierarchy: from the input
    // down to the base, each a closed manifold, each coarser than the one before.
    let mesh = torus(1.0, 0.35, 60, 24);
    let recorded = build(&mesh, &SimplifyOptions { record_levels: true, ..to(80, Vec::new()) }).unwrap();
    let refined = recorded.levels_by_refinement().unwrap();
    assert_eq!(refined.len(), recorded.levels.len());
    for (k, (a, b)) in recorded.levels.iter().zip(&refined).enumerate() {
        assert_eq!(a.ids, b.ids, "level {k}: vertices");
        assert_eq!(a.mesh.positions, b.mesh.positions, "level {k}");
        assert_eq!(a.mesh.face_count(), b.mesh.face_count(), "level {k}");
        assert_eq!(connectivity_match(&a.triangles_in_ids(), &b.triangles_in_ids()), 1.0, "level {k}: faces");
    }
    let parted = build_partitioned(&shared("bunny00.off"), 4, &to(377, Vec::new())).unwrap();
    let levels = parted.levels_by_refinement().unwrap();
    assert_eq!(levels.len(), parted.steps() + 1);
    assert_eq!(levels[0].mesh.face_count(), parted.input_triangles.len());
    assert_eq!(connectivity_match(&parted.input_triangles, &levels[0].triangles_in_ids()), 1.0);
    assert_eq!(levels.last().unwrap().mesh.vertex_count(), 377);
    for (k, pair) in levels.windows(2).enumerate() {
        assert!(pair[1].mesh.vertex_count() < pair[0].mesh.vertex_count(), "level {k} to the next");
        let report = ValidationReport::of(&pair[1].mesh);
        assert!(report.is_manifold() && report.boundary_loops == 0 && report.genus == Some(0), "{report:?}");
    }
}

#[test]
fn parts_that_would_cut_each_other_are_built_again_beside_each_other() {
    // A thin, bumpy pancake (an icosphere of level 5 squashed to 0.001 of its height, both
    // sheets bent alike) in two parts: its two sheets lie in different parts (the Morton
    // curve's first cut is by height), so each part's guard sees only its own sheet, and
    // built apart the sheets cut each other (at 16 face pairs). The partitioned build
    // finds that in the joined bases and builds the parts again one after the other
    // beside each other.
    use asperity::hierarchy::partition::{PartBuild, build_part, separate_parts};
    let mut mesh = icosphere(1.0, 5);
    for p in &mut mesh.positions {
        p.z = p.z * 0.001 + 0.003 * (31.0 * p.x).sin() * (11.0 * p.y).cos();
    }
    assert!(asperity::ffi::self_intersections(&mesh).unwrap().is_empty(), "the input cuts itself");
    let options = to(20, Vec::new());
    let partition = Partition::of(&mesh, 2).unwrap();
    let mut builds: Vec<PartBuild> = (0..2)
        .map(|k| build_part(&partition.part(&mesh, k).unwrap(), &options, mesh.vertex_count()).unwrap())
        .collect();
    let crossings = |builds: &[PartBuild]| {
        let faces: Vec<[u32; 3]> = builds.iter().flat_map(|b| b.base_triangles.iter().copied()).collect();
        asperity::ffi::self_intersections(&LevelMesh::compact(&mesh.positions, &faces).mesh).unwrap().len()
    };
    let apart = crossings(&builds);
    assert!(apart > 0, "the sheets built apart did not cut each other: the case tests nothing");
    let rebuilt = separate_parts(&mesh, &mut builds, |k| partition.part(&mesh, k), &options).unwrap();
    assert_eq!(&rebuilt[..2], &[0, 1]);
    assert_eq!(crossings(&builds), 0, "rebuilt beside each other, the sheets still cut each other ({apart} before)");
    // The whole build: no level cuts itself (its parts' levels side by side, then the
    // continuation's).
    let h = build_partitioned(&mesh, 2, &options).unwrap();
    assert!(h.target.reached, "{:?}", h.target);
    for (k, level) in h.levels_by_refinement().unwrap().iter().enumerate() {
        assert_eq!(asperity::ffi::self_intersections(&level.mesh).unwrap().len(), 0, "level {k} from the input");
    }
}

#[test]
fn copies_of_a_pinched_border_vertex_never_share_a_neighbour() {
    // Where a part pinches at a vertex (its faces meet there only at the vertex), the part
    // holds one copy per fan; the copies are one vertex of the joined mesh, so a part may
    // not give a vertex an edge to one copy when it has an edge to another (the joined
    // bases would hold that edge twice: a Menger sponge in 4 parts had 17 edges of four
    // faces, refused by the continuation's validation).
    let mesh = crate::common::menger_sponge(1.0);
    for parts in [3, 4, 6] {
        let h = build_partitioned(&mesh, parts, &to(mesh.vertex_count() / 20, Vec::new()))
            .unwrap_or_else(|e| panic!("{parts} parts: {e}"));
        let base = LevelMesh::compact(&mesh.positions, &h.base_triangles);
        let report = ValidationReport::of(&base.mesh);
        assert!(report.is_manifold(), "{parts} parts: {report:?}");
    }
}

#[test]
fn a_recipe_table_s_chunks_is_read_and_checked_like_the_flag() {
    use asperity::hierarchy::{HierarchyRequest, VertexTarget};
    use asperity::request::Spelling;
    let table = HierarchyRequest {
        chunks: Some(3),
        target_vertices: Some(VertexTarget::parse("5%").unwrap()),
        ..Default::default()
    };
    let options = HierarchyRequest::default().options_over(&table, 1000, false, Spelling::Flag).unwrap();
    assert_eq!(options.chunks, Some(3));
    let with_levels = HierarchyRequest { levels: Some(4), ..table.clone() };
    let e =
        HierarchyRequest::default().options_over(&with_levels, 1000, false, Spelling::Flag).unwrap_err().to_string();
    assert!(e.contains("[hierarchy] chunks = 3 takes no level limit yet ([hierarchy] levels = 4)"), "{e}");
    // The front end's own setting replaces the table's.
    let own = HierarchyRequest { chunks: Some(2), ..Default::default() };
    assert_eq!(own.options_over(&table, 1000, false, Spelling::Flag).unwrap().chunks, Some(2));
    let zero = HierarchyRequest { chunks: Some(0), ..Default::default() };
    let e = zero.options_over(&table, 1000, false, Spelling::Flag).unwrap_err().to_string();
    assert!(e.contains("--chunks 0: give 1 part or more"), "{e}");
}

#[test]
fn a_build_that_does_not_give_way_stops_where_it_is_stuck() {
    // A part's goal is a staging point (#40): without the give-way ladder a build stuck
    // short of its target keeps its feature vertices and angle floor and stops there.
    let fandisk = shared("fandisk.off");
    let options = SimplifyOptions { target_vertices: Some(20), ..Default::default() };
    let giving = build(&fandisk, &options).unwrap();
    let stuck = build(&fandisk, &SimplifyOptions { give_way: false, ..options }).unwrap();
    assert!(giving.target.reached, "{:?}", giving.target);
    assert!(!stuck.target.reached && stuck.base_vertex_count() > 20, "{:?}", stuck.target);
    assert!(stuck.feature_vertices > giving.feature_vertices);
    assert_eq!(stuck.target.min_angle_floor_deg, 5.0, "{:?}", stuck.target);
}

#[test]
fn a_partitioned_build_stops_at_an_error_bound_as_a_one_piece_build_does() {
    // #40: an error bound instead of a vertex target. It is a fraction of the input's
    // diagonal in every part (scaled from the part's own, smaller box) and in the
    // continuation, so the parts in turn remove what the bound allows and the joined
    // build stops where a one-piece build stops.
    let bunny = shared("bunny00.off");
    let bound = 0.004;
    let options = SimplifyOptions { max_error: Some(bound), keep_features: KeepFeatures::None, ..Default::default() };
    let hausdorff = |h: &asperity::hierarchy::Hierarchy| {
        let base = Mesh::new(h.positions.clone(), h.base_triangles.clone());
        asperity::hierarchy::compare::relative_hausdorff(&bunny, &base).unwrap()
    };
    let whole = build(&bunny, &options).unwrap();
    let parted = build_partitioned(&bunny, 4, &options).unwrap();
    let (whole_vertices, parted_vertices) = (whole.base_vertex_count(), parted.base_vertex_count());
    let (whole_distance, parted_distance) = (hausdorff(&whole), hausdorff(&parted));
    println!(
        "error bound {bound}: one piece {whole_vertices} vertices at {whole_distance:.5}, 4 parts {parted_vertices} at {parted_distance:.5}"
    );
    assert!(parted_distance <= 1.1 * whole_distance.max(bound), "{parted_distance} against {whole_distance}");
    let ratio = parted_vertices as f64 / whole_vertices as f64;
    assert!((0.8..=1.25).contains(&ratio), "{parted_vertices} vertices against {whole_vertices}");
    // The parts alone already remove what the bound allows inside them: the joined bases
    // hold far fewer vertices than the input.
    let partition = Partition::of(&bunny, 4).unwrap();
    let inside: usize = (0..4)
        .map(|k| {
            let part = partition.part(&bunny, k).unwrap();
            let built = asperity::hierarchy::partition::build_part(&part, &options, bunny.vertex_count()).unwrap();
            built.removals.len()
        })
        .sum();
    assert!(inside as f64 >= 0.5 * (bunny.vertex_count() - whole_vertices) as f64, "the parts removed {inside}");
}

/// A plan checks the mesh part by part, with no table of the whole mesh's edges: the
/// counts it refuses with are the whole mesh's, whatever the cut.
#[test]
fn a_partition_refuses_what_a_build_refuses_with_the_whole_mesh_s_counts() {
    let sheet = grid(24);
    let at = |x: f64, y: f64| sheet.positions.iter().position(|p| p.x == x && p.y == y).unwrap() as u32;
    let (lo, hi) = sheet.bounding_box().unwrap();
    // A face turned over: three edges its neighbours traverse as it does.
    let mut flipped = sheet.clone();
    let f = flipped.face_count() / 2 + 7;
    flipped.triangles[f].swap(1, 2);
    // Fins: a third face on two edges.
    let mut fins = sheet.clone();
    fins.positions.push(DVec3::new(0.0, 0.0, 1.0));
    let apex = sheet.vertex_count() as u32;
    for f in [fins.face_count() / 3, fins.face_count() / 2 + 11] {
        let [a, b, _] = fins.triangles[f];
        fins.triangles.push([a, b, apex]);
    }
    // Copies of the sheet whose first corner is the sheet's far corner or a vertex inside
    // it: vertices whose faces make two fans.
    let mut bowtie = sheet.clone();
    let (middle, far, first) = (at(0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y)), at(hi.x, hi.y), at(lo.x, lo.y));
    for (joined, offset) in [(far, hi - lo), (middle, DVec3::new(0.5, 0.5, 0.5) * (hi - lo).length())] {
        let start = bowtie.vertex_count() as u32;
        bowtie.positions.extend(sheet.positions.iter().map(|&p| p + DVec3::new(offset.x, offset.y, offset.z)));
        bowtie.triangles.extend(sheet.triangles.iter().map(|t| t.map(|v| if v == first { joined } else { v + start })));
    }
    for (name, mesh) in [("flipped", &flipped), ("fins", &fins), ("bowtie", &bowtie)] {
        let report = ValidationReport::of(mesh);
        assert!(!report.is_manifold() || report.inconsistently_oriented_edges > 0, "{name} is a bad mesh");
        let counts = format!(
            "({} non-manifold edges, {} non-manifold vertices, {} inconsistently oriented edges)",
            report.non_manifold_edges, report.non_manifold_vertices, report.inconsistently_oriented_edges
        );
        for parts in [1, 2, 3, 5, 8] {
            let e = Partition::of(mesh, parts).unwrap_err().to_string();
            assert!(e.contains(&counts), "{name} in {parts} parts: {e}, not {counts}");
        }
    }
}
