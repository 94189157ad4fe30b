//! Pictures of meshes without a GPU: a software rasteriser with shaded faces (two-sided
//! lighting, creased normals, vertex colours), hidden-line wireframe and point views — the
//! three views of seed 001 — and a camera fitted to the bounding box. Pictures are
//! supersampled and the same at any thread count.

mod camera;
pub mod hillshade;
mod raster;
mod request;
mod shade;
pub mod texture;
pub mod water;

use std::path::Path;

use glam::{DVec3, Vec3};
use rayon::prelude::*;

pub use camera::{Camera, UpAxis};
use raster::{Fill, Frame, Segment, Triangle};
pub use request::{Background, RenderRequest};
pub use shade::{CLAY, ramp};
use shade::{Lighting, corner_normals, face_normals, ramp_colors};

use crate::error::{Error, Result};
use crate::mesh::Mesh;

/// What is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum Mode {
    /// Shaded faces.
    #[default]
    Faces,
    /// Edges, with hidden lines removed.
    Wireframe,
    /// Vertices as dots.
    Points,
}

/// Where surface colours come from.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub enum ColorSource {
    /// The mesh's vertex colours (clay where it has none).
    #[default]
    Attribute,
    /// A ramp over the coordinate along the up axis.
    Height,
    /// A ramp over the named per-vertex scalar (a PLY property such as `mean_curvature`).
    Scalar(String),
    /// Clay everywhere.
    None,
}

/// Options of [`render`].
#[derive(Debug, Clone)]
pub struct RenderOptions {
    /// Picture size in pixels.
    pub width: usize,
    /// Picture height in pixels.
    pub height: usize,
    /// What is drawn.
    pub mode: Mode,
    /// Camera angle around the up axis, degrees.
    pub yaw_deg: f64,
    /// Camera angle above the horizon, degrees.
    pub pitch_deg: f64,
    /// The world axis that points up in the picture.
    pub up: UpAxis,
    /// Surface colours.
    pub colors: ColorSource,
    /// Background colour; `None` is transparent.
    pub background: Option<[u8; 3]>,
    /// Samples per pixel along each axis (1 to 4).
    pub samples: usize,
    /// Neighbouring faces further apart than this angle do not share normals (degrees).
    pub crease_deg: f64,
    /// Also draw the edges over shaded faces.
    pub edges: bool,
    /// A water plane drawn over the mesh (faces mode).
    pub water: Option<WaterView>,
    /// A texture drawn with the mesh's UVs (faces mode; the surface colours are then white).
    pub texture: Option<std::sync::Arc<texture::Texture>>,
}

/// A water plane of the picture: perpendicular to the up axis at `level` over the mesh's
/// extent, drawn as a Fresnel mix of sky and what lies below ([`water::fresnel`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WaterView {
    /// Height along the up axis, in the mesh's units.
    pub level: f64,
    /// Depth (along the view ray) over which the water's colour covers 1 − 1/e of what
    /// lies below, as a fraction of the mesh's bounding-box diagonal.
    pub clarity: f64,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            width: 1024,
            height: 768,
            mode: Mode::Faces,
            yaw_deg: 35.0,
            pitch_deg: 25.0,
            up: UpAxis::Z,
            colors: ColorSource::Attribute,
            background: Some([255, 255, 255]),
            samples: 2,
            crease_deg: 40.0,
            edges: false,
            water: None,
            texture: None,
        }
    }
}

/// An 8-bit RGBA picture, rows top to bottom.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Picture {
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// RGBA bytes, row-major.
    pub rgba: Vec<u8>,
}

impl Picture {
    /// The RGBA of pixel (x, y).
    pub fn pixel(&self, x: usize, y: usize) -> [u8; 4] {
        let i = 4 * (y * self.width + x);
        [self.rgba[i], self.rgba[i + 1], self.rgba[i + 2], self.rgba[i + 3]]
    }

    /// Pictures of the same height placed left to right, separated by `gap` pixels of
    /// `background`.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for no pictures or pictures of different heights.
    pub fn side_by_side(pictures: &[Picture], gap: usize, background: [u8; 3]) -> Result<Picture> {
        let height = pictures.first().map(|p| p.height).ok_or_else(|| Error::InvalidInput("no pictures".into()))?;
        if pictures.iter().any(|p| p.height != height) {
            return Err(Error::InvalidInput("side-by-side pictures need the same height".into()));
        }
        let width = pictures.iter().map(|p| p.width).sum::<usize>() + gap * (pictures.len() - 1);
        let fill = [background[0], background[1], background[2], 255];
        let mut rgba: Vec<u8> = fill.iter().copied().cycle().take(width * height * 4).collect();
        let mut x0 = 0;
        for p in pictures {
            for y in 0..height {
                let row = &p.rgba[4 * y * p.width..4 * (y + 1) * p.width];
                rgba[4 * (y * width + x0)..4 * (y * width + x0 + p.width)].copy_from_slice(row);
            }
            x0 += p.width + gap;
        }
        Ok(Picture { width, height, rgba })
    }

