//! The variable-resolution 4-k mesh hierarchy (thesis §4.4, §4.6; Velho \[13\], Velho &
//! Gomes \[3\], MAPS \[4\]): feature-sensitive four-face-cluster simplification down to a base
//! domain, the hierarchical parametrization of every removed vertex, and adaptive
//! refinement back to full resolution (or to any level, or only where a selection asks).
//!
//! Stages: [`build`] (simplify + parametrize) → [`Hierarchy`] → [`Refiner`] (refine, with
//! room for deformations between levels).
//!
//! Levels are numbered from the base domain (0) to the input (`steps`); a vertex removed by
//! simplification step s (0 = the first, finest step) belongs to level `steps − s`.

mod cluster;
pub mod compare;
mod compare_request;
mod conformal;
mod cost;
mod crossings;
mod give_way;
mod guard;
mod intersections;
mod lines;
mod param;
pub mod partition;
mod plan;
mod plan_cache;
mod record;
mod refine;
pub mod region;
mod hausdorff_in_pieces;
mod report;
mod request;
mod rings;
mod simplify;
mod sliver_budget;
mod store;
mod target;
mod vertex_class;
mod vertex_table;
mod wedges;

use glam::DVec3;
use serde::{Deserialize, Serialize};

pub use compare_request::CompareRequest;
pub use give_way::{TargetReport, topological_floor};
pub use intersections::added_triangle_intersections;
pub use param::ParamPoint;
pub use refine::{LevelMesh, LevelReport, Refiner, connectivity_match};
pub use report::BuildReport;
pub use request::HierarchyRequest;
pub use rings::{RingVec, Rings};
pub use simplify::{BOUNDARY_WEIGHT, build, build_with_openmesh_replay};
pub use target::VertexTarget;
pub use vertex_class::{VertexClass, vertex_classes};
pub use wedges::Wedges;

pub use crate::mesh::used_vertices;

/// The key shared by all rotations of an oriented triangle: rotated to start at its
/// smallest vertex id.
pub fn face_key(t: [u32; 3]) -> [u32; 3] {
    let i = (0..3).min_by_key(|&i| t[i]).unwrap_or(0);
    [t[i], t[(i + 1) % 3], t[(i + 2) % 3]]
}

/// Which feature classes (§4.4.1.1, Algorithm 1) simplification never removes.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub enum KeepFeatures {
    /// No vertex is a feature: every interior vertex may be removed.
    None,
    /// Corners only (thesis Fig. 5.15: features by corners alone; edges are removed like
    /// the rest of the surface).
    Corners,
    /// Corners and strong edges (the thesis' choice).
    #[default]
    Strong,
    /// Corners, strong edges and weak features.
    All,
}

/// What becomes of the feature vertices [`KeepFeatures`] chooses.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub enum FeatureVertices {
    /// Vertices on a feature line (exactly two feature edges) may be removed along it, so
    /// the line stays a line of every level; corners, junctions and ends are kept.
    #[default]
    AlongLines,
    /// No feature vertex is removed (the thesis' literal rule, §4.4.1.1).
    Keep,
}

