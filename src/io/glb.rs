//! glTF 2.0 binary (`.glb`) output through the `gltf` crate's JSON model and GLB container:
//! positions, normals (the mesh's own, or area-weighted), vertex colours, and per-vertex
//! scalars as application attributes (`_MEAN_CURVATURE`, ...). Several meshes (the levels
//! of a hierarchy) become one node each, side by side along x, with node extras naming the
//! level. Coordinates are stored as f32, as glTF requires.

use std::borrow::Cow;
use std::collections::BTreeMap;
use std::path::Path;

use glam::DVec3;
use gltf::json::validation::{Checked::Valid, USize64};
use gltf::json::{self as gj, Index};

use super::write_atomically;
use crate::error::{Error, Result};
use crate::mesh::Mesh;

/// One mesh of a `.glb` file, with its node name and extras.
pub struct GlbPart<'a> {
    /// The mesh.
    pub mesh: &'a Mesh,
    /// Node and mesh name.
    pub name: String,
    /// Node extras (JSON), e.g. `{"level": 3}`.
    pub extras: serde_json::Value,
}

/// Writes one mesh as a `.glb` file, atomically.
///
/// # Errors
/// [`Error::InvalidInput`] for an empty mesh or one too large for a GLB (4 GiB);
/// [`Error::Io`] naming the file.
pub fn write_glb(mesh: &Mesh, path: &Path) -> Result<()> {
    let name = path.file_stem().map_or("mesh".into(), |s| s.to_string_lossy().into_owned());
    write_glb_parts(&[GlbPart { mesh, name, extras: serde_json::Value::Null }], path)
}

/// Writes several meshes as nodes of one `.glb` scene, placed left to right along x with a
/// gap of a tenth of the widest one, atomically.
///
/// # Errors
/// As [`write_glb`].
pub fn write_glb_parts(parts: &[GlbPart], path: &Path) -> Result<()> {
    for part in parts {
        super::fits_single_precision(part.mesh, path)?;
    }
    let bytes = glb_bytes(parts)?;
    write_atomically(path, |out| out.write_all(&bytes))
}

/// The GLB file contents for `parts`.
///
/// # Errors
/// As [`write_glb`].
pub fn glb_bytes(parts: &[GlbPart]) -> Result<Vec<u8>> {
    let mut builder = Builder::default();
    let width = parts.iter().filter_map(|p| p.mesh.bounding_box()).map(|(lo, hi)| hi.x - lo.x).fold(0.0, f64::max);
    let mut x = 0.0;
    let mut nodes = Vec::new();
    for part in parts {
        part.mesh.check()?;
        let (lo, hi) = part
            .mesh
            .bounding_box()
            .ok_or_else(|| Error::InvalidInput(format!("{}: no vertices to write", part.name)))?;
        if part.mesh.triangles.is_empty() {
            return Err(Error::InvalidInput(format!("{}: no faces to write", part.name)));
        }
        let mesh = builder.mesh(part)?;
        let extras = match &part.extras {
            serde_json::Value::Null => None,
            value => Some(serde_json::value::to_raw_value(value).map_err(|e| Error::Internal(e.to_string()))?),
        };
        let offset = if parts.len() > 1 { (x - lo.x) as f32 } else { 0.0 };
        nodes.push(builder.root.push(gj::Node {
            mesh: Some(mesh),
            name: Some(part.name.clone()),
            extras,
            translation: (offset != 0.0).then_some([offset, 0.0, 0.0]),
            ..Default::default()
        }));
        x += (hi.x - lo.x) + 0.1 * width;
    }
    let scene = builder.root.push(gj::Scene { nodes, name: Some("asperity".into()), extensions: None, extras: None });
    builder.root.scene = Some(scene);
    builder.finish()
}

/// A glTF document and its binary chunk under construction (also used by
/// [`super::glb_scene`]).
#[derive(Default)]
pub(crate) struct Builder {
    pub(crate) root: gj::Root,
    bin: Vec<u8>,
    material: Option<Index<gj::Material>>,
    translucent: Option<Index<gj::Material>>,
}

