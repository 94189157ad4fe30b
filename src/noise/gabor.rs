//! Gabor noise (Lagae, Lefebvre, Drettakis, Dutré 2009; thesis eq. 3.20–3.21): a sparse
//! convolution of Gabor kernels g(p) = K·exp(−π a² |p|²)·cos(2π F0 (pₓ cos ω0 + p_y sin ω0))
//! with impulses from a Poisson process. The plane (or space) is cut into cells of the
//! kernel radius; each cell's impulses — a Poisson number with mean λ·(cell size)ᵈ, uniform
//! positions, weights uniform in [−1, 1], and in isotropic mode a uniform random
//! orientation — are a pure function of (seed, cell). A point sums the impulses of its
//! 3×3 (or 3×3×3) neighbouring cells. Output is divided by the analytic standard
//! deviation σ, σ² = λ E[w²] ∫g² (Campbell's theorem), so it has unit variance.

use std::f64::consts::{PI, TAU};

use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::hash::{Stream, derive_seed, hash_coords};
use crate::error::{Error, Result};

/// The kernel is truncated where its Gaussian falls to this fraction of its peak.
const TRUNCATION: f64 = 0.05;

/// Gabor noise parameters. Defaults are the reference set: K = 1, a = 0.05,
/// F0 = 0.0625, ω0 = π/4, 64 impulses per kernel, anisotropic.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct GaborParams {
    /// Kernel magnitude K.
    pub k: f64,
    /// Gaussian bandwidth a (the kernel radius is √(−ln 0.05 / π) / a).
    pub a: f64,
    /// Frequency F0 of the cosine, in cycles per unit.
    pub f0: f64,
    /// Orientation ω0 of the cosine, radians (anisotropic mode).
    pub omega0: f64,
    /// Expected number of impulses within one kernel's disc (2D) or ball (3D).
    pub impulses_per_kernel: f64,
    /// A random orientation per impulse instead of ω0.
    pub isotropic: bool,
}

impl Default for GaborParams {
    fn default() -> Self {
        GaborParams { k: 1.0, a: 0.05, f0: 0.0625, omega0: PI / 4.0, impulses_per_kernel: 64.0, isotropic: false }
    }
}

/// A tangent frame at a surface point: the cosine runs along cos ω·`tangent` + sin ω·`bitangent`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    /// First tangent direction (unit).
    pub tangent: DVec3,
    /// Second tangent direction (unit, orthogonal to `tangent`).
    pub bitangent: DVec3,
}

/// One impulse in the plane, with what every kernel evaluation needs precomputed.
#[derive(Debug, Clone, Copy)]
struct Impulse2 {
    x: f64,
    y: f64,
    /// Weight times K.
    weight: f64,
    /// Frequency vector 2π F0 (cos ω, sin ω).
    fx: f64,
    fy: f64,
    /// cos and sin of the impulse's phase 2π F0 (pᵢ · dir) (anisotropic mode).
    cos_phase: f64,
    sin_phase: f64,
}

/// Gabor noise with fixed parameters and seed.
#[derive(Debug, Clone)]
pub struct Gabor {
    params: GaborParams,
    seed: u64,
    radius: f64,
    gauss: f64,
    mean_per_cell_2d: f64,
    mean_per_cell_3d: f64,
    inv_sigma_2d: f64,
    inv_sigma_3d: f64,
}

impl Gabor {
    /// Gabor noise with `params` and `seed`.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] when K, a or the impulse count is not positive and finite,
    /// or F0 or ω0 is not finite.
    pub fn new(params: GaborParams, seed: u64) -> Result<Self> {
        let positive = |v: f64| v.is_finite() && v > 0.0;
        if !positive(params.k) || !positive(params.a) || !positive(params.impulses_per_kernel) {
            return Err(Error::InvalidInput("gabor: K, a and impulses per kernel must be positive".into()));
        }
        if !params.f0.is_finite() || params.f0 < 0.0 || !params.omega0.is_finite() {
            return Err(Error::InvalidInput("gabor: F0 must be non-negative and ω0 finite".into()));
        }
        let a = params.a;
        let radius = (-TRUNCATION.ln() / PI).sqrt() / a;
        let lambda_2d = params.impulses_per_kernel / (PI * radius * radius);
        let lambda_3d = params.impulses_per_kernel / (4.0 / 3.0 * PI * radius.powi(3));
        let cosine_energy = 1.0 + (-2.0 * PI * params.f0 * params.f0 / (a * a)).exp();
        let k2 = params.k * params.k;
        // σ² = λ · E[w²] · ∫g², with E[w²] = 1/3 for w uniform in [−1, 1].
        let var_2d = lambda_2d / 3.0 * k2 / (4.0 * a * a) * cosine_energy;
        let var_3d = lambda_3d / 3.0 * k2 / 2.0 * (2.0 * a * a).powf(-1.5) * cosine_energy;
        Ok(Gabor {
            params,
            seed: derive_seed(seed, "gabor"),
            radius,
            gauss: PI * a * a,
            mean_per_cell_2d: lambda_2d * radius * radius,
            mean_per_cell_3d: lambda_3d * radius.powi(3),
            inv_sigma_2d: 1.0 / var_2d.sqrt(),
            inv_sigma_3d: 1.0 / var_3d.sqrt(),
        })
    }

