//! The validation report: element counts, boundary loops, manifoldness, connected
//! components, Euler characteristic and genus (χ = V − E + F = Σ (2 − 2gᵢ − bᵢ)).

use glam::DVec3;
use serde::Serialize;

use super::Mesh;

/// Facts about a mesh's topology and geometry. Vertex counts in the Euler characteristic
/// are of *referenced* vertices; faces repeating a vertex count as faces but give no edges.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ValidationReport {
    /// All vertices, referenced or not.
    pub vertices: usize,
    /// Triangles.
    pub faces: usize,
    /// Distinct undirected edges.
    pub edges: usize,
    /// Closed chains of boundary edges (edges with one face), followed along the edges
    /// whatever the faces' orientation.
    pub boundary_loops: usize,
    /// Edges with more than two faces.
    pub non_manifold_edges: usize,
    /// Vertices whose faces form more than one fan.
    pub non_manifold_vertices: usize,
    /// Edges whose two faces traverse them in the same direction.
    pub inconsistently_oriented_edges: usize,
    /// Connected components of the faces.
    pub components: usize,
    /// V − E + F over referenced vertices.
    pub euler: i64,
    /// Whether the faces can be oriented consistently (false for a Möbius strip or a Klein
    /// bottle; a mesh whose faces are merely flipped is orientable). Edges with more than
    /// two faces are left out of the test.
    pub orientable: bool,
    /// Total genus, when the mesh is an orientable manifold (`None` otherwise).
    pub genus: Option<i64>,
    /// Faces repeating a vertex or of (near) zero area.
    pub degenerate_faces: usize,
    /// Vertices used by no face.
    pub unreferenced_vertices: usize,
    /// Bounding box corners (zero for an empty mesh).
    pub bbox_min: [f64; 3],
    /// See `bbox_min`.
    pub bbox_max: [f64; 3],
}

impl ValidationReport {
    /// Whether the mesh is an edge- and vertex-manifold surface.
    pub fn is_manifold(&self) -> bool {
        self.non_manifold_edges == 0 && self.non_manifold_vertices == 0
    }

    /// Whether the mesh is a closed manifold (no boundary).
    pub fn is_closed_manifold(&self) -> bool {
        self.is_manifold() && self.boundary_loops == 0
    }

    /// Computes the report for `mesh` (which must pass [`Mesh::check`]).
    pub fn of(mesh: &Mesh) -> Self {
        let nv = mesh.positions.len();
        let edges = EdgeTable::build(&mesh.triangles);

        let referenced = used_vertices(nv, &mesh.triangles);
        let referenced_count = referenced.iter().filter(|&&r| r).count();

        let mut non_manifold_edges = 0;
        let mut inconsistent = 0;
        let mut boundary = Vec::new();
        for group in edges.groups() {
            match group.len() {
                1 => boundary.push(group[0]),
                2 if group[0].forward == group[1].forward => inconsistent += 1,
                2 => {}
                _ => non_manifold_edges += 1,
            }
        }
        let edge_count = edges.groups().count();
        let boundary_loops = count_boundary_loops(&boundary);
        let orientable = is_orientable(mesh.triangles.len(), &edges);
        let non_manifold_vertices = count_non_manifold_vertices(mesh, &edges);
        let components = count_face_components(mesh, &referenced);

        let euler = referenced_count as i64 - edge_count as i64 + mesh.triangles.len() as i64;
        let genus = (non_manifold_edges == 0 && non_manifold_vertices == 0 && orientable)
            .then(|| 2 * components as i64 - boundary_loops as i64 - euler)
            .filter(|twice| twice % 2 == 0 && *twice >= 0)
            .map(|twice| twice / 2);

        let (lo, hi) = mesh.bounding_box().unwrap_or((DVec3::ZERO, DVec3::ZERO));
        ValidationReport {
            vertices: nv,
            faces: mesh.triangles.len(),
            edges: edge_count,
            boundary_loops,
            non_manifold_edges,
            non_manifold_vertices,
            inconsistently_oriented_edges: inconsistent,
            components,
            orientable,
            euler,
            genus,
            degenerate_faces: count_degenerate_faces(mesh),
            unreferenced_vertices: nv - referenced_count,
            bbox_min: lo.to_array(),
            bbox_max: hi.to_array(),
        }
    }
}

