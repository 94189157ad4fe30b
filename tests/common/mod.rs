//! Helpers shared by the integration tests.
#![allow(dead_code)]

use std::path::PathBuf;

/// `../shared/data/meshes` next to the checkout, or `None` (tests then skip with a message).
pub fn shared_meshes() -> Option<PathBuf> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/data/meshes");
    if dir.is_dir() {
        Some(dir)
    } else {
        eprintln!("skipping: {} is absent", dir.display());
        None
    }
}

/// Every `.off` file of the shared meshes, sorted.
pub fn shared_mesh_files() -> Vec<PathBuf> {
    let Some(dir) = shared_meshes() else {
        return Vec::new();
    };
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("read shared meshes")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "off"))
        .collect();
    files.sort();
    files
}
