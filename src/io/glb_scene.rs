//! glTF 2.0 scenes with node hierarchies and keyframe animation (`.glb`): the output of
//! the procedural scene generators. Meshes may carry per-vertex opacity (blended
//! material); nodes carry translation, rotation and scale; tracks animate them, linearly
//! or in steps. A sequence of frames (one mesh per frame) plays as frame nodes whose scale
//! steps between 0 and 1, so any viewer shows one frame at a time.

use std::collections::BTreeMap;
use std::path::Path;

use glam::{DQuat, DVec3};
use gltf::json::validation::Checked::Valid;
use gltf::json::{self as gj, Index};

use super::glb::Builder;
use super::write_atomically;
use crate::error::{Error, Result};
use crate::mesh::Mesh;

/// A mesh of the scene.
pub struct SceneMesh<'a> {
    /// The mesh.
    pub mesh: &'a Mesh,
    /// Its name.
    pub name: String,
    /// Per-vertex opacity (0 to 1), when the mesh is translucent.
    pub alpha: Option<Vec<f32>>,
}

/// A node: a transform, an optional mesh (index into the scene's meshes) and children.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneNode {
    /// Name.
    pub name: String,
    /// Index into [`GlbScene::meshes`].
    pub mesh: Option<usize>,
    /// Translation.
    pub translation: DVec3,
    /// Rotation.
    pub rotation: DQuat,
    /// Scale.
    pub scale: DVec3,
    /// Indices into [`GlbScene::nodes`].
    pub children: Vec<usize>,
}

impl SceneNode {
    /// A node at the origin, unrotated, unscaled.
    pub fn new(name: impl Into<String>, mesh: Option<usize>) -> Self {
        SceneNode {
            name: name.into(),
            mesh,
            translation: DVec3::ZERO,
            rotation: DQuat::IDENTITY,
            scale: DVec3::ONE,
            children: Vec::new(),
        }
    }
}

/// Keyframe values of one animated property.
#[derive(Debug, Clone, PartialEq)]
pub enum Keys {
    /// Translations.
    Translation(Vec<DVec3>),
    /// Rotations (normalised on writing).
    Rotation(Vec<DQuat>),
    /// Scales.
    Scale(Vec<DVec3>),
}

/// One animated property of one node.
#[derive(Debug, Clone, PartialEq)]
pub struct Track {
    /// Index into [`GlbScene::nodes`].
    pub node: usize,
    /// Key times in seconds, strictly increasing.
    pub times: Vec<f64>,
    /// Values, one per time.
    pub keys: Keys,
    /// Step (hold each value) rather than linear interpolation.
    pub step: bool,
}

/// A scene: meshes, nodes, the root nodes and one animation.
#[derive(Default)]
pub struct GlbScene<'a> {
    /// Meshes.
    pub meshes: Vec<SceneMesh<'a>>,
    /// Nodes.
    pub nodes: Vec<SceneNode>,
    /// The scene's top-level nodes.
    pub roots: Vec<usize>,
    /// Tracks of the scene's animation (none: no animation).
    pub tracks: Vec<Track>,
}

impl<'a> GlbScene<'a> {
    /// Adds a mesh; returns its index.
    pub fn add_mesh(&mut self, mesh: &'a Mesh, name: impl Into<String>, alpha: Option<Vec<f32>>) -> usize {
        self.meshes.push(SceneMesh { mesh, name: name.into(), alpha });
        self.meshes.len() - 1
    }

    /// Adds a node (a child of `parent`, or a root); returns its index.
    pub fn add_node(&mut self, node: SceneNode, parent: Option<usize>) -> usize {
        self.nodes.push(node);
        let index = self.nodes.len() - 1;
        match parent {
            Some(p) => self.nodes[p].children.push(index),
            None => self.roots.push(index),
        }
        index
    }

    /// A group node holding one child per mesh of `frames` (`None`: an empty frame), shown
    /// one at a time at `fps` frames per second (the first when the animation is not
    /// played).
    pub fn add_frames(&mut self, name: &str, frames: &[Option<usize>], fps: f64, parent: Option<usize>) -> usize {
        let group = self.add_node(SceneNode::new(name, None), parent);
        let count = frames.len();
        for (k, &mesh) in frames.iter().enumerate() {
            let mut node = SceneNode::new(format!("{name}_frame_{k:03}"), mesh);
            if k > 0 {
                node.scale = DVec3::ZERO;
            }
            let node = self.add_node(node, Some(group));
            if count < 2 {
                continue;
            }
            let at = |f: usize| f as f64 / fps;
            let (times, values): (Vec<f64>, Vec<f64>) = if k == 0 {
                (vec![0.0, at(1)], vec![1.0, 0.0])
            } else if k + 1 == count {
                (vec![0.0, at(k)], vec![0.0, 1.0])
            } else {
                (vec![0.0, at(k), at(k + 1)], vec![0.0, 1.0, 0.0])
            };
            let keys = Keys::Scale(values.into_iter().map(DVec3::splat).collect());
            self.tracks.push(Track { node, times, keys, step: true });
        }
        group
    }
}

