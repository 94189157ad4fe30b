//! Gabor noise (Lagae, Lefebvre, Drettakis, Dutré 2009; thesis eq. 3.20–3.21): a sparse
//! convolution of Gabor kernels g(p) = K·exp(−π a² |p|²)·cos(2π F0 (pₓ cos ω0 + p_y sin ω0))
//! with impulses from a Poisson process. The plane (or space) is cut into cells of the
//! kernel radius; each cell's impulses — a Poisson number with mean λ·(cell size)ᵈ, uniform
//! positions, weights uniform in [−1, 1], and in isotropic mode a uniform random
//! orientation — are a pure function of (seed, cell). A point sums the impulses of its
//! 3×3 (or 3×3×3) neighbouring cells. Output is divided by the analytic standard
//! deviation σ₁ of the noise with K = 1, σ₁² = λ E\[w²\] ∫(g/K)² (Campbell's theorem), so
//! its standard deviation is K: K is the kernel's magnitude (eq. 3.20) and scales the
//! noise linearly, while a, F0, ω0 and the impulse density shape it without changing its
//! contrast.

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

/// The most impulses per kernel Gabor and phasor noise take: each sample sums about that
/// many kernels, so 10⁴ (150 times the thesis' 64) already costs minutes for a large image
/// (#36: larger counts were capped without a word where the Poisson draw underflowed).
pub const MAX_IMPULSES_PER_KERNEL: f64 = 10_000.0;

