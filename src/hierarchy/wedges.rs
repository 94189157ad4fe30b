//! Texture coordinates and materials on every level (#22 B): which of a seam vertex's UVs
//! a level's face takes, and the UVs of vertices made by local subdivision.
//!
//! Levels keep the input's vertices, so a face's corner takes its vertex's UV, and a vertex
//! off the seams has one. A seam vertex has one UV per *wedge*, the sector of its faces
//! between two seam edges. Seams are simplified along themselves ([`super::lines`]), so a
//! level's seam edge v–x stands for the input's seam path from v to x, and a level's face
//! at v lies in the wedge that starts at the first input edge of the seam path bounding
//! its sector. Turning clockwise around v from the face until a seam edge v–x, then
//! following the input seam from v towards x, finds that first edge v–n; the wedge is the
//! input face on the left of v → n. A boundary met first is passed by turning the other
//! way (the wedge is then on the right of the seam edge found).
//!
//! A vertex w that local subdivision made at the midpoint of an edge a–b takes, on each
//! side of a → b, the mean of a's and b's UVs on that side (its parameter face's
//! interpolation, thesis §4.7.1.1). Where a–b ran along a seam, w joins the seam between a
//! and b, and a face at w takes the side it lies on.

use rustc_hash::FxHashMap;

use crate::error::{Error, Result};
use crate::mesh::Mesh;
use crate::mesh::uv::{CornerUvs, Materials};

/// The input's corner UVs and materials, and what finding wedges needs.
#[derive(Debug, Clone)]
pub struct Wedges {
    uvs: Option<CornerUvs>,
    materials: Option<Materials>,
    /// Directed input edge → (face on its left, corner of its start).
    half: FxHashMap<[u32; 2], (u32, u8)>,
    /// Seam neighbours of each vertex (empty off the seams).
    seam_neighbours: Vec<Vec<u32>>,
    /// A face and corner of each vertex, for vertices off the seams.
    any_corner: Vec<(u32, u8)>,
    /// The input's triangles.
    triangles: Vec<[u32; 3]>,
}

/// What a face's corner takes: a UV (an index into the values, the input's then the made
/// vertices') and the material of the face the wedge belongs to.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Wedge {
    uv: u32,
    material: u32,
}

/// A made vertex: the edge it split and what it takes on each side of it (left, right of
/// `ends[0]` → `ends[1]`).
#[derive(Debug, Clone, Copy)]
struct Made {
    sides: [Wedge; 2],
}

/// The mesh being given attributes: its faces, their directed edges, which vertices it
/// has, and the seams as they run in it.
struct Target<'a> {
    triangles: &'a [[u32; 3]],
    half: FxHashMap<[u32; 2], u32>,
    present: Vec<bool>,
    /// Seam neighbours of every id (input ones edited where made vertices joined a seam;
    /// a made vertex's are [towards its edge's first end, towards the second]).
    seams: Vec<Vec<u32>>,
    /// (v, made vertex on a seam next to v) → the input seam neighbour of v it stands for.
    stands_for: FxHashMap<[u32; 2], u32>,
    /// Level seam edge v–x → the first vertex of the seam path from v towards x.
    first_steps: FxHashMap<[u32; 2], u32>,
}

impl Wedges {
    /// The wedges of `input`, whose seam edges are `seams` ([`crate::mesh::uv::seam_edges`]); `None` when it
    /// has neither UVs nor materials.
    pub fn of(input: &Mesh, seams: &[[u32; 2]]) -> Option<Self> {
        if input.uvs.is_none() && input.materials.is_none() {
            return None;
        }
        let n = input.vertex_count();
        let mut half = FxHashMap::default();
        let mut any_corner = vec![(u32::MAX, 0u8); n];
        for (f, t) in input.triangles.iter().enumerate() {
            for k in 0..3 {
                half.insert([t[k], t[(k + 1) % 3]], (f as u32, k as u8));
                any_corner[t[k] as usize] = (f as u32, k as u8);
            }
        }
        let mut seam_neighbours = vec![Vec::new(); n];
        for &[a, b] in seams {
            seam_neighbours[a as usize].push(b);
            seam_neighbours[b as usize].push(a);
        }
        Some(Wedges {
            uvs: input.uvs.clone(),
            materials: input.materials.clone(),
            half,
            seam_neighbours,
            any_corner,
            triangles: input.triangles.clone(),
        })
    }

