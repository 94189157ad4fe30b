//! Every format written and read back: exactly for PLY/OFF, up to vertex order for OBJ
//! and STL (which reindex by use), and up to f32 rounding for binary STL.

use asperity::Mesh;
use asperity::io::{self, WriteOptions};
use asperity::mesh::primitives::{cube, grid, icosphere, torus};
use glam::DVec3;

use crate::common::{canonical, read_text, shared_mesh_files, temp_dir};

fn code_meshes() -> Vec<(&'static str, Mesh)> {
    vec![
        ("torus", torus(2.0, 0.5, 24, 12)),
        ("icosphere", icosphere(1.3, 2)),
        ("cube", cube(DVec3::splat(-1.0), DVec3::new(2.0, 1.0, 0.5), 2)),
        ("grid", grid(6)),
    ]
}

fn with_attributes(mut mesh: Mesh) -> Mesh {
    let n = mesh.vertex_count();
    mesh.normals = Some(mesh.positions.iter().map(|p| p.normalize_or_zero()).collect());
    mesh.colors = Some((0..n).map(|i| [(i % 256) as u8, (i * 7 % 256) as u8, 200]).collect());
    mesh.scalars.insert("mean_curvature".into(), (0..n).map(|i| i as f64 * 0.25 - 3.0).collect());
    mesh.scalars.insert("feature_class".into(), (0..n).map(|i| (i % 4) as f64).collect());
    mesh
}

fn round_trip(mesh: &Mesh, file: &str, ascii: bool) -> Mesh {
    let dir = temp_dir();
    let path = dir.path().join(file);
    io::write(mesh, &path, WriteOptions { ascii }).unwrap();
    let leftovers: Vec<_> = std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(leftovers.len(), 1, "only the output file remains: {leftovers:?}");
    io::read(&path).unwrap().mesh
}

#[test]
fn ply_round_trip_is_exact_with_every_attribute() {
    for (name, mesh) in code_meshes() {
        let mesh = with_attributes(mesh);
        for ascii in [false, true] {
            assert_eq!(round_trip(&mesh, "m.ply", ascii), mesh, "{name}, ascii {ascii}");
        }
    }
}

#[test]
fn off_round_trip_is_exact() {
    for (name, mesh) in code_meshes() {
        assert_eq!(round_trip(&mesh, "m.off", false), mesh, "{name}");
    }
}

#[test]
fn obj_round_trip_keeps_geometry_colours_and_normals() {
    for (name, mesh) in code_meshes() {
        let mut mesh = with_attributes(mesh);
        mesh.scalars.clear(); // OBJ has no scalar properties
        assert_eq!(round_trip(&mesh, "m.obj", false), mesh, "{name}: vertex order and count kept");
    }
}

#[test]
fn stl_round_trip_welds_corners_back_into_vertices() {
    for (name, mesh) in code_meshes() {
        assert_eq!(canonical(&round_trip(&mesh, "m.stl", true)), canonical(&mesh), "{name} ascii");
        let mut rounded = mesh.clone();
        for p in &mut rounded.positions {
            *p = p.as_vec3().as_dvec3();
        }
        assert_eq!(canonical(&round_trip(&mesh, "m.stl", false)), canonical(&rounded), "{name} binary");
    }
}

#[test]
fn shared_meshes_survive_every_format() {
    for file in shared_mesh_files() {
        let original = io::read(&file).unwrap().mesh;
        assert_eq!(original.validate().unreferenced_vertices, 0);
        for (ext, ascii) in [("ply", false), ("ply", true), ("off", false)] {
            assert_eq!(round_trip(&original, &format!("m.{ext}"), ascii), original, "{} as {ext}", file.display());
        }
        assert_eq!(round_trip(&original, "m.obj", false), original, "{} as obj", file.display());
        assert_eq!(canonical(&round_trip(&original, "m.stl", true)), canonical(&original), "{} as stl", file.display());
    }
}

