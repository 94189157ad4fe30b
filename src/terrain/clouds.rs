//! Clouds (seed 001, §IV): a 2D plasma made by midpoint displacement, normalised to
//! [0, 1], thresholded and coloured from sky to cloud.

use serde::{Deserialize, Serialize};

use super::{TerrainParams, whole};
use crate::error::{Error, Result};
use crate::mesh::{Rgb, blend_rgb};
use crate::request::Spelling;

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

/// The clouds request (#38): the cloud picture's parameters as the command line's
/// `asperity clouds` and Python's `asperity.clouds` give them, with one
/// [`CloudRequest::check`] for both.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
pub struct CloudRequest {
    /// Pixels per side, 2^n + 1.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = CloudRequest::default().size))]
    pub size: u64,
    /// Roughness H of the plasma.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = CloudRequest::default().hurst, allow_negative_numbers = true))]
    pub hurst: f64,
    /// Seed.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = 0))]
    pub seed: u64,
    /// Plasma values below this (0 to 1) are clear sky.
    #[cfg_attr(
        feature = "cli",
        arg(long, default_value_t = CloudRequest::default().threshold, allow_negative_numbers = true)
    )]
    pub threshold: f64,
    /// Sky colour R,G,B.
    #[cfg_attr(feature = "cli", arg(long, value_parser = crate::request::parse::rgb, default_value = "70,130,210"))]
    pub sky: Rgb,
    /// Cloud colour R,G,B.
    #[cfg_attr(feature = "cli", arg(long, value_parser = crate::request::parse::rgb, default_value = "255,255,255"))]
    pub cloud: Rgb,
}

impl Default for CloudRequest {
    fn default() -> Self {
        let d = CloudParams::default();
        CloudRequest {
            size: d.plasma.size,
            hurst: d.plasma.hurst,
            seed: d.plasma.seed,
            threshold: d.threshold,
            sky: d.sky,
            cloud: d.cloud,
        }
    }
}

impl CloudRequest {
    /// The request's own rules, in the messages every front end prints (`spelling` names
    /// the fields): the size is 2^n + 1; the threshold lies in [0, 1]; the picture (the plasma's heights, twice
    /// while smoothing, and the RGB pixels) fits the memory budget. The plasma checks its
    /// size and roughness when it is made.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] with the first rule broken; a picture too large is refused by
    /// estimate before allocating ([`crate::memory::ensure_available`]).
    pub fn check(&self, spelling: Spelling) -> Result<()> {
        if super::levels_of_size(self.size).is_none() {
            return Err(Error::InvalidInput(format!(
                "{}: must be 2^n + 1 (3, 5, 9, ... 513, ...)",
                spelling.with("size", self.size)
            )));
        }
        if !(0.0..=1.0).contains(&self.threshold) {
            return Err(Error::InvalidInput(format!(
                "{}: must lie in [0, 1]",
                spelling.with("threshold", self.threshold)
            )));
        }
        let points = self.size.saturating_mul(self.size);
        crate::memory::ensure_available(
            points.saturating_mul(2 * 8 + 3),
            &format!("a {0}x{0} cloud picture", self.size),
            &format!("ask for a smaller {}", spelling.of("size")),
        )
    }

    /// The library's parameters.
    pub fn params(&self) -> CloudParams {
        CloudParams {
            plasma: TerrainParams {
                size: self.size,
                hurst: self.hurst,
                seed: self.seed,
                ..CloudParams::default().plasma
            },
            threshold: self.threshold,
            sky: self.sky,
            cloud: self.cloud,
        }
    }

    /// The picture and its cloud cover ([`clouds`]), after [`CloudRequest::check`].
    ///
    /// # Errors
    /// As [`CloudRequest::check`] and [`clouds`].
    pub fn picture(&self, spelling: Spelling) -> Result<(Vec<u8>, f64)> {
        self.check(spelling)?;
        clouds(&self.params())
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
