//! Mesh repair for inputs the hierarchy cannot take as they are: degenerate and duplicate
//! faces removed, non-manifold vertices and edges split, faces oriented consistently,
//! unreferenced vertices dropped. Each stage is a pure function of the mesh, in input
//! order, so a repair is deterministic.
//!
//! The splitting follows the usual corner-fan construction (Guéziec et al., "Cutting and
//! stitching", IEEE TVCG 2001): the corners of a vertex are joined across the edges that
//! have exactly two faces; every fan beyond the first gets its own copy of the vertex.
//! Joined corners form paths or cycles around the vertex, so the result is manifold.

use std::fmt;

use rustc_hash::FxHashSet;
use serde::Serialize;

use super::Mesh;
use super::validate::{
    DisjointSets, EdgeTable, HalfEdgeUse, count_non_manifold_vertices, is_degenerate_face, is_degenerate_triangle,
    used_vertices,
};
use crate::error::Result;

/// What [`repair`] changed; all zero when the mesh needed nothing.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct RepairReport {
    /// Degenerate faces (repeating a vertex or of (relatively) zero area) removed, by any of
    /// the means below or, where none applies, by deleting the face.
    pub degenerate_faces: usize,
    /// Needles removed by collapsing their shortest edge (its two nearly coincident ends
    /// merged), which also removes the face on the edge's other side.
    pub collapsed_edges: usize,
    /// Caps (a corner on the opposite edge) removed by flipping their longest edge, which
    /// splits the face beyond it in two.
    pub flipped_edges: usize,
    /// Faces removed for using the same three vertices as an earlier face.
    pub duplicate_faces: usize,
    /// Vertices added by splitting non-manifold vertices and edges into manifold fans.
    pub split_vertices: usize,
    /// Faces whose orientation was reversed to agree with their neighbours.
    pub flipped_faces: usize,
    /// Vertices removed because no face used them.
    pub unreferenced_vertices: usize,
    /// Edges still traversed the same way by both faces: the surface is not orientable.
    pub non_orientable_edges: usize,
}

impl RepairReport {
    /// Whether the repair changed anything.
    pub fn changed(&self) -> bool {
        self.degenerate_faces
            + self.duplicate_faces
            + self.split_vertices
            + self.flipped_faces
            + self.unreferenced_vertices
            > 0
    }
}

impl fmt::Display for RepairReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let parts: Vec<String> = [
            (self.degenerate_faces, "degenerate face", "removed"),
            (self.duplicate_faces, "duplicate face", "removed"),
            (self.split_vertices, "vertex", "added by splitting non-manifold fans"),
            (self.flipped_faces, "face", "flipped"),
            (self.unreferenced_vertices, "unreferenced vertex", "dropped"),
            (self.non_orientable_edges, "non-orientable edge", "left"),
        ]
        .into_iter()
        .filter(|(n, _, _)| *n > 0)
        .map(|(n, what, done)| format!("{n} {} {done}", plural(what, n)))
        .collect();
        let mut parts = parts;
        if self.collapsed_edges + self.flipped_edges > 0
            && let Some(first) = parts.first_mut().filter(|_| self.degenerate_faces > 0) {
                first.push_str(&format!(
                    " ({} short {} collapsed, {} {} flipped, so the surface stays closed)",
                    self.collapsed_edges,
                    plural("edge", self.collapsed_edges),
                    self.flipped_edges,
                    plural("edge", self.flipped_edges)
                ));
            }
        if parts.is_empty() { f.write_str("nothing to repair") } else { f.write_str(&parts.join(", ")) }
    }
}

fn plural(word: &str, n: usize) -> String {
    match (n, word.strip_suffix("ex")) {
        (1, _) => word.to_string(),
        (_, Some(stem)) => format!("{stem}ices"),
        _ => format!("{word}s"),
    }
}

/// Repairs `mesh` (which must pass [`Mesh::check`]) in five stages: degenerate faces,
/// duplicate faces, non-manifold splitting, orientation, unreferenced vertices.
/// Attributes follow their vertices; split copies carry the original's.
///
/// # Errors
/// [`crate::Error::InvalidInput`] when the mesh fails [`Mesh::check`].
pub fn repair(mesh: &Mesh) -> Result<(Mesh, RepairReport)> {
    repair_merging(mesh).map(|(out, report, _)| (out, report))
}

