//! The terrain request (#38): every parameter that says which terrain is made, as the
//! command line's `asperity terrain` flags, Python's `asperity.terrain` keywords and C++'s
//! `TerrainOptions` give it, with the rules all three print: a parameter of one mode is
//! refused in another, naming the mode it belongs to ([`TerrainRequest::check_modes`]), and
//! the sizes, tiles, presets, erosion and memory are checked before anything is generated
//! ([`TerrainRequest::layout`], [`TerrainLayout::ready`]). A plan (`asperity terrain plan`)
//! stores the request and replays it for each tile.

use serde::{Deserialize, Serialize};

use super::{
    Distribution, DualParams, ErosionLayer, Grid, Heightfield, HydraulicErosion, Method, Palette, Preset, QuadSurface,
    Rect, TerrainParams, ThermalErosion, dual_midpoint_displacement, ramp_color, tile_rect_in,
};
use crate::error::{Error, Result};
use crate::mesh::Mesh;
use crate::request::Spelling;

/// Generators.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum TerrainMethod {
    /// Midpoint displacement / diamond-square (seed 001).
    #[default]
    Classic,
    /// Seed 002: uniform within the parents' range, Gaussian-smoothed.
    Smooth,
    /// Janeczek's dual midpoint displacement over a 3D quadrilateral (seed 000).
    Dual,
}

impl TerrainMethod {
    /// The method's name, as every front end writes it.
    pub fn name(self) -> &'static str {
        match self {
            TerrainMethod::Classic => "classic",
            TerrainMethod::Smooth => "smooth",
            TerrainMethod::Dual => "dual",
        }
    }
}

/// Erosion models.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum ErosionModel {
    /// Talus-angle thermal erosion (Musgrave et al. 1989): material slides downhill
    /// wherever the slope exceeds the talus angle; tiles equal the whole grid.
    Thermal,
    /// Hydraulic erosion by virtual pipes (Mei et al. 2007): rain, flow, dissolving,
    /// transport and deposition of sediment, evaporation; tiles equal the whole grid.
    Hydraulic,
}

/// A list of names as a request reads it: a list, one name, comma-separated text
/// (`"thermal,hydraulic"`, as the flag takes it), or null (none). Plans written before
/// hydraulic erosion stored one erosion model or null. A wrong name is named in the message.
fn name_list<'de, D, T>(d: D) -> std::result::Result<Vec<T>, D::Error>
where
    D: serde::Deserializer<'de>,
    T: serde::de::DeserializeOwned,
{
    let name = |text: &str| {
        serde_json::from_value::<T>(serde_json::Value::String(text.trim().to_string()))
            .map_err(serde::de::Error::custom)
    };
    match serde_json::Value::deserialize(d)? {
        serde_json::Value::Null => Ok(Vec::new()),
        serde_json::Value::String(text) => text.split(',').map(name).collect(),
        list @ serde_json::Value::Array(_) => serde_json::from_value(list).map_err(serde::de::Error::custom),
        other => Err(serde::de::Error::custom(format!("{other} is not a name, a list of names or text"))),
    }
}

/// The ramp's colours as a request reads them: five `[r, g, b]` (sea, low, mid, high,
/// peak), their named object, or the flag's text `R,G,B;R,G,B;…`; a wrong value is named.
fn palette_of<'de, D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Option<Palette>, D::Error> {
    match serde_json::Value::deserialize(d)? {
        serde_json::Value::Null => Ok(None),
        serde_json::Value::String(text) => {
            crate::request::parse::palette(&text).map(Some).map_err(serde::de::Error::custom)
        }
        colours => serde_json::from_value(colours).map(Some).map_err(serde::de::Error::custom),
    }
}

