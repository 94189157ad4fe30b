//! Beyond the thesis (its stated limitation, §6.0.1): displacements can make a surface cut
//! itself. CGAL finds the intersecting face pairs; damping halves the displacement (from
//! the undeformed "rest" position) of every vertex of an offending face, pass after pass,
//! and takes it back entirely after a few passes, until no pair is left. A surface whose
//! rest shape already intersects itself keeps those intersections (reported).

use glam::DVec3;
use serde::Serialize;

use crate::error::Result;
use crate::ffi::self_intersections;
use crate::mesh::Mesh;

/// Halving passes before an offending displacement is removed outright.
const HALVINGS: usize = 6;

/// What the self-intersection stage found and did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct IntersectionReport {
    /// Intersecting face pairs after detail, before damping.
    pub found: usize,
    /// Pairs left at the end.
    pub remaining: usize,
    /// Vertices whose displacement was damped.
    pub damped: usize,
    /// Damping passes run.
    pub passes: usize,
}

/// Counts self-intersections of `mesh` and, when `damp`, damps displacements (from `rest`,
/// one position per vertex) until none is left.
///
/// # Errors
/// [`crate::Error::Native`] if CGAL refuses the mesh.
pub fn resolve_self_intersections(mesh: &mut Mesh, rest: &[DVec3], damp: bool) -> Result<IntersectionReport> {
    let mut pairs = self_intersections(mesh)?;
    let mut report = IntersectionReport { found: pairs.len(), ..Default::default() };
    if damp {
        let displacement: Vec<DVec3> = mesh.positions.iter().zip(rest).map(|(p, r)| *p - *r).collect();
        let mut factor = vec![1.0f64; mesh.positions.len()];
        while !pairs.is_empty() && report.passes <= HALVINGS {
            let mut offending: Vec<usize> = pairs
                .iter()
                .flat_map(|pair| pair.iter().flat_map(|f| mesh.triangles[f.index()]))
                .map(|v| v as usize)
                .filter(|&v| factor[v] > 0.0 && displacement[v] != DVec3::ZERO)
                .collect();
            offending.sort_unstable();
            offending.dedup();
            if offending.is_empty() {
                break;
            }
            for v in offending {
                factor[v] = if report.passes == HALVINGS { 0.0 } else { factor[v] * 0.5 };
                mesh.positions[v] = rest[v] + displacement[v] * factor[v];
            }
            report.passes += 1;
            pairs = self_intersections(mesh)?;
        }
        report.damped = factor.iter().filter(|&&f| f < 1.0).count();
    }
    report.remaining = pairs.len();
    Ok(report)
}
