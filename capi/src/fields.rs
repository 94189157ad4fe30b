//! Fields over points and meshes for C++: terrain meshes, noise at given points, surface
//! analysis. Each takes the library's request (`TerrainRequest`, `NoiseRequest`,
//! `AnalysisRequest`), read from the C++ options struct's fields as a JSON object (#38), so
//! every parameter means what the command line's flag means, with the same checks and
//! messages, each naming the option as C++ spells it (`option .tile_size`).

use asperity::analysis::AnalysisRequest;
use asperity::noise::NoiseRequest;
use asperity::request::{Spelling, from_fields};
use asperity::terrain::TerrainRequest;
use asperity::{Error, Result};
use glam::DVec3;

use crate::arrays::{analysis_arrays, arrays_of, flat, mesh_of};
use crate::bridge::{Analysis, Report, TerrainMesh};
use crate::guarded;

pub fn terrain_mesh(fields: &str) -> Result<TerrainMesh, String> {
    guarded(|| {
        let start = std::time::Instant::now();
        let (request, tile) = TerrainRequest::from_fields(fields, Spelling::Member)?;
        let mesh = request.mesh(tile, Spelling::Member)?;
        let report = Report {
            input_vertices: 0,
            output_vertices: mesh.vertex_count(),
            levels: 0,
            seconds: start.elapsed().as_secs_f64(),
        };
        Ok(TerrainMesh {
            normals: mesh.normals.as_deref().map(flat).unwrap_or_default(),
            colors: mesh.colors.as_deref().map(|c| c.iter().flatten().copied().collect()).unwrap_or_default(),
            mesh: arrays_of(&mesh),
            report,
        })
    })
}

pub fn noise(points: &[f64], dimension: usize, fields: &str) -> Result<Vec<f64>, String> {
    guarded(|| {
        if !(dimension == 2 || dimension == 3) || !points.len().is_multiple_of(dimension) {
            return Err(Error::InvalidInput(format!(
                "{} coordinates are not points of dimension {dimension} (use 2 or 3)",
                points.len()
            )));
        }
        if let Some(k) = points.iter().position(|c| !c.is_finite()) {
            return Err(Error::InvalidInput(format!("point {}: a coordinate is not finite", k / dimension)));
        }
        let request: NoiseRequest = from_fields(fields, Spelling::Member)?;
        let points: Vec<DVec3> = match dimension {
            2 => points.chunks_exact(2).map(|p| DVec3::new(p[0], p[1], 0.0)).collect(),
            _ => points.chunks_exact(3).map(|p| DVec3::new(p[0], p[1], p[2])).collect(),
        };
        request.values_at(&points, dimension == 2, Spelling::Member)
    })
}

pub fn analyze(positions: &[f64], triangles: &[u32], fields: &str) -> Result<Analysis, String> {
    guarded(|| {
        let request: AnalysisRequest = from_fields(fields, Spelling::Member)?;
        Ok(analysis_arrays(&request.analyze(&mesh_of(positions, triangles)?, Spelling::Member)?))
    })
}
