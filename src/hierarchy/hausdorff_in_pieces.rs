//! The two-sided Hausdorff distance of a build's report, measured piece by piece so that
//! its memory does not grow with the input (#40: `simplify merge` held the whole input in
//! CGAL's half-edge mesh, its AABB tree and its samples, 800 MB at 3.3M triangles).
//!
//! Each side is sampled as CGAL's `approximate_Hausdorff_distance` samples by default: its
//! vertices, then as many random points on its faces (area-weighted) and on its edges
//! (length-weighted) as it has vertices. But every random number is a hash of the face,
//! the edge and the sample's index, so the samples do not depend on how the faces are
//! grouped or on the thread count. The other side is cut into pieces of at most
//! [`PIECE_FACES`] faces, spatially compact (runs of the Morton curve, as the partition
//! cuts), and each piece is an AABB tree of its own (CGAL's, [`DistanceTree`]); a sample's
//! distance is the least over the pieces whose box is nearer than its best so far. That
//! least is the distance to the whole side, so the measure is the same whatever the piece
//! size: the pieces bound the memory, never the result.

use glam::DVec3;

use super::partition::morton::morton_owners;
use crate::error::Result;
use crate::ffi::DistanceTree;
use crate::mesh::{Mesh, UnitFrame};
use crate::noise::hash::{hash_coords, mix64};

/// Faces one piece (one AABB tree) holds at most: about 14 MB of CGAL's tree.
pub const PIECE_FACES: usize = 1 << 16;
/// Random points on a side's faces, and on its edges, per vertex of that side (CGAL's
/// default counts).
const SAMPLES_PER_VERTEX: f64 = 1.0;
/// The seeds of the samples on faces and on edges.
const FACE_SEED: u64 = 0x6861_7573_646f_7266;
const EDGE_SEED: u64 = 0x6564_6765_7361_6d70;

/// The symmetric Hausdorff distance between the input (`positions`, `triangles`) and
/// `base`, as a share of the input's bounding-box diagonal: both are measured in the
/// input's unit frame, so the result does not depend on the model's units.
///
/// # Errors
/// [`crate::Error::InvalidInput`] for an input without vertices or whose extent overflows;
/// [`crate::Error::Native`] for a side without faces.
pub fn relative_hausdorff_in_pieces(positions: &[DVec3], triangles: &[[u32; 3]], base: &Mesh) -> Result<f64> {
    in_pieces_of(positions, triangles, base, PIECE_FACES)
}

/// As [`relative_hausdorff_in_pieces`], with pieces and batches of `piece` faces.
fn in_pieces_of(positions: &[DVec3], triangles: &[[u32; 3]], base: &Mesh, piece: usize) -> Result<f64> {
    let unit = UnitFrame::of_positions(positions)?;
    let input = Side { positions, triangles, unit, piece };
    let base = Side { positions: &base.positions, triangles: &base.triangles, unit, piece };
    let (there, back) = rayon::join(|| farthest_sample(&input, &base), || farthest_sample(&base, &input));
    Ok(there?.max(back?))
}

/// One side of the measure: its faces, read in the input's unit frame.
struct Side<'a> {
    positions: &'a [DVec3],
    triangles: &'a [[u32; 3]],
    unit: UnitFrame,
    /// Faces a piece or a batch holds at most.
    piece: usize,
}

impl Side<'_> {
    fn point(&self, v: u32) -> DVec3 {
        self.unit.to_unit(self.positions[v as usize])
    }

    fn corners(&self, f: usize) -> [DVec3; 3] {
        self.triangles[f].map(|v| self.point(v))
    }

    /// The random points per unit of the side's area and of its faces' sides' length:
    /// as many on its faces, and as many on its sides, as it has vertices.
    fn density(&self) -> Density {
        let (area, length) = self.area_and_length();
        let count = SAMPLES_PER_VERTEX * self.positions.len() as f64;
        let per = |total: f64| if total > 0.0 { count / total } else { 0.0 };
        Density { per_area: per(area), per_length: per(length) }
    }

    /// The faces' total area and their sides' total length (an edge between two faces
    /// counted twice, so each of its sides samples half of it), summed in face order in
    /// fixed runs: the same at any thread count.
    fn area_and_length(&self) -> (f64, f64) {
        use rayon::prelude::*;
        let runs: Vec<(f64, f64)> = self
            .triangles
            .par_chunks(PIECE_FACES)
            .map(|run| {
                run.iter().fold((0.0, 0.0), |(area, length), &t| {
                    let corners = t.map(|v| self.point(v));
                    (
                        area + triangle_area(corners),
                        length + sides(corners).map(|(a, b)| a.distance(b)).iter().sum::<f64>(),
                    )
                })
            })
            .collect();
        runs.iter().fold((0.0, 0.0), |(a, l), &(ra, rl)| (a + ra, l + rl))
    }

    /// The samples of some of the side's vertices and faces: the vertices, then the
    /// random points on the faces and their sides.
    fn samples(
        &self,
        vertices: impl Iterator<Item = usize>,
        faces: impl Iterator<Item = usize>,
        density: Density,
    ) -> Vec<DVec3> {
        let mut out: Vec<DVec3> = vertices.map(|v| self.point(v as u32)).collect();
        for f in faces {
            face_samples(f, self.corners(f), density, &mut out);
        }
        out
    }
}

