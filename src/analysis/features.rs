//! Feature classification by normal voting tensors (thesis §4.4.1.1; Wang et al. \[78\]):
//! T(vᵢ) = Σ μⱼ nⱼ nⱼᵀ over the incident faces (eq. 4.2) with
//! μⱼ = area(tⱼ)/area_max · exp(−‖cⱼ − vᵢ‖ / ‖cⱼ − vᵢ‖_max) (eq. 4.3); eigenvalues sorted
//! λ1 ≥ λ2 ≥ λ3 and normalised by √(λ1² + λ2² + λ3²); the classes of Algorithm 1 with the
//! neighbouring-vertex-coincidence (NVC) test; the feature propagation of Algorithm 4.

use glam::{DMat3, DVec3};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::FaceGeometry;
use crate::mesh::{Adjacency, Mesh};

/// Vertex classes of Algorithm 1, numbered as in the PLY output.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FeatureClass {
    /// Flat (or noise) vertex: 0.
    Face = 0,
    /// Weak feature: 1.
    Weak = 1,
    /// Strong edge: 2.
    StrongEdge = 2,
    /// Corner: 3.
    Corner = 3,
}

impl FeatureClass {
    /// Strong edges and corners: the vertices the simplification keeps by default.
    pub fn is_sharp(self) -> bool {
        matches!(self, FeatureClass::StrongEdge | FeatureClass::Corner)
    }
}

/// Thresholds of Algorithm 1 (defaults from the thesis) and of the NVC test.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FeatureOptions {
    /// Corner when λ3 exceeds this (0.1).
    pub corner_min_l3: f64,
    /// Face when λ2 is below this (0.02).
    pub face_max_l2: f64,
    /// Strong edge when λ2 exceeds this (0.1) and λ3 is below `flat_max_l3`.
    pub strong_min_l2: f64,
    /// Edge-like when λ3 is below this (0.02).
    pub flat_max_l3: f64,
    /// NVC: largest angle between coinciding diffusion directions, degrees (15).
    pub nvc_angle_degrees: f64,
    /// NVC: coincidences needed — more than 2 in the thesis, so 3.
    pub nvc_min_coincidences: usize,
    /// NVC: the k-ring searched for coinciding vertices (2: a 1-ring holds at most two
    /// neighbours along an edge line, so "more than 2" needs the second ring).
    pub nvc_rings: usize,
    /// NVC: a neighbour counts only if it lies along the vertex's diffusion direction: the
    /// direction to it within this angle of that line, degrees (30: a triangulated line
    /// strays from straight by up to half a face's angle).
    pub nvc_along_degrees: f64,
}

impl Default for FeatureOptions {
    fn default() -> Self {
        FeatureOptions {
            corner_min_l3: 0.1,
            face_max_l2: 0.02,
            strong_min_l2: 0.1,
            flat_max_l3: 0.02,
            nvc_angle_degrees: 15.0,
            nvc_min_coincidences: 3,
            nvc_rings: 2,
            nvc_along_degrees: 30.0,
        }
    }
}

impl FeatureOptions {
    /// These thresholds raised above the mesh's own noise. For λ3 over the mesh's
    /// vertices, with m its median and q its upper quartile, `corner_min_l3` and
    /// `flat_max_l3` are multiplied by max(1, (m + 6 (q − m)) / `corner_min_l3`); where that
    /// raises them (the mesh is rough), `strong_min_l2` and `face_max_l2` are multiplied by
    /// the same rule on λ2 and `strong_min_l2`. On a CAD part and a smooth scan most
    /// vertices lie on smooth or flat surface, both are ≈ 0 there and the thesis'
    /// thresholds stand; on a rough scan they are spread over every vertex (the femur's λ3
    /// has median 0.020 and upper quartile 0.060, and a tenth of its vertices lie above the
    /// corner threshold), and only vertices six quartile spreads above the median stand
    /// out (#34).
    pub fn calibrated(&self, tensors: &[VotingTensor]) -> FeatureOptions {
        if tensors.is_empty() {
            return *self;
        }
        let factor = |k: usize, threshold: f64| {
            let mut values: Vec<f64> = tensors.iter().map(|t| t.eigenvalues[k]).collect();
            values.sort_by(f64::total_cmp);
            let (median, quartile) = (values[(values.len() - 1) / 2], values[(values.len() - 1) * 3 / 4]);
            ((median + NOISE_SPREADS * (quartile - median)) / threshold).max(1.0)
        };
        // λ2 is raised only on a mesh whose λ3 is rough: on a coarse CAD part most vertices
        // can lie on creases (anchor: 487 of 519), and λ2's quartiles are then the creases'.
        let corner = factor(2, self.corner_min_l3);
        let edge = if corner > 1.0 { factor(1, self.strong_min_l2) } else { 1.0 };
        FeatureOptions {
            corner_min_l3: self.corner_min_l3 * corner,
            flat_max_l3: self.flat_max_l3 * corner,
            strong_min_l2: self.strong_min_l2 * edge,
            face_max_l2: self.face_max_l2 * edge,
            ..*self
        }
    }
}

