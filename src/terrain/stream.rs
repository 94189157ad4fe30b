//! Terrain output in bounded memory (seed 003, Wiseman & Nedunuri): rows are generated in
//! bands — each band computed by the region generator on the band plus a one-point margin
//! for normals — and written as soon as they are complete. Memory is O(width × band)
//! instead of O(width²); the bytes equal those of the whole grid written at once.

use std::borrow::Cow;
use std::io::Write;

use serde::{Deserialize, Serialize};

use super::{Rect, TerrainParams, grid_triangles, heights, normal_at};
use crate::error::{Error, Result};
use crate::io::obj;
use crate::io::ply::{PlyLayout, write_header, write_triangle, write_vertex};

/// Terrain encodings that can be written progressively.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum StreamFormat {
    /// Binary PLY with normals and colours (same bytes as the in-memory mesh writer).
    Ply,
    /// OBJ with colours and normals (same bytes as the in-memory mesh writer): heights are
    /// generated twice, once for the `v` lines and once for the `vn` lines that follow them.
    Obj,
    /// 16-bit greyscale PNG heightmap.
    Png16,
    /// Row-major u16 little-endian heights, no header.
    Raw16,
    /// Row-major f32 little-endian heights, no header.
    F32,
    /// 32-bit float OpenEXR, one channel `Y` (ZIP, scan lines in increasing order); written
    /// whole.
    Exr,
    /// 32-bit float baseline TIFF, one sample per pixel (BigTIFF past 4 GB); written whole.
    Tiff,
}

impl StreamFormat {
    /// The format named by a file extension.
    pub fn from_extension(ext: &str) -> Option<Self> {
        Some(match ext.to_ascii_lowercase().as_str() {
            "ply" => StreamFormat::Ply,
            "obj" => StreamFormat::Obj,
            "png" => StreamFormat::Png16,
            "raw16" | "raw" | "r16" => StreamFormat::Raw16,
            "f32" => StreamFormat::F32,
            "exr" => StreamFormat::Exr,
            "tif" | "tiff" => StreamFormat::Tiff,
            _ => return None,
        })
    }

    /// Whether rows can be written as they are generated (EXR and TIFF need the whole
    /// image: their encoders seek back to write offsets).
    pub fn streams(self) -> bool {
        !matches!(self, StreamFormat::Exr | StreamFormat::Tiff)
    }

    /// Whether heights are quantised to 16 bits over a range.
    pub fn is_16_bit(self) -> bool {
        matches!(self, StreamFormat::Png16 | StreamFormat::Raw16)
    }

    /// Whether this is a heightmap (not a mesh).
    pub fn is_heightmap(self) -> bool {
        !matches!(self, StreamFormat::Ply | StreamFormat::Obj)
    }

    /// The format's name in reports and sidecars.
    pub fn name(self) -> &'static str {
        match self {
            StreamFormat::Ply => "ply",
            StreamFormat::Obj => "obj",
            StreamFormat::Png16 => "png16",
            StreamFormat::Raw16 => "raw16",
            StreamFormat::F32 => "f32",
            StreamFormat::Exr => "exr32",
            StreamFormat::Tiff => "tiff32",
        }
    }

    /// The usual file extension.
    pub fn extension(self) -> &'static str {
        match self {
            StreamFormat::Ply => "ply",
            StreamFormat::Obj => "obj",
            StreamFormat::Png16 => "png",
            StreamFormat::Raw16 => "raw16",
            StreamFormat::F32 => "f32",
            StreamFormat::Exr => "exr",
            StreamFormat::Tiff => "tif",
        }
    }
}

/// Points a streamed band holds at most by default: 2²² heights, 32 MB of f64.
pub const BAND_POINTS: usize = 1 << 22;

