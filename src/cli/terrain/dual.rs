//! `--method dual`: Janeczek's dual midpoint displacement over a 3D quadrilateral.

use std::time::Instant;

use super::Job;
use crate::error::{Error, Result};
use crate::io::{self, WriteOptions};
use crate::request::Spelling;
use crate::terrain::{dual_mesh, dual_midpoint_displacement};

/// Janeczek's dual method: a quad surface written as a mesh with normals and a height ramp.
pub(super) fn run(job: &Job, start: Instant, ctx: crate::cli::Context) -> Result<()> {
    let g = job.generation;
    g.check_modes(&job.target(), Spelling::Flag)?;
    let format = io::Format::from_path(&job.output)?;
    if !matches!(format, io::Format::Ply | io::Format::Obj) {
        return Err(Error::InvalidInput(format!("{}: --method dual writes .ply or .obj", job.output.display())));
    }
    let params = g.dual_params(Spelling::Flag)?;
    let palette = g.colors.unwrap_or_default();
    if let Some(dir) = &g.steps {
        crate::io::create_output_dir(dir)?;
    }
    let mut step_error = None;
    let surface = dual_midpoint_displacement(&params, |level, surface| {
        if let (Some(dir), None) = (&g.steps, &step_error) {
            let path = dir.join(format!("level-{level:02}.ply"));
            if let Err(e) = io::write(&dual_mesh(surface, &params, &palette), &path, WriteOptions::default()) {
                step_error = Some(e);
            }
        }
    })?;
    if let Some(e) = step_error {
        return Err(e);
    }
    let mesh = dual_mesh(&surface, &params, &palette);
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
