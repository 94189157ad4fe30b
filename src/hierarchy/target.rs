//! A vertex target as users write it (`377` or `5%`).

use crate::error::{Error, Result};
use crate::request::Spelling;

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
    /// refused, naming the field `target_vertices` as `spelling` writes it (it would remove
    /// nothing, #36).
    ///
    /// # Errors
    /// [`Error::InvalidInput`] naming the field.
    pub fn resolve(self, vertices: usize, spelling: Spelling) -> Result<usize> {
        match self {
            VertexTarget::Vertices(v) if v > vertices => Err(Error::InvalidInput(format!(
                "{} is more than the input's {vertices} vertices: nothing would be removed",
                spelling.with("target_vertices", v)
            ))),
            VertexTarget::Vertices(v) => Ok(v),
            VertexTarget::Percent(p) => Ok(((vertices as f64 * p / 100.0).round() as usize).max(4)),
        }
    }
}

impl std::fmt::Display for VertexTarget {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        match self {
            VertexTarget::Vertices(v) => write!(f, "{v}"),
            VertexTarget::Percent(p) => write!(f, "{p}%"),
        }
    }
}

/// A count as a number (`377`), a share as text (`"1%"`).
impl serde::Serialize for VertexTarget {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        match self {
            VertexTarget::Vertices(v) => s.serialize_u64(*v as u64),
            VertexTarget::Percent(_) => s.collect_str(self),
        }
    }
}

/// A vertex count written as a number (`377`) or as text (`"377"`, `"1%"`), checked by
/// [`VertexTarget::parse`].
impl<'de> serde::Deserialize<'de> for VertexTarget {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        struct CountOrText;
        impl serde::de::Visitor<'_> for CountOrText {
            type Value = VertexTarget;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a vertex count (377) or text (\"377\", \"1%\")")
            }
            fn visit_u64<E: serde::de::Error>(self, n: u64) -> std::result::Result<VertexTarget, E> {
                VertexTarget::parse(&n.to_string()).map_err(E::custom)
            }
            fn visit_i64<E: serde::de::Error>(self, n: i64) -> std::result::Result<VertexTarget, E> {
                VertexTarget::parse(&n.to_string()).map_err(E::custom)
            }
            fn visit_str<E: serde::de::Error>(self, text: &str) -> std::result::Result<VertexTarget, E> {
                VertexTarget::parse(text).map_err(E::custom)
            }
        }
        d.deserialize_any(CountOrText)
    }
}