    /// A picture of a scalar grid (row-major, `width` per row) in grey, `range` black to
    /// white.
    pub fn grey(values: &[f64], width: usize, range: (f64, f64)) -> Picture {
        let span = (range.1 - range.0).max(1e-300);
        let rgba = values
            .iter()
            .flat_map(|v| {
                let g = (((v - range.0) / span).clamp(0.0, 1.0) * 255.0).round() as u8;
                [g, g, g, 255]
            })
            .collect();
        Picture { width, height: values.len() / width.max(1), rgba }
    }

    /// Writes the picture as an RGBA PNG, atomically.
    ///
    /// # Errors
    /// [`Error::Io`] naming the file.
    pub fn write_png(&self, path: &Path) -> Result<()> {
        crate::io::image::write_png_rgba8(path, &self.rgba, self.width)
    }
}

impl WaterView {
    /// A point on the plane, in the mesh's coordinates.
    fn up_point(&self, up: UpAxis) -> DVec3 {
        up.vector() * self.level
    }
}

/// The largest picture side.
pub const MAX_SIDE: usize = 16384;

/// Renders `mesh`.
///
/// # Errors
/// [`Error::InvalidInput`] for a picture size or sample count out of range, a mesh with
/// nothing to draw (no faces, or no vertices in point mode), non-finite coordinates, or an
/// unknown scalar property.
pub fn render(mesh: &Mesh, options: &RenderOptions) -> Result<Picture> {
    check(mesh, options)?;
    // Drawn in the mesh's unit frame (a uniform scale and a shift: the picture is the
    // same), so single-precision projection works whatever the model's units.
    let unit = crate::mesh::UnitFrame::of(mesh)?;
    let unit_mesh = unit.apply(mesh);
    let mesh = &unit_mesh;
    let s = options.samples;
    let (w, h) = (options.width * s, options.height * s);
    let bbox = mesh.bounding_box().ok_or_else(|| Error::InvalidInput("the mesh has no vertices".into()))?;
    let first = Camera::fit(bbox, options.up, options.yaw_deg, options.pitch_deg, w, h);
    let camera = first.framed(&mesh.positions.par_iter().map(|&p| first.project(p)).collect::<Vec<_>>(), w, h);
    let projected: Vec<Option<Vec3>> = mesh.positions.par_iter().map(|&p| camera.project(p)).collect();
    let base = match options.texture {
        Some(_) => vec![Vec3::ONE; mesh.vertex_count()],
        None => base_colors(mesh, &options.colors, options.up)?,
    };
    let mut frame = Frame::new(w, h);
    let lighting = Lighting::default();
    match options.mode {
        Mode::Faces => {
            let mut triangles = shaded_triangles(mesh, &camera, &projected, &base, &lighting, options);
            match (&options.texture, &mesh.uvs) {
                (Some(texture), Some(uvs)) => {
                    for (f, t) in triangles.iter_mut().enumerate() {
                        if let Some(t) = t {
                            t.uvs = Some([0, 1, 2].map(|k| glam::DVec2::from(uvs.at(f, k)).as_vec2()));
                        }
                    }
                    frame.textured_triangles(&triangles, texture);
                }
                _ => frame.triangles(&triangles, Fill::Shaded),
            }
            if options.edges {
                frame.segments(&edge_segments(mesh, &projected, |_| Vec3::splat(0.08)), 2e-3);
            }
            if let Some(view) = options.water {
                let level = unit.to_unit(view.up_point(options.up)).dot(options.up.vector());
                water::blend(&mut frame, &camera, bbox, options.up, level, view.clarity);
            }
        }
        Mode::Wireframe => {
            frame.triangles(&silhouettes(mesh, &projected), Fill::DepthOnly);
            let dark = |v: usize| base[v] * 0.45;
            frame.segments(&edge_segments(mesh, &projected, dark), 2e-3);
        }
        Mode::Points => {
            let normals = corner_normals(mesh, &face_normals(mesh), 180.0);
            let mut vertex_normal = vec![Vec3::ZERO; mesh.vertex_count()];
            for (t, n) in mesh.triangles.iter().zip(&normals) {
                for k in 0..3 {
                    vertex_normal[t[k] as usize] = n[k];
                }
            }
            let dots: Vec<(Vec3, Vec3)> = (0..mesh.vertex_count())
                .filter_map(|v| {
                    let p = projected[v]?;
                    let n = Lighting::facing(&camera, mesh.positions[v], vertex_normal[v]);
                    Some((p, lighting.shade(base[v], n)))
                })
                .collect();
            frame.triangles(&silhouettes(mesh, &projected), Fill::DepthOnly);
            // Sparse point sets get bigger dots (a quarter of the spacing, 1 to 3 pixels).
            let spacing = ((w * h) as f32 / (s * s * dots.len().max(1)) as f32).sqrt();
            frame.dots(&dots, (0.25 * spacing).clamp(1.0, 3.0) * s as f32 * 0.9, 5e-3);
        }
    }
    if !frame.covered.iter().any(|&c| c) {
        return Err(Error::InvalidInput(
            "nothing to draw: no face or point of the mesh covers a pixel (its faces have no area, or it has no extent)"
                .into(),
        ));
    }
    Ok(resolve(&frame, s, options.background))
}