/// How many quartile spreads above the median λ3 a corner stands out of a mesh's noise.
const NOISE_SPREADS: f64 = 6.0;

/// Eigen-analysis of a vertex's normal voting tensor.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct VotingTensor {
    /// Normalised eigenvalues λ1 ≥ λ2 ≥ λ3.
    pub eigenvalues: [f64; 3],
    /// Principal diffusion direction: the unit eigenvector of λ3, its largest component
    /// made positive so the sign is reproducible.
    pub diffusion: DVec3,
}

impl VotingTensor {
    /// The feature strength: λ2 + λ3 of the normalised tensor, 0 on a plane, about 0.5
    /// along a right-angled crease and higher at corners (what the give-way ladder of the
    /// hierarchy releases weakest first).
    pub fn strength(&self) -> f64 {
        self.eigenvalues[1] + self.eigenvalues[2]
    }
}

/// The normal voting tensor of every vertex, eigen-analysed.
pub fn voting_tensors(mesh: &Mesh, adjacency: &Adjacency, geometry: &FaceGeometry) -> Vec<VotingTensor> {
    (0..mesh.positions.len()).into_par_iter().map(|v| tensor_over(mesh, geometry, v, adjacency.faces(v))).collect()
}

/// Faces whose normals differ by more than this (cos 40°) are not averaged by
/// [`wide_voting_tensors`]: a crease sharper than that stays one.
const SMOOTHING_COS: f64 = 0.766_044_443_118_978;

/// The normal voting tensor of every vertex (eq. 4.2–4.3 over its faces, as
/// [`voting_tensors`]) with each face's normal first averaged over the faces that share
/// a vertex with it and whose normals lie within 40° of its own (area-weighted): the tensor at the scale of the one-ring, where noise
/// of a face's size averages out (see [`classify_at_two_scales`]).
pub fn wide_voting_tensors(mesh: &Mesh, adjacency: &Adjacency, geometry: &FaceGeometry) -> Vec<VotingTensor> {
    let smoothed: Vec<DVec3> = (0..mesh.triangles.len())
        .into_par_iter()
        .map(|f| {
            let mut near: Vec<u32> =
                mesh.triangles[f].iter().flat_map(|&v| adjacency.faces(v as usize)).copied().collect();
            near.sort_unstable();
            near.dedup();
            let n = geometry.normals[f];
            near.iter()
                .map(|&g| geometry.normals[g as usize])
                .zip(near.iter().map(|&g| geometry.areas[g as usize]))
                .filter(|(m, _)| m.dot(n) >= SMOOTHING_COS)
                .map(|(m, area)| m * area)
                .sum::<DVec3>()
                .normalize_or_zero()
        })
        .collect();
    let geometry = FaceGeometry { normals: smoothed, ..geometry.clone() };
    voting_tensors(mesh, adjacency, &geometry)
}

/// Eq. 4.2–4.3 at vertex `v` over `faces`, eigen-analysed.
fn tensor_over(mesh: &Mesh, geometry: &FaceGeometry, v: usize, faces: &[u32]) -> VotingTensor {
    let p = mesh.positions[v];
    let area_and_distance = |f: u32| (geometry.areas[f as usize], (geometry.centroids[f as usize] - p).length());
    let (area_max, dist_max) = faces.iter().fold((0.0f64, 0.0f64), |(am, dm), &f| {
        let (area, dist) = area_and_distance(f);
        (am.max(area), dm.max(dist))
    });
    if area_max <= 0.0 || dist_max <= 0.0 {
        return VotingTensor::default();
    }
    let mut t = DMat3::ZERO;
    for &f in faces {
        let (area, dist) = area_and_distance(f);
        let mu = area / area_max * (-dist / dist_max).exp();
        let n = geometry.normals[f as usize];
        t += DMat3::from_cols(n * n.x, n * n.y, n * n.z) * mu;
    }
    eigen_analysis(t)
}

