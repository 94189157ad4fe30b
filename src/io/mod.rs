//! Mesh files: one reader and one writer per format behind [`read`] and [`write()`], which
//! pick the format by extension. Readers never panic on bad input: they return
//! [`Error::Parse`] naming the file and the line, byte or element. Writers are atomic.

mod atomic;
pub mod glb;
pub mod glb_scene;
mod gltf_read;
pub mod image;
pub mod manifest;
pub mod obj;
mod off;
pub mod ply;
mod stl;
pub(crate) mod text;

use std::path::Path;

use crate::error::{Error, Location, Result};
use crate::mesh::Mesh;

pub use atomic::{
    OutputBatch, abandon_pending_outputs, create_output_dir, refuse_folder, write_atomically, written_size,
};

/// A mesh file format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Wavefront OBJ (our own reader: file vertex order kept).
    Obj,
    /// Stanford PLY, ASCII or binary (either endianness).
    Ply,
    /// Object File Format.
    Off,
    /// STereoLithography, ASCII or binary.
    Stl,
    /// glTF 2.0 binary (written with normals, colours, `TEXCOORD_0` and scalars; read:
    /// triangle lists, strips and fans of the default scene with node transforms and
    /// instancing applied, with their normals, `COLOR_0` and `TEXCOORD_0`).
    Glb,
    /// glTF 2.0 text: read as [`Format::Glb`] is, buffers in `data:` URIs or in files beside
    /// it; written as one file, its buffer a `data:` URI.
    Gltf,
}

impl Format {
    /// The format named by `path`'s extension (case-insensitive).
    ///
    /// # Errors
    /// [`Error::Parse`] for a missing or unknown extension.
    pub fn from_path(path: &Path) -> Result<Self> {
        let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("obj") => Ok(Format::Obj),
            Some("ply") => Ok(Format::Ply),
            Some("off") => Ok(Format::Off),
            Some("stl") => Ok(Format::Stl),
            Some("glb") => Ok(Format::Glb),
            Some("gltf") => Ok(Format::Gltf),
            _ => Err(Error::parse(
                path,
                Location::File,
                "unknown mesh format (expected .obj, .ply, .off, .stl, .glb or .gltf)",
            )),
        }
    }
}

/// A mesh read from a file, with what the reader changed or ignored.
#[derive(Debug, Clone)]
pub struct ReadOutcome {
    /// The mesh (polygons triangulated).
    pub mesh: Mesh,
    /// How many polygons with more than three corners were triangulated.
    pub triangulated_polygons: usize,
    /// What was ignored or merged ("vertex colours ignored", ...), one note each.
    pub notes: Vec<String>,
}

/// Options for [`write()`].
#[derive(Debug, Clone, Copy, Default)]
pub struct WriteOptions {
    /// Write text instead of binary where the format has both (PLY, STL).
    pub ascii: bool,
}

/// Reads a mesh, choosing the format by extension.
///
/// # Errors
/// [`Error::Io`] if the file cannot be read; [`Error::Parse`] naming the file and the line,
/// byte or element for malformed content.
pub fn read(path: &Path) -> Result<ReadOutcome> {
    let format = Format::from_path(path)?;
    let bytes = read_regular_file(path)?;
    read_bytes(&bytes, format, path)
}

/// The contents of the regular file at `path` (links followed). Anything else — a FIFO,
/// which would block, a device such as `/dev/zero`, which never ends, a directory — is
/// refused before it is opened, and no more than the file's size is read.
///
/// # Errors
/// [`Error::InvalidInput`] naming the path for a file that is not regular; [`Error::Io`] if
/// it cannot be read.
pub fn read_regular_file(path: &Path) -> Result<Vec<u8>> {
    use std::io::Read;
    let (file, size) = open_regular_file(path)?;
    let mut bytes = Vec::with_capacity(usize::try_from(size).unwrap_or(0).min(1 << 30));
    file.take(size).read_to_end(&mut bytes).map_err(|e| Error::io(path, e))?;
    Ok(bytes)
}

/// The regular file at `path`, opened, and its size; anything else is refused as
/// [`read_regular_file`] refuses it.
///
/// # Errors
/// As [`read_regular_file`].
pub(crate) fn open_regular_file(path: &Path) -> Result<(std::fs::File, u64)> {
    let metadata = std::fs::metadata(path).map_err(|e| Error::io(path, e))?;
    if !metadata.is_file() {
        let kind = describe_file_type(&metadata.file_type());
        return Err(Error::InvalidInput(format!(
            "{}: {kind}, not a regular file: only files are read",
            path.display()
        )));
    }
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    Ok((file, metadata.len()))
}