    /// The parameters.
    pub fn params(&self) -> &GaborParams {
        &self.params
    }

    /// Kernel radius (also the cell size).
    pub fn radius(&self) -> f64 {
        self.radius
    }

    fn cell_of(&self, v: f64) -> i64 {
        (v / self.radius).floor() as i64
    }

    /// The impulses of a 2D cell, appended to `out` sorted by x.
    fn cell_impulses_2d(&self, cx: i64, cy: i64, out: &mut Vec<Impulse2>) {
        let first = out.len();
        let mut rng = Stream::new(hash_coords(self.seed, &[cx, cy]));
        let count = rng.poisson(self.mean_per_cell_2d);
        let p = &self.params;
        let two_pi_f0 = TAU * p.f0;
        for _ in 0..count {
            let x = (cx as f64 + rng.unit()) * self.radius;
            let y = (cy as f64 + rng.unit()) * self.radius;
            let weight = rng.uniform(-1.0, 1.0) * p.k;
            let omega = if p.isotropic { rng.uniform(0.0, TAU) } else { p.omega0 };
            let (fx, fy) = (two_pi_f0 * omega.cos(), two_pi_f0 * omega.sin());
            let phase = fx * x + fy * y;
            out.push(Impulse2 { x, y, weight, fx, fy, cos_phase: phase.cos(), sin_phase: phase.sin() });
        }
        // Canonical order: by x (stable, so generation order on ties). A point can then skip
        // the impulses of its side columns that lie a radius or more away horizontally.
        out[first..].sort_by(|a, b| a.x.total_cmp(&b.x));
    }

    /// (cos ψ, sin ψ) of the point's phase ψ = 2π F0 (p · dir) (anisotropic mode).
    fn point_phase(&self, x: f64, y: f64) -> (f64, f64) {
        if self.params.isotropic {
            return (0.0, 0.0);
        }
        let two_pi_f0 = TAU * self.params.f0;
        let psi = two_pi_f0 * self.params.omega0.cos() * x + two_pi_f0 * self.params.omega0.sin() * y;
        (psi.cos(), psi.sin())
    }

    /// 2D noise at (x, y), unit variance.
    pub fn sample2(&self, x: f64, y: f64) -> f64 {
        let (cx, cy) = (self.cell_of(x), self.cell_of(y));
        let mut impulses = Vec::with_capacity(64);
        let mut row = RowImpulses::default();
        for dy in -1..=1 {
            for dx in -1..=1 {
                impulses.clear();
                self.cell_impulses_2d(cx + dx, cy + dy, &mut impulses);
                row.push_cell(self, &impulses, y);
            }
        }
        let cells: [usize; 9] = std::array::from_fn(|k| k);
        self.sum_at(&row, &cells, x, y) * self.inv_sigma_2d
    }

    /// The canonical sum at (x, y) over the 3×3 cells of a row set (row-major, so cell n
    /// lies in column n mod 3 − 1 relative to the point's), cell by cell in order.
    /// Per impulse: term = w·K·e^(−g dy²)·e^(−g dx²)·cos(...), kept when dx² + dy² < R²
    /// (a select, not a branch, in the anisotropic case). Batch and scalar paths both
    /// come here, so they agree bit for bit.
    #[inline(always)]
    fn sum_at(&self, row: &RowImpulses, cells: &[usize; 9], x: f64, y: f64) -> f64 {
        let r2_max = self.radius * self.radius;
        let g = self.gauss;
        let mut total = 0.0;
        if self.params.isotropic {
            for (n, &c) in cells.iter().enumerate() {
                let mut sum = 0.0;
                for k in row.window(c, n as i32 % 3 - 1, x, self.radius) {
                    let dx = x - row.x[k];
                    let dx2 = dx * dx;
                    if dx2 + row.dy2[k] < r2_max {
                        let cosine = (row.fx[k] * dx + row.fy[k] * (y - row.y[k])).cos();
                        sum += row.weighted[k] * exp_kernel(-g * dx2) * cosine;
                    }
                }
                total += sum;
            }
        } else {
            let (cos_psi, sin_psi) = self.point_phase(x, y);
            for (n, &c) in cells.iter().enumerate() {
                let range = row.window(c, n as i32 % 3 - 1, x, self.radius);
                let columns = row.x[range.clone()]
                    .iter()
                    .zip(&row.dy2[range.clone()])
                    .zip(&row.weighted[range.clone()])
                    .zip(row.cos_phase[range.clone()].iter().zip(&row.sin_phase[range]));
                let mut sum = 0.0;
                for (((xi, dy2), weighted), (cp, sp)) in columns {
                    let dx = x - xi;
                    let dx2 = dx * dx;
                    let term = weighted * exp_kernel(-g * dx2) * (cos_psi * cp + sin_psi * sp);
                    sum += if dx2 + dy2 < r2_max { term } else { 0.0 };
                }
                total += sum;
            }
        }
        total
    }