/// Which terrain is made: every parameter a plan stores and replays for each tile. Unset
/// parameters take the method's defaults; one that does not apply to the method or the
/// output is refused by [`TerrainRequest::check_modes`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
#[cfg_attr(feature = "cli", group(id = "generation", multiple = true))]
pub struct TerrainRequest {
    /// Generator.
    #[cfg_attr(feature = "cli", arg(long, value_enum, default_value_t = TerrainMethod::Classic))]
    pub method: TerrainMethod,
    /// Points per side, 2^n + 1 (classic, smooth; with --preset, a size the engine imports)
    /// [default: 257].
    #[cfg_attr(feature = "cli", arg(long))]
    pub size: Option<u64>,
    /// Seed 001's iterations k: a (2^k + 1)² grid, the same as --size 2^k+1.
    #[cfg_attr(feature = "cli", arg(long, conflicts_with = "size"))]
    pub iterations: Option<u32>,
    /// Roughness H: the displacement scale falls by 2^-H per level (default 0.8; 1.5 for dual).
    #[cfg_attr(feature = "cli", arg(long, allow_negative_numbers = true))]
    pub hurst: Option<f64>,
    /// Seed 001's roughness: the factor by which the perturbations shrink per iteration,
    /// 2^H (2 is --hurst 1).
    #[cfg_attr(feature = "cli", arg(long, conflicts_with = "hurst", allow_negative_numbers = true))]
    pub roughness: Option<f64>,
    /// Displacement scale at the first level (dual: the factor applied to (|x| + |y|)/2).
    #[cfg_attr(feature = "cli", arg(long, default_value_t = 1.0, allow_negative_numbers = true))]
    pub sigma: f64,
    /// Dual: first side of the quadrilateral X,Y,Z [default: 1,0,0].
    #[cfg_attr(feature = "cli", arg(long, value_parser = crate::request::parse::vector, allow_hyphen_values = true))]
    pub x: Option<[f64; 3]>,
    /// Dual: second side of the quadrilateral X,Y,Z [default: 0,1,0].
    #[cfg_attr(feature = "cli", arg(long, value_parser = crate::request::parse::vector, allow_hyphen_values = true))]
    pub y: Option<[f64; 3]>,
    /// Dual: number of divisions n ((2^n + 1)² points) [default: 9].
    #[cfg_attr(feature = "cli", arg(long))]
    pub levels: Option<u32>,
    /// Dual: displace by σ itself instead of a random sample.
    #[cfg_attr(feature = "cli", arg(long))]
    pub deterministic: bool,
    /// Dual: one sample per point along the cross product of its two pairs.
    #[cfg_attr(feature = "cli", arg(long))]
    pub cross_product: bool,
    /// Dual: keep the original points where they are (shows his Fig. 2 artifacts).
    #[cfg_attr(feature = "cli", arg(long))]
    pub no_mean_correction: bool,
    /// Dual: also write each division's surface as DIR/level-NN.ply.
    #[cfg_attr(feature = "cli", arg(long))]
    pub steps: Option<std::path::PathBuf>,
    /// Seed.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = 0))]
    pub seed: u64,
    /// Displacement distribution (classic, smooth's corners) [default: normal].
    #[cfg_attr(feature = "cli", arg(long, value_enum))]
    pub distribution: Option<Distribution>,
    /// Mean of the distribution (classic, smooth's corners) [default: 0].
    #[cfg_attr(feature = "cli", arg(long, allow_hyphen_values = true))]
    pub mean: Option<f64>,
    /// Variance of the distribution (classic, smooth's corners) [default: 1].
    #[cfg_attr(feature = "cli", arg(long, allow_negative_numbers = true))]
    pub variance: Option<f64>,
    /// Corner heights A,B,C,D (x0y0, xNy0, x0yN, xNyN), set exactly as in seed 001's
    /// applet [default: each a random draw around 0].
    #[cfg_attr(feature = "cli", arg(long, value_parser = crate::request::parse::four, allow_hyphen_values = true))]
    pub corners: Option<[f64; 4]>,
    /// Seed 001's applet variant: constant scale, random sign.
    #[cfg_attr(feature = "cli", arg(long))]
    pub applet: bool,
    /// World width (x) (classic, smooth) [default: 10].
    #[cfg_attr(feature = "cli", arg(long, allow_negative_numbers = true))]
    pub width: Option<f64>,
    /// World depth (y) (classic, smooth) [default: 10].
    #[cfg_attr(feature = "cli", arg(long, allow_negative_numbers = true))]
    pub depth: Option<f64>,
    /// Seed 001's max height: the highest peak's height; every height is scaled so the
    /// whole grid's highest point is exactly this (classic, smooth; measured on the whole
    /// grid before erosion, so not with --stream or --tile; exclusive with --sigma and
    /// --corners, which set heights too).
    #[cfg_attr(feature = "cli", arg(long, conflicts_with_all = ["sigma", "corners"], allow_negative_numbers = true))]
    pub max_height: Option<f64>,
    /// Raise everything below this height to it.
    #[cfg_attr(feature = "cli", arg(long, allow_hyphen_values = true))]
    pub sea_level: Option<f64>,
    /// Ramp colours SEA;LOW;MID;HIGH;PEAK, each R,G,B.
    #[cfg_attr(feature = "cli", arg(long, value_parser = crate::request::parse::palette))]
    #[serde(deserialize_with = "palette_of")]
    pub colors: Option<Palette>,
    /// Height above the sea that gets the peak colour (default: half the height scale).
    #[cfg_attr(feature = "cli", arg(long, allow_negative_numbers = true))]
    pub peak_height: Option<f64>,
    /// Grid type (classic, smooth) [default: square].
    #[cfg_attr(feature = "cli", arg(long, value_enum))]
    pub grid: Option<Grid>,
    /// Height range LO,HI mapped to 16 bits (.png, .raw16); default ± the height scale.
    #[cfg_attr(feature = "cli", arg(long, value_parser = crate::request::parse::range, allow_hyphen_values = true))]
    pub range: Option<(f64, f64)>,
    /// Erode the generated heights (classic, smooth): thermal, hydraulic, or
    /// thermal,hydraulic (in that order); identical in tiles, which are computed with a halo
    /// of one point per thermal and two per hydraulic iteration.
    #[cfg_attr(feature = "cli", arg(long, value_enum, value_delimiter = ','))]
    #[serde(deserialize_with = "name_list")]
    pub erode: Vec<ErosionModel>,
    /// Erosion iterations, of each erosion (with --erode) [default: 50].
    #[cfg_attr(feature = "cli", arg(long))]
    pub erode_iterations: Option<u32>,
    /// Talus angle in degrees: the steepest slope erosion leaves in place (with --erode
    /// thermal) [default: 30].
    #[cfg_attr(feature = "cli", arg(long, allow_negative_numbers = true))]
    pub talus: Option<f64>,
    /// Rain Kr: water depth added per unit time, world height units (with --erode
    /// hydraulic) [default: 0.01].
    #[cfg_attr(feature = "cli", arg(long, allow_negative_numbers = true))]
    pub rain: Option<f64>,
    /// Evaporation Ke: share of the water evaporating per unit time, below 1/--time-step
    /// (with --erode hydraulic) [default: 0.5].
    #[cfg_attr(feature = "cli", arg(long, allow_negative_numbers = true))]
    pub evaporation: Option<f64>,
    /// Sediment capacity Kc: sediment the water carries per unit of speed and sin(tilt)
    /// (with --erode hydraulic) [default: 1].
    #[cfg_attr(feature = "cli", arg(long, allow_negative_numbers = true))]
    pub capacity: Option<f64>,
    /// Dissolving rate Ks in (0, 1]: share of the missing capacity dissolved per iteration
    /// (with --erode hydraulic) [default: 0.3].
    #[cfg_attr(feature = "cli", arg(long, allow_negative_numbers = true))]
    pub dissolving: Option<f64>,
    /// Deposition rate Kd in (0, 1]: share of the excess sediment deposited per iteration
    /// (with --erode hydraulic) [default: 0.3].
    #[cfg_attr(feature = "cli", arg(long, allow_negative_numbers = true))]
    pub deposition: Option<f64>,
    /// Time step Δt in (0, 1] (with --erode hydraulic) [default: 0.05].
    #[cfg_attr(feature = "cli", arg(long, allow_negative_numbers = true))]
    pub time_step: Option<f64>,
    /// Also write these layers of the hydraulic erosion beside a heightmap, in its format:
    /// flow, sediment, water, wetness (masks in [0, 1]: water that ran through, deposits,
    /// standing water, water over the run), as OUTPUT's name with .flow, .sediment, .water
    /// or .wetness before the extension (with --erode hydraulic).
    #[cfg_attr(feature = "cli", arg(long, value_enum, value_delimiter = ','))]
    #[serde(deserialize_with = "name_list", skip_serializing_if = "Vec::is_empty")]
    pub layers: Vec<ErosionLayer>,
    /// Write what a game engine imports: unity (RAW16 little-endian, 2^n + 1 from 33 to
    /// 4097 points a side) or unreal (PNG16, 127, 253, 505, 1009, 2017, 4033 or 8129);
    /// tiles named NAME_x{X}_y{Y}; a JSON sidecar with the height mapping.
    #[cfg_attr(feature = "cli", arg(long, value_enum))]
    pub preset: Option<Preset>,
}

