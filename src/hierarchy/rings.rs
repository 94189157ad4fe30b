//! The planning side's view of the hierarchy's topology: a snapshot of the half-edge
//! store's 1-rings (one batched call) plus the rings that the operations planned since the
//! snapshot have changed. Planning a level on this view, then replaying the same operations
//! on OpenMesh in one call per operation, keeps the store the single source of truth while
//! Rust decides (geometry-central's split of connectivity queries from the mesh they read).
//!
//! Rings are counter-clockwise: for a face (a, b, c), `b` is followed by `c` in `a`'s ring.
//! An interior vertex's ring is cyclic; a boundary vertex's ring is open (it runs from one
//! boundary neighbour to the other).

use rustc_hash::FxHashMap;

use crate::error::{Error, Result};
use crate::ffi::{Csr, HalfEdgeMesh};
use crate::mesh::VertexId;

/// 1-rings of a half-edge store's live vertices, editable locally.
#[derive(Debug, Clone)]
pub struct Rings {
    csr: Csr,
    /// Vertex index → row of `csr` (`u32::MAX`: not fetched, i.e. removed or isolated).
    row: Vec<u32>,
    boundary: Vec<bool>,
    edited: FxHashMap<u32, Vec<u32>>,
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
        let mut row = vec![u32::MAX; slots];
        let mut boundary = vec![false; slots];
        for (i, (&v, &b)) in live.iter().zip(&flags).enumerate() {
            row[v as usize] = i as u32;
            boundary[v as usize] = b;
        }
        Ok(Rings { csr, row, boundary, edited: FxHashMap::default() })
    }

    /// Number of vertex slots.
    pub fn slots(&self) -> usize {
        self.row.len()
    }

    /// The ring of `v` (empty for a vertex that is not on any face).
    pub fn ring(&self, v: u32) -> &[u32] {
        if let Some(r) = self.edited.get(&v) {
            return r;
        }
        match self.row[v as usize] {
            u32::MAX => &[],
            r => self.csr.row(r as usize),
        }
    }

    /// Number of neighbours.
    pub fn degree(&self, v: u32) -> usize {
        self.ring(v).len()
    }

    /// Whether `v` lies on a boundary (fixed by interior operations).
    pub fn is_boundary(&self, v: u32) -> bool {
        self.boundary[v as usize]
    }

    /// Whether `a` and `b` are joined by an edge.
    pub fn has_edge(&self, a: u32, b: u32) -> bool {
        self.ring(a).contains(&b)
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

    fn edit(&mut self, v: u32) -> &mut Vec<u32> {
        if !self.edited.contains_key(&v) {
            let copy = self.ring(v).to_vec();
            self.edited.insert(v, copy);
        }
        self.edited.get_mut(&v).expect("inserted above")
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
        self.edited.insert(v, vec![b, c, a, d]);
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
        let [c0, c1, c2, c3] = [ring[k], ring[(k + 1) % 4], ring[(k + 2) % 4], ring[(k + 3) % 4]];
        self.replace(c0, v, c2)?;
        self.remove(c1, v)?;
        self.replace(c2, v, c0)?;
        self.remove(c3, v)?;
        self.edited.insert(v, Vec::new());
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