/// Random points per unit of a side's area and of its faces' sides' length.
#[derive(Clone, Copy)]
struct Density {
    per_area: f64,
    per_length: f64,
}

/// The random points of face `f` and of its three sides. Each count is its expected value
/// (density × area or length) rounded down or up by a hash; a point on the face is uniform
/// on the triangle (the square-root map of two hashed numbers; Turk 1990), a point on a
/// side uniform on the segment.
fn face_samples(f: usize, corners: [DVec3; 3], density: Density, out: &mut Vec<DVec3>) {
    let face = f as i64;
    let count = |seed: u64, key: i64, expected: f64| {
        let up = unit_interval(hash_coords(seed, &[face, key, -1])) < expected.fract();
        expected.floor() as i64 + i64::from(up)
    };
    let [a, b, c] = corners;
    for j in 0..count(FACE_SEED, 0, density.per_area * triangle_area(corners)) {
        let r = unit_interval(hash_coords(FACE_SEED, &[face, 0, 2 * j])).sqrt();
        let s = unit_interval(hash_coords(FACE_SEED, &[face, 0, 2 * j + 1]));
        out.push(a * (1.0 - r) + b * (r * (1.0 - s)) + c * (r * s));
    }
    for (k, (p, q)) in sides(corners).into_iter().enumerate() {
        let side = k as i64 + 1;
        for j in 0..count(EDGE_SEED, side, density.per_length * p.distance(q)) {
            out.push(p.lerp(q, unit_interval(hash_coords(EDGE_SEED, &[face, side, j]))));
        }
    }
}

/// A triangle's three sides, in its order.
fn sides([a, b, c]: [DVec3; 3]) -> [(DVec3, DVec3); 3] {
    [(a, b), (b, c), (c, a)]
}

fn triangle_area([a, b, c]: [DVec3; 3]) -> f64 {
    0.5 * (b - a).cross(c - a).length()
}

/// A number in [0, 1) from 53 bits of a hash.
fn unit_interval(h: u64) -> f64 {
    (mix64(h) >> 11) as f64 / (1u64 << 53) as f64
}

/// The largest distance from a sample of `from` to the surface of `to`. Both sides'
/// samples are the same whatever the pieces, and a sample's distance is its least over
/// the pieces, so the result is too, at any thread count (and at any piece size, but for
/// the last bits of a near-tie between two faces, which a chained query's start decides).
fn farthest_sample(from: &Side<'_>, to: &Side<'_>) -> Result<f64> {
    use rayon::prelude::*;
    let density = from.density();
    let pieces = Pieces::of(to);
    if pieces.boxes.len() > 1 {
        return farthest_over_pieces(from, to, &pieces, density);
    }
    // One tree: the samples in runs of the side's vertices, then of its faces, in index
    // order, each run asked on its own thread.
    let tree = pieces.tree(to, 0)?;
    let step = from.piece;
    let vertex_runs = (0..from.positions.len()).step_by(step).map(|s| (s..(s + step).min(from.positions.len()), 0..0));
    let face_runs = (0..from.triangles.len()).step_by(step).map(|s| (0..0, s..(s + step).min(from.triangles.len())));
    let runs: Vec<_> = vertex_runs.chain(face_runs).collect();
    runs.into_par_iter()
        .map(|(vertices, faces)| {
            let farthest = tree.distances(&from.samples(vertices, faces, density))?;
            Ok(farthest.into_iter().fold(0.0f64, f64::max))
        })
        .try_reduce(|| 0.0, |a, b| Ok(a.max(b)))
}

