//! The JSON sidecar written beside a heightmap: where its points lie in the world and what
//! its values mean, so a 16-bit file maps back to world heights exactly and a tile finds
//! its place in the mosaic.

use serde::{Deserialize, Serialize};

use super::stream::StreamFormat;
use super::{Grid, Rect, TerrainParams};

/// What one heightmap file holds.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Sidecar {
    /// The heightmap's file name.
    pub file: String,
    /// Its size in bytes (a rerun of a plan checks it before skipping the tile).
    pub bytes: u64,
    /// Its format: png16, raw16, f32, exr32 or tiff32.
    pub format: String,
    /// Points per row.
    pub columns: usize,
    /// Rows.
    pub rows: usize,
    /// The file's rectangle on the generation grid (inclusive grid indices) and that
    /// grid's points per side.
    pub grid: GridPlacement,
    /// World coordinates of the first point and the spacing between points.
    pub world: WorldPlacement,
    /// The lowest and highest height in the file, world units (before 16-bit quantisation).
    pub heights: HeightRange,
    /// For 16-bit files: world height = `offset + value × scale`, value in 0..=65535.
    pub encoding: Option<Quantisation>,
    /// Byte order of headerless files (raw16, f32).
    pub byte_order: Option<String>,
    /// The fingerprint of the plan this file belongs to.
    pub plan: Option<String>,
    /// For an erosion layer (flow, sediment, water, wetness) written beside the heights:
    /// its name. Its values are masks in [0, 1] (`heights` then holds the file's lowest
    /// and highest value).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub layer: Option<String>,
}

/// The file's place on the generation grid.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GridPlacement {
    /// Points per side of the generation grid.
    pub size: u64,
    /// First column.
    pub x0: u64,
    /// First row.
    pub y0: u64,
    /// Last column.
    pub x1: u64,
    /// Last row.
    pub y1: u64,
    /// square, or triangle (rows shifted by half a step per row).
    pub lattice: String,
}

/// The file's place in the world.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WorldPlacement {
    /// x of the first point.
    pub x: f64,
    /// y of the first point.
    pub y: f64,
    /// Distance between neighbouring points of a row.
    pub spacing_x: f64,
    /// Distance between neighbouring rows.
    pub spacing_y: f64,
}

impl WorldPlacement {
    /// Grid point (x, y)'s world position and the grid's spacing along rows and between
    /// rows (on a triangular lattice, rows are √3/2 of a step apart).
    pub fn of(params: &TerrainParams, x: u64, y: u64) -> Self {
        let origin = params.position(x, y, 0.0);
        let zero = params.position(0, 0, 0.0);
        WorldPlacement {
            x: origin.x,
            y: origin.y,
            spacing_x: params.position(1, 0, 0.0).x - zero.x,
            spacing_y: params.position(0, 1, 0.0).y - zero.y,
        }
    }
}

/// A range of heights.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct HeightRange {
    /// Lowest.
    pub min: f64,
    /// Highest.
    pub max: f64,
}

/// How 16-bit values map to heights.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Quantisation {
    /// The height of value 0.
    pub offset: f64,
    /// The height step of one unit: (hi − lo) / 65535.
    pub scale: f64,
    /// The height of value 0 (= offset).
    pub lo: f64,
    /// The height of value 65535.
    pub hi: f64,
}

impl Quantisation {
    /// The mapping of `range` onto 0..=65535.
    pub fn of(range: (f64, f64)) -> Self {
        Quantisation { offset: range.0, scale: (range.1 - range.0) / 65535.0, lo: range.0, hi: range.1 }
    }
}

impl Sidecar {
    /// The sidecar of the heightmap of `rect` written as `format`, heights between
    /// `heights.min` and `heights.max`.
    pub fn new(
        params: &TerrainParams,
        rect: Rect,
        format: StreamFormat,
        range: (f64, f64),
        heights: HeightRange,
    ) -> Self {
        let triangle = params.grid != Grid::Square;
        Sidecar {
            file: String::new(),
            bytes: 0,
            format: format.name().into(),
            columns: rect.width(),
            rows: rect.height(),
            grid: GridPlacement {
                size: params.size,
                x0: rect.x0,
                y0: rect.y0,
                x1: rect.x1,
                y1: rect.y1,
                lattice: if triangle { "triangle" } else { "square" }.into(),
            },
            world: WorldPlacement::of(params, rect.x0, rect.y0),
            heights,
            encoding: format.is_16_bit().then(|| Quantisation::of(range)),
            byte_order: matches!(format, StreamFormat::Raw16 | StreamFormat::F32).then(|| "little-endian".into()),
            layer: None,
            plan: None,
        }
    }

    /// The sidecar's path for a heightmap: the heightmap's path with `.json` appended.
    pub fn path_for(heightmap: &std::path::Path) -> std::path::PathBuf {
        let mut name = heightmap.as_os_str().to_owned();
        name.push(".json");
        name.into()
    }
}
