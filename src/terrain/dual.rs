//! Janeczek's dual midpoint displacement over an arbitrary 3D quadrilateral (seed 000).
//! The surface starts as the quad (0, x, y, x + y) and each division doubles its
//! resolution: the diamond step puts a point at the mean of each quad's four corners
//! displaced by the mean of the two diagonals' displacements; a buffer row or column
//! outside the border continues the slope; the square step does the same for each edge
//! point from its (left, right) and (up, down) pairs; the original points are then moved to
//! the mean of their four new neighbours (two along a border, the four corners fixed) so
//! they do not stand out as peaks or pits (his Fig. 2). Each pair (P1, P2) is displaced
//! along the unit vector perpendicular to P1P2 in the plane of ẑ (the quad's normal) and
//! P1P2, by a normal sample times σ; σ starts at s·r with s = scale·(|x| + |y|)/2 and
//! r = c^−H, c = 2, and is multiplied by r each division. The result is a quad surface,
//! not necessarily a height field.

use glam::DVec3;
use rand_distr::{Distribution as _, StandardNormal};

use super::random::CounterRng;
use crate::error::{Error, Result};
use crate::mesh::Mesh;
use crate::noise::hash::{Stream, derive_seed, hash_coords};

/// Parameters of the dual method.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DualParams {
    /// First side of the quadrilateral.
    pub x: DVec3,
    /// Second side.
    pub y: DVec3,
    /// H, between 1 and 2 in Janeczek's experiments.
    pub hurst: f64,
    /// Number of divisions n (the surface has (2ⁿ + 1)² points).
    pub levels: u32,
    /// The scale factor applied to s = (|x| + |y|)/2.
    pub scale: f64,
    /// Seed.
    pub seed: u64,
    /// Use σ itself instead of a normal sample (his non-random mode).
    pub deterministic: bool,
    /// His conclusion's variant: one sample per new point, along the unit cross product of
    /// its two pairs' directions, instead of one per pair.
    pub cross_product: bool,
    /// Move the original points to the mean of their new neighbours (on by default).
    pub mean_correction: bool,
}

impl Default for DualParams {
    fn default() -> Self {
        DualParams {
            x: DVec3::X,
            y: DVec3::Y,
            hurst: 1.5,
            levels: 9,
            scale: 1.0,
            seed: 0,
            deterministic: false,
            cross_product: false,
            mean_correction: true,
        }
    }
}

/// A grid of 3D points, `m` along x by `n` along y, point (i, j) at `points[i * n + j]`.
#[derive(Debug, Clone, PartialEq)]
pub struct QuadSurface {
    /// Points along the first side.
    pub m: usize,
    /// Points along the second side.
    pub n: usize,
    /// The points.
    pub points: Vec<DVec3>,
}

impl QuadSurface {
    fn at(&self, i: usize, j: usize) -> DVec3 {
        self.points[i * self.n + j]
    }

    /// The surface as triangles (two per quad).
    pub fn to_mesh(&self) -> Mesh {
        let triangles = (0..self.m - 1)
            .flat_map(|i| {
                (0..self.n - 1).flat_map(move |j| {
                    let a = (i * self.n + j) as u32;
                    let (b, c, d) = (a + self.n as u32, a + self.n as u32 + 1, a + 1);
                    [[a, b, c], [a, c, d]]
                })
            })
            .collect();
        Mesh::new(self.points.clone(), triangles)
    }
}

/// Generates the surface; `snapshot` is called with the surface after every division
/// (level 0 is the initial quad).
///
/// # Errors
/// [`Error::InvalidInput`] for parallel or degenerate sides, non-finite numbers or more than
/// 14 divisions.
pub fn dual_midpoint_displacement(
    params: &DualParams,
    mut snapshot: impl FnMut(u32, &QuadSurface),
) -> Result<QuadSurface> {
    let normal = params.x.cross(params.y);
    let finite = params.x.is_finite() && params.y.is_finite() && params.hurst.is_finite() && params.scale.is_finite();
    if !finite || normal.length_squared() == 0.0 {
        return Err(Error::InvalidInput("dual: x and y must be finite, non-parallel vectors".into()));
    }
    if params.levels > 14 {
        return Err(Error::InvalidInput(format!("dual: {} divisions is too many (at most 14)", params.levels)));
    }
    let z = normal.normalize();
    let ratio = 2f64.powf(-params.hurst);
    let mut sigma = params.scale * (params.x.length() + params.y.length()) / 2.0 * ratio;
    let seed = derive_seed(params.seed, "dual");
    let mut p = QuadSurface { m: 2, n: 2, points: vec![DVec3::ZERO, params.y, params.x, params.x + params.y] };
    snapshot(0, &p);
    for level in 1..=params.levels {
        p = divide(&p, z, sigma, seed, level, params);
        snapshot(level, &p);
        sigma *= ratio;
    }
    Ok(p)
}

/// Displacement direction of a pair: the unit vector perpendicular to P1P2 in the plane of
/// ẑ and P1P2 (ẑ itself when the pair is parallel to ẑ... which a surface pair is not).
fn perpendicular(z: DVec3, p1: DVec3, p2: DVec3) -> DVec3 {
    let delta = (p2 - p1).normalize_or_zero();
    let v = z - delta * z.dot(delta);
    if v.length_squared() > 0.0 { v.normalize() } else { z }
}