/// The default rows per streamed band for rows of `width` points: as many as fit
/// [`BAND_POINTS`], from 64 (a 65537-point row: 32 MB) to 1024. Taller bands recompute
/// fewer coarse levels per row: 8193² streams at 89 % of in-memory with 64 rows and
/// 99 % with 511 (`cargo bench --bench terrain`).
pub fn default_band(width: usize) -> usize {
    (BAND_POINTS / width.max(1)).clamp(64, 1024)
}

/// Maps a height to 16 bits over `range` (clamped).
pub fn to_u16(h: f64, range: (f64, f64)) -> u16 {
    // Non-negative, so adding ½ and truncating rounds to nearest without a libm call.
    (((h - range.0) / (range.1 - range.0)).clamp(0.0, 1.0) * 65535.0 + 0.5) as u16
}

/// Writes the terrain on `rect` in `format`, `band` rows at a time. `range` maps heights to
/// 16-bit values (PNG, RAW16).
///
/// # Errors
/// [`Error::InvalidInput`] for invalid parameters or sizes the format cannot hold;
/// [`Error::Io`] (with the placeholder path `terrain output`) when `w` fails.
pub fn write_terrain(
    params: &TerrainParams,
    rect: Rect,
    format: StreamFormat,
    range: (f64, f64),
    band: usize,
    w: &mut dyn Write,
) -> Result<()> {
    write_terrain_observed(params, rect, None, format, range, band, w, &mut |_, _, _| {})
}

/// [`write_terrain`], showing each band of finished heights to `observe(field, y0, y1)`
/// once, as it is written (rows y0..=y1 of `field`): a preview or a statistic is then made
/// from the streamed rows, in the stream's bounded memory. `known`, if given, already holds
/// the finished heights on `rect` (from [`super::heights_and_layers`]): a heightmap is then
/// written from them instead of being generated again.
///
/// # Errors
/// As [`write_terrain`].
#[allow(clippy::too_many_arguments)]
pub fn write_terrain_observed(
    params: &TerrainParams,
    rect: Rect,
    known: Option<&super::Heightfield>,
    format: StreamFormat,
    range: (f64, f64),
    band: usize,
    w: &mut dyn Write,
    observe: &mut dyn FnMut(&super::Heightfield, u64, u64),
) -> Result<()> {
    let source = |region: Rect| known_or(known, region, || heights(params, region));
    let band = if known.is_some() && format.is_heightmap() { rect.height() } else { band };
    write_values(params, &source, rect, format, range, band, w, observe)
}

/// Where a writer's values come from: the values on a rectangle of the grid, borrowed
/// where they are known already.
type Source<'a> = &'a dyn Fn(Rect) -> Result<Cow<'a, super::Heightfield>>;

/// `known` where it covers exactly `region` (borrowed, not copied), else `compute`'s.
fn known_or<'a>(
    known: Option<&'a super::Heightfield>,
    region: Rect,
    compute: impl FnOnce() -> Result<super::Heightfield>,
) -> Result<Cow<'a, super::Heightfield>> {
    match known {
        Some(field) if field.rect == region => Ok(Cow::Borrowed(field)),
        _ => compute().map(Cow::Owned),
    }
}

/// Writes one erosion layer (a mask in [0, 1], see [`super::ErosionLayers`]) on `rect` as a
/// heightmap in `format`, `band` rows at a time (each band runs the erosion on its
/// rectangle and halo again, in bounded memory); 16-bit formats map [0, 1] onto 0..=65535.
/// `values`, where given, holds the layer on `rect` already (one erosion run for the heights
/// and every layer of a file written whole).
///
/// # Errors
/// [`Error::InvalidInput`] for a mesh format (layers are heightmaps), for parameters
/// without hydraulic erosion, or as [`write_terrain`].
#[allow(clippy::too_many_arguments)]
pub fn write_layer(
    params: &TerrainParams,
    rect: Rect,
    layer: super::ErosionLayer,
    values: Option<&super::Heightfield>,
    format: StreamFormat,
    band: usize,
    w: &mut dyn Write,
    observe: &mut dyn FnMut(&super::Heightfield, u64, u64),
) -> Result<()> {
    if !format.is_heightmap() {
        return Err(Error::InvalidInput(format!(
            "the {} layer is a heightmap: write the terrain as .png, .raw16, .f32, .exr or .tif",
            layer.name()
        )));
    }
    let computed = |region: Rect| {
        known_or(values, region, || Ok(super::heights_and_layers(params, region, &[layer])?.1.remove(0)))
    };
    let band = if values.is_some() { rect.height() } else { band };
    write_values(params, &computed, rect, format, LAYER_RANGE, band, w, observe)
}