    /// 2D noise over a row-major grid: `out[j * width + i]` = sample2(x0 + i·step, y0 + j·step).
    /// Bit-identical to [`Gabor::sample2`] at every point; bands of rows run in parallel,
    /// each generating its cells' impulses once and filtering them once per row.
    pub fn fill_grid2(&self, x0: f64, y0: f64, step: f64, width: usize, out: &mut [f64]) {
        use rayon::prelude::*;
        if width == 0 {
            return;
        }
        if !(step.is_finite() && step > 0.0 && x0.is_finite() && y0.is_finite()) {
            // The cell cache assumes increasing coordinates: evaluate point by point instead.
            super::fill_parallel(out, |k| self.sample2(x0 + (k % width) as f64 * step, y0 + (k / width) as f64 * step));
            return;
        }
        const BAND: usize = 32;
        out.par_chunks_mut(width * BAND).enumerate().for_each(|(band, rows)| {
            let first_row = band * BAND;
            let cache = CellCache::build(self, x0, y0 + first_row as f64 * step, step, width, rows.len() / width);
            let mut row_set = RowImpulses::default();
            for (r, row) in rows.chunks_mut(width).enumerate() {
                let y = y0 + (first_row + r) as f64 * step;
                let cy = self.cell_of(y);
                // The three cell rows around y, every cached column, filtered for this row.
                row_set.clear();
                for dy in -1..=1 {
                    for cx in cache.x_first..cache.x_first + cache.columns as i64 {
                        row_set.push_cell(self, cache.cell(cx, cy + dy), y);
                    }
                }
                for (i, value) in row.iter_mut().enumerate() {
                    let x = x0 + i as f64 * step;
                    let column = (self.cell_of(x) - cache.x_first) as usize;
                    let cells: [usize; 9] = std::array::from_fn(|k| (k / 3) * cache.columns + column + k % 3 - 1);
                    *value = self.sum_at(&row_set, &cells, x, y) * self.inv_sigma_2d;
                }
            }
        });
    }

    /// 3D noise at a surface point with its tangent frame, unit variance: impulses live in
    /// 3D cells, the Gaussian uses the 3D distance and the cosine runs along
    /// cos ω·tangent + sin ω·bitangent, so the stripes follow the frame (e.g. a mesh's
    /// feature directions).
    pub fn sample3(&self, p: DVec3, frame: Frame) -> f64 {
        let c = [self.cell_of(p.x), self.cell_of(p.y), self.cell_of(p.z)];
        let r2_max = self.radius * self.radius;
        let params = &self.params;
        let two_pi_f0 = TAU * params.f0;
        let fixed_dir = frame.tangent * params.omega0.cos() + frame.bitangent * params.omega0.sin();
        let mut sum = 0.0;
        for dz in -1..=1 {
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let cell = [c[0] + dx, c[1] + dy, c[2] + dz];
                    let mut rng = Stream::new(hash_coords(self.seed, &cell));
                    let count = rng.poisson(self.mean_per_cell_3d);
                    for _ in 0..count {
                        let q = DVec3::new(
                            (cell[0] as f64 + rng.unit()) * self.radius,
                            (cell[1] as f64 + rng.unit()) * self.radius,
                            (cell[2] as f64 + rng.unit()) * self.radius,
                        );
                        let weight = rng.uniform(-1.0, 1.0) * params.k;
                        let dir = if params.isotropic {
                            let omega = rng.uniform(0.0, TAU);
                            frame.tangent * omega.cos() + frame.bitangent * omega.sin()
                        } else {
                            fixed_dir
                        };
                        let d = p - q;
                        let r2 = d.length_squared();
                        if r2 < r2_max {
                            sum += weight * (-self.gauss * r2).exp() * (two_pi_f0 * d.dot(dir)).cos();
                        }
                    }
                }
            }
        }
        sum * self.inv_sigma_3d
    }
}

