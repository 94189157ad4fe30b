//! glTF binary output (#8): what we write reads back with the `gltf` crate (positions,
//! indices, normals, colours, scalar attributes; hierarchy levels as nodes with extras),
//! our own reader returns the mesh, hostile files are typed errors, and the Khronos
//! validator (when `scripts/install-gltf-validator.sh` could install it) finds no error.

use std::path::{Path, PathBuf};

use asperity::io::glb::{GlbPart, glb_bytes, write_glb};
use asperity::mesh::primitives::torus;

use crate::common::{shared_meshes, temp_dir};

fn coloured_torus() -> asperity::Mesh {
    let mut mesh = torus(1.0, 0.35, 24, 12);
    mesh.colors = Some((0..mesh.vertex_count()).map(|i| [(i % 256) as u8, 40, 200]).collect());
    mesh.scalars.insert("mean_curvature".into(), (0..mesh.vertex_count()).map(|i| i as f64 * 0.5).collect());
    mesh
}

/// Runs the Khronos validator on `files` when it is installed; says so when it is not.
pub fn khronos_validate(files: &[PathBuf]) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    if !root.join("target/gltf-validator/node_modules/gltf-validator/package.json").is_file() {
        eprintln!("gltf-validator not installed (scripts/install-gltf-validator.sh): Khronos validation skipped");
        return;
    }
    let out = std::process::Command::new("node")
        .arg(root.join("scripts/validate-gltf.js"))
        .args(files)
        .output()
        .expect("node runs");
    let report = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "validator: {report}{}", String::from_utf8_lossy(&out.stderr));
    assert!(report.contains("0 errors, 0 warnings"), "{report}");
}

#[test]
fn a_written_glb_reads_back_with_the_gltf_crate() {
    let mesh = coloured_torus();
    let tmp = temp_dir();
    let path = tmp.path().join("torus.glb");
    write_glb(&mesh, &path).unwrap();
    let (document, buffers, _) = gltf::import(&path).unwrap();
    let primitive = document.meshes().next().unwrap().primitives().next().unwrap();
    let reader = primitive.reader(|b| Some(&buffers[b.index()]));
    let positions: Vec<[f32; 3]> = reader.read_positions().unwrap().collect();
    assert_eq!(positions.len(), mesh.vertex_count());
    for (p, q) in positions.iter().zip(&mesh.positions) {
        assert_eq!(*p, q.as_vec3().to_array());
    }
    let indices: Vec<u32> = reader.read_indices().unwrap().into_u32().collect();
    assert_eq!(indices, mesh.triangles.iter().flatten().copied().collect::<Vec<_>>());
    let normals: Vec<[f32; 3]> = reader.read_normals().unwrap().collect();
    assert!(normals.iter().all(|n| (glam::Vec3::from(*n).length() - 1.0).abs() < 1e-5));
    let colors: Vec<[u8; 3]> = reader.read_colors(0).unwrap().into_rgb_u8().collect();
    assert_eq!(colors, *mesh.colors.as_ref().unwrap());
    let curvature = primitive
        .attributes()
        .find(|(semantic, _)| semantic.to_string() == "_MEAN_CURVATURE")
        .expect("the scalar travels as an application attribute");
    assert_eq!(curvature.1.count(), mesh.vertex_count());
    // The material is matte, not glTF's default metal.
    let material = primitive.material();
    assert_eq!(material.pbr_metallic_roughness().metallic_factor(), 0.0);
    khronos_validate(&[path]);
}

#[test]
fn our_reader_returns_what_we_wrote_and_refuses_garbage() {
    let mesh = coloured_torus();
    let tmp = temp_dir();
    let path = tmp.path().join("t.glb");
    asperity::io::write(&mesh, &path, Default::default()).unwrap();
    let back = asperity::io::read(&path).unwrap().mesh;
    assert_eq!(back.triangles, mesh.triangles);
    assert_eq!(back.colors, mesh.colors);
    for (p, q) in back.positions.iter().zip(&mesh.positions) {
        assert!((*p - *q).length() < 1e-6);
    }
    let bytes = glb_bytes(&[GlbPart { mesh: &mesh, name: "t".into(), extras: serde_json::Value::Null }]).unwrap();
    for (name, contents) in [
        ("empty.glb", Vec::new()),
        ("cut.glb", bytes[..bytes.len() / 2].to_vec()),
        ("noise.glb", (0..4096u32).map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8).collect()),
        ("header.glb", b"glTF\x02\0\0\0\xff\xff\xff\x7f".to_vec()),
    ] {
        let p = tmp.path().join(name);
        std::fs::write(&p, contents).unwrap();
        let err = asperity::io::read(&p).unwrap_err().to_string();
        assert!(err.contains(name), "{err}");
    }
}

#[test]
fn hierarchy_levels_become_nodes_naming_their_level() {
    let dir = shared_meshes();
    let tmp = temp_dir();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_asperity"))
        .args([
            "simplify",
            dir.join("eight.off").to_str().unwrap(),
            "--levels",
            "3",
            "-o",
            "base.ply",
            "--lod-out",
            "lod.glb",
        ])
        .current_dir(tmp.path())
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let path = tmp.path().join("lod.glb");
    let (document, _, _) = gltf::import(&path).unwrap();
    let nodes: Vec<_> = document.nodes().collect();
    assert_eq!(nodes.len(), 4, "levels 0..=3");
    let mut faces = Vec::new();
    for (k, node) in nodes.iter().enumerate() {
        assert_eq!(node.name(), Some(format!("level {k:02}").as_str()));
        let extras: serde_json::Value = serde_json::from_str(node.extras().as_ref().unwrap().get()).unwrap();
        assert_eq!(extras["level"], k);
        faces.push(extras["faces"].as_u64().unwrap());
    }
    assert!(faces.windows(2).all(|w| w[0] < w[1]), "coarse to fine: {faces:?}");
    assert_eq!(*faces.last().unwrap(), 634, "the finest level is the input");
    khronos_validate(&[path]);
}