/// [`farthest_sample`] when `to` is cut into several pieces. `from` is cut as `to` is, into
/// runs of the Morton curve, so each run of samples has a compact box: each piece's tree is
/// built once (the pieces on the threads) and asked only about the runs whose box is
/// nearer than their largest best distance so far, and of those, about the samples its box
/// may come nearer than their own best. Skipping never changes a sample's least distance:
/// a piece is skipped only when its box is farther than the best by more than rounding
/// could make a distance fall short of its box's ([`beyond`]), so every skipped piece's
/// distance exceeds the final least, and each distance is found from its point alone
/// (which samples a piece is asked about depends on the threads' timing): the least over
/// all the pieces, at any thread count.
fn farthest_over_pieces(from: &Side<'_>, to: &Side<'_>, pieces: &Pieces, density: Density) -> Result<f64> {
    use rayon::prelude::*;
    use std::sync::atomic::{AtomicU64, Ordering::Relaxed};
    let runs = SampleRuns::of(from);
    let samples = |r: usize| from.samples(runs.vertices(r), runs.faces(r), density);
    // Each run's box, and a first bound for all its samples: the farthest two points of
    // its box and of the piece box nearest in that sense can be (a little more, so that
    // rounding cannot make that piece look farther than the bound).
    let first: Vec<(PieceBox, usize)> = (0..runs.count())
        .into_par_iter()
        .map(|r| {
            let points = samples(r);
            (PieceBox::around(points.iter().copied()), points.len())
        })
        .collect();
    // A distance is never negative, so its bits order as it does: `fetch_min` on the bits.
    let bits = |d: f64| AtomicU64::new(d.to_bits());
    let mut best = Vec::with_capacity(first.len());
    let mut run_bound = Vec::with_capacity(first.len());
    for (bounds, count) in &first {
        let bound = pieces.boxes.iter().map(|p| bounds.farthest_to(p)).fold(f64::INFINITY, f64::min) * (1.0 + 1e-9);
        best.push((0..*count).map(|_| bits(bound)).collect::<Vec<_>>());
        run_bound.push(bits(bound));
    }
    let load = |a: &AtomicU64| f64::from_bits(a.load(Relaxed));
    (0..pieces.boxes.len()).into_par_iter().try_for_each(|k| {
        let piece_box = &pieces.boxes[k];
        let mut tree = None;
        for (r, (run_box, _)) in first.iter().enumerate() {
            if beyond(run_box.gap_to(piece_box), load(&run_bound[r])) {
                continue;
            }
            let points = samples(r);
            let best = &best[r];
            let asked: Vec<usize> =
                (0..points.len()).filter(|&i| !beyond(piece_box.nearest(points[i]), load(&best[i]))).collect();
            if asked.is_empty() {
                continue;
            }
            let tree = match &mut tree {
                Some(tree) => tree,
                None => tree.insert(pieces.tree(to, k)?),
            };
            let queried: Vec<DVec3> = asked.iter().map(|&i| points[i]).collect();
            for (&i, d) in asked.iter().zip(tree.distances_each_alone(&queried)?) {
                best[i].fetch_min(d.to_bits(), Relaxed);
            }
            let largest = best.iter().map(load).fold(0.0, f64::max);
            run_bound[r].fetch_min(largest.to_bits(), Relaxed);
        }
        Ok::<(), crate::Error>(())
    })?;
    Ok(best.iter().flatten().map(load).fold(0.0, f64::max))
}

/// Whether a box `gap` away is surely farther than a `best` distance: by more than the
/// rounding of a distance computed to a face in the box (CGAL's projection, in the unit
/// frame, so of coordinates at most about 1), which may fall a few ulps short of the box's
/// own distance.
fn beyond(gap: f64, best: f64) -> bool {
    gap > best * (1.0 + 1e-9) + 1e-12
}

/// A side's samples in spatially compact runs: its faces in the Morton runs [`Pieces`]
/// makes, each vertex with the first run holding one of its faces (a vertex on no face,
/// with the first run).
struct SampleRuns {
    faces: Pieces,
    /// The vertices, run after run.
    vertex_order: Vec<u32>,
    /// Where each run's vertices start in `vertex_order`, and the end.
    vertex_starts: Vec<usize>,
}

impl SampleRuns {
    fn of(side: &Side<'_>) -> Self {
        let faces = Pieces::of(side);
        let count = faces.boxes.len();
        let mut run_of = vec![0u32; side.positions.len()];
        let mut seen = vec![false; side.positions.len()];
        for k in 0..count {
            for f in faces.faces(k) {
                for v in side.triangles[f] {
                    if !std::mem::replace(&mut seen[v as usize], true) {
                        run_of[v as usize] = k as u32;
                    }
                }
            }
        }
        drop(seen);
        let (vertex_order, vertex_starts) = group_by_run(&run_of, count);
        SampleRuns { faces, vertex_order, vertex_starts }
    }