fn eigen_analysis(t: DMat3) -> VotingTensor {
    let (values, smallest) = symmetric_eigen3(t);
    let raw = values.map(|l| l.max(0.0));
    let norm = (raw[0] * raw[0] + raw[1] * raw[1] + raw[2] * raw[2]).sqrt();
    if norm <= 0.0 {
        return VotingTensor::default();
    }
    let largest = if smallest.x.abs() >= smallest.y.abs() && smallest.x.abs() >= smallest.z.abs() {
        smallest.x
    } else if smallest.y.abs() >= smallest.z.abs() {
        smallest.y
    } else {
        smallest.z
    };
    let diffusion = if largest < 0.0 { -smallest } else { smallest };
    VotingTensor { eigenvalues: raw.map(|l| l / norm), diffusion }
}

/// Eigenvalues (descending) of a symmetric 3×3 matrix and a unit eigenvector of the
/// smallest, in closed form: the trigonometric roots of the characteristic cubic (Smith
/// 1961) locate the spectrum; the better-separated extreme eigenvalue's eigenvector (the
/// longest cross product of two rows of A − λI) splits off, and the remaining 2×2 problem
/// is solved exactly. When λ₂ = λ₃ the eigenvector returned is one unit vector of that
/// plane, chosen deterministically.
pub fn symmetric_eigen3(a: DMat3) -> ([f64; 3], DVec3) {
    let (a00, a01, a02) = (a.x_axis.x, a.y_axis.x, a.z_axis.x);
    let (a11, a12, a22) = (a.y_axis.y, a.z_axis.y, a.z_axis.z);
    let off = a01 * a01 + a02 * a02 + a12 * a12;
    let q = (a00 + a11 + a22) / 3.0;
    let (l1, l2, l3) = if off == 0.0 {
        let mut d = [a00, a11, a22];
        d.sort_by(|x, y| y.total_cmp(x));
        (d[0], d[1], d[2])
    } else {
        let p2 = (a00 - q).powi(2) + (a11 - q).powi(2) + (a22 - q).powi(2) + 2.0 * off;
        let p = (p2 / 6.0).sqrt();
        let b = (a - DMat3::from_diagonal(DVec3::splat(q))) * (1.0 / p);
        let r = (b.determinant() / 2.0).clamp(-1.0, 1.0);
        let phi = r.acos() / 3.0;
        let l1 = q + 2.0 * p * phi.cos();
        let l3 = q + 2.0 * p * (phi + 2.0 * std::f64::consts::PI / 3.0).cos();
        (l1, 3.0 * q - l1 - l3, l3)
    };
    let scale = l1.abs().max(l3.abs()).max(f64::MIN_POSITIVE);
    if l1 - l3 <= 1e-12 * scale {
        return ([l1, l2, l3], DVec3::X); // a multiple of the identity: every direction
    }
    // The trigonometric roots are accurate only for a well-separated eigenvalue: take the
    // extreme one with the larger gap, its eigenvector, and solve the remaining 2×2 problem
    // on the orthogonal plane in closed form (Kopp 2008's hybrid idea).
    let eigenvector = |lambda: f64| {
        let m = a - DMat3::from_diagonal(DVec3::splat(lambda));
        let rows = [m.row(0), m.row(1), m.row(2)];
        [rows[0].cross(rows[1]), rows[0].cross(rows[2]), rows[1].cross(rows[2])]
            .into_iter()
            .max_by(|u, v| u.length_squared().total_cmp(&v.length_squared()))
            .expect("three candidates")
            .normalize()
    };
    let top_separated = l1 - l2 >= l2 - l3;
    let e = eigenvector(if top_separated { l1 } else { l3 });
    let u = e.any_orthonormal_vector();
    let w = e.cross(u);
    let (p, q2, r) = (u.dot(a * u), u.dot(a * w), w.dot(a * w));
    // Eigen-decomposition of [[p, q2], [q2, r]]: mean ± radius.
    let (mean, radius) = ((p + r) / 2.0, ((p - r) / 2.0).hypot(q2));
    let (hi, lo) = (mean + radius, mean - radius);
    // Eigenvector of the 2×2 for `lo`, expressed in 3D.
    let lo_vector = || {
        let (x, y) = if q2 != 0.0 {
            (q2, lo - p)
        } else if p <= r {
            (1.0, 0.0)
        } else {
            (0.0, 1.0)
        };
        (u * x + w * y).normalize()
    };
    if top_separated { ([l1, hi, lo], lo_vector()) } else { ([hi, lo, l3], e) }
}

