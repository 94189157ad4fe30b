//! The analysis request (#38): the thresholds and weights of [`analyze`] as the command
//! line's `asperity analyze`, Python's `asperity.analyze` and C++'s `asperity::analyze`
//! give them, with one [`AnalysisRequest::check`] for all three.

use serde::{Deserialize, Serialize};

use super::{AnalysisOptions, FeatureOptions, NormalWeighting, SurfaceAnalysis, analyze};
use crate::error::{Error, Result};
use crate::mesh::Mesh;
use crate::request::Spelling;

/// Surface analysis settings: normal weights (eq. 3.2) and Algorithm 1's thresholds on the
/// normalised eigenvalues of the voting tensor (eq. 4.2–4.3).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
pub struct AnalysisRequest {
    /// Vertex normal weights.
    #[cfg_attr(feature = "cli", arg(long, value_enum, default_value_t = NormalWeighting::Angle))]
    pub normals: NormalWeighting,
    /// Corner when the normalised λ3 exceeds this.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = AnalysisRequest::default().corner, allow_negative_numbers = true))]
    pub corner: f64,
    /// Face vertex when λ2 is below this.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = AnalysisRequest::default().face, allow_negative_numbers = true))]
    pub face: f64,
    /// Strong edge when λ2 exceeds this.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = AnalysisRequest::default().strong, allow_negative_numbers = true))]
    pub strong: f64,
}

impl Default for AnalysisRequest {
    fn default() -> Self {
        let d = FeatureOptions::default();
        AnalysisRequest {
            normals: NormalWeighting::default(),
            corner: d.corner_min_l3,
            face: d.face_max_l2,
            strong: d.strong_min_l2,
        }
    }
}

impl AnalysisRequest {
    /// The request's own rules, in the messages every front end prints (`spelling` names
    /// the fields): each threshold is a normalised eigenvalue, so a number from 0 to 1.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] with the first rule broken.
    pub fn check(&self, spelling: Spelling) -> Result<()> {
        for (field, value) in [("corner", self.corner), ("face", self.face), ("strong", self.strong)] {
            if !(0.0..=1.0).contains(&value) {
                return Err(Error::InvalidInput(format!(
                    "{}: must lie in [0, 1] (a normalised eigenvalue of the voting tensor)",
                    spelling.with(field, value)
                )));
            }
        }
        Ok(())
    }

    /// The library's options.
    pub fn options(&self) -> AnalysisOptions {
        AnalysisOptions {
            normal_weighting: self.normals,
            features: FeatureOptions {
                corner_min_l3: self.corner,
                face_max_l2: self.face,
                strong_min_l2: self.strong,
                ..FeatureOptions::default()
            },
        }
    }

    /// [`analyze`] with these settings, after [`AnalysisRequest::check`].
    ///
    /// # Errors
    /// As [`AnalysisRequest::check`] and [`analyze`].
    pub fn analyze(&self, mesh: &Mesh, spelling: Spelling) -> Result<SurfaceAnalysis> {
        self.check(spelling)?;
        analyze(mesh, &self.options())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_threshold_outside_the_eigenvalues_range_is_named() {
        assert!(AnalysisRequest::default().check(Spelling::Flag).is_ok());
        for (bad, name) in [
            (AnalysisRequest { corner: -0.1, ..Default::default() }, "--corner -0.1"),
            (AnalysisRequest { face: f64::NAN, ..Default::default() }, "--face NaN"),
            (AnalysisRequest { strong: 2.0, ..Default::default() }, "--strong 2"),
        ] {
            let message = bad.check(Spelling::Flag).unwrap_err().to_string();
            assert!(message.contains(name), "{message}");
        }
    }

    #[test]
    fn every_setting_changes_the_analysis_of_a_cube() {
        let mesh = crate::mesh::primitives::cube(glam::DVec3::ZERO, glam::DVec3::ONE, 4);
        let base = AnalysisRequest::default().analyze(&mesh, Spelling::Flag).unwrap();
        for other in [
            AnalysisRequest { normals: NormalWeighting::Uniform, ..Default::default() },
            AnalysisRequest { corner: 0.9, ..Default::default() },
            AnalysisRequest { face: 0.0, ..Default::default() },
            AnalysisRequest { strong: 0.9, ..Default::default() },
        ] {
            let changed = other.analyze(&mesh, Spelling::Flag).unwrap();
            assert!(changed.normals != base.normals || changed.classes != base.classes, "{other:?}");
        }
    }
}
