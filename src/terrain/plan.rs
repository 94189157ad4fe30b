//! A terrain cut into tiles that existing job runners run — Kubernetes Indexed Jobs, Slurm
//! job arrays, GNU parallel, `xargs -P` — one process per tile, each given its index: the
//! manifest (`plan.json`: every tile's index, rectangle, file and command, and the
//! [`TerrainRequest`] every tile is made with), the GDAL mosaics of the tiles and, for
//! headerless formats, a VRT per tile. Tiles are computed from the same parameters on
//! their own rectangle (erosion with its halo), so together they equal the whole grid bit
//! for bit. A tile is complete when its sidecar exists and names the plan's fingerprint and
//! the tile's size in bytes ([`tile_complete`]): a rerun of a failed array skips the
//! complete ones.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::mosaic::{MosaicTile, raw_descriptor, source_of, vrt};
use super::sidecar::{Quantisation, Sidecar, WorldPlacement};
use super::stream::{LAYER_RANGE, StreamFormat};
use super::{ErosionLayer, TerrainRequest, TerrainSetup, tiles_per_side};
use crate::error::{Error, Result};
use crate::io::write_atomically;

/// The manifest's layout version.
pub const PLAN_VERSION: u32 = 1;

/// The manifest: everything a tile's process needs, and what the mosaic is made of.
#[derive(Debug, Serialize, Deserialize)]
pub struct Plan {
    /// The manifest's layout version.
    pub version: u32,
    /// A hash of what the tiles are made from (parameters, sizes, format); tiles' sidecars
    /// record it.
    pub fingerprint: String,
    /// Points per side of the whole terrain.
    pub size: u64,
    /// Points per side of a tile.
    pub tile_size: u64,
    /// Tiles per side.
    pub tiles_per_side: u64,
    /// The tiles' file format (extension).
    pub format: String,
    /// The GDAL mosaic, relative to the plan's folder.
    pub mosaic: String,
    /// Each erosion layer's mosaic (`mosaic.LAYER.vrt`), by layer name.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub layer_mosaics: BTreeMap<String, String>,
    /// Every tile, by index.
    pub tiles: Vec<PlannedTile>,
    /// The generation parameters every tile is made with.
    pub parameters: TerrainRequest,
}

/// One tile of the plan.
#[derive(Debug, Serialize, Deserialize)]
pub struct PlannedTile {
    /// Its index: what --tile-index, $JOB_COMPLETION_INDEX or $SLURM_ARRAY_TASK_ID names.
    pub index: u64,
    /// Its column of tiles.
    pub x: u64,
    /// Its row of tiles.
    pub y: u64,
    /// Its rectangle on the grid, inclusive: x0, y0, x1, y1.
    pub rect: [u64; 4],
    /// Its file, relative to the plan's folder.
    pub output: String,
    /// The command that makes it.
    pub command: Vec<String>,
}

/// The fingerprint of what a plan's tiles are made from.
fn plan_fingerprint(parameters: &TerrainRequest, size: u64, tile_size: u64, format: &str) -> Result<String> {
    let text =
        serde_json::to_string(&(parameters, size, tile_size, format)).map_err(|e| Error::Internal(e.to_string()))?;
    Ok(crate::io::manifest::fingerprint(&format!("asperity terrain plan v{PLAN_VERSION} {text}")))
}

/// Tile (x, y)'s file in the plan's folder: `tiles/terrain_x{x}_y{y}.{format}`, the
/// presets' tile naming.
fn tile_output(x: u64, y: u64, format: &str) -> String {
    super::presets::tile_path(Path::new(&format!("tiles/terrain.{format}")), x, y).to_string_lossy().into_owned()
}

/// The file of `layer` beside the heightmap `output`: its name with `.LAYER` before the
/// extension (`terrain.png` → `terrain.flow.png`).
pub fn layer_path(output: &Path, layer: ErosionLayer) -> PathBuf {
    let stem = output.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let name = match output.extension() {
        Some(ext) => format!("{stem}.{}.{}", layer.name(), ext.to_string_lossy()),
        None => format!("{stem}.{}", layer.name()),
    };
    output.with_file_name(name)
}

/// The mosaic of `layer`'s tiles, in the plan's folder: `mosaic.LAYER.vrt`.
fn layer_mosaic(layer: ErosionLayer) -> String {
    format!("mosaic.{}.vrt", layer.name())
}

/// For headerless tiles (RAW16, F32): each tile's descriptor beside it in `dir`, which
/// the mosaic names ([`source_of`]).
fn write_raw_descriptors(dir: &Path, tiles: &[MosaicTile], format: StreamFormat) -> Result<()> {
    if !matches!(format, StreamFormat::Raw16 | StreamFormat::F32) {
        return Ok(());
    }
    for t in tiles {
        let name = Path::new(&t.file).file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        write_text(&dir.join(source_of(&t.file, format)), &raw_descriptor(&name, t.columns, t.rows, format))?;
    }
    Ok(())
}

fn write_text(path: &Path, text: &str) -> Result<()> {
    write_atomically(path, |w| w.write_all(text.as_bytes()))
}

