//! Surface analysis (thesis §3.1.2, §4.4.1.1, §5.2.2): vertex normals, discrete gradient,
//! curvatures, normal-voting-tensor feature classes, diffusion directions. Every quantity
//! is gathered per vertex in a fixed order, so results do not depend on thread count.

mod curvature;
mod features;
mod gradient;
mod normals;
mod orient;
mod quadric;
mod request;

use glam::DVec3;
use serde::{Deserialize, Serialize};

pub use curvature::{Curvatures, angle_deficits, curvatures};
pub use features::{
    FeatureClass, FeatureOptions, VotingTensor, classify, classify_at_two_scales, propagate_features, symmetric_eigen3,
    voting_tensors, wide_voting_tensors,
};
pub use gradient::face_gradients;
pub use normals::{FaceGeometry, NormalWeighting, face_normals, vertex_normals};
pub use orient::orient_line_field;
pub use quadric::{Quadric, share_removed_quadric};
pub use request::AnalysisRequest;

use crate::error::Result;
use crate::mesh::{Adjacency, Mesh, Rgb};

/// Options for [`analyze`].
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct AnalysisOptions {
    /// Vertex normal weights (angle by default).
    pub normal_weighting: NormalWeighting,
    /// Feature thresholds.
    pub features: FeatureOptions,
}

/// Everything [`analyze`] computes, one entry per vertex.
#[derive(Debug, Clone)]
pub struct SurfaceAnalysis {
    /// Unit vertex normals.
    pub normals: Vec<DVec3>,
    /// Curvatures.
    pub curvatures: Curvatures,
    /// Voting tensors (normalised eigenvalues and diffusion direction).
    pub tensors: Vec<VotingTensor>,
    /// Feature classes (Algorithm 1).
    pub classes: Vec<FeatureClass>,
}

impl SurfaceAnalysis {
    /// Principal diffusion direction of each vertex.
    pub fn diffusion(&self) -> Vec<DVec3> {
        self.tensors.iter().map(|t| t.diffusion).collect()
    }

    /// normal × diffusion direction (§5.2.2): a tangent direction across the feature lines.
    pub fn normal_cross_diffusion(&self) -> Vec<DVec3> {
        self.normal_cross(self.diffusion())
    }

    /// The diffusion directions with consistent signs over the mesh ([`orient_line_field`]):
    /// the eigenvector's sign is arbitrary, and a displacement or a phase that follows it
    /// must not flip between neighbours that point the same way (#26 A2).
    pub fn oriented_diffusion(&self, adjacency: &Adjacency) -> Vec<DVec3> {
        let mut field = self.diffusion();
        orient_line_field(&mut field, adjacency);
        field
    }

    /// normal × [`SurfaceAnalysis::oriented_diffusion`].
    pub fn oriented_normal_cross_diffusion(&self, adjacency: &Adjacency) -> Vec<DVec3> {
        self.normal_cross(self.oriented_diffusion(adjacency))
    }

    /// normal × each direction of `field`, normalised.
    fn normal_cross(&self, field: Vec<DVec3>) -> Vec<DVec3> {
        self.normals.iter().zip(field).map(|(n, d)| n.cross(d).normalize_or_zero()).collect()
    }

    /// Number of vertices of each class, indexed by the class number.
    pub fn class_counts(&self) -> [usize; 4] {
        let mut counts = [0; 4];
        for c in &self.classes {
            counts[*c as usize] += 1;
        }
        counts
    }

    /// Stores the results on `mesh` as normals, scalars (`mean_curvature`,
    /// `gaussian_curvature`, `k1`, `k2`, `feature_class`, `diffusion_x/y/z`) and vertex
    /// colours showing the classes.
    pub fn attach_to(&self, mesh: &mut Mesh) {
        let c = &self.curvatures;
        mesh.normals = Some(self.normals.clone());
        for (name, values) in
            [("mean_curvature", &c.mean), ("gaussian_curvature", &c.gaussian), ("k1", &c.k1), ("k2", &c.k2)]
        {
            mesh.scalars.insert(name.to_string(), values.clone());
        }
        mesh.scalars.insert("feature_class".into(), self.classes.iter().map(|c| *c as u8 as f64).collect());
        let diffusion = self.diffusion();
        for (k, axis) in ["diffusion_x", "diffusion_y", "diffusion_z"].into_iter().enumerate() {
            mesh.scalars.insert(axis.into(), diffusion.iter().map(|d| d[k]).collect());
        }
        mesh.colors = Some(self.classes.iter().map(|c| class_color(*c)).collect());
    }
}

/// Display colour of a class: light grey faces, green weak features, blue strong edges,
/// red corners.
pub fn class_color(class: FeatureClass) -> Rgb {
    match class {
        FeatureClass::Face => [200, 200, 200],
        FeatureClass::Weak => [40, 170, 60],
        FeatureClass::StrongEdge => [30, 80, 220],
        FeatureClass::Corner => [220, 40, 40],
    }
}

/// Normals, curvatures, voting tensors and feature classes of `mesh`.
///
/// # Errors
/// [`crate::Error::InvalidInput`] for an inconsistent mesh.
pub fn analyze(mesh: &Mesh, options: &AnalysisOptions) -> Result<SurfaceAnalysis> {
    mesh.check()?;
    let adjacency = Adjacency::of(mesh);
    let faces = FaceGeometry::of(mesh);
    let normals = vertex_normals(mesh, &adjacency, &faces, options.normal_weighting);
    let curvatures = curvatures(mesh, &adjacency, &faces, &normals);
    let tensors = voting_tensors(mesh, &adjacency, &faces);
    let classes = classify(&mesh.positions, &adjacency, &tensors, &options.features);
    Ok(SurfaceAnalysis { normals, curvatures, tensors, classes })
}
