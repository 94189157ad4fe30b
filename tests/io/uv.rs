//! #22 B: texture coordinates and materials read, written and carried through the
//! hierarchy (seams simplified along themselves, so no level tears the texture).

use std::f64::consts::{PI, TAU};

use asperity::io;
use asperity::mesh::Mesh;
use asperity::mesh::uv::{CornerUvs, Materials, seam_edges};
use glam::DVec3;

use crate::common::{read_text, temp_dir};

/// A latitude–longitude unit sphere, `columns` × `rows` cells, UV (longitude / 2π,
/// latitude) with one seam along the meridian of longitude 0 (u = 0 on one side, 1 on the
/// other); two materials, north and south.
pub fn uv_sphere(columns: u32, rows: u32) -> Mesh {
    let mut positions = vec![DVec3::Z, -DVec3::Z];
    let ring = |r: u32, c: u32| 2 + (r - 1) * columns + c % columns;
    for r in 1..rows {
        let theta = PI * f64::from(r) / f64::from(rows);
        for c in 0..columns {
            let phi = TAU * f64::from(c) / f64::from(columns);
            positions.push(DVec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos()));
        }
    }
    // UV values: one per (ring, column 0..=columns) so that column `columns` is the seam's
    // other side, and one per pole.
    let mut values = vec![[0.5, 1.0], [0.5, 0.0]];
    let uv = |r: u32, c: u32| 2 + (r - 1) * (columns + 1) + c;
    for r in 1..rows {
        for c in 0..=columns {
            values.push([f64::from(c) / f64::from(columns), 1.0 - f64::from(r) / f64::from(rows)]);
        }
    }
    let (mut triangles, mut corners, mut material) = (Vec::new(), Vec::new(), Vec::new());
    let mut face = |t: [u32; 3], c: [u32; 3], row: u32| {
        triangles.push(t);
        corners.push(c);
        material.push(u32::from(2 * row >= rows));
    };
    for c in 0..columns {
        face([0, ring(1, c), ring(1, c + 1)], [0, uv(1, c), uv(1, c + 1)], 0);
        face([1, ring(rows - 1, c + 1), ring(rows - 1, c)], [1, uv(rows - 1, c + 1), uv(rows - 1, c)], rows - 1);
        for r in 1..rows - 1 {
            let (a, b, cc, d) = (ring(r, c), ring(r + 1, c), ring(r + 1, c + 1), ring(r, c + 1));
            let (ua, ub, uc, ud) = (uv(r, c), uv(r + 1, c), uv(r + 1, c + 1), uv(r, c + 1));
            face([a, b, cc], [ua, ub, uc], r);
            face([a, cc, d], [ua, uc, ud], r);
        }
    }
    let mut mesh = Mesh::new(positions, triangles);
    mesh.uvs = Some(CornerUvs { values, corners });
    mesh.materials = Some(Materials {
        libraries: vec!["sphere materials.mtl".into()],
        names: vec!["north".into(), "south".into()],
        faces: material,
    });
    mesh.check().unwrap();
    mesh
}

/// The UV of each (vertex, face) corner.
fn corner_uvs(mesh: &Mesh) -> Vec<([u64; 3], [u64; 2])> {
    let uvs = mesh.uvs.as_ref().expect("UVs");
    let mut out: Vec<_> = (0..mesh.face_count())
        .flat_map(|f| {
            (0..3).map(move |k| {
                // + 0 makes −0 and 0 one key (the glTF reader's transform does the same).
                let p = (mesh.positions[mesh.triangles[f][k] as usize] + DVec3::ZERO).to_array().map(f64::to_bits);
                let uv = uvs.at(f, k).map(f64::to_bits);
                (p, uv)
            })
        })
        .collect();
    out.sort_unstable();
    out.dedup();
    out
}

#[test]
fn the_sphere_has_one_seam_meridian_and_a_material_line() {
    let mesh = uv_sphere(16, 8);
    let seams = seam_edges(&mesh);
    // The meridian (8 edges from pole to pole) and the equator between the materials (16).
    assert_eq!(seams.len(), 8 + 16, "{seams:?}");
}