impl Default for TerrainRequest {
    fn default() -> Self {
        TerrainRequest {
            method: TerrainMethod::Classic,
            size: None,
            iterations: None,
            hurst: None,
            roughness: None,
            sigma: 1.0,
            x: None,
            y: None,
            levels: None,
            deterministic: false,
            cross_product: false,
            no_mean_correction: false,
            steps: None,
            seed: 0,
            distribution: None,
            mean: None,
            variance: None,
            corners: None,
            applet: false,
            width: None,
            depth: None,
            max_height: None,
            sea_level: None,
            colors: None,
            peak_height: None,
            grid: None,
            range: None,
            erode: Vec::new(),
            erode_iterations: None,
            talus: None,
            rain: None,
            evaporation: None,
            capacity: None,
            dissolving: None,
            deposition: None,
            time_step: None,
            layers: Vec::new(),
            preset: None,
        }
    }
}

/// What a terrain is made as: the output's kind, the tile and how it is written. The rules
/// of [`TerrainRequest::check_modes`] and the memory estimate look at it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct TerrainTarget {
    /// The output's kind.
    pub output: TerrainOutput,
    /// Tile (i, j) only, of `tile_size` points a side.
    pub tile: Option<(u64, u64)>,
    /// Points per tile side, 2^k + 1.
    pub tile_size: Option<u64>,
    /// Rows written as they are generated, `band` at a time.
    pub stream: bool,
    /// Rows per streamed band.
    pub band: Option<usize>,
    /// A coloured picture is made too.
    pub preview: bool,
    /// A sidecar is written beside a heightmap.
    pub sidecar: bool,
}

impl TerrainTarget {
    /// Rows per streamed band for a region `width` points wide: `band`, or as many as
    /// [`super::stream::default_band`] gives; `None` when the terrain is written whole.
    pub fn streamed_band(&self, width: usize) -> Option<usize> {
        self.stream.then(|| self.band.unwrap_or_else(|| super::stream::default_band(width)))
    }
}