/// The `.glb` bytes of `scene`.
///
/// # Errors
/// [`Error::InvalidInput`] for an empty mesh, a node or mesh index out of range, a track
/// whose times are not strictly increasing or do not match its values, or more than 4 GiB.
pub fn scene_glb_bytes(scene: &GlbScene) -> Result<Vec<u8>> {
    let mut builder = Builder::default();
    let mut meshes = Vec::with_capacity(scene.meshes.len());
    for part in &scene.meshes {
        part.mesh.check()?;
        if part.mesh.triangles.is_empty() {
            return Err(Error::InvalidInput(format!("{}: no faces to write", part.name)));
        }
        if part.alpha.as_ref().is_some_and(|a| a.len() != part.mesh.vertex_count()) {
            return Err(Error::InvalidInput(format!("{}: one opacity per vertex needed", part.name)));
        }
        meshes.push(builder.mesh_with_alpha(part.mesh, &part.name, part.alpha.as_deref(), DVec3::ZERO)?);
    }
    let node_count = scene.nodes.len();
    let in_range = |i: usize, what: &str| {
        if i < node_count { Ok(Index::new(i as u32)) } else { Err(Error::InvalidInput(format!("{what}: node {i} of {node_count}"))) }
    };
    for node in &scene.nodes {
        let mesh = match node.mesh {
            Some(m) => Some(*meshes.get(m).ok_or_else(|| Error::InvalidInput(format!("{}: no mesh {m}", node.name)))?),
            None => None,
        };
        let children = node.children.iter().map(|&c| in_range(c, &node.name)).collect::<Result<Vec<_>>>()?;
        let rotation = node.rotation.normalize();
        builder.root.push(gj::Node {
            mesh,
            name: Some(node.name.clone()),
            translation: (node.translation != DVec3::ZERO).then(|| node.translation.as_vec3().to_array()),
            rotation: (rotation != DQuat::IDENTITY).then(|| gj::scene::UnitQuaternion(rotation.as_quat().to_array())),
            scale: (node.scale != DVec3::ONE).then(|| node.scale.as_vec3().to_array()),
            children: (!children.is_empty()).then_some(children),
            ..Default::default()
        });
    }
    let roots = scene.roots.iter().map(|&r| in_range(r, "scene root")).collect::<Result<Vec<_>>>()?;
    let root_scene = builder.root.push(gj::Scene { nodes: roots, name: Some("asperity".into()), extensions: None, extras: None });
    builder.root.scene = Some(root_scene);
    if !scene.tracks.is_empty() {
        let animation = animation(&mut builder, &scene.tracks, node_count)?;
        builder.root.push(animation);
    }
    builder.finish()
}

/// Writes `scene` as a `.glb` file, atomically.
///
/// # Errors
/// As [`scene_glb_bytes`]; [`Error::Io`] naming the file.
pub fn write_scene_glb(scene: &GlbScene, path: &Path) -> Result<()> {
    for part in &scene.meshes {
        super::fits_single_precision(part.mesh, path, glam::DVec3::ZERO)?;
    }
    let bytes = scene_glb_bytes(scene)?;
    write_atomically(path, |out| out.write_all(&bytes))
}

