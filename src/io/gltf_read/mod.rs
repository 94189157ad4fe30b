//! glTF 2.0 reading, `.glb` and `.gltf`, as the specification defines it (Khronos, *glTF 2.0
//! Specification*, 2021): the GLB container or JSON text, buffers in the binary chunk, in
//! base64 `data:` URIs or in files beside the document; accessors of every component type,
//! strided or sparse, normalised or quantized (`KHR_mesh_quantization`); triangle lists,
//! strips and fans; the default scene's node trees with their transforms, and
//! `EXT_mesh_gpu_instancing`. Every drawn triangle primitive becomes part of one mesh, in
//! world coordinates, with normals, `COLOR_0` and `TEXCOORD_0` where every part has them.
//!
//! Before anything is decoded, the scene's vertex and triangle counts (instances included)
//! are estimated from the accessors' declared counts and refused beyond what a mesh can index
//! or the memory can hold ([`crate::memory::ensure_available`]).

mod accessor;
mod buffers;
mod scene;

use std::borrow::Cow;
use std::collections::HashMap;
use std::path::Path;

use glam::{DMat3, DVec3};
use gltf::json::mesh::{Mode, Semantic};
use gltf::json::validation::Checked;

use self::accessor::{Accessors, Use};
use self::buffers::Buffers;
use crate::error::{Error, Location, Result};
use crate::mesh::Mesh;

pub(crate) use self::buffers::data_uri;

/// Extensions a file may require that change nothing this reader reads (materials,
/// textures, lights) or that it implements.
fn understood(extension: &str) -> bool {
    matches!(extension, "KHR_mesh_quantization" | "EXT_mesh_gpu_instancing" | "KHR_lights_punctual" | "KHR_xmp_json_ld")
        || ["KHR_materials_", "KHR_texture_", "EXT_texture_", "MSFT_texture_"].iter().any(|p| extension.starts_with(p))
}

/// Reads a `.glb` or `.gltf` file's bytes; `path` names it in errors and locates the
/// files its buffers name.
pub(crate) fn parse(bytes: &[u8], path: &Path) -> Result<super::ReadOutcome> {
    let glb;
    let (json, bin): (Cow<[u8]>, Option<&[u8]>) = if bytes.starts_with(b"glTF") {
        check_glb_header(bytes, path)?;
        glb = gltf::binary::Glb::from_slice(bytes)
            .map_err(|e| Error::parse(path, Location::File, format!("GLB: {e}")))?;
        (Cow::Borrowed(&glb.json[..]), glb.bin.as_deref())
    } else {
        (Cow::Borrowed(bytes.strip_prefix(b"\xef\xbb\xbf").unwrap_or(bytes)), None)
    };
    let in_glb = bytes.starts_with(b"glTF");
    let json_error = |e: serde_json::Error| {
        if in_glb {
            Error::parse(path, Location::File, format!("GLB JSON chunk: {e}"))
        } else {
            Error::parse(path, Location::Line(e.line().max(1)), format!("glTF JSON: {e}"))
        }
    };
    let root: gltf::json::Root = serde_json::from_slice(&json).map_err(json_error)?;
    if let Some(unread) = root.extensions_required.iter().find(|e| !understood(e)) {
        return Err(Error::parse(
            path,
            Location::File,
            format!("the file requires the glTF extension {unread}, which asperity does not read (export it without)"),
        ));
    }
    let mut notes = Vec::new();
    if root.extensions_used.iter().any(|e| e == "KHR_texture_transform") {
        notes.push("KHR_texture_transform is not applied: TEXCOORD_0 is read as stored".to_string());
    }
    let extended = if root.extensions_used.iter().any(|e| e == "EXT_mesh_gpu_instancing") {
        serde_json::from_slice(&json).map_err(json_error)?
    } else {
        serde_json::Value::Null
    };
    let buffers = Buffers::new(&root, path, bin);
    let accessors = Accessors { root: &root, buffers: &buffers };
    let located = |(at, msg): scene::Located| Error::parse(path, at, msg);
    let instances = scene::instances(&root, &accessors, &extended).map_err(located)?;
    check_budget(&root, &accessors, &instances, path, bytes.len())?;

    let mut decoded: HashMap<usize, Vec<Part>> = HashMap::new();
    let mut dropped = 0;
    let mut out = Assembly::default();
    for instance in &instances {
        let parts = match decoded.entry(instance.mesh) {
            std::collections::hash_map::Entry::Occupied(known) => known.into_mut(),
            std::collections::hash_map::Entry::Vacant(slot) => {
                let parts = decode_mesh(&root, &accessors, instance.mesh, &mut notes).map_err(located)?;
                dropped += parts.iter().map(|p| p.dropped).sum::<usize>();
                slot.insert(parts)
            }
        };
        for part in parts.iter() {
            out.add(part, instance.world);
        }
    }
    let mesh = out.finish(&mut notes);
    if mesh.positions.is_empty() {
        return Err(Error::parse(path, Location::File, "no triangle mesh in the default scene"));
    }
    notes.extend(super::repeated_vertex_note(dropped));
    Ok(super::ReadOutcome { mesh, triangulated_polygons: 0, notes })
}

