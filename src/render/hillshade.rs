//! Hillshaded pictures of heightfields: the colour ramp by height darkened by the light of
//! a sun in the north-west, 45° up (the cartographers' convention), computed from central
//! differences of the grid.

use glam::DVec3;
use rayon::prelude::*;

use super::Picture;
use crate::mesh::Rgb;

/// A heightfield to picture: `heights` row-major, `columns` per row, rows along +y.
pub struct Relief<'a> {
    /// Heights, row-major.
    pub heights: &'a [f64],
    /// Points per row.
    pub columns: usize,
    /// World distance between neighbouring columns and rows.
    pub spacing: (f64, f64),
    /// Vertical exaggeration of the light (1 = true slopes); `None` picks the one that makes
    /// the mean slope 30°, so that gentle and steep terrains both read.
    pub exaggeration: Option<f64>,
}

impl Relief<'_> {
    /// The slope (gradient) at grid point (x, y) by central differences, one-sided at the
    /// borders.
    fn gradient(&self, x: usize, y: usize) -> (f64, f64) {
        let (w, h) = (self.columns, self.heights.len() / self.columns);
        let at = |x: usize, y: usize| self.heights[y * w + x];
        let (x0, x1) = (x.saturating_sub(1), (x + 1).min(w - 1));
        let (y0, y1) = (y.saturating_sub(1), (y + 1).min(h - 1));
        (
            (at(x1, y) - at(x0, y)) / ((x1 - x0).max(1) as f64 * self.spacing.0),
            (at(x, y1) - at(x, y0)) / ((y1 - y0).max(1) as f64 * self.spacing.1),
        )
    }

    fn auto_exaggeration(&self) -> f64 {
        let (w, h) = (self.columns, self.heights.len() / self.columns);
        let stride = (w.max(h) / 256).max(1);
        let (mut sum, mut n) = (0.0, 0usize);
        for y in (0..h).step_by(stride) {
            for x in (0..w).step_by(stride) {
                let (dx, dy) = self.gradient(x, y);
                sum += dx.hypot(dy);
                n += 1;
            }
        }
        let mean = sum / n.max(1) as f64;
        if mean > 1e-12 && mean.is_finite() { 30f64.to_radians().tan() / mean } else { 1.0 }
    }
}

/// The picture of `relief`, one pixel per grid point, north (+y) up, coloured by
/// `color(height)`.
pub fn hillshade(relief: &Relief, color: impl Fn(f64) -> Rgb + Sync) -> Picture {
    let (w, h) = (relief.columns, relief.heights.len() / relief.columns.max(1));
    let sun = {
        let (azimuth, altitude) = (315f64.to_radians(), 45f64.to_radians());
        DVec3::new(azimuth.sin() * altitude.cos(), azimuth.cos() * altitude.cos(), altitude.sin())
    };
    let exaggeration = relief.exaggeration.unwrap_or_else(|| relief.auto_exaggeration());
    let mut rgba = vec![0u8; w * h * 4];
    rgba.par_chunks_mut(w * 4).enumerate().for_each(|(row, out)| {
        let y = h - 1 - row;
        for x in 0..w {
            let (dx, dy) = relief.gradient(x, y);
            let normal = DVec3::new(-dx * exaggeration, -dy * exaggeration, 1.0).normalize();
            let light = 0.35 + 0.65 * normal.dot(sun).max(0.0) / sun.z;
            let c = color(relief.heights[y * w + x]);
            let px = &mut out[4 * x..4 * x + 4];
            for k in 0..3 {
                px[k] = (c[k] as f64 * light).round().clamp(0.0, 255.0) as u8;
            }
            px[3] = 255;
        }
    });
    Picture { width: w, height: h, rgba }
}
