//! The render request (#38): a picture's settings as the command line's `asperity render`
//! and Python's `asperity.render` give them, with one [`RenderRequest::options`] that
//! checks them for both.

use std::path::PathBuf;

use serde::{Deserialize, Serialize};

use super::{ColorSource, Mode, RenderOptions, UpAxis, WaterView};
use crate::error::{Error, Result};
use crate::request::Spelling;

/// Camera, picture, water and texture settings of [`super::render`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
pub struct RenderRequest {
    /// Picture size W,H in pixels.
    #[cfg_attr(feature = "cli", arg(long, value_parser = crate::request::parse::size, default_value = "1024,768"))]
    pub size: (usize, usize),
    /// Faces (shaded), wireframe (hidden lines removed) or points.
    #[cfg_attr(feature = "cli", arg(long, value_enum, default_value_t = Mode::Faces))]
    pub mode: Mode,
    /// Camera angle around the up axis, degrees.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = 35.0, allow_hyphen_values = true))]
    pub yaw: f64,
    /// Camera angle above the horizon, degrees.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = 25.0, allow_hyphen_values = true))]
    pub pitch: f64,
    /// The axis that points up in the picture.
    #[cfg_attr(feature = "cli", arg(long, value_enum, default_value_t = UpAxis::Z))]
    pub up: UpAxis,
    /// Colours: attribute (vertex colours), height, none, or scalar:NAME (a PLY property).
    #[cfg_attr(feature = "cli", arg(long, value_parser = ColorSource::parse, default_value = "attribute"))]
    #[serde(with = "as_text")]
    pub colors: ColorSource,
    /// Background: transparent or #rrggbb.
    #[cfg_attr(feature = "cli", arg(long, value_parser = Background::parse, default_value = "#ffffff"))]
    #[serde(with = "as_text")]
    pub background: Background,
    /// Samples per pixel along each axis (1 to 4).
    #[cfg_attr(feature = "cli", arg(long, default_value_t = 2))]
    pub samples: usize,
    /// Faces further apart than this angle do not share normals (degrees; 180 smooths all;
    /// faces mode) [default: 40].
    #[cfg_attr(feature = "cli", arg(long, allow_negative_numbers = true))]
    pub crease: Option<f64>,
    /// Draw the edges over shaded faces (faces mode).
    #[cfg_attr(feature = "cli", arg(long))]
    pub edges: bool,
    /// Draw water at this height along the up axis (mesh units) over the mesh's extent: a
    /// Fresnel mix of sky and what lies below (faces mode).
    #[cfg_attr(feature = "cli", arg(long, allow_negative_numbers = true))]
    pub water_level: Option<f64>,
    /// How far one sees into the water, as a fraction of the bounding-box diagonal
    /// (with --water-level, water_level) [default: 0.02].
    #[cfg_attr(feature = "cli", arg(long))]
    pub water_clarity: Option<f64>,
    /// Draw the mesh with this texture (PNG) at its UVs (faces mode; the mesh needs texture
    /// coordinates: OBJ vt, PLY s t, glTF TEXCOORD_0). Replaces --colors (colors).
    #[cfg_attr(feature = "cli", arg(long))]
    pub texture: Option<PathBuf>,
}

impl Default for RenderRequest {
    fn default() -> Self {
        let d = RenderOptions::default();
        RenderRequest {
            size: (d.width, d.height),
            mode: d.mode,
            yaw: d.yaw_deg,
            pitch: d.pitch_deg,
            up: d.up,
            colors: d.colors,
            background: Background(d.background),
            samples: d.samples,
            crease: None,
            edges: d.edges,
            water_level: None,
            water_clarity: None,
            texture: None,
        }
    }
}

impl RenderRequest {
    /// The request's own rules, in the messages every front end prints (`spelling` names
    /// the fields): shading settings (crease, edges, water, texture) only in faces mode;
    /// water clarity only with a water level; a texture gives the colours. The picture's
    /// size and samples are checked by [`super::render`] against the memory budget.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] with the first rule broken.
    pub fn check(&self, spelling: Spelling) -> Result<()> {
        if self.mode != Mode::Faces {
            let mode = spelling.with("mode", format!("{:?}", self.mode).to_lowercase());
            let shading = [
                ("crease", self.crease.is_some()),
                ("edges", self.edges),
                ("water_level", self.water_level.is_some()),
                ("texture", self.texture.is_some()),
            ];
            if let Some((field, _)) = shading.iter().find(|(_, given)| *given) {
                return Err(Error::InvalidInput(format!(
                    "{} applies only to {} (shading), not {mode}",
                    spelling.of(field),
                    spelling.with("mode", "faces")
                )));
            }
        }
        if self.water_clarity.is_some() && self.water_level.is_none() {
            return Err(Error::InvalidInput(format!(
                "{} applies only with {}",
                spelling.of("water_clarity"),
                spelling.of("water_level")
            )));
        }
        if self.texture.is_some() && self.colors != ColorSource::Attribute {
            return Err(Error::InvalidInput(format!(
                "{} gives the colours: {} cannot be used with it",
                spelling.of("texture"),
                spelling.of("colors")
            )));
        }
        Ok(())
    }