    /// The seam edges of a level of the input whose faces are `triangles` (smaller id
    /// first, sorted): its edges between two seam vertices that the input's seam runs
    /// along through vertices the level has not (a partitioned build's joined parts, #40,
    /// which the continuation simplifies along these as a one-piece build does).
    ///
    /// # Errors
    /// [`Error::Internal`] for a vertex that is not the input's.
    pub fn level_seam_edges(&self, triangles: &[[u32; 3]]) -> Result<Vec<[u32; 2]>> {
        let n = self.seam_neighbours.len();
        let target = self.target(triangles, n)?;
        let mut seams: Vec<[u32; 2]> = target
            .seam_steps(n)
            .into_keys()
            .filter(|&[v, x]| v < x && (target.half.contains_key(&[v, x]) || target.half.contains_key(&[x, v])))
            .collect();
        seams.sort_unstable();
        Ok(seams)
    }

    /// The mesh of `triangles` to give attributes, its vertices below `total` (the input's
    /// and those made by splits): which are present, and each directed edge's face.
    fn target<'a>(&self, triangles: &'a [[u32; 3]], total: usize) -> Result<Target<'a>> {
        if let Some(v) = triangles.iter().flatten().find(|&&v| v as usize >= total) {
            return Err(Error::Internal(format!("vertex {v} is neither an input vertex nor made: its UV is unknown")));
        }
        let mut target = Target {
            triangles,
            half: FxHashMap::default(),
            present: vec![false; total],
            seams: self.seam_neighbours.clone(),
            stands_for: FxHashMap::default(),
            first_steps: FxHashMap::default(),
        };
        for (f, t) in triangles.iter().enumerate() {
            for k in 0..3 {
                target.present[t[k] as usize] = true;
                target.half.insert([t[k], t[(k + 1) % 3]], f as u32);
            }
        }
        Ok(target)
    }

    /// The corner UVs and face materials of `triangles`, in their order: a level's or a
    /// refinement's faces, whose vertices are input vertices and the vertices made by
    /// `splits` (vertex n + i split edge `splits[i]` at its midpoint, in that order).
    ///
    /// # Errors
    /// [`Error::Internal`] when a face's wedge cannot be found (a seam the mesh does not
    /// keep: a bug of the simplification) or a vertex is neither an input one nor made.
    pub fn level(&self, triangles: &[[u32; 3]], splits: &[[u32; 2]]) -> Result<(Option<CornerUvs>, Option<Materials>)> {
        let n = self.seam_neighbours.len();
        let total = n + splits.len();
        let mut target = self.target(triangles, total)?;
        // Where each made vertex lies: the vertex next to each end along its edge, and
        // whether the edge ran along a seam (then it joins the seam).
        let mut next: FxHashMap<[u32; 2], u32> = FxHashMap::default();
        target.seams.resize(total, Vec::new());
        for (i, &[a, b]) in splits.iter().enumerate() {
            let w = (n + i) as u32;
            next.insert([a, b], w);
            next.insert([b, a], w);
            if let Some([from_a, from_b]) = target.seam_path_ends(a, b) {
                target.join_seam(a, from_a, w);
                target.join_seam(b, from_b, w);
                target.seams[w as usize] = vec![a, b];
            }
        }
        target.first_steps = target.seam_steps(n);
        let adjacent = |p: u32, q: u32| {
            let mut x = q;
            while let Some(&y) = next.get(&[p, x]) {
                x = y;
            }
            x
        };
        // Made vertices' two sides, in order (a made vertex's ends were made before it).
        let mut values: Vec<[f64; 2]> = self.uvs.as_ref().map(|u| u.values.clone()).unwrap_or_default();
        let mut made: Vec<Made> = Vec::with_capacity(splits.len());
        for (i, &[a, b]) in splits.iter().enumerate() {
            let (xa, xb) = (adjacent(a, b), adjacent(b, a));
            let mut sides = [Wedge { uv: 0, material: u32::MAX }; 2];
            for (side, (fa, fb)) in [([a, xa], [xb, b]), ([xa, a], [b, xb])].into_iter().enumerate() {
                let at = |v: u32, edge: [u32; 2]| {
                    let f = *target.half.get(&edge)?;
                    self.corner(&target, &made, n, f, v)
                };
                let (ua, ub) = (at(a, fa), at(b, fb));
                sides[side] = match (ua, ub) {
                    (Some(ua), Some(ub)) => {
                        let uv = self.uvs.as_ref().map_or(0, |_| {
                            let [p, q] = [values[ua.uv as usize], values[ub.uv as usize]];
                            values.push([0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1])]);
                            (values.len() - 1) as u32
                        });
                        Wedge { uv, material: ua.material }
                    }
                    _ => Wedge { uv: u32::MAX, material: u32::MAX },
                };
            }
            // Sides that agree share one coordinate; a side on a boundary takes the other's.
            if sides[1].uv != u32::MAX && sides[0].uv != u32::MAX && self.uvs.is_some() {
                let last = values.len() - 1;
                if values[last] == values[last - 1] && sides[1].uv as usize == last {
                    values.pop();
                    sides[1].uv = sides[0].uv;
                }
            }
            if sides[0].uv == u32::MAX {
                sides[0] = sides[1];
            } else if sides[1].uv == u32::MAX {
                sides[1] = sides[0];
            }
            if sides[0].uv == u32::MAX {
                return Err(Error::Internal(format!("made vertex {} on edge {a}–{b}: no face beside it", n + i)));
            }
            made.push(Made { sides });
        }
        let mut corners: Vec<[u32; 3]> = Vec::with_capacity(triangles.len());
        let mut faces = Vec::with_capacity(triangles.len());
        for (f, t) in triangles.iter().enumerate() {
            let mut wedge = [Wedge { uv: 0, material: 0 }; 3];
            for k in 0..3 {
                wedge[k] = self.corner(&target, &made, n, f as u32, t[k]).ok_or_else(|| {
                    Error::Internal(format!("face {f} {t:?}: no wedge of vertex {} holds it", t[k]))
                })?;
            }
            corners.push(wedge.map(|w| w.uv));
            // A corner off the seams has its one material; any corner's is the face's.
            faces.push(wedge[0].material);
        }
        // Only the coordinates the faces use, in order of first use.
        let uvs = self.uvs.as_ref().map(|_| {
            let mut index = vec![u32::MAX; values.len()];
            let mut used = Vec::new();
            for c in corners.iter_mut().flatten() {
                if index[*c as usize] == u32::MAX {
                    index[*c as usize] = used.len() as u32;
                    used.push(values[*c as usize]);
                }
                *c = index[*c as usize];
            }
            CornerUvs { values: used, corners }
        });
        let materials =
            self.materials.as_ref().map(|m| Materials { libraries: m.libraries.clone(), names: m.names.clone(), faces });
        Ok((uvs, materials))
    }

    /// What corner `v` of face `f` of the target takes.
    fn corner(&self, target: &Target, made: &[Made], n: usize, f: u32, v: u32) -> Option<Wedge> {
        if v as usize >= n {
            let m = made.get(v as usize - n)?;
            if m.sides[0] == m.sides[1] || target.seams[v as usize].is_empty() {
                return Some(m.sides[0]);
            }
            // On a seam: the side of the edge the face lies on. Left of w → (towards the
            // first end) is the right of first → second.
            let (x, clockwise) = target.turn_to_seam(f, v)?;
            let towards_first = target.seams[v as usize].first() == Some(&x);
            let left_of_edge = towards_first != clockwise;
            return Some(m.sides[if left_of_edge { 0 } else { 1 }]);
        }
        if target.seams[v as usize].is_empty() {
            return Some(self.input_wedge(self.any_corner[v as usize]));
        }
        let (x, clockwise) = target.turn_to_seam(f, v)?;
        let step = *target.first_steps.get(&[v, x])?;
        // A made vertex next to v on a seam stands for the input seam neighbour it replaced.
        let step = target.stands_for.get(&[v, step]).copied().unwrap_or(step);
        let (g, j) = if clockwise {
            *self.half.get(&[v, step])?
        } else {
            let (g, _) = *self.half.get(&[step, v])?;
            (g, self.corner_index(g, v)?)
        };
        Some(self.input_wedge((g, j)))
    }

    fn input_wedge(&self, (f, k): (u32, u8)) -> Wedge {
        Wedge {
            uv: self.uvs.as_ref().map_or(0, |u| u.corners[f as usize][k as usize]),
            material: self.materials.as_ref().map_or(u32::MAX, |m| m.faces[f as usize]),
        }
    }

    /// The corner of `v` in input face `f`.
    fn corner_index(&self, f: u32, v: u32) -> Option<u8> {
        self.triangles[f as usize].iter().position(|&w| w == v).map(|k| k as u8)
    }
}