/// An output's kind, as far as the rules tell them apart.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TerrainOutput {
    /// A coloured mesh (.ply, .obj).
    Mesh,
    /// A 16-bit heightmap (.png, .raw16): heights mapped through a range.
    Heightmap16,
    /// A float heightmap (.f32, .exr, .tif) or heights in memory.
    #[default]
    Heightmap,
}

impl TerrainOutput {
    /// The kind of an output file with extension `ext` (lower case; another extension is a
    /// float heightmap here and refused by the writer).
    pub fn of_extension(ext: &str) -> Self {
        match ext {
            "ply" | "obj" => TerrainOutput::Mesh,
            "png" | "raw16" | "raw" | "r16" => TerrainOutput::Heightmap16,
            _ => TerrainOutput::Heightmap,
        }
    }
}

/// The tile a front end asks for in memory: tile (i, j) of `tile_size` points a side.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct TerrainTile {
    /// Tile (i, j).
    pub tile: Option<(u64, u64)>,
    /// Points per tile side, 2^k + 1; tiles share their borders.
    pub tile_size: Option<u64>,
}

impl TerrainTile {
    /// The target of a terrain made in memory as `output` on this tile.
    fn target(self, output: TerrainOutput) -> TerrainTarget {
        TerrainTarget { output, tile: self.tile, tile_size: self.tile_size, ..TerrainTarget::default() }
    }
}

/// The fields of a [`TerrainRequest`] that apply to the command line only, which writes
/// files: refused by name from the embeddings rather than ignored.
const FILE_FIELDS: [&str; 9] =
    ["output", "preview", "format", "stream", "band", "sidecar", "plan", "tile_index", "steps"];

/// Pairs of fields of which one may be given (each sets what the other sets).
const EXCLUSIVE: [(&str, &str); 4] =
    [("iterations", "size"), ("roughness", "hurst"), ("max_height", "sigma"), ("max_height", "corners")];

impl TerrainRequest {
    /// The request and the tile from a JSON object of fields (Python's keyword arguments,
    /// C++'s option members): the request's fields and `tile`, `tile_size`, read strictly;
    /// the command line's file fields and a pair that sets the same thing twice are refused,
    /// naming them as `spelling` writes them.
    ///
    /// # Errors
    /// As [`crate::request::from_fields`]; a file field; two exclusive fields.
    pub fn from_fields(json: &str, spelling: Spelling) -> Result<(TerrainRequest, TerrainTile)> {
        let mut fields = crate::request::field_map(json)?;
        // A file field set to false (Python's `stream=False`) leaves it out, as null does.
        let left_out = |name: &str, value: &serde_json::Value| {
            value.is_null() || (FILE_FIELDS.contains(&name) && *value == serde_json::Value::Bool(false))
        };
        fields.retain(|name, value| !left_out(name, value));
        if let Some(name) = FILE_FIELDS.iter().find(|name| fields.contains_key(**name)) {
            return Err(Error::InvalidInput(format!(
                "{} applies to the command line's asperity terrain, which writes files: here it would be ignored",
                spelling.of(name)
            )));
        }
        if let Some((a, b)) = EXCLUSIVE.iter().find(|(a, b)| fields.contains_key(*a) && fields.contains_key(*b)) {
            return Err(Error::InvalidInput(format!(
                "{} and {} set the same thing: give one",
                spelling.of(a),
                spelling.of(b)
            )));
        }
        let mut tile = serde_json::Map::new();
        for name in ["tile", "tile_size"] {
            if let Some(value) = fields.remove(name) {
                tile.insert(name.to_string(), value);
            }
        }
        let tile: TerrainTile = crate::request::from_field_map(tile, spelling, &[], &[])?;
        let request = crate::request::from_field_map(fields, spelling, &["layers", "tile", "tile_size"], &FILE_FIELDS)?;
        Ok((request, tile))
    }

    /// H from `hurst`, or from `roughness` (2^H), or the method's default (0.8; 1.5 for
    /// dual).
    ///
    /// # Errors
    /// A roughness that is not positive.
    pub fn hurst(&self, spelling: Spelling) -> Result<f64> {
        let default = if self.method == TerrainMethod::Dual { 1.5 } else { 0.8 };
        match (self.hurst, self.roughness) {
            (_, Some(r)) if !(r.is_finite() && r > 0.0) => {
                Err(Error::InvalidInput(format!("{} must be positive (it is 2^H)", spelling.with("roughness", r))))
            }
            (_, Some(r)) => Ok(r.log2()),
            (h, None) => Ok(h.unwrap_or(default)),
        }
    }