    /// The rasteriser's options after [`RenderRequest::check`], the texture read.
    ///
    /// # Errors
    /// As [`RenderRequest::check`]; an unreadable texture.
    pub fn options(&self, spelling: Spelling) -> Result<RenderOptions> {
        self.check(spelling)?;
        let texture = match &self.texture {
            Some(path) => Some(std::sync::Arc::new(super::texture::Texture::read_png(path)?)),
            None => None,
        };
        Ok(RenderOptions {
            width: self.size.0,
            height: self.size.1,
            mode: self.mode,
            yaw_deg: self.yaw,
            pitch_deg: self.pitch,
            up: self.up,
            colors: self.colors.clone(),
            background: self.background.0,
            samples: self.samples,
            crease_deg: self.crease.unwrap_or(RenderOptions::default().crease_deg),
            edges: self.edges,
            water: self.water_level.map(|level| WaterView { level, clarity: self.water_clarity.unwrap_or(0.02) }),
            texture,
        })
    }
}

/// A picture background: a colour, or transparent (`None`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Background(pub Option<[u8; 3]>);

impl Background {
    /// Reads `transparent` or `#rrggbb`.
    ///
    /// # Errors
    /// A message saying what is expected.
    pub fn parse(s: &str) -> std::result::Result<Background, String> {
        if s.eq_ignore_ascii_case("transparent") {
            return Ok(Background(None));
        }
        let hex = s
            .strip_prefix('#')
            .filter(|h| h.len() == 6 && h.is_ascii())
            .ok_or_else(|| format!("`{s}`: expected `transparent` or #rrggbb"))?;
        let byte =
            |i: usize| u8::from_str_radix(&hex[i..i + 2], 16).map_err(|_| format!("`{s}` is not a #rrggbb colour"));
        Ok(Background(Some([byte(0)?, byte(2)?, byte(4)?])))
    }
}

impl std::fmt::Display for Background {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        match self.0 {
            None => f.write_str("transparent"),
            Some([r, g, b]) => write!(f, "#{r:02x}{g:02x}{b:02x}"),
        }
    }
}

impl ColorSource {
    /// Reads `attribute`, `height`, `none` or `scalar:NAME`.
    ///
    /// # Errors
    /// A message saying what is expected.
    pub fn parse(s: &str) -> std::result::Result<ColorSource, String> {
        match s {
            "attribute" => Ok(ColorSource::Attribute),
            "height" => Ok(ColorSource::Height),
            "none" => Ok(ColorSource::None),
            _ => match s.strip_prefix("scalar:") {
                Some(name) if !name.is_empty() => Ok(ColorSource::Scalar(name.to_string())),
                _ => Err(format!("`{s}`: expected attribute, height, none or scalar:NAME")),
            },
        }
    }
}

impl std::fmt::Display for ColorSource {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        match self {
            ColorSource::Attribute => f.write_str("attribute"),
            ColorSource::Height => f.write_str("height"),
            ColorSource::None => f.write_str("none"),
            ColorSource::Scalar(name) => write!(f, "scalar:{name}"),
        }
    }
}

/// A field read and written as the text the command line takes (`"#ffffff"`,
/// `"scalar:mean_curvature"`).
mod as_text {
    use serde::{Deserialize, Deserializer, Serializer};

    /// Values with a text form: `parse` and `Display`.
    pub trait Text: Sized + std::fmt::Display {
        fn from_text(s: &str) -> Result<Self, String>;
    }
    impl Text for super::Background {
        fn from_text(s: &str) -> Result<Self, String> {
            super::Background::parse(s)
        }
    }
    impl Text for super::ColorSource {
        fn from_text(s: &str) -> Result<Self, String> {
            super::ColorSource::parse(s)
        }
    }

    pub fn serialize<T: Text, S: Serializer>(value: &T, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(value)
    }

    pub fn deserialize<'de, T: Text, D: Deserializer<'de>>(d: D) -> Result<T, D::Error> {
        let text = String::deserialize(d)?;
        T::from_text(&text).map_err(serde::de::Error::custom)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shading_settings_outside_faces_mode_are_named() {
        let points = |r: RenderRequest| RenderRequest { mode: Mode::Points, ..r };
        let message = |r: RenderRequest, s: Spelling| r.check(s).unwrap_err().to_string();
        let edges = points(RenderRequest { edges: true, ..Default::default() });
        assert_eq!(
            message(edges.clone(), Spelling::Flag),
            "invalid input: --edges applies only to --mode faces (shading), not --mode points"
        );
        assert!(message(edges, Spelling::Keyword).contains("edges= applies only to mode=faces"));
        let clarity = RenderRequest { water_clarity: Some(0.1), ..Default::default() };
        assert!(message(clarity, Spelling::Keyword).contains("water_clarity= applies only with water_level="));
    }

    #[test]
    fn text_fields_round_trip() {
        let r = RenderRequest {
            colors: ColorSource::Scalar("k1".into()),
            background: Background(None),
            ..Default::default()
        };
        let json = serde_json::to_string(&r).unwrap();
        assert!(json.contains("\"scalar:k1\"") && json.contains("\"transparent\""), "{json}");
        assert_eq!(serde_json::from_str::<RenderRequest>(&json).unwrap(), r);
        assert_eq!(Background::parse("#0a0b0c").unwrap().to_string(), "#0a0b0c");
        assert!(serde_json::from_str::<RenderRequest>(r#"{"colors": "rainbow"}"#).is_err());
    }
}
