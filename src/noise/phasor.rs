//! Phasor noise (Tricard, Efremov, Zanni, Neyret, Martínez, Lefebvre, "Procedural phasor
//! noise", ACM TOG 38(4), 2019): the phase of complex Gabor noise, φ = arg G (their eq. 4),
//! put through a periodic profile. It keeps Gabor's spectral control — F0, ω0 or isotropy,
//! the bandwidth a, the impulse density — with a constant contrast: the value's envelope is
//! K everywhere, where Gabor's fades wherever its impulses cancel.

use serde::{Deserialize, Serialize};

use super::gabor::{Frame, Gabor, GaborParams};
use crate::error::Result;

/// The periodic profile a phase goes through (Tricard et al. §4.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum Profile {
    /// sin φ.
    #[default]
    Sine,
    /// The sign of sin φ: stripes of −K and K with sharp edges.
    Square,
    /// φ/π: a ramp from −K to K each period.
    Sawtooth,
}

impl Profile {
    /// The profile at phase `phi` ∈ [−π, π], in [−1, 1].
    pub fn at(self, phi: f64) -> f64 {
        match self {
            Profile::Sine => phi.sin(),
            Profile::Square => {
                if phi.sin() >= 0.0 {
                    1.0
                } else {
                    -1.0
                }
            }
            Profile::Sawtooth => phi / std::f64::consts::PI,
        }
    }
}

/// Phasor noise with fixed parameters, profile and seed: the impulses are Gabor noise's for
/// the same parameters and seed.
#[derive(Debug, Clone)]
pub struct Phasor {
    gabor: Gabor,
    profile: Profile,
}

impl Phasor {
    /// Phasor noise with Gabor's `params` (K is the output's amplitude), `profile` and `seed`.
    ///
    /// # Errors
    /// As [`Gabor::new`].
    pub fn new(params: GaborParams, profile: Profile, seed: u64) -> Result<Self> {
        Ok(Phasor { gabor: Gabor::new(params, seed)?, profile })
    }

    fn value(&self, (re, im): (f64, f64)) -> f64 {
        self.gabor.params().k * self.profile.at(im.atan2(re))
    }

    /// 2D phasor noise at (x, y), in [−K, K].
    pub fn sample2(&self, x: f64, y: f64) -> f64 {
        self.value(self.gabor.complex2(x, y))
    }

    /// Phasor noise at a surface point with its tangent frame (as [`Gabor::sample3`]).
    pub fn sample3(&self, p: glam::DVec3, frame: Frame) -> f64 {
        self.value(self.gabor.complex3(p, frame))
    }
}