/// One division: (m, n) points → (2m − 1, 2n − 1).
fn divide(p: &QuadSurface, z: DVec3, sigma: f64, seed: u64, level: u32, params: &DualParams) -> QuadSurface {
    let (m, n) = (p.m, p.n);
    let (qm, qn) = (2 * m - 1, 2 * n - 1);
    // Q with a buffer ring: index k of the dense array is grid index k − 1.
    let (bm, bn) = (qm + 2, qn + 2);
    let mut q = vec![DVec3::ZERO; bm * bn];
    let idx = |i: isize, j: isize| ((i + 1) as usize) * bn + (j + 1) as usize;
    let sample = |i: usize, j: usize, pair: i64| -> f64 {
        if params.deterministic {
            return sigma;
        }
        let mut stream = Stream::new(hash_coords(seed, &[i64::from(level), i as i64, j as i64, pair]));
        let g: f64 = StandardNormal.sample(&mut CounterRng(&mut stream));
        g * sigma
    };
    // New point from two pairs: mean of the four points plus the pairs' displacements.
    let displace = |i: usize, j: usize, a: (DVec3, DVec3), b: (DVec3, DVec3)| -> DVec3 {
        let mean = (a.0 + a.1 + b.0 + b.1) / 4.0;
        if params.cross_product {
            let mut dir = (a.1 - a.0).cross(b.1 - b.0).normalize_or_zero();
            if dir.dot(z) < 0.0 {
                dir = -dir;
            }
            return mean + dir * sample(i, j, 0);
        }
        let da = perpendicular(z, a.0, a.1) * sample(i, j, 0);
        let db = perpendicular(z, b.0, b.1) * sample(i, j, 1);
        mean + (da + db) / 2.0
    };
    for i in 0..m {
        for j in 0..n {
            q[idx(2 * i as isize, 2 * j as isize)] = p.at(i, j);
        }
    }
    // Diamond step: quad centres from the two diagonals (LR, UL) and (LL, UR).
    for i in 0..m - 1 {
        for j in 0..n - 1 {
            let (ul, ll, ur, lr) = (p.at(i, j), p.at(i, j + 1), p.at(i + 1, j), p.at(i + 1, j + 1));
            q[idx(2 * i as isize + 1, 2 * j as isize + 1)] = displace(2 * i + 1, 2 * j + 1, (lr, ul), (ll, ur));
        }
    }
    // Buffers continuing the slope beyond each border: mean of the border pair reflected
    // through the neighbouring centre.
    for j in 0..n - 1 {
        let (cj, qj) = (2 * j as isize + 1, j);
        let mean = (p.at(0, qj) + p.at(0, qj + 1)) / 2.0;
        q[idx(-1, cj)] = mean + (mean - q[idx(1, cj)]);
        let mean = (p.at(m - 1, qj) + p.at(m - 1, qj + 1)) / 2.0;
        q[idx(qm as isize, cj)] = mean + (mean - q[idx(qm as isize - 2, cj)]);
    }
    for i in 0..m - 1 {
        let ci = 2 * i as isize + 1;
        let mean = (p.at(i, 0) + p.at(i + 1, 0)) / 2.0;
        q[idx(ci, -1)] = mean + (mean - q[idx(ci, 1)]);
        let mean = (p.at(i, n - 1) + p.at(i + 1, n - 1)) / 2.0;
        q[idx(ci, qn as isize)] = mean + (mean - q[idx(ci, qn as isize - 2)]);
    }
    // Square step: points between two originals, from the pair of originals and the pair of
    // centres (or buffers) across.
    for i in 0..m - 1 {
        for j in 0..n {
            let (gi, gj) = (2 * i as isize + 1, 2 * j as isize);
            let (left, right) = (p.at(i, j), p.at(i + 1, j));
            let (up, down) = (q[idx(gi, gj - 1)], q[idx(gi, gj + 1)]);
            q[idx(gi, gj)] = displace(gi as usize, gj as usize, (up, down), (left, right));
        }
    }
    for i in 0..m {
        for j in 0..n - 1 {
            let (gi, gj) = (2 * i as isize, 2 * j as isize + 1);
            let (left, right) = (q[idx(gi - 1, gj)], q[idx(gi + 1, gj)]);
            let (up, down) = (p.at(i, j), p.at(i, j + 1));
            q[idx(gi, gj)] = displace(gi as usize, gj as usize, (up, down), (left, right));
        }
    }
    let mut out = QuadSurface {
        m: qm,
        n: qn,
        points: (0..qm)
            .flat_map(|i| (0..qn).map(move |j| (i, j)))
            .map(|(i, j)| q[idx(i as isize, j as isize)])
            .collect(),
    };
    if params.mean_correction {
        correct_originals(&mut out);
    }
    out
}

/// Moves the original (even, even) points to the mean of their new neighbours: four inside,
/// the two along the border on an edge; the corners stay.
fn correct_originals(s: &mut QuadSurface) {
    let (m, n) = (s.m, s.n);
    let old = s.points.clone();
    let at = |i: usize, j: usize| old[i * n + j];
    for i in (0..m).step_by(2) {
        for j in (0..n).step_by(2) {
            let (edge_i, edge_j) = (i == 0 || i == m - 1, j == 0 || j == n - 1);
            s.points[i * n + j] = match (edge_i, edge_j) {
                (true, true) => continue,
                (false, false) => (at(i - 1, j) + at(i + 1, j) + at(i, j - 1) + at(i, j + 1)) / 4.0,
                (true, false) => (at(i, j - 1) + at(i, j + 1)) / 2.0,
                (false, true) => (at(i - 1, j) + at(i + 1, j)) / 2.0,
            };
        }
    }
}
