//! The planning side's view of the hierarchy's topology: the 1-rings of the half-edge
//! store, fetched once (one batched call) and then edited in place by the same flips,
//! splits and welds that are replayed on OpenMesh in one call per operation, so Rust
//! decides on plain arrays while OpenMesh checks and keeps every operation
//! (geometry-central's split of connectivity queries from the mesh they read). A journal
//! takes a batch of planned edits back when a level's plans change.
//!
//! Rings are counter-clockwise: for a face (a, b, c), `b` is followed by `c` in `a`'s ring.
//! An interior vertex's ring is cyclic; a boundary vertex's ring is open (it runs from one
//! boundary neighbour to the other).

use rayon::prelude::*;
use smallvec::SmallVec;

use crate::error::{Error, Result};
use crate::ffi::HalfEdgeMesh;
use crate::mesh::VertexId;

/// Ring-sized storage: inline up to degree 8 (rings grow past it only on coarse levels),
/// so planning allocates nothing per cluster and a level's plans stay compact.
pub type RingVec<T> = SmallVec<[T; 8]>;

/// One vertex's ring.
type Ring = RingVec<u32>;

/// 1-rings of a half-edge store's live vertices, edited in place; a journal can take a
/// batch of edits back.
#[derive(Debug, Clone)]
pub struct Rings {
    rings: Vec<Ring>,
    boundary: Vec<bool>,
    journal: Option<Journal>,
    /// Vertices no new edge may join two of (a part's border, #40); empty: none.
    fenced: Vec<bool>,
    /// Each copy of a pinched border vertex and its other copies ([`Rings::twin`]).
    copies: rustc_hash::FxHashMap<u32, SmallVec<[u32; 2]>>,
}

/// The rings as they were before their first edit since the checkpoint.
#[derive(Debug, Clone, Default)]
struct Journal {
    saved: Vec<(u32, Ring)>,
    touched: Vec<bool>,
}

impl Rings {
    /// Fetches the rings and boundary flags of `live` vertices of a store with `slots`
    /// vertex slots (two batched calls).
    ///
    /// # Errors
    /// [`Error::Native`] if a vertex is deleted or out of range.
    pub fn fetch(store: &HalfEdgeMesh, live: &[u32], slots: usize) -> Result<Self> {
        let ids: &[VertexId] = bytemuck::cast_slice(live);
        let csr = store.one_rings(ids)?;
        let flags = store.boundary_flags(ids)?;
        let mut rings = vec![Ring::new(); slots];
        let mut boundary = vec![false; slots];
        for (i, (&v, &b)) in live.iter().zip(&flags).enumerate() {
            rings[v as usize] = Ring::from_slice(csr.row(i));
            boundary[v as usize] = b;
        }
        Ok(Rings { rings, boundary, journal: None, fenced: Vec::new(), copies: Default::default() })
    }

    /// Number of vertex slots.
    pub fn slots(&self) -> usize {
        self.rings.len()
    }

    /// The ring of `v` (empty for a vertex that is not on any face).
    pub fn ring(&self, v: u32) -> &[u32] {
        &self.rings[v as usize]
    }

    /// Number of neighbours.
    pub fn degree(&self, v: u32) -> usize {
        self.rings[v as usize].len()
    }

    /// Whether `v`, its degree changed by `gain` by operations planned before, can lose one
    /// more neighbour and keep a valid fan: at least three neighbours inside, two on a
    /// boundary (a single triangle's corner). Simplification's flips and welds and
    /// refinement's link flips all check this.
    pub fn may_lose_neighbour(&self, v: u32, gain: i64) -> bool {
        let least = if self.is_boundary(v) { 2 } else { 3 };
        self.degree(v) as i64 + gain > least
    }

    /// Whether `v` lies on a boundary (fixed by interior operations).
    pub fn is_boundary(&self, v: u32) -> bool {
        self.boundary[v as usize]
    }

    /// The faces around `vertices`, each once (from its smallest vertex, which must be
    /// among `vertices`), counter-clockwise and rotated to start at that vertex, in the
    /// order of `vertices`.
    pub fn faces(&self, vertices: &[u32]) -> Vec<[u32; 3]> {
        vertices
            .par_iter()
            .flat_map_iter(|&v| {
                let ring = self.ring(v);
                let m = ring.len();
                let pairs = if self.is_boundary(v) { m.saturating_sub(1) } else { m };
                (0..pairs).map(move |i| [v, ring[i], ring[(i + 1) % m]]).filter(|t| t[1] > t[0] && t[2] > t[0])
            })
            .collect()
    }

    /// Starts recording edits, so that [`Rings::rollback`] can take them back.
    pub fn checkpoint(&mut self) {
        let touched = vec![false; self.rings.len()];
        self.journal = Some(Journal { saved: Vec::new(), touched });
    }

