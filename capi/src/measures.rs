//! What C++ asks of a mesh without changing it: the validation report (`asperity info`),
//! the Hausdorff distance (CGAL, in the reference's unit frame), and the triangulation of
//! polygon faces (an OpenMesh `PolyMesh`), the same ear clipping the file readers use.

use asperity::Error;
use asperity::hierarchy::compare::relative_hausdorff;
use asperity::mesh::triangulate_polygon;

use crate::arrays::{mesh_of, vectors_of};
use crate::guarded;

/// `asperity info`'s validation report as JSON.
pub fn validate(positions: &[f64], triangles: &[u32]) -> Result<String, String> {
    guarded(|| {
        let mesh = mesh_of(positions, triangles)?;
        Ok(serde_json::to_string(&mesh.validate()).expect("a report serialises"))
    })
}

/// The two-sided Hausdorff distance from `reference` to `other`, a share of the
/// reference's bounding-box diagonal.
pub fn hausdorff(
    reference_positions: &[f64],
    reference_triangles: &[u32],
    other_positions: &[f64],
    other_triangles: &[u32],
) -> Result<f64, String> {
    guarded(|| {
        let reference = mesh_of(reference_positions, reference_triangles)?;
        let other = mesh_of(other_positions, other_triangles)?;
        relative_hausdorff(&reference, &other)
    })
}

/// Triangles (3 ids each) of polygons given as corner counts and their corners in order:
/// a polygon of n corners gives n − 2 triangles, in polygon order (ear clipping in the
/// polygon's plane; a triangle passes through unchanged).
pub fn triangulate(positions: &[f64], corner_counts: &[u32], corners: &[u32]) -> Result<Vec<u32>, String> {
    guarded(|| {
        if !positions.len().is_multiple_of(3) {
            return Err(Error::InvalidInput(format!("{} coordinates are not a multiple of 3", positions.len())));
        }
        let points = vectors_of(positions);
        let mut triangles = Vec::new();
        let mut start = 0usize;
        for (face, &count) in corner_counts.iter().enumerate() {
            let end = start + count as usize;
            let Some(polygon) = corners.get(start..end).filter(|_| count >= 3) else {
                return Err(Error::InvalidInput(format!("face {face} has {count} corners (or the corners run out)")));
            };
            if let Some(&v) = polygon.iter().find(|&&v| v as usize >= points.len()) {
                return Err(Error::InvalidInput(format!("face {face} names vertex {v} of {}", points.len())));
            }
            triangulate_polygon(&points, polygon, &mut triangles);
            start = end;
        }
        Ok(triangles.into_iter().flatten().collect())
    })
}
