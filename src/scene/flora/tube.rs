//! Branch tubes: each chain of internal nodes (a node and, repeatedly, its most upright
//! internal child) is one generalised cylinder — a ring of vertices at its start, at every
//! joint (across the bisector of the two segments, so a bend does not pinch) and at its
//! end — closed by a fan at both ends. Rings are framed by parallel transport (the
//! rotation-minimising frame), so tubes do not twist. A chain that branches off starts
//! inside its parent's tube, so the two meet without a gap.

use glam::{DQuat, DVec3};

use super::{FloraRules, Node};
use crate::mesh::Mesh;

/// The tubes of every chain of internal nodes, bark-coloured.
pub(super) fn branches(nodes: &[Node], rules: &FloraRules, sides: u32) -> Mesh {
    let internal = |i: usize| !nodes[i].children.is_empty();
    // Each internal node's continuation: its least pitched internal child.
    let continuation: Vec<Option<usize>> = nodes
        .iter()
        .map(|n| {
            n.children
                .iter()
                .copied()
                .filter(|&c| internal(c))
                .min_by(|&a, &b| nodes[a].pitch.total_cmp(&nodes[b].pitch).then(a.cmp(&b)))
        })
        .collect();
    let mut parent = vec![None; nodes.len()];
    for (i, n) in nodes.iter().enumerate() {
        for &c in &n.children {
            parent[c] = Some(i);
        }
    }
    let mut mesh = Mesh::default();
    for (start, &parent_of_start) in parent.iter().enumerate() {
        let continues_parent = parent_of_start.is_some_and(|p| continuation[p] == Some(start));
        if !internal(start) || continues_parent {
            continue;
        }
        let mut chain = vec![start];
        while let Some(next) = continuation[*chain.last().expect("non-empty")] {
            chain.push(next);
        }
        let sunk = parent_of_start.map_or(0.0, |p| 0.8 * nodes[p].radius);
        tube(&mut mesh, &chain.iter().map(|&i| &nodes[i]).collect::<Vec<_>>(), rules.taper, sunk, sides);
    }
    mesh.colors = Some(vec![rules.bark; mesh.vertex_count()]);
    mesh
}

/// Appends one closed tube along `chain`, its start moved back `sunk` along its axis.
fn tube(mesh: &mut Mesh, chain: &[&Node], taper: f64, sunk: f64, sides: u32) {
    let first = chain[0];
    let last = chain[chain.len() - 1];
    let mut rings: Vec<(DVec3, DVec3, f64)> = vec![(first.base - first.axis() * sunk, first.axis(), first.radius)];
    for pair in chain.windows(2) {
        let direction = (pair[0].axis() + pair[1].axis()).try_normalize().unwrap_or(pair[1].axis());
        rings.push((pair[1].base, direction, pair[1].radius));
    }
    rings.push((last.tip(), last.axis(), last.radius * taper));
    let start = mesh.positions.len() as u32;
    let mut side = rings[0].1.any_orthonormal_vector();
    let mut previous = rings[0].1;
    for &(centre, direction, radius) in &rings {
        side = DQuat::from_rotation_arc(previous, direction) * side;
        side = (side - direction * side.dot(direction)).normalize();
        previous = direction;
        let binormal = direction.cross(side);
        for k in 0..sides {
            let angle = std::f64::consts::TAU * f64::from(k) / f64::from(sides);
            mesh.positions.push(centre + radius * (side * angle.cos() + binormal * angle.sin()));
        }
    }
    let at = |ring: usize, k: u32| start + ring as u32 * sides + k % sides;
    for ring in 0..rings.len() - 1 {
        for k in 0..sides {
            let (a, b, c, d) = (at(ring, k), at(ring, k + 1), at(ring + 1, k + 1), at(ring + 1, k));
            mesh.triangles.push([a, b, c]);
            mesh.triangles.push([a, c, d]);
        }
    }
    let base = mesh.positions.len() as u32;
    mesh.positions.push(rings[0].0);
    let top = base + 1;
    mesh.positions.push(rings[rings.len() - 1].0);
    let end = rings.len() - 1;
    for k in 0..sides {
        mesh.triangles.push([base, at(0, k + 1), at(0, k)]);
        mesh.triangles.push([top, at(end, k), at(end, k + 1)]);
    }
}
