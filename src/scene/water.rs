//! Water (seed 002, "Water", its geometry): a surface at sea level over a terrain's extent,
//! moved by a sum of directional waves, with each vertex's water depth over the terrain
//! as an attribute — shallow water is the more transparent (the seed's shore effect). The
//! waves are sinusoids h = A·cos(k·(d·x) − ω·t + φ) whose angular frequency follows
//! deep-water dispersion, ω² = g·k.

use glam::{DVec2, DVec3};
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::mesh::Mesh;
use crate::noise::hash::{Stream, derive_seed};

/// Gravity in the dispersion relation, world units per second squared.
pub const GRAVITY: f64 = 9.81;

/// One directional wave.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Wave {
    /// Direction of travel in the xy-plane, radians from +x.
    pub direction: f64,
    /// Crest-to-crest distance.
    pub wavelength: f64,
    /// Height of a crest above the mean.
    pub amplitude: f64,
    /// Phase, radians.
    pub phase: f64,
}

impl Wave {
    /// Height of the wave at `p` and time `t`.
    pub fn height(&self, p: DVec2, t: f64) -> f64 {
        let k = std::f64::consts::TAU / self.wavelength;
        let omega = (GRAVITY * k).sqrt();
        let d = DVec2::from_angle(self.direction);
        self.amplitude * (k * d.dot(p) - omega * t + self.phase).cos()
    }
}

/// `count` waves from the seed for a sea of `extent` (its larger side): directions within
/// 35° of one wind direction, wavelengths from 1/40 to 1/8 of the extent, amplitudes a
/// steepness of 0.04/count of the wavelength (so their sum stays gentle).
pub fn waves_from_seed(seed: u64, count: usize, extent: f64) -> Vec<Wave> {
    let mut draw = Stream::new(derive_seed(seed, "water waves"));
    let wind = draw.uniform(0.0, std::f64::consts::TAU);
    (0..count)
        .map(|_| {
            let wavelength = extent * draw.uniform(1.0 / 40.0, 1.0 / 8.0);
            Wave {
                direction: wind + draw.uniform(-35f64.to_radians(), 35f64.to_radians()),
                wavelength,
                amplitude: 0.04 / count as f64 * wavelength,
                phase: draw.uniform(0.0, std::f64::consts::TAU),
            }
        })
        .collect()
}

/// The terrain's height below a regular grid of points (the highest face over each point),
/// found by rasterising the faces' xy-projections onto the grid.
#[derive(Debug, Clone)]
pub struct Floor {
    lo: DVec2,
    step: DVec2,
    cols: usize,
    heights: Vec<Option<f64>>,
}

impl Floor {
    /// The floor of `terrain` (z up) under a `cols` × `rows` grid over `lo..hi`.
    pub fn of(terrain: &Mesh, lo: DVec2, hi: DVec2, cols: usize, rows: usize) -> Floor {
        let step = (hi - lo) / DVec2::new((cols - 1).max(1) as f64, (rows - 1).max(1) as f64);
        let mut heights = vec![None::<f64>; cols * rows];
        for t in &terrain.triangles {
            let [a, b, c] = t.map(|v| terrain.positions[v as usize]);
            let grid = |p: DVec3| (p.truncate() - lo) / step;
            let (ga, gb, gc) = (grid(a), grid(b), grid(c));
            let (min, max) = (ga.min(gb).min(gc), ga.max(gb).max(gc));
            let area = (gb - ga).perp_dot(gc - ga);
            if area.abs() < 1e-300 {
                continue;
            }
            let (x0, x1) = (min.x.ceil().max(0.0) as usize, (max.x.floor().min((cols - 1) as f64)).max(-1.0));
            let (y0, y1) = (min.y.ceil().max(0.0) as usize, (max.y.floor().min((rows - 1) as f64)).max(-1.0));
            if x1 < 0.0 || y1 < 0.0 {
                continue;
            }
            for y in y0..=y1 as usize {
                for x in x0..=x1 as usize {
                    let p = DVec2::new(x as f64, y as f64);
                    let wb = (p - ga).perp_dot(gc - ga) / area;
                    let wc = (gb - ga).perp_dot(p - ga) / area;
                    let wa = 1.0 - wb - wc;
                    if wa < -1e-9 || wb < -1e-9 || wc < -1e-9 {
                        continue;
                    }
                    let z = wa * a.z + wb * b.z + wc * c.z;
                    let slot = &mut heights[y * cols + x];
                    *slot = Some(slot.map_or(z, |h| h.max(z)));
                }
            }
        }
        Floor { lo, step, cols, heights }
    }

    /// The floor height at grid point (x, y), if a face lies over or under it.
    pub fn at(&self, x: usize, y: usize) -> Option<f64> {
        self.heights[y * self.cols + x]
    }

    /// Grid points.
    pub fn point_count(&self) -> usize {
        self.heights.len()
    }