    fn count(&self) -> usize {
        self.faces.boxes.len()
    }

    fn vertices(&self, r: usize) -> impl Iterator<Item = usize> + '_ {
        self.vertex_order[self.vertex_starts[r]..self.vertex_starts[r + 1]].iter().map(|&v| v as usize)
    }

    fn faces(&self, r: usize) -> impl Iterator<Item = usize> + '_ {
        self.faces.faces(r)
    }
}

/// The items `0..owner.len()` grouped by their owner (`0..count`), each group in
/// ascending order, and where each group starts, and the end (a counting sort).
fn group_by_run(owner: &[u32], count: usize) -> (Vec<u32>, Vec<usize>) {
    let mut starts = vec![0usize; count + 1];
    owner.iter().for_each(|&k| starts[k as usize + 1] += 1);
    (0..count).for_each(|k| starts[k + 1] += starts[k]);
    let mut next = starts.clone();
    let mut order = vec![0u32; owner.len()];
    for (item, &k) in owner.iter().enumerate() {
        order[next[k as usize]] = item as u32;
        next[k as usize] += 1;
    }
    (order, starts)
}

/// A side's faces cut into pieces of at most `piece` faces: runs of the Morton
/// curve of their centroids (the partition's cut), each with its box.
struct Pieces {
    /// The faces, piece after piece.
    order: Vec<u32>,
    /// Where each piece starts in `order`, and the end.
    starts: Vec<usize>,
    boxes: Vec<PieceBox>,
}

impl Pieces {
    fn of(side: &Side<'_>) -> Self {
        let faces = side.triangles.len();
        let count = faces.div_ceil(side.piece).max(1);
        if count == 1 {
            return Pieces { order: Vec::new(), starts: vec![0, faces], boxes: vec![PieceBox::of(side, 0..faces)] };
        }
        let owner = morton_owners(side.positions, side.triangles, &side.unit, count);
        let (order, starts) = group_by_run(&owner, count);
        drop(owner);
        let boxes = (0..count)
            .map(|k| PieceBox::of(side, order[starts[k]..starts[k + 1]].iter().map(|&f| f as usize)))
            .collect();
        Pieces { order, starts, boxes }
    }

    /// The faces of piece `k`.
    fn faces(&self, k: usize) -> impl Iterator<Item = usize> + '_ {
        let whole = self.order.is_empty().then(|| self.starts[0]..self.starts[1]);
        let run = if self.order.is_empty() { &[][..] } else { &self.order[self.starts[k]..self.starts[k + 1]] };
        whole.into_iter().flatten().chain(run.iter().map(|&f| f as usize))
    }

    /// The AABB tree of piece `k`, on its own vertices.
    fn tree(&self, side: &Side<'_>, k: usize) -> Result<DistanceTree> {
        if self.order.is_empty() {
            let points: Vec<DVec3> = (0..side.positions.len() as u32).map(|v| side.point(v)).collect();
            return DistanceTree::new(&points, side.triangles);
        }
        let faces = &self.order[self.starts[k]..self.starts[k + 1]];
        let mut local = std::collections::HashMap::with_capacity(faces.len());
        let mut points = Vec::with_capacity(faces.len() / 2 + 3);
        let triangles: Vec<[u32; 3]> = faces
            .iter()
            .map(|&f| {
                side.triangles[f as usize].map(|v| {
                    *local.entry(v).or_insert_with(|| {
                        points.push(side.point(v));
                        points.len() as u32 - 1
                    })
                })
            })
            .collect();
        DistanceTree::new(&points, &triangles)
    }
}

/// The bounding box of a piece's faces.
struct PieceBox {
    lo: DVec3,
    hi: DVec3,
}

impl PieceBox {
    fn of(side: &Side<'_>, faces: impl Iterator<Item = usize>) -> Self {
        Self::around(faces.flat_map(|f| side.corners(f)))
    }

    /// The box of some points.
    fn around(points: impl IntoIterator<Item = DVec3>) -> Self {
        let mut out = PieceBox { lo: DVec3::INFINITY, hi: DVec3::NEG_INFINITY };
        for p in points {
            out.lo = out.lo.min(p);
            out.hi = out.hi.max(p);
        }
        out
    }

    /// The least distance between a point of this box and a point of `other` (0 when they
    /// meet; infinite when either is empty).
    fn gap_to(&self, other: &PieceBox) -> f64 {
        if self.lo.x > self.hi.x || other.lo.x > other.hi.x {
            return f64::INFINITY;
        }
        (other.lo - self.hi).max(self.lo - other.hi).max(DVec3::ZERO).length()
    }

