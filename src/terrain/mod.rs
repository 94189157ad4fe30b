//! Fractal terrain (seeds 000–003): the classic diamond-square generator on any region of
//! a (2ⁿ + 1)² grid, sea level, colour ramp, normals by central differences, meshes, tiles
//! and streaming in bounded memory. Heights are a pure function of (seed, level, grid
//! point), so a tile or a streamed band equals the matching part of the whole grid.

mod clouds;
mod diamond_square;
pub mod drainage;
mod dual;
pub mod erosion;
pub mod files;
pub mod hydraulic;
pub mod mosaic;
pub mod plan;
pub mod presets;
pub mod preview;
mod random;
mod request;
pub mod sidecar;
pub mod stream;
mod whole_file;

use glam::DVec3;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

pub use clouds::{CloudParams, CloudRequest, clouds};
pub use diamond_square::{DiamondSquare, Lattice, Rect, Rule};
pub use dual::{DualParams, QuadSurface, dual_midpoint_displacement};
pub use erosion::ThermalErosion;
pub use hydraulic::{ErosionLayers, HydraulicBudget, HydraulicErosion};
pub use presets::Preset;
pub use random::{Displacements, Distribution};
pub use request::{
    ErosionModel, TerrainLayout, TerrainMethod, TerrainOutput, TerrainRequest, TerrainSetup, TerrainTarget, TerrainTile,
    dual_mesh,
};

use crate::error::{Error, Result};
use crate::mesh::{Mesh, Rgb};

/// Terrain generators.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// Midpoint displacement / diamond-square (Fournier, Fussell & Carpenter; seed 001).
    #[default]
    Classic,
    /// Seed 002: new points uniform within their parents' range, then a 3×3 Gaussian
    /// filter applied twice; colours blended through a logistic function.
    Smooth,
}

/// Grid types (seed 001).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum Grid {
    /// Square cells, two triangles each.
    #[default]
    Square,
    /// A triangular lattice: every triangle split into four per level.
    Triangle,
    /// The triangular lattice on a hexagonal tile (the hexagon inscribed in the lattice's
    /// rhombus).
    Hex,
}

/// The largest height a terrain may reach ([`crate::mesh::MAX_COORDINATE`]).
pub const MAX_HEIGHT: f64 = crate::mesh::MAX_COORDINATE;

/// Parameters of a terrain.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TerrainParams {
    /// Generator.
    pub method: Method,
    /// Grid type. Triangle and hex grids use the lattice spacing width/(size − 1) on both
    /// axes: rows are √3/2 of it apart, so `depth` is not used.
    pub grid: Grid,
    /// Points per side, 2ⁿ + 1.
    pub size: u64,
    /// Roughness H (seed 001): the displacement scale is multiplied by 2^(−H) per level.
    pub hurst: f64,
    /// Displacement scale at the first level.
    pub sigma: f64,
    /// Seed.
    pub seed: u64,
    /// Distribution of the displacements.
    pub distribution: Distribution,
    /// Mean of the displacements (before scaling).
    pub mean: f64,
    /// Variance of the displacements (before scaling).
    pub variance: f64,
    /// Corner heights (x0y0, xNy0, x0yN, xNyN) as seed 001's applet sets them: the grid's
    /// four corners are exactly these. `None`: each corner is a random draw around 0.
    pub corners: Option<[f64; 4]>,
    /// Seed 001's applet variant: scale not decreasing, random sign.
    pub applet: bool,
    /// World extent along x.
    pub width: f64,
    /// World extent along y.
    pub depth: f64,
    /// Heights below this are raised to it (the sea plane), when set.
    pub sea_level: Option<f64>,
    /// Every height is multiplied by this before the sea clamp (1 leaves them as
    /// generated); [`TerrainParams::with_max_height`] sets it from seed 001's max height.
    pub height_factor: f64,
    /// Colours of the height ramp.
    pub palette: Palette,
    /// Height (above the sea, or above 0) that gets the peak colour; by default half of
    /// [`TerrainParams::height_scale`].
    pub peak_height: Option<f64>,
    /// Thermal erosion applied to the generated heights (after the height factor, before
    /// the sea clamp), when set.
    #[serde(default)]
    pub erosion: Option<ThermalErosion>,
    /// Hydraulic erosion (virtual pipes, Mei et al. 2007), after the thermal erosion when
    /// both are set, before the sea clamp.
    #[serde(default)]
    pub hydraulic: Option<HydraulicErosion>,
}