/// Classes of Algorithm 1. Vertices that match no rule (for example λ2 > 0.1 with
/// 0.02 ≤ λ3 ≤ 0.1, or a weak candidate failing NVC) are face vertices.
///
/// NVC (Wang et al., as §4.4.1.1 states it): "given a vertex vᵢ (that is not a face
/// vertex), we try to find, along its principal diffusion direction, neighboring non-face
/// vertices which have similar principal diffusion direction" (within 15°); more than two
/// such make it a weak-edge vertex. "Along" is a neighbour in the k-ring whose direction
/// from vᵢ lies within [`FeatureOptions::nvc_along_degrees`] of the diffusion line.
pub fn classify(
    positions: &[glam::DVec3],
    adjacency: &Adjacency,
    tensors: &[VotingTensor],
    options: &FeatureOptions,
) -> Vec<FeatureClass> {
    let o = options;
    let provisional: Vec<Option<FeatureClass>> = tensors
        .iter()
        .map(|t| {
            let [_, l2, l3] = t.eigenvalues;
            if l3 > o.corner_min_l3 {
                Some(FeatureClass::Corner)
            } else if l2 < o.face_max_l2 {
                Some(FeatureClass::Face)
            } else if l2 > o.strong_min_l2 && l3 < o.flat_max_l3 {
                Some(FeatureClass::StrongEdge)
            } else if l2 <= o.strong_min_l2 && l3 < o.flat_max_l3 {
                None // weak candidate: decided by NVC
            } else {
                Some(FeatureClass::Face)
            }
        })
        .collect();
    let cos_limit = o.nvc_angle_degrees.to_radians().cos();
    let cos_along = o.nvc_along_degrees.to_radians().cos();
    (0..tensors.len())
        .into_par_iter()
        .map(|v| {
            provisional[v].unwrap_or_else(|| {
                // NVC: non-face vertices along the diffusion direction whose own
                // direction coincides.
                let d = tensors[v].diffusion;
                let along = |w: u32| {
                    let to = (positions[w as usize] - positions[v]).normalize_or_zero();
                    to.dot(d).abs() >= cos_along
                };
                let coincidences = adjacency
                    .k_ring(v, o.nvc_rings)
                    .iter()
                    .filter(|&&w| provisional[w as usize] != Some(FeatureClass::Face) && along(w))
                    .filter(|&&w| tensors[w as usize].diffusion.dot(d).abs() >= cos_limit)
                    .count();
                if coincidences >= o.nvc_min_coincidences { FeatureClass::Weak } else { FeatureClass::Face }
            })
        })
        .collect()
}

/// Algorithm 1's classes at two scales: a vertex keeps its sharp class (corner, strong
/// edge) only where its tensor over normals averaged at the one-ring's scale (`wide`,
/// [`wide_voting_tensors`]) is sharp too; otherwise it takes that tensor's class. A CAD
/// corner or crease is sharp at both scales (the same planes meet there, more than 40°
/// apart); the noise of a rough scan is not: one bent face tilts a one-ring tensor, and
/// the averaged normals smooth it out. Both use the thesis' thresholds raised above the
/// mesh's noise ([`FeatureOptions::calibrated`]; #34: on the shared femur scan the corners
/// fall from 557 to 26, see `docs/ARCHITECTURE.md`).
pub fn classify_at_two_scales(
    positions: &[glam::DVec3],
    adjacency: &Adjacency,
    tensors: &[VotingTensor],
    wide: &[VotingTensor],
    options: &FeatureOptions,
) -> Vec<FeatureClass> {
    let options = &options.calibrated(tensors);
    let near = classify(positions, adjacency, tensors, options);
    let far = classify(positions, adjacency, wide, options);
    near.into_iter().zip(far).map(|(a, b)| if a.is_sharp() && !b.is_sharp() { b } else { a }).collect()
}

/// Feature propagation of Algorithm 4: a vertex that is not a feature but has at least
/// two feature neighbours becomes one (decided on the marks before the pass, so the result
/// does not depend on vertex order); a vertex is removable only when neither it nor any
/// neighbour is a feature. Returns (features after `passes` passes, removable).
pub fn propagate_features(adjacency: &Adjacency, features: &[bool], passes: usize) -> (Vec<bool>, Vec<bool>) {
    let mut marks = features.to_vec();
    for _ in 0..passes {
        let before = marks.clone();
        let mut grew = false;
        for (v, mark) in marks.iter_mut().enumerate() {
            if !before[v] && adjacency.neighbours(v).iter().filter(|&&w| before[w as usize]).count() >= 2 {
                *mark = true;
                grew = true;
            }
        }
        // A pass that marks nothing leaves the next ones nothing to do (#36: huge pass
        // counts ran empty passes for hours).
        if !grew {
            break;
        }
    }
    let removable =
        (0..marks.len()).map(|v| !marks[v] && adjacency.neighbours(v).iter().all(|&w| !marks[w as usize])).collect();
    (marks, removable)
}