/// Reads what a plan cuts of a mesh — positions, faces, UVs and materials — as
/// [`read`] reads it, and whether it was read as a stream: binary PLY and binary STL are
/// read as their elements come, so neither the file's bytes nor the attributes a plan does
/// not use (normals, colours, other scalars) are ever held whole; other files are read
/// whole and those attributes dropped.
///
/// # Errors
/// As [`read`].
pub fn read_lean(path: &Path) -> Result<(ReadOutcome, bool)> {
    let streamed = match Format::from_path(path)? {
        Format::Ply => ply::read_lean(path)?,
        Format::Stl => stl::read_lean(path)?,
        _ => None,
    };
    if let Some(read) = streamed {
        return Ok((read, true));
    }
    let mut read = read(path)?;
    read.mesh.normals = None;
    read.mesh.colors = None;
    read.mesh.scalars.clear();
    Ok((read, false))
}

fn describe_file_type(kind: &std::fs::FileType) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    if kind.is_dir() {
        "a directory"
    } else if kind.is_fifo() {
        "a FIFO"
    } else if kind.is_char_device() {
        "a character device"
    } else if kind.is_block_device() {
        "a block device"
    } else if kind.is_socket() {
        "a socket"
    } else {
        "a special file"
    }
}

/// Parses mesh file contents already in memory; `path` is used in messages only.
///
/// # Errors
/// As [`read`].
pub fn read_bytes(bytes: &[u8], format: Format, path: &Path) -> Result<ReadOutcome> {
    if bytes.is_empty() {
        return Err(Error::parse(path, Location::File, "the file is empty"));
    }
    let outcome = match format {
        Format::Obj => obj::parse(bytes, path)?,
        Format::Ply => ply::parse(bytes, path)?,
        Format::Off => off::parse(bytes, path)?,
        Format::Stl => stl::parse(bytes, path)?,
        Format::Glb | Format::Gltf => gltf_read::parse(bytes, path)?,
    };
    outcome.mesh.check().map_err(|e| Error::parse(path, Location::File, e.to_string()))?;
    Ok(outcome)
}

/// Writes a mesh, choosing the format by extension; the file appears complete or not at all.
///
/// # Errors
/// [`Error::InvalidInput`] for an inconsistent mesh; [`Error::Io`] if writing fails.
pub fn write(mesh: &Mesh, path: &Path, options: WriteOptions) -> Result<()> {
    write_as(mesh, path, Format::from_path(path)?, options)
}

/// Writes a mesh in a given format whatever the file name; atomic like [`write()`].
///
/// # Errors
/// As [`write()`].
pub fn write_as(mesh: &Mesh, path: &Path, format: Format, options: WriteOptions) -> Result<()> {
    mesh.check()?;
    if format == Format::Stl {
        fits_single_precision(mesh, path, glam::DVec3::ZERO)?;
    }
    if matches!(format, Format::Glb | Format::Gltf) {
        return glb::write_mesh(mesh, path, format == Format::Gltf);
    }
    write_atomically(path, |w| match format {
        Format::Obj => obj::write(mesh, w),
        Format::Ply => ply::write(mesh, w, options.ascii),
        Format::Off => off::write(mesh, w),
        Format::Stl => stl::write(mesh, w, options.ascii),
        Format::Glb | Format::Gltf => unreachable!("written above"),
    })
}

/// Refuses a mesh a single-precision format (STL, glTF) cannot hold, its positions stored
/// from `origin`: a coordinate beyond f32's range would be written as infinity, a file our own
/// readers refuse; and faces whose corners f32 would merge or make collinear (coordinates like
/// 1e6 with detail of 0.01) would come back collapsed (#36: 16 of 320 at 1e6, all at 1e9).
///
/// # Errors
/// [`Error::InvalidInput`] naming `path` and the first such vertex and its coordinate, or the
/// count of faces that would collapse.
pub(crate) fn fits_single_precision(mesh: &Mesh, path: &Path, origin: glam::DVec3) -> Result<()> {
    let limit = f64::from(f32::MAX);
    if let Some((v, p)) = mesh.positions.iter().enumerate().find(|(_, p)| (**p - origin).abs().max_element() > limit) {
        return Err(Error::InvalidInput(format!(
            "vertex {v} ({:?}, {:?}, {:?}) lies beyond single precision, which {} would store; write .ply, .off or .obj to keep it",
            p.x,
            p.y,
            p.z,
            path.display()
        )));
    }
    let collapsed = faces_collapsed_in_single_precision(mesh, origin);
    if collapsed > 0 {
        let glb = if origin == glam::DVec3::ZERO && matches!(Format::from_path(path), Ok(Format::Stl)) {
            ", or .glb, which stores a mesh far from the origin about its centre"
        } else {
            ""
        };
        return Err(Error::InvalidInput(format!(
            "{collapsed} of {} faces would collapse in the single precision {} stores (coordinates too large for their detail): write .ply, .off or .obj to keep them{glb}",
            mesh.triangles.len(),
            path.display()
        )));
    }
    Ok(())
}

