//! The plan's lean read (#40): binary PLY and binary STL read as their elements come,
//! keeping positions, faces and UVs, give the mesh, notes and errors the whole read gives.

use std::path::Path;

use asperity::io::{ReadOutcome, read, read_lean};

use crate::common::temp_dir;

/// A binary PLY (either byte order) with normals, colours, UVs and another scalar per
/// vertex, a face flag after the corners, a quad, a pentagon, a polygon repeating a
/// corner, one left with two distinct corners, and an element asperity skips.
fn ply_bytes(big_endian: bool) -> Vec<u8> {
    let order = if big_endian { "big" } else { "little" };
    let mut out = format!(
        "ply\nformat binary_{order}_endian 1.0\nelement vertex 7\nproperty float x\nproperty float y\nproperty float z\n\
         property float nx\nproperty float ny\nproperty float nz\nproperty uchar red\nproperty uchar green\n\
         property uchar blue\nproperty float s\nproperty float t\nproperty double quality\n\
         element face 5\nproperty list uchar int vertex_indices\nproperty uchar flags\n\
         element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n"
    )
    .into_bytes();
    let f32b = |v: f32| if big_endian { v.to_be_bytes() } else { v.to_le_bytes() };
    let i32b = |v: i32| if big_endian { v.to_be_bytes() } else { v.to_le_bytes() };
    let points = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [2.0, 0.5, 0.0],
        [1.5, 2.0, 0.1],
        [-1.0, 0.5, 0.0],
    ];
    for (i, p) in points.iter().enumerate() {
        for c in p.iter().chain(&[0.0, 0.0, 1.0]) {
            out.extend(f32b(*c));
        }
        out.extend([10 * i as u8, 20, 30]);
        out.extend(f32b(p[0] * 0.5));
        out.extend(f32b(p[1] * 0.25));
        out.extend(if big_endian { (i as f64).to_be_bytes() } else { (i as f64).to_le_bytes() });
    }
    let faces: [&[i32]; 5] = [&[0, 1, 2, 3], &[1, 4, 5, 2, 2], &[3, 2, 5], &[6, 0, 6, 3], &[4, 4, 1]];
    for face in faces {
        out.push(face.len() as u8);
        face.iter().for_each(|&v| out.extend(i32b(v)));
        out.push(7);
    }
    out.extend(i32b(0));
    out.extend(i32b(1));
    out
}

/// What a lean read keeps of `read`: the attributes a plan does not use dropped.
fn lean(mut read: ReadOutcome) -> ReadOutcome {
    read.mesh.normals = None;
    read.mesh.colors = None;
    read.mesh.scalars.clear();
    read
}

fn assert_same(streamed: &ReadOutcome, whole: &ReadOutcome, what: &str) {
    assert_eq!(streamed.mesh, whole.mesh, "{what}: mesh");
    assert_eq!(streamed.notes, whole.notes, "{what}: notes");
    assert_eq!(streamed.triangulated_polygons, whole.triangulated_polygons, "{what}: polygons");
}

fn write(dir: &Path, name: &str, bytes: &[u8]) -> std::path::PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

#[test]
fn a_streamed_binary_ply_is_the_whole_read_without_what_a_plan_does_not_use() {
    let dir = temp_dir();
    for big_endian in [false, true] {
        let path = write(dir.path(), "mesh.ply", &ply_bytes(big_endian));
        let whole = read(&path).unwrap();
        assert!(whole.mesh.normals.is_some() && whole.mesh.uvs.is_some() && whole.mesh.scalars.contains_key("quality"));
        assert_eq!(whole.triangulated_polygons, 2, "the quad and the pentagon");
        let (streamed, was_streamed) = read_lean(&path).unwrap();
        assert!(was_streamed);
        assert_same(&streamed, &lean(whole), &format!("big endian {big_endian}"));
    }
}

#[test]
fn a_streamed_ply_cut_short_or_with_a_bad_index_is_refused_as_the_whole_read_refuses_it() {
    let dir = temp_dir();
    let bytes = ply_bytes(false);
    let mut bad_index = bytes.clone();
    let at = bad_index.len() - 8 - 1 - 4; // the last face's last corner, before its flag and the edge
    bad_index[at..at + 4].copy_from_slice(&99i32.to_le_bytes());
    for (name, bytes) in [("short", &bytes[..bytes.len() - 30]), ("index", &bad_index[..])] {
        let path = write(dir.path(), &format!("{name}.ply"), bytes);
        let whole = read(&path).unwrap_err().to_string();
        let streamed = read_lean(&path).unwrap_err().to_string();
        assert_eq!(streamed, whole, "{name}");
        assert!(whole.contains("face") && whole.contains("byte"), "{name}: {whole}");
    }
}

#[test]
fn a_binary_stl_is_streamed_and_text_files_are_read_whole() {
    let dir = temp_dir();
    let sphere = asperity::mesh::primitives::icosphere(1.0, 2);
    let stl = dir.path().join("sphere.stl");
    asperity::io::write(&sphere, &stl, Default::default()).unwrap();
    let (streamed, was_streamed) = read_lean(&stl).unwrap();
    assert!(was_streamed);
    assert_same(&streamed, &read(&stl).unwrap(), "binary STL");
    for name in ["sphere.obj", "sphere-text.ply", "sphere-text.stl"] {
        let path = dir.path().join(name);
        asperity::io::write(&sphere, &path, asperity::io::WriteOptions { ascii: true }).unwrap();
        let (read_whole, was_streamed) = read_lean(&path).unwrap();
        assert!(!was_streamed, "{name}");
        assert_same(&read_whole, &lean(read(&path).unwrap()), name);
    }
}
