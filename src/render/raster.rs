//! A band-parallel z-buffer rasteriser: the supersampled frame is cut into bands of rows,
//! primitives are binned per band in input order, and every band is drawn independently.
//! Within a band primitives are drawn in input order and the nearer sample wins (ties keep
//! the first), so the picture is the same at any thread count.

use glam::{Vec2, Vec3};
use rayon::prelude::*;

/// Rows per band.
const BAND_ROWS: usize = 16;

/// The supersampled frame: linear colour, inverse depth (0 = nothing) and coverage.
pub struct Frame {
    pub width: usize,
    pub height: usize,
    pub color: Vec<Vec3>,
    pub depth: Vec<f32>,
    pub covered: Vec<bool>,
}

/// One band of a frame, rows `y0..y0 + rows`.
pub struct Band<'a> {
    y0: usize,
    width: usize,
    color: &'a mut [Vec3],
    depth: &'a mut [f32],
    covered: &'a mut [bool],
}

/// What a triangle writes: colour and depth, or depth alone (hidden-line pass).
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Fill {
    Shaded,
    DepthOnly,
}

/// A projected triangle: corners (pixels and inverse depth), corner colours and, for a
/// textured mesh, corner UVs.
pub struct Triangle {
    pub corners: [Vec3; 3],
    pub colors: [Vec3; 3],
    pub uvs: Option<[Vec2; 3]>,
}

/// A projected line segment with end colours.
pub struct Segment {
    pub ends: [Vec3; 2],
    pub colors: [Vec3; 2],
}

impl Frame {
    pub fn new(width: usize, height: usize) -> Self {
        let n = width * height;
        Frame { width, height, color: vec![Vec3::ZERO; n], depth: vec![0.0; n], covered: vec![false; n] }
    }

    fn band_count(&self) -> usize {
        self.height.div_ceil(BAND_ROWS)
    }

    /// The bands whose rows `lo..=hi` (pixel coordinates, clamped) touch.
    fn bands_of(&self, lo: f32, hi: f32) -> Option<std::ops::RangeInclusive<usize>> {
        if !(hi >= 0.0 && lo < self.height as f32) {
            return None;
        }
        let first = lo.max(0.0) as usize / BAND_ROWS;
        let last = (hi.min(self.height as f32 - 1.0) as usize) / BAND_ROWS;
        Some(first..=last)
    }

    /// Sorts primitive indices into the bands their vertical extent `extent(i)` touches.
    fn bin(&self, count: usize, extent: impl Fn(usize) -> Option<(f32, f32)>) -> Vec<Vec<u32>> {
        let mut bins = vec![Vec::new(); self.band_count()];
        for i in 0..count {
            if let Some(bands) = extent(i).and_then(|(lo, hi)| self.bands_of(lo, hi)) {
                for b in bands {
                    bins[b].push(i as u32);
                }
            }
        }
        bins
    }

    /// Runs `draw` on every band with that band's bin, in parallel.
    fn each_band(&mut self, bins: &[Vec<u32>], draw: impl Fn(&mut Band, &[u32]) + Sync) {
        let width = self.width;
        let rows = BAND_ROWS * width;
        self.color
            .par_chunks_mut(rows)
            .zip(self.depth.par_chunks_mut(rows))
            .zip(self.covered.par_chunks_mut(rows))
            .enumerate()
            .for_each(|(b, ((color, depth), covered))| {
                let mut band = Band { y0: b * BAND_ROWS, width, color, depth, covered };
                draw(&mut band, &bins[b]);
            });
    }

    /// Draws triangles (skipping `None`s) with the z-buffer.
    pub fn triangles(&mut self, triangles: &[Option<Triangle>], fill: Fill) {
        self.draw(triangles, fill, None);
    }

    /// Draws shaded triangles whose colours are multiplied by `texture` at their UVs,
    /// interpolated perspective-correctly.
    pub fn textured_triangles(&mut self, triangles: &[Option<Triangle>], texture: &super::texture::Texture) {
        self.draw(triangles, Fill::Shaded, Some(texture));
    }

    fn draw(&mut self, triangles: &[Option<Triangle>], fill: Fill, texture: Option<&super::texture::Texture>) {
        let bins = self.bin(triangles.len(), |i| {
            let t = triangles[i].as_ref()?;
            let ys = t.corners.map(|c| c.y);
            Some((ys[0].min(ys[1]).min(ys[2]), ys[0].max(ys[1]).max(ys[2])))
        });
        self.each_band(&bins, |band, ids| {
            for &i in ids {
                if let Some(t) = &triangles[i as usize] {
                    band.triangle(t, fill, texture);
                }
            }
        });
    }

    /// Draws segments one sample wide, visible where they are not behind a surface by
    /// more than `tolerance` (relative inverse depth).
    pub fn segments(&mut self, segments: &[Segment], tolerance: f32) {
        let bins = self.bin(segments.len(), |i| {
            let [a, b] = segments[i].ends;
            Some((a.y.min(b.y), a.y.max(b.y)))
        });
        self.each_band(&bins, |band, ids| {
            for &i in ids {
                band.segment(&segments[i as usize], tolerance);
            }
        });
    }

