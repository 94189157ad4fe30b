//! Flags of one mode refused in another, with the mode they belong to in the message.

use clap::ValueEnum;

use super::{ErodeArg, Job, MethodArg};
use crate::error::{Error, Result};

/// Every flag another mode would use is refused where it would be ignored, with the mode
/// it belongs to in the message: dual's quadrilateral flags with the heightfield methods,
/// the grid's flags with dual, `--band` without `--stream`, `--range` without a 16-bit
/// output, colours without a coloured output.
pub(super) fn refuse_other_modes_flags(job: &Job) -> Result<()> {
    let g = job.generation;
    let dual = g.method == MethodArg::Dual;
    let method = g.method.to_possible_value().map_or_else(String::new, |v| v.get_name().to_string());
    let ext = job.extension();
    let mesh_output = matches!(ext.as_str(), "ply" | "obj");
    let sixteen_bit = matches!(ext.as_str(), "png" | "raw16" | "raw" | "r16");
    let coloured = mesh_output || job.preview.is_some();
    let heightfield = "--method classic and smooth";
    let hydraulic = g.erode.contains(&ErodeArg::Hydraulic);
    let rules: [(&str, bool, bool, &str); 39] = [
        ("--iterations", g.iterations.is_some(), !dual, heightfield),
        (
            "--max-height",
            g.max_height.is_some(),
            !dual && !job.stream && job.tile.is_none(),
            "whole grids of --method classic and smooth (the highest peak is measured on the whole grid: not with --stream or --tile)",
        ),
        (
            "--roughness",
            g.roughness.is_some(),
            g.method != MethodArg::Smooth,
            "--method classic and dual (smooth's points are uniform within their parents' range)",
        ),
        ("--x", g.x.is_some(), dual, "--method dual"),
        ("--y", g.y.is_some(), dual, "--method dual"),
        ("--levels", g.levels.is_some(), dual, "--method dual"),
        ("--deterministic", g.deterministic, dual, "--method dual"),
        ("--cross-product", g.cross_product, dual, "--method dual"),
        ("--no-mean-correction", g.no_mean_correction, dual, "--method dual"),
        ("--steps", g.steps.is_some(), dual, "--method dual"),
        ("--size", g.size.is_some(), !dual, heightfield),
        ("--distribution", g.distribution.is_some(), !dual, heightfield),
        ("--mean", g.mean.is_some(), !dual, heightfield),
        ("--variance", g.variance.is_some(), !dual, heightfield),
        ("--corners", g.corners.is_some(), !dual, heightfield),
        ("--width", g.width.is_some(), !dual, heightfield),
        ("--depth", g.depth.is_some(), !dual, heightfield),
        ("--sea-level", g.sea_level.is_some(), !dual, heightfield),
        ("--grid", g.grid.is_some(), !dual, heightfield),
        ("--stream", job.stream, !dual, heightfield),
        ("--tile", job.tile.is_some(), !dual, heightfield),
        ("--applet", g.applet, g.method == MethodArg::Classic, "--method classic (seed 001's applet)"),
        (
            "--hurst",
            g.hurst.is_some(),
            g.method != MethodArg::Smooth,
            "--method classic and dual (smooth's points are uniform within their parents' range)",
        ),
        ("--band", job.band.is_some(), job.stream, "--stream"),
        ("--erode", !g.erode.is_empty(), !dual, heightfield),
        ("--erode-iterations", g.erode_iterations.is_some(), !g.erode.is_empty(), "--erode"),
        ("--talus", g.talus.is_some(), g.erode.contains(&ErodeArg::Thermal), "--erode thermal"),
        ("--rain", g.rain.is_some(), hydraulic, "--erode hydraulic"),
        ("--evaporation", g.evaporation.is_some(), hydraulic, "--erode hydraulic"),
        ("--capacity", g.capacity.is_some(), hydraulic, "--erode hydraulic"),
        ("--dissolving", g.dissolving.is_some(), hydraulic, "--erode hydraulic"),
        ("--deposition", g.deposition.is_some(), hydraulic, "--erode hydraulic"),
        ("--time-step", g.time_step.is_some(), hydraulic, "--erode hydraulic"),
        ("--layers", !g.layers.is_empty(), hydraulic, "--erode hydraulic"),
        ("--preset", g.preset.is_some(), !dual, heightfield),
        (
            "--sidecar",
            job.sidecar,
            !dual && !mesh_output,
            "heightmap outputs (.png, .raw16, .f32, .exr, .tif) of --method classic and smooth",
        ),
        ("--tile-size", job.tile_size.is_some(), job.tile.is_some(), "--tile"),
        (
            "--range",
            g.range.is_some(),
            !dual && sixteen_bit,
            "16-bit outputs (.png, .raw16) of --method classic and smooth",
        ),
        (
            "--peak-height",
            g.peak_height.is_some(),
            !dual && coloured,
            "coloured outputs (a .ply or .obj mesh, or --preview) of --method classic and smooth",
        ),
    ];
    match rules.iter().find(|&&(_, given, applies, _)| given && !applies) {
        Some((flag, _, _, belongs)) => Err(Error::InvalidInput(format!(
            "{flag} applies only to {belongs}: with --method {method} and this output it would be ignored"
        ))),
        None => match (g.colors.is_some(), coloured) {
            (true, false) => Err(Error::InvalidInput(
                "--colors applies only to coloured outputs (a .ply or .obj mesh, or --preview)".into(),
            )),
            _ => Ok(()),
        },
    }
}