impl Gabor {
    /// Gabor noise with `params` and `seed`.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] when K, a or the impulse count is not positive and finite,
    /// the impulse count is above [`MAX_IMPULSES_PER_KERNEL`], or F0 or ω0 is not finite.
    pub fn new(params: GaborParams, seed: u64) -> Result<Self> {
        let positive = |v: f64| v.is_finite() && v > 0.0;
        if !positive(params.k) || !positive(params.a) || !positive(params.impulses_per_kernel) {
            return Err(Error::InvalidInput("gabor: K, a and impulses per kernel must be positive".into()));
        }
        if params.impulses_per_kernel > MAX_IMPULSES_PER_KERNEL {
            return Err(Error::InvalidInput(format!(
                "gabor: {} impulses per kernel: at most {MAX_IMPULSES_PER_KERNEL} (each sample sums about that many)",
                params.impulses_per_kernel
            )));
        }
        if !params.f0.is_finite() || params.f0 < 0.0 || !params.omega0.is_finite() {
            return Err(Error::InvalidInput("gabor: F0 must be non-negative and ω0 finite".into()));
        }
        let a = params.a;
        let radius = (-TRUNCATION.ln() / PI).sqrt() / a;
        let lambda_2d = params.impulses_per_kernel / (PI * radius * radius);
        let lambda_3d = params.impulses_per_kernel / (4.0 / 3.0 * PI * radius.powi(3));
        let cosine_energy = 1.0 + (-2.0 * PI * params.f0 * params.f0 / (a * a)).exp();
        // σ₁² = λ · E[w²] · ∫(g/K)², with E[w²] = 1/3 for w uniform in [−1, 1]: K stays
        // in the output.
        let var_2d = lambda_2d / 3.0 / (4.0 * a * a) * cosine_energy;
        let var_3d = lambda_3d / 3.0 / 2.0 * (2.0 * a * a).powf(-1.5) * cosine_energy;
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

    /// The cell index along one axis, within ±2⁶⁰ so that the neighbouring cells' indices
    /// cannot overflow (far beyond 2⁵³ cells a coordinate no longer resolves a cell anyway;
    /// #42: 1e300 from Python overflowed the neighbour's index). NaN is cell 0.
    fn cell_of(&self, v: f64) -> i64 {
        const FAR: f64 = (1u64 << 60) as f64;
        (v / self.radius).floor().clamp(-FAR, FAR) as i64
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

    /// 2D noise at (x, y), standard deviation K.
    pub fn sample2(&self, x: f64, y: f64) -> f64 {
        let (cx, cy) = (self.cell_of(x), self.cell_of(y));
        let mut impulses = Vec::with_capacity(64);
        let mut rows = RowImpulses::default();
        for dy in -1..=1 {
            for dx in -1..=1 {
                impulses.clear();
                self.cell_impulses_2d(cx + dx, cy + dy, &mut impulses);
                rows.push_cell(self, &impulses, y);
            }
            rows.end_row();
        }
        let windows = std::array::from_fn(|r| rows.window(r, x, self.radius));
        self.sum_at(&rows, &windows, x, y) * self.inv_sigma_2d
    }

    /// The canonical sum at (x, y): over the three cell rows around y in order, the impulses
    /// of each row whose |x − xᵢ| < R (a window of the row's x-sorted impulses), four lanes
    /// per window (see [`LANES`]). Per impulse: term = w·K·e^(−g dy²)·e^(−g dx²)·cos(...),
    /// kept when dx² + dy² < R² (a select, not a branch). Batch and scalar paths both come
    /// here with the same windows, so they agree bit for bit.
    #[inline(always)]
    fn sum_at(&self, rows: &RowImpulses, windows: &[std::ops::Range<usize>; 3], x: f64, y: f64) -> f64 {
        let r2_max = self.radius * self.radius;
        let g = self.gauss;
        let mut total = 0.0;
        if self.params.isotropic {
            for window in windows {
                let mut sum = 0.0;
                for k in window.clone() {
                    let dx = x - rows.x[k];
                    let dx2 = dx * dx;
                    if dx2 + rows.dy2[k] < r2_max {
                        let cosine = (rows.fx[k] * dx + rows.fy[k] * (y - rows.y[k])).cos();
                        sum += rows.weighted[k] * exp_kernel(-g * dx2) * cosine;
                    }
                }
                total += sum;
            }
        } else {
            let psi = self.point_phase(x, y);
            for window in windows {
                total += anisotropic_window_sum(rows, window.clone(), x, g, r2_max, psi);
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
            #[cfg(target_arch = "x86_64")]
            if std::arch::is_x86_feature_detected!("avx2") {
                // SAFETY: the CPU supports AVX2, checked just above.
                #[allow(unsafe_code)]
                unsafe {
                    self.fill_band_avx2(x0, y0, step, width, first_row, rows)
                };
                return;
            }
            self.fill_band(x0, y0, step, width, first_row, rows);
        });
    }

    /// [`Gabor::fill_band`] compiled for AVX2: the same operations in the same order (Rust
    /// never fuses a multiply and an add on its own), so the same bits, four lanes at a time.
    ///
    /// # Safety
    /// The CPU must support AVX2 (an `unsafe fn` because safe `#[target_feature]` functions
    /// need Rust 1.86 and the crate supports 1.85).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    #[allow(unsafe_code)]
    unsafe fn fill_band_avx2(&self, x0: f64, y0: f64, step: f64, width: usize, first_row: usize, out: &mut [f64]) {
        self.fill_band(x0, y0, step, width, first_row, out);
    }

    /// Grid rows `first_row..` (`out` holds whole rows of `width`): the band's cells are
    /// generated once; per row, the three cell rows around it are filtered by dy, and the
    /// windows slide along x as the samples do.
    #[inline(always)]
    fn fill_band(&self, x0: f64, y0: f64, step: f64, width: usize, first_row: usize, out: &mut [f64]) {
        let cache = CellCache::build(self, x0, y0 + first_row as f64 * step, step, width, out.len() / width);
        let mut rows = RowImpulses::default();
        for (r, row) in out.chunks_mut(width).enumerate() {
            let y = y0 + (first_row + r) as f64 * step;
            let cy = self.cell_of(y);
            rows.clear();
            for dy in -1..=1 {
                for cx in cache.x_first..cache.x_first + cache.columns as i64 {
                    rows.push_cell(self, cache.cell(cx, cy + dy), y);
                }
                rows.end_row();
            }
            let mut windows: [std::ops::Range<usize>; 3] =
                std::array::from_fn(|r| rows.row(r).start..rows.row(r).start);
            for (i, value) in row.iter_mut().enumerate() {
                let x = x0 + i as f64 * step;
                for (r, window) in windows.iter_mut().enumerate() {
                    rows.slide(r, window, x, self.radius);
                }
                *value = self.sum_at(&rows, &windows, x, y) * self.inv_sigma_2d;
            }
        }
    }

    /// The complex 2D sum at (x, y) (Tricard et al. 2019, eq. 3): each impulse's kernel with
    /// the cosine replaced by e^(i 2π F0 d·(p − pᵢ)), its envelope [`phase_envelope`]. Its
    /// argument is phasor noise's phase.
    pub(super) fn complex2(&self, x: f64, y: f64) -> (f64, f64) {
        let (cx, cy) = (self.cell_of(x), self.cell_of(y));
        let r2_max = self.radius * self.radius;
        let mut impulses = Vec::with_capacity(64);
        let (mut re, mut im) = (0.0, 0.0);
        for dy in -1..=1 {
            for dx in -1..=1 {
                impulses.clear();
                self.cell_impulses_2d(cx + dx, cy + dy, &mut impulses);
                for i in &impulses {
                    let (ddx, ddy) = (x - i.x, y - i.y);
                    let r2 = ddx * ddx + ddy * ddy;
                    if r2 < r2_max {
                        let envelope = i.weight * phase_envelope(self.gauss, r2);
                        let (sin, cos) = (i.fx * ddx + i.fy * ddy).sin_cos();
                        re += envelope * cos;
                        im += envelope * sin;
                    }
                }
            }
        }
        (re, im)
    }

    /// The complex sum at a surface point (as [`Gabor::complex2`], over [`Gabor::sample3`]'s impulses).
    pub(super) fn complex3(&self, p: DVec3, frame: Frame) -> (f64, f64) {
        let two_pi_f0 = TAU * self.params.f0;
        let (mut re, mut im) = (0.0, 0.0);
        self.for_each_impulse3(p, frame, |weight, r2, d, dir| {
            let envelope = weight * phase_envelope(self.gauss, r2);
            let (sin, cos) = (two_pi_f0 * d.dot(dir)).sin_cos();
            re += envelope * cos;
            im += envelope * sin;
        });
        (re, im)
    }

    /// Calls `f(weight·K, r², p − q, direction)` for every impulse q of the 3×3×3 cells
    /// around `p` within a kernel radius, in the canonical order. The direction runs along
    /// cos ω·tangent + sin ω·bitangent, or, isotropic, is the impulse's random 3D direction
    /// projected on the tangent plane (Lagae et al. 2009 §5: it needs no frame, only the
    /// normal tangent × bitangent).
    fn for_each_impulse3(&self, p: DVec3, frame: Frame, mut f: impl FnMut(f64, f64, DVec3, DVec3)) {
        let c = [self.cell_of(p.x), self.cell_of(p.y), self.cell_of(p.z)];
        let r2_max = self.radius * self.radius;
        let params = &self.params;
        let fixed_dir = frame.tangent * params.omega0.cos() + frame.bitangent * params.omega0.sin();
        let normal = frame.tangent.cross(frame.bitangent);
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
                            let z = rng.uniform(-1.0, 1.0);
                            let phi = rng.uniform(0.0, TAU);
                            let rho = (1.0 - z * z).max(0.0).sqrt();
                            let d = DVec3::new(rho * phi.cos(), rho * phi.sin(), z);
                            d - normal * normal.dot(d)
                        } else {
                            fixed_dir
                        };
                        let d = p - q;
                        let r2 = d.length_squared();
                        if r2 < r2_max {
                            f(weight, r2, d, dir);
                        }
                    }
                }
            }
        }
    }

    /// 3D noise at a surface point with its tangent frame, standard deviation K (2D
    /// isotropic: about K): impulses live in 3D cells, the Gaussian uses the 3D distance
    /// and the cosine runs along cos ω·tangent + sin ω·bitangent, so the stripes follow the
    /// frame (e.g. a mesh's feature directions). Isotropic noise is Lagae et al.'s
    /// setup-free surface noise (2009, §5): each impulse's frequency is a random 3D
    /// direction projected on the tangent plane at the point, so it depends on the normal
    /// (tangent × bitangent) only and turning the frame about it changes nothing.
    pub fn sample3(&self, p: DVec3, frame: Frame) -> f64 {
        let two_pi_f0 = TAU * self.params.f0;
        let mut sum = 0.0;
        self.for_each_impulse3(p, frame, |weight, r2, d, dir| {
            sum += weight * (-self.gauss * r2).exp() * (two_pi_f0 * d.dot(dir)).cos();
        });
        sum * self.inv_sigma_3d
    }
}

