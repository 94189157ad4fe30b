//! What a build knows of a vertex's feature: its class by Algorithm 1 at two scales
//! (thesis §3.1.4, eq. 4.2–4.3; [`classify_at_two_scales`]), its feature strength and
//! the crease's direction. A partitioned build's parts hand their base vertices' classes
//! to the continuation (#40), which then classifies nothing itself.

use glam::DVec3;

use crate::analysis::{FaceGeometry, FeatureClass, classify_at_two_scales, voting_tensors, wide_voting_tensors};
use crate::mesh::{Adjacency, Mesh};

/// A vertex's feature class, strength and principal diffusion direction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VertexClass {
    /// Algorithm 1's class at two scales.
    pub class: FeatureClass,
    /// λ2 + λ3 of the normalised voting tensor, the smaller of the two scales': what the
    /// give-way ladder releases weakest first.
    pub strength: f64,
    /// The unit eigenvector of λ3 (along a crease), zero where the build did not keep it
    /// (a vertex that is no feature vertex for the build's options, or a corner).
    pub direction: DVec3,
}

impl Default for VertexClass {
    fn default() -> Self {
        VertexClass::FLAT
    }
}

impl VertexClass {
    /// A flat vertex of no strength: what a vertex is when features are not asked for.
    pub const FLAT: VertexClass = VertexClass { class: FeatureClass::Face, strength: 0.0, direction: DVec3::ZERO };

    /// Of the classes several parts found for one vertex on their border (each seeing
    /// only its own side of the vertex's neighbourhood), the sharpest; the first of equals.
    pub fn sharpest(classes: impl IntoIterator<Item = VertexClass>) -> Option<VertexClass> {
        classes.into_iter().fold(None, |best: Option<VertexClass>, c| match best {
            Some(b) if b.class >= c.class => Some(b),
            _ => Some(c),
        })
    }
}

/// Every vertex's class of `mesh` (Algorithm 1 at two scales, thresholds calibrated to
/// the mesh's noise), strength and diffusion direction.
pub fn vertex_classes(mesh: &Mesh) -> Vec<VertexClass> {
    let adjacency = Adjacency::of(mesh);
    let geometry = FaceGeometry::of(mesh);
    let tensors = voting_tensors(mesh, &adjacency, &geometry);
    let wide = wide_voting_tensors(mesh, &adjacency, &geometry);
    let classes = classify_at_two_scales(&mesh.positions, &adjacency, &tensors, &wide, &Default::default());
    classes
        .into_iter()
        .zip(tensors.iter().zip(&wide))
        .map(|(class, (near, far))| VertexClass {
            class,
            strength: near.strength().min(far.strength()),
            direction: near.diffusion,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn class(class: FeatureClass, strength: f64) -> VertexClass {
        VertexClass { class, strength, direction: DVec3::X * strength }
    }

    #[test]
    fn the_sharpest_class_wins_and_the_first_of_equals() {
        let found = [
            class(FeatureClass::Weak, 0.1),
            class(FeatureClass::StrongEdge, 0.2),
            class(FeatureClass::StrongEdge, 0.3),
        ];
        assert_eq!(VertexClass::sharpest(found), Some(found[1]));
        assert_eq!(VertexClass::sharpest([class(FeatureClass::Face, 0.4)]), Some(class(FeatureClass::Face, 0.4)));
        assert_eq!(VertexClass::sharpest([]), None);
    }
}
