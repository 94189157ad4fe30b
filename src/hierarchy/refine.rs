//! Adaptive refinement (thesis §4.6): from the base domain, each level's removed vertices
//! are re-inserted in removal order by splitting the edge of their parameter face nearest
//! to their parameter point (Algorithm 2), then each inserted vertex's degree is restored
//! to its degree on that level by flipping the link edge opposite its widest angle
//! (Algorithm 3). Insertions whose recorded diagonal no longer exists — after operators
//! that change connectivity, or when only a region is refined — split the parameter
//! face's edge nearest the vertex, or else the nearest edge around that face (Algorithm 2);
//! where that split would overlap (Fig. 4.10), the nearest edge one ring further whose
//! split does not.
//!
//! A vertex is placed at its input position plus the displacement of its parameter point
//! (the interpolated face moved from where it was at simplification): without deformation
//! that displacement is exactly zero and every input position comes back bit for bit.

use std::borrow::Cow;
use std::collections::HashSet;

use glam::DVec3;
use serde::Serialize;

use super::cluster::widest_link_edge;
use super::conformal::interpolate;
use super::cost::point_segment_distance_squared;
use super::rings::Rings;
use super::store::{expect_done, exported_triangles};
use super::{Hierarchy, Removal, face_key, used_vertices};
use crate::error::{Error, Result};
use crate::ffi::HalfEdgeMesh;
use crate::mesh::Mesh;

/// A level's mesh, compacted, with each vertex's input id.
#[derive(Debug, Clone, Default)]
pub struct LevelMesh {
    /// The mesh (vertices on at least one face).
    pub mesh: Mesh,
    /// Input id of each vertex of `mesh`.
    pub ids: Vec<u32>,
}

impl LevelMesh {
    /// Keeps the vertices `triangles` use, in id order.
    pub fn compact(positions: &[DVec3], triangles: &[[u32; 3]]) -> Self {
        let mut index = vec![u32::MAX; positions.len()];
        let mut ids = Vec::new();
        for (v, used) in used_vertices(positions.len(), triangles).into_iter().enumerate() {
            if used {
                index[v] = ids.len() as u32;
                ids.push(v as u32);
            }
        }
        let mesh = Mesh::new(
            ids.iter().map(|&v| positions[v as usize]).collect(),
            triangles.iter().map(|t| t.map(|v| index[v as usize])).collect(),
        );
        LevelMesh { mesh, ids }
    }

    /// The faces in input ids.
    pub fn triangles_in_ids(&self) -> Vec<[u32; 3]> {
        self.mesh.triangles.iter().map(|t| t.map(|v| self.ids[v as usize])).collect()
    }

    /// Whether this holds every vertex of `input` at its input position.
    pub fn has_input_positions(&self, input: &Mesh) -> bool {
        self.ids.len() == input.vertex_count()
            && self.ids.iter().zip(&self.mesh.positions).all(|(&id, p)| *p == input.positions[id as usize])
    }
}

/// What one refinement level did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct LevelReport {
    /// The level reached.
    pub level: usize,
    /// Vertices inserted.
    pub inserted: usize,
    /// Of those, inserted through the neighbour search (their face was gone): Algorithm 2
    /// over the edges around their parameter face.
    pub relocated: usize,
    /// Of those, placed farther out because the nearest edge overlapped (Fig. 4.10): the
    /// nearest edge one ring further whose split does not overlap.
    pub widened: usize,
    /// Vertices left out (not selected, or no face near them).
    pub skipped: usize,
    /// Degree-fix flips.
    pub flips: usize,
    /// Of those, Algorithm 3's: the link edge opposite the widest angle (the others flip
    /// back the recorded ring).
    pub widest_flips: usize,
    /// Inserted vertices whose level degree could not be restored.
    pub degree_misses: usize,
}

impl LevelReport {
    /// `reports` summed (`level` is the last one's).
    pub fn total(reports: &[LevelReport]) -> LevelReport {
        let mut t = LevelReport::default();
        for r in reports {
            t.level = r.level;
            t.inserted += r.inserted;
            t.relocated += r.relocated;
            t.widened += r.widened;
            t.skipped += r.skipped;
            t.flips += r.flips;
            t.widest_flips += r.widest_flips;
            t.degree_misses += r.degree_misses;
        }
        t
    }
}

/// How an inserted vertex's edge was found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Placement {
    /// The recorded weld diagonal (the exact replay).
    Recorded,
    /// Algorithm 2: the nearest interior edge around the parameter face.
    Searched,
    /// The nearest edge one ring further, because the nearest one overlapped (Fig. 4.10).
    Widened,
}

