//! One value per live vertex of a build. A one-piece build's live vertices are all of its
//! mesh's, so its table is a plain array; a partitioned build's continuation (#40) runs on
//! a mesh that names every input vertex but whose faces use only the parts' bases (a few
//! per cent of them), so its table holds values for those only, reached through a slot per
//! vertex: 4 bytes per input vertex instead of the value's size (a quadric's 80).

use std::ops::{Index, IndexMut};

use crate::error::{Error, Result};

/// Values by vertex id: dense, or sparse over the vertices given.
#[derive(Debug, Clone, Default)]
pub struct VertexTable<T> {
    /// Each vertex's index into `values` (`NONE` for a vertex without one); empty when
    /// the table is dense.
    slots: Vec<u32>,
    values: Vec<T>,
}

/// A vertex without a value in a sparse table.
const NONE: u32 = u32::MAX;

impl<T: Copy + Default> VertexTable<T> {
    /// One value per vertex, vertex `v`'s at `values[v]`.
    pub fn dense(values: Vec<T>) -> Self {
        VertexTable { slots: Vec::new(), values }
    }

    /// Values for `given` vertices of `n` (a later entry of a vertex replaces an earlier),
    /// and the default for each of `live` not given.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for a vertex out of range, naming `what` was given.
    pub fn sparse(n: usize, given: &[(u32, T)], live: &[u32], what: &str) -> Result<Self> {
        let mut table = VertexTable { slots: vec![NONE; n], values: Vec::with_capacity(live.len()) };
        for &(v, value) in given {
            let slot = table
                .slots
                .get_mut(v as usize)
                .ok_or_else(|| Error::InvalidInput(format!("a {what} handed over for vertex {v} of {n}")))?;
            if *slot == NONE {
                *slot = table.values.len() as u32;
                table.values.push(value);
            } else {
                table.values[*slot as usize] = value;
            }
        }
        for &v in live {
            let slot = &mut table.slots[v as usize];
            if *slot == NONE {
                *slot = table.values.len() as u32;
                table.values.push(T::default());
            }
        }
        Ok(table)
    }

    fn position(&self, v: usize) -> usize {
        match self.slots.is_empty() {
            true => v,
            false => {
                let slot = self.slots[v];
                assert!(slot != NONE, "vertex {v} has no value in a sparse vertex table");
                slot as usize
            }
        }
    }
}

impl<T: Copy + Default> Index<usize> for VertexTable<T> {
    type Output = T;
    fn index(&self, v: usize) -> &T {
        &self.values[self.position(v)]
    }
}

impl<T: Copy + Default> IndexMut<usize> for VertexTable<T> {
    fn index_mut(&mut self, v: usize) -> &mut T {
        let at = self.position(v);
        &mut self.values[at]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sparse_table_holds_the_given_and_the_live_vertices_only() {
        let table = VertexTable::sparse(6, &[(4, 7.0), (1, 2.0), (4, 9.0)], &[0, 1, 4], "value").unwrap();
        assert_eq!((table[4], table[1], table[0]), (9.0, 2.0, 0.0));
        assert_eq!(table.values.len(), 3);
        assert!(VertexTable::sparse(3, &[(3, 1.0)], &[], "value").is_err());
        let dense = VertexTable::dense(vec![1.0, 2.0]);
        assert_eq!(dense[1], 2.0);
    }

    #[test]
    #[should_panic(expected = "no value")]
    fn a_sparse_table_refuses_a_vertex_it_does_not_hold() {
        let table = VertexTable::sparse(3, &[(0, 1.0)], &[], "value").unwrap();
        let _ = table[2];
    }
}