impl Plan {
    /// The plan of `parameters`' terrain in tiles of `tile_size` points a side as `format`
    /// files, `setup` the terrain's (its first tile's: the checks each tile's process will
    /// make), in the folder `dir`, whose name each tile's command carries.
    ///
    /// # Errors
    /// Tiles that do not cover the terrain exactly.
    pub fn new(
        parameters: &TerrainRequest,
        setup: &TerrainSetup,
        tile_size: u64,
        format: &str,
        dir: &Path,
    ) -> Result<Plan> {
        let tiles = tiles_per_side(setup.extent, tile_size)?;
        let dir_text = dir.to_string_lossy().into_owned();
        let span = tile_size - 1;
        let planned = (0..tiles * tiles)
            .map(|index| {
                let (x, y) = (index % tiles, index / tiles);
                PlannedTile {
                    index,
                    x,
                    y,
                    rect: [x * span, y * span, (x + 1) * span, (y + 1) * span],
                    output: tile_output(x, y, format),
                    command: ["asperity", "terrain", "--plan", &dir_text, "--tile-index", &index.to_string()]
                        .map(String::from)
                        .to_vec(),
                }
            })
            .collect();
        let layer_mosaics = setup.layers.iter().map(|&l| (l.name().to_string(), layer_mosaic(l))).collect();
        Ok(Plan {
            version: PLAN_VERSION,
            fingerprint: plan_fingerprint(parameters, setup.extent, tile_size, format)?,
            size: setup.extent,
            tile_size,
            tiles_per_side: tiles,
            format: format.to_string(),
            mosaic: "mosaic.vrt".into(),
            layer_mosaics,
            tiles: planned,
            parameters: parameters.clone(),
        })
    }

    /// Writes the plan into `dir`: the headerless tiles' descriptors, the mosaic of the
    /// heights and one per erosion layer (`setup` gives the world placement and the
    /// heights' 16-bit range), then the manifest; returns the manifest's path.
    ///
    /// # Errors
    /// A file that cannot be written; a format that is not a heightmap's.
    pub fn write(&self, dir: &Path, setup: &TerrainSetup) -> Result<PathBuf> {
        let format = StreamFormat::from_extension(&self.format)
            .filter(|f| f.is_heightmap())
            .ok_or_else(|| Error::InvalidInput(format!("a plan's tiles are heightmaps, not .{}", self.format)))?;
        crate::io::create_output_dir(&dir.join("tiles"))?;
        let world = WorldPlacement::of(&setup.params, 0, 0);
        let side = self.tile_size as usize;
        let heights: Vec<MosaicTile> = self
            .tiles
            .iter()
            .map(|t| MosaicTile { file: t.output.clone(), x: t.rect[0], y: t.rect[1], columns: side, rows: side })
            .collect();
        let mosaics = std::iter::once((None, self.mosaic.clone()))
            .chain(setup.layers.iter().map(|&l| (Some(l), layer_mosaic(l))));
        for (layer, name) in mosaics {
            let tiles: Vec<MosaicTile> = match layer {
                None => heights.clone(),
                Some(layer) => heights
                    .iter()
                    .map(|t| MosaicTile {
                        file: layer_path(Path::new(&t.file), layer).to_string_lossy().into_owned(),
                        ..t.clone()
                    })
                    .collect(),
            };
            write_raw_descriptors(dir, &tiles, format)?;
            let range = if layer.is_some() { LAYER_RANGE } else { setup.range };
            let quantisation = format.is_16_bit().then(|| Quantisation::of(range));
            write_text(&dir.join(&name), &vrt(self.size, self.size, format, quantisation, world, &tiles))?;
        }
        let text = serde_json::to_string_pretty(self).map_err(|e| Error::Internal(e.to_string()))?;
        let manifest = dir.join("plan.json");
        write_text(&manifest, &text)?;
        Ok(manifest)
    }

    /// The plan in `dir`, read from its manifest.
    ///
    /// # Errors
    /// No manifest, not a plan, or a plan of another layout version.
    pub fn read(dir: &Path) -> Result<Plan> {
        crate::io::manifest::read_plan(dir, "terrain", PLAN_VERSION, |p: &Plan| p.version)
    }

    /// Tile `index` of the plan read from `dir`, and the fingerprint its sidecar must name:
    /// recomputed from the parameters, not read, so an edited manifest makes new tiles and
    /// never skips stale ones; the tile's file must be the plan's own name for it, so an
    /// edited manifest cannot send a tile outside the plan's folder.
    ///
    /// # Errors
    /// An index outside the plan; a tile whose file is not the plan's name for it.
    pub fn tile(&self, index: u64, dir: &Path) -> Result<(&PlannedTile, String)> {
        let Some(tile) = self.tiles.iter().find(|t| t.index == index) else {
            return Err(Error::InvalidInput(format!(
                "tile index {index} is outside the plan's {} tiles (0..{})",
                self.tiles.len(),
                self.tiles.len().saturating_sub(1)
            )));
        };
        let named = tile_output(tile.x, tile.y, &self.format);
        if tile.output != named {
            return Err(Error::InvalidInput(format!(
                "{}: tile {index}'s output {:?} is not the plan's name for tile {},{} ({named:?}): make the plan again",
                dir.join("plan.json").display(),
                tile.output,
                tile.x,
                tile.y,
            )));
        }
        Ok((tile, plan_fingerprint(&self.parameters, self.size, self.tile_size, &self.format)?))
    }
}

/// Whether the tile at `output` is complete for the plan `fingerprint`: its sidecar names
/// the plan and the tile's size in bytes.
pub fn tile_complete(output: &Path, fingerprint: &str) -> bool {
    let Ok(text) = std::fs::read_to_string(Sidecar::path_for(output)) else { return false };
    let Ok(sidecar) = serde_json::from_str::<Sidecar>(&text) else { return false };
    let size = std::fs::metadata(output).map(|m| m.len()).ok();
    sidecar.plan.as_deref() == Some(fingerprint) && size == Some(sidecar.bytes)
}