/// A directed use of an undirected edge by a face.
#[derive(Debug, Clone, Copy)]
pub(crate) struct HalfEdgeUse {
    pub lo: u32,
    pub hi: u32,
    pub face: u32,
    /// Whether the face traverses the edge from `lo` to `hi`.
    pub forward: bool,
}

/// Every face's half-edges sorted by undirected edge, so that the uses of one edge are
/// adjacent. Faces repeating a vertex contribute no half-edges.
pub(crate) struct EdgeTable {
    uses: Vec<HalfEdgeUse>,
}

impl EdgeTable {
    pub fn build(triangles: &[[u32; 3]]) -> Self {
        let mut uses = Vec::with_capacity(triangles.len() * 3);
        for (f, t) in triangles.iter().enumerate() {
            if repeats_a_vertex(*t) {
                continue;
            }
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                uses.push(HalfEdgeUse { lo: a.min(b), hi: a.max(b), face: f as u32, forward: a < b });
            }
        }
        uses.sort_unstable_by_key(|u| (u.lo, u.hi, u.face));
        EdgeTable { uses }
    }

    /// The uses of each undirected edge, one slice per edge.
    pub fn groups(&self) -> impl Iterator<Item = &[HalfEdgeUse]> {
        self.uses.chunk_by(|a, b| (a.lo, a.hi) == (b.lo, b.hi))
    }
}

/// Counts the closed chains of boundary edges, walking them as undirected edges (a face
/// flipped against its neighbour does not split a loop in two): from an unused edge, each
/// step takes an unused boundary edge at the current vertex until the walk is back.
fn count_boundary_loops(boundary: &[HalfEdgeUse]) -> usize {
    let mut ends: Vec<(u32, usize)> = Vec::with_capacity(2 * boundary.len());
    for (i, e) in boundary.iter().enumerate() {
        ends.push((e.lo, i));
        ends.push((e.hi, i));
    }
    ends.sort_unstable();
    let at = |v: u32| {
        let start = ends.partition_point(|&(w, _)| w < v);
        ends[start..].iter().take_while(move |&&(w, _)| w == v).map(|&(_, i)| i)
    };
    let mut used = vec![false; boundary.len()];
    let mut loops = 0;
    for first in 0..boundary.len() {
        if used[first] {
            continue;
        }
        used[first] = true;
        let origin = boundary[first].lo;
        let mut vertex = boundary[first].hi;
        while vertex != origin {
            let Some(next) = at(vertex).find(|&i| !used[i]) else { break };
            used[next] = true;
            let e = boundary[next];
            vertex = if e.lo == vertex { e.hi } else { e.lo };
        }
        loops += 1;
    }
    loops
}

/// Whether every component's faces can be given one orientation: a face across a
/// consistently traversed edge keeps its neighbour's orientation, across an inconsistent
/// one it takes the opposite; a conflict means a Möbius-like twist. Each face has two
/// nodes in a union-find, as it is (f) and flipped (f + faces); an edge joins each of its
/// faces' nodes with the other's that agrees with it, and a face whose two nodes end in
/// one set cannot be oriented: 16 bytes per face, where lists of each face's neighbours
/// took about 64.
fn is_orientable(faces: usize, edges: &EdgeTable) -> bool {
    let mut sides = DisjointSets::new(2 * faces);
    for group in edges.groups().filter(|g| g.len() == 2) {
        let (f, g) = (group[0].face as usize, group[1].face as usize);
        let (g_agreeing, g_opposed) = match group[0].forward == group[1].forward {
            true => (g + faces, g),
            false => (g, g + faces),
        };
        sides.union(f, g_agreeing);
        sides.union(f + faces, g_opposed);
    }
    (0..faces).all(|f| sides.find(f) != sides.find(f + faces))
}