/// The impulses of a row's candidate cells that lie within one radius of the row
/// vertically, as parallel arrays, with the row-constant factor w·K·e^(−g dy²) precomputed.
#[derive(Default)]
struct RowImpulses {
    offsets: Vec<usize>,
    x: Vec<f64>,
    y: Vec<f64>,
    dy2: Vec<f64>,
    weighted: Vec<f64>,
    cos_phase: Vec<f64>,
    sin_phase: Vec<f64>,
    fx: Vec<f64>,
    fy: Vec<f64>,
}

impl RowImpulses {
    fn clear(&mut self) {
        self.offsets.clear();
        for v in [
            &mut self.x,
            &mut self.y,
            &mut self.dy2,
            &mut self.weighted,
            &mut self.cos_phase,
            &mut self.sin_phase,
            &mut self.fx,
            &mut self.fy,
        ] {
            v.clear();
        }
    }

    /// Appends one cell (its impulses with dy² < R² at row `y`, keeping their x order) as the next cell.
    fn push_cell(&mut self, g: &Gabor, impulses: &[Impulse2], y: f64) {
        if self.offsets.is_empty() {
            self.offsets.push(0);
        }
        let r2_max = g.radius * g.radius;
        for i in impulses {
            let dy = y - i.y;
            let dy2 = dy * dy;
            if dy2 >= r2_max {
                continue;
            }
            self.x.push(i.x);
            self.y.push(i.y);
            self.dy2.push(dy2);
            self.weighted.push(i.weight * exp_kernel(-g.gauss * dy2));
            self.cos_phase.push(i.cos_phase);
            self.sin_phase.push(i.sin_phase);
            self.fx.push(i.fx);
            self.fy.push(i.fy);
        }
        self.offsets.push(self.x.len());
    }

    #[inline(always)]
    fn range(&self, cell: usize) -> std::ops::Range<usize> {
        self.offsets[cell]..self.offsets[cell + 1]
    }

    /// The part of a cell's range that can reach `x`: impulses with x − xᵢ ≥ R (cells to
    /// the left) or x − xᵢ ≤ −R (cells to the right) have dx² ≥ R², so their term is zero
    /// and skipping them leaves the sum unchanged.
    #[inline(always)]
    fn window(&self, cell: usize, side: i32, x: f64, radius: f64) -> std::ops::Range<usize> {
        let range = self.range(cell);
        let xs = &self.x[range.clone()];
        match side {
            -1 => range.start + xs.partition_point(|&xi| x - xi >= radius)..range.end,
            1 => range.start..range.start + xs.partition_point(|&xi| x - xi > -radius),
            _ => range,
        }
    }
}

/// e^x for x in [−ln 20, 0] (the truncated kernel's range), to about 1e-7 relative:
/// e^x = (e^(x/8))⁸ with a degree-7 Taylor polynomial for e^(x/8), |x/8| ≤ 0.375.
/// Branchless and several times cheaper than libm's `exp`.
#[inline(always)]
fn exp_kernel(x: f64) -> f64 {
    let t = x * 0.125;
    let p = 1.0
        + t * (1.0
            + t * (0.5
                + t * (1.0 / 6.0 + t * (1.0 / 24.0 + t * (1.0 / 120.0 + t * (1.0 / 720.0 + t * (1.0 / 5040.0)))))));
    let p2 = p * p;
    let p4 = p2 * p2;
    p4 * p4
}

/// The impulses of every cell a band of grid rows touches (plus a one-cell border).
struct CellCache {
    x_first: i64,
    y_first: i64,
    columns: usize,
    offsets: Vec<usize>,
    impulses: Vec<Impulse2>,
}

impl CellCache {
    fn build(g: &Gabor, x0: f64, y0: f64, step: f64, width: usize, rows: usize) -> Self {
        let x_first = g.cell_of(x0) - 1;
        let x_last = g.cell_of(x0 + (width.saturating_sub(1)) as f64 * step) + 1;
        let y_first = g.cell_of(y0) - 1;
        let y_last = g.cell_of(y0 + (rows.saturating_sub(1)) as f64 * step) + 1;
        let columns = (x_last - x_first + 1) as usize;
        let mut offsets = vec![0];
        let mut impulses = Vec::new();
        for cy in y_first..=y_last {
            for cx in x_first..=x_last {
                g.cell_impulses_2d(cx, cy, &mut impulses);
                offsets.push(impulses.len());
            }
        }
        CellCache { x_first, y_first, columns, offsets, impulses }
    }

    #[inline(always)]
    fn cell(&self, cx: i64, cy: i64) -> &[Impulse2] {
        let k = (cy - self.y_first) as usize * self.columns + (cx - self.x_first) as usize;
        &self.impulses[self.offsets[k]..self.offsets[k + 1]]
    }
}