/// (gone, kept) vertex pairs a repair's needle collapses merged, in order.
type Merges = Vec<(u32, u32)>;

/// [`repair`], with the pairs its needle collapses merged.
fn repair_merging(mesh: &Mesh) -> Result<(Mesh, RepairReport, Merges)> {
    mesh.check()?;
    let mut out = mesh.clone();
    let (degenerate, merged) = remove_degenerate_faces_merging(&mut out);
    let mut report = RepairReport {
        degenerate_faces: degenerate.removed,
        collapsed_edges: degenerate.collapsed,
        flipped_edges: degenerate.flipped,
        duplicate_faces: remove_duplicate_faces(&mut out),
        ..Default::default()
    };
    report.split_vertices = split_non_manifold_fans(&mut out);
    (report.flipped_faces, report.non_orientable_edges) = orient_faces(&mut out);
    report.unreferenced_vertices = drop_unreferenced_vertices(&mut out);
    Ok((out, report, merged))
}

/// Where each vertex of a repaired mesh came from, and which vertex stands for each input
/// vertex, so that callers keep their own numbering (#36: Python's arrays came back shorter
/// than the caller's when the repair dropped a vertex).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct VertexOrigins {
    /// For each repaired vertex, the input vertex it is; a split copy names the vertex it
    /// copies.
    pub source: Vec<u32>,
    /// For each input vertex, the repaired vertex that stands for it: itself renumbered (the
    /// first of its copies), the vertex a collapsed needle merged it into, or `None` for a
    /// vertex no face used.
    pub stands_for: Vec<Option<u32>>,
}

/// The scalar that carries input ids through [`repair`] (scalars follow their vertices
/// through every stage; a name no file can hold).
const ORIGIN_SCALAR: &str = "\u{0}asperity-origin";

/// [`repair`], with where every vertex came from.
///
/// # Errors
/// As [`repair`].
pub fn repair_with_origins(mesh: &Mesh) -> Result<(Mesh, RepairReport, VertexOrigins)> {
    let mut marked = mesh.clone();
    marked.scalars.insert(ORIGIN_SCALAR.into(), (0..mesh.vertex_count()).map(|v| v as f64).collect());
    let (mut out, report, merged) = repair_merging(&marked)?;
    let source: Vec<u32> =
        out.scalars.remove(ORIGIN_SCALAR).unwrap_or_default().into_iter().map(|v| v as u32).collect();
    let mut stands_for: Vec<Option<u32>> = vec![None; mesh.vertex_count()];
    for (v, &u) in source.iter().enumerate() {
        stands_for[u as usize].get_or_insert(v as u32);
    }
    // A vertex a needle's collapse merged away is stood for by the vertex it went into
    // (which may itself have gone into another later).
    let into: rustc_hash::FxHashMap<u32, u32> = merged.iter().copied().collect();
    for &(gone, _) in &merged {
        let mut at = gone;
        for _ in 0..=merged.len() {
            let Some(&kept) = into.get(&at) else { break };
            if let Some(v) = stands_for[kept as usize] {
                stands_for[gone as usize] = Some(v);
                break;
            }
            at = kept;
        }
    }
    Ok((out, report, VertexOrigins { source, stands_for }))
}

/// What [`remove_degenerate_faces`] did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct DegenerateRemoval {
    /// Degenerate faces gone, by whatever means.
    pub removed: usize,
    /// Short edges collapsed (needles).
    pub collapsed: usize,
    /// Long edges flipped (caps).
    pub flipped: usize,
}

/// A needle's shortest edge is at most this fraction of its longest; otherwise a zero-area
/// face is a cap (its third corner lies on its longest edge).
const NEEDLE_RATIO: f64 = 1e-3;

/// Removes faces that repeat a vertex or have zero area relative to their longest edge,
/// keeping the surface closed where it was (deleting a zero-area face leaves a hole where
/// its neighbours met it): as Botsch & Kobbelt's remeshing and Attene's MeshFix treat
/// degenerate triangles, a needle (two nearly coincident corners) is removed by collapsing
/// its shortest edge onto its lower-numbered end, which also removes the needle across
/// that edge, and a cap (a corner on the opposite edge) by flipping that longest edge,
/// which splits the face beyond it in two along the cap's corner. A face repeating a
/// vertex is deleted: its two copies of an edge join its neighbours, which then meet. A
/// degenerate face neither rule can remove (a cap on a boundary, a flip that would
/// duplicate an edge) is deleted. Positions never move.
pub fn remove_degenerate_faces(mesh: &mut Mesh) -> DegenerateRemoval {
    remove_degenerate_faces_merging(mesh).0
}

