//! Which meshes a glTF document draws, and where (glTF 2.0 §3.5 "Scenes", §3.5.3
//! "Transformations"; the `EXT_mesh_gpu_instancing` extension): the default scene's node
//! trees walked from their roots, each node's transform (matrix, or translation × rotation ×
//! scale) composed with its parent's, and each instance of an instanced node composed under
//! its node. The node hierarchy must be a set of disjoint trees, as the specification requires:
//! a node listed as a child twice would draw its subtree twice per listing, which a kilobyte
//! of JSON can turn into 2²⁴ copies.

use glam::{DMat4, DQuat, DVec3};

use super::accessor::{Accessors, Use};
use crate::error::Location;

/// One drawing of a mesh: its index and world transform.
pub(super) struct Instance {
    pub(super) mesh: usize,
    pub(super) world: DMat4,
}

/// A located error: the element of the file and the message.
pub(super) type Located = (Location, String);

fn node_error(node: usize, msg: impl Into<String>) -> Located {
    (Location::Element("node", node), msg.into())
}

/// Every mesh the default scene draws (the first scene when none is marked default; every
/// root node when the file has no scene; every mesh once when it has no node either).
pub(super) fn instances(
    root: &gltf::json::Root,
    accessors: &Accessors,
    json: &serde_json::Value,
) -> Result<Vec<Instance>, Located> {
    let parents = parents(root)?;
    let roots: Vec<usize> = match root.scene.map(|s| s.value()).or((!root.scenes.is_empty()).then_some(0)) {
        Some(s) => {
            let scene =
                root.scenes.get(s).ok_or_else(|| (Location::File, format!("the default scene {s} does not exist")))?;
            let mut listed = std::collections::HashSet::new();
            let mut roots = Vec::new();
            for node in &scene.nodes {
                let n = node.value();
                if n >= root.nodes.len() {
                    return Err((Location::Element("scene", s), format!("node {n} does not exist")));
                }
                if let Some(p) = parents[n] {
                    return Err((
                        Location::Element("scene", s),
                        format!("lists node {n} as a root, but it is a child of node {p}"),
                    ));
                }
                if !listed.insert(n) {
                    return Err((Location::Element("scene", s), format!("lists node {n} twice")));
                }
                roots.push(n);
            }
            roots
        }
        None if root.nodes.is_empty() => {
            return Ok((0..root.meshes.len()).map(|mesh| Instance { mesh, world: DMat4::IDENTITY }).collect());
        }
        None => (0..root.nodes.len()).filter(|&n| parents[n].is_none()).collect(),
    };
    let mut out = Vec::new();
    let mut stack: Vec<(usize, DMat4)> = roots.into_iter().rev().map(|n| (n, DMat4::IDENTITY)).collect();
    while let Some((n, parent)) = stack.pop() {
        let node = &root.nodes[n];
        let world = parent * local_transform(node);
        if !world.is_finite() {
            return Err(node_error(
                n,
                "its transform is not finite (a zero rotation quaternion, or numbers beyond f64)",
            ));
        }
        if let Some(children) = &node.children {
            stack.extend(children.iter().rev().map(|c| (c.value(), world)));
        }
        let Some(mesh) = node.mesh.map(|m| m.value()) else { continue };
        if mesh >= root.meshes.len() {
            return Err(node_error(n, format!("mesh {mesh} does not exist (the file has {})", root.meshes.len())));
        }
        match gpu_instances(json, n, accessors)? {
            None => out.push(Instance { mesh, world }),
            Some(locals) => {
                if let Some(k) = locals.iter().position(|m| !m.is_finite()) {
                    return Err(node_error(
                        n,
                        format!("EXT_mesh_gpu_instancing: instance {k}'s transform is not finite (a zero rotation?)"),
                    ));
                }
                out.extend(locals.into_iter().map(|local| Instance { mesh, world: world * local }));
            }
        }
    }
    Ok(out)
}