impl Builder {
    /// Appends `bytes` (4-byte aligned) as a buffer view; animation data has no target.
    fn view(&mut self, bytes: &[u8], target: Option<gj::buffer::Target>) -> Index<gj::buffer::View> {
        while self.bin.len() % 4 != 0 {
            self.bin.push(0);
        }
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        self.root.push(gj::buffer::View {
            buffer: Index::new(0),
            byte_length: USize64::from(bytes.len()),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: None,
            name: None,
            target: target.map(Valid),
            extensions: None,
            extras: None,
        })
    }

    #[allow(clippy::too_many_arguments)]
    pub(crate) fn accessor(
        &mut self,
        bytes: &[u8],
        target: Option<gj::buffer::Target>,
        count: usize,
        component: gj::accessor::ComponentType,
        kind: gj::accessor::Type,
        normalized: bool,
        bounds: Option<(Vec<f32>, Vec<f32>)>,
    ) -> Index<gj::Accessor> {
        let view = self.view(bytes, target);
        self.root.push(gj::Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64::from(count),
            component_type: Valid(gj::accessor::GenericComponentType(component)),
            extensions: None,
            extras: None,
            type_: Valid(kind),
            min: bounds.as_ref().map(|(lo, _)| serde_json::json!(lo)),
            max: bounds.map(|(_, hi)| serde_json::json!(hi)),
            name: None,
            normalized,
            sparse: None,
        })
    }

    fn vec3(&mut self, values: &[[f32; 3]], with_bounds: bool) -> Index<gj::Accessor> {
        let bounds = with_bounds.then(|| {
            values.iter().fold(([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]), |(lo, hi), v| {
                ([0, 1, 2].map(|k| lo[k].min(v[k])), [0, 1, 2].map(|k| hi[k].max(v[k])))
            })
        });
        let bounds = bounds.map(|(lo, hi): ([f32; 3], [f32; 3])| (lo.to_vec(), hi.to_vec()));
        self.accessor(
            bytemuck::cast_slice(values),
            Some(gj::buffer::Target::ArrayBuffer),
            values.len(),
            gj::accessor::ComponentType::F32,
            gj::accessor::Type::Vec3,
            false,
            bounds,
        )
    }

    /// A matte material (glTF's default is fully metallic).
    fn material(&mut self) -> Index<gj::Material> {
        if let Some(m) = self.material {
            return m;
        }
        let m = self.root.push(gj::Material {
            name: Some("matte".into()),
            double_sided: true,
            pbr_metallic_roughness: gj::material::PbrMetallicRoughness {
                metallic_factor: gj::material::StrengthFactor(0.0),
                roughness_factor: gj::material::StrengthFactor(0.8),
                ..Default::default()
            },
            ..Default::default()
        });
        self.material = Some(m);
        m
    }

    /// A glossy material blending by the vertex colours' alpha (water).
    fn translucent(&mut self) -> Index<gj::Material> {
        if let Some(m) = self.translucent {
            return m;
        }
        let m = self.root.push(gj::Material {
            name: Some("translucent".into()),
            double_sided: true,
            alpha_mode: Valid(gj::material::AlphaMode::Blend),
            pbr_metallic_roughness: gj::material::PbrMetallicRoughness {
                metallic_factor: gj::material::StrengthFactor(0.0),
                roughness_factor: gj::material::StrengthFactor(0.15),
                ..Default::default()
            },
            ..Default::default()
        });
        self.translucent = Some(m);
        m
    }

    fn mesh(&mut self, part: &GlbPart) -> Result<Index<gj::Mesh>> {
        self.mesh_with_alpha(part.mesh, &part.name, None)
    }

    /// A glTF mesh of `mesh`; with `alpha` (one per vertex), colours carry it and the
    /// material blends.
    pub(crate) fn mesh_with_alpha(&mut self, mesh: &Mesh, name: &str, alpha: Option<&[f32]>) -> Result<Index<gj::Mesh>> {
        // glTF holds one UV per vertex: seam vertices are split.
        let split;
        let copied_alpha: Vec<f32>;
        let (mesh, alpha) = if mesh.uvs.is_some() {
            let source;
            (split, source) = crate::mesh::uv::split_by_uv(mesh);
            copied_alpha = alpha.map(|a| source.iter().map(|&s| a[s as usize]).collect()).unwrap_or_default();
            (&split, alpha.map(|_| copied_alpha.as_slice()))
        } else {
            (mesh, alpha)
        };
        let mut attributes = BTreeMap::new();
        let positions: Vec<[f32; 3]> = mesh.positions.iter().map(|p| p.as_vec3().to_array()).collect();
        attributes.insert(Valid(gj::mesh::Semantic::Positions), self.vec3(&positions, true));
        let normals: Vec<[f32; 3]> = match &mesh.normals {
            Some(n) => n.iter().map(|v| v.normalize_or(DVec3::Z).as_vec3().to_array()).collect(),
            None => area_weighted_normals(mesh),
        };
        attributes.insert(Valid(gj::mesh::Semantic::Normals), self.vec3(&normals, false));
        if let Some(colors) = &mesh.colors {
            let opacity = |v: usize| alpha.map_or(255, |a| (a[v].clamp(0.0, 1.0) * 255.0).round() as u8);
            let rgba: Vec<u8> = colors.iter().enumerate().flat_map(|(v, c)| [c[0], c[1], c[2], opacity(v)]).collect();
            let colors = self.accessor(
                &rgba,
                Some(gj::buffer::Target::ArrayBuffer),
                mesh.vertex_count(),
                gj::accessor::ComponentType::U8,
                gj::accessor::Type::Vec4,
                true,
                None,
            );
            attributes.insert(Valid(gj::mesh::Semantic::Colors(0)), colors);
        }
        if let Some(uvs) = &mesh.uvs {
            // glTF's v runs down the image, OBJ's and PLY's (asperity's) up.
            let st: Vec<[f32; 2]> = uvs.values.iter().map(|&[u, v]| [u as f32, (1.0 - v) as f32]).collect();
            let accessor = self.accessor(
                bytemuck::cast_slice(&st),
                Some(gj::buffer::Target::ArrayBuffer),
                st.len(),
                gj::accessor::ComponentType::F32,
                gj::accessor::Type::Vec2,
                false,
                None,
            );
            attributes.insert(Valid(gj::mesh::Semantic::TexCoords(0)), accessor);
        }
        for (name, values) in &mesh.scalars {
            let floats: Vec<f32> = values.iter().map(|&v| v as f32).collect();
            let accessor = self.accessor(
                bytemuck::cast_slice(&floats),
                Some(gj::buffer::Target::ArrayBuffer),
                floats.len(),
                gj::accessor::ComponentType::F32,
                gj::accessor::Type::Scalar,
                false,
                None,
            );
            attributes.insert(Valid(gj::mesh::Semantic::Extras(name.to_ascii_uppercase())), accessor);
        }
        let indices = self.accessor(
            bytemuck::cast_slice(&mesh.triangles),
            Some(gj::buffer::Target::ElementArrayBuffer),
            mesh.triangles.len() * 3,
            gj::accessor::ComponentType::U32,
            gj::accessor::Type::Scalar,
            false,
            None,
        );
        let material = if alpha.is_some() { self.translucent() } else { self.material() };
        Ok(self.root.push(gj::Mesh {
            name: Some(name.to_string()),
            primitives: vec![gj::mesh::Primitive {
                attributes,
                indices: Some(indices),
                material: Some(material),
                mode: Valid(gj::mesh::Mode::Triangles),
                targets: None,
                extensions: None,
                extras: None,
            }],
            weights: None,
            extensions: None,
            extras: None,
        }))
    }

    /// The GLB bytes of the document.
    pub(crate) fn finish(mut self) -> Result<Vec<u8>> {
        while self.bin.len() % 4 != 0 {
            self.bin.push(0);
        }
        if self.bin.len() > (u32::MAX as usize) - (1 << 20) {
            return Err(Error::InvalidInput(format!("{} bytes of geometry exceed a GLB file's 4 GiB", self.bin.len())));
        }
        self.root.asset.generator = Some(format!("asperity {}", env!("CARGO_PKG_VERSION")));
        self.root.push(gj::Buffer {
            byte_length: USize64::from(self.bin.len()),
            name: None,
            uri: None,
            extensions: None,
            extras: None,
        });
        let json = gj::serialize::to_vec(&self.root).map_err(|e| Error::Internal(format!("glTF JSON: {e}")))?;
        let glb = gltf::binary::Glb {
            header: gltf::binary::Header { magic: *b"glTF", version: 2, length: 0 },
            json: Cow::Owned(json),
            bin: Some(Cow::Owned(self.bin)),
        };
        glb.to_vec().map_err(|e| Error::Internal(format!("GLB container: {e}")))
    }
}

