//! The noise request (#38): every parameter of a noise field, as the command line's
//! `asperity noise`, Python's `asperity.noise` and C++'s `asperity::noise` take it, with
//! one [`NoiseRequest::check`] for all three.

use glam::{DVec2, DVec3};
use serde::{Deserialize, Serialize};

use super::{Fractal, Frame, GaborParams, MAX_IMPULSES_PER_KERNEL, MAX_OCTAVES, NoiseField, NoiseKind, NoiseSpec};
use super::{Precision, Profile};
use crate::error::{Error, Result};
use crate::request::Spelling;

/// A noise field's parameters; an unset one takes its kind's default. A parameter of
/// another kind is refused by [`NoiseRequest::check`] (it would have no effect).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
pub struct NoiseRequest {
    /// Which noise.
    #[cfg_attr(feature = "cli", arg(long, value_enum, default_value_t = NoiseKind::Perlin))]
    pub kind: NoiseKind,
    /// Octaves of the fractal kinds, 1 to 32 [default: 6; wood 1, eq. 4.13's single noise,
    /// whose contour bands are the rings].
    #[cfg_attr(feature = "cli", arg(long))]
    pub octaves: Option<u32>,
    /// Frequency ratio between octaves (fractal kinds) [default: 2].
    #[cfg_attr(feature = "cli", arg(long, allow_negative_numbers = true))]
    pub lacunarity: Option<f64>,
    /// Amplitude ratio between octaves (fractal kinds) [default: 0.5].
    #[cfg_attr(feature = "cli", arg(long, allow_negative_numbers = true))]
    pub gain: Option<f64>,
    /// Offset d of the multifractal (eq. 4.12) [default: 1].
    #[cfg_attr(feature = "cli", arg(long, allow_hyphen_values = true))]
    pub offset: Option<f64>,
    /// Gabor kernel magnitude K: the noise's standard deviation (phasor: its amplitude)
    /// [default: 1].
    #[cfg_attr(feature = "cli", arg(long, allow_negative_numbers = true))]
    pub k: Option<f64>,
    /// Gabor bandwidth a [default: 0.05].
    #[cfg_attr(feature = "cli", arg(long, allow_negative_numbers = true))]
    pub a: Option<f64>,
    /// Gabor frequency F0, cycles per unit [default: 0.0625].
    #[cfg_attr(feature = "cli", arg(long, allow_negative_numbers = true))]
    pub f0: Option<f64>,
    /// Gabor orientation ω0, radians [default: π/4].
    #[cfg_attr(feature = "cli", arg(long, allow_hyphen_values = true))]
    pub omega: Option<f64>,
    /// Gabor impulses per kernel, at most 10000 [default: 64].
    #[cfg_attr(feature = "cli", arg(long, allow_negative_numbers = true))]
    pub impulses: Option<f64>,
    /// Gabor: a random orientation per impulse.
    #[cfg_attr(feature = "cli", arg(long))]
    pub isotropic: bool,
    /// Phasor noise's profile of the phase: sine, square or sawtooth [default: sine].
    #[cfg_attr(feature = "cli", arg(long, value_enum))]
    pub profile: Option<Profile>,
    /// Seed.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = 0))]
    pub seed: u64,
    /// Arithmetic of Perlin noise and fBm: f64, or f32 — single precision with its own
    /// 32-bit lattice hash, a different noise (coordinates clamped to ±2^24), about twice as
    /// fast [default: f64].
    #[cfg_attr(feature = "cli", arg(long, value_enum))]
    pub precision: Option<Precision>,
}

/// Which kinds each parameter applies to, as a message names them.
const FRACTAL_KINDS: &str = "the fractal kinds (fbm, turbulence, marble, multifractal, wood)";