/// How many times its own size a glTF file may expand to (past 1 GiB) without a memory
/// budget set by the user: a kilobyte of nodes can instance a mesh millions of times.
const AMPLIFICATION: u64 = 256;

/// The triangles a primitive of `mode` draws from `count` corners (none for points and lines).
fn triangle_count(mode: Mode, count: u64) -> u64 {
    match mode {
        Mode::Triangles => count / 3,
        Mode::TriangleStrip | Mode::TriangleFan => count.saturating_sub(2),
        Mode::Points | Mode::Lines | Mode::LineLoop | Mode::LineStrip => 0,
    }
}

/// Refuses a scene whose instances would make more vertices than a mesh can index, or more
/// than the memory holds, from the declared counts (nothing decoded yet).
fn check_budget(
    root: &gltf::json::Root,
    accessors: &Accessors,
    instances: &[scene::Instance],
    path: &Path,
    file_bytes: usize,
) -> Result<()> {
    let mut per_mesh: HashMap<usize, (u64, u64)> = HashMap::new();
    let (mut vertices, mut triangles) = (0u64, 0u64);
    for instance in instances {
        let (v, t) = *per_mesh.entry(instance.mesh).or_insert_with(|| {
            root.meshes[instance.mesh].primitives.iter().fold((0, 0), |(v, t), p| {
                let Checked::Valid(mode) = p.mode else { return (v, t) };
                let positions = p
                    .attributes
                    .get(&Checked::Valid(Semantic::Positions))
                    .and_then(|a| accessors.count(a.value()).ok())
                    .unwrap_or(0) as u64;
                let corners = p.indices.and_then(|i| accessors.count(i.value()).ok()).map_or(positions, |c| c as u64);
                // Every triangle-mode primitive's vertices are read, whatever it draws.
                if triangle_count(mode, 3) == 0 {
                    (v, t)
                } else {
                    (v.saturating_add(positions), t.saturating_add(triangle_count(mode, corners)))
                }
            })
        });
        vertices = vertices.saturating_add(v);
        triangles = triangles.saturating_add(t);
    }
    let what = format!("{} mesh instance(s) drawing {vertices} vertices and {triangles} triangles", instances.len());
    if vertices > u64::from(u32::MAX) || triangles > u64::from(u32::MAX) {
        return Err(Error::parse(path, Location::File, format!("{what}: more than a mesh can index (2^32)")));
    }
    // Positions and normals (f64), colours, per-vertex UVs; corners and per-corner UVs.
    let bytes = vertices.saturating_mul(24 + 24 + 3 + 16).saturating_add(triangles.saturating_mul(12 + 48));
    // Instancing lets a small file ask for a lot: past 1 GiB and AMPLIFICATION times the
    // file, only a budget the user set (--max-memory) says it is wanted.
    let fold = bytes / (file_bytes.max(1) as u64);
    if bytes > 1 << 30 && fold > AMPLIFICATION && !crate::memory::budget_is_set() {
        return Err(Error::parse(
            path,
            Location::File,
            format!(
                "{what}: about {} GiB from a file of {file_bytes} bytes ({fold} times its size); set --max-memory to allow it",
                bytes >> 30
            ),
        ));
    }
    crate::memory::ensure_available(bytes, &format!("reading {what}"), "read a smaller scene")
        .map_err(|e| e.about_file(path))
}

