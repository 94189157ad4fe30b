//! The local subdivision operator (thesis §4.7.1.1, Fig. 4.15): a concentric 4-8 pattern
//! around a vertex. Step 1 splits every link edge of the vertex; each later step splits
//! the vertex's spokes of one family, alternating between the "even" spokes (towards the
//! original ring vertices) and the "odd" ones (towards the link midpoints), so refinement
//! moves inward and no vertex outside the closed 1-ring moves. Around a degree-4 vertex
//! this is exactly the 4-8 mesh's bisection; other degrees follow the same pattern.
//!
//! Centres must be interior vertices whose closed 1-rings are disjoint (graph distance at
//! least 3), so that no two centres share a link edge; others are skipped.
//!
//! Like the thesis' extensions (Fig. 5.9), a subdivided region keeps the resolution it was
//! given: the detail pipeline does not re-insert the hierarchy's vertices whose parameter
//! face or recorded degree-fix flips touch it, nor — level after level — those whose face
//! or flips touch a vertex left out that way, so every insertion that happens restores its
//! recorded neighbourhood and the refined surface does not fold.

use crate::error::Result;
use crate::hierarchy::Refiner;

/// What a subdivision made: each new vertex with the edge it split.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Subdivision {
    /// The centres actually subdivided.
    pub centres: Vec<u32>,
    /// (split edge, new vertex), in creation order.
    pub splits: Vec<([u32; 2], u32)>,
    /// The centres and their original ring vertices: the closed 1-rings that changed.
    pub region: Vec<u32>,
}

/// Subdivides `steps` concentric steps around each usable centre (ids, in order).
///
/// # Errors
/// As [`Refiner::split_at_midpoints`].
pub fn subdivide_around(refiner: &mut Refiner, centres: &[u32], steps: usize) -> Result<Subdivision> {
    let mut out = Subdivision::default();
    if steps == 0 {
        return Ok(out);
    }
    let mut claimed = vec![false; refiner.vertex_slots()];
    let mut families: Vec<[Vec<u32>; 2]> = Vec::new();
    for &c in centres {
        let rings = refiner.rings();
        if !refiner.is_present(c) || rings.is_boundary(c) || rings.degree(c) < 3 {
            continue;
        }
        let ring = rings.ring(c).to_vec();
        if claimed[c as usize] || ring.iter().any(|&x| claimed[x as usize]) {
            continue;
        }
        claimed[c as usize] = true;
        ring.iter().for_each(|&x| claimed[x as usize] = true);
        out.centres.push(c);
        out.region.push(c);
        out.region.extend_from_slice(&ring);
        families.push([ring, Vec::new()]);
    }
    // Step 1: the link edges.
    let link_edges: Vec<[u32; 2]> =
        families.iter().flat_map(|[ring, _]| (0..ring.len()).map(|j| [ring[j], ring[(j + 1) % ring.len()]])).collect();
    let made = refiner.split_at_midpoints(&link_edges)?;
    let mut next = made.iter();
    for [ring, odd] in &mut families {
        odd.extend(ring.iter().map(|_| *next.next().expect("one vertex per link edge")));
    }
    out.splits.extend(link_edges.into_iter().zip(made));
    // Later steps: even spokes, odd spokes, even, ...
    for step in 2..=steps {
        let family = step % 2;
        let spokes: Vec<[u32; 2]> =
            out.centres.iter().zip(&families).flat_map(|(&c, f)| f[family].iter().map(move |&x| [c, x])).collect();
        let made = refiner.split_at_midpoints(&spokes)?;
        let mut next = made.iter();
        for f in &mut families {
            for x in &mut f[family] {
                *x = *next.next().expect("one vertex per spoke");
            }
        }
        out.splits.extend(spokes.into_iter().zip(made));
    }
    Ok(out)
}