    /// Every parameter another mode would use is refused where it would be ignored, with
    /// the mode it belongs to in the message: the quadrilateral's with the heightfield
    /// methods, the grid's with dual, `band` without `stream`, `range` without a 16-bit
    /// output, colours without a coloured output.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] naming the first parameter that does not apply.
    pub fn check_modes(&self, target: &TerrainTarget, spelling: Spelling) -> Result<()> {
        let dual = self.method == TerrainMethod::Dual;
        let smooth = self.method == TerrainMethod::Smooth;
        let mesh_output = target.output == TerrainOutput::Mesh;
        let sixteen_bit = target.output == TerrainOutput::Heightmap16;
        let coloured = mesh_output || target.preview;
        let hydraulic = self.erode.contains(&ErosionModel::Hydraulic);
        let thermal = self.erode.contains(&ErosionModel::Thermal);
        let method = |name: &str| spelling.with("method", name);
        let heightfield = format!("{} and smooth", method("classic"));
        let not_smooth =
            format!("{} and dual (smooth's points are uniform within their parents' range)", method("classic"));
        let dual_only = method("dual");
        let hydraulic_only = spelling.with("erode", "hydraulic");
        // Pictures and files are the command line's; the others make meshes in memory.
        let coloured_outputs = match spelling {
            Spelling::Flag => "coloured outputs (a .ply or .obj mesh, or --preview)".to_string(),
            _ => "coloured outputs (a mesh)".to_string(),
        };
        let max_height_only = format!(
            "whole grids of {heightfield} (the highest peak is measured on the whole grid: not with {} or {})",
            spelling.of("stream"),
            spelling.of("tile")
        );
        let applet_only = format!("{} (seed 001's applet)", method("classic"));
        let stream_only = spelling.of("stream");
        let erode_only = spelling.of("erode");
        let thermal_only = spelling.with("erode", "thermal");
        let tile_only = spelling.of("tile");
        let sidecar_only = format!("heightmap outputs (.png, .raw16, .f32, .exr, .tif) of {heightfield}");
        let range_only = format!("16-bit outputs (.png, .raw16) of {heightfield}");
        let peak_only = format!("{coloured_outputs} of {heightfield}");
        let rules: [(&str, bool, bool, &str); 39] = [
            ("iterations", self.iterations.is_some(), !dual, &heightfield),
            (
                "max_height",
                self.max_height.is_some(),
                !dual && !target.stream && target.tile.is_none(),
                &max_height_only,
            ),
            ("roughness", self.roughness.is_some(), !smooth, &not_smooth),
            ("x", self.x.is_some(), dual, &dual_only),
            ("y", self.y.is_some(), dual, &dual_only),
            ("levels", self.levels.is_some(), dual, &dual_only),
            ("deterministic", self.deterministic, dual, &dual_only),
            ("cross_product", self.cross_product, dual, &dual_only),
            ("no_mean_correction", self.no_mean_correction, dual, &dual_only),
            ("steps", self.steps.is_some(), dual, &dual_only),
            ("size", self.size.is_some(), !dual, &heightfield),
            ("distribution", self.distribution.is_some(), !dual, &heightfield),
            ("mean", self.mean.is_some(), !dual, &heightfield),
            ("variance", self.variance.is_some(), !dual, &heightfield),
            ("corners", self.corners.is_some(), !dual, &heightfield),
            ("width", self.width.is_some(), !dual, &heightfield),
            ("depth", self.depth.is_some(), !dual, &heightfield),
            ("sea_level", self.sea_level.is_some(), !dual, &heightfield),
            ("grid", self.grid.is_some(), !dual, &heightfield),
            ("stream", target.stream, !dual, &heightfield),
            ("tile", target.tile.is_some(), !dual, &heightfield),
            ("applet", self.applet, self.method == TerrainMethod::Classic, &applet_only),
            ("hurst", self.hurst.is_some(), !smooth, &not_smooth),
            ("band", target.band.is_some(), target.stream, &stream_only),
            ("erode", !self.erode.is_empty(), !dual, &heightfield),
            ("erode_iterations", self.erode_iterations.is_some(), !self.erode.is_empty(), &erode_only),
            ("talus", self.talus.is_some(), thermal, &thermal_only),
            ("rain", self.rain.is_some(), hydraulic, &hydraulic_only),
            ("evaporation", self.evaporation.is_some(), hydraulic, &hydraulic_only),
            ("capacity", self.capacity.is_some(), hydraulic, &hydraulic_only),
            ("dissolving", self.dissolving.is_some(), hydraulic, &hydraulic_only),
            ("deposition", self.deposition.is_some(), hydraulic, &hydraulic_only),
            ("time_step", self.time_step.is_some(), hydraulic, &hydraulic_only),
            ("layers", !self.layers.is_empty(), hydraulic, &hydraulic_only),
            ("preset", self.preset.is_some(), !dual, &heightfield),
            ("sidecar", target.sidecar, !dual && !mesh_output, &sidecar_only),
            ("tile_size", target.tile_size.is_some(), target.tile.is_some(), &tile_only),
            ("range", self.range.is_some(), !dual && sixteen_bit, &range_only),
            ("peak_height", self.peak_height.is_some(), !dual && coloured, &peak_only),
        ];
        if let Some((field, _, _, belongs)) = rules.iter().find(|(_, given, applies, _)| *given && !applies) {
            return Err(Error::InvalidInput(format!(
                "{} applies only to {belongs}: with {} and this output it would be ignored",
                spelling.of(field),
                method(self.method.name())
            )));
        }
        if self.colors.is_some() && !coloured {
            return Err(Error::InvalidInput(format!("{} applies only to {coloured_outputs}", spelling.of("colors"))));
        }
        if target.tile.is_some() && target.tile_size.is_none() {
            return Err(Error::InvalidInput(format!("{} needs {}", spelling.of("tile"), spelling.of("tile_size"))));
        }
        Ok(())
    }