/// [`remove_degenerate_faces`], with the (gone, kept) vertex pairs its collapses merged.
fn remove_degenerate_faces_merging(mesh: &mut Mesh) -> (DegenerateRemoval, Merges) {
    let mut state = Degenerates::new(mesh);
    let mut queue: std::collections::VecDeque<usize> =
        (0..mesh.face_count()).filter(|&f| is_degenerate_face(mesh, f)).collect();
    let mut budget = 4 * queue.len() + 16;
    while let Some(f) = queue.pop_front() {
        if !state.alive[f] || !state.is_degenerate(f) {
            continue;
        }
        let made = if budget == 0 { None } else { state.remove(f) };
        budget = budget.saturating_sub(1);
        match made {
            Some(new_faces) => queue.extend(new_faces.into_iter().filter(|&g| state.is_degenerate(g))),
            None => state.delete(f),
        }
    }
    let Degenerates { triangles, alive, report, uv_corners, merged, .. } = state;
    mesh.triangles = triangles;
    if let (Some(uvs), Some(corners)) = (&mut mesh.uvs, uv_corners) {
        uvs.corners = corners;
    }
    mesh.retain_faces(&alive);
    (report, merged)
}

/// The faces while degenerate ones are removed: directed edges to faces, vertices to faces.
struct Degenerates<'a> {
    positions: &'a [glam::DVec3],
    triangles: Vec<[u32; 3]>,
    alive: Vec<bool>,
    edges: rustc_hash::FxHashMap<(u32, u32), usize>,
    faces_of: Vec<Vec<usize>>,
    report: DegenerateRemoval,
    /// Each face's UV indices, following its corners through collapses and flips.
    uv_corners: Option<Vec<[u32; 3]>>,
    /// (gone, kept) for every collapse, in order.
    merged: Vec<(u32, u32)>,
}

impl<'a> Degenerates<'a> {
    fn new(mesh: &'a Mesh) -> Self {
        let mut edges = rustc_hash::FxHashMap::default();
        let mut faces_of = vec![Vec::new(); mesh.vertex_count()];
        for (f, t) in mesh.triangles.iter().enumerate() {
            for i in 0..3 {
                edges.insert((t[i], t[(i + 1) % 3]), f);
                faces_of[t[i] as usize].push(f);
            }
        }
        let alive = vec![true; mesh.face_count()];
        Degenerates {
            positions: &mesh.positions,
            triangles: mesh.triangles.clone(),
            alive,
            edges,
            faces_of,
            report: DegenerateRemoval::default(),
            uv_corners: mesh.uvs.as_ref().map(|u| u.corners.clone()),
            merged: Vec::new(),
        }
    }

    fn is_degenerate(&self, f: usize) -> bool {
        self.alive[f] && is_degenerate_triangle(self.positions, self.triangles[f])
    }

    /// Removes degenerate face `f` by a collapse or a flip; returns the faces that changed
    /// (to check again), or `None` when neither applies.
    fn remove(&mut self, f: usize) -> Option<Vec<usize>> {
        let t = self.triangles[f];
        if super::validate::repeats_a_vertex(t) {
            return None;
        }
        let p = t.map(|v| self.positions[v as usize]);
        let length = |i: usize| p[i].distance_squared(p[(i + 1) % 3]);
        let shortest = (0..3).min_by(|&a, &b| length(a).total_cmp(&length(b))).expect("three edges");
        let longest = (0..3).max_by(|&a, &b| length(a).total_cmp(&length(b))).expect("three edges");
        if length(shortest) <= NEEDLE_RATIO * NEEDLE_RATIO * length(longest) {
            let (a, b) = (t[shortest], t[(shortest + 1) % 3]);
            return Some(self.collapse(a.min(b), a.max(b)));
        }
        self.flip(f, longest)
    }