/// Area-weighted unit vertex normals (+z for isolated vertices).
fn area_weighted_normals(mesh: &Mesh) -> Vec<[f32; 3]> {
    use crate::analysis::{FaceGeometry, NormalWeighting, vertex_normals};
    let normals =
        vertex_normals(mesh, &crate::mesh::Adjacency::of(mesh), &FaceGeometry::of(mesh), NormalWeighting::Area);
    // glTF requires unit normals: a vertex without faces gets +Z.
    normals.iter().map(|n| n.try_normalize().unwrap_or(DVec3::Z).as_vec3().to_array()).collect()
}

/// The GLB container header (magic, version, total length) checked before the `gltf`
/// crate sees it: gltf 1.4.1 subtracts the header size from the declared length unchecked
/// and panics on a length below 12 (found by `make fuzz`, tests/data/fuzz/read_glb).
fn check_glb_header(bytes: &[u8], path: &Path) -> Result<()> {
    use crate::error::Location;
    if !bytes.starts_with(b"glTF") {
        return Ok(()); // JSON glTF, or not glTF at all: the crate says which
    }
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

/// Reads every triangle primitive of the default scene (or of all meshes without scenes),
/// node transforms applied, into one mesh with normals and colours when all parts have them.
/// Why an accessor's data cannot be read, if it cannot: no buffer view (sparse or
/// all-zero accessors are not read), data in an external file, no binary chunk, or a view
/// that runs past the binary chunk.
fn check_accessor_data(accessor: &gltf::Accessor, blob: Option<&[u8]>) -> std::result::Result<(), String> {
    let a = accessor.index();
    let Some(view) = accessor.view() else {
        return Err(format!("accessor {a} has no buffer view (sparse or all-zero accessors are not read)"));
    };
    match view.buffer().source() {
        gltf::buffer::Source::Uri(uri) => Err(format!(
            "accessor {a}'s data is in the external file `{}` (only data inside the .glb is read)",
            super::text::shorten(uri)
        )),
        gltf::buffer::Source::Bin => {
            let Some(blob) = blob else {
                return Err(format!("accessor {a} refers to the binary chunk, and the file has none"));
            };
            let stride = view.stride().unwrap_or(accessor.size());
            let needed = accessor.count().checked_sub(1).map_or(0, |last| last * stride + accessor.size());
            let end = view.offset() + accessor.offset() + needed;
            if end > view.offset() + view.length() || end > blob.len() {
                return Err(format!(
                    "accessor {a} needs bytes up to {end}, beyond its buffer view or the binary chunk ({} bytes)",
                    blob.len()
                ));
            }
            Ok(())
        }
    }
}

pub(crate) fn parse(bytes: &[u8], path: &Path) -> Result<super::ReadOutcome> {
    use crate::error::Location;
    check_glb_header(bytes, path)?;
    let gltf = gltf::Gltf::from_slice(bytes).map_err(|e| Error::parse(path, Location::File, format!("glTF: {e}")))?;
    let blob = gltf.blob.as_deref();
    let mut out = Mesh::default();
    let (mut normals, mut colors, mut texcoords) = (Some(Vec::new()), Some(Vec::new()), Some(Vec::new()));
    let mut some_texcoords = false;
    let mut notes = Vec::new();
    let mut dropped = 0;
    let mut stack: Vec<(gltf::Node, glam::DMat4, usize)> = match gltf.default_scene().or_else(|| gltf.scenes().next()) {
        Some(scene) => scene.nodes().map(|n| (n, glam::DMat4::IDENTITY, 0)).collect(),
        None => Vec::new(),
    };
    let node_count = gltf.nodes().len();
    while let Some((node, parent, depth)) = stack.pop() {
        if depth > node_count {
            return Err(Error::parse(path, Location::Element("node", node.index()), "the node hierarchy has a cycle"));
        }
        let local = glam::Mat4::from_cols_array_2d(&node.transform().matrix()).as_dmat4();
        let world = parent * local;
        stack.extend(node.children().map(|c| (c, world, depth + 1)));
        let Some(mesh) = node.mesh() else { continue };
        for primitive in mesh.primitives() {
            if primitive.mode() != gltf::mesh::Mode::Triangles {
                notes.push(format!("mesh {}: a {:?} primitive ignored", mesh.index(), primitive.mode()));
                continue;
            }
            let reader = primitive.reader(|buffer| match buffer.source() {
                gltf::buffer::Source::Bin => blob,
                gltf::buffer::Source::Uri(_) => None,
            });
            let element = Location::Element("mesh", mesh.index());
            let at_primitive =
                |msg: String| Error::parse(path, element.clone(), format!("primitive {}: {msg}", primitive.index()));
            for (what, accessor) in
                [("POSITION", primitive.get(&gltf::Semantic::Positions)), ("the indices", primitive.indices())]
            {
                if let Some(accessor) = accessor {
                    check_accessor_data(&accessor, blob).map_err(|m| at_primitive(format!("{what}: {m}")))?;
                }
            }
            let positions: Vec<DVec3> = reader
                .read_positions()
                .ok_or_else(|| at_primitive("no POSITION attribute (a triangle primitive needs one)".into()))?
                .map(|p| world.transform_point3(glam::Vec3::from(p).as_dvec3()))
                .collect();
            let base = out.positions.len() as u32;
            let count = positions.len() as u32;
            let indices: Vec<u32> = match reader.read_indices() {
                Some(i) => i.into_u32().collect(),
                None => (0..count).collect(),
            };
            if indices.len() % 3 != 0 {
                return Err(at_primitive(format!("{} triangle indices are not a multiple of 3", indices.len())));
            }
            for (k, t) in indices.chunks_exact(3).enumerate() {
                if let Err(msg) = super::check_polygon(t, positions.len()) {
                    return Err(at_primitive(format!("triangle {k}: {msg}")));
                }
                let t = [t[0], t[1], t[2]];
                if crate::mesh::repeats_a_vertex(t) {
                    dropped += 1;
                    continue;
                }
                out.triangles.push(t.map(|v| base + v));
            }
            normals = match (normals, reader.read_normals()) {
                (Some(mut all), Some(n)) => {
                    all.extend(n.map(|v| world.transform_vector3(glam::Vec3::from(v).as_dvec3()).normalize_or_zero()));
                    Some(all)
                }
                _ => None,
            };
            let primitive_texcoords = reader.read_tex_coords(0);
            some_texcoords |= primitive_texcoords.is_some();
            texcoords = match (texcoords, primitive_texcoords) {
                // glTF's v runs down the image, asperity's up.
                (Some(mut all), Some(t)) => {
                    all.extend(t.into_f32().map(|[s, t]| [f64::from(s), 1.0 - f64::from(t)]));
                    Some(all)
                }
                _ => None,
            };
            colors = match (colors, reader.read_colors(0)) {
                (Some(mut all), Some(c)) => {
                    all.extend(c.into_rgb_u8());
                    Some(all)
                }
                _ => None,
            };
            out.positions.extend(positions);
        }
    }
    if out.positions.is_empty() {
        return Err(Error::parse(path, Location::File, "no triangle mesh in the default scene"));
    }
    out.normals = normals.filter(|n| n.len() == out.positions.len());
    out.colors = colors.filter(|c| c.len() == out.positions.len());
    out.uvs = texcoords
        .filter(|t| t.len() == out.positions.len())
        .map(|t| crate::mesh::uv::CornerUvs::per_vertex(t, &out.triangles));
    if some_texcoords && out.uvs.is_none() {
        notes.push("TEXCOORD_0 on only some primitives: ignored (every vertex needs one)".to_string());
    }
    notes.extend(super::repeated_vertex_note(dropped));
    Ok(super::ReadOutcome { mesh: out, triangulated_polygons: 0, notes })
}
