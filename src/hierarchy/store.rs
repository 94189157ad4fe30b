//! The OpenMesh store of a hierarchy (the design card's topology for refinement and the C++
//! API): what the build's replay and refinement read back from it, and their check that
//! OpenMesh carried out every planned operation.

use crate::error::{Error, Result};
use crate::ffi::{self, HalfEdgeMesh, OpStatus};

/// Planning checks every condition OpenMesh checks, so a refusal is a bug.
pub(super) fn expect_done(what: &str, pairs: &[[u32; 2]], status: &[OpStatus]) -> Result<()> {
    match status.iter().position(|&s| s != OpStatus::Done) {
        None => Ok(()),
        Some(i) => Err(Error::Internal(format!(
            "OpenMesh refused the planned {what} {}–{} ({:?})",
            pairs[i][0], pairs[i][1], status[i]
        ))),
    }
}

/// The store's live faces in store vertex indices.
pub(super) fn exported_triangles(store: &HalfEdgeMesh) -> Result<Vec<[u32; 3]>> {
    let exported = store.export()?;
    let mut store_index = vec![0u32; exported.mesh.vertex_count()];
    for (i, &e) in exported.vertex_remap.iter().enumerate() {
        if e != ffi::INVALID_INDEX {
            store_index[e as usize] = i as u32;
        }
    }
    Ok(exported.mesh.triangles.iter().map(|t| t.map(|v| store_index[v as usize])).collect())
}
