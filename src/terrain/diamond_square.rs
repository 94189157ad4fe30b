//! Midpoint displacement / diamond-square on a (2ⁿ + 1)² grid (Fournier, Fussell &
//! Carpenter 1982; seed 001): at level l (spacing d = 2ⁿ⁻ˡ) every square centre gets the
//! mean of its four corners plus a displacement, then every diamond point the mean of its
//! (three or four) neighbours at distance d plus a displacement; the displacement scale is
//! σ·2^(−H·l). Seed 001's applet variant keeps the scale constant and draws a random sign.
//! Seed 002's rule instead draws each new point uniformly within its parents' range.
//!
//! The generator works on any grid-aligned rectangle: level l on a rectangle needs level
//! l − 1 on the rectangle grown by 2d, so a whole grid, a tile or a band of rows are the same
//! computation and agree bit for bit. Rows of a level are computed in parallel.

use rayon::prelude::*;

use super::random::Displacements;

/// How a new point is made from its parents.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Rule {
    /// Mean of the parents plus a scaled displacement (Fournier, Fussell & Carpenter).
    MeanPlusDisplacement,
    /// Uniform within the range of the parents (seed 002): never leaves the corners' range.
    UniformInSupport,
}

/// The lattice the grid indices stand for (seed 001's grid types).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum Lattice {
    /// Squares: diamond-square (square centres, then diamonds).
    #[default]
    Square,
    /// Triangles: point (i, j) sits at (i + j/2, j·√3/2); each level splits every triangle
    /// into four by displacing its edge midpoints, each from its edge's two ends.
    Triangle,
}

/// Parameters of the generator.
#[derive(Debug, Clone, Copy)]
pub struct DiamondSquare {
    /// How new points are made.
    pub rule: Rule,
    /// Square or triangular lattice.
    pub lattice: Lattice,
    /// n: the grid has 2ⁿ + 1 points per side.
    pub levels: u32,
    /// Roughness H: the displacement scale is multiplied by 2^(−H) per level.
    pub hurst: f64,
    /// Displacement scale σ at level 0.
    pub sigma: f64,
    /// Heights of the four corners (x0y0, xNy0, x0yN, xNyN), kept exactly; `None` draws
    /// each (a level-0 displacement around 0).
    pub corners: Option<[f64; 4]>,
    /// Seed 001's applet: constant scale, random sign.
    pub applet: bool,
    /// Random numbers.
    pub random: Displacements,
}

/// The mean of two to four parents; dividing by 2 or 4 is multiplying by 0.5 or 0.25 (the
/// same bits), which spares the division on all but the border's three-parent points.
#[inline(always)]
fn mean(parents: &[f64]) -> f64 {
    let sum = parents.iter().sum::<f64>();
    match parents.len() {
        4 => sum * 0.25,
        2 => sum * 0.5,
        n => sum / n as f64,
    }
}

/// A rectangle of grid points (inclusive bounds, fine-grid coordinates).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Rect {
    /// First column.
    pub x0: u64,
    /// First row.
    pub y0: u64,
    /// Last column.
    pub x1: u64,
    /// Last row.
    pub y1: u64,
}

impl Rect {
    /// Number of columns.
    pub fn width(&self) -> usize {
        (self.x1 - self.x0 + 1) as usize
    }
    /// Number of rows.
    pub fn height(&self) -> usize {
        (self.y1 - self.y0 + 1) as usize
    }

    /// The rectangle grown by `margin` on every side, clipped to a grid whose last index is `last`.
    pub fn grown(&self, margin: u64, last: u64) -> Rect {
        Rect {
            x0: self.x0.saturating_sub(margin),
            y0: self.y0.saturating_sub(margin),
            x1: (self.x1 + margin).min(last),
            y1: (self.y1 + margin).min(last),
        }
    }
}

/// Heights of one level on a rectangle aligned to the level's spacing `d`: value (i, j) is
/// the height at (x0 + i·d, y0 + j·d).
struct LevelGrid {
    /// log₂ of the spacing d.
    shift: u32,
    x0: u64,
    y0: u64,
    cols: usize,
    rows: usize,
    values: Vec<f64>,
}

impl LevelGrid {
    #[inline(always)]
    fn get(&self, x: u64, y: u64) -> f64 {
        let i = ((x - self.x0) >> self.shift) as usize;
        let j = ((y - self.y0) >> self.shift) as usize;
        debug_assert!(i < self.cols && j < self.rows);
        self.values[j * self.cols + i]
    }
}

impl DiamondSquare {
    /// Points per side, 2ⁿ + 1.
    pub fn side(&self) -> u64 {
        (1u64 << self.levels) + 1
    }

    fn scale(&self, level: u32) -> f64 {
        if self.applet { self.sigma } else { self.sigma * (-self.hurst * f64::from(level)).exp2() }
    }