fn check(mesh: &Mesh, options: &RenderOptions) -> Result<()> {
    if !(1..=MAX_SIDE).contains(&options.width) || !(1..=MAX_SIDE).contains(&options.height) {
        return Err(Error::InvalidInput(format!(
            "picture size {}x{} is outside 1..={MAX_SIDE}",
            options.width, options.height
        )));
    }
    if !(1..=4).contains(&options.samples) {
        return Err(Error::InvalidInput(format!("{} samples per pixel: use 1 to 4", options.samples)));
    }
    // The frame holds colour, depth and coverage per sample (17 bytes), the picture and its
    // PNG encoding 4 bytes a pixel each: refused before allocating where the machine has
    // not that much (#36: 16384x16384 at 2 samples aborted on 12.9 GB).
    let pixels = (options.width * options.height) as u64;
    let samples = pixels * (options.samples * options.samples) as u64;
    crate::memory::ensure_available(
        samples * 17 + pixels * 8,
        &format!("a {}x{} picture at {} samples", options.width, options.height, options.samples),
        "render a smaller picture (--size) or fewer samples (--samples)",
    )?;
    if let Some(w) = options.water {
        if options.mode != Mode::Faces {
            return Err(Error::InvalidInput("a water plane is drawn only in faces mode".into()));
        }
        if !(w.level.is_finite() && w.clarity.is_finite() && w.clarity > 0.0) {
            return Err(Error::InvalidInput("the water level must be finite and its clarity positive".into()));
        }
    }
    if options.texture.is_some() {
        if options.mode != Mode::Faces {
            return Err(Error::InvalidInput("a texture is drawn only in faces mode".into()));
        }
        if mesh.uvs.is_none() {
            return Err(Error::InvalidInput(
                "the mesh has no texture coordinates to draw a texture with (OBJ vt, PLY s t, glTF TEXCOORD_0)".into(),
            ));
        }
    }
    if !options.yaw_deg.is_finite() || !options.pitch_deg.is_finite() {
        return Err(Error::InvalidInput("camera angles must be finite".into()));
    }
    if options.mode != Mode::Points && mesh.triangles.is_empty() {
        return Err(Error::InvalidInput("the mesh has no faces to draw (try --mode points)".into()));
    }
    mesh.check()
}

/// Per-vertex base colours (linear 0..1).
fn base_colors(mesh: &Mesh, source: &ColorSource, up: UpAxis) -> Result<Vec<Vec3>> {
    Ok(match source {
        ColorSource::Attribute => match &mesh.colors {
            Some(colors) => colors.iter().map(|c| Vec3::from(c.map(|x| x as f32 / 255.0))).collect(),
            None => vec![CLAY; mesh.vertex_count()],
        },
        ColorSource::None => vec![CLAY; mesh.vertex_count()],
        ColorSource::Height => {
            let axis = up.vector();
            let heights: Vec<f64> = mesh.positions.iter().map(|p| p.dot(axis)).collect();
            let (lo, hi) = heights.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &h| (a.min(h), b.max(h)));
            heights.iter().map(|h| ramp((h - lo) / (hi - lo).max(1e-300))).collect()
        }
        ColorSource::Scalar(name) => match mesh.scalars.get(name) {
            Some(values) => ramp_colors(values),
            None => {
                let known: Vec<&str> = mesh.scalars.keys().map(String::as_str).collect();
                return Err(Error::InvalidInput(format!(
                    "the mesh has no scalar property `{name}` (it has: {})",
                    if known.is_empty() { "none".to_string() } else { known.join(", ") }
                )));
            }
        },
    })
}