#[test]
fn obj_round_trip_keeps_positions_uvs_and_materials_bit_exact() {
    let mesh = uv_sphere(24, 12);
    let dir = temp_dir();
    let path = dir.path().join("sphere.obj");
    io::write(&mesh, &path, io::WriteOptions::default()).unwrap();
    let back = io::read(&path).unwrap();
    assert!(back.notes.is_empty(), "{:?}", back.notes);
    assert_eq!(back.mesh, mesh);
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("mtllib sphere materials.mtl") && text.contains("usemtl south"));
    // Welded: one `v` per position, the seam lives in the `vt` indices.
    assert_eq!(text.lines().filter(|l| l.starts_with("v ")).count(), mesh.vertex_count());
}

#[test]
fn obj_texture_coordinates_follow_polygons_and_partial_ones_are_refused_with_a_note() {
    let quad = "mtllib a.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl red\nf 1/1 2/2 3/3 4/4\n";
    let (_dir, read) = read_text("quad.obj", quad);
    let uvs = read.mesh.uvs.as_ref().expect("UVs kept");
    for (f, t) in read.mesh.triangles.iter().enumerate() {
        for (k, &v) in t.iter().enumerate() {
            let p = read.mesh.positions[v as usize];
            assert_eq!(uvs.at(f, k), [p.x, p.y], "corner {k} of triangle {f}");
        }
    }
    let m = read.mesh.materials.as_ref().unwrap();
    assert_eq!((m.libraries.clone(), m.names.clone(), m.faces.clone()), (vec!["a.mtl".into()], vec!["red".into()], vec![0, 0]));
    let partial = "v 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nf 1/1 2 3\n";
    let (_dir, read) = read_text("partial.obj", partial);
    assert!(read.mesh.uvs.is_none());
    assert!(read.notes.iter().any(|n| n.contains("1 of 3 triangle corners")), "{:?}", read.notes);
}

#[test]
fn ply_and_glb_hold_one_uv_per_vertex_so_seams_are_split_on_writing() {
    let mesh = uv_sphere(24, 12);
    let dir = temp_dir();
    for name in ["sphere.ply", "sphere.glb"] {
        let path = dir.path().join(name);
        io::write(&mesh, &path, io::WriteOptions::default()).unwrap();
        let back = io::read(&path).unwrap().mesh;
        // One extra vertex per seam side: 11 ring vertices on the meridian; the
        // equator's material line splits nothing (UVs agree across it).
        assert_eq!(back.vertex_count(), mesh.vertex_count() + 11, "{name}");
        let mut expected = mesh.clone();
        if name.ends_with(".glb") {
            // glTF stores single precision.
            expected.positions.iter_mut().for_each(|p| *p = p.as_vec3().as_dvec3() + DVec3::ZERO);
        }
        let (want, got) = (corner_uvs(&expected), corner_uvs(&back));
        if name.ends_with(".ply") {
            assert_eq!(got, want, "{name}: every corner's position and UV, bit for bit");
        } else {
            assert_eq!(got.len(), want.len());
            for ((p, a), (q, b)) in got.iter().zip(&want) {
                assert_eq!(p, q, "{name}");
                let (a, b) = (a.map(f64::from_bits), b.map(f64::from_bits));
                assert!((a[0] - b[0]).abs() < 1e-6 && (a[1] - b[1]).abs() < 1e-6, "{name}: {a:?} vs {b:?}");
            }
        }
    }
}

/// Cylindrical UVs around the z axis through the box centre (u = angle / 2π, v = height),
/// with a seam where the angle wraps: a face whose corners straddle it gets u + 1 on its
/// low side, so those vertices carry two UVs.
fn with_cylindrical_uvs(mut mesh: Mesh) -> Mesh {
    let (lo, hi) = mesh.bounding_box().unwrap();
    let centre = 0.5 * (lo + hi);
    let at = |p: DVec3| {
        let d = p - centre;
        [(d.y.atan2(d.x) / TAU).rem_euclid(1.0), (p.z - lo.z) / (hi.z - lo.z).max(f64::MIN_POSITIVE)]
    };
    let mut values = Vec::new();
    let mut corners = Vec::new();
    for t in &mesh.triangles {
        let mut uv = t.map(|v| at(mesh.positions[v as usize]));
        let us = uv.map(|c| c[0]);
        if us.iter().cloned().fold(f64::MIN, f64::max) - us.iter().cloned().fold(f64::MAX, f64::min) > 0.5 {
            for c in &mut uv {
                if c[0] < 0.5 {
                    c[0] += 1.0;
                }
            }
        }
        let first = values.len() as u32;
        values.extend(uv);
        corners.push([first, first + 1, first + 2]);
    }
    mesh.uvs = Some(CornerUvs { values, corners });
    mesh
}

