//! The compare request (#38): `asperity compare`'s settings as the command line and
//! Python's `asperity.compare` give them, with one [`CompareRequest::check`] for both.

use serde::{Deserialize, Serialize};

use super::compare::{CompareReport, METHODS, compare_report};
use super::{FeatureVertices, HierarchyRequest, KeepFeatures, SimplifyOptions, VertexTarget};
use crate::error::{Error, Result};
use crate::mesh::Mesh;
use crate::request::Spelling;

/// Which methods to compare, at which vertex budget, and what ours keeps.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
pub struct CompareRequest {
    /// Vertex budget: a count ("377") or a share of the input's vertices ("1%").
    #[cfg_attr(feature = "cli", arg(long, default_value = "1%", value_parser = VertexTarget::parse))]
    pub target_vertices: VertexTarget,
    /// Methods to run, comma-separated (asperity, openmesh, cgal, meshoptimizer).
    #[cfg_attr(feature = "cli", arg(long, value_delimiter = ',', default_values_t = METHODS.map(String::from)))]
    pub methods: Vec<String>,
    /// Feature vertices our simplification keeps (they can stop it above the budget).
    #[cfg_attr(feature = "cli", arg(long, value_enum, default_value_t = KeepFeatures::Strong))]
    pub keep_features: KeepFeatures,
    /// Our feature vertices on lines: simplified along them or kept [default: along-lines].
    /// Needs --keep-features (keep_features) corners, strong or all.
    #[cfg_attr(feature = "cli", arg(long, value_enum))]
    pub feature_vertices: Option<FeatureVertices>,
}

impl Default for CompareRequest {
    fn default() -> Self {
        CompareRequest {
            target_vertices: VertexTarget::Percent(1.0),
            methods: METHODS.map(String::from).to_vec(),
            keep_features: KeepFeatures::Strong,
            feature_vertices: None,
        }
    }
}

impl CompareRequest {
    /// The request's own rules, in the messages every front end prints (`spelling` names
    /// the fields): at least one method, each one of [`METHODS`] and named once. The vertex
    /// budget and our settings are checked against the mesh by [`CompareRequest::report`].
    ///
    /// # Errors
    /// [`Error::InvalidInput`] with the first rule broken.
    pub fn check(&self, spelling: Spelling) -> Result<()> {
        let field = spelling.of("methods");
        if self.methods.is_empty() {
            return Err(Error::InvalidInput(format!("{field} names no method (use {})", METHODS.join(", "))));
        }
        for (i, method) in self.methods.iter().enumerate() {
            if !METHODS.contains(&method.as_str()) {
                return Err(Error::InvalidInput(format!(
                    "{field}: unknown method '{method}' (expected one of {})",
                    METHODS.join(", ")
                )));
            }
            if self.methods[..i].contains(method) {
                return Err(Error::InvalidInput(format!("{field}: '{method}' is named twice")));
            }
        }
        Ok(())
    }

    /// Compares the methods on `mesh` ([`compare_report`]) after [`CompareRequest::check`];
    /// ours is built with the hierarchy request these settings make (its checks, its
    /// messages).
    ///
    /// # Errors
    /// As [`CompareRequest::check`], [`HierarchyRequest::options`] and [`compare_report`].
    pub fn report(&self, mesh: &Mesh, spelling: Spelling) -> Result<CompareReport> {
        self.check(spelling)?;
        let ours = HierarchyRequest {
            target_vertices: Some(self.target_vertices),
            keep_features: Some(self.keep_features),
            feature_vertices: self.feature_vertices,
            ..HierarchyRequest::default()
        }
        .options(mesh.vertex_count(), false, spelling)?;
        let target = ours.target_vertices.unwrap_or(mesh.vertex_count());
        let methods: Vec<&str> = self.methods.iter().map(String::as_str).collect();
        compare_report(mesh, target, &methods, &SimplifyOptions { target_vertices: None, ..ours })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn methods_are_checked_before_any_runs() {
        assert!(CompareRequest::default().check(Spelling::Flag).is_ok());
        let with = |methods: &[&str]| CompareRequest {
            methods: methods.iter().map(|m| m.to_string()).collect(),
            ..Default::default()
        };
        let message = |r: CompareRequest| r.check(Spelling::Keyword).unwrap_err().to_string();
        assert!(message(with(&[])).contains("methods= names no method"));
        assert!(message(with(&["asperity", "qslim"])).contains("methods=: unknown method 'qslim'"));
        assert!(message(with(&["cgal", "cgal"])).contains("'cgal' is named twice"));
    }
}