/// Colours of the height ramp: the sea (at or below sea level, or 0), then land from low
/// to peak at 0, 45 %, 70 % and 100 % of the peak height.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Palette {
    /// At or below the sea.
    pub sea: Rgb,
    /// Lowland.
    pub low: Rgb,
    /// Upland.
    pub mid: Rgb,
    /// Mountain.
    pub high: Rgb,
    /// Peaks.
    pub peak: Rgb,
}

impl Default for Palette {
    fn default() -> Self {
        Palette {
            sea: [30, 70, 160],
            low: [60, 140, 60],
            mid: [110, 150, 70],
            high: [130, 100, 70],
            peak: [250, 250, 250],
        }
    }
}

impl Default for TerrainParams {
    fn default() -> Self {
        TerrainParams {
            method: Method::Classic,
            grid: Grid::Square,
            size: 257,
            hurst: 0.8,
            sigma: 1.0,
            seed: 0,
            distribution: Distribution::Normal,
            mean: 0.0,
            variance: 1.0,
            corners: None,
            applet: false,
            width: 10.0,
            depth: 10.0,
            sea_level: None,
            height_factor: 1.0,
            palette: Palette::default(),
            peak_height: None,
            erosion: None,
            hydraulic: None,
        }
    }
}

/// The subdivision levels n of a grid of `size` = 2ⁿ + 1 points a side, n from 1 to 31;
/// `None` for any other size.
pub(crate) fn levels_of_size(size: u64) -> Option<u32> {
    let n = size.checked_sub(1).filter(|m| m.is_power_of_two()).map(|m| m.trailing_zeros());
    n.filter(|l| (1..=31).contains(l))
}

impl TerrainParams {
    /// The generator, after checking the parameters.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] when the size is not 2ⁿ + 1 (n from 1 to 31) or a number is
    /// not finite.
    pub fn generator(&self) -> Result<DiamondSquare> {
        let Some(levels) = levels_of_size(self.size) else {
            return Err(Error::InvalidInput(format!(
                "terrain size {} must be 2^n + 1 (3, 5, 9, ... 2147483649)",
                self.size
            )));
        };
        let numbers = [self.hurst, self.sigma, self.mean, self.variance, self.width, self.depth];
        if numbers.iter().chain(self.corners.iter().flatten()).any(|v| !v.is_finite())
            || self.sea_level.is_some_and(|s| !s.is_finite())
            || !self.height_factor.is_finite()
        {
            return Err(Error::InvalidInput("terrain parameters must be finite numbers".into()));
        }
        if self.variance < 0.0 || self.width <= 0.0 || self.depth <= 0.0 {
            return Err(Error::InvalidInput("variance must be ≥ 0 and width, depth > 0".into()));
        }
        if let Some(erosion) = &self.erosion {
            erosion.validate()?;
        }
        if let Some(hydraulic) = &self.hydraulic {
            hydraulic.validate()?;
        }
        self.check_height_bound(levels)?;
        Ok(DiamondSquare {
            lattice: match self.grid {
                Grid::Square => Lattice::Square,
                Grid::Triangle | Grid::Hex => Lattice::Triangle,
            },
            rule: match self.method {
                Method::Classic => Rule::MeanPlusDisplacement,
                Method::Smooth => Rule::UniformInSupport,
            },
            levels,
            hurst: self.hurst,
            sigma: self.sigma,
            corners: self.corners,
            applet: self.applet,
            random: Displacements::new(self.seed, self.distribution, self.mean, self.variance),
        })
    }

