//! `asperity render IN -o OUT.png`: a picture of a mesh from the software rasteriser.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use serde_json::json;

use super::Context;
use crate::error::{Error, Result};
use crate::render::{ColorSource, Mode, RenderOptions, UpAxis, render};

/// Camera and picture settings shared by `render` and the commands with `--preview`.
#[derive(Debug, Clone, Args)]
pub struct ViewArgs {
    /// Picture size W,H in pixels.
    #[arg(long, value_parser = super::parse::size, default_value = "1024,768")]
    pub size: (usize, usize),
    /// Faces (shaded), wireframe (hidden lines removed) or points.
    #[arg(long, value_enum, default_value_t = Mode::Faces)]
    pub mode: Mode,
    /// Camera angle around the up axis, degrees.
    #[arg(long, default_value_t = 35.0, allow_hyphen_values = true)]
    pub yaw: f64,
    /// Camera angle above the horizon, degrees.
    #[arg(long, default_value_t = 25.0, allow_hyphen_values = true)]
    pub pitch: f64,
    /// The axis that points up in the picture.
    #[arg(long, value_enum, default_value_t = UpAxis::Z)]
    pub up: UpAxis,
    /// Colours: attribute (vertex colours), height, none, or scalar:NAME (a PLY property).
    #[arg(long, value_parser = super::parse::color_source, default_value = "attribute")]
    pub colors: ColorSource,
    /// Background: transparent or #rrggbb.
    #[arg(long, value_parser = super::parse::background, default_value = "#ffffff")]
    pub background: super::parse::Background,
    /// Samples per pixel along each axis (1 to 4).
    #[arg(long, default_value_t = 2)]
    pub samples: usize,
    /// Faces further apart than this angle do not share normals (degrees; 180 smooths all;
    /// faces mode) [default: 40].
    #[arg(long, allow_negative_numbers = true)]
    pub crease: Option<f64>,
    /// Draw the edges over shaded faces (faces mode).
    #[arg(long)]
    pub edges: bool,
}

impl ViewArgs {
    /// The rasteriser's options.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for `--crease` or `--edges` outside faces mode, where
    /// nothing is shaded and the faces' edges are all the picture has or nothing.
    pub fn options(&self) -> Result<RenderOptions> {
        if self.mode != Mode::Faces {
            let mode = format!("{:?}", self.mode).to_lowercase();
            if self.crease.is_some() {
                return Err(Error::InvalidInput(format!(
                    "--crease applies only to --mode faces (shading), not {mode}"
                )));
            }
            if self.edges {
                return Err(Error::InvalidInput(format!("--edges applies only to --mode faces, not {mode}")));
            }
        }
        Ok(RenderOptions {
            width: self.size.0,
            height: self.size.1,
            mode: self.mode,
            yaw_deg: self.yaw,
            pitch_deg: self.pitch,
            up: self.up,
            colors: self.colors.clone(),
            background: self.background.0,
            samples: self.samples,
            crease_deg: self.crease.unwrap_or(40.0),
            edges: self.edges,
            water: None,
            texture: None,
        })
    }
}

/// The subcommand's flags (`RenderArgs`).
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// Input mesh (.obj, .ply, .off, .stl, .glb, .gltf).
    input: PathBuf,
    /// Output picture (.png).
    #[arg(short, long)]
    output: PathBuf,
    #[command(flatten)]
    view: ViewArgs,
    /// Draw water at this height along the up axis (mesh units) over the mesh's extent: a
    /// Fresnel mix of sky and what lies below (faces mode).
    #[arg(long, allow_negative_numbers = true)]
    water_level: Option<f64>,
    /// How far one sees into the water, as a fraction of the bounding-box diagonal
    /// (with --water-level) [default: 0.02].
    #[arg(long)]
    water_clarity: Option<f64>,
    /// Draw the mesh with this texture (PNG) at its UVs (faces mode; the mesh needs texture
    /// coordinates: OBJ vt, PLY s t, glTF TEXCOORD_0). Replaces --colors.
    #[arg(long)]
    texture: Option<PathBuf>,
    #[command(flatten)]
    repair: super::input::RepairArg,
}

impl RenderArgs {
    /// The library options the flags give.
    ///
    /// # Errors
    /// Invalid flags; `--water-clarity` without `--water-level`.
    pub fn options(&self) -> Result<crate::render::RenderOptions> {
        let mut options = self.view.options()?;
        if self.water_clarity.is_some() && self.water_level.is_none() {
            return Err(Error::InvalidInput("--water-clarity applies only with --water-level".into()));
        }
        options.water = self
            .water_level
            .map(|level| crate::render::WaterView { level, clarity: self.water_clarity.unwrap_or(0.02) });
        if let Some(path) = &self.texture {
            if self.view.mode != Mode::Faces {
                let mode = format!("{:?}", self.view.mode).to_lowercase();
                return Err(Error::InvalidInput(format!("--texture applies only to --mode faces, not {mode}")));
            }
            if self.view.colors != ColorSource::Attribute {
                return Err(Error::InvalidInput("--texture gives the colours: --colors cannot be used with it".into()));
            }
            options.texture = Some(std::sync::Arc::new(crate::render::texture::Texture::read_png(path)?));
        }
        Ok(options)
    }

    /// Whether `--repair` was given.
    pub fn repair(&self) -> bool {
        self.repair.repair
    }
}

/// Runs the subcommand.
pub fn run(args: RenderArgs, ctx: Context) -> Result<()> {
    let start = Instant::now();
    super::require_extension(&args.output, &["png"])?;
    let options = args.options()?;
    let input = super::input::read_input(&args.input, args.repair, ctx)?;
    let mesh = &input.read.mesh;
    let picture = ctx.spin("render", &args.input.display().to_string(), || render(mesh, &options))?;
    picture.write_png(&args.output)?;
    ctx.report(
        || {
            format!(
                "render: {} ({} tris, {}) => {} {}x{} in {} ms",
                args.input.display(),
                mesh.face_count(),
                format!("{:?}", options.mode).to_lowercase(),
                args.output.display(),
                picture.width,
                picture.height,
                super::millis(start)
            )
        },
        || {
            json!({
                "input": args.input, "output": args.output, "triangles": mesh.face_count(),
                "width": picture.width, "height": picture.height, "mode": options.mode, "repair": input.repair_json(),
                "seconds": start.elapsed().as_secs_f64(),
            })
        },
    );
    Ok(())
}