    /// The grid point's position in the plane.
    pub fn point(&self, x: usize, y: usize) -> DVec2 {
        self.lo + DVec2::new(x as f64, y as f64) * self.step
    }
}

/// Parameters of a water surface.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WaterParams {
    /// Sea level (z).
    pub level: f64,
    /// Grid cells along the longer side.
    pub cells: usize,
    /// The waves.
    pub waves: Vec<Wave>,
    /// Depth over which the water's opacity rises by 1 − 1/e.
    pub clarity: f64,
}

/// The water request (#38): what `asperity water` asks for over a terrain, in the
/// terrain's units where it says so and as shares of the terrain's larger side otherwise.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
pub struct WaterRequest {
    /// Sea level (z, in the terrain's units).
    #[cfg_attr(feature = "cli", arg(long, allow_negative_numbers = true))]
    pub level: f64,
    /// Grid cells along the terrain's longer side.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = WaterRequest::default().cells))]
    pub cells: usize,
    /// Directional waves summed.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = WaterRequest::default().waves))]
    pub waves: usize,
    /// Seed of the waves' directions, lengths and phases.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = 0))]
    pub seed: u64,
    /// Depth at which the water's opacity has risen by 1 − 1/e, as a fraction of the
    /// terrain's larger side.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = WaterRequest::default().clarity))]
    pub clarity: f64,
    /// Frames written.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = WaterRequest::default().frames))]
    pub frames: usize,
}

impl Default for WaterRequest {
    fn default() -> Self {
        WaterRequest { level: 0.0, cells: 128, waves: 4, seed: 0, clarity: 0.02, frames: 24 }
    }
}

impl WaterRequest {
    /// The most water vertices over all frames.
    pub const MAX_VERTICES: usize = 1 << 25;

    /// The request's own rules: 1 to 1000 frames and at most 64 waves.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] naming the rule.
    pub fn check(&self) -> Result<()> {
        if !(1..=1000).contains(&self.frames) || self.waves > 64 {
            return Err(Error::InvalidInput("water: 1 to 1000 frames and at most 64 waves".into()));
        }
        Ok(())
    }

    /// The surface's parameters over a terrain whose larger side is `extent` long.
    pub fn params(&self, extent: f64) -> WaterParams {
        WaterParams {
            level: self.level,
            cells: self.cells,
            waves: waves_from_seed(self.seed, self.waves, extent),
            clarity: self.clarity * extent,
        }
    }

    /// The water's frames over `terrain` at `fps` (its floor sampled once), refused before
    /// they are made when they would exceed [`WaterRequest::MAX_VERTICES`].
    ///
    /// # Errors
    /// A rule of [`WaterRequest::check`]; a terrain without vertices or one the water
    /// cannot lie on ([`water_floor`]); too many vertices.
    pub fn frames_over(&self, terrain: &Mesh, fps: f64) -> Result<(WaterParams, Vec<Mesh>)> {
        self.check()?;
        let (lo, hi) =
            terrain.bounding_box().ok_or_else(|| Error::InvalidInput("the terrain has no vertices".into()))?;
        let params = self.params((hi - lo).truncate().max_element());
        let floor = water_floor(terrain, &params)?;
        let vertices = floor.point_count() * self.frames;
        if vertices > Self::MAX_VERTICES {
            return Err(Error::InvalidInput(format!(
                "water: {} frames of {} vertices exceed {} vertices: lower --cells or --frames",
                self.frames,
                floor.point_count(),
                Self::MAX_VERTICES
            )));
        }
        let frames = (0..self.frames).map(|k| surface_on(&floor, &params, k as f64 / fps)).collect();
        Ok((params, frames))
    }
}

/// Colours of shallow and deep water.
const SHALLOW: [f64; 3] = [70.0, 170.0, 175.0];
const DEEP: [f64; 3] = [18.0, 55.0, 120.0];

/// The water surface at time `t` over `terrain`'s xy extent: positions at sea level plus
/// the waves, the scalar `depth` (sea level minus the floor, 0 on land, the deepest depth
/// where no face lies), colours from shallow to deep.
///
/// # Errors
/// [`Error::InvalidInput`] for a terrain without faces or extent, cells outside 1..=4096,
/// or non-finite or non-positive parameters.
pub fn water_surface(terrain: &Mesh, params: &WaterParams, t: f64) -> Result<Mesh> {
    let floor = water_floor(terrain, params)?;
    Ok(surface_on(&floor, params, t))
}