/// Checks every recorded level of `mesh`'s hierarchy: each corner's UV is one its vertex
/// has in the input, and no face spans the seam: the u extent of the faces `measurable`
/// accepts (corner positions) stays under 1/2, where a face across the seam would reach
/// nearly 1.
fn assert_levels_keep_uvs(name: &str, mesh: &Mesh, target: usize, measurable: &dyn Fn([DVec3; 3]) -> bool) -> usize {
    assert_levels_keep_uvs_in(name, mesh, target, None, measurable)
}

/// [`assert_levels_keep_uvs`] for a build in `chunks` parts (#40) or in one piece.
fn assert_levels_keep_uvs_in(
    name: &str,
    mesh: &Mesh,
    target: usize,
    chunks: Option<usize>,
    measurable: &dyn Fn([DVec3; 3]) -> bool,
) -> usize {
    use asperity::hierarchy::{KeepFeatures, SimplifyOptions, build};
    let options = SimplifyOptions {
        target_vertices: Some(target),
        keep_features: KeepFeatures::None,
        record_levels: true,
        chunks,
        ..SimplifyOptions::default()
    };
    let h = build(mesh, &options).unwrap();
    let input_uvs = mesh.uvs.as_ref().unwrap();
    let mut uvs_of = vec![Vec::new(); mesh.vertex_count()];
    for (f, t) in mesh.triangles.iter().enumerate() {
        for k in 0..3 {
            uvs_of[t[k] as usize].push(input_uvs.at(f, k));
        }
    }
    let mut levels = h.levels.clone();
    levels.push(h.base_mesh());
    for (depth, level) in levels.into_iter().enumerate() {
        let level = h.with_attributes(level).unwrap();
        level.mesh.check().unwrap();
        let uvs = level.mesh.uvs.as_ref().expect("UVs on every level");
        let mut measured = 0;
        for (f, t) in level.mesh.triangles.iter().enumerate() {
            let us: Vec<f64> = (0..3).map(|k| uvs.at(f, k)[0]).collect();
            let extent = us.iter().cloned().fold(f64::MIN, f64::max) - us.iter().cloned().fold(f64::MAX, f64::min);
            if measurable(t.map(|v| level.mesh.positions[v as usize])) {
                measured += 1;
                assert!(extent < 0.5, "{name}: level {depth} face {f} spans the seam (u {us:?})");
            }
            for (k, &v) in t.iter().enumerate() {
                let id = level.ids[v as usize] as usize;
                assert!(uvs_of[id].contains(&uvs.at(f, k)), "{name}: level {depth}: vertex {id} got a UV it never had");
            }
        }
        assert!(2 * measured > level.mesh.face_count(), "{name}: level {depth}: only {measured} faces measured");
    }
    h.base_vertex_count()
}

#[test]
fn every_level_keeps_the_uvs_and_no_face_spans_a_seam() {
    // At the poles u is any value: faces there are not measured.
    let off_poles = |p: [DVec3; 3]| p.iter().all(|p| p.z.abs() < 0.999);
    let sphere = uv_sphere(48, 24);
    let base = assert_levels_keep_uvs("uv sphere", &sphere, 60, &off_poles);
    // The seam's ends (the poles) and its path stay; the rest simplifies.
    assert!(base < 200, "uv sphere: {base} base vertices");
    let torus = with_cylindrical_uvs(asperity::mesh::primitives::torus(1.0, 0.35, 64, 24));
    assert!(!seam_edges(&torus).is_empty());
    let base = assert_levels_keep_uvs("torus", &torus, 100, &|_| true);
    assert!(base < 400, "torus: {base} base vertices");
}

