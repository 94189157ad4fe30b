//! `--method dual`: Janeczek's dual midpoint displacement over a 3D quadrilateral.

use std::time::Instant;

use super::{Generation, Job, hurst_of};
use crate::analysis::{FaceGeometry, NormalWeighting, vertex_normals};
use crate::error::{Error, Result};
use crate::io::{self, WriteOptions};
use crate::mesh::Adjacency;
use crate::terrain::{DualParams, QuadSurface, dual_midpoint_displacement, ramp_color};

/// The dual method's parameters from the flags.
fn params_of(g: &Generation) -> Result<DualParams> {
    Ok(DualParams {
        x: g.x.unwrap_or([1.0, 0.0, 0.0]).into(),
        y: g.y.unwrap_or([0.0, 1.0, 0.0]).into(),
        hurst: hurst_of(g, 1.5)?,
        levels: g.levels.unwrap_or(9),
        scale: g.sigma,
        seed: g.seed,
        deterministic: g.deterministic,
        cross_product: g.cross_product,
        mean_correction: !g.no_mean_correction,
    })
}

/// The dual method's final surface as the command writes it (normals, height colours).
pub(super) fn mesh_of(job: &Job) -> Result<crate::mesh::Mesh> {
    super::rules::refuse_other_modes_flags(job)?;
    let params = params_of(job.generation)?;
    let surface = dual_midpoint_displacement(&params, |_, _| {})?;
    Ok(dual_mesh(&surface, &params, job.generation))
}

/// Janeczek's dual method: a quad surface written as a mesh with normals and a height ramp.
pub(super) fn run(job: &Job, start: Instant, ctx: crate::cli::Context) -> Result<()> {
    super::rules::refuse_other_modes_flags(job)?;
    let g = job.generation;
    let format = io::Format::from_path(&job.output)?;
    if !matches!(format, io::Format::Ply | io::Format::Obj) {
        return Err(Error::InvalidInput(format!("{}: --method dual writes .ply or .obj", job.output.display())));
    }
    let params = params_of(g)?;
    if let Some(dir) = &g.steps {
        crate::io::create_output_dir(dir)?;
    }
    let mut step_error = None;
    let surface = dual_midpoint_displacement(&params, |level, surface| {
        if let (Some(dir), None) = (&g.steps, &step_error) {
            let path = dir.join(format!("level-{level:02}.ply"));
            if let Err(e) = io::write(&dual_mesh(surface, &params, g), &path, WriteOptions::default()) {
                step_error = Some(e);
            }
        }
    })?;
    if let Some(e) = step_error {
        return Err(e);
    }
    let mesh = dual_mesh(&surface, &params, g);
    io::write(&mesh, &job.output, WriteOptions::default())?;
    if let Some(preview) = &job.preview {
        crate::cli::require_extension(preview, &["png"])?;
        let up = crate::render::UpAxis::Z;
        let options = crate::render::RenderOptions { up, ..Default::default() };
        crate::render::render(&mesh, &options)?.write_png(preview)?;
    }
    ctx.report(
        || {
            format!(
                "terrain: dual {}x{} (H {}, {} divisions, seed {}) => {} in {} ms",
                surface.m,
                surface.n,
                params.hurst,
                params.levels,
                params.seed,
                job.output.display(),
                crate::cli::millis(start)
            )
        },
        || {
            serde_json::json!({
                "method": "dual", "output": job.output, "preview": job.preview, "columns": surface.m,
                "rows": surface.n, "hurst": params.hurst, "levels": params.levels, "seed": params.seed,
                "seconds": start.elapsed().as_secs_f64(),
            })
        },
    );
    Ok(())
}

/// The quad surface as a mesh with angle-weighted normals and colours by height along the
/// quad's normal (the surface's own range).
fn dual_mesh(surface: &QuadSurface, params: &DualParams, g: &Generation) -> crate::mesh::Mesh {
    let mut m = surface.to_mesh();
    let adjacency = Adjacency::of(&m);
    m.normals = Some(vertex_normals(&m, &adjacency, &FaceGeometry::of(&m), NormalWeighting::Angle));
    let z = params.x.cross(params.y).normalize();
    let heights: Vec<f64> = m.positions.iter().map(|p| p.dot(z)).collect();
    let (lo, hi) = heights.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &h| (a.min(h), b.max(h)));
    let palette = g.colors.unwrap_or_default();
    m.colors = Some(heights.iter().map(|h| ramp_color(&palette, (h - lo) / (hi - lo).max(1e-12), false)).collect());
    m
}