/// Walks a hierarchy from its base domain towards the input, one level at a time.
pub struct Refiner<'h> {
    hierarchy: &'h Hierarchy,
    store: HalfEdgeMesh,
    rings: Rings,
    /// The hierarchy's positions until something moves a vertex or adds one (then a copy
    /// of its own): a plain refinement holds no second copy (#35's peak).
    positions: Cow<'h, [DVec3]>,
    present: Vec<bool>,
    live: Vec<u32>,
    level: usize,
    follow_deformation: bool,
}

impl std::fmt::Debug for Refiner<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Refiner {{ level: {}, vertices: {} }}", self.level, self.live.len())
    }
}

impl<'h> Refiner<'h> {
    /// Starts at the base domain (level 0).
    ///
    /// # Errors
    /// [`Error::Native`] if OpenMesh refuses the base domain.
    pub fn new(hierarchy: &'h Hierarchy) -> Result<Self> {
        // Every input vertex gets its slot now (removed ones isolated), so store indices
        // are input ids for the refiner's whole life.
        let all = Mesh::new(hierarchy.positions.clone(), hierarchy.base_triangles.clone());
        let mut store = HalfEdgeMesh::from_mesh(&all)?;
        drop(all);
        // Room for the input's faces and edges at once: grown by doubling while the levels
        // are refined, OpenMesh's arrays would hold the old copy beside the new one at the
        // last growth, at full resolution (reserved pages not yet written are not resident).
        let (n, faces) = (hierarchy.positions.len(), hierarchy.input_triangles.len());
        store.reserve(n, (faces * 3 / 2 + faces / 8).max(3 * n), faces)?;
        let present = used_vertices(n, &hierarchy.base_triangles);
        let live: Vec<u32> = (0..n as u32).filter(|&v| present[v as usize]).collect();
        let rings = Rings::fetch(&store, &live, n)?;
        Ok(Refiner {
            hierarchy,
            store,
            rings,
            positions: Cow::Borrowed(&hierarchy.positions),
            present,
            live,
            level: 0,
            follow_deformation: true,
        })
    }

    /// The current level (0: base domain; `hierarchy.steps()`: fully refined).
    pub fn level(&self) -> usize {
        self.level
    }

    /// Whether refinement has reached the input's level.
    pub fn is_finished(&self) -> bool {
        self.level >= self.hierarchy.steps()
    }

    /// Current vertex positions, by input id (absent vertices keep their input position).
    pub fn positions(&self) -> &[DVec3] {
        &self.positions
    }

    /// Mutable positions: deformations applied between levels move vertices here; later
    /// insertions follow the moved surface.
    pub fn positions_mut(&mut self) -> &mut [DVec3] {
        self.positions.to_mut()
    }

    /// Whether later insertions follow the deformed surface (the parametrization update of
    /// §4.5.1, on by default). Off, every vertex returns to its input position, which is
    /// what Fig. 4.7(a) shows going wrong after a deformation.
    pub fn set_follow_deformation(&mut self, follow: bool) {
        self.follow_deformation = follow;
    }

    /// Number of vertex slots: input vertices plus those operators have added.
    pub fn vertex_slots(&self) -> usize {
        self.positions.len()
    }

    /// Splits `edges` (in order) at their current midpoints, making new vertices with ids
    /// from [`Refiner::vertex_slots`] up; returns them. Operators that add resolution
    /// between levels (local subdivision, §4.7.1.1) use this; later insertions whose
    /// recorded face was split find their edge through the neighbour search.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] if OpenMesh refuses a split (an edge that is not in the mesh).
    pub fn split_at_midpoints(&mut self, edges: &[[u32; 2]]) -> Result<Vec<u32>> {
        let mut made = Vec::with_capacity(edges.len());
        for chunk in edges.chunks(4096) {
            let points: Vec<DVec3> =
                chunk.iter().map(|e| (self.positions[e[0] as usize] + self.positions[e[1] as usize]) * 0.5).collect();
            for ((edge, (status, vertex)), p) in chunk.iter().zip(self.store.split_edges(chunk, &points)?).zip(points) {
                let Some(v) = vertex.filter(|v| v.index() == self.positions.len()) else {
                    return Err(Error::InvalidInput(format!("cannot split edge {}–{} ({status:?})", edge[0], edge[1])));
                };
                self.positions.to_mut().push(p);
                self.present.push(true);
                made.push(v.0);
            }
        }
        self.live = (0..self.present.len() as u32).filter(|&v| self.present[v as usize]).collect();
        self.rings = Rings::fetch(&self.store, &self.live, self.present.len())?;
        Ok(made)
    }