#[test]
fn a_partitioned_build_keeps_the_uvs_and_materials_on_every_level() {
    // #40: the parts carry the input's corner UVs and materials, so their seams are the
    // input's; the joined bases' continuation simplifies the seams along themselves, and
    // every level (made by refinement) takes the input's attributes.
    let off_poles = |p: [DVec3; 3]| p.iter().all(|p| p.z.abs() < 0.999);
    let sphere = uv_sphere(48, 24);
    let base = assert_levels_keep_uvs_in("uv sphere in 3 parts", &sphere, 60, Some(3), &off_poles);
    assert!(base < 200, "uv sphere in 3 parts: {base} base vertices");
    let torus = with_cylindrical_uvs(asperity::mesh::primitives::torus(1.0, 0.35, 64, 24));
    let base = assert_levels_keep_uvs_in("torus in 4 parts", &torus, 100, Some(4), &|_| true);
    assert!(base < 400, "torus in 4 parts: {base} base vertices");
    // A part's file holds its UVs and materials (a part built in another process).
    use asperity::hierarchy::partition::{Partition, files};
    let tmp = crate::common::temp_dir();
    let partition = Partition::of(&sphere, 3).unwrap();
    let mut with_seams = 0;
    for k in 0..3 {
        let part = partition.part(&sphere, k).unwrap();
        with_seams += usize::from(!seam_edges(&part.mesh).is_empty());
        let file = tmp.path().join(format!("{k}.part"));
        files::write_part(&part, &file).unwrap();
        let read = files::read_part(&file, sphere.vertex_count()).unwrap();
        assert_eq!((&read.mesh.uvs, &read.mesh.materials), (&part.mesh.uvs, &part.mesh.materials), "part {k}");
    }
    assert!(with_seams >= 1, "no part holds a seam");
    // A part file whose materials are not numbered in order of first use is refused at
    // the material's byte (its hash made to match: a file written so, not cut short).
    let file = tmp.path().join("0.part");
    let mut bytes = std::fs::read(&file).unwrap();
    let part = partition.part(&sphere, 0).unwrap();
    // The materials come before the border quadrics (a count, ten f64 each) and the hash.
    let at = bytes.len() - 8 - (8 + 80 * part.border.len()) - 4 * part.mesh.face_count();
    bytes[at..at + 4].copy_from_slice(&5u32.to_le_bytes());
    let body = bytes.len() - 8;
    let hash = asperity::io::manifest::fnv1a(asperity::io::manifest::FNV_OFFSET, &bytes[..body]);
    bytes[body..].copy_from_slice(&hash.to_le_bytes());
    let broken = tmp.path().join("broken.part");
    std::fs::write(&broken, &bytes).unwrap();
    let e = files::read_part(&broken, sphere.vertex_count()).unwrap_err();
    let text = e.to_string();
    assert_eq!(e.exit_code(), 2);
    let named = text.contains(&format!("broken.part: byte {at}"));
    assert!(named && text.contains("material 5 before material 0"), "{text}");
    // Refinement restores every face with its UVs and material.
    let options = asperity::hierarchy::SimplifyOptions {
        target_vertices: Some(60),
        keep_features: asperity::hierarchy::KeepFeatures::None,
        chunks: Some(3),
        ..Default::default()
    };
    let h = asperity::hierarchy::build(&sphere, &options).unwrap();
    let mut refiner = asperity::hierarchy::Refiner::new(&h).unwrap();
    refiner.refine_all().unwrap();
    let full = h.with_attributes(refiner.mesh().unwrap()).unwrap().mesh;
    let faces_with_attributes = |m: &Mesh| {
        let (uvs, materials) = (m.uvs.as_ref().unwrap(), m.materials.as_ref().unwrap());
        let mut faces: Vec<_> = (0..m.face_count())
            .map(|f| {
                let corners = (0..3).map(|k| {
                    let p = m.positions[m.triangles[f][k] as usize].to_array().map(f64::to_bits);
                    (p, uvs.at(f, k).map(f64::to_bits))
                });
                let mut corners: Vec<_> = corners.collect();
                let first = (0..3).min_by_key(|&k| corners[k].0).unwrap();
                corners.rotate_left(first);
                (corners, materials.names.get(materials.faces[f] as usize).cloned())
            })
            .collect();
        faces.sort();
        faces
    };
    assert_eq!(faces_with_attributes(&full), faces_with_attributes(&sphere));
}

