//! Clouds (seed 001, §IV): a 2D plasma made by midpoint displacement, normalised to
//! [0, 1], thresholded and coloured from sky to cloud.

use super::{TerrainParams, whole};
use crate::error::{Error, Result};
use crate::mesh::{Rgb, blend_rgb};

/// Cloud image parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CloudParams {
    /// The plasma (a classic terrain's heights).
    pub plasma: TerrainParams,
    /// Plasma values below this (in [0, 1]) are clear sky.
    pub threshold: f64,
    /// Colour of clear sky.
    pub sky: Rgb,
    /// Colour of the densest cloud.
    pub cloud: Rgb,
}

impl Default for CloudParams {
    fn default() -> Self {
        CloudParams {
            plasma: TerrainParams { size: 513, hurst: 0.7, ..TerrainParams::default() },
            threshold: 0.45,
            sky: [70, 130, 210],
            cloud: [255, 255, 255],
        }
    }
}

/// The cloud image, row-major RGB, `plasma.size` pixels per side; and the fraction of
/// pixels covered by cloud.
///
/// # Errors
/// [`Error::InvalidInput`] for invalid plasma parameters or a threshold outside [0, 1].
pub fn clouds(params: &CloudParams) -> Result<(Vec<u8>, f64)> {
    if !(0.0..=1.0).contains(&params.threshold) {
        return Err(Error::InvalidInput(format!("cloud threshold {} must lie in [0, 1]", params.threshold)));
    }
    let plasma = whole(&TerrainParams { sea_level: None, ..params.plasma })?;
    let (lo, hi) = plasma.heights.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &h| (a.min(h), b.max(h)));
    let span = (hi - lo).max(f64::MIN_POSITIVE);
    let mut covered = 0usize;
    let mut rgb = Vec::with_capacity(plasma.heights.len() * 3);
    for h in &plasma.heights {
        let v = (h - lo) / span;
        let density = if params.threshold >= 1.0 {
            0.0
        } else {
            ((v - params.threshold) / (1.0 - params.threshold)).clamp(0.0, 1.0)
        };
        if density > 0.0 {
            covered += 1;
        }
        // Square root: thin cloud edges fade in quickly, as wisps do.
        let t = density.sqrt();
        rgb.extend(blend_rgb(params.sky, params.cloud, t));
    }
    Ok((rgb, covered as f64 / plasma.heights.len() as f64))
}