impl NoiseRequest {
    /// The request's own rules, in the messages every front end prints (`spelling` names
    /// the fields): a parameter of another kind is refused, naming the kinds it belongs to;
    /// octaves are 1 to [`MAX_OCTAVES`]; impulses at most [`MAX_IMPULSES_PER_KERNEL`]. The
    /// noise itself checks the rest when it is made ([`NoiseRequest::field`]).
    ///
    /// # Errors
    /// [`Error::InvalidInput`] with the first rule broken.
    pub fn check(&self, spelling: Spelling) -> Result<()> {
        let fractal = matches!(
            self.kind,
            NoiseKind::Fbm | NoiseKind::Turbulence | NoiseKind::Marble | NoiseKind::Multifractal | NoiseKind::Wood
        );
        let spectral = matches!(self.kind, NoiseKind::Gabor | NoiseKind::Phasor);
        let perlin = matches!(self.kind, NoiseKind::Perlin | NoiseKind::Fbm);
        let phasor = self.kind == NoiseKind::Phasor;
        let multifractal = self.kind == NoiseKind::Multifractal;
        let kind = |value: &str| spelling.with("kind", value);
        let [spectral_kinds, phasor_kind, multifractal_kind, perlin_kinds] =
            ["gabor and phasor", "phasor", "multifractal", "perlin and fbm"].map(kind);
        let rules: [(&str, bool, bool, &str); 12] = [
            ("octaves", self.octaves.is_some(), fractal, FRACTAL_KINDS),
            ("lacunarity", self.lacunarity.is_some(), fractal, FRACTAL_KINDS),
            ("gain", self.gain.is_some(), fractal, FRACTAL_KINDS),
            ("offset", self.offset.is_some(), multifractal, &multifractal_kind),
            ("k", self.k.is_some(), spectral, &spectral_kinds),
            ("a", self.a.is_some(), spectral, &spectral_kinds),
            ("f0", self.f0.is_some(), spectral, &spectral_kinds),
            ("omega", self.omega.is_some(), spectral, &spectral_kinds),
            ("impulses", self.impulses.is_some(), spectral, &spectral_kinds),
            ("isotropic", self.isotropic, spectral, &spectral_kinds),
            ("profile", self.profile.is_some(), phasor, &phasor_kind),
            ("precision", self.precision.is_some(), perlin, &perlin_kinds),
        ];
        if let Some((field, _, _, kinds)) = rules.iter().find(|&&(_, given, applies, _)| given && !applies) {
            return Err(Error::InvalidInput(format!(
                "{} applies only to {kinds}, not to {}",
                spelling.of(field),
                kind(&format!("{:?}", self.kind).to_lowercase())
            )));
        }
        if let Some(octaves) = self.octaves.filter(|&o| o == 0 || o > MAX_OCTAVES) {
            return Err(Error::InvalidInput(format!(
                "{} must be 1 to {MAX_OCTAVES}",
                spelling.with("octaves", octaves)
            )));
        }
        if let Some(impulses) = self.impulses.filter(|&i| i > MAX_IMPULSES_PER_KERNEL) {
            return Err(Error::InvalidInput(format!(
                "{} must be at most {MAX_IMPULSES_PER_KERNEL}",
                spelling.with("impulses", impulses)
            )));
        }
        Ok(())
    }

    /// The noise's full specification: each unset parameter its kind's default.
    pub fn spec(&self) -> NoiseSpec {
        let fractal = Fractal::default();
        let gabor = GaborParams::default();
        NoiseSpec {
            kind: self.kind,
            fractal: Fractal {
                octaves: self.octaves.unwrap_or(self.kind.default_octaves()),
                lacunarity: self.lacunarity.unwrap_or(fractal.lacunarity),
                gain: self.gain.unwrap_or(fractal.gain),
                offset: self.offset.unwrap_or(fractal.offset),
                ..fractal
            },
            gabor: GaborParams {
                k: self.k.unwrap_or(gabor.k),
                a: self.a.unwrap_or(gabor.a),
                f0: self.f0.unwrap_or(gabor.f0),
                omega0: self.omega.unwrap_or(gabor.omega0),
                impulses_per_kernel: self.impulses.unwrap_or(gabor.impulses_per_kernel),
                isotropic: self.isotropic,
            },
            profile: self.profile.unwrap_or_default(),
            seed: self.seed,
            precision: self.precision.unwrap_or_default(),
        }
    }

    /// The checked request's noise field.
    ///
    /// # Errors
    /// [`NoiseRequest::check`]'s, then the noise's own (a non-finite or out-of-range value).
    pub fn field(&self, spelling: Spelling) -> Result<NoiseField> {
        self.check(spelling)?;
        NoiseField::new(&self.spec())
    }

