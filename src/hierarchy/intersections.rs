//! The guard's broad phase (`guard.rs`): which pairs of triangles, at least one of them new,
//! could intersect — a box grid over the new triangles and a certified plane-side filter —
//! with CGAL's exact test (`ffi::triangle_pairs_intersect`) on the pairs left.

use glam::DVec3;

use crate::error::{Error, Result};
use crate::ffi;
use crate::mesh::{Aabb, BoxGrid, certainly_apart};

/// The intersecting pairs of triangles with at least one from `added`, all over
/// `positions`, sorted: index k < `kept.len()` names `kept[k]`, and `kept.len() + i` names
/// `added[i]`. Triangles sharing a vertex or an edge intersect only if they overlap beyond
/// it (the rules of CGAL's `self_intersections`, with CGAL's exact predicates); pairs
/// within `kept` are not tested, so checking a planned retriangulation against the surface
/// it joins costs one pass over `kept` plus work proportional to the retriangulation.
///
/// The broad phase is a [`BoxGrid`] over the added triangles, queried by every triangle on
/// all threads; of the pairs whose boxes overlap, those the certified plane-side filter
/// ([`certainly_apart`]) cannot separate go to CGAL in batches, also across threads.
///
/// # Errors
/// [`Error::InvalidInput`] for an out-of-range index or a non-finite coordinate;
/// [`Error::Native`] if CGAL fails.
pub fn added_triangle_intersections(
    positions: &[DVec3],
    kept: &[[u32; 3]],
    added: &[[u32; 3]],
) -> Result<Vec<[u32; 2]>> {
    use rayon::prelude::*;
    for (i, t) in kept.iter().chain(added).enumerate() {
        for &v in t {
            let p = positions
                .get(v as usize)
                .ok_or_else(|| Error::InvalidInput(format!("triangle {i} names vertex {v} of {}", positions.len())))?;
            if !p.is_finite() {
                return Err(Error::InvalidInput(format!("vertex {v} of triangle {i} has a non-finite coordinate")));
            }
        }
    }
    let bbox =
        |t: &[u32; 3]| Aabb::of_triangle(positions[t[0] as usize], positions[t[1] as usize], positions[t[2] as usize]);
    let grid = BoxGrid::new(added.par_iter().map(bbox).collect());
    let nk = kept.len() as u32;
    // Candidates: kept against added, then added against added (each pair once), whose
    // boxes overlap and which the plane-side filter cannot tell apart.
    const CHUNK: usize = 1 << 12;
    let near_kept = kept.par_chunks(CHUNK).enumerate().map(|(c, part)| {
        let mut pairs = Vec::new();
        for (k, t) in part.iter().enumerate() {
            let k = (c * CHUNK + k) as u32;
            grid.query(&bbox(t), |i| {
                if !certainly_apart(positions, *t, added[i as usize]) {
                    pairs.push([k, nk + i]);
                }
            });
        }
        pairs
    });
    let near_added = grid.boxes().par_chunks(CHUNK).enumerate().map(|(c, part)| {
        let mut pairs = Vec::new();
        for (i, b) in part.iter().enumerate() {
            let i = (c * CHUNK + i) as u32;
            grid.query(b, |j| {
                if j > i && !certainly_apart(positions, added[i as usize], added[j as usize]) {
                    pairs.push([nk + i, nk + j]);
                }
            });
        }
        pairs
    });
    let candidates: Vec<[u32; 2]> = near_kept.chain(near_added).flatten_iter().collect();
    let hits: Vec<Vec<[u32; 2]>> = candidates
        .par_chunks(CHUNK)
        .map(|part| {
            let flags = ffi::triangle_pairs_intersect(positions, kept, added, part)?;
            Ok(part.iter().zip(flags).filter(|(_, f)| *f != 0).map(|(p, _)| *p).collect())
        })
        .collect::<Result<_>>()?;
    let mut pairs: Vec<[u32; 2]> = hits.into_iter().flatten().collect();
    pairs.sort_unstable();
    Ok(pairs)
}