/// A triangle primitive decoded once, in its mesh's coordinates.
struct Part {
    positions: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
    normals: Option<Vec<DVec3>>,
    uvs: Option<Vec<[f64; 2]>>,
    colors: Option<Vec<[u8; 3]>>,
    /// Triangles of a list that repeat a vertex (dropped; strips' joins are not counted).
    dropped: usize,
}

fn decode_mesh(
    root: &gltf::json::Root,
    accessors: &Accessors,
    m: usize,
    notes: &mut Vec<String>,
) -> std::result::Result<Vec<Part>, scene::Located> {
    let mut parts = Vec::new();
    for (p, primitive) in root.meshes[m].primitives.iter().enumerate() {
        let at = |msg: String| (Location::Element("mesh", m), format!("primitive {p}: {msg}"));
        let Checked::Valid(mode) = primitive.mode else {
            return Err(at("its mode is not one glTF defines".into()));
        };
        if triangle_count(mode, 3) == 0 {
            notes.push(format!("mesh {m}: a {mode:?} primitive ignored (only triangles are read)"));
            continue;
        }
        parts.push(decode_primitive(accessors, primitive, mode).map_err(at)?);
    }
    Ok(parts)
}

fn decode_primitive(
    accessors: &Accessors,
    primitive: &gltf::json::mesh::Primitive,
    mode: Mode,
) -> std::result::Result<Part, String> {
    let attribute = |semantic: Semantic| primitive.attributes.get(&Checked::Valid(semantic)).map(|a| a.value());
    let read = |index: usize, use_: Use| accessors.read(index, use_).map_err(|m| format!("{}: {m}", use_.name()));
    let Some(position) = attribute(Semantic::Positions) else {
        return Err("no POSITION attribute (a triangle primitive needs one)".into());
    };
    let (values, _) = read(position, Use::Position)?;
    let positions: Vec<DVec3> = values.chunks_exact(3).map(DVec3::from_slice).collect();
    let count = positions.len();
    // Every attribute has POSITION's count (checked on the declarations, before reading).
    let read_beside = |index: usize, use_: Use| {
        let declared = accessors.count(index).map_err(|m| format!("{}: {m}", use_.name()))?;
        if declared != count {
            return Err(format!("{} has {declared} elements but POSITION has {count}", use_.name()));
        }
        read(index, use_)
    };
    let normals = match attribute(Semantic::Normals) {
        Some(a) => Some(read_beside(a, Use::Normal)?.0.chunks_exact(3).map(DVec3::from_slice).collect()),
        None => None,
    };
    let uvs = match attribute(Semantic::TexCoords(0)) {
        // glTF's v runs down the image, asperity's up.
        Some(a) => Some(read_beside(a, Use::TexCoord)?.0.chunks_exact(2).map(|t| [t[0], 1.0 - t[1]]).collect()),
        None => None,
    };
    let colors = match attribute(Semantic::Colors(0)) {
        Some(a) => {
            let (v, n) = read_beside(a, Use::Color)?;
            let to_byte = |c: f64| (c.clamp(0.0, 1.0) * 255.0).round() as u8;
            Some(v.chunks_exact(n).map(|c| [to_byte(c[0]), to_byte(c[1]), to_byte(c[2])]).collect())
        }
        None => None,
    };
    let corners: Vec<u32> = match primitive.indices {
        Some(i) => accessors.read_indices(i.value()).map_err(|m| format!("the indices: {m}"))?,
        None => (0..count as u32).collect(),
    };
    if mode == Mode::Triangles && !corners.len().is_multiple_of(3) {
        return Err(format!("{} triangle indices are not a multiple of 3", corners.len()));
    }
    if let Some(k) = corners.iter().position(|&v| v as usize >= count) {
        return Err(format!("corner {k}: vertex index {} is out of range (there are {count} vertices)", corners[k]));
    }
    let mut triangles = Vec::with_capacity(triangle_count(mode, corners.len() as u64) as usize);
    let mut dropped = 0;
    let drawn = triangle_count(mode, corners.len() as u64) as usize;
    for i in 0..drawn {
        // §3.7.2.1: a list's i-th triangle, a strip's alternating orientation, a fan around corner 0.
        let t = match mode {
            Mode::TriangleStrip if i % 2 == 0 => [corners[i], corners[i + 1], corners[i + 2]],
            Mode::TriangleStrip => [corners[i], corners[i + 2], corners[i + 1]],
            Mode::TriangleFan => [corners[i + 1], corners[i + 2], corners[0]],
            _ => [corners[3 * i], corners[3 * i + 1], corners[3 * i + 2]],
        };
        if crate::mesh::repeats_a_vertex(t) {
            dropped += usize::from(mode == Mode::Triangles);
            continue;
        }
        triangles.push(t);
    }
    Ok(Part { positions, triangles, normals, uvs, colors, dropped })
}