    /// The largest distance between a point of this box and a point of `other`.
    fn farthest_to(&self, other: &PieceBox) -> f64 {
        (other.hi - self.lo).abs().max((self.hi - other.lo).abs()).length()
    }

    /// The distance from `p` to the box: no face of the piece is nearer.
    fn nearest(&self, p: DVec3) -> f64 {
        (self.lo - p).max(p - self.hi).max(DVec3::ZERO).length()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::primitives;

    /// A bumpy sphere and a coarse sphere: the measure is the same with pieces of 64 faces
    /// (dozens of trees) as with one tree, since a sample's least distance over the pieces
    /// is its distance to the whole, and the same at any thread count.
    #[test]
    fn the_pieces_bound_the_memory_never_the_result() {
        let mut fine = primitives::icosphere(1.0, 4);
        for (v, p) in fine.positions.iter_mut().enumerate() {
            *p *= 1.0 + 0.02 * (v as f64 * 0.7).sin();
        }
        let coarse = primitives::icosphere(1.0, 1);
        let whole = in_pieces_of(&fine.positions, &fine.triangles, &coarse, usize::MAX >> 1).unwrap();
        let reverse_whole = in_pieces_of(&coarse.positions, &coarse.triangles, &fine, usize::MAX >> 1).unwrap();
        for piece in [8, 64, 1000] {
            let pieced = in_pieces_of(&fine.positions, &fine.triangles, &coarse, piece).unwrap();
            assert_eq!(pieced.to_bits(), whole.to_bits(), "pieces of {piece}");
            let reverse = in_pieces_of(&coarse.positions, &coarse.triangles, &fine, piece).unwrap();
            assert_eq!(reverse.to_bits(), reverse_whole.to_bits(), "the other way, pieces of {piece}");
        }
        assert!(reverse_whole > 0.0 && (reverse_whole / whole - 1.0).abs() < 0.5, "{reverse_whole} against {whole}");
        assert!(whole > 0.0);
        for threads in [1, 3] {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            let d = pool.install(|| in_pieces_of(&fine.positions, &fine.triangles, &coarse, 64).unwrap());
            assert_eq!(d.to_bits(), whole.to_bits(), "{threads} threads");
        }
    }

    /// Two parallel squares h apart: every sample is h away, in any unit.
    #[test]
    fn parallel_squares_are_their_gap_apart_in_any_unit() {
        for scale in [1e-6, 1.0, 1e6] {
            let lower = primitives::grid(8);
            let mut upper = lower.clone();
            let lift = DVec3::new(0.0, 0.0, 0.01);
            upper.positions.iter_mut().for_each(|p| *p += lift);
            let mut both = lower.clone();
            both.positions.extend(&upper.positions);
            let n = lower.positions.len() as u32;
            both.triangles.extend(upper.triangles.iter().map(|t| t.map(|v| v + n)));
            let scaled = |m: &Mesh| Mesh::new(m.positions.iter().map(|&p| p * scale).collect(), m.triangles.clone());
            let (both, lower) = (scaled(&both), scaled(&lower));
            let diagonal = UnitFrame::of(&both).unwrap().diagonal;
            let d = in_pieces_of(&both.positions, &both.triangles, &lower, 16).unwrap();
            assert!((d - 0.01 * scale / diagonal).abs() < 1e-9, "{d} at scale {scale}");
            // Every sample is as far as every other within rounding: where the pieces'
            // order could decide the last bits, it does not.
            for threads in [1, 3] {
                let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
                for (from, to) in [(&both, &lower), (&lower, &both)] {
                    let again = pool.install(|| in_pieces_of(&from.positions, &from.triangles, to, 16).unwrap());
                    let first = in_pieces_of(&from.positions, &from.triangles, to, 16).unwrap();
                    assert_eq!(again.to_bits(), first.to_bits(), "{threads} threads at scale {scale}");
                }
            }
        }
    }

    /// The measure is close to CGAL's sampled one (which samples differently).
    #[test]
    fn it_is_near_cgal_s_sampled_measure() {
        let mut fine = primitives::icosphere(1.0, 4);
        for (v, p) in fine.positions.iter_mut().enumerate() {
            *p *= 1.0 + 0.02 * (v as f64 * 0.7).sin();
        }
        let coarse = primitives::icosphere(1.0, 2);
        let ours = relative_hausdorff_in_pieces(&fine.positions, &fine.triangles, &coarse).unwrap();
        let cgal = super::super::compare::relative_hausdorff(&fine, &coarse).unwrap();
        assert!((ours / cgal - 1.0).abs() < 0.1, "{ours} against CGAL's {cgal}");
    }
}