/// The impulses of the three cell rows around a grid row that lie within one radius of it
/// vertically, as parallel arrays, with the row-constant factor w·K·e^(−g dy²)
/// precomputed. Each cell row is its cells' impulses in column order, and each cell's are
/// sorted by x, so a cell row is sorted by x.
#[derive(Default)]
struct RowImpulses {
    /// Start of each cell row, then the end of the last.
    row_starts: Vec<usize>,
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
        self.row_starts.clear();
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

    /// Appends one cell's impulses with dy² < R² at row `y`, keeping their x order, to the current cell row.
    fn push_cell(&mut self, g: &Gabor, impulses: &[Impulse2], y: f64) {
        if self.row_starts.is_empty() {
            self.row_starts.push(0);
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
    }

    /// Closes the current cell row.
    fn end_row(&mut self) {
        if self.row_starts.is_empty() {
            self.row_starts.push(0);
        }
        self.row_starts.push(self.x.len());
    }

    #[inline(always)]
    fn row(&self, r: usize) -> std::ops::Range<usize> {
        self.row_starts[r]..self.row_starts[r + 1]
    }

    /// The impulses of cell row `r` with |x − xᵢ| < R: those farther away horizontally
    /// have dx² ≥ R², so their term is zero and skipping them leaves the sum unchanged.
    #[inline(always)]
    fn window(&self, r: usize, x: f64, radius: f64) -> std::ops::Range<usize> {
        let range = self.row(r);
        let xs = &self.x[range.clone()];
        range.start + xs.partition_point(|&xi| x - xi >= radius)
            ..range.start + xs.partition_point(|&xi| x - xi > -radius)
    }

    /// Moves `window` (cell row `r`'s, for an x no larger than this one) to x: the same
    /// range [`RowImpulses::window`] finds, found by walking forward.
    #[inline(always)]
    fn slide(&self, r: usize, window: &mut std::ops::Range<usize>, x: f64, radius: f64) {
        let end = self.row_starts[r + 1];
        while window.start < end && x - self.x[window.start] >= radius {
            window.start += 1;
        }
        window.end = window.end.max(window.start);
        while window.end < end && x - self.x[window.end] > -radius {
            window.end += 1;
        }
    }
}

/// Lanes of the anisotropic kernel sum: the window's terms are added into LANES partial
/// sums (term k into lane k mod LANES) combined pairwise at the end. A fixed association,
/// so the sum is the same on every path (scalar, batch, any SIMD width) while it vectorises.
const LANES: usize = 4;

/// Terms computed per pass of [`anisotropic_window_sum`]: a stack buffer.
const TERM_BLOCK: usize = 64;

/// Σ over the window of w·K·e^(−g dy²)·e^(−g dx²)·cos(ψ − φᵢ), terms with dx² + dy² ≥ R²
/// selected away; cos(ψ − φᵢ) = cos ψ cos φᵢ + sin ψ sin φᵢ, so no cosine per impulse.
/// The terms of a block are first written to a buffer (a plain map, which the compiler
/// vectorises fully), padded with +0 to whole lanes, then added lane-wise.
#[inline(always)]
fn anisotropic_window_sum(
    row: &RowImpulses,
    window: std::ops::Range<usize>,
    x: f64,
    g: f64,
    r2_max: f64,
    (cos_psi, sin_psi): (f64, f64),
) -> f64 {
    let mut lanes = [0.0; LANES];
    let mut terms = [0.0; TERM_BLOCK];
    for start in window.clone().step_by(TERM_BLOCK) {
        let block = start..(start + TERM_BLOCK).min(window.end);
        let m = block.len();
        let impulses = row.x[block.clone()]
            .iter()
            .zip(&row.dy2[block.clone()])
            .zip(&row.weighted[block.clone()])
            .zip(row.cos_phase[block.clone()].iter().zip(&row.sin_phase[block]));
        for (t, (((xi, dy2), weighted), (cp, sp))) in terms.iter_mut().zip(impulses) {
            let dx = x - xi;
            let dx2 = dx * dx;
            let term = weighted * exp_kernel(-g * dx2) * (cos_psi * cp + sin_psi * sp);
            *t = if dx2 + dy2 < r2_max { term } else { 0.0 };
        }
        let padded = m.div_ceil(LANES) * LANES;
        terms[m..padded].fill(0.0);
        for chunk in terms[..padded].chunks_exact(LANES) {
            for (lane, t) in lanes.iter_mut().zip(chunk) {
                *lane += t;
            }
        }
    }
    (lanes[0] + lanes[1]) + (lanes[2] + lanes[3])
}

/// The Gaussian envelope of a kernel in phasor noise's complex sum, lowered by its value
/// at the truncation radius (e^(−g R²) = [`TRUNCATION`]) so that it falls to zero there.
/// Gabor noise keeps the plain truncated Gaussian (Lagae et al. 2009): a kernel leaving
/// the support changes its value by at most 5 % of one kernel's peak. The phase of the sum
/// amplifies such a step by 1/|G|, and |G| is small wherever impulses cancel: with the
/// plain Gaussian, 688 of 8·10⁶ steps of 10⁻³ along lines jumped by more than 0.05 of
/// phasor noise's range of 2 (up to 1.5: arcs where the stripes break off); with this
/// envelope the sum, and so the phase away from its isolated zeros, is continuous.
#[inline(always)]
fn phase_envelope(g: f64, r2: f64) -> f64 {
    (-g * r2).exp() - TRUNCATION
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