#[test]
fn obj_reader_agrees_with_tobj_on_real_meshes() {
    // tobj (the reference OBJ reader) renumbers by first use, so compare in that form.
    let dir = temp_dir();
    for file in shared_mesh_files() {
        let original = io::read(&file).unwrap().mesh;
        let path = dir.path().join("m.obj");
        io::write(&original, &path, WriteOptions::default()).unwrap();
        let options = tobj::LoadOptions { single_index: true, triangulate: true, ..Default::default() };
        let (models, _) = tobj::load_obj(&path, &options).unwrap();
        let m = &models[0].mesh;
        let positions = m.positions.chunks(3).map(|c| DVec3::new(c[0], c[1], c[2])).collect();
        let triangles = m.indices.chunks(3).map(|t| [t[0], t[1], t[2]]).collect();
        let reference = Mesh::new(positions, triangles);
        let ours = io::read(&path).unwrap().mesh;
        assert_eq!(canonical(&ours), canonical(&reference), "{}", file.display());
    }
}

#[test]
fn polygons_are_triangulated_and_counted() {
    // An L-shaped (non-convex) hexagon: a fan from vertex 0 would cover the notch.
    let (_dir, outcome) = read_text("l.off", "OFF\n6 1 0\n0 0 0\n2 0 0\n2 1 0\n1 1 0\n1 2 0\n0 2 0\n6 0 1 2 3 4 5\n");
    assert_eq!(outcome.triangulated_polygons, 1);
    let mesh = outcome.mesh;
    assert_eq!(mesh.face_count(), 4);
    let area: f64 = (0..4)
        .map(|f| {
            let [a, b, c] = mesh.triangle_points(f);
            let z = (b - a).cross(c - a).z;
            assert!(z > 0.0, "triangle {f} keeps the polygon's orientation");
            z / 2.0
        })
        .sum();
    assert!((area - 3.0).abs() < 1e-12, "area {area}");
}

#[test]
fn obj_keeps_every_vertex_in_file_order_across_groups() {
    // Groups share the file's vertex numbering: nothing is renumbered, welded or dropped,
    // unreferenced vertices included, so per-vertex data keeps lining up (#24 item 8).
    let text = "v 0 0 0\nv 1 0 0\nv 9 9 9\nv 1 1 0\nv 0 1 0\ng first\nf 1 2 4\ng second\nf -5 -2 -1\n";
    let (_dir, outcome) = read_text("groups.obj", text);
    let mesh = &outcome.mesh;
    assert_eq!(mesh.vertex_count(), 5, "the unreferenced `v 9 9 9` is kept");
    assert_eq!(mesh.positions[2], DVec3::splat(9.0));
    assert_eq!(mesh.positions[4], DVec3::new(0.0, 1.0, 0.0), "file order");
    assert_eq!(mesh.triangles, vec![[0, 1, 3], [0, 3, 4]]);
    // A vertex-only file is its vertices (commands that need faces refuse it).
    let (_dir, outcome) = read_text("points.obj", "v 0 0 0\nv 1 0 0\n");
    assert_eq!((outcome.mesh.vertex_count(), outcome.mesh.face_count()), (2, 0));
    // Faces may refer to vertices further down; statements without triangles are noted.
    let (_dir, outcome) = read_text("forward.obj", "f 1 2 3\nl 1 2\nv 0 0 0\nv 1 0 0\nv 0 1 0\n");
    assert_eq!(outcome.mesh.triangles, vec![[0, 1, 2]]);
    assert!(outcome.notes.iter().any(|n| n.contains("`l`")), "{:?}", outcome.notes);
}