impl Target<'_> {
    /// The seam path from `a` towards `b` through vertices absent here: the first vertex
    /// after `a` and the last before `b`, if it reaches `b`.
    fn seam_path_ends(&self, a: u32, b: u32) -> Option<[u32; 2]> {
        self.seams[a as usize].iter().find_map(|&first| {
            let (previous, current) = self.walk_seam(a, first, |w| w == b);
            (current == b).then_some([first, previous])
        })
    }

    /// Walks the seam from `from` through `first` while the vertices are absent here and on
    /// a line (two seam neighbours), stopping early at a vertex `stop` accepts; returns the
    /// last two vertices (the walk's end is `.1`: present, stopped at, or where the seam
    /// branches or ends).
    fn walk_seam(&self, from: u32, first: u32, stop: impl Fn(u32) -> bool) -> (u32, u32) {
        let (mut previous, mut current) = (from, first);
        let mut guard = self.seams.len();
        while !stop(current) && !self.present[current as usize] && guard > 0 {
            let ahead = &self.seams[current as usize];
            let Some(&next) = ahead.iter().find(|&&w| w != previous).filter(|_| ahead.len() == 2) else {
                break;
            };
            (previous, current) = (current, next);
            guard -= 1;
        }
        (previous, current)
    }

    /// Made vertex `w` takes the place of `v`'s seam neighbour `old`.
    fn join_seam(&mut self, v: u32, old: u32, w: u32) {
        if let Some(slot) = self.seams[v as usize].iter_mut().find(|s| **s == old) {
            *slot = w;
        }
        let original = self.stands_for.get(&[v, old]).copied().unwrap_or(old);
        self.stands_for.insert([v, w], original);
    }

    /// For each present seam vertex v among the first `n` (the input's) and each seam
    /// edge v–x here: the first vertex of the seam path from v to x.
    fn seam_steps(&self, n: usize) -> FxHashMap<[u32; 2], u32> {
        let mut steps = FxHashMap::default();
        for v in 0..n {
            if !self.present[v] {
                continue;
            }
            for &first in &self.seams[v] {
                let (_, current) = self.walk_seam(v as u32, first, |_| false);
                if self.present[current as usize] {
                    steps.entry([v as u32, current]).or_insert(first);
                }
            }
        }
        steps
    }

    /// Turns around `v` from face `f` to the first seam edge: clockwise (the face on its
    /// left) or, past a boundary, counter-clockwise (on its right). Returns the edge's
    /// other end and the direction.
    fn turn_to_seam(&self, f: u32, v: u32) -> Option<(u32, bool)> {
        let is_seam = |x: u32| self.seams[v as usize].contains(&x) || self.first_steps.contains_key(&[v, x]);
        // No ring of a level is this large; a walk that finds no seam gives up.
        const LIMIT: usize = 1 << 12;
        let t = self.triangles[f as usize];
        let k = t.iter().position(|&w| w == v)?;
        let mut a = t[(k + 1) % 3];
        for _ in 0..LIMIT {
            if is_seam(a) {
                return Some((a, true));
            }
            let Some(&across) = self.half.get(&[a, v]) else { break };
            let u = self.triangles[across as usize];
            let j = u.iter().position(|&w| w == v)?;
            a = u[(j + 1) % 3];
        }
        let mut b = t[(k + 2) % 3];
        for _ in 0..LIMIT {
            if is_seam(b) {
                return Some((b, false));
            }
            let across = *self.half.get(&[v, b])?;
            let u = self.triangles[across as usize];
            let j = u.iter().position(|&w| w == v)?;
            b = u[(j + 2) % 3];
        }
        None
    }
}