    /// Refuses parameters whose heights could pass [`MAX_HEIGHT`] (#36: `--sigma 1e308` ended
    /// in "vertex 1 has a non-finite coordinate", naming no parameter): the corners plus every
    /// level's largest displacement, σ·2^(−H·l)·(|mean| + 40·√variance).
    fn check_height_bound(&self, levels: u32) -> Result<()> {
        let per_level = self.mean.abs() + 40.0 * self.variance.sqrt();
        let sum: f64 = (0..=levels).map(|l| if self.applet { 1.0 } else { (-self.hurst * f64::from(l)).exp2() }).sum();
        let corners = self.corners.iter().flatten().fold(0.0f64, |m, c| m.max(c.abs()));
        let bound = (corners + self.sigma.abs() * sum * per_level) * self.height_factor.abs().max(1.0);
        if bound.is_finite() && bound <= MAX_HEIGHT {
            return Ok(());
        }
        let short = |v: f64| if v != 0.0 && !(1e-4..1e6).contains(&v.abs()) { format!("{v:e}") } else { v.to_string() };
        Err(Error::InvalidInput(format!(
            "terrain heights could reach about {bound:.1e} (sigma {}, mean {}, variance {}, Hurst {} over {levels} levels), beyond {MAX_HEIGHT:.0e}: lower sigma",
            short(self.sigma),
            short(self.mean),
            short(self.variance),
            short(self.hurst)
        )))
    }

    /// The points around a rectangle its erosion reaches (thermal then hydraulic: one
    /// and two points per iteration), which a tile computes with it.
    pub fn erosion_halo(&self) -> u64 {
        self.erosion.map_or(0, |e| e.halo()) + self.hydraulic.map_or(0, |h| h.halo())
    }

    /// A height scale independent of the data (so tiles agree): four times the standard
    /// deviation of the summed displacements, σ·√(Σ 4^(−H·l)).
    pub fn height_scale(&self) -> f64 {
        let levels = (self.size.max(2) - 1).trailing_zeros();
        let sum: f64 =
            (0..=levels).map(|l| if self.applet { 1.0 } else { (-2.0 * self.hurst * f64::from(l)).exp2() }).sum();
        4.0 * self.sigma * (self.variance.max(1e-12) * sum).sqrt() * self.height_factor.abs()
    }

    /// Seed 001's "max height" (the highest peak's height): the same terrain with every
    /// height scaled so that its highest point is `top` exactly. It measures the whole
    /// grid once (so tiles of the result still agree), before any sea clamp or erosion (which
    /// then lowers the peaks).
    ///
    /// # Errors
    /// [`Error::InvalidInput`] when `top` is not positive or no point of the terrain lies
    /// above 0 (nothing to scale to a peak).
    pub fn with_max_height(self, top: f64) -> Result<Self> {
        if !(top.is_finite() && top > 0.0) {
            return Err(Error::InvalidInput(format!("max height {top} must be positive")));
        }
        let raw = TerrainParams { height_factor: 1.0, sea_level: None, erosion: None, hydraulic: None, ..self };
        let last = self.size.saturating_sub(1);
        let peak = heights(&raw, Rect { x0: 0, y0: 0, x1: last, y1: last })?
            .heights
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max);
        if peak.is_nan() || peak <= 0.0 {
            return Err(Error::InvalidInput(format!(
                "no point of this terrain lies above 0 (highest {peak}): there is no peak to scale to max height {top}"
            )));
        }
        Ok(TerrainParams { height_factor: top / peak, ..self })
    }

    /// World position of grid point (x, y) with height h (z up).
    pub fn position(&self, x: u64, y: u64, h: f64) -> DVec3 {
        let last = (self.size - 1) as f64;
        match self.grid {
            Grid::Square => DVec3::new(x as f64 * self.width / last, y as f64 * self.depth / last, h),
            Grid::Triangle | Grid::Hex => {
                let s = self.width / last;
                DVec3::new((x as f64 + 0.5 * y as f64) * s, y as f64 * (0.75f64).sqrt() * s, h)
            }
        }
    }

    /// Whether grid point (x, y) belongs to the terrain's domain (all of it, except for the
    /// hexagonal tile: L/2 ≤ x + y ≤ 3L/2 with L = size − 1).
    pub fn in_domain(&self, x: u64, y: u64) -> bool {
        let l = self.size - 1;
        self.grid != Grid::Hex || (2 * (x + y) >= l && 2 * (x + y) <= 3 * l)
    }

    /// The colour of a height: blue at or below the sea (or 0 without a sea), then green,
    /// brown and white towards [`TerrainParams::height_scale`].
    pub fn color(&self, h: f64) -> Rgb {
        let sea = self.sea_level.unwrap_or(0.0);
        if h <= sea {
            return self.palette.sea;
        }
        let peak = self.peak_height.unwrap_or(self.height_scale() * 0.5).max(1e-12);
        ramp_color(&self.palette, (h - sea) / peak, self.method == Method::Smooth)
    }
}