    /// Whether vertex `v` is in the current mesh.
    pub fn is_present(&self, v: u32) -> bool {
        self.present[v as usize]
    }

    /// The current level's vertices (input ids, ascending).
    pub fn vertices(&self) -> &[u32] {
        &self.live
    }

    /// The current 1-rings.
    pub fn rings(&self) -> &Rings {
        &self.rings
    }

    /// Refines every remaining level.
    ///
    /// # Errors
    /// As [`Refiner::refine_level`].
    pub fn refine_all(&mut self) -> Result<Vec<LevelReport>> {
        let mut reports = Vec::new();
        let (first, steps) = (self.level as u64, self.hierarchy.steps() as u64);
        crate::progress::report("refine", 0, steps - first);
        while !self.is_finished() {
            reports.push(self.refine_level(&|_| true)?);
            crate::progress::report("refine", self.level as u64 - first, steps - first);
        }
        Ok(reports)
    }

    /// Refines one level, inserting only the vertices `select` accepts.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] when already at the input level; [`Error::Internal`] if
    /// OpenMesh refuses a planned operation.
    pub fn refine_level(&mut self, select: &dyn Fn(u32) -> bool) -> Result<LevelReport> {
        if self.is_finished() {
            return Err(Error::InvalidInput("the hierarchy is already fully refined".into()));
        }
        let hierarchy = self.hierarchy;
        let step = hierarchy.steps() - 1 - self.level;
        let mut report = LevelReport { level: self.level + 1, ..Default::default() };
        let mut edges = Vec::new();
        let mut vertices = Vec::new();
        let mut points = Vec::new();
        let mut inserted: Vec<&Removal> = Vec::new();
        for r in hierarchy.step(step) {
            if !select(r.vertex) {
                report.skipped += 1;
                continue;
            }
            let point = self.insertion_point(r);
            let Some((edge, placement)) = self.insertion_edge(r, point) else {
                report.skipped += 1;
                continue;
            };
            let relocated = placement != Placement::Recorded;
            report.widened += usize::from(placement == Placement::Widened);
            match r.boundary {
                true => self.rings.split_boundary(edge[0], edge[1], r.vertex)?,
                false => self.rings.split(edge[0], edge[1], r.vertex)?,
            }
            // Bit for bit: a signed zero is a change too.
            if self.positions[r.vertex as usize].to_array().map(f64::to_bits) != point.to_array().map(f64::to_bits) {
                self.positions.to_mut()[r.vertex as usize] = point;
            }
            self.present[r.vertex as usize] = true;
            report.relocated += usize::from(relocated);
            edges.push(edge);
            vertices.push(r.vertex);
            points.push(point);
            inserted.push(r);
        }
        report.inserted = inserted.len();
        let flips = self.fix_degrees(&inserted, &mut report)?;
        expect_done("insertion", &edges, &self.store.insert_on_edges(&edges, &vertices, &points)?)?;
        expect_done("degree-fix flip", &flips, &self.store.flip_edges(&flips)?)?;
        report.flips = flips.len();
        // The rings already hold the splits and flips the store just carried out.
        self.live = (0..self.present.len() as u32).filter(|&v| self.present[v as usize]).collect();
        self.level += 1;
        Ok(report)
    }

    /// Where `r` goes: its input position plus the displacement of its parameter point
    /// (exactly its input position when nothing moved).
    fn insertion_point(&self, r: &Removal) -> DVec3 {
        let f = r.local.face;
        let original = self.hierarchy.positions[r.vertex as usize];
        if !self.follow_deformation {
            return original;
        }
        let shift = if f.iter().all(|&v| self.present[v as usize]) {
            let now = interpolate(f.map(|v| self.positions[v as usize]), r.local.bary);
            let then = interpolate(f.map(|v| self.hierarchy.positions[v as usize]), r.local.bary);
            now - then
        } else {
            let moved: Vec<DVec3> = f
                .iter()
                .filter(|&&v| self.present[v as usize])
                .map(|&v| self.positions[v as usize] - self.hierarchy.positions[v as usize])
                .collect();
            if moved.is_empty() { DVec3::ZERO } else { moved.iter().sum::<DVec3>() / moved.len() as f64 }
        };
        if shift == DVec3::ZERO { original } else { original + shift }
    }