    /// The grid, region and parameters of a heightfield terrain made as `target`, checked
    /// before anything is generated: the size (or iterations), a preset's sizes, a tile on
    /// the grid, the erosion models and their order, the parameters' ranges.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] naming the first parameter broken; `method` dual.
    pub fn layout(&self, target: &TerrainTarget, spelling: Spelling) -> Result<TerrainLayout> {
        self.check_modes(target, spelling)?;
        if self.method == TerrainMethod::Dual {
            return Err(Error::InvalidInput(format!(
                "{} makes a 3D surface, not a heightfield",
                spelling.with("method", "dual")
            )));
        }
        let method = if self.method == TerrainMethod::Smooth { Method::Smooth } else { Method::Classic };
        let hurst = self.hurst(spelling)?;
        let size = match self.iterations {
            Some(k @ 1..=31) => (1u64 << k) + 1,
            Some(k) => {
                return Err(Error::InvalidInput(format!(
                    "{} must be between 1 and 31",
                    spelling.with("iterations", k)
                )));
            }
            None => self.size.unwrap_or(257),
        };
        if let Some((lo, hi)) = self.range
            && hi.partial_cmp(&lo) != Some(std::cmp::Ordering::Greater)
        {
            return Err(Error::InvalidInput(format!(
                "{}: the range needs LO < HI",
                spelling.with("range", format!("{lo},{hi}"))
            )));
        }
        let grid = self.grid.unwrap_or_default();
        if grid == Grid::Hex && target.tile.is_some() {
            return Err(Error::InvalidInput(format!(
                "a hexagonal tile is one terrain: {} applies to square and triangle grids",
                spelling.of("tile")
            )));
        }
        // A preset's size is what the engine imports; the grid is the next 2^n + 1.
        let (extent, grid_size) = match self.preset {
            Some(preset) => {
                if grid != Grid::Square {
                    return Err(Error::InvalidInput(format!(
                        "{}: game engines import square grids, not {}",
                        spelling.with("preset", preset.engine().to_lowercase()),
                        spelling.with("grid", format!("{grid:?}"))
                    )));
                }
                match (target.tile, target.tile_size) {
                    (Some(_), Some(t)) => preset.check_size(t, &spelling.of("tile_size"))?,
                    _ => preset.check_size(size, &spelling.of("size"))?,
                }
                (size, Preset::generation_size(size))
            }
            None => (size, size),
        };
        // A window of a larger grid keeps the world extent on the window.
        let stretch = (grid_size - 1) as f64 / (extent.max(2) - 1) as f64;
        let params = TerrainParams {
            method,
            grid,
            size: grid_size,
            hurst,
            sigma: self.sigma,
            seed: self.seed,
            distribution: self.distribution.unwrap_or_default(),
            mean: self.mean.unwrap_or(0.0),
            variance: self.variance.unwrap_or(1.0),
            corners: self.corners,
            applet: self.applet,
            width: self.width.unwrap_or(10.0) * stretch,
            depth: self.depth.unwrap_or(10.0) * stretch,
            sea_level: self.sea_level,
            height_factor: 1.0,
            palette: self.colors.unwrap_or_default(),
            peak_height: self.peak_height,
            erosion: None,
            hydraulic: None,
        };
        let params = self.with_erosion(params, spelling)?;
        params.generator()?;
        let rect = match (target.tile, target.tile_size) {
            (Some((i, j)), Some(tile_size)) => tile_rect_in(extent, i, j, tile_size)?,
            _ => Rect { x0: 0, y0: 0, x1: extent - 1, y1: extent - 1 },
        };
        let mut layers: Vec<ErosionLayer> = Vec::new();
        for &layer in &self.layers {
            if !layers.contains(&layer) {
                layers.push(layer);
            }
        }
        Ok(TerrainLayout { params, rect, extent, hurst, layers, max_height: self.max_height, range: self.range })
    }