/// The land colours of `palette` at t ∈ [0, 1] (stops at 0, 0.45, 0.7, 1), blended linearly
/// or, as in seed 002, through a logistic function between stops.
pub fn ramp_color(palette: &Palette, t: f64, logistic: bool) -> Rgb {
    let stops = [(0.0, palette.low), (0.45, palette.mid), (0.7, palette.high), (1.0, palette.peak)];
    let t = t.clamp(0.0, 1.0);
    let k = stops.windows(2).position(|w| t <= w[1].0).unwrap_or(2);
    let ((t0, c0), (t1, c1)) = (stops[k], stops[k + 1]);
    let linear = (t - t0) / (t1 - t0);
    let s = if logistic { 1.0 / (1.0 + (-12.0 * (linear - 0.5)).exp()) } else { linear };
    crate::mesh::blend_rgb(c0, c1, s)
}

/// Heights on a rectangle of the grid, after the sea clamp.
#[derive(Debug, Clone, PartialEq)]
pub struct Heightfield {
    /// The rectangle (grid coordinates).
    pub rect: Rect,
    /// Row-major heights, `rect.width()` per row.
    pub heights: Vec<f64>,
}

impl Heightfield {
    /// Height at grid point (x, y), which must lie in the rectangle.
    pub fn at(&self, x: u64, y: u64) -> f64 {
        self.heights[(y - self.rect.y0) as usize * self.rect.width() + (x - self.rect.x0) as usize]
    }
}

/// The finished heights (erosion and sea clamp applied) on `rect`.
///
/// # Errors
/// [`Error::InvalidInput`] for invalid parameters or a rectangle outside the grid.
pub fn heights(params: &TerrainParams, rect: Rect) -> Result<Heightfield> {
    Ok(finished(params, rect, &[])?.0)
}

/// The finished heights on `rect` and each of `which` layers of the hydraulic erosion
/// (none without hydraulic erosion).
fn finished(params: &TerrainParams, rect: Rect, which: &[ErosionLayer]) -> Result<(Heightfield, Vec<Heightfield>)> {
    let generator = params.generator()?;
    let last = params.size - 1;
    if rect.x0 > rect.x1 || rect.y0 > rect.y1 || rect.x1 > last || rect.y1 > last {
        return Err(Error::InvalidInput(format!("region {rect:?} is outside the {0}x{0} grid", params.size)));
    }
    let halo = params.erosion_halo();
    let mut layers = Vec::new();
    let mut field = if halo > 0 || params.erosion.is_some() || params.hydraulic.is_some() {
        // Erosion's halo: the points whose erosion reaches the rectangle.
        let mut grown = generated_heights(params, &generator, rect.grown(halo, last));
        if let Some(erosion) = &params.erosion {
            erosion::erode(&mut grown, params, erosion);
        }
        match &params.hydraulic {
            Some(hydraulic) if !which.is_empty() => {
                let (_, all) = hydraulic::erode_with_layers(&mut grown, params, hydraulic);
                layers = which.iter().map(|layer| erosion::crop_values(grown.rect, layer.of(&all), rect)).collect();
            }
            Some(hydraulic) => {
                hydraulic::erode(&mut grown, params, hydraulic);
            }
            None => {}
        }
        erosion::crop(&grown, rect)
    } else {
        generated_heights(params, &generator, rect)
    };
    if let Some(sea) = params.sea_level {
        field.heights.par_iter_mut().for_each(|h| *h = h.max(sea));
    }
    Ok((field, layers))
}

/// A layer of hydraulic erosion written beside the heights (see [`ErosionLayers`] for what
/// each holds): a mask in [0, 1].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum ErosionLayer {
    /// Water that ran through each point over the run: rivers and gullies.
    Flow,
    /// Sediment deposited by the run: fans and valley floors.
    Sediment,
    /// Water standing after the run: lakes.
    Water,
    /// Water depth over the run.
    Wetness,
}