/// A vertex is non-manifold when its face corners split into several fans, i.e. the
/// corners cannot all be reached from one another across edges incident to the vertex.
pub(crate) fn count_non_manifold_vertices(mesh: &Mesh, edges: &EdgeTable) -> usize {
    non_manifold_vertices(&mesh.triangles, mesh.positions.len(), edges).iter().filter(|&&b| b).count()
}

/// Which of `vertex_count` vertices have faces in more than one fan.
fn non_manifold_vertices(triangles: &[[u32; 3]], vertex_count: usize, edges: &EdgeTable) -> Vec<bool> {
    let corner = |face: u32, v: u32| -> usize {
        let t = triangles[face as usize];
        3 * face as usize + t.iter().position(|&x| x == v).expect("vertex of face")
    };
    let mut corners = DisjointSets::new(triangles.len() * 3);
    for group in edges.groups() {
        for u in &group[1..] {
            corners.union(corner(group[0].face, group[0].lo), corner(u.face, u.lo));
            corners.union(corner(group[0].face, group[0].hi), corner(u.face, u.hi));
        }
    }
    let mut fan_root = vec![u32::MAX; vertex_count];
    let mut non_manifold = vec![false; vertex_count];
    for (f, t) in triangles.iter().enumerate() {
        if repeats_a_vertex(*t) {
            continue;
        }
        for (k, &v) in t.iter().enumerate() {
            let root = corners.find(3 * f + k) as u32;
            let slot = &mut fan_root[v as usize];
            if *slot == u32::MAX {
                *slot = root;
            } else if *slot != root {
                non_manifold[v as usize] = true;
            }
        }
    }
    non_manifold
}

/// What makes a mesh other than an oriented manifold, counted as [`ValidationReport`]
/// counts it.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct TopologyCounts {
    /// Edges with more than two faces.
    pub non_manifold_edges: usize,
    /// Vertices whose faces form more than one fan.
    pub non_manifold_vertices: usize,
    /// Edges whose two faces traverse them in the same direction.
    pub inconsistently_oriented_edges: usize,
}

impl TopologyCounts {
    /// The counts of a whole mesh's report.
    pub fn of_report(report: &ValidationReport) -> Self {
        TopologyCounts {
            non_manifold_edges: report.non_manifold_edges,
            non_manifold_vertices: report.non_manifold_vertices,
            inconsistently_oriented_edges: report.inconsistently_oriented_edges,
        }
    }

    /// The counts of a piece of a mesh (`triangles` over `vertex_count` vertices) that
    /// holds every face of the edges `edge_whole` names and of the vertices `vertex_whole`
    /// names, counting only those: pieces that between them name each edge and vertex once
    /// sum to the whole mesh's counts, with none of them holding the whole mesh (a
    /// partitioned plan: each part for its inside, the border vertices' stars for the
    /// border).
    pub fn of_piece(
        triangles: &[[u32; 3]],
        vertex_count: usize,
        vertex_whole: impl Fn(u32) -> bool,
        edge_whole: impl Fn(u32, u32) -> bool,
    ) -> Self {
        let edges = EdgeTable::build(triangles);
        let mut counts = TopologyCounts::default();
        for group in edges.groups().filter(|g| edge_whole(g[0].lo, g[0].hi)) {
            match group.len() {
                1 => {}
                2 => counts.inconsistently_oriented_edges += usize::from(group[0].forward == group[1].forward),
                _ => counts.non_manifold_edges += 1,
            }
        }
        let non_manifold = non_manifold_vertices(triangles, vertex_count, &edges);
        counts.non_manifold_vertices =
            (0..vertex_count as u32).filter(|&v| non_manifold[v as usize] && vertex_whole(v)).count();
        counts
    }