    /// The noise at `points`: in the plane (x, y), as `asperity noise` samples its pictures,
    /// when `planar`; else in space with the global frame.
    ///
    /// # Errors
    /// As [`NoiseRequest::field`].
    pub fn values_at(&self, points: &[DVec3], planar: bool, spelling: Spelling) -> Result<Vec<f64>> {
        let field = self.field(spelling)?;
        Ok(if planar {
            let plane: Vec<DVec2> = points.iter().map(|p| p.truncate()).collect();
            field.sample2_batch(&plane)
        } else {
            let frames = vec![Frame { tangent: DVec3::X, bitangent: DVec3::Y }; points.len()];
            field.sample3_batch(points, &frames)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::request::from_fields;

    #[test]
    fn a_parameter_of_another_kind_is_refused_in_each_front_ends_spelling() {
        let request = NoiseRequest { octaves: Some(4), ..NoiseRequest::default() };
        let message = |s| request.check(s).unwrap_err().to_string();
        assert!(message(Spelling::Flag).contains("--octaves applies only to the fractal kinds"));
        assert!(message(Spelling::Keyword).contains("octaves= applies only to"));
        assert!(message(Spelling::Keyword).ends_with("not to kind=perlin"), "{}", message(Spelling::Keyword));
        assert!(message(Spelling::Member).contains("option .octaves applies only to"));
        let gabor = NoiseRequest { kind: NoiseKind::Gabor, profile: Some(Profile::Square), ..NoiseRequest::default() };
        assert!(
            gabor.check(Spelling::Flag).unwrap_err().to_string().contains("--profile applies only to --kind phasor")
        );
    }

    #[test]
    fn fields_are_read_strictly() {
        let request: NoiseRequest =
            from_fields(r#"{"kind": "fbm", "octaves": 3, "gain": null}"#, Spelling::Keyword).unwrap();
        assert_eq!(request, NoiseRequest { kind: NoiseKind::Fbm, octaves: Some(3), ..NoiseRequest::default() });
        let unknown = from_fields::<NoiseRequest>(r#"{"octave": 3}"#, Spelling::Keyword).unwrap_err().to_string();
        assert!(unknown.contains("octave= is not an option here") && unknown.contains("octaves="), "{unknown}");
        let wrong = from_fields::<NoiseRequest>(r#"{"octaves": "six"}"#, Spelling::Member).unwrap_err().to_string();
        assert!(wrong.starts_with("invalid input: option .octaves: invalid type"), "{wrong}");
    }

    #[test]
    fn every_parameter_changes_the_noise_of_its_kind() {
        let points: Vec<DVec3> = (0..64).map(|i| DVec3::new(0.37 * f64::from(i), 0.11 * f64::from(i), 0.5)).collect();
        let values = |r: &NoiseRequest| r.values_at(&points, false, Spelling::Flag).unwrap();
        let fbm = NoiseRequest { kind: NoiseKind::Fbm, ..NoiseRequest::default() };
        let gabor = NoiseRequest { kind: NoiseKind::Gabor, ..NoiseRequest::default() };
        let changed = [
            (&fbm, NoiseRequest { octaves: Some(2), ..fbm.clone() }),
            (&fbm, NoiseRequest { lacunarity: Some(2.7), ..fbm.clone() }),
            (&fbm, NoiseRequest { gain: Some(0.8), ..fbm.clone() }),
            (&fbm, NoiseRequest { seed: 9, ..fbm.clone() }),
            (&gabor, NoiseRequest { k: Some(2.0), ..gabor.clone() }),
            (&gabor, NoiseRequest { a: Some(0.08), ..gabor.clone() }),
            (&gabor, NoiseRequest { f0: Some(0.2), ..gabor.clone() }),
            (&gabor, NoiseRequest { omega: Some(0.3), ..gabor.clone() }),
            (&gabor, NoiseRequest { isotropic: true, ..gabor.clone() }),
        ];
        for (base, request) in changed {
            assert_ne!(values(base), values(&request), "{request:?}");
        }
    }
}