impl ErosionLayer {
    /// Every layer, in the order files and reports list them.
    pub const ALL: [ErosionLayer; 4] =
        [ErosionLayer::Flow, ErosionLayer::Sediment, ErosionLayer::Water, ErosionLayer::Wetness];

    /// The layer's name (in file names and on the command line).
    pub fn name(self) -> &'static str {
        match self {
            ErosionLayer::Flow => "flow",
            ErosionLayer::Sediment => "sediment",
            ErosionLayer::Water => "water",
            ErosionLayer::Wetness => "wetness",
        }
    }

    /// The layer named `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|l| l.name() == name)
    }

    fn of(self, layers: &ErosionLayers) -> &[f64] {
        match self {
            ErosionLayer::Flow => &layers.flow,
            ErosionLayer::Sediment => &layers.sediment,
            ErosionLayer::Water => &layers.water,
            ErosionLayer::Wetness => &layers.wetness,
        }
    }
}

/// The finished heights on `rect` and each of `which` layers of its hydraulic erosion, from
/// one run (the heights are [`heights`]' bit for bit; layers, like heights, are the whole
/// grid's on any rectangle: tiles and bands agree).
///
/// # Errors
/// [`Error::InvalidInput`] as [`heights`], or when `params` has no hydraulic erosion.
pub fn heights_and_layers(
    params: &TerrainParams,
    rect: Rect,
    which: &[ErosionLayer],
) -> Result<(Heightfield, Vec<Heightfield>)> {
    if params.hydraulic.is_none() {
        return Err(Error::InvalidInput("erosion layers need hydraulic erosion (--erode hydraulic)".into()));
    }
    finished(params, rect, which)
}

/// The generator's heights on `rect` times the height factor, smoothed by seed 002's
/// filter for the smooth method.
fn generated_heights(params: &TerrainParams, generator: &DiamondSquare, rect: Rect) -> Heightfield {
    let last = params.size - 1;
    let mut field = if params.method == Method::Smooth {
        // Two 3×3 Gaussian passes: each height depends on raw heights two points away.
        let grown = rect.grown(2, last);
        let raw = Heightfield { rect: grown, heights: raw_heights(generator, grown) };
        let once = gaussian_3x3(&raw, params.size, rect.grown(1, last));
        gaussian_3x3(&once, params.size, rect)
    } else {
        Heightfield { rect, heights: raw_heights(generator, rect) }
    };
    let factor = params.height_factor;
    if factor != 1.0 {
        field.heights.par_iter_mut().for_each(|h| *h *= factor);
    }
    field
}

/// One pass of the 3×3 Gaussian filter ([1 2 1]ᵀ[1 2 1] / 16) over `rect`, from `field`
/// (which must hold `rect` grown by one point within the grid); at the grid border the
/// weights of the points that exist are renormalised.
fn gaussian_3x3(field: &Heightfield, size: u64, rect: Rect) -> Heightfield {
    let last = size - 1;
    let cols = rect.width();
    let mut heights = vec![0.0; cols * rect.height()];
    heights.par_chunks_mut(cols).enumerate().for_each(|(j, row)| {
        let y = rect.y0 + j as u64;
        for (i, value) in row.iter_mut().enumerate() {
            let x = rect.x0 + i as u64;
            let (mut sum, mut weight) = (0.0, 0.0);
            for (dy, wy) in [(-1i64, 1.0), (0, 2.0), (1, 1.0)] {
                for (dx, wx) in [(-1i64, 1.0), (0, 2.0), (1, 1.0)] {
                    let (nx, ny) = (x as i64 + dx, y as i64 + dy);
                    if nx < 0 || ny < 0 || nx as u64 > last || ny as u64 > last {
                        continue;
                    }
                    sum += wx * wy * field.at(nx as u64, ny as u64);
                    weight += wx * wy;
                }
            }
            *value = sum / weight;
        }
    });
    Heightfield { rect, heights }
}