/// The values of a layer's 16-bit samples: masks in [0, 1].
pub const LAYER_RANGE: (f64, f64) = (0.0, 1.0);

/// The writer behind [`write_terrain_observed`] and [`write_layer`]: `source` gives the
/// values (heights, or a layer) on each band's rectangle.
#[allow(clippy::too_many_arguments)]
fn write_values(
    params: &TerrainParams,
    source: Source<'_>,
    rect: Rect,
    format: StreamFormat,
    range: (f64, f64),
    band: usize,
    w: &mut dyn Write,
    observe: &mut dyn FnMut(&super::Heightfield, u64, u64),
) -> Result<()> {
    let (cols, rows) = (rect.width(), rect.height());
    let band = band.max(1);
    let io = |e: std::io::Error| Error::io("terrain output", e);
    match format {
        StreamFormat::Ply => {
            if params.grid == super::Grid::Hex {
                return Err(Error::InvalidInput(
                    "hexagonal tiles are written whole (no --stream for hex meshes)".into(),
                ));
            }
            let vertices = cols * rows;
            if vertices > i32::MAX as usize {
                return Err(Error::InvalidInput(format!("{cols}x{rows} vertices exceed PLY's int indices: use tiles")));
            }
            let layout = PlyLayout {
                vertices,
                faces: 2 * (cols - 1) * (rows - 1),
                normals: true,
                colors: true,
                scalars: Vec::new(),
                ascii: false,
            };
            write_header(w, &layout).map_err(io)?;
            for_each_band(params, source, rect, band, true, observe, |field, y0, y1| {
                for y in y0..=y1 {
                    for x in rect.x0..=rect.x1 {
                        let h = field.at(x, y);
                        let normal = normal_at(params, field, x, y);
                        write_vertex(w, false, params.position(x, y, h), Some(normal), Some(params.color(h)), &[])?;
                    }
                }
                Ok(())
            })
            .map_err(io)?;
            for t in grid_triangles(params.grid, cols, rows) {
                write_triangle(w, false, t).map_err(io)?;
            }
        }
        StreamFormat::Obj => {
            if params.grid == super::Grid::Hex {
                return Err(Error::InvalidInput(
                    "hexagonal tiles are written whole (no --stream for hex meshes)".into(),
                ));
            }
            if (cols * rows) as u64 > u64::from(u32::MAX) {
                return Err(Error::InvalidInput(format!("{cols}x{rows} vertices exceed 32-bit indices: use tiles")));
            }
            obj::write_header(w).map_err(io)?;
            for_each_band(params, source, rect, band, false, observe, |field, y0, y1| {
                for y in y0..=y1 {
                    for x in rect.x0..=rect.x1 {
                        let h = field.at(x, y);
                        obj::write_vertex(w, params.position(x, y, h), Some(params.color(h)))?;
                    }
                }
                Ok(())
            })
            .map_err(io)?;
            for_each_band(params, source, rect, band, true, &mut |_, _, _| {}, |field, y0, y1| {
                for y in y0..=y1 {
                    for x in rect.x0..=rect.x1 {
                        obj::write_normal(w, normal_at(params, field, x, y))?;
                    }
                }
                Ok(())
            })
            .map_err(io)?;
            for t in grid_triangles(params.grid, cols, rows) {
                obj::write_face(w, t, true).map_err(io)?;
            }
        }
        StreamFormat::Raw16 | StreamFormat::F32 => {
            let mut row_bytes = Vec::with_capacity(cols * 4);
            for_each_band(params, source, rect, band, false, observe, |field, y0, y1| {
                for y in y0..=y1 {
                    row_bytes.clear();
                    for x in rect.x0..=rect.x1 {
                        let h = field.at(x, y);
                        if format == StreamFormat::F32 {
                            row_bytes.extend_from_slice(&(h as f32).to_le_bytes());
                        } else {
                            row_bytes.extend_from_slice(&to_u16(h, range).to_le_bytes());
                        }
                    }
                    w.write_all(&row_bytes)?;
                }
                Ok(())
            })
            .map_err(io)?;
        }
        StreamFormat::Exr | StreamFormat::Tiff => {
            let (Ok(width), Ok(height)) = (u32::try_from(cols), u32::try_from(rows)) else {
                return Err(Error::InvalidInput(format!("{cols}x{rows} is too large for one image: use tiles")));
            };
            let mut encoded = None;
            for_each_band(params, source, rect, rows, false, observe, |field, _, _| {
                let values: Vec<f32> = field.heights.iter().map(|&h| h as f32).collect();
                encoded = Some(match format {
                    StreamFormat::Exr => super::whole_file::exr(values, width, height),
                    _ => super::whole_file::tiff(&values, width, height),
                });
                Ok(())
            })
            .map_err(io)?;
            let bytes = encoded.expect("one band covers the image").map_err(io)?;
            w.write_all(&bytes).map_err(io)?;
        }
        StreamFormat::Png16 => {
            let (Ok(width), Ok(height)) = (u32::try_from(cols), u32::try_from(rows)) else {
                return Err(Error::InvalidInput("terrain too large for PNG".into()));
            };
            let mut encoder = png::Encoder::new(&mut *w, width, height);
            encoder.set_color(png::ColorType::Grayscale);
            encoder.set_depth(png::BitDepth::Sixteen);
            let mut writer = encoder.write_header().map_err(|e| io(std::io::Error::other(e)))?;
            let mut stream = writer.stream_writer().map_err(|e| io(std::io::Error::other(e)))?;
            let mut row_bytes = Vec::with_capacity(cols * 2);
            for_each_band(params, source, rect, band, false, observe, |field, y0, y1| {
                for y in y0..=y1 {
                    row_bytes.clear();
                    for x in rect.x0..=rect.x1 {
                        row_bytes.extend_from_slice(&to_u16(field.at(x, y), range).to_be_bytes());
                    }
                    stream.write_all(&row_bytes)?;
                }
                Ok(())
            })
            .map_err(io)?;
            stream.finish().map_err(|e| io(std::io::Error::other(e)))?;
        }
    }
    Ok(())
}

/// Calls `emit(field, y0, y1)` for consecutive bands of rows of `rect`; `field` holds the
/// band (plus a one-point margin inside the grid when `margin`, for normals).
fn for_each_band(
    params: &TerrainParams,
    source: Source<'_>,
    rect: Rect,
    band: usize,
    margin: bool,
    observe: &mut dyn FnMut(&super::Heightfield, u64, u64),
    mut emit: impl FnMut(&super::Heightfield, u64, u64) -> std::io::Result<()>,
) -> std::io::Result<()> {
    let last = params.size - 1;
    let m = u64::from(margin);
    let mut y0 = rect.y0;
    crate::progress::report("terrain", 0, rect.y1 - rect.y0 + 1);
    while y0 <= rect.y1 {
        let y1 = (y0 + band as u64 - 1).min(rect.y1);
        let region = Rect { y0, y1, ..rect }.grown(m, last);
        let field = source(region).map_err(std::io::Error::other)?;
        observe(&field, y0, y1);
        emit(&field, y0, y1)?;
        crate::progress::report("terrain", y1 - rect.y0 + 1, rect.y1 - rect.y0 + 1);
        y0 = y1 + 1;
    }
    Ok(())
}
