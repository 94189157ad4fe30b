//! glTF read as the specification defines it (#36): text files with external buffers and
//! `data:` URIs, strips and fans, sparse and quantized accessors, node transforms (a mirror
//! keeps the outside out) and `EXT_mesh_gpu_instancing`; `.gltf` written in one piece; and
//! single-precision formats that keep a mesh far from the origin whole. Documents are made
//! here, byte by byte; hostile ones are in `tests/data/bad/` (`gltf-*`).

use base64::Engine as _;
use glam::DVec3;
use serde_json::{Value, json};

use asperity::mesh::primitives::{icosphere, torus};

use crate::common::temp_dir;

/// A glTF document under construction: one buffer, a view per accessor.
#[derive(Default)]
struct Doc {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Doc {
    /// Appends `bytes` as a view and returns its index.
    fn view(&mut self, bytes: &[u8]) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        self.views.push(json!({"buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len()}));
        self.bin.extend_from_slice(bytes);
        self.views.len() - 1
    }

    fn accessor(&mut self, value: Value) -> usize {
        self.accessors.push(value);
        self.accessors.len() - 1
    }

    fn floats(&mut self, values: &[f32], kind: &str) -> usize {
        let view = self.view(&values.iter().flat_map(|v| v.to_le_bytes()).collect::<Vec<_>>());
        let width = match kind {
            "VEC2" => 2,
            "VEC3" => 3,
            "VEC4" => 4,
            _ => 1,
        };
        self.accessor(json!({"bufferView": view, "componentType": 5126, "count": values.len() / width, "type": kind}))
    }

    fn indices(&mut self, values: &[u32]) -> usize {
        let view = self.view(&values.iter().flat_map(|v| v.to_le_bytes()).collect::<Vec<_>>());
        self.accessor(json!({"bufferView": view, "componentType": 5125, "count": values.len(), "type": "SCALAR"}))
    }

    /// The JSON with `rest` merged in and the buffer at `uri` (a data: URI when `None`).
    fn json(&self, rest: Value, uri: Option<&str>) -> String {
        let data = format!(
            "data:application/octet-stream;base64,{}",
            base64::engine::general_purpose::STANDARD.encode(&self.bin)
        );
        let mut doc = json!({
            "asset": {"version": "2.0"},
            "buffers": [{"byteLength": self.bin.len(), "uri": uri.map_or(data, str::to_string)}],
            "bufferViews": self.views,
            "accessors": self.accessors,
        });
        for (k, v) in rest.as_object().unwrap() {
            doc[k] = v.clone();
        }
        doc.to_string()
    }
}

fn read_text(json: &str) -> asperity::Mesh {
    let tmp = temp_dir();
    let path = tmp.path().join("doc.gltf");
    std::fs::write(&path, json).unwrap();
    asperity::io::read(&path).unwrap_or_else(|e| panic!("{e}")).mesh
}

fn one_mesh(primitive: Value) -> Value {
    json!({"scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}], "meshes": [{"primitives": [primitive]}]})
}

/// The z of each face's normal (twice the signed area for planar input).
fn face_normals_z(mesh: &asperity::Mesh) -> Vec<f64> {
    mesh.triangles
        .iter()
        .map(|&[a, b, c]| {
            let p = |v: u32| mesh.positions[v as usize];
            (p(b) - p(a)).cross(p(c) - p(a)).z
        })
        .collect()
}

#[test]
fn strips_and_fans_read_as_the_triangles_a_list_would_give() {
    // A strip zigzagging along x (clockwise seen from +z) and a fan around the origin
    // (counter-clockwise).
    let strip = [0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 2.0, 0.0, 0.0];
    let fan = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0, 0.0, -1.0, 1.0, 0.0];
    for (positions, mode, expected) in [(strip, 5, -1.0), (fan, 6, 1.0)] {
        let mut doc = Doc::default();
        let p = doc.floats(&positions, "VEC3");
        let i = doc.indices(&[0, 1, 2, 3, 4]);
        let mesh =
            read_text(&doc.json(one_mesh(json!({"attributes": {"POSITION": p}, "indices": i, "mode": mode})), None));
        assert_eq!(mesh.triangles.len(), 3, "mode {mode}");
        let z = face_normals_z(&mesh);
        // Every triangle of a strip or fan has the orientation of its first one.
        assert!(z.iter().all(|&z| z.signum() == expected), "mode {mode}: {z:?}");
    }
}

#[test]
fn quantized_and_sparse_accessors_read_as_their_values() {
    let mut doc = Doc::default();
    // Positions as normalized unsigned shorts (KHR_mesh_quantization): 65535 is 1.
    let shorts: Vec<u8> = [0u16, 0, 0, 65535, 0, 0, 0, 65535, 0, 0].iter().flat_map(|v| v.to_le_bytes()).collect();
    // Each element of a vertex attribute is aligned to 4 bytes: stride 8 for 6-byte elements.
    let mut strided = Vec::new();
    for k in 0..3 {
        strided.extend_from_slice(&shorts[6 * k..6 * k + 6]);
        strided.extend_from_slice(&[0, 0]);
    }
    let view = doc.view(&strided);
    doc.views[view]["byteStride"] = json!(8);
    let p = doc
        .accessor(json!({"bufferView": view, "componentType": 5123, "normalized": true, "count": 3, "type": "VEC3"}));
    // A sparse accessor of normals without a view: zeros, with vertex 1's replaced.
    let sparse_index = doc.view(&1u32.to_le_bytes());
    let sparse_value = doc.view(&[0.0f32, 0.0, 1.0].iter().flat_map(|v| v.to_le_bytes()).collect::<Vec<_>>());
    let n = doc.accessor(json!({"componentType": 5126, "count": 3, "type": "VEC3",
        "sparse": {"count": 1, "indices": {"bufferView": sparse_index, "componentType": 5125}, "values": {"bufferView": sparse_value}}}));
    let rest = one_mesh(json!({"attributes": {"POSITION": p, "NORMAL": n}}));
    let mut rest = rest;
    rest["extensionsUsed"] = json!(["KHR_mesh_quantization"]);
    rest["extensionsRequired"] = json!(["KHR_mesh_quantization"]);
    let mesh = read_text(&doc.json(rest, None));
    assert_eq!(mesh.positions, vec![DVec3::ZERO, DVec3::X, DVec3::Y]);
    assert_eq!(mesh.normals.unwrap(), vec![DVec3::ZERO, DVec3::Z, DVec3::ZERO]);
}

#[test]
fn external_buffers_beside_the_file_read_like_data_uris() {
    let mut doc = Doc::default();
    let sphere = icosphere(1.0, 1);
    let floats: Vec<f32> = sphere.positions.iter().flat_map(|p| p.as_vec3().to_array()).collect();
    let p = doc.floats(&floats, "VEC3");
    let i = doc.indices(&sphere.triangles.iter().flatten().copied().collect::<Vec<_>>());
    let rest = one_mesh(json!({"attributes": {"POSITION": p}, "indices": i}));
    let tmp = temp_dir();
    std::fs::create_dir(tmp.path().join("data")).unwrap();
    std::fs::write(tmp.path().join("data/my mesh.bin"), &doc.bin).unwrap();
    let path = tmp.path().join("external.gltf");
    std::fs::write(&path, doc.json(rest.clone(), Some("data/my%20mesh.bin"))).unwrap();
    let external = asperity::io::read(&path).unwrap().mesh;
    let embedded = read_text(&doc.json(rest, None));
    assert_eq!(external.triangles, sphere.triangles);
    assert_eq!(external.positions, embedded.positions);
    assert_eq!(external.triangles, embedded.triangles);
}

#[test]
fn node_transforms_compose_and_a_mirror_keeps_the_outside_out() {
    let sphere = icosphere(1.0, 1);
    let mut doc = Doc::default();
    let floats: Vec<f32> = sphere.positions.iter().flat_map(|p| p.as_vec3().to_array()).collect();
    let p = doc.floats(&floats, "VEC3");
    let i = doc.indices(&sphere.triangles.iter().flatten().copied().collect::<Vec<_>>());
    // A parent moved along x, its child mirrored in x and scaled by 2.
    let rest = json!({
        "scene": 0, "scenes": [{"nodes": [0]}],
        "nodes": [{"translation": [10.0, 0.0, 0.0], "children": [1]}, {"scale": [-2.0, 2.0, 2.0], "mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": p}, "indices": i}]}],
    });
    let mesh = read_text(&doc.json(rest, None));
    for (got, original) in mesh.positions.iter().zip(&sphere.positions) {
        let expected = DVec3::new(10.0 - 2.0 * original.x, 2.0 * original.y, 2.0 * original.z);
        assert!((*got - expected).length() < 1e-5, "{got} against {expected}");
    }
    // The signed volume stays positive: the mirror turned the winding as glTF says.
    let volume: f64 = mesh
        .triangles
        .iter()
        .map(|&[a, b, c]| {
            let q = |v: u32| mesh.positions[v as usize] - DVec3::new(10.0, 0.0, 0.0);
            q(a).dot(q(b).cross(q(c)))
        })
        .sum();
    assert!(volume > 0.0, "signed volume {volume}");
}

#[test]
fn gpu_instancing_draws_every_instance() {
    let mut doc = Doc::default();
    let p = doc.floats(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0], "VEC3");
    let t = doc.floats(&[0.0, 0.0, 0.0, 5.0, 0.0, 0.0, 0.0, 0.0, 7.0], "VEC3");
    let rest = json!({
        "extensionsUsed": ["EXT_mesh_gpu_instancing"],
        "scene": 0, "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "extensions": {"EXT_mesh_gpu_instancing": {"attributes": {"TRANSLATION": t}}}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": p}}]}],
    });
    let mesh = read_text(&doc.json(rest, None));
    assert_eq!(mesh.triangles.len(), 3);
    assert_eq!(mesh.positions[3], DVec3::new(5.0, 0.0, 0.0));
    assert_eq!(mesh.positions[8], DVec3::new(0.0, 1.0, 7.0));
}