#[test]
fn a_shared_scan_with_generated_uvs_keeps_them_on_every_level() {
    let path = crate::common::shared_meshes().join("bunny00.off");
    let mesh = io::read(&path).unwrap_or_else(|e| panic!("{e}: the shared meshes belong in {}", path.display())).mesh;
    let mesh = with_cylindrical_uvs(mesh);
    let target = mesh.vertex_count() / 20;
    // Near the axis the angle, and so u, is ill-defined: faces measured are those whose
    // corners all lie away from it and within a quarter turn of each other.
    let (lo, hi) = mesh.bounding_box().unwrap();
    let (centre, reach) = (0.5 * (lo + hi), 0.2 * (hi - lo).truncate().min_element());
    let clear = |p: [DVec3; 3]| {
        let angle = p.map(|q| (q.y - centre.y).atan2(q.x - centre.x));
        let apart = |a: f64, b: f64| ((a - b).rem_euclid(TAU)).min((b - a).rem_euclid(TAU));
        p.iter().all(|q| (*q - centre).truncate().length() > reach)
            && apart(angle[0], angle[1]).max(apart(angle[1], angle[2])).max(apart(angle[0], angle[2])) < TAU / 4.0
    };
    let base = assert_levels_keep_uvs("bunny00", &mesh, target, &clear);
    assert!(base <= 2 * target, "bunny00: {base} base vertices for a target of {target}");
}

/// An 8 × 8 check texture whose texels encode their check: red (i + ½)·32, green
/// (j + ½)·32, blue 255. Lighting scales the three channels alike, so a pixel's check is
/// read back from its red and green against its blue.
fn check_index_texture() -> asperity::render::texture::Texture {
    let side = 64;
    let texels = (0..side * side)
        .map(|k| {
            let (x, y) = (k % side, k / side);
            // Image rows run down; check j counts up the v axis.
            let (i, j) = (x / 8, 7 - y / 8);
            glam::Vec3::new((i as f32 + 0.5) * 32.0 / 255.0, (j as f32 + 0.5) * 32.0 / 255.0, 1.0)
        })
        .collect();
    asperity::render::texture::Texture::new(side, side, texels).unwrap()
}

/// The check (i, j) each fully covered pixel shows.
fn checks_seen(mesh: &Mesh, yaw: f64) -> Vec<Option<(i32, i32)>> {
    use asperity::render::{RenderOptions, render};
    let options = RenderOptions {
        width: 160,
        height: 160,
        yaw_deg: yaw,
        pitch_deg: 10.0,
        background: None,
        texture: Some(std::sync::Arc::new(check_index_texture())),
        ..RenderOptions::default()
    };
    let picture = render(mesh, &options).unwrap();
    picture
        .rgba
        .chunks_exact(4)
        .map(|p| {
            (p[3] == 255 && p[2] > 40).then(|| {
                let read = |c: u8| ((f32::from(c) / f32::from(p[2]) * 255.0 / 32.0).floor() as i32).clamp(0, 7);
                (read(p[0]), read(p[1]))
            })
        })
        .collect()
}

#[test]
fn a_coarse_level_draws_the_same_checks_as_the_input() {
    use asperity::hierarchy::{KeepFeatures, SimplifyOptions, build};
    let sphere = uv_sphere(64, 32);
    let options = SimplifyOptions {
        target_vertices: Some(sphere.vertex_count() / 8),
        keep_features: KeepFeatures::None,
        ..SimplifyOptions::default()
    };
    let h = build(&sphere, &options).unwrap();
    let base = h.with_attributes(h.base_mesh()).unwrap().mesh;
    // The seam lies at +x; the four views see it from the front, both sides and behind.
    for yaw in [0.0, 90.0, 180.0, 270.0] {
        let (fine, coarse) = (checks_seen(&sphere, yaw), checks_seen(&base, yaw));
        let both: Vec<((i32, i32), (i32, i32))> =
            fine.iter().zip(&coarse).filter_map(|(a, b)| Some(((*a)?, (*b)?))).collect();
        assert!(both.len() > 5000, "yaw {yaw}: {} pixels compared", both.len());
        // u wraps: checks 0 and 7 are neighbours across the seam.
        let apart = |a: i32, b: i32| (a - b).rem_euclid(8).min((b - a).rem_euclid(8));
        let torn = both.iter().filter(|((i, j), (k, l))| apart(*i, *k) > 1 || (j - l).abs() > 1).count();
        let share = torn as f64 / both.len() as f64;
        assert!(share < 0.01, "yaw {yaw}: {:.2} % of the pixels show a check more than one away", share * 100.0);
    }
}

fn asperity(args: &[&str], cwd: &std::path::Path) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_asperity")).args(args).current_dir(cwd).output().expect("run asperity")
}