    /// `params` with the erosions the request asks for.
    fn with_erosion(&self, params: TerrainParams, spelling: Spelling) -> Result<TerrainParams> {
        use ErosionModel::{Hydraulic, Thermal};
        if !matches!(self.erode.as_slice(), [] | [Thermal] | [Hydraulic] | [Thermal, Hydraulic]) {
            return Err(Error::InvalidInput(format!(
                "{} runs thermal, hydraulic or thermal,hydraulic (each once, thermal first)",
                spelling.of("erode")
            )));
        }
        let iterations = self.erode_iterations.unwrap_or(50);
        let erosion = self
            .erode
            .contains(&Thermal)
            .then(|| ThermalErosion { iterations, talus_degrees: self.talus.unwrap_or(30.0) });
        let hydraulic = self.erode.contains(&Hydraulic).then(|| {
            let d = HydraulicErosion::default();
            HydraulicErosion {
                iterations,
                rain: self.rain.unwrap_or(d.rain),
                evaporation: self.evaporation.unwrap_or(d.evaporation),
                capacity: self.capacity.unwrap_or(d.capacity),
                dissolving: self.dissolving.unwrap_or(d.dissolving),
                deposition: self.deposition.unwrap_or(d.deposition),
                time_step: self.time_step.unwrap_or(d.time_step),
            }
        });
        Ok(TerrainParams { erosion, hydraulic, ..params })
    }

    /// The dual method's parameters (the caller has refused other modes' parameters with
    /// [`TerrainRequest::check_modes`]).
    ///
    /// # Errors
    /// A roughness that is not positive.
    pub fn dual_params(&self, spelling: Spelling) -> Result<DualParams> {
        Ok(DualParams {
            x: self.x.unwrap_or([1.0, 0.0, 0.0]).into(),
            y: self.y.unwrap_or([0.0, 1.0, 0.0]).into(),
            hurst: self.hurst(spelling)?,
            levels: self.levels.unwrap_or(9),
            scale: self.sigma,
            seed: self.seed,
            deterministic: self.deterministic,
            cross_product: self.cross_product,
            mean_correction: !self.no_mean_correction,
        })
    }

    /// The heights on `tile` (the whole grid without one), as `asperity terrain` writes
    /// them to `.f32`.
    ///
    /// # Errors
    /// As [`TerrainRequest::layout`] and [`TerrainLayout::ready`]; `layers`, which
    /// [`TerrainRequest::heights_and_layers`] gives.
    pub fn heights(&self, tile: TerrainTile, spelling: Spelling) -> Result<Heightfield> {
        if !self.layers.is_empty() {
            return Err(Error::InvalidInput(format!(
                "{} are made beside the heights: ask for the heights and layers together",
                spelling.of("layers")
            )));
        }
        let target = tile.target(TerrainOutput::Heightmap);
        let setup = self.layout(&target, spelling)?.ready(&target, spelling)?;
        super::heights(&setup.params, setup.rect)
    }

    /// The heights [`TerrainRequest::heights`] gives and the hydraulic erosion's `layers`
    /// (all four when it names none), from one run, each a mask in [0, 1]
    /// ([`super::ErosionLayers`]).
    ///
    /// # Errors
    /// As [`TerrainRequest::heights`]; without hydraulic erosion.
    #[allow(clippy::type_complexity)]
    pub fn heights_and_layers(
        &self,
        tile: TerrainTile,
        spelling: Spelling,
    ) -> Result<(Heightfield, Vec<(ErosionLayer, Heightfield)>)> {
        if self.method != TerrainMethod::Dual && !self.erode.contains(&ErosionModel::Hydraulic) {
            return Err(Error::InvalidInput(format!(
                "erosion layers need hydraulic erosion ({})",
                spelling.with("erode", "hydraulic")
            )));
        }
        let target = tile.target(TerrainOutput::Heightmap);
        let mut layout = self.layout(&target, spelling)?;
        // No layers named: all four, in the memory estimate too.
        if layout.layers.is_empty() {
            layout.layers = ErosionLayer::ALL.to_vec();
        }
        let setup = layout.ready(&target, spelling)?;
        let (heights, fields) = super::heights_and_layers(&setup.params, setup.rect, &setup.layers)?;
        Ok((heights, setup.layers.into_iter().zip(fields).collect()))
    }

    /// The mesh `asperity terrain` writes to `.ply`: a heightfield's on `tile` (positions,
    /// normals, height colours) or the dual method's surface.
    ///
    /// # Errors
    /// As [`TerrainRequest::layout`] and [`TerrainLayout::ready`], or the dual method's.
    pub fn mesh(&self, tile: TerrainTile, spelling: Spelling) -> Result<Mesh> {
        let target = tile.target(TerrainOutput::Mesh);
        if !self.layers.is_empty() {
            return Err(Error::InvalidInput(format!(
                "{} are heightmaps made beside the heights, not a mesh",
                spelling.of("layers")
            )));
        }
        if self.method == TerrainMethod::Dual {
            self.check_modes(&target, spelling)?;
            let params = self.dual_params(spelling)?;
            let surface = dual_midpoint_displacement(&params, |_, _| {})?;
            return Ok(dual_mesh(&surface, &params, &self.colors.unwrap_or_default()));
        }
        let setup = self.layout(&target, spelling)?.ready(&target, spelling)?;
        super::mesh(&setup.params, setup.rect)
    }
}