/// Options of [`build`]. Simplification stops at the first limit reached, or when a
/// level can remove nothing more.
#[derive(Debug, Clone, PartialEq)]
pub struct SimplifyOptions {
    /// Stop at this many vertices.
    pub target_vertices: Option<usize>,
    /// Stop after this many levels (simplification steps).
    pub levels: Option<usize>,
    /// Never remove a vertex whose E(v) exceeds this distance, as a fraction of the
    /// bounding-box diagonal (E is a squared distance; it is compared squared).
    pub max_error: Option<f64>,
    /// Feature classes: the vertices that are features.
    pub keep_features: KeepFeatures,
    /// Whether feature vertices on lines are simplified along them or kept.
    pub feature_vertices: FeatureVertices,
    /// Vertices the user marked as unremovable.
    pub keep_vertices: Vec<u32>,
    /// The border of a part built apart (#40, [`partition`]): kept, and no two of them
    /// joined by a new edge, so that parts built apart join into a manifold.
    pub border_vertices: Vec<u32>,
    /// Border vertices that are copies of one vertex of the whole mesh (a part pinched
    /// there, split into one copy per fan), in groups: no flip or weld gives one of them a
    /// neighbour another already has, which the joined parts would hold twice.
    pub border_copies: Vec<Vec<u32>>,
    /// Weight of the removal error in E(v) (eq. 4.1).
    pub removal_weight: f64,
    /// Weight of the swap error in E(v) (eq. 4.1).
    pub swap_weight: f64,
    /// Algorithm 3's angle threshold, degrees.
    pub fix_threshold_degrees: f64,
    /// Keep a copy of every level's mesh (for `--levels-out`).
    pub record_levels: bool,
    /// Test each level as planned for self-intersections (CGAL) and leave out the clusters
    /// whose new faces would cut the surface.
    pub prevent_intersections: bool,
    /// Whether the vertex target comes first (#34): kept vertices released and the angle
    /// floor relaxed where a level is stuck short of it. Off, a build stuck short of its
    /// target stops there: a part of a partitioned build (#40), whose goal is a staging
    /// point that the continuation, seeing the whole mesh, goes beyond.
    pub give_way: bool,
    /// Build in this many parts along the Morton curve of the faces, in parallel, their
    /// borders fenced, then continue on their joined bases ([`partition`], #40; needs a
    /// vertex target; levels are made by refinement when recorded).
    pub chunks: Option<usize>,
    /// Faces beside the mesh that its new faces must not cut either (with
    /// `prevent_intersections`): a part rebuilt beside the other parts' bases (#40).
    pub obstacles: Obstacles,
}

/// Faces beside a mesh being simplified, which the intersection guard tests its levels'
/// new faces against as it tests the mesh's own (#40: the other parts' bases, which a
/// part built apart cannot see). A corner below the mesh's vertex count is that vertex
/// (a vertex both share, such as a part's border vertex); corner `n + i` is `points[i]`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Obstacles {
    /// The corners that are not vertices of the mesh.
    pub points: Vec<DVec3>,
    /// The faces.
    pub faces: Vec<[u32; 3]>,
}

impl Default for SimplifyOptions {
    fn default() -> Self {
        SimplifyOptions {
            target_vertices: None,
            levels: None,
            max_error: None,
            keep_features: KeepFeatures::Strong,
            feature_vertices: FeatureVertices::AlongLines,
            keep_vertices: Vec::new(),
            border_vertices: Vec::new(),
            border_copies: Vec::new(),
            removal_weight: 0.75,
            swap_weight: 0.25,
            fix_threshold_degrees: 90.0,
            record_levels: false,
            prevent_intersections: true,
            give_way: true,
            chunks: None,
            obstacles: Obstacles::default(),
        }
    }
}

impl SimplifyOptions {
    /// Refuses options no build can use: a negative or non-finite `max_error` or weight, a
    /// threshold outside 0–180°. (The command line names the flags first; this is the
    /// check for every other caller.)
    ///
    /// # Errors
    /// [`crate::Error::InvalidInput`] naming the field.
    pub fn check(&self) -> crate::Result<()> {
        let bad = |name: &str, value: f64, rule: &str| {
            Err(crate::Error::InvalidInput(format!("simplify option {name} = {value}: {rule}")))
        };
        if let Some(e) = self.max_error.filter(|e| !(*e >= 0.0 && e.is_finite())) {
            return bad("max_error", e, "must be a non-negative fraction of the diagonal");
        }
        for (name, w) in [("removal_weight", self.removal_weight), ("swap_weight", self.swap_weight)] {
            if !(w >= 0.0 && w.is_finite()) {
                return bad(name, w, "must be non-negative");
            }
        }
        let t = self.fix_threshold_degrees;
        if !(t > 0.0 && t <= 180.0) {
            return bad("fix_threshold_degrees", t, "must be above 0 and at most 180");
        }
        if self.chunks == Some(0) {
            return Err(crate::Error::InvalidInput("simplify option chunks = 0: must be at least 1".into()));
        }
        if self.obstacles.points.iter().any(|p| !p.is_finite()) {
            return Err(crate::Error::InvalidInput("an obstacle point is not finite".into()));
        }
        Ok(())
    }
}