#[test]
fn the_command_line_keeps_uvs_through_simplify_and_draws_them() {
    let dir = temp_dir();
    let d = dir.path();
    io::write(&uv_sphere(32, 16), &d.join("sphere.obj"), io::WriteOptions::default()).unwrap();
    std::fs::write(d.join("sphere materials.mtl"), "newmtl north\nnewmtl south\n").unwrap();
    std::fs::create_dir(d.join("out")).unwrap();
    let out = asperity(
        &["simplify", "sphere.obj", "-o", "out/base.obj", "--target-vertices", "20%", "--levels-out", "levels", "--lod-out", "lod.glb"],
        d,
    );
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    // Levels in the input's format, with their UVs and materials; libraries found from
    // their new folders.
    for name in ["out/base.obj", "levels/level_00.obj", "levels/level_03.obj"] {
        let read = io::read(&d.join(name)).unwrap();
        assert!(read.mesh.uvs.is_some() && read.mesh.materials.is_some(), "{name}");
        let library = &read.mesh.materials.as_ref().unwrap().libraries[0];
        let folder = d.join(name).parent().unwrap().to_path_buf();
        assert!(folder.join(library).exists(), "{name}: mtllib {library}");
    }
    let lod = io::read(&d.join("lod.glb")).unwrap().mesh;
    assert!(lod.uvs.is_some(), "TEXCOORD_0 in the LOD file");
    // Region refinement across the seam (at +x) keeps them too.
    let out = asperity(&["refine", "sphere.obj", "--region", "half_space = { axis = \"x\", above = 0.6 }", "-o", "out/r.obj"], d);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(!String::from_utf8_lossy(&out.stderr).contains("not carried"));
    let refined = io::read(&d.join("out/r.obj")).unwrap().mesh;
    assert!(refined.uvs.is_some() && refined.materials.is_some());
    // render --texture draws them; a mesh without UVs or another mode is refused.
    let checker: Vec<u8> = (0..16 * 16).flat_map(|k| if (k % 16 / 4 + k / 64) % 2 == 0 { [220, 40, 40] } else { [30, 30, 200] }).collect();
    asperity::io::image::write_png_rgb8(&d.join("checker.png"), &checker, 16).unwrap();
    let plain = asperity(&["render", "out/base.obj", "-o", "plain.png", "--size", "96,72"], d);
    let textured =
        asperity(&["render", "out/base.obj", "-o", "textured.png", "--size", "96,72", "--texture", "checker.png"], d);
    assert!(plain.status.success() && textured.status.success(), "{}", String::from_utf8_lossy(&textured.stderr));
    assert_ne!(std::fs::read(d.join("plain.png")).unwrap(), std::fs::read(d.join("textured.png")).unwrap());
    io::write(&Mesh::new(vec![DVec3::ZERO, DVec3::X, DVec3::Y], vec![[0, 1, 2]]), &d.join("bare.ply"), io::WriteOptions::default()).unwrap();
    for (args, says) in [
        (&["render", "bare.ply", "-o", "x.png", "--texture", "checker.png"][..], "no texture coordinates"),
        (&["render", "out/base.obj", "-o", "x.png", "--texture", "checker.png", "--mode", "wireframe"][..], "--mode faces"),
        (&["render", "out/base.obj", "-o", "x.png", "--texture", "checker.png", "--colors", "height"][..], "--colors"),
    ] {
        let out = asperity(args, d);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.code() == Some(2) && stderr.contains(says), "{args:?}: {stderr}");
    }
}

