//! A heightfield terrain written to files: the mesh or heightmap, the erosion layers
//! beside it (`t.png` → `t.flow.png`) and, when asked, a sidecar beside each, written
//! after its file (a sidecar means its file is complete). Every file is written atomically.

use std::path::PathBuf;

use super::TerrainSetup;
use super::plan::layer_path;
use super::preview::PreviewSampler;
use super::sidecar::{HeightRange, Sidecar};
use super::stream::{LAYER_RANGE, StreamFormat, write_layer, write_terrain_observed};
use super::{ErosionLayer, Heightfield, Rect};
use crate::error::{Error, Result};
use crate::io::{self, WriteOptions, write_atomically};

/// Where and how a heightfield terrain is written.
#[derive(Debug, Clone)]
pub struct TerrainFiles {
    /// The mesh or heightmap file.
    pub output: PathBuf,
    /// Its encoding.
    pub format: StreamFormat,
    /// A mesh (PLY, OBJ) made whole in memory rather than streamed row by row.
    pub whole_mesh: bool,
    /// Whether a sidecar (OUTPUT.json) goes beside the heightmap and each layer.
    pub sidecar: bool,
    /// Rows per band when streamed in bounded memory; `None`: written whole.
    pub band: Option<usize>,
    /// The plan's fingerprint, recorded in the sidecars of a planned tile.
    pub plan: Option<String>,
}

/// The files [`TerrainFiles::write`] wrote beside the output.
#[derive(Debug, Clone, Default)]
pub struct WrittenTerrain {
    /// The layers' files, in the order asked.
    pub layers: Vec<PathBuf>,
    /// The heightmap's sidecar.
    pub sidecar: Option<PathBuf>,
}

impl TerrainFiles {
    /// Generates `terrain` and writes its files, handing the streamed rows to `preview`
    /// when given.
    ///
    /// # Errors
    /// The generator's errors; I/O errors naming the file.
    pub fn write(&self, terrain: &TerrainSetup, mut preview: Option<&mut PreviewSampler>) -> Result<WrittenTerrain> {
        let (params, rect) = (&terrain.params, terrain.rect);
        if self.whole_mesh {
            let format = if self.format == StreamFormat::Obj { io::Format::Obj } else { io::Format::Ply };
            io::write_as(&super::mesh(params, rect)?, &self.output, format, WriteOptions::default())?;
            return Ok(WrittenTerrain::default());
        }
        let band = self.band.unwrap_or_else(|| rect.height());
        // A file written whole takes its heights and every layer from one erosion run; a
        // streamed one runs it again per file, band by band, in bounded memory.
        let known = match (terrain.layers.is_empty(), self.band) {
            (false, None) => Some(super::heights_and_layers(params, rect, &terrain.layers)?),
            _ => None,
        };
        let mut extremes = HeightRange { min: f64::INFINITY, max: f64::NEG_INFINITY };
        let mut failure = None;
        write_atomically(&self.output, |w| {
            let mut observe = |field: &Heightfield, y0: u64, y1: u64| {
                if let Some(sampler) = preview.as_deref_mut() {
                    sampler.take(field, y0, y1);
                }
                if self.sidecar {
                    widen(&mut extremes, field, rect, y0, y1);
                }
            };
            let known = known.as_ref().map(|(field, _)| field);
            write_terrain_observed(params, rect, known, self.format, terrain.range, band, w, &mut observe)
                .map_err(|e| io_or_kept(e, &mut failure))
        })
        .map_err(|e| failure.take().unwrap_or(e))?;
        let mut written = WrittenTerrain::default();
        for (k, &layer) in terrain.layers.iter().enumerate() {
            let values = known.as_ref().map(|(_, layers)| &layers[k]);
            written.layers.push(self.write_layer_file(terrain, layer, values, band)?);
        }
        if self.sidecar {
            written.sidecar = Some(self.write_sidecar(terrain, &self.output, terrain.range, extremes, None)?);
        }
        Ok(written)
    }

    /// Writes `layer` beside the heightmap (its values on the rectangle when known, else
    /// streamed band by band) and, with the heightmap's, its sidecar; returns its path.
    fn write_layer_file(
        &self,
        terrain: &TerrainSetup,
        layer: ErosionLayer,
        values: Option<&Heightfield>,
        band: usize,
    ) -> Result<PathBuf> {
        let path = layer_path(&self.output, layer);
        let mut extremes = HeightRange { min: f64::INFINITY, max: f64::NEG_INFINITY };
        let rect = terrain.rect;
        let mut failure = None;
        write_atomically(&path, |w| {
            let mut observe = |field: &Heightfield, y0: u64, y1: u64| widen(&mut extremes, field, rect, y0, y1);
            write_layer(&terrain.params, rect, layer, values, self.format, band, w, &mut observe)
                .map_err(|e| io_or_kept(e, &mut failure))
        })
        .map_err(|e| failure.take().unwrap_or(e))?;
        if self.sidecar {
            self.write_sidecar(terrain, &path, LAYER_RANGE, extremes, Some(layer))?;
        }
        Ok(path)
    }

    /// Writes FILE.json beside `file` (the heightmap or a layer, already written).
    fn write_sidecar(
        &self,
        terrain: &TerrainSetup,
        file: &std::path::Path,
        range: (f64, f64),
        extremes: HeightRange,
        layer: Option<ErosionLayer>,
    ) -> Result<PathBuf> {
        let mut sidecar = Sidecar::new(&terrain.params, terrain.rect, self.format, range, extremes);
        sidecar.file = file.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        sidecar.bytes = io::written_size(file)?;
        sidecar.plan = self.plan.clone();
        sidecar.layer = layer.map(|l| l.name().to_string());
        let path = Sidecar::path_for(file);
        let text = serde_json::to_string_pretty(&sidecar).map_err(|e| Error::Internal(e.to_string()))?;
        write_atomically(&path, |w| w.write_all(format!("{text}\n").as_bytes()))?;
        Ok(path)
    }
}

/// Widens `extremes` to the values of rows y0..=y1 of `field` over `rect`'s columns.
fn widen(extremes: &mut HeightRange, field: &Heightfield, rect: Rect, y0: u64, y1: u64) {
    for y in y0..=y1 {
        for x in rect.x0..=rect.x1 {
            let v = field.at(x, y);
            extremes.min = extremes.min.min(v);
            extremes.max = extremes.max.max(v);
        }
    }
}

/// A writer's error as `write_atomically` takes it: an I/O error goes back to it (which
/// names the file); any other keeps its type in `failure` and returns its message.
fn io_or_kept(e: Error, failure: &mut Option<Error>) -> std::io::Error {
    match e {
        Error::Io { source, .. } => source,
        other => {
            let message = other.to_string();
            *failure = Some(other);
            std::io::Error::other(message)
        }
    }
}
