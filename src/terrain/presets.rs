//! Game-engine presets: the heightmap format, sizes and tile names each engine imports.
//!
//! - Unity's terrain imports 16-bit RAW heightmaps (little-endian, "Windows" byte order) of
//!   2ⁿ + 1 points a side, 33 to 4097 (Unity manual, "Terrain settings: Import Raw").
//! - Unreal's landscape imports 16-bit greyscale PNGs; its recommended landscape sizes are
//!   127, 253, 505, 1009, 2017, 4033 and 8129 points a side (Unreal Engine documentation,
//!   "Landscape Technical Guide: Recommended Landscape Sizes"), which are not 2ⁿ + 1: the
//!   terrain is generated on the next 2ⁿ + 1 grid and its first N × N points are written.
//! - Tiles of both are named `{name}_x{X}_y{Y}`: the pattern of Unreal's tiled landscape
//!   import (World Partition); Unity has no tile naming of its own, and gets the same.

use serde::{Deserialize, Serialize};

use super::stream::StreamFormat;
use crate::error::{Error, Result};

/// A game engine whose import rules the output follows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum Preset {
    /// Unity: RAW16 little-endian, 2ⁿ + 1 points a side from 33 to 4097.
    Unity,
    /// Unreal: PNG16, sizes 127, 253, 505, 1009, 2017, 4033, 8129.
    Unreal,
}

/// Unreal's recommended landscape sizes, points a side.
const UNREAL_SIZES: [u64; 7] = [127, 253, 505, 1009, 2017, 4033, 8129];

impl Preset {
    /// The engine's name in messages.
    pub fn engine(self) -> &'static str {
        match self {
            Preset::Unity => "Unity",
            Preset::Unreal => "Unreal",
        }
    }

    /// The heightmap format the engine imports.
    pub fn format(self) -> StreamFormat {
        match self {
            Preset::Unity => StreamFormat::Raw16,
            Preset::Unreal => StreamFormat::Png16,
        }
    }

    /// File extensions the engine's importer expects.
    pub fn extensions(self) -> &'static [&'static str] {
        match self {
            Preset::Unity => &["raw", "r16", "raw16"],
            Preset::Unreal => &["png"],
        }
    }

    /// Every size (points a side) the engine imports, ascending.
    pub fn sizes(self) -> Vec<u64> {
        match self {
            Preset::Unity => (5..=12).map(|n| (1u64 << n) + 1).collect(),
            Preset::Unreal => UNREAL_SIZES.to_vec(),
        }
    }

    /// Checks that the engine imports a heightmap of `side` points a side (`what` names it
    /// in the message: "--size", "--tile-size").
    ///
    /// # Errors
    /// [`Error::InvalidInput`] naming the nearest size the engine imports.
    pub fn check_size(self, side: u64, what: &str) -> Result<()> {
        let sizes = self.sizes();
        if sizes.contains(&side) {
            return Ok(());
        }
        let nearest = sizes.iter().copied().min_by_key(|s| s.abs_diff(side)).unwrap_or(side);
        let list: Vec<String> = sizes.iter().map(u64::to_string).collect();
        Err(Error::InvalidInput(format!(
            "{what} {side}: {} does not import a heightmap of {side} points a side (it takes {}); nearest: {nearest}",
            self.engine(),
            list.join(", ")
        )))
    }

    /// The 2ⁿ + 1 generation grid whose first `side` points a side are written.
    pub fn generation_size(side: u64) -> u64 {
        (side.max(2) - 1).next_power_of_two() + 1
    }
}

/// The name of tile (i, j) made from a base path: `dir/name.ext` → `dir/name_x{i}_y{j}.ext`.
pub fn tile_path(base: &std::path::Path, i: u64, j: u64) -> std::path::PathBuf {
    let stem = base.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let name = match base.extension() {
        Some(ext) => format!("{stem}_x{i}_y{j}.{}", ext.to_string_lossy()),
        None => format!("{stem}_x{i}_y{j}"),
    };
    base.with_file_name(name)
}