    /// The edge to split and how it was found: the weld's diagonal while the recorded face
    /// exists, else the nearest interior edge around it (Algorithm 2 over the neighbouring
    /// faces); when that split would overlap (Fig. 4.10), the nearest edge one ring
    /// further out whose split does not.
    fn insertion_edge(&self, r: &Removal, point: DVec3) -> Option<([u32; 2], Placement)> {
        let f = r.local.face;
        if self.rings.has_face(f[0], f[1], f[2]) && self.rings.has_edge(r.diagonal[0], r.diagonal[1]) {
            return Some((r.diagonal, Placement::Recorded));
        }
        if r.boundary {
            // Moved inside, a boundary vertex would change the boundary: it waits.
            return None;
        }
        if self.rings.has_face(f[0], f[1], f[2]) {
            // Algorithm 2 in its own words: the parameter face's edge nearest the point.
            let i = super::cluster::nearest_edge(f.map(|v| self.positions[v as usize]), point);
            let (a, b) = (f[i], f[(i + 1) % 3]);
            let interior = self.rings.left_of(a, b).is_some() && self.rings.right_of(a, b).is_some();
            if interior && !self.overlaps([a, b], point) {
                return Some(([a.min(b), a.max(b)], Placement::Searched));
            }
        }
        let around: Vec<u32> = f.iter().copied().filter(|&u| self.present[u as usize]).collect();
        let edge = self.nearest_interior_edge(&around, point, |_| true)?;
        if !self.overlaps(edge, point) {
            return Some((edge, Placement::Searched));
        }
        let mut wider: Vec<u32> = around.iter().flat_map(|&u| self.rings.ring(u).iter().copied()).collect();
        wider.extend(&around);
        wider.sort_unstable();
        wider.dedup();
        self.nearest_interior_edge(&wider, point, |e| !self.overlaps(e, point)).map(|e| (e, Placement::Widened))
    }

    /// Fig. 4.10: the insertion overlaps when the point is farther from the split edge's
    /// midpoint than the longest edge of the two triangles the split divides.
    fn overlaps(&self, edge: [u32; 2], point: DVec3) -> bool {
        let (Some(c), Some(d)) = (self.rings.left_of(edge[0], edge[1]), self.rings.right_of(edge[0], edge[1])) else {
            return true;
        };
        let p = |v: u32| self.positions[v as usize];
        let [a, b] = edge;
        let longest =
            [(a, b), (a, c), (b, c), (a, d), (b, d)].iter().map(|&(x, y)| p(x).distance(p(y))).fold(0.0, f64::max);
        point.distance((p(a) + p(b)) * 0.5) > longest
    }

    /// The interior edge nearest `point` among the edges around the (present) vertices
    /// `around` that `fits` accepts (ties by vertex ids).
    fn nearest_interior_edge(&self, around: &[u32], point: DVec3, fits: impl Fn([u32; 2]) -> bool) -> Option<[u32; 2]> {
        let mut best: Option<(f64, [u32; 2])> = None;
        for &u in around {
            for &x in self.rings.ring(u) {
                if self.rings.left_of(u, x).is_none() || self.rings.right_of(u, x).is_none() {
                    continue;
                }
                let key = [u.min(x), u.max(x)];
                if !fits(key) {
                    continue;
                }
                let d = point_segment_distance_squared(point, self.positions[u as usize], self.positions[x as usize]);
                if best.is_none_or(|(bd, bk)| d < bd || (d == bd && key < bk)) {
                    best = Some((d, key));
                }
            }
        }
        best.map(|(_, e)| e)
    }

    /// Restores every inserted vertex's level degree (Algorithm 3): first by flipping back
    /// the link edges across its recorded ring vertices, then — where those are gone — by
    /// flipping the link edge opposite its widest angle, if that angle reaches the
    /// threshold. Returns the flips, applied to the rings already.
    fn fix_degrees(&mut self, inserted: &[&Removal], report: &mut LevelReport) -> Result<Vec<[u32; 2]>> {
        let fresh: HashSet<u32> = inserted.iter().map(|r| r.vertex).collect();
        let mut flips = Vec::new();
        for r in inserted {
            let v = r.vertex;
            let mut recorded = self.hierarchy.restore_of(r).iter();
            while self.rings.degree(v) < r.degree as usize {
                let ring = self.rings.ring(v).to_vec();
                let m = ring.len();
                // An open (boundary) ring has no link edge from its last vertex to its first.
                let links = if r.boundary { m - 1 } else { m };
                let link = |j: usize| (ring[j], ring[(j + 1) % m]);
                let wanted = recorded.next().and_then(|&[a, x]| {
                    (0..links).find(|&j| ring[j] == a && self.rings.right_of(a, link(j).1) == Some(x))
                });
                let widest = wanted.is_none();
                let chosen = wanted.or_else(|| {
                    (!r.boundary)
                        .then(|| {
                            widest_link_edge(
                                self.positions[v as usize],
                                &ring,
                                &self.positions,
                                self.hierarchy.fix_threshold,
                            )
                        })
                        .flatten()
                });
                let Some((a, b)) = chosen.map(link).filter(|&(a, b)| self.can_flip_link(v, a, b, &fresh)) else {
                    report.degree_misses += 1;
                    break;
                };
                self.rings.flip(a, b)?;
                flips.push([a, b]);
                report.widest_flips += usize::from(widest);
            }
        }
        Ok(flips)
    }