    /// Takes back every edit since the checkpoint (which stays in force).
    pub fn rollback(&mut self) {
        if let Some(journal) = &mut self.journal {
            for (v, ring) in journal.saved.drain(..).rev() {
                journal.touched[v as usize] = false;
                self.rings[v as usize] = ring;
            }
        }
    }

    /// Keeps the edits since the checkpoint and stops recording.
    pub fn commit(&mut self) {
        self.journal = None;
    }

    /// Whether `a` and `b` are joined by an edge.
    pub fn has_edge(&self, a: u32, b: u32) -> bool {
        self.ring(a).contains(&b)
    }

    /// Fences `vertices`: no flip or weld may join two of them by an edge they do not
    /// have. A part built apart (#40) fences its border, whose edges in the other parts it
    /// cannot see, so that the parts' levels join into a manifold.
    pub fn fence(&mut self, vertices: &[u32]) {
        if vertices.is_empty() {
            return;
        }
        self.fenced = vec![false; self.rings.len()];
        for &v in vertices {
            self.fenced[v as usize] = true;
        }
    }

    /// Makes each group of `groups` copies of one vertex (a part's border vertex where
    /// the part pinches, #40): no flip or weld may join a vertex to one copy when it has an
    /// edge to another, since the parts joined hold the copies as one vertex.
    pub fn twin(&mut self, groups: &[Vec<u32>]) {
        for group in groups {
            for &v in group {
                self.copies.insert(v, group.iter().copied().filter(|&w| w != v).collect());
            }
        }
    }

    /// Whether a flip or weld may make the edge a–b: it does not exist (nor, for copies of
    /// one vertex, to another copy), and a and b are not both fenced.
    pub fn may_join(&self, a: u32, b: u32) -> bool {
        let both_fenced = !self.fenced.is_empty() && self.fenced[a as usize] && self.fenced[b as usize];
        !both_fenced && !self.has_edge(a, b) && (self.copies.is_empty() || !self.joins_a_copy(a, b))
    }

    /// Whether some vertex is held as copies of one ([`Rings::twin`]): a plan then reads
    /// edges beyond its ring's.
    pub fn has_copies(&self) -> bool {
        !self.copies.is_empty()
    }

    /// Whether a–b would repeat an edge between one's copy and the other.
    fn joins_a_copy(&self, a: u32, b: u32) -> bool {
        let twice = |x: u32, y: u32| self.copies.get(&y).is_some_and(|c| c.iter().any(|&y2| self.has_edge(x, y2)));
        twice(a, b) || twice(b, a)
    }

    /// The third vertex `c` of the face (a, b, c) left of a → b, if there is one.
    pub fn left_of(&self, a: u32, b: u32) -> Option<u32> {
        let ring = self.ring(a);
        let i = ring.iter().position(|&x| x == b)?;
        if i + 1 < ring.len() {
            Some(ring[i + 1])
        } else if self.is_boundary(a) {
            None
        } else {
            Some(ring[0])
        }
    }

    /// The third vertex `d` of the face (b, a, d) right of a → b, if there is one.
    pub fn right_of(&self, a: u32, b: u32) -> Option<u32> {
        let ring = self.ring(a);
        let i = ring.iter().position(|&x| x == b)?;
        if i > 0 {
            Some(ring[i - 1])
        } else if self.is_boundary(a) {
            None
        } else {
            ring.last().copied()
        }
    }

    /// Whether the face (a, b, c) exists with this orientation.
    pub fn has_face(&self, a: u32, b: u32, c: u32) -> bool {
        self.left_of(a, b) == Some(c)
    }

    fn edit(&mut self, v: u32) -> &mut Ring {
        if let Some(journal) = &mut self.journal
            && !journal.touched[v as usize]
        {
            journal.touched[v as usize] = true;
            journal.saved.push((v, self.rings[v as usize].clone()));
        }
        &mut self.rings[v as usize]
    }

    fn replace(&mut self, v: u32, old: u32, new: u32) -> Result<()> {
        let ring = self.edit(v);
        let i = ring.iter().position(|&x| x == old).ok_or_else(|| missing(v, old))?;
        ring[i] = new;
        Ok(())
    }

    fn remove(&mut self, v: u32, old: u32) -> Result<()> {
        let ring = self.edit(v);
        let i = ring.iter().position(|&x| x == old).ok_or_else(|| missing(v, old))?;
        ring.remove(i);
        Ok(())
    }

    /// Inserts `new` right after `after` in `v`'s ring.
    fn insert_after(&mut self, v: u32, after: u32, new: u32) -> Result<()> {
        let ring = self.edit(v);
        let i = ring.iter().position(|&x| x == after).ok_or_else(|| missing(v, after))?;
        ring.insert(i + 1, new);
        Ok(())
    }

