//! The unit frame of a mesh: its bounding box's centre at the origin and its diagonal of
//! length one. Measures that are fractions of the diagonal (Hausdorff distances, errors,
//! tolerances) are taken in it, so they do not depend on the model's units and stay finite
//! for coordinates near the ends of the f64 range (a product of two 1e200 coordinates
//! overflows; their ratio to the diagonal does not).

use glam::DVec3;

use super::Mesh;
use crate::error::{Error, Result};

/// A translation and a uniform scale taking a mesh's bounding box to a box of diagonal 1
/// centred at the origin.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UnitFrame {
    /// The bounding box's centre (in the mesh's units).
    pub centre: DVec3,
    /// The bounding box's diagonal (in the mesh's units); 1 for a mesh of one point.
    pub diagonal: f64,
}

impl UnitFrame {
    /// The frame of `mesh`'s bounding box.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for a mesh without vertices, or whose bounding box's extent
    /// overflows f64 (such a model cannot be measured in any frame).
    pub fn of(mesh: &Mesh) -> Result<Self> {
        Self::of_positions(&mesh.positions)
    }

    /// The frame of the bounding box of `positions`.
    ///
    /// # Errors
    /// As [`UnitFrame::of`].
    pub fn of_positions(positions: &[DVec3]) -> Result<Self> {
        let (lo, hi) = super::bounding_box_of(positions)
            .ok_or_else(|| Error::InvalidInput("the mesh has no vertices to measure".into()))?;
        let extent = hi - lo;
        if !extent.is_finite() {
            return Err(Error::InvalidInput(format!(
                "the bounding box [{lo:?} .. {hi:?}] has an extent beyond the range of double precision"
            )));
        }
        let largest = extent.max_element();
        let diagonal = if largest > 0.0 { largest * (extent / largest).length() } else { 1.0 };
        Ok(UnitFrame { centre: lo * 0.5 + hi * 0.5, diagonal })
    }

    /// `p` in the frame.
    pub fn to_unit(&self, p: DVec3) -> DVec3 {
        (p - self.centre) / self.diagonal
    }

    /// A copy of `mesh` with its positions in the frame (attributes kept).
    pub fn apply(&self, mesh: &Mesh) -> Mesh {
        let mut out = mesh.clone();
        for p in &mut out.positions {
            *p = self.to_unit(*p);
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn huge_and_tiny_models_have_the_same_unit_frame_image() {
        let unit = crate::mesh::primitives::icosphere(1.0, 1);
        let image = UnitFrame::of(&unit).unwrap().apply(&unit);
        for scale in [1e-200, 1e-3, 1e90, 1e200] {
            let mut scaled = unit.clone();
            scaled.positions.iter_mut().for_each(|p| *p = *p * scale + DVec3::splat(3.0 * scale));
            let frame = UnitFrame::of(&scaled).unwrap();
            assert!(frame.diagonal.is_finite() && frame.diagonal > 0.0);
            for (a, b) in frame.apply(&scaled).positions.iter().zip(&image.positions) {
                assert!((*a - *b).length() < 1e-12, "scale {scale}: {a} vs {b}");
            }
        }
        let mut overflowing = unit.clone();
        overflowing.positions[0].x = -1e308;
        overflowing.positions[1].x = 1e308;
        assert!(UnitFrame::of(&overflowing).is_err());
    }
}
