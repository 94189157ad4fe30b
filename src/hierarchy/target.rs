//! A vertex target as users write it (`377` or `5%`), and a recipe's `[hierarchy]` table
//! resolved into build options: one function every front end (the command line, Python and
//! C++) calls, so that none reads the table its own way (#36: C++ read only
//! `target_vertices`).

use serde::Deserialize;

use super::{KeepFeatures, SimplifyOptions};
use crate::error::{Error, Result};

/// A vertex budget, absolute or relative.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum VertexTarget {
    /// A vertex count.
    Vertices(usize),
    /// A share of the input's vertices, in percent.
    Percent(f64),
}

impl VertexTarget {
    /// Reads `377` or `5%`.
    ///
    /// # Errors
    /// A message saying what is wrong (0 vertices, a share outside (0, 100] %).
    pub fn parse(s: &str) -> std::result::Result<Self, String> {
        if let Some(p) = s.strip_suffix('%') {
            let p: f64 = p.trim().parse().map_err(|_| format!("'{s}' is not a percentage"))?;
            if !(p > 0.0 && p <= 100.0) {
                return Err(format!("'{s}' must be above 0% and at most 100%"));
            }
            Ok(VertexTarget::Percent(p))
        } else {
            match s.trim().parse() {
                Ok(0) => Err(format!(
                    "'{s}' must be at least 1 vertex (a build asked for fewer than its topology allows stops there and says so)"
                )),
                Ok(v) => Ok(VertexTarget::Vertices(v)),
                Err(_) => Err(format!("'{s}' is not a vertex count or a percentage")),
            }
        }
    }

    /// The vertex count for an input of `vertices` vertices; a count above the input's is
    /// refused, naming `source` (it would remove nothing, #36).
    ///
    /// # Errors
    /// [`Error::InvalidInput`] naming `source`.
    pub fn resolve(self, vertices: usize, source: &str) -> Result<usize> {
        match self {
            VertexTarget::Vertices(v) if v > vertices => Err(Error::InvalidInput(format!(
                "{source} {v} is more than the input's {vertices} vertices: nothing would be removed"
            ))),
            VertexTarget::Vertices(v) => Ok(v),
            VertexTarget::Percent(p) => Ok(((vertices as f64 * p / 100.0).round() as usize).max(4)),
        }
    }
}

/// A `[hierarchy]` table read against an input of some size: each setting the table gives.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SectionSettings {
    /// `target_vertices`, resolved.
    pub target_vertices: Option<usize>,
    /// `levels`.
    pub levels: Option<usize>,
    /// `max_error`.
    pub max_error: Option<f64>,
    /// `keep_features`.
    pub keep_features: Option<KeepFeatures>,
}

impl HierarchySection {
    /// The table's settings for an input of `vertices` vertices, each checked.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] naming the table's key.
    pub fn settings(&self, vertices: usize) -> Result<SectionSettings> {
        let target_vertices = match self.target_vertices.as_deref() {
            Some(text) => Some(
                VertexTarget::parse(text)
                    .map_err(|e| Error::InvalidInput(format!("[hierarchy] target_vertices: {e}")))?
                    .resolve(vertices, "[hierarchy] target_vertices")?,
            ),
            None => None,
        };
        if let Some(e) = self.max_error.filter(|e| !(*e >= 0.0 && e.is_finite())) {
            return Err(Error::InvalidInput(format!("[hierarchy] max_error = {e} must be a non-negative fraction")));
        }
        let keep_features = match self.keep_features.as_deref() {
            None => None,
            Some("none") => Some(KeepFeatures::None),
            Some("corners") => Some(KeepFeatures::Corners),
            Some("strong") => Some(KeepFeatures::Strong),
            Some("all") => Some(KeepFeatures::All),
            Some(other) => {
                return Err(Error::InvalidInput(format!(
                    "[hierarchy] keep_features = \"{other}\": use none, corners, strong or all"
                )));
            }
        };
        Ok(SectionSettings { target_vertices, levels: self.levels, max_error: self.max_error, keep_features })
    }

    /// `options` with every setting the table gives applied (what a front end without
    /// flags of its own, as C++'s `detail`, builds with).
    ///
    /// # Errors
    /// As [`HierarchySection::settings`].
    pub fn apply(&self, options: SimplifyOptions, vertices: usize) -> Result<SimplifyOptions> {
        let s = self.settings(vertices)?;
        Ok(SimplifyOptions {
            target_vertices: s.target_vertices.or(options.target_vertices),
            levels: s.levels.or(options.levels),
            max_error: s.max_error.or(options.max_error),
            keep_features: s.keep_features.unwrap_or(options.keep_features),
            ..options
        })
    }
}

/// A recipe's `[hierarchy]` table (read with the recipe, `crate::detail::Recipe`).
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HierarchySection {
    /// "377" (or 377) or "1%".
    #[serde(default, deserialize_with = "count_or_text")]
    pub target_vertices: Option<String>,
    /// Number of levels.
    pub levels: Option<usize>,
    /// Maximum error, fraction of the bounding-box diagonal.
    pub max_error: Option<f64>,
    /// "none", "corners", "strong" or "all".
    pub keep_features: Option<String>,
}

/// A vertex count written as a number (`377`) or as text (`"377"`, `"1%"`).
fn count_or_text<'de, D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Option<String>, D::Error> {
    struct CountOrText;
    impl serde::de::Visitor<'_> for CountOrText {
        type Value = String;
        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str("a vertex count (377) or text (\"377\", \"1%\")")
        }
        fn visit_u64<E: serde::de::Error>(self, n: u64) -> std::result::Result<String, E> {
            Ok(n.to_string())
        }
        fn visit_i64<E: serde::de::Error>(self, n: i64) -> std::result::Result<String, E> {
            Ok(n.to_string())
        }
        fn visit_str<E: serde::de::Error>(self, text: &str) -> std::result::Result<String, E> {
            Ok(text.to_string())
        }
    }
    d.deserialize_any(CountOrText).map(Some)
}