    /// Flips the interior edge a–b: faces (a, b, c) and (b, a, d) become (c, a, d) and
    /// (d, b, c). Returns the new edge (c, d).
    ///
    /// # Errors
    /// [`Error::Internal`] if a–b is not an interior edge.
    pub fn flip(&mut self, a: u32, b: u32) -> Result<[u32; 2]> {
        let (c, d) = self.wings(a, b)?;
        self.remove(a, b)?;
        self.remove(b, a)?;
        self.insert_after(c, a, d)?;
        self.insert_after(d, b, c)?;
        Ok([c, d])
    }

    /// Splits the interior edge a–b with the (isolated) vertex `v`: faces (a, b, c) and
    /// (b, a, d) become (a, v, c), (v, b, c), (b, v, d), (v, a, d).
    ///
    /// # Errors
    /// [`Error::Internal`] if a–b is not an interior edge or `v` is on a face.
    pub fn split(&mut self, a: u32, b: u32, v: u32) -> Result<()> {
        if !self.ring(v).is_empty() {
            return Err(Error::Internal(format!("vertex {v} is already on a face")));
        }
        let (c, d) = self.wings(a, b)?;
        self.replace(a, b, v)?;
        self.replace(b, a, v)?;
        self.insert_after(c, a, v)?;
        self.insert_after(d, b, v)?;
        *self.edit(v) = Ring::from_slice(&[b, c, a, d]);
        Ok(())
    }

    /// Splits the boundary edge a–b with the (isolated) vertex `v`: its face (a, b, c) (or
    /// (b, a, c)) becomes (a, v, c) and (v, b, c), and `v` joins the boundary.
    ///
    /// # Errors
    /// [`Error::Internal`] if a–b is not a boundary edge or `v` is on a face.
    pub fn split_boundary(&mut self, a: u32, b: u32, v: u32) -> Result<()> {
        if !self.ring(v).is_empty() {
            return Err(Error::Internal(format!("vertex {v} is already on a face")));
        }
        let (a, b, c) = match (self.left_of(a, b), self.right_of(a, b)) {
            (Some(c), None) => (a, b, c),
            (None, Some(c)) => (b, a, c),
            _ => return Err(Error::Internal(format!("{a}–{b} is not a boundary edge"))),
        };
        self.replace(a, b, v)?;
        self.replace(b, a, v)?;
        self.insert_after(c, a, v)?;
        *self.edit(v) = Ring::from_slice(&[b, c, a]);
        self.boundary[v as usize] = true;
        Ok(())
    }

    /// Removes the degree-3 boundary vertex `v` (ring b0, r, b1) by collapsing it onto a
    /// boundary neighbour: its two faces become (b0, r, b1), and b0–b1 a boundary edge.
    ///
    /// # Errors
    /// [`Error::Internal`] if `v` is not a boundary vertex of degree 3.
    pub fn weld_boundary(&mut self, v: u32) -> Result<()> {
        let ring = self.ring(v);
        if ring.len() != 3 || !self.is_boundary(v) {
            return Err(Error::Internal(format!("vertex {v} is not a boundary vertex of degree 3")));
        }
        let [b0, r, b1] = [ring[0], ring[1], ring[2]];
        self.replace(b0, v, b1)?;
        self.replace(b1, v, b0)?;
        self.remove(r, v)?;
        self.edit(v).clear();
        Ok(())
    }

    /// Removes the degree-4 vertex `v` by collapsing it onto its neighbour `to` (a
    /// four-face-cluster weld): with ring (to, c1, c2, c3) the new faces are
    /// (to, c1, c2) and (to, c2, c3).
    ///
    /// # Errors
    /// [`Error::Internal`] if `v` does not have degree 4 with `to` in its ring.
    pub fn weld(&mut self, v: u32, to: u32) -> Result<()> {
        let ring = self.ring(v);
        let k = ring.iter().position(|&x| x == to).ok_or_else(|| missing(v, to))?;
        if ring.len() != 4 || self.is_boundary(v) {
            return Err(Error::Internal(format!("vertex {v} is not an interior degree-4 vertex")));
        }
        let [c0, c1, c2, c3] = [0, 1, 2, 3].map(|i| ring[(k + i) % 4]);
        self.replace(c0, v, c2)?;
        self.remove(c1, v)?;
        self.replace(c2, v, c0)?;
        self.remove(c3, v)?;
        self.edit(v).clear();
        Ok(())
    }

    /// The two wing vertices (left, right) of the interior edge a–b.
    fn wings(&self, a: u32, b: u32) -> Result<(u32, u32)> {
        match (self.left_of(a, b), self.right_of(a, b)) {
            (Some(c), Some(d)) => Ok((c, d)),
            _ => Err(Error::Internal(format!("{a}–{b} is not an interior edge"))),
        }
    }
}

fn missing(v: u32, x: u32) -> Error {
    Error::Internal(format!("vertex {x} is not in the ring of vertex {v}"))
}