#[test]
fn gltf_text_written_reads_back_like_glb() {
    let mesh = torus(1.0, 0.35, 16, 8);
    let tmp = temp_dir();
    let (text, binary) = (tmp.path().join("t.gltf"), tmp.path().join("t.glb"));
    asperity::io::write(&mesh, &text, Default::default()).unwrap();
    asperity::io::write(&mesh, &binary, Default::default()).unwrap();
    let json: Value = serde_json::from_slice(&std::fs::read(&text).unwrap()).unwrap();
    assert!(json["buffers"][0]["uri"].as_str().unwrap().starts_with("data:application/octet-stream;base64,"));
    let (a, b) = (asperity::io::read(&text).unwrap().mesh, asperity::io::read(&binary).unwrap().mesh);
    assert_eq!(a.positions, b.positions);
    assert_eq!(a.triangles, mesh.triangles);
    crate::io::glb::khronos_validate(&[text]);
}

#[test]
fn a_mesh_far_from_the_origin_keeps_its_faces_in_single_precision() {
    let tmp = temp_dir();
    // 320 faces a quarter unit across, as UTM-like coordinates put them.
    for shift in [1e7, 1e9] {
        let mut mesh = icosphere(0.25, 2);
        for p in &mut mesh.positions {
            *p += DVec3::new(shift, -shift, 0.5 * shift);
        }
        let path = tmp.path().join(format!("far-{shift}.glb"));
        asperity::io::write(&mesh, &path, Default::default()).unwrap();
        let back = asperity::io::read(&path).unwrap().mesh;
        assert_eq!(back.triangles, mesh.triangles, "shift {shift}: no face dropped");
        for (got, original) in back.positions.iter().zip(&mesh.positions) {
            assert!((*got - *original).length() < 1e-6 * shift, "shift {shift}: {got} against {original}");
            // Within the sphere, f32 about the centre keeps far more than the shape needs.
        }
        let shape = |m: &asperity::Mesh, v: usize| m.positions[v] - m.positions[0];
        for v in 1..mesh.positions.len() {
            assert!(
                (shape(&back, v) - shape(&mesh, v)).length() < 1e-6,
                "shift {shift}: vertex {v}'s place in the mesh"
            );
        }
        // STL holds no offset: it refuses, counting the faces that would collapse.
        let err = asperity::io::write(&mesh, &tmp.path().join("far.stl"), Default::default()).unwrap_err().to_string();
        assert!(err.contains("faces would collapse in the single precision"), "{err}");
        assert!(!tmp.path().join("far.stl").exists());
    }
}

