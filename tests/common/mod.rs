//! Helpers shared by the integration tests.
#![allow(dead_code)]

use std::path::PathBuf;

/// `../shared/data/meshes` next to the checkout, or `None` (tests then skip with a message).
pub fn shared_meshes() -> PathBuf {
    let fetched = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("target/test-meshes/data/meshes");
    let dir = [shared_meshes_dir(), fetched.clone()].into_iter().find(|d| d.is_dir());
    dir.unwrap_or_else(|| {
        panic!(
            "the shared test meshes are missing: they belong in {} (see its README.md) or, fetched by scripts/fetch-test-meshes.sh (make test runs it), in {}",
            shared_meshes_dir().display(),
            fetched.display()
        )
    })
}

/// Where the shared meshes belong.
fn shared_meshes_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/data/meshes")
}

/// Whether the shared meshes are there (for checks of programs that use them when they
/// are, as `demo` does).
pub fn shared_meshes_present() -> bool {
    shared_meshes_dir().is_dir()
}

/// Every `.off` file of the shared meshes, sorted.
pub fn shared_mesh_files() -> Vec<PathBuf> {
    let dir = shared_meshes();
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("read shared meshes")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "off"))
        .collect();
    files.sort();
    files
}

use asperity::Mesh;

/// The mesh renumbered so vertices appear in order of first use by the triangles
/// (unreferenced vertices dropped): formats that store corners (STL) and readers that
/// reindex by use (tobj, the reference OBJ reader) compare equal to the original in this form.
pub fn canonical(mesh: &Mesh) -> Mesh {
    let mut new_index = vec![u32::MAX; mesh.vertex_count()];
    let mut positions = Vec::new();
    let mut order = Vec::new();
    let triangles = mesh
        .triangles
        .iter()
        .map(|t| {
            t.map(|v| {
                let slot = &mut new_index[v as usize];
                if *slot == u32::MAX {
                    *slot = positions.len() as u32;
                    positions.push(mesh.positions[v as usize]);
                    order.push(v as usize);
                }
                *slot
            })
        })
        .collect();
    let mut out = Mesh::new(positions, triangles);
    out.normals = mesh.normals.as_ref().map(|n| order.iter().map(|&v| n[v]).collect());
    out.colors = mesh.colors.as_ref().map(|c| order.iter().map(|&v| c[v]).collect());
    out
}

/// A temporary folder for a test's files.
pub fn temp_dir() -> tempfile::TempDir {
    tempfile::tempdir().expect("temporary folder")
}

/// Writes `contents` to a file named `name` in a fresh temporary folder and reads it back as
/// a mesh (the folder is returned so the file outlives the call).
pub fn read_text(name: &str, contents: &str) -> (tempfile::TempDir, asperity::io::ReadOutcome) {
    let dir = temp_dir();
    let path = dir.path().join(name);
    std::fs::write(&path, contents).expect("write test file");
    let outcome = asperity::io::read(&path).expect("read test file");
    (dir, outcome)
}

/// A closed, bumpy, very flat ellipsoid (an icosphere of subdivision level 3 squashed
/// to 0.005 of its height): its top and bottom are so close that removing vertices
/// without the intersection guard makes levels cut through themselves.
pub fn thin_pancake() -> Mesh {
    let mut mesh = asperity::mesh::primitives::icosphere(1.0, 3);
    for p in &mut mesh.positions {
        p.z *= 0.005;
        p.z += 0.004 * (13.0 * p.x).sin() * (11.0 * p.y).cos();
    }
    mesh
}

/// A Menger sponge of level 2 made of voxels (9³ cells, 400 cubes), its boundary faces
/// triangulated and welded, turned about z by the integer matrix ((3, −4), (4, 3)) (a
/// rotation scaled by 5, so every coordinate stays an exact integer) and scaled by
/// `scale`: a CAD-like solid whose coplanar faces meet in exact oblique lines, where a
/// transform's rounding decides whether two faces touch.
pub fn menger_sponge(scale: f64) -> Mesh {
    let filled = |c: [i64; 3]| {
        c.iter().all(|&x| (0..9).contains(&x)) && {
            let ones = |d: i64| c.iter().filter(|&&x| (x / d) % 3 == 1).count();
            ones(1) < 2 && ones(3) < 2
        }
    };
    let mut index: std::collections::HashMap<[i64; 3], u32> = std::collections::HashMap::new();
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    let mut vertex = |p: [i64; 3], positions: &mut Vec<glam::DVec3>| {
        *index.entry(p).or_insert_with(|| {
            let turned = [3 * p[0] - 4 * p[1], 4 * p[0] + 3 * p[1], 5 * p[2]];
            positions.push(glam::DVec3::new(turned[0] as f64, turned[1] as f64, turned[2] as f64) * scale);
            positions.len() as u32 - 1
        })
    };
    for x in 0..9 {
        for y in 0..9 {
            for z in 0..9 {
                let c = [x, y, z];
                if !filled(c) {
                    continue;
                }
                for axis in 0..3 {
                    for dir in [-1i64, 1] {
                        let mut n = c;
                        n[axis] += dir;
                        if filled(n) {
                            continue;
                        }
                        // The face's corners, counter-clockwise seen from outside.
                        let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
                        let mut base = c;
                        if dir > 0 {
                            base[axis] += 1;
                        }
                        let corner = |du: i64, dw: i64| {
                            let mut p = base;
                            p[u] += du;
                            p[w] += dw;
                            p
                        };
                        let mut quad = [corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)];
                        if dir < 0 {
                            quad.reverse();
                        }
                        let ids = quad.map(|p| vertex(p, &mut positions));
                        triangles.push([ids[0], ids[1], ids[2]]);
                        triangles.push([ids[0], ids[2], ids[3]]);
                    }
                }
            }
        }
    }
    Mesh { positions, triangles, ..Mesh::default() }
}