    /// Merges vertex `gone` into `kept`: every face of `gone` takes `kept`, faces with both
    /// are deleted.
    fn collapse(&mut self, kept: u32, gone: u32) -> Vec<usize> {
        let faces = std::mem::take(&mut self.faces_of[gone as usize]);
        // The faces that take `kept` take its UV from a face holding both (the needle).
        let kept_uv = self.uv_corners.as_ref().and_then(|uv| {
            faces.iter().find_map(|&f| {
                let t = self.triangles[f];
                let k = t.iter().position(|&v| v == kept)?;
                (self.alive[f] && t.contains(&gone)).then_some(uv[f][k])
            })
        });
        let mut changed = Vec::new();
        for f in faces {
            // A face flipped earlier may no longer hold `gone` (its list keeps it).
            if !self.alive[f] || !self.triangles[f].contains(&gone) {
                continue;
            }
            if self.triangles[f].contains(&kept) {
                self.delete(f);
                continue;
            }
            self.unlink(f);
            for (k, v) in self.triangles[f].iter_mut().enumerate() {
                if *v == gone {
                    *v = kept;
                    if let (Some(uv), Some(kept_uv)) = (&mut self.uv_corners, kept_uv) {
                        uv[f][k] = kept_uv;
                    }
                }
            }
            self.link(f);
            self.faces_of[kept as usize].push(f);
            changed.push(f);
        }
        self.report.collapsed += 1;
        self.merged.push((gone, kept));
        changed
    }

    /// Flips edge `i` of cap `f` with the face across it: (a, b, c) and (b, a, d) become
    /// (c, a, d) and (d, b, c).
    fn flip(&mut self, f: usize, i: usize) -> Option<Vec<usize>> {
        let t = self.triangles[f];
        let (a, b, c) = (t[i], t[(i + 1) % 3], t[(i + 2) % 3]);
        let g = *self.edges.get(&(b, a))?;
        if g == f || !self.alive[g] {
            return None;
        }
        let u = self.triangles[g];
        let k = (0..3).find(|&k| u[k] == b && u[(k + 1) % 3] == a)?;
        let d = u[(k + 2) % 3];
        if d == c || self.edges.contains_key(&(c, d)) || self.edges.contains_key(&(d, c)) {
            return None;
        }
        self.unlink(f);
        self.unlink(g);
        self.triangles[f] = [c, a, d];
        self.triangles[g] = [d, b, c];
        if let Some(uv) = &mut self.uv_corners {
            // Each corner keeps the UV its vertex had in the face it came from.
            let (uf, ug) = (uv[f], uv[g]);
            let tc = uf[(i + 2) % 3];
            uv[f] = [tc, uf[i], ug[(k + 2) % 3]];
            uv[g] = [ug[(k + 2) % 3], uf[(i + 1) % 3], tc];
        }
        self.link(f);
        self.link(g);
        self.faces_of[d as usize].push(f);
        self.faces_of[c as usize].push(g);
        self.report.flipped += 1;
        self.report.removed += 1;
        Some(vec![f, g])
    }

    fn delete(&mut self, f: usize) {
        self.unlink(f);
        self.alive[f] = false;
        self.report.removed += 1;
    }

    fn unlink(&mut self, f: usize) {
        let t = self.triangles[f];
        for i in 0..3 {
            let key = (t[i], t[(i + 1) % 3]);
            if self.edges.get(&key) == Some(&f) {
                self.edges.remove(&key);
            }
        }
    }

    fn link(&mut self, f: usize) {
        let t = self.triangles[f];
        for i in 0..3 {
            self.edges.insert((t[i], t[(i + 1) % 3]), f);
        }
    }
}

/// Removes every face whose vertex set equals an earlier face's, whatever its orientation.
pub fn remove_duplicate_faces(mesh: &mut Mesh) -> usize {
    let mut seen = FxHashSet::default();
    let keep: Vec<bool> = mesh
        .triangles
        .iter()
        .map(|t| {
            let mut key = *t;
            key.sort_unstable();
            seen.insert(key)
        })
        .collect();
    mesh.retain_faces(&keep)
}