#[test]
fn a_small_file_that_instances_gigabytes_needs_a_budget_set() {
    // 65536 quantized positions drawn as one strip (256 kB), instanced by 256 nodes (3 kB of
    // JSON): about 2 GiB of mesh, 8000 times the file. Without --max-memory it is refused
    // before anything is decoded; with a budget, the budget decides.
    let mut doc = Doc::default();
    let bytes: Vec<u8> =
        (0..65536u32).flat_map(|i| [(i % 251) as u8, (i / 251 % 251) as u8, (i % 7) as u8, 0]).collect();
    let view = doc.view(&bytes);
    doc.views[view]["byteStride"] = json!(4);
    let p = doc.accessor(json!({"bufferView": view, "componentType": 5121, "count": 65536, "type": "VEC3"}));
    let nodes: Vec<Value> = (0..256).map(|_| json!({"mesh": 0})).collect();
    let rest = json!({
        "scene": 0, "scenes": [{"nodes": (0..256).collect::<Vec<_>>()}], "nodes": nodes,
        "meshes": [{"primitives": [{"attributes": {"POSITION": p}, "mode": 5}]}],
    });
    let tmp = temp_dir();
    std::fs::write(tmp.path().join("many.gltf"), doc.json(rest, None)).unwrap();
    let run = |args: &[&str]| {
        std::process::Command::new(env!("CARGO_BIN_EXE_asperity")).args(args).current_dir(tmp.path()).output().unwrap()
    };
    let out = run(&["info", "many.gltf"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("256 mesh instance(s) drawing 16777216 vertices")
            && stderr.contains("set --max-memory to allow it"),
        "{stderr}"
    );
    let out = run(&["--max-memory", "1G", "info", "many.gltf"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("more than the --max-memory budget of 1.0 GiB"), "{stderr}");
}