/// One removed vertex, in removal order.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Removal {
    /// The vertex (index in the input mesh).
    pub vertex: u32,
    /// The simplification step that removed it (0 = first).
    pub step: u32,
    /// Its degree on the level it was removed from (restored by refinement, Algorithm 3).
    pub degree: u32,
    /// Whether it was removed along a boundary (its diagonal is a boundary edge of the
    /// coarser level, which refinement splits).
    pub boundary: bool,
    /// Where it lies on the next coarser level: the face the weld left and barycentric
    /// coordinates (refinement re-inserts it there).
    pub local: ParamPoint,
    /// The edge its weld created, which refinement splits.
    pub diagonal: [u32; 2],
    /// `Hierarchy::restore[restore[0]..restore[1]]`: the link edges refinement flips, in
    /// order, to restore the degree (Algorithm 3), each as (its first vertex in the ring,
    /// the ring vertex across it).
    pub restore: [u32; 2],
}

/// A vertex's place in the base domain.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BasePoint {
    /// Face of the base domain (input vertex ids) and barycentric coordinates.
    pub point: ParamPoint,
    /// The level at which the vertex appears (0: a base vertex).
    pub level: u32,
}

/// Each input vertex's base-domain point ([`Hierarchy::base_points`]).
pub struct BasePoints<'a> {
    params: &'a [Option<ParamPoint>],
    /// Each parametrized removed vertex's level; [`NO_LEVEL`] for the others.
    level: Vec<u32>,
    /// Each base vertex's first base face and its corner there.
    corners: std::collections::HashMap<u32, ([u32; 3], usize)>,
}

/// No level: a vertex not removed with a parameter point.
const NO_LEVEL: u32 = u32::MAX;

impl BasePoints<'_> {
    /// Vertex `v`'s point: a removed vertex's parameter point, else a base vertex's corner
    /// of its first base face, else `None` (a vertex on no face).
    pub fn get(&self, v: usize) -> Option<BasePoint> {
        if self.level[v] != NO_LEVEL {
            return self.params[v].map(|point| BasePoint { point, level: self.level[v] });
        }
        self.corners.get(&(v as u32)).map(|&(face, i)| {
            let mut bary = [0.0; 3];
            bary[i] = 1.0;
            BasePoint { point: ParamPoint { face, bary }, level: 0 }
        })
    }
}

/// A vertex's place in the base domain by face index (see
/// [`Hierarchy::indexed_parametrization`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IndexedBasePoint {
    /// Index in [`Hierarchy::base_triangles`].
    pub face: usize,
    /// Barycentric coordinates in that triangle's corner order.
    pub barycentric: [f64; 3],
    /// The level at which the vertex appears (0: a base vertex).
    pub level: u32,
}

