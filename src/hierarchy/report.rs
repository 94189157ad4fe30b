//! The report of a hierarchy build, as every front end gives it: the command line's
//! `simplify --json`, Python's `Hierarchy.report` and C++'s `Hierarchy::report_json()` read the
//! same fields from here (meshoptimizer's one-line result reports, with the measures a
//! user checks a simplification by).

use glam::DVec3;
use serde::Serialize;

use super::compare::ShapeReport;
use super::hausdorff_in_pieces::relative_hausdorff_in_pieces;
use super::{BuildStages, Hierarchy, TargetReport};
use crate::error::Result;
use crate::mesh::Mesh;

/// What a build made, how close to the input it is, and what stopped it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BuildReport {
    /// Vertices of the input.
    pub input_vertices: usize,
    /// Faces of the input.
    pub input_faces: usize,
    /// Vertices of the base domain.
    pub output_vertices: usize,
    /// Faces of the base domain.
    pub output_faces: usize,
    /// Simplification levels (the hierarchy has one more level: the input's).
    pub levels: usize,
    /// Feature vertices kept through every level.
    pub feature_vertices_kept: usize,
    /// The base domain's two-sided Hausdorff distance to the input, a share of the input's
    /// bounding-box diagonal: sampled as CGAL samples by default (each side's vertices, and
    /// as many points on its faces, area-weighted, and on its edges, length-weighted) in the
    /// input's unit frame, distances by CGAL's AABB trees over pieces of the other side
    /// (`hausdorff_in_pieces`), so its memory does not grow with the input.
    pub hausdorff: f64,
    /// Smallest angle of the base domain's triangles, degrees.
    pub min_angle_deg: f64,
    /// Share of the base domain's triangles with an angle under 5°.
    pub sliver_share: f64,
    /// The vertex target: whether it was reached, what gave way, what stopped the build.
    pub target: TargetReport,
    /// What gave way to reach the target, in words ("nothing" when nothing did).
    pub gave_way: String,
    /// Seconds of the build.
    pub seconds: f64,
    /// Seconds by stage.
    pub stage_seconds: BuildStages,
}

impl BuildReport {
    /// Measures `hierarchy`, built from `input`, and its base domain `base`.
    ///
    /// # Errors
    /// CGAL's errors from the Hausdorff distance.
    pub fn of(input: &Mesh, hierarchy: &Hierarchy, base: &Mesh) -> Result<Self> {
        Self::of_faces(&input.positions, &input.triangles, hierarchy, base)
    }

    /// As [`BuildReport::of`], for an input given by its positions and faces (a
    /// partitioned build's, which its hierarchy holds).
    ///
    /// # Errors
    /// CGAL's errors from the Hausdorff distance.
    pub fn of_faces(positions: &[DVec3], triangles: &[[u32; 3]], hierarchy: &Hierarchy, base: &Mesh) -> Result<Self> {
        let shape = ShapeReport::of(base);
        Ok(BuildReport {
            input_vertices: positions.len(),
            input_faces: triangles.len(),
            output_vertices: base.vertex_count(),
            output_faces: base.face_count(),
            levels: hierarchy.steps(),
            feature_vertices_kept: hierarchy.feature_vertices,
            hausdorff: relative_hausdorff_in_pieces(positions, triangles, base)?,
            min_angle_deg: shape.min_angle_deg,
            sliver_share: shape.sliver_share,
            target: hierarchy.target.clone(),
            gave_way: hierarchy.target.gave_way(),
            seconds: hierarchy.seconds,
            stage_seconds: hierarchy.stages,
        })
    }

    /// The one-line summary (`simplify`'s line after its name).
    pub fn line(&self) -> String {
        format!(
            "{} tris => {} tris, {} levels, {} feature vertices kept (hausdorff {:.3}%, min angle {:.2}°, slivers {:.2}%)",
            self.input_faces,
            self.output_faces,
            self.levels,
            self.feature_vertices_kept,
            self.hausdorff * 100.0,
            self.min_angle_deg,
            self.sliver_share * 100.0,
        )
    }

    /// The lines a user must see about the target (none when it was met without giving
    /// anything way): what gave way, and a `note:` when it was not reached.
    pub fn target_lines(&self) -> Vec<String> {
        let target = &self.target;
        let Some(asked) = target.target_vertices else { return Vec::new() };
        let vertices = self.output_vertices;
        let mut lines = Vec::new();
        if self.gave_way != "nothing" {
            lines.push(format!("target: {asked} vertices asked, {vertices} reached; gave way: {}", self.gave_way));
        }
        if !target.reached {
            lines.push(format!(
                "note: the target of {asked} vertices was not reached ({vertices} vertices; the topology allows {}): stopped by {}",
                target.floor_vertices,
                target.stopped_by.as_deref().unwrap_or("nothing left to remove")
            ));
        }
        lines
    }
}