/// One animation with a sampler and a channel per track; equal time lists share one
/// accessor.
fn animation(builder: &mut Builder, tracks: &[Track], node_count: usize) -> Result<gj::Animation> {
    use gj::accessor::{ComponentType, Type};
    let mut time_accessors: BTreeMap<Vec<u64>, Index<gj::Accessor>> = BTreeMap::new();
    let (mut samplers, mut channels) = (Vec::new(), Vec::new());
    for (i, track) in tracks.iter().enumerate() {
        let bad = |msg: &str| Err(Error::InvalidInput(format!("animation track {i}: {msg}")));
        if track.node >= node_count {
            return bad("no such node");
        }
        let count = match &track.keys {
            Keys::Translation(v) | Keys::Scale(v) => v.len(),
            Keys::Rotation(v) => v.len(),
        };
        if track.times.is_empty() || count != track.times.len() {
            return bad("one value per key time needed");
        }
        if !track.times.windows(2).all(|w| w[0] < w[1]) || !track.times.iter().all(|t| t.is_finite() && *t >= 0.0) {
            return bad("key times must be finite, at least 0 and strictly increasing");
        }
        let times: Vec<f32> = track.times.iter().map(|&t| t as f32).collect();
        if !times.windows(2).all(|w| w[0] < w[1]) {
            return bad("key times too close for single precision");
        }
        let key: Vec<u64> = times.iter().map(|t| u64::from(t.to_bits())).collect();
        let input = match time_accessors.get(&key) {
            Some(&a) => a,
            None => {
                let (lo, hi) = (times[0], times[times.len() - 1]);
                // Animation inputs need their bounds; animation data has no buffer target.
                let bounds = Some((vec![lo], vec![hi]));
                let a = builder.accessor(bytemuck::cast_slice(&times), None, times.len(), ComponentType::F32, Type::Scalar, false, bounds);
                time_accessors.insert(key, a);
                a
            }
        };
        let (values, kind, path): (Vec<f32>, Type, gj::animation::Property) = match &track.keys {
            Keys::Translation(v) => {
                (v.iter().flat_map(|p| p.as_vec3().to_array()).collect(), Type::Vec3, gj::animation::Property::Translation)
            }
            Keys::Scale(v) => (v.iter().flat_map(|p| p.as_vec3().to_array()).collect(), Type::Vec3, gj::animation::Property::Scale),
            Keys::Rotation(v) => (
                v.iter().flat_map(|q| q.normalize().as_quat().to_array()).collect(),
                Type::Vec4,
                gj::animation::Property::Rotation,
            ),
        };
        let output = builder.accessor(bytemuck::cast_slice(&values), None, count, ComponentType::F32, kind, false, None);
        samplers.push(gj::animation::Sampler {
            input,
            interpolation: Valid(if track.step {
                gj::animation::Interpolation::Step
            } else {
                gj::animation::Interpolation::Linear
            }),
            output,
            extensions: None,
            extras: None,
        });
        channels.push(gj::animation::Channel {
            sampler: Index::new(i as u32),
            target: gj::animation::Target {
                node: Index::new(track.node as u32),
                path: Valid(path),
                extensions: None,
                extras: None,
            },
            extensions: None,
            extras: None,
        });
    }
    Ok(gj::Animation { name: Some("scene".into()), channels, samplers, extensions: None, extras: None })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_show_one_at_a_time_and_empty_frames_have_no_mesh() {
        let cube = crate::mesh::primitives::cube(DVec3::ZERO, DVec3::ONE, 1);
        let mut doc = GlbScene::default();
        let mesh = doc.add_mesh(&cube, "cube", None);
        let group = doc.add_frames("f", &[Some(mesh), None, Some(mesh)], 10.0, None);
        assert_eq!(doc.nodes[group].children.len(), 3);
        let frames: Vec<&SceneNode> = doc.nodes[group].children.iter().map(|&c| &doc.nodes[c]).collect();
        assert_eq!(frames.iter().map(|n| n.mesh).collect::<Vec<_>>(), [Some(mesh), None, Some(mesh)]);
        assert_eq!(frames[0].scale, DVec3::ONE, "the first frame shows without the animation");
        assert!(frames[1..].iter().all(|n| n.scale == DVec3::ZERO));
        // Frame k is scaled 1 from k/fps and 0 again from (k+1)/fps, in steps.
        let middle = doc.tracks.iter().find(|t| t.node == doc.nodes[group].children[1]).unwrap();
        assert_eq!(middle.times, [0.0, 0.1, 0.2]);
        assert_eq!(middle.keys, Keys::Scale(vec![DVec3::ZERO, DVec3::ONE, DVec3::ZERO]));
        assert!(middle.step);
        let bytes = scene_glb_bytes(&doc).unwrap();
        let gltf = gltf::Gltf::from_slice(&bytes).unwrap();
        assert_eq!(gltf.animations().next().unwrap().channels().count(), 3);
    }

    #[test]
    fn tracks_with_bad_times_are_refused() {
        let mut doc = GlbScene::default();
        let node = doc.add_node(SceneNode::new("n", None), None);
        doc.tracks.push(Track { node, times: vec![0.0, 0.0], keys: Keys::Translation(vec![DVec3::ZERO; 2]), step: false });
        assert!(scene_glb_bytes(&doc).unwrap_err().to_string().contains("strictly increasing"));
        doc.tracks[0] = Track { node: 7, times: vec![0.0], keys: Keys::Translation(vec![DVec3::ZERO]), step: false };
        assert!(scene_glb_bytes(&doc).is_err());
    }
}