/// The generator's heights on `rect`.
fn raw_heights(generator: &DiamondSquare, rect: Rect) -> Vec<f64> {
    // Tall regions are cut into bands computed in parallel: every band equals the matching
    // rows of the whole, and bands stay cache-sized (one huge level buffer is slower).
    const BAND: usize = 256;
    let cols = rect.width();
    if rect.height() > 2 * BAND {
        let mut values = vec![0.0; cols * rect.height()];
        values.par_chunks_mut(cols * BAND).enumerate().for_each(|(b, chunk)| {
            let y0 = rect.y0 + (b * BAND) as u64;
            let band = Rect { y0, y1: y0 + (chunk.len() / cols) as u64 - 1, ..rect };
            generator.heights_into(band, chunk);
        });
        values
    } else {
        // At the finest level (spacing 1) the generator's region is exactly `rect`.
        generator.heights(rect)
    }
}

/// The whole grid.
///
/// # Errors
/// As [`heights`].
pub fn whole(params: &TerrainParams) -> Result<Heightfield> {
    let last = params.size.saturating_sub(1);
    heights(params, Rect { x0: 0, y0: 0, x1: last, y1: last })
}

/// The rectangle of tile (i, j) with `tile_size` = 2ᵏ + 1 points per side: neighbouring
/// tiles share their border row or column.
///
/// # Errors
/// [`Error::InvalidInput`] when the tile size does not divide the grid or the tile is outside it.
pub fn tile_rect(params: &TerrainParams, i: u64, j: u64, tile_size: u64) -> Result<Rect> {
    tile_rect_in(params.size, i, j, tile_size)
}

/// The rectangle of tile (i, j) of `tile_size` points per side cut from the first
/// `extent` × `extent` points of the grid (a preset's window of a larger grid).
///
/// # Errors
/// As [`tile_rect`].
pub fn tile_rect_in(extent: u64, i: u64, j: u64, tile_size: u64) -> Result<Rect> {
    let tiles = tiles_per_side(extent, tile_size)?;
    if i >= tiles || j >= tiles {
        return Err(Error::InvalidInput(format!("tile {i},{j} is outside the {tiles}x{tiles} tiles")));
    }
    let span = tile_size - 1;
    Ok(Rect { x0: i * span, y0: j * span, x1: (i + 1) * span, y1: (j + 1) * span })
}

/// How many tiles of `tile_size` points (sharing borders) cover `extent` points a side.
///
/// # Errors
/// [`Error::InvalidInput`] when the tiles do not cover it exactly.
pub fn tiles_per_side(extent: u64, tile_size: u64) -> Result<u64> {
    let span = tile_size.saturating_sub(1);
    let last = extent.saturating_sub(1);
    if span == 0 {
        return Err(Error::InvalidInput(format!("tile size {tile_size} must be at least 2 points")));
    }
    if !last.is_multiple_of(span) {
        // Name the sizes that do fit (#36: the message named only the arithmetic).
        let below = last / span * span + 1;
        let above = below + span;
        let sizes = if below > 1 { format!("sizes {below} or {above}") } else { format!("size {above}") };
        return Err(Error::InvalidInput(format!(
            "tiles of {tile_size} points do not cover a grid of {extent} exactly (k tiles cover k·{span} + 1 points): nearest {sizes}"
        )));
    }
    Ok(last / span)
}

/// Unit normal at grid point (x, y) from heights known on `field` (which must hold the
/// point's neighbours inside the grid): central differences (one-sided on the border) on
/// square grids; on triangular lattices the area-weighted normal of the fan of its six
/// lattice neighbours.
pub fn normal_at(params: &TerrainParams, field: &Heightfield, x: u64, y: u64) -> DVec3 {
    let last = params.size - 1;
    if params.grid != Grid::Square {
        const RING: [(i64, i64); 6] = [(1, 0), (0, 1), (-1, 1), (-1, 0), (0, -1), (1, -1)];
        let centre = params.position(x, y, field.at(x, y));
        let neighbour = |(dx, dy): (i64, i64)| {
            let (nx, ny) = (x as i64 + dx, y as i64 + dy);
            (nx >= 0 && ny >= 0 && nx as u64 <= last && ny as u64 <= last)
                .then(|| params.position(nx as u64, ny as u64, field.at(nx as u64, ny as u64)) - centre)
        };
        let mut sum = DVec3::ZERO;
        for k in 0..6 {
            if let (Some(a), Some(b)) = (neighbour(RING[k]), neighbour(RING[(k + 1) % 6])) {
                sum += a.cross(b);
            }
        }
        return sum.normalize_or_zero();
    }
    let (xa, xb) = (x.saturating_sub(1), (x + 1).min(last));
    let (ya, yb) = (y.saturating_sub(1), (y + 1).min(last));
    let dx = params.width / last as f64 * (xb - xa) as f64;
    let dy = params.depth / last as f64 * (yb - ya) as f64;
    let gx = (field.at(xb, y) - field.at(xa, y)) / dx;
    let gy = (field.at(x, yb) - field.at(x, ya)) / dy;
    DVec3::new(-gx, -gy, 1.0).normalize()
}

