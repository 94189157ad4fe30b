//! Consistent signs for a line field (a direction per vertex, defined up to sign, such as the
//! diffusion direction of the voting tensor): the propagation Hoppe et al. (1992, §3.3)
//! orient tangent planes with. Starting from the lowest vertex id of each component, the
//! field is carried along a maximum spanning tree whose edge weights are |dᵤ·dᵥ|, flipping
//! each newly reached vertex to agree with the vertex it is reached from. Nearly parallel
//! neighbours are joined first, so sign changes remain only where the field itself turns
//! (and where a closed surface forces one), not between vertices that point the same way.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use glam::DVec3;

use crate::mesh::Adjacency;

/// A candidate tree edge: reach `to` from `from`, whose alignment is `weight`.
#[derive(PartialEq)]
struct Reach {
    weight: f64,
    to: u32,
    from: u32,
}

impl Eq for Reach {}

impl Ord for Reach {
    fn cmp(&self, other: &Self) -> Ordering {
        // The heaviest first; ties by the lowest ids, so the tree is the same every run.
        self.weight.total_cmp(&other.weight).then(other.to.cmp(&self.to)).then(other.from.cmp(&self.from))
    }
}

impl PartialOrd for Reach {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// Flips entries of `field` (one per vertex of `adjacency`) so that vertices joined by the
/// maximum spanning tree of |dᵤ·dᵥ| agree in sign. Zero vectors are left as they are and
/// carry no orientation.
pub fn orient_line_field(field: &mut [DVec3], adjacency: &Adjacency) {
    let n = field.len();
    let mut reached = vec![false; n];
    let mut heap = BinaryHeap::new();
    for root in 0..n {
        if reached[root] {
            continue;
        }
        reached[root] = true;
        push_neighbours(root, field, adjacency, &reached, &mut heap);
        while let Some(Reach { to, from, .. }) = heap.pop() {
            let (to, from) = (to as usize, from as usize);
            if reached[to] {
                continue;
            }
            reached[to] = true;
            if field[to].dot(field[from]) < 0.0 {
                field[to] = -field[to];
            }
            push_neighbours(to, field, adjacency, &reached, &mut heap);
        }
    }
}

fn push_neighbours(v: usize, field: &[DVec3], adjacency: &Adjacency, reached: &[bool], heap: &mut BinaryHeap<Reach>) {
    for &u in adjacency.neighbours(v) {
        if !reached[u as usize] {
            heap.push(Reach { weight: field[v].dot(field[u as usize]).abs(), to: u, from: v as u32 });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Mesh;

    #[test]
    fn a_strip_with_random_signs_comes_out_consistent() {
        // A strip of 2 × 12 vertices whose field turns slowly along it, signs scrambled.
        let mut positions = Vec::new();
        for i in 0..12 {
            positions.push(DVec3::new(f64::from(i), 0.0, 0.0));
            positions.push(DVec3::new(f64::from(i), 1.0, 0.0));
        }
        let mut triangles = Vec::new();
        for i in 0..11u32 {
            triangles.push([2 * i, 2 * i + 2, 2 * i + 1]);
            triangles.push([2 * i + 1, 2 * i + 2, 2 * i + 3]);
        }
        let mesh = Mesh::new(positions, triangles);
        let adjacency = Adjacency::of(&mesh);
        let mut field: Vec<DVec3> = (0..24)
            .map(|v| {
                let angle = f64::from(v / 2) * 0.1;
                let d = DVec3::new(angle.cos(), angle.sin(), 0.0);
                if (v * 7) % 3 == 0 { -d } else { d }
            })
            .collect();
        orient_line_field(&mut field, &adjacency);
        for v in 0..24 {
            for &u in adjacency.neighbours(v) {
                assert!(field[v].dot(field[u as usize]) > 0.0, "{v} and {u} disagree");
            }
        }
    }
}