/// How many faces of a mesh far from the origin for its size ([`glb::origin_of`]) lose their
/// area because of where it lies: their corners, less `origin`, rounded to f32 are collinear,
/// though rounded about the mesh's own centre they are not. Near the origin, a face too small
/// for f32 (as marching tetrahedra make) is f32's ordinary limit, which every
/// single-precision writer has, and is not counted.
pub(crate) fn faces_collapsed_in_single_precision(mesh: &Mesh, origin: glam::DVec3) -> usize {
    use rayon::prelude::*;
    let centre = glb::origin_of(mesh);
    if centre == origin {
        return 0;
    }
    let flat = |[a, b, c]: [glam::DVec3; 3]| (b - a).cross(c - a) == glam::DVec3::ZERO;
    let round = |p: glam::DVec3, about: glam::DVec3| (p - about).as_vec3().as_dvec3();
    mesh.triangles
        .par_iter()
        .filter(|t| {
            let corners = t.map(|v| mesh.positions[v as usize]);
            flat(corners.map(|p| round(p, origin))) && !flat(corners.map(|p| round(p, centre)))
        })
        .count()
}

/// Bit pattern of a position for welding duplicates; adding 0.0 turns -0.0 into 0.0 so
/// both weld together.
pub(crate) fn weld_key(p: glam::DVec3) -> [u64; 3] {
    [(p.x + 0.0).to_bits(), (p.y + 0.0).to_bits(), (p.z + 0.0).to_bits()]
}

/// Checks a face's corner count and indices against the vertex count.
pub(crate) fn check_polygon(polygon: &[u32], vertex_count: usize) -> std::result::Result<(), String> {
    if polygon.len() < 3 {
        return Err(format!("a face needs at least 3 vertices, this one has {}", polygon.len()));
    }
    if let Some(v) = polygon.iter().find(|&&v| v as usize >= vertex_count) {
        return Err(format!("vertex index {v} is out of range (there are {vertex_count} vertices)"));
    }
    Ok(())
}

/// Removes corners that repeat the corner before them (cyclically: a quad a b b c is the
/// triangle a b c) and tells whether what is left is a face: at least three corners, none
/// repeated. Faces that repeat a vertex — common in CAD exports, whose welded corners
/// collapse thin facets — have no area; the readers drop them and say how many
/// ([`repeated_vertex_note`]) instead of refusing the file.
pub(crate) fn without_repeated_corners(polygon: &mut Vec<u32>) -> bool {
    polygon.dedup();
    while polygon.len() > 1 && polygon.first() == polygon.last() {
        polygon.pop();
    }
    polygon.len() >= 3 && !repeats_a_corner(polygon)
}

/// Whether a corner appears twice in `polygon`: pairwise for small polygons, by sorting a
/// copy for large ones (#36: pairwise is quadratic, 7 % of reading one face of 100k
/// corners; the rest was the texture-coordinate search `obj.rs` now does by table).
fn repeats_a_corner(polygon: &[u32]) -> bool {
    if polygon.len() <= 32 {
        return polygon.iter().enumerate().any(|(i, a)| polygon[i + 1..].contains(a));
    }
    let mut sorted = polygon.to_vec();
    sorted.sort_unstable();
    sorted.windows(2).any(|w| w[0] == w[1])
}

/// The reader note for `dropped` faces that repeated a vertex (none for zero).
pub(crate) fn repeated_vertex_note(dropped: usize) -> Option<String> {
    (dropped > 0).then(|| format!("{dropped} face(s) repeating a vertex dropped (they have no area)"))
}

/// Largest element count a file of `remaining` bytes can hold at `min_bytes` per element;
/// used to refuse absurd header counts before allocating.
pub(crate) fn check_count_fits(
    count: usize,
    min_bytes: usize,
    remaining: usize,
    what: &str,
) -> std::result::Result<(), String> {
    match count.checked_mul(min_bytes.max(1)) {
        Some(need) if need <= remaining => Ok(()),
        _ => Err(format!("the header declares {count} {what} but only {remaining} bytes follow")),
    }
}