/// A built hierarchy: the input, the base domain, the removals and the parametrization.
#[derive(Debug, Clone)]
pub struct Hierarchy {
    /// Input positions (simplification never moves a vertex).
    pub positions: Vec<DVec3>,
    /// Input triangles.
    pub input_triangles: Vec<[u32; 3]>,
    /// The base domain's triangles, in input vertex ids.
    pub base_triangles: Vec<[u32; 3]>,
    /// Every removed vertex, in removal order.
    pub removals: Vec<Removal>,
    /// The link edges each removal's refinement flips (see [`Removal::restore`]).
    pub restore: Vec<[u32; 2]>,
    /// `removals[step_starts[s]..step_starts[s + 1]]` were removed by step s.
    pub step_starts: Vec<usize>,
    /// Final base-domain point of each removed vertex (`None` for base vertices).
    pub params: Vec<Option<ParamPoint>>,
    /// Vertices that could not be removed (features, user marks).
    pub kept: Vec<bool>,
    /// Number of feature vertices in the base domain.
    pub feature_vertices: usize,
    /// Every level's mesh, finest (the input) first, when recorded.
    pub levels: Vec<LevelMesh>,
    /// Algorithm 3's angle threshold, radians (used where a recorded face is gone).
    pub fix_threshold: f64,
    /// Build time.
    pub seconds: f64,
    /// Build time by stage.
    pub stages: BuildStages,
    /// The input's UVs and materials, for carrying them to every level (`None` when it has
    /// neither).
    pub wedges: Option<Wedges>,
    /// Whether the vertex target was reached, and what gave way to reach it.
    pub target: TargetReport,
    /// The feature class of each base vertex, by vertex id, as the build found it: what a
    /// partitioned build's parts hand to its continuation (#40).
    pub classes: Vec<(u32, VertexClass)>,
}

/// Seconds [`build`] spent in each stage (summed over levels): a one-line report of where
/// the time goes.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct BuildStages {
    /// Validation, feature classification, quadrics, loading the half-edge store and its
    /// rings.
    pub prepare: f64,
    /// Compacting the recorded levels, and, when the build replays its plans on OpenMesh
    /// ([`build_with_openmesh_replay`]), exporting the store's base domain and checking it
    /// against the planning rings.
    pub export: f64,
    /// Estimating E(v) for every candidate and sorting.
    pub ranking: f64,
    /// Greedy cluster selection and planning.
    pub planning: f64,
    /// The intersection guard.
    pub guard: f64,
    /// Replaying flips and welds on the OpenMesh store (on the recorder thread, alongside
    /// the next level's planning); 0 unless the build checks itself
    /// ([`build_with_openmesh_replay`], debug builds).
    pub store: f64,
    /// Updating the parametrization (MAPS re-mapping of the removed vertices).
    pub parametrization: f64,
    /// Writing the removal records (recorder thread).
    pub records: f64,
    /// Planning waiting for the recorder to take a level.
    pub handoff: f64,
}

impl BuildStages {
    /// The planning thread's stages by name, in the order the build runs them.
    pub fn planning_thread(&self) -> [(&'static str, f64); 6] {
        [
            ("prepare", self.prepare),
            ("ranking", self.ranking),
            ("planning", self.planning),
            ("guard", self.guard),
            ("parametrization", self.parametrization),
            ("handoff", self.handoff),
        ]
    }
}

impl std::fmt::Display for BuildStages {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        for (i, (name, seconds)) in self.planning_thread().into_iter().enumerate() {
            write!(f, "{}{name} {seconds:.2} s", if i > 0 { ", " } else { "" })?;
        }
        write!(
            f,
            "; recorder thread: store {:.2} s, records {:.2} s, export {:.2} s",
            self.store, self.records, self.export
        )
    }
}

impl Hierarchy {
    /// Number of simplification steps (the input is level `steps()`, the base level 0).
    pub fn steps(&self) -> usize {
        self.step_starts.len() - 1
    }

    /// The link edges (first vertex, vertex across) refinement flips for `r`, in order.
    pub fn restore_of(&self, r: &Removal) -> &[[u32; 2]] {
        &self.restore[r.restore[0] as usize..r.restore[1] as usize]
    }

    /// The removals of step `s`.
    pub fn step(&self, s: usize) -> &[Removal] {
        &self.removals[self.step_starts[s]..self.step_starts[s + 1]]
    }

    /// Number of vertices of the base domain.
    pub fn base_vertex_count(&self) -> usize {
        used_vertices(self.positions.len(), &self.base_triangles).iter().filter(|&&u| u).count()
    }

    /// The base domain as a compact mesh, with each vertex's input id.
    pub fn base_mesh(&self) -> LevelMesh {
        LevelMesh::compact(&self.positions, &self.base_triangles)
    }