/// Gives every fan of face corners around a vertex, beyond the first, its own vertex.
/// Returns the number of vertices added. Faces repeating a vertex must be gone (see
/// [`remove_degenerate_faces`]).
///
/// The first pass joins corners across two-face edges and, on an edge with more faces,
/// across the first pair (in face order) that runs it in opposite directions, so that a
/// fin glued to a surface comes off and the surface stays whole. Should that leave an
/// edge with more than two faces (the fans meet again around a vertex), a second pass
/// joins across two-face edges only, which always ends in a manifold: corners joined so
/// form paths or cycles around each vertex.
pub fn split_non_manifold_fans(mesh: &mut Mesh) -> usize {
    let added_before = mesh.vertex_count();
    for join_pairs in [true, false] {
        let edges = EdgeTable::build(&mesh.triangles);
        let corner = |face: u32, v: u32| -> usize {
            let t = mesh.triangles[face as usize];
            3 * face as usize + t.iter().position(|&x| x == v).expect("vertex of face")
        };
        if !join_pairs && edges.groups().all(|g| g.len() <= 2) && count_non_manifold_vertices(mesh, &edges) == 0 {
            break;
        }
        let mut fans = DisjointSets::new(mesh.triangles.len() * 3);
        for group in edges.groups() {
            let pair = match group.len() {
                2 => Some((group[0], group[1])),
                n if n > 2 && join_pairs => opposite_pair(group),
                _ => None,
            };
            if let Some((a, b)) = pair {
                fans.union(corner(a.face, a.lo), corner(b.face, b.lo));
                fans.union(corner(a.face, a.hi), corner(b.face, b.hi));
            }
        }
        // The first fan met (in face order) keeps the vertex; later fans get copies.
        let mut first_fan = vec![u32::MAX; mesh.vertex_count()];
        let mut copy_of_fan = rustc_hash::FxHashMap::default();
        let mut copies: Vec<u32> = Vec::new();
        for f in 0..mesh.triangles.len() {
            for k in 0..3 {
                let v = mesh.triangles[f][k];
                let fan = fans.find(3 * f + k) as u32;
                let slot = &mut first_fan[v as usize];
                if *slot == u32::MAX {
                    *slot = fan;
                } else if *slot != fan {
                    let next = (mesh.vertex_count() + copies.len()) as u32;
                    let id = *copy_of_fan.entry(fan).or_insert_with(|| {
                        copies.push(v);
                        next
                    });
                    mesh.triangles[f][k] = id;
                }
            }
        }
        append_copies(mesh, &copies);
    }
    mesh.vertex_count() - added_before
}

/// The first two uses of an edge (in face order) that run it in opposite directions.
fn opposite_pair(group: &[HalfEdgeUse]) -> Option<(HalfEdgeUse, HalfEdgeUse)> {
    let first = group[0];
    let partner = group[1..].iter().find(|u| u.forward != first.forward)?;
    Some((first, *partner))
}

/// Appends copies of the vertices `sources`, attributes included.
fn append_copies(mesh: &mut Mesh, sources: &[u32]) {
    let pick = |v: &u32| *v as usize;
    mesh.positions.extend(sources.iter().map(|v| mesh.positions[pick(v)]).collect::<Vec<_>>());
    if let Some(normals) = &mut mesh.normals {
        normals.extend(sources.iter().map(|v| normals[pick(v)]).collect::<Vec<_>>());
    }
    if let Some(colors) = &mut mesh.colors {
        colors.extend(sources.iter().map(|v| colors[pick(v)]).collect::<Vec<_>>());
    }
    for values in mesh.scalars.values_mut() {
        values.extend(sources.iter().map(|v| values[pick(v)]).collect::<Vec<_>>());
    }
}

/// Orients each edge-connected component consistently by a breadth-first walk across
/// two-face edges, then keeps the orientation most of the component's faces already had
/// (so a consistently oriented mesh is untouched). Returns the faces flipped and the
/// edges that still disagree (non-orientable surfaces such as a Möbius strip).
pub fn orient_faces(mesh: &mut Mesh) -> (usize, usize) {
    let faces = mesh.triangles.len();
    let edges = EdgeTable::build(&mesh.triangles);
    // Neighbours across two-face edges, with whether both faces run the edge the same way.
    let mut links: Vec<Vec<(u32, bool)>> = vec![Vec::new(); faces];
    for group in edges.groups().filter(|g| g.len() == 2) {
        let (a, b) = (group[0], group[1]);
        let same = a.forward == b.forward;
        links[a.face as usize].push((b.face, same));
        links[b.face as usize].push((a.face, same));
    }
    const UNSEEN: u8 = 2;
    let mut flip = vec![UNSEEN; faces];
    let mut conflicts = 0;
    let mut flipped = 0;
    let mut queue = std::collections::VecDeque::new();
    for seed in 0..faces {
        if flip[seed] != UNSEEN {
            continue;
        }
        let mut component = vec![seed];
        flip[seed] = 0;
        queue.push_back(seed);
        while let Some(f) = queue.pop_front() {
            for &(g, same) in &links[f] {
                let want = flip[f] ^ u8::from(same);
                match flip[g as usize] {
                    UNSEEN => {
                        flip[g as usize] = want;
                        component.push(g as usize);
                        queue.push_back(g as usize);
                    }
                    have if have != want => conflicts += 1,
                    _ => {}
                }
            }
        }
        let to_flip = component.iter().filter(|&&f| flip[f] == 1).count();
        let invert = 2 * to_flip > component.len();
        for &f in &component {
            if (flip[f] == 1) != invert {
                mesh.triangles[f].swap(1, 2);
                if let Some(uvs) = &mut mesh.uvs {
                    uvs.corners[f].swap(1, 2);
                }
                flipped += 1;
            }
        }
    }
    // Each disagreeing edge was met from both of its faces.
    (flipped, conflicts / 2)
}

