//! Fields over points and meshes for C++: terrain meshes, noise at given points, surface
//! analysis. Noise takes the library's request (`NoiseRequest`, read from the C++ options
//! struct's fields); terrain still takes `asperity terrain`'s flags (the C++ options struct
//! turned into them, #38), so every parameter means what the command line's flag means,
//! with the same checks and messages.

use asperity::analysis::AnalysisRequest;
use asperity::cli::{self, parse_flags};
use asperity::noise::NoiseRequest;
use asperity::request::{Spelling, from_fields};
use asperity::{Error, Result};
use glam::DVec3;

use crate::arrays::{analysis_arrays, arrays_of, flat, mesh_of};
use crate::bridge::{Analysis, Report, TerrainMesh};
use crate::guarded;

/// How the C++ options structs spell a flag: `.size` for `--size`.
fn member(name: &str) -> String {
    format!("option .{name}")
}

// cxx passes a C++ `rust::Vec<rust::String>` as `&Vec<String>`.
#[allow(clippy::ptr_arg)]
pub fn terrain_mesh(flags: &Vec<String>) -> Result<TerrainMesh, String> {
    guarded(|| {
        let start = std::time::Instant::now();
        let args: cli::terrain::TerrainArgs =
            parse_flags("terrain", &["-o", "<mesh>.ply"], flags.clone(), &["--range", "--preset"], member)?;
        let mesh = cli::terrain::mesh_of(&args)?;
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