/// Each node's parent, checking that the nodes form disjoint trees.
fn parents(root: &gltf::json::Root) -> Result<Vec<Option<usize>>, Located> {
    let count = root.nodes.len();
    let mut parents = vec![None; count];
    for (n, node) in root.nodes.iter().enumerate() {
        for child in node.children.iter().flatten() {
            let c = child.value();
            if c >= count {
                return Err(node_error(n, format!("child {c} does not exist (the file has {count} nodes)")));
            }
            if c == n {
                return Err(node_error(n, "is its own child"));
            }
            if parents[c] == Some(n) {
                return Err(node_error(n, format!("lists node {c} as a child twice: glTF's nodes form trees")));
            }
            if let Some(p) = parents[c] {
                return Err(node_error(
                    n,
                    format!(
                        "lists node {c} as a child, which node {p} lists too: glTF's nodes form trees, one parent each"
                    ),
                ));
            }
            parents[c] = Some(n);
        }
    }
    // With one parent each, a cycle has no root above it: walking up from each node, marking
    // the nodes with where the walk started, meets its own mark only on a cycle. Every node
    // is marked once.
    let mut mark = vec![usize::MAX; count];
    for start in 0..count {
        let mut at = start;
        while mark[at] == usize::MAX {
            mark[at] = start;
            match parents[at] {
                Some(p) => at = p,
                None => break,
            }
        }
        if mark[at] == start && parents[at].is_some() {
            return Err(node_error(at, "is its own ancestor (the node hierarchy has a cycle)"));
        }
    }
    Ok(parents)
}

/// A node's local transform: its matrix, or T × R × S.
fn local_transform(node: &gltf::json::Node) -> DMat4 {
    if let Some(m) = node.matrix {
        return DMat4::from_cols_array(&m.map(f64::from));
    }
    let t = node.translation.map_or(DVec3::ZERO, |t| DVec3::from(t.map(f64::from)));
    let r = node.rotation.map_or(DQuat::IDENTITY, |r| {
        let [x, y, z, w] = r.0.map(f64::from);
        DQuat::from_xyzw(x, y, z, w).normalize()
    });
    let s = node.scale.map_or(DVec3::ONE, |s| DVec3::from(s.map(f64::from)));
    DMat4::from_scale_rotation_translation(s, r, t)
}

/// The instance transforms of node `n` under `EXT_mesh_gpu_instancing`, if it has them.
fn gpu_instances(json: &serde_json::Value, n: usize, accessors: &Accessors) -> Result<Option<Vec<DMat4>>, Located> {
    let Some(attributes) = json
        .get("nodes")
        .and_then(|nodes| nodes.get(n))
        .and_then(|node| node.pointer("/extensions/EXT_mesh_gpu_instancing/attributes"))
    else {
        return Ok(None);
    };
    let at_node = |m: String| node_error(n, format!("EXT_mesh_gpu_instancing: {m}"));
    let read = |name: &str, use_: Use| -> Result<Option<Vec<f64>>, Located> {
        let Some(value) = attributes.get(name) else { return Ok(None) };
        let index = value.as_u64().ok_or_else(|| at_node(format!("{name} is not an accessor index")))?;
        accessors.read(index as usize, use_).map(|(v, _)| Some(v)).map_err(|m| at_node(format!("{name}: {m}")))
    };
    let translation = read("TRANSLATION", Use::InstanceTranslation)?;
    let rotation = read("ROTATION", Use::InstanceRotation)?;
    let scale = read("SCALE", Use::InstanceScale)?;
    let counts: Vec<usize> = [(&translation, 3), (&rotation, 4), (&scale, 3)]
        .iter()
        .filter_map(|(values, n)| values.as_ref().map(|v| v.len() / n))
        .collect();
    let Some(&count) = counts.first() else {
        return Err(at_node("no TRANSLATION, ROTATION or SCALE attribute".into()));
    };
    if counts.iter().any(|&c| c != count) {
        return Err(at_node(format!("its attributes count different numbers of instances ({counts:?})")));
    }
    crate::memory::ensure_available(
        (count as u64).saturating_mul(std::mem::size_of::<Instance>() as u64),
        &format!("{count} instances"),
        "read a smaller scene",
    )
    .map_err(|e| at_node(e.to_string()))?;
    Ok(Some(
        (0..count)
            .map(|i| {
                let t = translation.as_ref().map_or(DVec3::ZERO, |v| DVec3::new(v[3 * i], v[3 * i + 1], v[3 * i + 2]));
                let r = rotation.as_ref().map_or(DQuat::IDENTITY, |v| {
                    DQuat::from_xyzw(v[4 * i], v[4 * i + 1], v[4 * i + 2], v[4 * i + 3]).normalize()
                });
                let s = scale.as_ref().map_or(DVec3::ONE, |v| DVec3::new(v[3 * i], v[3 * i + 1], v[3 * i + 2]));
                DMat4::from_scale_rotation_translation(s, r, t)
            })
            .collect(),
    ))
}