/// Triangles of a `cols`×`rows` vertex grid (two per cell, row by row), vertex (i, j) at
/// index j·cols + i. Square grids cut each cell along (i, j)–(i + 1, j + 1); triangular
/// lattices along their third lattice direction, (i + 1, j)–(i, j + 1).
pub fn grid_triangles(grid: Grid, cols: usize, rows: usize) -> impl Iterator<Item = [u32; 3]> {
    (0..rows.saturating_sub(1)).flat_map(move |j| {
        (0..cols.saturating_sub(1)).flat_map(move |i| {
            let a = (j * cols + i) as u32;
            let (b, c, d) = (a + 1, a + 1 + cols as u32, a + cols as u32);
            if grid == Grid::Square { [[a, b, c], [a, c, d]] } else { [[a, b, d], [b, c, d]] }
        })
    })
}

/// The mesh of `rect` (a whole grid or a tile): positions, normals, colours.
///
/// # Errors
/// As [`heights`]; [`Error::InvalidInput`] when the rectangle has 2³² vertices or more.
pub fn mesh(params: &TerrainParams, rect: Rect) -> Result<Mesh> {
    let (cols, rows) = (rect.width(), rect.height());
    if cols.checked_mul(rows).is_none_or(|n| n > u32::MAX as usize) {
        return Err(Error::InvalidInput(format!("{cols}x{rows} vertices exceed 32-bit indices: use tiles")));
    }
    let last = params.size - 1;
    let grown = rect.grown(1, last);
    let field = heights(params, grown)?;
    let points: Vec<(u64, u64)> = (rect.y0..=rect.y1).flat_map(|y| (rect.x0..=rect.x1).map(move |x| (x, y))).collect();
    let positions = points.par_iter().map(|&(x, y)| params.position(x, y, field.at(x, y))).collect();
    let normals = points.par_iter().map(|&(x, y)| normal_at(params, &field, x, y)).collect();
    let colors = points.par_iter().map(|&(x, y)| params.color(field.at(x, y))).collect();
    let mut mesh = Mesh::new(positions, grid_triangles(params.grid, cols, rows).collect());
    mesh.normals = Some(normals);
    mesh.colors = Some(colors);
    if params.grid == Grid::Hex {
        keep_domain(&mut mesh, params, &points);
    }
    Ok(mesh)
}

/// Drops the triangles with a vertex outside the domain, then the vertices no triangle uses.
fn keep_domain(mesh: &mut Mesh, params: &TerrainParams, points: &[(u64, u64)]) {
    let inside: Vec<bool> = points.iter().map(|&(x, y)| params.in_domain(x, y)).collect();
    mesh.triangles.retain(|t| t.iter().all(|&v| inside[v as usize]));
    let mut used = vec![false; points.len()];
    for t in &mesh.triangles {
        for &v in t {
            used[v as usize] = true;
        }
    }
    let mut remap = vec![u32::MAX; points.len()];
    let mut next = 0;
    for (v, &u) in used.iter().enumerate() {
        if u {
            remap[v] = next;
            next += 1;
        }
    }
    keep_used(&mut mesh.positions, &used);
    if let Some(n) = &mut mesh.normals {
        keep_used(n, &used);
    }
    if let Some(c) = &mut mesh.colors {
        keep_used(c, &used);
    }
    for t in &mut mesh.triangles {
        *t = t.map(|v| remap[v as usize]);
    }
}

fn keep_used<T>(values: &mut Vec<T>, used: &[bool]) {
    let mut k = 0;
    values.retain(|_| {
        k += 1;
        used[k - 1]
    });
}