    /// Draws round dots of `radius` samples at `points` (position, colour), visible where
    /// they are not behind a surface by more than `tolerance` (relative inverse depth).
    pub fn dots(&mut self, points: &[(Vec3, Vec3)], radius: f32, tolerance: f32) {
        let bins = self.bin(points.len(), |i| Some((points[i].0.y - radius, points[i].0.y + radius)));
        self.each_band(&bins, |band, ids| {
            for &i in ids {
                let (p, c) = points[i as usize];
                band.dot(p, c, radius, tolerance);
            }
        });
    }
}

/// Twice the signed area of (a, b, p).
fn edge(a: Vec2, b: Vec2, p: Vec2) -> f32 {
    (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x)
}

impl Band<'_> {
    fn rows(&self) -> usize {
        self.depth.len() / self.width
    }

    /// Writes a sample if it is nearer than what is there.
    fn put(&mut self, x: usize, y: usize, z: f32, color: Vec3, fill: Fill) {
        let i = (y - self.y0) * self.width + x;
        if z > self.depth[i] {
            self.depth[i] = z;
            if fill == Fill::Shaded {
                self.color[i] = color;
                self.covered[i] = true;
            }
        }
    }

    fn triangle(&mut self, t: &Triangle, fill: Fill, texture: Option<&super::texture::Texture>) {
        let [a, b, c] = t.corners.map(|v| v.truncate());
        let area = edge(a, b, c);
        if area.abs() < 1e-12 || !area.is_finite() {
            return;
        }
        let (lo, hi) = (a.min(b).min(c), a.max(b).max(c));
        let x0 = lo.x.max(0.0).floor() as usize;
        let x1 = (hi.x.ceil().max(0.0) as usize).min(self.width);
        let y0 = (lo.y.max(0.0).floor() as usize).max(self.y0);
        let y1 = (hi.y.ceil().max(0.0) as usize).min(self.y0 + self.rows());
        let inv = 1.0 / area;
        let z = t.corners.map(|v| v.z);
        for y in y0..y1 {
            for x in x0..x1 {
                let p = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                let (w0, w1, w2) = (edge(b, c, p) * inv, edge(c, a, p) * inv, edge(a, b, p) * inv);
                if w0 < 0.0 || w1 < 0.0 || w2 < 0.0 {
                    continue;
                }
                let depth = w0 * z[0] + w1 * z[1] + w2 * z[2];
                let mut color = t.colors[0] * w0 + t.colors[1] * w1 + t.colors[2] * w2;
                if let (Some(texture), Some(uv)) = (texture, &t.uvs) {
                    // Linear in screen space are uv·(1/depth) and 1/depth.
                    let uv = (uv[0] * (w0 * z[0]) + uv[1] * (w1 * z[1]) + uv[2] * (w2 * z[2])) / depth;
                    color *= texture.sample(uv);
                }
                self.put(x, y, depth, color, fill);
            }
        }
    }

    fn segment(&mut self, s: &Segment, tolerance: f32) {
        let [a, b] = s.ends;
        let d = b - a;
        let steps = d.x.abs().max(d.y.abs()).ceil().clamp(1.0, 1e6) as usize;
        let (row0, row1) = (self.y0 as f32, (self.y0 + self.rows()) as f32);
        for k in 0..=steps {
            let t = k as f32 / steps as f32;
            let p = a + d * t;
            if p.x < 0.0 || p.x >= self.width as f32 || p.y < row0 || p.y >= row1 {
                continue;
            }
            self.put_over(p.x as usize, p.y as usize, p.z, s.colors[0].lerp(s.colors[1], t), tolerance);
        }
    }

    /// Writes a line or dot sample unless a surface is nearer by more than `tolerance`.
    fn put_over(&mut self, x: usize, y: usize, z: f32, color: Vec3, tolerance: f32) {
        let i = (y - self.y0) * self.width + x;
        if z >= self.depth[i] * (1.0 - tolerance) {
            self.depth[i] = self.depth[i].max(z);
            self.color[i] = color;
            self.covered[i] = true;
        }
    }

    fn dot(&mut self, p: Vec3, color: Vec3, radius: f32, tolerance: f32) {
        let rows = (self.y0 as f32, (self.y0 + self.rows()) as f32);
        let y0 = (p.y - radius).floor().max(rows.0) as usize;
        let y1 = ((p.y + radius).ceil().min(rows.1)).max(0.0) as usize;
        let x0 = (p.x - radius).floor().max(0.0) as usize;
        let x1 = ((p.x + radius).ceil().min(self.width as f32)).max(0.0) as usize;
        for y in y0..y1 {
            for x in x0..x1 {
                let q = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                if q.distance_squared(p.truncate()) <= radius * radius {
                    self.put_over(x, y, p.z, color, tolerance);
                }
            }
        }
    }
}