    /// The sum of two pieces' counts.
    pub fn plus(self, other: Self) -> Self {
        TopologyCounts {
            non_manifold_edges: self.non_manifold_edges + other.non_manifold_edges,
            non_manifold_vertices: self.non_manifold_vertices + other.non_manifold_vertices,
            inconsistently_oriented_edges: self.inconsistently_oriented_edges + other.inconsistently_oriented_edges,
        }
    }

    /// Whether no edge and no vertex is non-manifold.
    pub fn is_manifold(&self) -> bool {
        self.non_manifold_edges == 0 && self.non_manifold_vertices == 0
    }
}

fn count_face_components(mesh: &Mesh, referenced: &[bool]) -> usize {
    let mut sets = DisjointSets::new(referenced.len());
    for t in &mesh.triangles {
        sets.union(t[0] as usize, t[1] as usize);
        sets.union(t[1] as usize, t[2] as usize);
    }
    (0..referenced.len()).filter(|&v| referenced[v] && sets.find(v) == v).count()
}

/// Faces that repeat a vertex or whose area is below 1e-12 of their longest edge squared.
fn count_degenerate_faces(mesh: &Mesh) -> usize {
    (0..mesh.triangles.len()).filter(|&f| is_degenerate_face(mesh, f)).count()
}

/// Whether the triangle `t` names one vertex twice (it has no area and no edges).
pub fn repeats_a_vertex(t: [u32; 3]) -> bool {
    t[0] == t[1] || t[1] == t[2] || t[0] == t[2]
}

/// Whether face `f` repeats a vertex or has (relatively) zero area.
pub fn is_degenerate_face(mesh: &Mesh, f: usize) -> bool {
    is_degenerate_triangle(&mesh.positions, mesh.triangles[f])
}

/// Whether the triangle `t` on `positions` repeats a vertex or has zero area relative to
/// its longest edge (see [`is_degenerate_face`]).
pub fn is_degenerate_triangle(positions: &[glam::DVec3], t: [u32; 3]) -> bool {
    if repeats_a_vertex(t) {
        return true;
    }
    let [a, b, c] = t.map(|v| positions[v as usize]);
    // Relative to the triangle's own size, so the test does not depend on the model's
    // units: the edges are divided by their largest coordinate before any product.
    let (ab, ac, bc) = (b - a, c - a, c - b);
    let scale = ab.abs().max_element().max(ac.abs().max_element()).max(bc.abs().max_element());
    if scale == 0.0 {
        return true;
    }
    if !scale.is_finite() {
        return false;
    }
    let (ab, ac, bc) = (ab / scale, ac / scale, bc / scale);
    let longest = ab.length_squared().max(bc.length_squared()).max(ac.length_squared());
    ab.cross(ac).length() <= 1e-12 * longest
}

/// Union–find with path halving and union by size.
pub(crate) struct DisjointSets {
    parent: Vec<u32>,
    size: Vec<u32>,
}

impl DisjointSets {
    pub fn new(n: usize) -> Self {
        DisjointSets { parent: (0..n as u32).collect(), size: vec![1; n] }
    }

    pub fn find(&mut self, mut x: usize) -> usize {
        while self.parent[x] as usize != x {
            let grand = self.parent[self.parent[x] as usize];
            self.parent[x] = grand;
            x = grand as usize;
        }
        x
    }

    pub fn union(&mut self, a: usize, b: usize) {
        let (mut ra, mut rb) = (self.find(a), self.find(b));
        if ra == rb {
            return;
        }
        if self.size[ra] < self.size[rb] {
            std::mem::swap(&mut ra, &mut rb);
        }
        self.parent[rb] = ra as u32;
        self.size[ra] += self.size[rb];
    }
}

/// Which of `vertex_count` vertices the triangles use.
pub fn used_vertices(vertex_count: usize, triangles: &[[u32; 3]]) -> Vec<bool> {
    let mut used = vec![false; vertex_count];
    for t in triangles {
        for &v in t {
            used[v as usize] = true;
        }
    }
    used
}