/// A heightfield terrain's grid, region and parameters, before its memory and height
/// mapping are settled ([`TerrainLayout::ready`]).
#[derive(Debug, Clone)]
pub struct TerrainLayout {
    /// The generator's parameters (without `max_height`'s scaling).
    pub params: TerrainParams,
    /// The region made.
    pub rect: Rect,
    /// Points per side of the region tiles are cut from (the grid, or a preset's window).
    pub extent: u64,
    /// The roughness H used.
    pub hurst: f64,
    /// Erosion layers made beside the heights, each once, in the order asked.
    pub layers: Vec<ErosionLayer>,
    max_height: Option<f64>,
    range: Option<(f64, f64)>,
}

/// A heightfield terrain ready to be generated.
#[derive(Debug, Clone)]
pub struct TerrainSetup {
    /// The generator's parameters (scaled to `max_height` when asked).
    pub params: TerrainParams,
    /// The region made.
    pub rect: Rect,
    /// Points per side of the region tiles are cut from (the grid, or a preset's window).
    pub extent: u64,
    /// The roughness H used.
    pub hurst: f64,
    /// Erosion layers made beside the heights, each once, in the order asked.
    pub layers: Vec<ErosionLayer>,
    /// Heights mapped to 16 bits: `range`, or ± the height scale.
    pub range: (f64, f64),
}

/// Memory a whole-grid mesh takes per grid point: the heights and their coarser levels,
/// positions, normals, colours and two triangles (peak measured at 2049²: 99 bytes).
const MESH_BYTES_PER_POINT: u64 = 112;

/// Memory a heightmap's rows take per point: the heights, the coarser levels that feed them
/// and the encoded output (peak measured at 2049²: 11 bytes; twice that with smoothing).
const HEIGHTS_BYTES_PER_POINT: u64 = 16;

impl TerrainLayout {
    /// Checks that the terrain fits in memory as `target` makes it (refused by estimate
    /// before allocating) and scales it to `max_height` (which measures the whole grid).
    ///
    /// # Errors
    /// Too large for the machine; a `max_height` that is not positive.
    pub fn ready(self, target: &TerrainTarget, spelling: Spelling) -> Result<TerrainSetup> {
        let TerrainLayout { params, rect, extent, hurst, layers, max_height, range } = self;
        let whole_mesh = target.output == TerrainOutput::Mesh && !target.stream;
        let halo = 2 * params.erosion_halo();
        let rows_at_once =
            target.streamed_band(rect.width()).map_or(rect.height(), |band| band.max(1).min(rect.height()));
        let bytes_per_point = if whole_mesh { MESH_BYTES_PER_POINT } else { HEIGHTS_BYTES_PER_POINT };
        let smoothing = if params.method == Method::Smooth || params.erosion.is_some() || params.hydraulic.is_some() {
            2
        } else {
            1
        };
        // Hydraulic erosion's state: water, sediment and the pipes' flux, each twice.
        let hydraulic_bytes = params.hydraulic.map_or(0, |_| super::hydraulic::BYTES_PER_POINT)
            + if layers.is_empty() { 0 } else { super::hydraulic::LAYER_BYTES_PER_POINT + 8 * layers.len() as u64 };
        // A halo never reaches past the grid: 100000 erosion iterations on a whole 257² grid
        // were refused as needing 8965.8 GB (#36).
        let (rows, columns) =
            ((rows_at_once as u64 + halo).min(params.size), (rect.width() as u64 + halo).min(params.size));
        crate::memory::ensure_available(
            rows * columns * (bytes_per_point * smoothing + hydraulic_bytes),
            &format!("a {}x{} terrain built whole", rect.width(), rect.height()),
            &match spelling {
                Spelling::Flag => "write a heightmap with --stream, or cut it into --tile pieces".to_string(),
                _ => format!("ask for a tile ({}, {})", spelling.of("tile"), spelling.of("tile_size")),
            },
        )?;
        let params = match max_height {
            Some(top) => params.with_max_height(top)?,
            None => params,
        };
        let scale = params.height_scale();
        Ok(TerrainSetup { params, rect, extent, hurst, layers, range: range.unwrap_or((-scale, scale)) })
    }
}

/// The dual method's quad surface as a mesh with angle-weighted normals and colours by
/// height along the quad's normal (the surface's own range), as `asperity terrain` writes it.
pub fn dual_mesh(surface: &QuadSurface, params: &DualParams, palette: &Palette) -> Mesh {
    use crate::analysis::{FaceGeometry, NormalWeighting, vertex_normals};
    let mut m = surface.to_mesh();
    let adjacency = crate::mesh::Adjacency::of(&m);
    m.normals = Some(vertex_normals(&m, &adjacency, &FaceGeometry::of(&m), NormalWeighting::Angle));
    let z = params.x.cross(params.y).normalize();
    let heights: Vec<f64> = m.positions.iter().map(|p| p.dot(z)).collect();
    let (lo, hi) = heights.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &h| (a.min(h), b.max(h)));
    m.colors = Some(heights.iter().map(|h| ramp_color(palette, (h - lo) / (hi - lo).max(1e-12), false)).collect());
    m
}