/// The mesh under construction from placed parts; an attribute survives only if every part
/// has it.
#[derive(Default)]
struct Assembly {
    mesh: Mesh,
    normals: Option<Vec<DVec3>>,
    uvs: Option<Vec<[f64; 2]>>,
    colors: Option<Vec<[u8; 3]>>,
    some_uvs: bool,
    started: bool,
}

impl Assembly {
    fn add(&mut self, part: &Part, world: glam::DMat4) {
        if !self.started {
            self.started = true;
            self.normals = Some(Vec::new());
            self.uvs = Some(Vec::new());
            self.colors = Some(Vec::new());
        }
        let base = self.mesh.positions.len() as u32;
        let linear = DMat3::from_mat4(world);
        let mirrored = linear.determinant() < 0.0;
        self.mesh.positions.extend(part.positions.iter().map(|&p| world.transform_point3(p)));
        self.mesh.triangles.extend(part.triangles.iter().map(|&[a, b, c]| {
            // §3.7.2.1: a transform of negative determinant turns the winding.
            if mirrored { [base + a, base + c, base + b] } else { [base + a, base + b, base + c] }
        }));
        let normal_matrix = (linear.determinant() != 0.0).then(|| linear.inverse().transpose());
        self.normals = match (self.normals.take(), &part.normals, normal_matrix) {
            (Some(mut all), Some(n), Some(m)) => {
                all.extend(n.iter().map(|&v| (m * v).normalize_or_zero()));
                Some(all)
            }
            _ => None,
        };
        self.some_uvs |= part.uvs.is_some();
        self.uvs = match (self.uvs.take(), &part.uvs) {
            (Some(mut all), Some(t)) => {
                all.extend_from_slice(t);
                Some(all)
            }
            _ => None,
        };
        self.colors = match (self.colors.take(), &part.colors) {
            (Some(mut all), Some(c)) => {
                all.extend_from_slice(c);
                Some(all)
            }
            _ => None,
        };
    }

    fn finish(self, notes: &mut Vec<String>) -> Mesh {
        let mut mesh = self.mesh;
        let n = mesh.positions.len();
        mesh.normals = self.normals.filter(|v| v.len() == n);
        mesh.colors = self.colors.filter(|c| c.len() == n);
        mesh.uvs =
            self.uvs.filter(|t| t.len() == n).map(|t| crate::mesh::uv::CornerUvs::per_vertex(t, &mesh.triangles));
        if self.some_uvs && mesh.uvs.is_none() {
            notes.push("TEXCOORD_0 on only some primitives: ignored (every vertex needs one)".to_string());
        }
        mesh
    }
}

/// The GLB container header (magic, version, total length) checked before the `gltf`
/// crate sees it: gltf 1.4.1 subtracts the header size from the declared length unchecked
/// and panics on a length below 12 (found by `make fuzz`, tests/data/fuzz/read_glb).
fn check_glb_header(bytes: &[u8], path: &Path) -> Result<()> {
    let word = |at: usize| bytes.get(at..at + 4).map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]));
    let (Some(version), Some(length)) = (word(4), word(8)) else {
        return Err(Error::parse(
            path,
            Location::File,
            format!("GLB: the file ends inside its 12-byte header ({} bytes)", bytes.len()),
        ));
    };
    if version != 2 {
        return Err(Error::parse(path, Location::Byte(4), format!("GLB: version {version} (only glTF 2.0 is read)")));
    }
    const HEADERS: u32 = 12 + 8; // file header and the JSON chunk's header
    if length < HEADERS || length as usize > bytes.len() {
        return Err(Error::parse(
            path,
            Location::Byte(8),
            format!(
                "GLB: the header declares {length} bytes but the file has {} (at least {HEADERS} needed)",
                bytes.len()
            ),
        ));
    }
    Ok(())
}
