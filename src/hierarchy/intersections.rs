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
    triangle_intersections_across(positions, kept, added, AddedPairs::Tested, AddedRuns::Single)
}

/// Whether [`triangle_intersections_across`] tests the pairs of two added triangles.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum AddedPairs {
    /// Tested, as [`added_triangle_intersections`] does.
    Tested,
    /// Left out: the caller knows they cannot matter (the guard's later rounds, whose
    /// added faces all belong to the level before and so crossed there already if they cross).
    LeftOut,
}

/// [`added_triangle_intersections`], with the pairs of two added triangles tested or left
/// out, and the added triangles taken in `runs`: consecutive triangles that lie close
/// together (a plan's retriangulation), bucketed in the grid by one box each.
///
/// A pair's triangles' boxes overlap only if their runs' boxes do, so the pairs found are
/// those of [`AddedRuns::Single`], whatever the runs; a run's box saves the grid one
/// entry, and a query one hit, per triangle it holds beyond the first. The guard's first
/// round runs its plans' triangles this way: on the 327 k-triangle sphere (#35) each
/// level's face queries met about eight planned triangles' boxes each, most of them the
/// neighbouring plans' triangles at a shared corner.
pub(super) fn triangle_intersections_across(
    positions: &[DVec3],
    kept: &[[u32; 3]],
    added: &[[u32; 3]],
    among_added: AddedPairs,
    runs: AddedRuns<'_>,
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
    let bbox = |t: &[u32; 3]| face_box(positions, *t);
    let boxes: Vec<Aabb> = added.par_iter().map(bbox).collect();
    let runs = RunTable::new(runs, added.len())?;
    // With one triangle per run, the grid's boxes are the triangles' own.
    let (grid, own_boxes) = match &runs.starts {
        None => (BoxGrid::new(boxes), None),
        Some(starts) => {
            let run_box = |w: &[u32]| {
                boxes[w[0] as usize..w[1] as usize]
                    .iter()
                    .copied()
                    .reduce(|a, b| a.union(&b))
                    .expect("runs are not empty")
            };
            (BoxGrid::new(starts.par_windows(2).map(run_box).collect()), Some(boxes))
        }
    };
    let triangle_boxes = own_boxes.as_deref().unwrap_or(grid.boxes());
    let nk = kept.len() as u32;
    // Candidates: kept against added, then added against added (each pair once), whose
    // boxes overlap and which the plane-side filter cannot tell apart.
    let near =
        |s: [u32; 3], b: &Aabb, i: usize| b.overlaps(&triangle_boxes[i]) && !certainly_apart(positions, s, added[i]);
    let near_kept = kept.par_chunks(CHUNK).enumerate().map(|(c, part)| {
        let mut pairs = Vec::new();
        for (k, t) in part.iter().enumerate() {
            let k = (c * CHUNK + k) as u32;
            let b = bbox(t);
            grid.query(&b, |r| {
                for i in runs.range(r) {
                    if near(*t, &b, i) {
                        pairs.push([k, nk + i as u32]);
                    }
                }
            });
        }
        pairs
    });
    let run_count = if among_added == AddedPairs::Tested { runs.len() } else { 0 };
    let near_added = (0..run_count).into_par_iter().with_min_len(CHUNK).fold(Vec::new, |mut pairs, r| {
        let range = runs.range(r as u32);
        for i in range.clone() {
            for j in i + 1..range.end {
                if near(added[j], &triangle_boxes[j], i) {
                    pairs.push([nk + i as u32, nk + j as u32]);
                }
            }
        }
        grid.query(&grid.boxes()[r], |q| {
            if q as usize > r {
                for i in range.clone() {
                    for j in runs.range(q) {
                        if near(added[j], &triangle_boxes[j], i) {
                            pairs.push([nk + i as u32, nk + j as u32]);
                        }
                    }
                }
            }
        });
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

/// How [`triangle_intersections_across`] groups the added triangles.
#[derive(Debug, Clone, Copy)]
pub(super) enum AddedRuns<'a> {
    /// Each triangle alone.
    Single,
    /// Consecutive runs of these many triangles (summing to the added triangles' count).
    Sizes(&'a [usize]),
}

/// The added triangles' runs as ranges: `starts` holds each non-empty run's first
/// triangle and, last, the count (none: one triangle per run).
struct RunTable {
    starts: Option<Vec<u32>>,
    count: usize,
}

impl RunTable {
    fn new(runs: AddedRuns<'_>, count: usize) -> Result<Self> {
        let AddedRuns::Sizes(sizes) = runs else { return Ok(RunTable { starts: None, count }) };
        let total: usize = sizes.iter().sum();
        if total != count {
            return Err(Error::Internal(format!("runs of {total} triangles for {count} added triangles")));
        }
        let mut starts = Vec::with_capacity(sizes.len() + 1);
        let mut at = 0u32;
        for &size in sizes.iter().filter(|&&s| s > 0) {
            starts.push(at);
            at += size as u32;
        }
        starts.push(at);
        Ok(RunTable { starts: Some(starts), count })
    }

    /// Number of runs.
    fn len(&self) -> usize {
        self.starts.as_ref().map_or(self.count, |s| s.len() - 1)
    }

    /// The added triangles of run `r`.
    fn range(&self, r: u32) -> std::ops::Range<usize> {
        match &self.starts {
            None => r as usize..r as usize + 1,
            Some(starts) => starts[r as usize] as usize..starts[r as usize + 1] as usize,
        }
    }
}

/// Which of the listed `pairs` of `faces` (indices into `faces`, two distinct faces each)
/// intersect, one flag per pair, by the rules and predicates of
/// [`added_triangle_intersections`]: pairs whose boxes are apart or that the plane-side
/// filter separates are not sent to CGAL (both tests are certain, so the answer is the one
/// CGAL would give).
///
/// # Errors
/// [`Error::Native`] if CGAL fails.
pub(super) fn listed_pairs_intersect(positions: &[DVec3], faces: &[[u32; 3]], pairs: &[[u32; 2]]) -> Result<Vec<bool>> {
    use rayon::prelude::*;
    let chunks: Vec<Vec<bool>> = pairs
        .par_chunks(CHUNK)
        .map(|part| {
            let near: Vec<bool> = part
                .iter()
                .map(|&[a, b]| {
                    let (s, t) = (faces[a as usize], faces[b as usize]);
                    face_box(positions, s).overlaps(&face_box(positions, t)) && !certainly_apart(positions, s, t)
                })
                .collect();
            let uncertain: Vec<[u32; 2]> = part.iter().zip(&near).filter(|(_, n)| **n).map(|(p, _)| *p).collect();
            let mut flags = ffi::triangle_pairs_intersect(positions, faces, &[], &uncertain)?.into_iter();
            Ok(near.into_iter().map(|n| n && flags.next().is_some_and(|f| f != 0)).collect())
        })
        .collect::<Result<_>>()?;
    Ok(chunks.into_iter().flatten().collect())
}

/// Pairs are gathered and sent to CGAL in chunks of this many, across threads.
const CHUNK: usize = 1 << 12;

/// The bounding box of face `t`.
fn face_box(positions: &[DVec3], t: [u32; 3]) -> Aabb {
    Aabb::of_triangle(positions[t[0] as usize], positions[t[1] as usize], positions[t[2] as usize])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Uniform numbers in [0, 1) from a xorshift sequence seeded with `state` (not zero).
    fn numbers(mut state: u64) -> impl FnMut() -> f64 {
        move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// A soup of `n` small triangles in the unit cube, many crossing, some sharing corners.
    fn soup(n: usize) -> (Vec<DVec3>, Vec<[u32; 3]>) {
        let mut unit = numbers(0x9E37_79B9_7F4A_7C15);
        let mut positions = Vec::new();
        for _ in 0..n {
            let centre = DVec3::new(unit(), unit(), unit());
            for _ in 0..3 {
                positions.push(centre + 0.15 * DVec3::new(unit() - 0.5, unit() - 0.5, unit() - 0.5));
            }
        }
        // Every fifth triangle reuses a corner of the one before, to exercise the shared-corner rules.
        let faces = (0..n as u32)
            .map(|i| if i % 5 == 4 { [3 * i - 1, 3 * i + 1, 3 * i + 2] } else { [3 * i, 3 * i + 1, 3 * i + 2] })
            .collect();
        (positions, faces)
    }

    /// Fans of triangles around shared centres: every other one flat in the plane z = 0
    /// beside the flat ones next to it (exactly coplanar, as CAD parts are, and overlapping
    /// them), the others tilted and apart; some spokes skip two rim points, so that some of
    /// a fan's triangles overlap and most only touch.
    fn fans(n: usize) -> (Vec<DVec3>, Vec<[u32; 3]>) {
        let mut unit = numbers(0x2545_F491_4F6C_DD1D);
        let (mut positions, mut faces) = (Vec::new(), Vec::new());
        for f in 0..n {
            // The flat fans side by side in one plane, overlapping their neighbours.
            let centre = if f % 2 == 0 { DVec3::new(0.6 * f as f64, unit(), 0.0) } else { DVec3::splat(f as f64) };
            let tilt = if f % 2 == 0 { DVec3::ZERO } else { DVec3::new(unit(), unit(), 0.0) - 0.5 };
            let first = positions.len() as u32;
            positions.push(centre);
            let k = 7;
            for j in 0..k {
                let angle = std::f64::consts::TAU * (j as f64 + 0.6 * unit()) / k as f64;
                let (x, y) = (angle.cos() * (0.5 + unit()), angle.sin() * (0.5 + unit()));
                positions.push(centre + DVec3::new(x, y, tilt.x * x + tilt.y * y));
            }
            for j in 0..k as u32 {
                let next = if unit() < 0.8 { (j + 1) % k as u32 } else { (j + 3) % k as u32 };
                faces.push([first, first + 1 + j, first + 1 + next]);
            }
        }
        (positions, faces)
    }

    #[test]
    fn pairs_certified_apart_are_apart_for_cgal() {
        let (positions, faces) = fans(120);
        // Every pair within a fan (they share its centre) and across neighbouring fans.
        let pairs: Vec<[u32; 2]> = (0..faces.len() as u32)
            .flat_map(|a| (a + 1..faces.len() as u32).map(move |b| [a, b]))
            .filter(|&[a, b]| b / 7 - a / 7 <= 2)
            .collect();
        let cgal = ffi::triangle_pairs_intersect(&positions, &faces, &[], &pairs).unwrap();
        let apart: Vec<bool> =
            pairs.iter().map(|&[a, b]| certainly_apart(&positions, faces[a as usize], faces[b as usize])).collect();
        for ((pair, hit), apart) in pairs.iter().zip(&cgal).zip(&apart) {
            assert!(!(*apart && *hit != 0), "pair {pair:?} certified apart crosses for CGAL");
        }
        let (crossing, certified) = (cgal.iter().filter(|&&h| h != 0).count(), apart.iter().filter(|&&a| a).count());
        assert!(crossing > 20, "the fans overlap at only {crossing} pairs");
        // Most pairs CGAL calls apart here touch or lie in a plane: the edge planes must certify most of them.
        assert!(
            2 * certified > pairs.len() - crossing,
            "{certified} of {} pairs apart certified",
            pairs.len() - crossing
        );
    }

    #[test]
    fn leaving_out_added_pairs_drops_exactly_those() {
        let (positions, faces) = soup(400);
        let (kept, added) = faces.split_at(250);
        let nk = kept.len() as u32;
        let all = added_triangle_intersections(&positions, kept, added).unwrap();
        let across =
            triangle_intersections_across(&positions, kept, added, AddedPairs::LeftOut, AddedRuns::Single).unwrap();
        assert!(all.iter().any(|p| p[0] >= nk), "the soup has no crossing between added triangles");
        assert!(!across.is_empty(), "the soup has no crossing between kept and added triangles");
        let expected: Vec<[u32; 2]> = all.into_iter().filter(|p| p[0] < nk).collect();
        assert_eq!(across, expected);
    }

    #[test]
    fn runs_of_added_triangles_find_the_pairs_each_alone_finds() {
        let (positions, faces) = soup(500);
        let (kept, added) = faces.split_at(200);
        // Runs of 0 to 6 triangles, the soup's neighbours in index order far apart in space.
        let mut sizes = Vec::new();
        let (mut left, mut k) = (added.len(), 0usize);
        while left > 0 {
            let size = (k % 7).min(left);
            sizes.push(size);
            left -= size;
            k = (k * 5 + 3) % 1009;
        }
        for among in [AddedPairs::Tested, AddedPairs::LeftOut] {
            let alone = triangle_intersections_across(&positions, kept, added, among, AddedRuns::Single).unwrap();
            let in_runs =
                triangle_intersections_across(&positions, kept, added, among, AddedRuns::Sizes(&sizes)).unwrap();
            assert!(alone.len() > 20, "the soup crosses itself only {} times", alone.len());
            assert_eq!(in_runs, alone, "{among:?}");
        }
        let short = triangle_intersections_across(&positions, kept, added, AddedPairs::Tested, AddedRuns::Sizes(&[3]));
        assert!(matches!(short, Err(Error::Internal(_))));
    }

    #[test]
    fn listed_pairs_agree_with_the_grid_search() {
        let (positions, faces) = soup(300);
        let found = added_triangle_intersections(&positions, &[], &faces).unwrap();
        let n = faces.len() as u32;
        let every_pair: Vec<[u32; 2]> = (0..n).flat_map(|a| (a + 1..n).map(move |b| [a, b])).collect();
        let flags = listed_pairs_intersect(&positions, &faces, &every_pair).unwrap();
        let listed: Vec<[u32; 2]> = every_pair.iter().zip(flags).filter(|(_, f)| *f).map(|(p, _)| *p).collect();
        assert!(listed.len() > 10, "the soup crosses itself only {} times", listed.len());
        assert_eq!(listed, found);
    }
}