fn triangle_at(t: &[u32; 3], projected: &[Option<Vec3>], colors: [Vec3; 3]) -> Option<Triangle> {
    let corners = [projected[t[0] as usize]?, projected[t[1] as usize]?, projected[t[2] as usize]?];
    Some(Triangle { corners, colors, uvs: None })
}

/// The triangles as occluders only (hidden-line and hidden-point removal).
fn silhouettes(mesh: &Mesh, projected: &[Option<Vec3>]) -> Vec<Option<Triangle>> {
    mesh.triangles.par_iter().map(|t| triangle_at(t, projected, [Vec3::ZERO; 3])).collect()
}

/// Lit corner colours per triangle, normals turned towards the eye (two-sided lighting).
fn shaded_triangles(
    mesh: &Mesh,
    camera: &Camera,
    projected: &[Option<Vec3>],
    base: &[Vec3],
    lighting: &Lighting,
    options: &RenderOptions,
) -> Vec<Option<Triangle>> {
    let faces = face_normals(mesh);
    let corners = corner_normals(mesh, &faces, options.crease_deg);
    mesh.triangles
        .par_iter()
        .zip(&corners)
        .zip(&faces)
        .map(|((t, normals), face)| {
            let centroid = t.iter().map(|&v| mesh.positions[v as usize]).sum::<DVec3>() / 3.0;
            let front = camera.to_view(*face).dot(-camera.view_ray(centroid)) >= 0.0;
            let colors = [0, 1, 2].map(|k| {
                let n = camera.to_view(normals[k].as_dvec3());
                lighting.shade(base[t[k] as usize], if front { n } else { -n })
            });
            triangle_at(t, projected, colors)
        })
        .collect()
}

/// Every edge once (the triangle's own orientation, lower index first for inner edges).
fn edge_segments(mesh: &Mesh, projected: &[Option<Vec3>], color: impl Fn(usize) -> Vec3 + Sync) -> Vec<Segment> {
    let adjacency = crate::mesh::Adjacency::of(mesh);
    let shared =
        |a: u32, b: u32| adjacency.faces(a as usize).iter().filter(|f| adjacency.faces(b as usize).contains(f)).count();
    mesh.triangles
        .iter()
        .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
        .filter(|&(a, b)| a < b || shared(a, b) == 1)
        .filter_map(|(a, b)| {
            let ends = [projected[a as usize]?, projected[b as usize]?];
            Some(Segment { ends, colors: [color(a as usize), color(b as usize)] })
        })
        .collect()
}

/// Averages each pixel's samples; uncovered samples take the background (or transparency).
fn resolve(frame: &Frame, s: usize, background: Option<[u8; 3]>) -> Picture {
    let (width, height) = (frame.width / s, frame.height / s);
    let back = background.map_or(Vec3::ZERO, |c| Vec3::from(c.map(|x| x as f32 / 255.0)));
    let mut rgba = vec![0u8; width * height * 4];
    rgba.par_chunks_mut(width * 4).enumerate().for_each(|(y, row)| {
        for x in 0..width {
            let (mut sum, mut covered) = (Vec3::ZERO, 0usize);
            for dy in 0..s {
                for dx in 0..s {
                    let i = (y * s + dy) * frame.width + x * s + dx;
                    if frame.covered[i] {
                        sum += frame.color[i];
                        covered += 1;
                    } else if background.is_some() {
                        sum += back;
                    }
                }
            }
            let n = (s * s) as f32;
            let (color, alpha) = match background {
                Some(_) => (sum / n, 1.0),
                None if covered > 0 => (sum / covered as f32, covered as f32 / n),
                None => (Vec3::ZERO, 0.0),
            };
            let px = &mut row[4 * x..4 * x + 4];
            px[..3].copy_from_slice(&color.to_array().map(|c| (c.clamp(0.0, 1.0) * 255.0).round() as u8));
            px[3] = (alpha * 255.0).round() as u8;
        }
    });
    Picture { width, height, rgba }
}