#[test]
fn detail_carries_uvs_materials_and_colours_through_subdivision() {
    use asperity::detail::{DetailOptions, Recipe, apply};
    let mut sphere = uv_sphere(48, 24);
    sphere.colors = Some((0..sphere.vertex_count()).map(|v| [(v % 256) as u8, 7, 9]).collect());
    sphere.normals = Some(sphere.positions.clone());
    let noise = Recipe::parse(
        "seed = 3\n[[step]]\nop = \"noise\"\nlevel = -1\nnoise = { kind = \"fbm\", amplitude = 0.01, frequency = 4.0 }\n",
    )
    .unwrap();
    let out = apply(&sphere, &noise, &DetailOptions::default()).unwrap();
    assert!(out.attribute_notes.is_empty(), "{:?}", out.attribute_notes);
    let result = &out.result;
    let (uvs, colors) = (result.mesh.uvs.as_ref().expect("UVs"), result.mesh.colors.as_ref().expect("colours"));
    assert!(result.mesh.materials.is_some() && result.mesh.normals.is_some());
    let input_uvs = sphere.uvs.as_ref().unwrap();
    let mut uvs_of = vec![Vec::new(); sphere.vertex_count()];
    for (f, t) in sphere.triangles.iter().enumerate() {
        for k in 0..3 {
            uvs_of[t[k] as usize].push(input_uvs.at(f, k));
        }
    }
    for (f, t) in result.mesh.triangles.iter().enumerate() {
        for k in 0..3 {
            let id = result.ids[t[k] as usize] as usize;
            assert!(uvs_of[id].contains(&uvs.at(f, k)));
            assert_eq!(colors[t[k] as usize], sphere.colors.as_ref().unwrap()[id]);
        }
    }
    // Local subdivision across the seam (at +x) and at the pole where it ends: the made
    // vertices take their edge's mean UV on each side, so no face spans the seam.
    let subdivide = Recipe::parse(
        "[[step]]\nop = \"subdivide\"\nlevel = -1\nselect = { sphere = { center = [1.0, 0.5, 0.5], radius = 0.15 } }\nsubdivide = { steps = 3 }\n[[step]]\nop = \"subdivide\"\nlevel = -1\nselect = { sphere = { center = [0.5, 0.5, 1.0], radius = 0.1 } }\nsubdivide = { steps = 2 }\n",
    )
    .unwrap();
    let out = apply(&sphere, &subdivide, &DetailOptions::default()).unwrap();
    assert!(out.attribute_notes.is_empty(), "{:?}", out.attribute_notes);
    let made = out.result.mesh.vertex_count() - sphere.vertex_count();
    assert!(made > 50, "{made} vertices made");
    let uvs = out.result.mesh.uvs.as_ref().expect("UVs");
    let mut seam_faces = 0;
    for (f, t) in out.result.mesh.triangles.iter().enumerate() {
        let p = t.map(|v| out.result.mesh.positions[v as usize]);
        let us: Vec<f64> = (0..3).map(|k| uvs.at(f, k)[0]).collect();
        let extent = us.iter().cloned().fold(f64::MIN, f64::max) - us.iter().cloned().fold(f64::MAX, f64::min);
        if p.iter().all(|p| p.z.abs() < 0.999) {
            assert!(extent < 0.5, "face {f} spans the seam (u {us:?})");
        }
        // Faces touching the seam meridian in the subdivided region.
        seam_faces += usize::from(t.iter().any(|&v| out.result.ids[v as usize] as usize >= sphere.vertex_count()) && us.iter().any(|&u| u == 0.0 || u == 1.0));
        for (k, &v) in t.iter().enumerate() {
            let id = out.result.ids[v as usize] as usize;
            if id < sphere.vertex_count() {
                assert!(uvs_of[id].contains(&uvs.at(f, k)), "input vertex {id} got a UV it never had");
            }
        }
    }
    assert!(seam_faces > 4, "only {seam_faces} subdivided faces on the seam");
    assert_eq!(out.result.mesh.colors.as_ref().map(Vec::len), Some(out.result.mesh.vertex_count()));
}

#[test]
fn obj_faces_without_a_material_stay_without_one() {
    // A level may list a face with no material after a named one: written first, since
    // OBJ gives every face after a `usemtl` that material.
    let mut mesh = Mesh::new(
        vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::ONE],
        vec![[0, 1, 2], [2, 1, 3]],
    );
    mesh.materials = Some(Materials { libraries: vec![], names: vec!["red".into()], faces: vec![0, u32::MAX] });
    let dir = temp_dir();
    let path = dir.path().join("m.obj");
    io::write(&mesh, &path, io::WriteOptions::default()).unwrap();
    let back = io::read(&path).unwrap().mesh;
    let material_of = |m: &Mesh, t: [u32; 3]| {
        let f = m.triangles.iter().position(|&u| u == t).unwrap();
        m.materials.as_ref().unwrap().faces[f]
    };
    assert_eq!(material_of(&back, [2, 1, 3]), u32::MAX);
    assert_eq!(back.materials.as_ref().unwrap().names[material_of(&back, [0, 1, 2]) as usize], "red");
}
