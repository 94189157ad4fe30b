//! glTF 2.0 output through the `gltf` crate's JSON model: binary (`.glb`, the GLB
//! container) or text (`.gltf`, its one buffer embedded as a base64 `data:` URI, so the file
//! stands alone). Positions, normals (the mesh's own, or area-weighted), vertex colours, and
//! per-vertex scalars as application attributes (`_MEAN_CURVATURE`, ...). Several meshes (the
//! levels of a hierarchy) become one node each, side by side along x, with node extras naming
//! the level. Coordinates are stored as f32, as glTF requires; a mesh far from the origin for
//! its size (geographic coordinates) is stored about its centre, which becomes its node's
//! translation, so its faces keep their shape (#36: at 1e6, 16 of 320 faces collapsed).

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

/// Writes one mesh as a `.glb` (or `.gltf`) file, atomically.
///
/// # Errors
/// [`Error::InvalidInput`] for an empty mesh or one too large for a GLB (4 GiB);
/// [`Error::Io`] naming the file.
pub fn write_glb(mesh: &Mesh, path: &Path) -> Result<()> {
    write_mesh(mesh, path, is_text(path))
}

/// Writes one mesh as glTF text (`text`) or GLB, whatever `path`'s extension.
pub(crate) fn write_mesh(mesh: &Mesh, path: &Path, text: bool) -> Result<()> {
    let name = path.file_stem().map_or("mesh".into(), |s| s.to_string_lossy().into_owned());
    write_parts(&[GlbPart { mesh, name, extras: serde_json::Value::Null }], path, text)
}

fn is_text(path: &Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("gltf"))
}

/// Writes several meshes as nodes of one `.glb` scene (a `.gltf` one when `path` ends so),
/// placed left to right along x with a gap of a tenth of the widest one, atomically.
///
/// # Errors
/// As [`write_glb`].
pub fn write_glb_parts(parts: &[GlbPart], path: &Path) -> Result<()> {
    write_parts(parts, path, is_text(path))
}

fn write_parts(parts: &[GlbPart], path: &Path, text: bool) -> Result<()> {
    for part in parts {
        super::fits_single_precision(part.mesh, path, origin_of(part.mesh))?;
    }
    let bytes = if text { builder_of(parts)?.finish_text()? } else { glb_bytes(parts)? };
    write_atomically(path, |out| out.write_all(&bytes))
}

/// The GLB file contents for `parts`.
///
/// # Errors
/// As [`write_glb`].
pub fn glb_bytes(parts: &[GlbPart]) -> Result<Vec<u8>> {
    builder_of(parts)?.finish()
}

/// Where a mesh is stored from: the origin, or, for a mesh farther from it than 16 times its
/// diagonal (where f32 keeps fewer than 20 bits of the mesh's own size), the centre of its
/// box rounded to f32, so that the node's f32 translation holds it exactly.
pub(crate) fn origin_of(mesh: &Mesh) -> DVec3 {
    let Some((lo, hi)) = mesh.bounding_box() else { return DVec3::ZERO };
    let far = lo.abs().max(hi.abs()).max_element();
    if far > 16.0 * (hi - lo).length() { ((lo + hi) * 0.5).as_vec3().as_dvec3() } else { DVec3::ZERO }
}

fn builder_of(parts: &[GlbPart]) -> Result<Builder> {
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
        let origin = origin_of(part.mesh);
        let mesh = builder.mesh_with_alpha(part.mesh, &part.name, None, origin)?;
        let extras = match &part.extras {
            serde_json::Value::Null => None,
            value => Some(serde_json::value::to_raw_value(value).map_err(|e| Error::Internal(e.to_string()))?),
        };
        let offset = if parts.len() > 1 { x - lo.x } else { 0.0 };
        let translation = (origin + DVec3::new(offset, 0.0, 0.0)).as_vec3().to_array();
        nodes.push(builder.root.push(gj::Node {
            mesh: Some(mesh),
            name: Some(part.name.clone()),
            extras,
            translation: (translation != [0.0; 3]).then_some(translation),
            ..Default::default()
        }));
        x += (hi.x - lo.x) + 0.1 * width;
    }
    let scene = builder.root.push(gj::Scene { nodes, name: Some("asperity".into()), extensions: None, extras: None });
    builder.root.scene = Some(scene);
    Ok(builder)
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
        while !self.bin.len().is_multiple_of(4) {
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

    /// A glTF mesh of `mesh`, its positions stored from `origin` (which its node's
    /// translation must add back); with `alpha` (one per vertex), colours carry it and the
    /// material blends.
    pub(crate) fn mesh_with_alpha(
        &mut self,
        mesh: &Mesh,
        name: &str,
        alpha: Option<&[f32]>,
        origin: DVec3,
    ) -> Result<Index<gj::Mesh>> {
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
        let positions: Vec<[f32; 3]> = mesh.positions.iter().map(|&p| (p - origin).as_vec3().to_array()).collect();
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

    /// The document with its one buffer declared: inside the GLB container (`uri` none) or
    /// embedded as a `data:` URI.
    fn close(&mut self, uri: Option<String>) -> Result<Vec<u8>> {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        if self.bin.len() > (u32::MAX as usize) - (1 << 20) {
            return Err(Error::InvalidInput(format!(
                "{} bytes of geometry exceed a glTF file's 4 GiB",
                self.bin.len()
            )));
        }
        self.root.asset.generator = Some(format!("asperity {}", env!("CARGO_PKG_VERSION")));
        self.root.push(gj::Buffer {
            byte_length: USize64::from(self.bin.len()),
            name: None,
            uri,
            extensions: None,
            extras: None,
        });
        gj::serialize::to_vec(&self.root).map_err(|e| Error::Internal(format!("glTF JSON: {e}")))
    }

    /// The `.gltf` text of the document, its buffer embedded.
    pub(crate) fn finish_text(mut self) -> Result<Vec<u8>> {
        let uri = super::gltf_read::data_uri(&self.bin);
        self.close(Some(uri))
    }

    /// The GLB bytes of the document.
    pub(crate) fn finish(mut self) -> Result<Vec<u8>> {
        let json = self.close(None)?;
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
