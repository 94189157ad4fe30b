//! Feature lines simplified along themselves (#19; an extension of the thesis §4.4.1.1,
//! whose literal rule keeps every feature vertex).
//!
//! The feature edges are the edges joining two feature vertices of the input (Algorithm 1's
//! classes chosen by `--keep-features`) that follow the feature (the caller's test: see
//! `simplify::follows_feature`), the boundary edges and the texture seams (#22: the
//! edges whose faces disagree on a UV or a material, [`crate::mesh::uv::seam_edges`]). A feature or boundary vertex
//! with exactly two feature edges lies on a line; one with any other count is a junction or
//! an end and, like a corner, is never removed. A line vertex may be removed only by the
//! weld whose diagonal joins its two line neighbours, so the line stays a line of the
//! coarser level: the two feature edges become one. Each feature edge carries a bound on
//! how far the input's line between its ends lies from it (Cohen et al. 1997's
//! successive-mapping bound, along the line): merging v–a and v–b into a–b gives
//! max(bound(v–a), bound(v–b)) + dist(v, a–b).

use rustc_hash::FxHashMap;

use super::rings::Rings;

/// The feature edges of the current level, each with its distance bound.
#[derive(Debug, Clone, Default)]
pub struct FeatureLines {
    /// Feature edges (smaller id first) and the bound on the input line's distance from
    /// each.
    edges: FxHashMap<[u32; 2], f64>,
    /// Vertices that lie on a line (exactly two feature edges) and may go along it.
    on_line: Vec<bool>,
    /// Vertices on a boundary of the input.
    boundary: Vec<bool>,
    /// Vertices on a texture seam of the input.
    seam_vertex: Vec<bool>,
}

fn key(a: u32, b: u32) -> [u32; 2] {
    [a.min(b), a.max(b)]
}

impl FeatureLines {
    /// The lines of a mesh whose feature vertices are `feature` (edges from `triangles`),
    /// with its boundary loops and the `seams` (edges, any order of ends) as lines too.
    /// Corners are never line vertices, and none is when `along` is false (the lines are then
    /// only reported); vertices whose removal the caller forbids are left to the caller's
    /// `kept` flags. An edge joining two feature vertices is a feature edge only where
    /// `follows(a, b)` (it runs along the feature, not across a face between two features).
    pub fn new(
        feature: &[bool],
        corner: &[bool],
        triangles: &[[u32; 3]],
        along: bool,
        seams: &[[u32; 2]],
        follows: impl Fn(u32, u32) -> bool,
    ) -> Self {
        let n = feature.len();
        let directed: rustc_hash::FxHashSet<[u32; 2]> =
            triangles.iter().flat_map(|t| (0..3).map(move |k| [t[k], t[(k + 1) % 3]])).collect();
        let mut edges = FxHashMap::default();
        let mut boundary = vec![false; n];
        for &[a, b] in &directed {
            let open = !directed.contains(&[b, a]);
            if open {
                boundary[a as usize] = true;
                boundary[b as usize] = true;
            }
            if open || (a < b && feature[a as usize] && feature[b as usize] && follows(a, b)) {
                edges.insert(key(a, b), 0.0);
            }
        }
        let mut seam_vertex = vec![false; n];
        for &[a, b] in seams {
            edges.insert(key(a, b), 0.0);
            seam_vertex[a as usize] = true;
            seam_vertex[b as usize] = true;
        }
        let mut degree = vec![0u8; n];
        for &[a, b] in edges.keys() {
            degree[a as usize] = degree[a as usize].saturating_add(1);
            degree[b as usize] = degree[b as usize].saturating_add(1);
        }
        let on_line = (0..n)
            .map(|v| along && (feature[v] || boundary[v] || seam_vertex[v]) && !corner[v] && degree[v] == 2)
            .collect();
        FeatureLines { edges, on_line, boundary, seam_vertex }
    }

    /// Whether `v` is on a boundary of the input.
    pub fn is_boundary(&self, v: u32) -> bool {
        self.boundary.get(v as usize).copied().unwrap_or(false)
    }

    /// Whether `v` is on a texture seam of the input.
    pub fn is_on_seam(&self, v: u32) -> bool {
        self.seam_vertex.get(v as usize).copied().unwrap_or(false)
    }

    /// Whether `v` lies on a line.
    pub fn is_on_line(&self, v: u32) -> bool {
        self.on_line.get(v as usize).copied().unwrap_or(false)
    }

    /// The two line neighbours of the line vertex `v` (in ring order) and the larger bound
    /// of its two feature edges; `None` if `v` is not on a line.
    pub fn neighbours(&self, v: u32, rings: &Rings) -> Option<([u32; 2], f64)> {
        if !self.is_on_line(v) {
            return None;
        }
        let mut found = [0u32; 2];
        let mut count = 0;
        let mut bound: f64 = 0.0;
        for &r in rings.ring(v) {
            if let Some(&b) = self.edges.get(&key(v, r)) {
                if count < 2 {
                    found[count] = r;
                }
                count += 1;
                bound = bound.max(b);
            }
        }
        (count == 2).then_some((found, bound))
    }

    /// Whether `v` is a line vertex that can no longer go along its line: the level's ring
    /// of `v` holds other than two of its feature edges (a line neighbour went, or a
    /// released junction beside it).
    pub fn is_stranded(&self, v: u32, rings: &Rings) -> bool {
        self.is_on_line(v) && self.neighbours(v, rings).is_none()
    }

    /// Releases `v` (#34: the target comes first): a boundary vertex keeps only its two
    /// boundary edges as feature edges and goes along its boundary; an inside vertex with
    /// exactly two feature edges goes along them; any other loses its feature edges and may
    /// be removed like a surface vertex.
    pub fn release(&mut self, v: u32, rings: &Rings) {
        let ring = rings.ring(v);
        if rings.is_boundary(v) {
            if let [_, inner @ .., _] = ring {
                for &r in inner {
                    self.edges.remove(&key(v, r));
                }
            }
            self.on_line[v as usize] = true;
            return;
        }
        let on_edges = ring.iter().filter(|&&r| self.edges.contains_key(&key(v, r))).count();
        if on_edges == 2 {
            self.on_line[v as usize] = true;
        } else {
            for &r in ring {
                self.edges.remove(&key(v, r));
            }
            self.on_line[v as usize] = false;
        }
    }

    /// The larger bound of the feature edges `v`–`a` and `v`–`b` (0 for an edge that is
    /// not a feature edge).
    pub fn bound_between(&self, v: u32, a: u32, b: u32) -> f64 {
        let bound = |w: u32| self.edges.get(&key(v, w)).copied().unwrap_or(0.0);
        bound(a).max(bound(b))
    }

    /// Lets the inside line vertex `v` off its line (the give-way ladder's last release):
    /// its feature edges go, and it may be removed like a surface vertex.
    pub fn leave(&mut self, v: u32, rings: &Rings) {
        for &r in rings.ring(v) {
            self.edges.remove(&key(v, r));
        }
        self.on_line[v as usize] = false;
    }

    /// Records the removal of the line vertex `v` along its line: its feature edges to
    /// `ends` become the edge between them, with bound `bound`.
    pub fn merge(&mut self, v: u32, ends: [u32; 2], bound: f64) {
        self.edges.remove(&key(v, ends[0]));
        self.edges.remove(&key(v, ends[1]));
        self.edges.insert(key(ends[0], ends[1]), bound);
        self.on_line[v as usize] = false;
    }
}