/// The floor under the water grid of `params` over `terrain`.
///
/// # Errors
/// As [`water_surface`].
pub fn water_floor(terrain: &Mesh, params: &WaterParams) -> Result<Floor> {
    if !(params.level.is_finite() && params.clarity.is_finite() && params.clarity > 0.0) {
        return Err(Error::InvalidInput("water level must be finite and clarity positive".into()));
    }
    if !(1..=4096).contains(&params.cells) {
        return Err(Error::InvalidInput(format!("{} water cells: use 1 to 4096", params.cells)));
    }
    if params.waves.iter().any(|w| !(w.wavelength > 0.0 && w.wavelength.is_finite() && w.amplitude.is_finite())) {
        return Err(Error::InvalidInput("waves need a positive wavelength and a finite amplitude".into()));
    }
    let (lo, hi) = terrain
        .bounding_box()
        .filter(|_| !terrain.triangles.is_empty())
        .ok_or_else(|| Error::InvalidInput("the terrain has no faces to put water over".into()))?;
    let size = (hi - lo).truncate();
    if !(size.x > 0.0 && size.y > 0.0) {
        return Err(Error::InvalidInput("the terrain has no extent in x and y to put water over".into()));
    }
    let cell = size.max_element() / params.cells as f64;
    let (cols, rows) = ((size.x / cell).round().max(1.0) as usize + 1, (size.y / cell).round().max(1.0) as usize + 1);
    Ok(Floor::of(terrain, lo.truncate(), hi.truncate(), cols, rows))
}

/// The water surface at time `t` on a floor grid.
pub fn surface_on(floor: &Floor, params: &WaterParams, t: f64) -> Mesh {
    let rows = floor.heights.len() / floor.cols;
    let deepest = floor.heights.iter().flatten().fold(0.0f64, |d, &h| d.max(params.level - h));
    let mut positions = Vec::with_capacity(floor.heights.len());
    let mut depth = Vec::with_capacity(floor.heights.len());
    for y in 0..rows {
        for x in 0..floor.cols {
            let p = floor.point(x, y);
            let z = params.level + params.waves.iter().map(|w| w.height(p, t)).sum::<f64>();
            positions.push(p.extend(z));
            depth.push(floor.at(x, y).map_or(deepest, |h| (params.level - h).max(0.0)));
        }
    }
    let colors = depth
        .iter()
        .map(|&d| {
            let s = opacity(d, params.clarity);
            [0, 1, 2].map(|k| (SHALLOW[k] + (DEEP[k] - SHALLOW[k]) * s).round() as u8)
        })
        .collect();
    let triangles = crate::terrain::grid_triangles(crate::terrain::Grid::Square, floor.cols, rows).collect();
    let mut mesh = Mesh::new(positions, triangles);
    mesh.colors = Some(colors);
    mesh.scalars.insert("depth".into(), depth);
    mesh
}

/// Opacity of water `depth` deep: 1 − exp(−depth/clarity), from 0.15 at the shore.
pub fn opacity(depth: f64, clarity: f64) -> f64 {
    0.15 + 0.85 * (1.0 - (-depth.max(0.0) / clarity).exp())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A ramp rising along x: z = x − 0.5 over the unit square.
    fn ramp() -> Mesh {
        let mut mesh = crate::mesh::primitives::grid(8);
        for p in &mut mesh.positions {
            p.z = p.x - 0.5;
        }
        mesh
    }

    #[test]
    fn depth_is_the_sea_level_above_the_floor_and_zero_on_land() {
        let params = WaterParams { level: 0.0, cells: 16, waves: Vec::new(), clarity: 0.1 };
        let water = water_surface(&ramp(), &params, 0.0).unwrap();
        let depth = &water.scalars["depth"];
        for (p, &d) in water.positions.iter().zip(depth) {
            assert_eq!(p.z, 0.0, "no waves: flat at sea level");
            assert!((d - (0.5 - p.x).max(0.0)).abs() < 1e-9, "depth {d} at x {}", p.x);
        }
        let report = water.validate();
        assert!(report.is_manifold() && report.boundary_loops == 1);
    }

    #[test]
    fn waves_move_with_time_and_follow_deep_water_dispersion() {
        let wave = Wave { direction: 0.0, wavelength: 2.0, amplitude: 0.1, phase: 0.0 };
        let k = std::f64::consts::TAU / 2.0;
        let period = std::f64::consts::TAU / (GRAVITY * k).sqrt();
        let p = DVec2::new(0.3, 0.7);
        assert!((wave.height(p, 0.0) - wave.height(p, period)).abs() < 1e-12);
        assert!((wave.height(p, 0.0) - wave.height(p, period / 2.0)).abs() > 0.01);
        // A crest travels at the phase velocity ω/k.
        let speed = (GRAVITY / k).sqrt();
        assert!((wave.height(p, 0.0) - wave.height(p + DVec2::X * speed * 0.25, 0.25)).abs() < 1e-12);
        let waves = waves_from_seed(5, 4, 100.0);
        assert_eq!(waves, waves_from_seed(5, 4, 100.0));
        assert!(waves.iter().all(|w| (2.5..=12.5).contains(&w.wavelength)));
    }

    #[test]
    fn shallow_water_is_more_transparent() {
        assert!(opacity(0.0, 1.0) < opacity(0.5, 1.0) && opacity(0.5, 1.0) < opacity(5.0, 1.0));
        assert!((opacity(0.0, 1.0) - 0.15).abs() < 1e-12);
    }
}
