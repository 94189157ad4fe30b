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
        for k in 0..3 {
            let p = read.mesh.positions[t[k] as usize];
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