    /// Whether flipping v's link edge a–b (giving v a new neighbour across it) is valid.
    fn can_flip_link(&self, v: u32, a: u32, b: u32, fresh: &HashSet<u32>) -> bool {
        match self.rings.right_of(a, b) {
            Some(x) => {
                x != v
                    && !fresh.contains(&x)
                    && !self.rings.has_edge(v, x)
                    && self.rings.may_lose_neighbour(a, 0)
                    && self.rings.may_lose_neighbour(b, 0)
            }
            None => false,
        }
    }

    /// The current mesh, compacted, with input ids.
    ///
    /// # Errors
    /// [`Error::Native`] if the export fails.
    pub fn mesh(&self) -> Result<LevelMesh> {
        Ok(LevelMesh::compact(&self.positions, &self.triangles()?))
    }

    /// The current faces in input ids.
    ///
    /// # Errors
    /// [`Error::Native`] if the export fails.
    pub fn triangles(&self) -> Result<Vec<[u32; 3]>> {
        exported_triangles(&self.store)
    }
}

impl Hierarchy {
    /// Every level's mesh, finest (the input) first, as a build that records its levels
    /// gives them, made by refining the base domain one whole level at a time: the levels
    /// of a hierarchy whose build did not record them (a partitioned build's, #40).
    /// Refinement replays each level's recorded welds and flips, so each level is the one
    /// the build made (the same faces; tested against recorded levels).
    ///
    /// # Errors
    /// As [`Refiner::new`] and [`Refiner::refine_level`].
    pub fn levels_by_refinement(&self) -> Result<Vec<LevelMesh>> {
        let mut refiner = Refiner::new(self)?;
        let mut levels = vec![refiner.mesh()?];
        while !refiner.is_finished() {
            refiner.refine_level(&|_| true)?;
            levels.push(refiner.mesh()?);
        }
        levels.reverse();
        Ok(levels)
    }
}

/// Fraction of `original`'s faces (as oriented triangles, any rotation) found in `refined`.
pub fn connectivity_match(original: &[[u32; 3]], refined: &[[u32; 3]]) -> f64 {
    if original.is_empty() {
        return 1.0;
    }
    let have: HashSet<[u32; 3]> = refined.iter().map(|&t| face_key(t)).collect();
    original.iter().filter(|&&t| have.contains(&face_key(t))).count() as f64 / original.len() as f64
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hierarchy::{SimplifyOptions, build};
    use crate::mesh::primitives::torus;

    /// A refinement that moves nothing reads the hierarchy's positions in place; the first
    /// move (or added vertex) gives the refiner a copy of its own, and the hierarchy keeps
    /// the input's.
    #[test]
    fn positions_are_copied_only_when_something_moves() {
        let mesh = torus(1.0, 0.35, 24, 12);
        let h = build(&mesh, &SimplifyOptions::default()).unwrap();
        let mut refiner = Refiner::new(&h).unwrap();
        refiner.refine_all().unwrap();
        assert!(matches!(refiner.positions, Cow::Borrowed(_)), "an undeformed refinement copied the positions");
        assert_eq!(refiner.positions(), &mesh.positions[..]);
        let mut moved = Refiner::new(&h).unwrap();
        moved.refine_level(&|_| true).unwrap();
        let v = moved.vertices()[0];
        moved.positions_mut()[v as usize].x += 0.5;
        moved.refine_all().unwrap();
        assert!(matches!(moved.positions, Cow::Owned(_)));
        assert_eq!(moved.positions()[v as usize].x, mesh.positions[v as usize].x + 0.5);
        assert_eq!(h.positions, mesh.positions, "the hierarchy's positions moved with the refiner's");
    }
}