/// Removes vertices no face uses, renumbering the rest in order (attributes follow).
pub fn drop_unreferenced_vertices(mesh: &mut Mesh) -> usize {
    let n = mesh.vertex_count();
    let mut next = 0u32;
    let new_id: Vec<u32> = used_vertices(n, &mesh.triangles)
        .into_iter()
        .map(|used| {
            if !used {
                return u32::MAX;
            }
            next += 1;
            next - 1
        })
        .collect();
    if next as usize == n {
        return 0;
    }
    for t in &mut mesh.triangles {
        *t = t.map(|v| new_id[v as usize]);
    }
    fn keep<T: Copy>(values: &mut Vec<T>, new_id: &[u32]) {
        let mut i = 0;
        values.retain(|_| {
            i += 1;
            new_id[i - 1] != u32::MAX
        });
    }
    keep(&mut mesh.positions, &new_id);
    if let Some(v) = &mut mesh.normals {
        keep(v, &new_id);
    }
    if let Some(v) = &mut mesh.colors {
        keep(v, &new_id);
    }
    for v in mesh.scalars.values_mut() {
        keep(v, &new_id);
    }
    n - next as usize
}

#[cfg(test)]
mod origin_tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn origins_follow_dropped_split_and_merged_vertices() {
        // Two triangles sharing vertex 0 only (a bow tie: 0 is split), an unused vertex 3,
        // and a needle: vertex 7 nearly on vertex 6, collapsed into it.
        let positions = vec![
            DVec3::ZERO,
            DVec3::X,
            DVec3::Y,
            DVec3::splat(9.0),
            -DVec3::X,
            -DVec3::Y,
            DVec3::new(5.0, 0.0, 0.0),
            DVec3::new(5.0, 1e-9, 0.0),
            DVec3::new(6.0, 0.0, 0.0),
            DVec3::new(5.5, 1.0, 0.0),
            DVec3::new(5.5, -1.0, 0.0),
        ];
        let triangles = vec![[0, 1, 2], [0, 4, 5], [6, 8, 9], [7, 6, 10], [6, 7, 9]];
        let mesh = Mesh { positions, triangles, ..Mesh::default() };
        let (repaired, report, origins) = repair_with_origins(&mesh).unwrap();
        assert!(report.split_vertices >= 1 && report.unreferenced_vertices >= 1, "{report:?}");
        assert_eq!(origins.source.len(), repaired.vertex_count());
        assert!(repaired.scalars.is_empty(), "the marker scalar is removed");
        for (v, &u) in origins.source.iter().enumerate() {
            assert_eq!(repaired.positions[v], mesh.positions[u as usize], "vertex {v} is input {u}");
        }
        assert_eq!(origins.stands_for[3], None, "no face used vertex 3");
        assert_eq!(origins.source.iter().filter(|&&u| u == 0).count(), 2, "the bow tie's centre split in two");
        for u in [0usize, 1, 2, 4, 5, 6, 8, 9] {
            let v = origins.stands_for[u].expect("kept") as usize;
            assert_eq!(origins.source[v] as usize, u);
        }
        if report.collapsed_edges > 0 {
            let v = origins.stands_for[7].expect("merged") as usize;
            assert_eq!(origins.source[v], 6, "the needle's end merged into its neighbour");
        }
    }
}