    #[inline(always)]
    fn displacement(&self, level: u32, scale: f64, x: u64, y: u64) -> f64 {
        let r = self.random.sample(level, x, y);
        if self.applet { r.abs() * self.random.sign(level, x, y) * scale } else { r * scale }
    }

    /// A new point from its parents (in a fixed order), by the generator's rule.
    #[inline(always)]
    fn new_point(&self, parents: &[f64], level: u32, scale: f64, x: u64, y: u64) -> f64 {
        match self.rule {
            Rule::MeanPlusDisplacement => mean(parents) + self.displacement(level, scale, x, y),
            Rule::UniformInSupport => {
                let (lo, hi) =
                    parents.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &p| (lo.min(p), hi.max(p)));
                lo + (hi - lo) * self.random.unit(level, x, y)
            }
        }
    }

    /// The finished heights on `rect` (row-major, `rect.width()` per row).
    pub fn heights(&self, rect: Rect) -> Vec<f64> {
        self.level(self.levels, rect, None).values
    }

    /// The finished heights on `rect`, written into `out` (`rect.width() × rect.height()`
    /// values, row-major) without an intermediate buffer.
    ///
    /// # Panics
    /// When `out` has the wrong length (a caller bug).
    pub fn heights_into(&self, rect: Rect, out: &mut [f64]) {
        assert_eq!(out.len(), rect.width() * rect.height(), "output length must match the rectangle");
        self.level(self.levels, rect, Some(out));
    }

    /// Level `level` on `rect` (snapped outward to the level's lattice and clipped to the grid).
    /// With `out`, the level's values go there and the returned grid holds none.
    fn level(&self, level: u32, rect: Rect, out: Option<&mut [f64]>) -> LevelGrid {
        let last = self.side() - 1;
        let shift = self.levels - level;
        let d = 1u64 << shift;
        let snap = |r: Rect| Rect {
            x0: r.x0 / d * d,
            y0: r.y0 / d * d,
            x1: (r.x1.div_ceil(d) * d).min(last),
            y1: (r.y1.div_ceil(d) * d).min(last),
        };
        let r = snap(rect);
        let (cols, rows) = (((r.x1 - r.x0) / d + 1) as usize, ((r.y1 - r.y0) / d + 1) as usize);
        if level == 0 {
            let values = (0..rows * cols)
                .map(|k| {
                    let (x, y) = (r.x0 + (k % cols) as u64 * d, r.y0 + (k / cols) as u64 * d);
                    let corner = usize::from(x == last) + 2 * usize::from(y == last);
                    match self.corners {
                        Some(fixed) => fixed[corner],
                        None => self.displacement(0, self.scale(0), x, y),
                    }
                })
                .collect();
            let values: Vec<f64> = values;
            if let Some(out) = out {
                out.copy_from_slice(&values);
                return LevelGrid { shift, x0: r.x0, y0: r.y0, cols, rows, values: Vec::new() };
            }
            return LevelGrid { shift, x0: r.x0, y0: r.y0, cols, rows, values };
        }
        let mut owned = Vec::new();
        let values: &mut [f64] = match out {
            Some(slice) => slice,
            None => {
                owned = vec![0.0; rows * cols];
                &mut owned
            }
        };
        match self.lattice {
            Lattice::Square => self.fill_square_level(level, r, shift, values),
            Lattice::Triangle => self.fill_triangle_level(level, r, shift, values),
        }
        LevelGrid { shift, x0: r.x0, y0: r.y0, cols, rows, values: owned }
    }

    /// Fills level `level` of the square lattice on the snapped rectangle `r` (row-major,
    /// spacing d = 2^shift) into `values`: square centres first, then diamonds.
    fn fill_square_level(&self, level: u32, r: Rect, shift: u32, values: &mut [f64]) {
        let last = self.side() - 1;
        let d = 1u64 << shift;
        let cols = ((r.x1 - r.x0) >> shift) as usize + 1;
        let two_d = 2 * d;
        let grown = r.grown(two_d, last);
        let coarse = self.level(level - 1, grown, None);
        let scale = self.scale(level);
        // Square centres ((2a + 1)·d, (2b + 1)·d) within d of the rectangle: the mean of the
        // four coarse corners plus a displacement. Computed once; diamonds reuse them.
        let (a0, a1) = (r.x0.saturating_sub(two_d).div_ceil(two_d), (r.x1 / two_d).min(last / two_d - 1));
        let (b0, b1) = (r.y0.saturating_sub(two_d).div_ceil(two_d), (r.y1 / two_d).min(last / two_d - 1));
        let centre_cols = (a1 + 1 - a0) as usize;
        let mut centres = vec![0.0; centre_cols * (b1 + 1 - b0) as usize];
        centres.par_chunks_mut(centre_cols).enumerate().for_each(|(jb, row)| {
            let y = (2 * (b0 + jb as u64) + 1) * d;
            for (ia, value) in row.iter_mut().enumerate() {
                let x = (2 * (a0 + ia as u64) + 1) * d;
                let parents = [
                    coarse.get(x - d, y - d),
                    coarse.get(x + d, y - d),
                    coarse.get(x - d, y + d),
                    coarse.get(x + d, y + d),
                ];
                *value = self.new_point(&parents, level, scale, x, y);
            }
        });
        // Rows of the coarse level and of the centres, and column indices into them.
        let coarse_row = |y: u64| {
            let j = ((y - coarse.y0) >> (shift + 1)) as usize;
            &coarse.values[j * coarse.cols..(j + 1) * coarse.cols]
        };
        let centre_row = |y: u64| {
            let b = ((y >> (shift + 1)) - b0) as usize;
            &centres[b * centre_cols..(b + 1) * centre_cols]
        };
        let coarse_col = |x: u64| ((x - coarse.x0) >> (shift + 1)) as usize;
        let centre_col = |x: u64| ((x >> (shift + 1)) - a0) as usize;
        values.par_chunks_mut(cols).enumerate().for_each(|(j, row)| {
            let y = r.y0 + j as u64 * d;
            if (y >> shift) & 1 == 0 {
                // Coarse points alternate with diamonds whose left and right neighbours are
                // coarse points and whose upper and lower neighbours are square centres.
                let here = coarse_row(y);
                let up = (y >= d).then(|| centre_row(y - d));
                let down = (y + d <= last).then(|| centre_row(y + d));
                for (i, value) in row.iter_mut().enumerate() {
                    let x = r.x0 + i as u64 * d;
                    if (x >> shift) & 1 == 0 {
                        *value = here[coarse_col(x)];
                        continue;
                    }
                    let mut parents = [here[coarse_col(x - d)], here[coarse_col(x + d)], 0.0, 0.0];
                    let mut count = 2;
                    for neighbours in [up, down].into_iter().flatten() {
                        parents[count] = neighbours[centre_col(x)];
                        count += 1;
                    }
                    *value = self.new_point(&parents[..count], level, scale, x, y);
                }
            } else {
                // Square centres alternate with diamonds whose left and right neighbours are
                // square centres and whose upper and lower neighbours are coarse points.
                let here = centre_row(y);
                let (up, down) = (coarse_row(y - d), coarse_row(y + d));
                for (i, value) in row.iter_mut().enumerate() {
                    let x = r.x0 + i as u64 * d;
                    if (x >> shift) & 1 == 1 {
                        *value = here[centre_col(x)];
                        continue;
                    }
                    let mut parents = [0.0; 4];
                    let mut count = 0;
                    if x >= d {
                        parents[count] = here[centre_col(x - d)];
                        count += 1;
                    }
                    if x + d <= last {
                        parents[count] = here[centre_col(x + d)];
                        count += 1;
                    }
                    parents[count] = up[coarse_col(x)];
                    parents[count + 1] = down[coarse_col(x)];
                    *value = self.new_point(&parents[..count + 2], level, scale, x, y);
                }
            }
        });
    }

    /// Fills level `level` of the triangular lattice on the snapped rectangle `r`: every new point
    /// is an edge midpoint whose parents are the edge's ends, coarse points at distance d —
    /// along x (odd, even), along y (even, odd) or along the anti-diagonal (odd, odd).
    fn fill_triangle_level(&self, level: u32, r: Rect, shift: u32, values: &mut [f64]) {
        let last = self.side() - 1;
        let d = 1u64 << shift;
        let grown = r.grown(d, last);
        let coarse = self.level(level - 1, grown, None);
        let scale = self.scale(level);
        let cols = ((r.x1 - r.x0) >> shift) as usize + 1;
        values.par_chunks_mut(cols).enumerate().for_each(|(j, row)| {
            let y = r.y0 + ((j as u64) << shift);
            let y_odd = (y >> shift) & 1 == 1;
            for (i, value) in row.iter_mut().enumerate() {
                let x = r.x0 + ((i as u64) << shift);
                let x_odd = (x >> shift) & 1 == 1;
                *value = match (x_odd, y_odd) {
                    (false, false) => coarse.get(x, y),
                    (true, false) => self.new_point(&[coarse.get(x - d, y), coarse.get(x + d, y)], level, scale, x, y),
                    (false, true) => self.new_point(&[coarse.get(x, y - d), coarse.get(x, y + d)], level, scale, x, y),
                    (true, true) => {
                        self.new_point(&[coarse.get(x - d, y + d), coarse.get(x + d, y - d)], level, scale, x, y)
                    }
                };
            }
        });
    }
}