#[test]
fn obj_errors_name_the_line_and_quote_the_token() {
    let dir = temp_dir();
    for (text, line, phrase) in [
        ("v 0 0 0\nv 1 0 0\nf 1 2\n", 3, "a face needs at least 3 vertices, this one has 2"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n", 4, "vertex index 0 is invalid"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n", 4, "face corner `-4`"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1 2/1 3/1\n", 4, "texture coordinate index 1 is out of range"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//2 2//1 3//1\n", 5, "face corner `1//2`: normal index 2"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3/a\n", 4, "`a` is not an integer"),
        ("v 0 0 0 1 1\n", 1, "this one has 5 values"),
        ("v 0 0 0\nv 1 \\\n 0 0\nv 0 1 0\nf 1 2 x\n", 5, "face corner `x`"),
    ] {
        let path = dir.path().join("bad.obj");
        std::fs::write(&path, text).unwrap();
        let message = asperity::io::read(&path).unwrap_err().to_string();
        assert!(message.contains(&format!("line {line}: ")) && message.contains(phrase), "{text:?}: {message}");
    }
}

#[test]
fn files_with_bom_crlf_and_comments_read() {
    let (_dir, outcome) =
        read_text("crlf.off", "\u{feff}OFF\r\n# a comment\r\n3 1 0\r\n0 0 0\r1 0 0\n0 1 0 # trailing\r\n3 0 1 2\r\n");
    let mesh = outcome.mesh;
    assert_eq!((mesh.vertex_count(), mesh.face_count()), (3, 1));
}

/// #36: a Latin-1 byte (é = 0xE9) in a comment is read; outside a comment it is refused,
/// naming its byte from the file's start (the byte-order mark counted).
#[test]
fn latin_1_bytes_read_in_comments_and_are_refused_elsewhere() {
    let dir = temp_dir();
    let write = |name: &str, bytes: &[u8]| {
        let path = dir.path().join(name);
        std::fs::write(&path, bytes).unwrap();
        asperity::io::read(&path)
    };
    let obj = b"# export\xe9 par un mod\xe8leur\nv 0 0 0\nv 1 0 0\nv 0 1 0 # coin \xe9\nf 1 2 3\n";
    let mesh = write("latin.obj", obj).unwrap().mesh;
    assert_eq!((mesh.vertex_count(), mesh.face_count()), (3, 1));
    let off = b"\xef\xbb\xbfOFF\r# \xe9\r3 1 0\r0 0 0\r1 0 0\r0 1 0\r3 0 1 2\r";
    let mesh = write("latin.off", off).unwrap().mesh;
    assert_eq!((mesh.vertex_count(), mesh.face_count()), (3, 1));
    let message = write("bad.obj", b"\xef\xbb\xbfv 0 0 0\nv 1 0 \xe9\n").unwrap_err().to_string();
    assert!(message.contains("byte 17") && message.contains("not a text file"), "{message}");
}

#[test]
fn big_endian_ply_and_other_elements_read() {
    let dir = temp_dir();
    let path = dir.path().join("be.ply");
    let mut bytes = b"ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nproperty uchar quality\nelement face 1\nproperty list uchar uint vertex_indices\nelement edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n".to_vec();
    for (i, p) in [[0f32, 0., 0.], [1., 0., 0.], [0., 1., 0.]].iter().enumerate() {
        for c in p {
            bytes.extend(c.to_be_bytes());
        }
        bytes.push(i as u8 * 10);
    }
    bytes.push(3);
    for v in [0u32, 1, 2] {
        bytes.extend(v.to_be_bytes());
    }
    bytes.extend(0i32.to_be_bytes());
    bytes.extend(1i32.to_be_bytes());
    std::fs::write(&path, bytes).unwrap();
    let outcome = io::read(&path).unwrap();
    assert_eq!(outcome.mesh.positions[1], DVec3::X);
    assert_eq!(outcome.mesh.triangles, vec![[0, 1, 2]]);
    assert_eq!(outcome.mesh.scalars["quality"], vec![0.0, 10.0, 20.0]);
    assert!(outcome.notes.iter().any(|n| n.contains("edge")));
}

#[test]
fn faces_repeating_a_vertex_are_dropped_with_a_note_in_every_reader() {
    // #24 item 6: CAD exports weld corners of thin facets together; such faces have no
    // area and are dropped (a quad with a doubled corner is the triangle it really is).
    let cases = [
        ("r.off", "OFF\n4 3 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n3 0 1 2\n4 1 3 3 2\n3 0 0 1\n"),
        ("r.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 4 3\nf 1 1 2\n"),
        (
            "r.ply",
            "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nelement face 3\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n3 0 1 2\n4 1 3 3 2\n3 0 0 1\n",
        ),
    ];
    for (name, text) in cases {
        let (_dir, outcome) = crate::common::read_text(name, text);
        assert_eq!(outcome.mesh.triangles, vec![[0, 1, 2], [1, 3, 2]], "{name}");
        assert!(
            outcome.notes.iter().any(|n| n.contains("1 face(s) repeating a vertex dropped")),
            "{name}: {:?}",
            outcome.notes
        );
    }
}

#[test]
fn an_overlong_ply_header_is_called_overlong_not_truncated() {
    // #24 item 10: a 10 MB comment used to be reported as a truncated header.
    let text = format!("ply\nformat ascii 1.0\ncomment {}\nelement vertex 0\nend_header\n", "x".repeat(2 << 20));
    let dir = temp_dir();
    let path = dir.path().join("long.ply");
    std::fs::write(&path, text).unwrap();
    let err = io::read(&path).unwrap_err().to_string();
    assert!(err.contains("longer than that is refused") && !err.contains("truncated"), "{err}");
}

#[test]
fn an_ascii_stl_of_several_solids_is_read_whole() {
    // CAD exports write one solid per part, one after the other (#36: the second was
    // dropped without a word).
    let dir = temp_dir();
    let facet = |z: f64| {
        format!(
            "facet normal 0 0 1\n outer loop\n  vertex 0 0 {z}\n  vertex 1 0 {z}\n  vertex 0 1 {z}\n endloop\nendfacet\n"
        )
    };
    let text = format!("solid a\n{}endsolid a\nsolid b\n{}{}endsolid b\n", facet(0.0), facet(1.0), facet(2.0));
    let path = dir.path().join("two.stl");
    std::fs::write(&path, text).unwrap();
    let read = io::read(&path).unwrap();
    assert_eq!(read.mesh.face_count(), 3, "every solid's facets");
    assert!(read.notes.iter().any(|n| n.contains("2 solids")), "{:?}", read.notes);
    // Anything else after `endsolid` is an error naming its line.
    std::fs::write(&path, format!("solid a\n{}endsolid a\nfacet\n", facet(0.0))).unwrap();
    let message = io::read(&path).unwrap_err().to_string();
    assert!(message.contains("line 10") && message.contains("after `endsolid`"), "{message}");
}

#[test]
fn an_stl_whose_corners_all_coincide_counts_its_welds() {
    // Every facet has no area and is dropped; the welds are counted over the corners read
    // (#36: the count wrapped to 18446744073709551614).
    let dir = temp_dir();
    let facet = "facet normal 0 0 1\n outer loop\n  vertex 1 1 1\n  vertex 1 1 1\n  vertex 1 1 1\n endloop\nendfacet\n";
    let path = dir.path().join("point.stl");
    std::fs::write(&path, format!("solid p\n{facet}{facet}endsolid p\n")).unwrap();
    let read = io::read(&path).unwrap();
    assert_eq!(read.mesh.face_count(), 0);
    assert!(read.notes.iter().any(|n| n == "STL: 5 duplicate corners welded"), "{:?}", read.notes);
}

#[test]
fn a_large_obj_face_keeps_each_corner_s_texture_coordinate() {
    // Faces of more than 32 corners look their corners' texture coordinates up in a table
    // (#36: a search per triangle corner made a 100k-corner face take seconds).
    let dir = temp_dir();
    let n = 1000;
    let mut text = String::new();
    for i in 0..n {
        let a = std::f64::consts::TAU * i as f64 / n as f64;
        text += &format!("v {} {} 0\nvt {} 0.5\n", a.cos(), a.sin(), i as f64 / n as f64);
    }
    text += "f";
    for i in 1..=n {
        text += &format!(" {i}/{i}");
    }
    text += "\n";
    let path = dir.path().join("disc.obj");
    std::fs::write(&path, text).unwrap();
    let read = io::read(&path).unwrap();
    assert_eq!(read.mesh.face_count(), n - 2);
    let uvs = read.mesh.uvs.as_ref().expect("every corner has a texture coordinate");
    for (t, corners) in read.mesh.triangles.iter().zip(&uvs.corners) {
        for (&v, &c) in t.iter().zip(corners) {
            assert_eq!(uvs.values[c as usize][0], v as f64 / n as f64, "vertex {v}'s own coordinate");
        }
    }
}