    /// `level` (a level's or a refinement's mesh of input vertices) with the input's UVs
    /// and materials on its faces (see [`Hierarchy::attach_attributes`]).
    ///
    /// # Errors
    /// As [`Hierarchy::attach_attributes`].
    pub fn with_attributes(&self, mut level: LevelMesh) -> crate::Result<LevelMesh> {
        self.attach_attributes(&mut level, &[])?;
        Ok(level)
    }

    /// Puts the input's UVs and materials on the faces of `level`, a level's or a
    /// refinement's mesh whose vertices are input vertices and those made by `splits`
    /// (see [`Wedges::level`]); nothing changes when the input has neither.
    ///
    /// # Errors
    /// [`crate::Error::Internal`] when a face lies in no wedge of a seam vertex; `level`
    /// is then left as it was.
    pub fn attach_attributes(&self, level: &mut LevelMesh, splits: &[[u32; 2]]) -> crate::Result<()> {
        if let Some(wedges) = &self.wedges {
            (level.mesh.uvs, level.mesh.materials) = wedges.level(&level.triangles_in_ids(), splits)?;
        }
        Ok(())
    }

    /// Every input vertex's base-domain point and level (base vertices sit on a corner of
    /// one of their faces); `None` for vertices on no face.
    pub fn base_parametrization(&self) -> Vec<Option<BasePoint>> {
        let points = self.base_points();
        (0..self.positions.len()).map(|v| points.get(v)).collect()
    }

    /// [`Hierarchy::base_parametrization`] one vertex at a time, from 4 bytes a vertex
    /// instead of 48 (#40: a merge's `--param-out` is written vertex by vertex).
    pub fn base_points(&self) -> BasePoints<'_> {
        let steps = self.steps() as u32;
        let mut level = vec![NO_LEVEL; self.positions.len()];
        for r in &self.removals {
            if self.params[r.vertex as usize].is_some() {
                level[r.vertex as usize] = steps - r.step;
            }
        }
        let mut corners = std::collections::HashMap::new();
        for t in &self.base_triangles {
            for (i, &v) in t.iter().enumerate() {
                corners.entry(v).or_insert((*t, i));
            }
        }
        BasePoints { params: &self.params, level, corners }
    }

    /// The refinement level at which each vertex first appears (0: a base vertex; the
    /// input's level, [`Hierarchy::steps`], for a vertex on no face): what a level's
    /// operator reads as each vertex's age ([`crate::detail::LevelView::with_appearance`]).
    pub fn appearance_levels(&self) -> Vec<u32> {
        let steps = self.steps() as u32;
        self.base_parametrization().iter().map(|p| p.map_or(steps, |p| p.level)).collect()
    }

    /// [`Hierarchy::base_parametrization`] with each face as its index in `base_triangles`
    /// (the order of [`Hierarchy::base_mesh`]'s triangles) and the barycentric coordinates
    /// in that triangle's corner order.
    ///
    /// # Errors
    /// [`crate::Error::Internal`] if a vertex's face is not a base face (a bug).
    pub fn indexed_parametrization(&self) -> crate::Result<Vec<Option<IndexedBasePoint>>> {
        let index: std::collections::HashMap<[u32; 3], usize> =
            self.base_triangles.iter().enumerate().map(|(k, &t)| (face_key(t), k)).collect();
        let points = self.base_parametrization();
        points
            .iter()
            .enumerate()
            .map(|(v, point)| {
                let Some(BasePoint { point, level }) = point else { return Ok(None) };
                let face = *index.get(&face_key(point.face)).ok_or_else(|| {
                    crate::Error::Internal(format!("vertex {v}'s base face {:?} is not a base face", point.face))
                })?;
                let corners = self.base_triangles[face];
                let mut bary = [0.0; 3];
                for (corner, id) in corners.iter().enumerate() {
                    let k = point.face.iter().position(|f| f == id).expect("the same face, rotated");
                    bary[corner] = point.bary[k];
                }
                Ok(Some(IndexedBasePoint { face, barycentric: bary, level: *level }))
            })
            .collect()
    }
}
