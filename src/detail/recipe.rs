//! Recipes: a TOML file listing detail steps (operator, level, selection, parameters,
//! seed), documented in `docs/recipes.md`. Parsing rejects unknown keys, so a misspelt
//! parameter is an error naming the line instead of a silently ignored setting.

use std::path::Path;

use serde::Deserialize;

use crate::analysis::FeatureClass;
use crate::error::Result;
use crate::hierarchy::HierarchyRequest;
use crate::noise::NoiseKind;

/// A parsed recipe.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Recipe {
    /// Seed of every step that does not name its own.
    #[serde(default)]
    pub seed: u64,
    /// How to build the hierarchy (the `[hierarchy]` table, any field of the hierarchy's
    /// request): every front end applies it with [`HierarchyRequest::options_over`], its own
    /// settings first; library callers of [`super::apply`] pass
    /// [`super::DetailOptions::simplify`] made so.
    #[serde(default)]
    pub hierarchy: HierarchyRequest,
    /// The steps, applied in order within each level, coarse levels first.
    #[serde(default, rename = "step")]
    pub steps: Vec<Step>,
    /// Vertex colours by how far detail moved each vertex (thesis Fig. 5.6: "black coloring
    /// at the deformed areas"); none by default.
    #[serde(default)]
    pub color: Option<ColorSection>,
}

/// The `[color]` table: each vertex of the result coloured between `rest` and `deformed`
/// by its displacement from its undeformed position, as a share s of the largest: `rest`
/// up to s = `from`, `deformed` from s = `to`, linear between.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ColorSection {
    /// Colour of the vertices moved least (sRGB, 0 to 255).
    pub rest: [u8; 3],
    /// Colour of the vertices moved most.
    pub deformed: [u8; 3],
    /// Share of the largest displacement up to which a vertex keeps `rest` (default 0).
    #[serde(default)]
    pub from: f64,
    /// Share of the largest displacement from which a vertex is `deformed` (default 1).
    #[serde(default = "one")]
    pub to: f64,
}

fn one() -> f64 {
    1.0
}

impl ColorSection {
    fn check(&self) -> std::result::Result<(), String> {
        if !((0.0..1.0).contains(&self.from) && self.from < self.to && self.to <= 1.0) {
            return Err(format!("color needs 0 <= from < to <= 1 (from = {}, to = {})", self.from, self.to));
        }
        Ok(())
    }

    /// The colour of each vertex of `positions` displaced from `rest`.
    pub fn colors(&self, positions: &[glam::DVec3], rest: &[glam::DVec3]) -> Vec<[u8; 3]> {
        let moved: Vec<f64> = positions.iter().zip(rest).map(|(p, r)| p.distance(*r)).collect();
        let largest = moved.iter().copied().fold(0.0, f64::max);
        moved
            .iter()
            .map(|&d| {
                let share = if largest > 0.0 { d / largest } else { 0.0 };
                let t = ((share - self.from) / (self.to - self.from)).clamp(0.0, 1.0);
                crate::mesh::blend_rgb(self.rest, self.deformed, t)
            })
            .collect()
    }
}

/// Which operator a step runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum OperatorKind {
    /// Procedural displacement (eq. 4.5, 4.14, 4.15; §4.7.3).
    Noise,
    /// Noise with level-modulated parameters and a random per-centre shift (§4.7.5.2).
    Variation,
    /// Noise restricted by feature classes (§4.7.4); needs `select.features`.
    Feature,
    /// Extensions with 2-ring propagation (Algorithm 5).
    Organic,
    /// Tapering (eq. 4.6–4.7).
    Taper,
    /// Twisting (eq. 4.8–4.9).
    Twist,
    /// Loop-mask smoothing (§4.7.1.2).
    Smooth,
    /// Local 4-8 subdivision around vertices (§4.7.1.1).
    Subdivide,
}

/// One step.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Step {
    /// The operator.
    pub op: OperatorKind,
    /// Hierarchy level: 0 is the base domain, counting towards the input; negative values
    /// count back from the input (-1 is the input's level). Clamped to the hierarchy.
    #[serde(default = "finest")]
    pub level: i64,
    /// The step's seed (default: derived from the recipe's seed and the step's index).
    pub seed: Option<u64>,
    /// Which vertices (default: all).
    #[serde(default)]
    pub select: Selection,
    /// Noise parameters (noise, variation, feature, organic).
    #[serde(default)]
    pub noise: NoiseParams,
    /// Taper and twist parameters.
    #[serde(default)]
    pub geometric: GeometricParams,
    /// Smoothing parameters.
    #[serde(default)]
    pub smooth: SmoothParams,
    /// Subdivision parameters (also the organic operator's optional pre-subdivision).
    #[serde(default)]
    pub subdivide: SubdivideParams,
    /// Organic operator parameters.
    #[serde(default)]
    pub organic: OrganicParams,
}

fn finest() -> i64 {
    -1
}

/// A vertex selection: every clause given must hold (they combine by "and"); the
/// independent-set clause, if any, thins the result last.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Selection {
    /// Inside a box, in coordinates normalised to the input's bounding box (0 to 1).
    pub r#box: Option<BoxClause>,
    /// Inside a sphere: centre normalised to the bounding box, radius a fraction of its diagonal.
    pub sphere: Option<SphereClause>,
    /// One side of an axis-aligned plane, normalised coordinates ("vertical component above z").
    pub half_space: Option<HalfSpaceClause>,
    /// A curvature range (scale-free: mean, k1, k2 times the diagonal; Gaussian times its square).
    pub curvature: Option<CurvatureClause>,
    /// Feature classes on or off (Algorithm 4 propagation optional).
    pub features: Option<FeatureClause>,
    /// k-rings around seed vertices (input ids) or the vertices nearest given points.
    pub around: Option<AroundClause>,
    /// A maximal independent set with k-ring exclusion (§5.2.0.1).
    pub independent: Option<IndependentClause>,
}

/// `box = { min = [x, y, z], max = [x, y, z] }`.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoxClause {
    /// Lower corner (normalised).
    pub min: [f64; 3],
    /// Upper corner (normalised).
    pub max: [f64; 3],
}

/// `sphere = { center = [x, y, z], radius = r }`.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SphereClause {
    /// Centre (normalised).
    pub center: [f64; 3],
    /// Radius, fraction of the diagonal.
    pub radius: f64,
}

/// An axis name.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Axis {
    /// x.
    X,
    /// y.
    Y,
    /// z.
    #[default]
    Z,
}

impl Axis {
    /// 0, 1 or 2.
    pub fn index(self) -> usize {
        self as usize
    }
}

/// `half_space = { axis = "z", above = 0.6 }` (or `below`).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HalfSpaceClause {
    /// The axis.
    #[serde(default)]
    pub axis: Axis,
    /// Keep vertices whose normalised coordinate is at least this.
    pub above: Option<f64>,
    /// Keep vertices whose normalised coordinate is at most this.
    pub below: Option<f64>,
}

/// Which curvature.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum CurvatureKind {
    /// Mean curvature H.
    Mean,
    /// Gaussian curvature K.
    Gaussian,
    /// Maximum principal curvature.
    K1,
    /// Minimum principal curvature.
    K2,
}

/// `curvature = { kind = "gaussian", min = -1.0, max = 0.0 }`.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CurvatureClause {
    /// Which curvature.
    pub kind: CurvatureKind,
    /// Lower bound (scale-free).
    pub min: Option<f64>,
    /// Upper bound (scale-free).
    pub max: Option<f64>,
}

/// On the features, or off them.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum FeatureMode {
    /// Only feature vertices.
    #[default]
    On,
    /// Only non-feature vertices.
    Off,
}

/// `features = { classes = ["strong", "corner"], mode = "on", propagate = 1 }`.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FeatureClause {
    /// Classes that count as features: "corner", "strong", "weak".
    #[serde(default = "sharp_classes")]
    pub classes: Vec<ClassName>,
    /// On or off the features.
    #[serde(default)]
    pub mode: FeatureMode,
    /// Passes of Algorithm 4's propagation (a vertex with two feature neighbours joins).
    #[serde(default)]
    pub propagate: usize,
}

fn sharp_classes() -> Vec<ClassName> {
    vec![ClassName::Corner, ClassName::Strong]
}

/// A feature class name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ClassName {
    /// Corner vertices.
    Corner,
    /// Strong-edge vertices.
    Strong,
    /// Weak-edge vertices.
    Weak,
    /// Face (smooth) vertices.
    Face,
}

impl ClassName {
    /// The analysis class.
    pub fn class(self) -> FeatureClass {
        match self {
            ClassName::Corner => FeatureClass::Corner,
            ClassName::Strong => FeatureClass::StrongEdge,
            ClassName::Weak => FeatureClass::Weak,
            ClassName::Face => FeatureClass::Face,
        }
    }
}

/// `around = { vertices = [12, 40], points = [[0.5, 0.5, 1.0]], rings = 2 }`.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AroundClause {
    /// Seed vertices, by input id.
    #[serde(default)]
    pub vertices: Vec<u32>,
    /// Seed points (normalised); each picks its nearest vertex at the step's level.
    #[serde(default)]
    pub points: Vec<[f64; 3]>,
    /// Rings around each seed (0: the seeds only).
    #[serde(default)]
    pub rings: usize,
}

/// `independent = { exclusion = 2 }`.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IndependentClause {
    /// Every chosen vertex removes its k-ring from the candidates.
    #[serde(default = "two")]
    pub exclusion: usize,
    /// Visit candidates in a seeded random order instead of by id.
    #[serde(default = "yes")]
    pub shuffle: bool,
}

fn two() -> usize {
    2
}

fn yes() -> bool {
    true
}

/// Displacement direction.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Direction {
    /// Along the normal (eq. 4.5).
    #[default]
    Normal,
    /// Against the normal (eq. 4.14).
    Inward,
    /// Along the diffusion direction (§5.2.2).
    Diffusion,
    /// Along normal × diffusion (§5.2.2).
    NormalCrossDiffusion,
}

/// Which level number l divides a step's displacement (eq. 4.5, p ← p + (nl/l)·n(p)).
///
/// Eq. 4.4 calls l "the level of detail of the vertex in the variable resolution
/// representation", and §4.2 gives each vertex its own ("Each vertex v belongs to a level of
/// detail given by an integer number l"): that is [`Attenuate::Vertex`]. It makes a step's
/// displacement vary between neighbours of different levels — a base vertex among
/// input-level ones moves 1/L as far — which is the dotted field #26 B7 removes, so a
/// recipe says which it wants; the default, [`Attenuate::Step`], divides every vertex by the
/// level of the step ("the base domain will be less modified and the original mesh will
/// suffer the most significant changes"), continuous over the surface. In recipes `true`
/// means `"step"` and `false` `"none"`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum Attenuate {
    /// No division.
    None,
    /// l of the step's level: 1 at the input's level, one more per coarser level.
    #[default]
    Step,
    /// l of each vertex: the level of the hierarchy it first belongs to, 1 for vertices
    /// of the input's level only, L + 1 for base vertices.
    Vertex,
}

impl<'de> Deserialize<'de> for Attenuate {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> std::result::Result<Self, D::Error> {
        #[derive(Deserialize)]
        #[serde(untagged)]
        enum Written {
            Flag(bool),
            Name(String),
            Other(serde::de::IgnoredAny),
        }
        let expected = "attenuate: expected true, false, \"step\", \"vertex\" or \"none\"";
        match Written::deserialize(deserializer)? {
            Written::Other(_) => Err(serde::de::Error::custom(expected)),
            Written::Flag(true) => Ok(Attenuate::Step),
            Written::Flag(false) => Ok(Attenuate::None),
            Written::Name(name) => match name.as_str() {
                "step" => Ok(Attenuate::Step),
                "vertex" => Ok(Attenuate::Vertex),
                "none" => Ok(Attenuate::None),
                other => Err(serde::de::Error::custom(format!("{expected}, not \"{other}\""))),
            },
        }
    }
}

/// Distance attenuation of propagated noise.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Attenuation {
    /// Only the ring's influence.
    None,
    /// Influence / max(1, d / mean edge length) (eq. 4.15).
    #[default]
    InverseDistance,
}

/// Per-ring propagation parameters (Table 5.1).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RingParams {
    /// Share of the noise this ring receives.
    pub influence: f64,
    /// Gabor K for this ring (default: the step's).
    pub k: Option<f64>,
    /// Gabor a for this ring (default: the step's).
    pub a: Option<f64>,
    /// Gabor F0 for this ring (default: the step's).
    pub f0: Option<f64>,
}

/// The `noise` table.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct NoiseParams {
    /// Noise kind.
    pub kind: NoiseKind,
    /// Peak displacement, fraction of the bounding-box diagonal (× K for Gabor and phasor
    /// noise): the bound no vertex of the step exceeds ([`crate::noise::NoiseField::unit`]).
    pub amplitude: f64,
    /// Features per bounding-box diagonal (Perlin lattice cells; Gabor and phasor cycles at
    /// the reference F0, 0.0625).
    pub frequency: f64,
    /// Octaves of the fractal kinds.
    pub octaves: u32,
    /// Lacunarity.
    pub lacunarity: f64,
    /// Gain.
    pub gain: f64,
    /// Multifractal offset.
    pub offset: f64,
    /// Gabor K.
    pub k: f64,
    /// Gabor a, the kernel's bandwidth, in the units where `frequency` cycles of the
    /// reference F0 span the diagonal: a larger a, a narrower kernel.
    pub a: f64,
    /// Gabor F0, the cosine's frequency in those units: cycles per diagonal are
    /// `frequency` × F0 / 0.0625 (0.125 doubles them).
    pub f0: f64,
    /// Gabor ω0, radians.
    pub omega: f64,
    /// Gabor impulses per kernel.
    pub impulses: f64,
    /// Gabor isotropic mode.
    pub isotropic: bool,
    /// Phasor noise's profile (sine, square, sawtooth).
    pub profile: crate::noise::Profile,
    /// Orient Gabor and phasor kernels by the diffusion direction (else by a fixed 3D
    /// direction projected on the tangent plane). Unset: true, unless `orientation` is given.
    pub follow_diffusion: Option<bool>,
    /// The 3D direction whose projection on each tangent plane orients Gabor and phasor
    /// kernels in place of the diffusion direction (Lagae et al. 2009, §5): with ω0 = π/2
    /// phasor stripes run along it, as combed hair runs from a crown down the z axis.
    pub orientation: Option<[f64; 3]>,
    /// Displacement direction.
    pub direction: Direction,
    /// Divide by a level number l (eq. 4.5; l = 1 at the input level, growing coarser):
    /// the step's or each vertex's ([`Attenuate`]).
    pub attenuate: Attenuate,
    /// Level-modulated lacunarity and gain (§4.7.3.1); default on for `variation`.
    pub modulate: Option<bool>,
    /// Displace vertices already noised by an earlier step.
    pub accumulate: bool,
    /// Propagation rings (Table 5.1); empty: no propagation.
    pub rings: Vec<RingParams>,
    /// Propagation attenuation (eq. 4.15).
    pub attenuation: Attenuation,
    /// Variation operator: random per-centre shift of lacunarity and amplitude (§5.2.0.1).
    pub shift: Option<f64>,
    /// Marble only: cycles of eq. 4.11's sine per bounding-box diagonal along x, measured
    /// apart from `frequency` (which then sets the turbulence's features alone). Unset, the
    /// sine runs on the noise-space p_x as the equation writes it, whose stripes the
    /// turbulence term drowns at any frequency.
    pub stripes: Option<f64>,
}

impl Default for NoiseParams {
    fn default() -> Self {
        NoiseParams {
            kind: NoiseKind::Turbulence,
            amplitude: 0.01,
            frequency: 8.0,
            octaves: 4,
            lacunarity: 2.0,
            gain: 0.5,
            offset: 1.0,
            k: 1.0,
            a: 0.05,
            f0: 0.0625,
            omega: std::f64::consts::FRAC_PI_4,
            impulses: 64.0,
            isotropic: false,
            profile: crate::noise::Profile::Sine,
            follow_diffusion: None,
            orientation: None,
            direction: Direction::Normal,
            attenuate: Attenuate::Step,
            modulate: None,
            accumulate: false,
            rings: Vec::new(),
            attenuation: Attenuation::InverseDistance,
            shift: None,
            stripes: None,
        }
    }
}

impl NoiseParams {
    /// Whether the kernels follow the diffusion direction: as asked, else unless an
    /// orientation is given.
    pub fn follows_diffusion(&self) -> bool {
        self.follow_diffusion.unwrap_or(self.orientation.is_none())
    }

    /// A parameter of another kind than `kind`'s would be ignored: it is refused (a value
    /// differing from the default counts as given).
    fn check_kind_parameters(&self) -> std::result::Result<(), String> {
        let d = NoiseParams::default();
        let ring_gabor = self.rings.iter().any(|r| r.k.is_some() || r.a.is_some() || r.f0.is_some());
        let gabor_only = [
            ("k", self.k != d.k),
            ("a", self.a != d.a),
            ("f0", self.f0 != d.f0),
            ("omega", self.omega != d.omega),
            ("impulses", self.impulses != d.impulses),
            ("isotropic", self.isotropic),
            ("rings' k, a and f0", ring_gabor),
            ("follow_diffusion", self.follow_diffusion.is_some()),
            ("orientation", self.orientation.is_some()),
        ];
        let kind = format!("{:?}", self.kind).to_lowercase();
        if !self.kind.is_spectral()
            && let Some((name, _)) = gabor_only.iter().find(|(_, given)| *given)
        {
            return Err(format!("noise {name} applies only to kind = \"gabor\" or \"phasor\", not to \"{kind}\""));
        }
        if let Some(o) = self.orientation {
            if self.follow_diffusion == Some(true) {
                return Err("noise orientation and follow_diffusion = true both orient the kernels: give one".into());
            }
            if !o.iter().all(|c| c.is_finite()) || o == [0.0; 3] {
                return Err(format!("noise orientation must be a non-zero finite 3D direction, not {o:?}"));
            }
        }
        if self.kind != NoiseKind::Phasor && self.profile != d.profile {
            return Err(format!("noise profile applies only to kind = \"phasor\", not to \"{kind}\""));
        }
        if self.kind != NoiseKind::Marble && self.stripes.is_some() {
            return Err(format!("noise stripes applies only to kind = \"marble\", not to \"{kind}\""));
        }
        if self.stripes.is_some_and(|c| !(c.is_finite() && c > 0.0)) {
            return Err("noise stripes must be a positive number of cycles per diagonal".into());
        }
        if self.kind != NoiseKind::Multifractal && self.offset != d.offset {
            return Err(format!("noise offset applies only to kind = \"multifractal\", not to \"{kind}\""));
        }
        Ok(())
    }
}

/// The `geometric` table (taper and twist).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct GeometricParams {
    /// The axis kept unchanged.
    pub axis: Axis,
    /// Taper: r = (1 + z)/scale; twist: θ = z·scale degrees.
    pub scale: f64,
    /// Map the axis coordinate to [-1, 1] over the input's bounding box (§4.7.2.1).
    pub normalize: bool,
    /// Subtracted from z before the equations, so that a restricted region can start
    /// unchanged (taper with scale 1, twist with any scale, are the identity at z = offset).
    pub offset: f64,
}

impl Default for GeometricParams {
    fn default() -> Self {
        GeometricParams { axis: Axis::Z, scale: 2.0, normalize: true, offset: 0.0 }
    }
}

/// The `smooth` table.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SmoothParams {
    /// Passes of the Loop masks.
    pub iterations: usize,
}

impl Default for SmoothParams {
    fn default() -> Self {
        SmoothParams { iterations: 1 }
    }
}

/// The `subdivide` table.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SubdivideParams {
    /// Concentric 4-8 steps (link edges, then alternately even and odd spokes).
    pub steps: usize,
}

impl Default for SubdivideParams {
    fn default() -> Self {
        SubdivideParams { steps: 2 }
    }
}

/// The `organic` table.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct OrganicParams {
    /// Extension height, fraction of the diagonal (scaled by 0.5 + |noise| per centre).
    pub height: f64,
    /// How far a random vertex's normal bends each extension (0: straight out).
    pub bend: f64,
    /// Weights of the centre, its 1-ring and its 2-ring (thesis: 1, 1/1.5, 1/2).
    pub rings: Vec<f64>,
    /// Local subdivision steps before extending (0: none).
    pub subdivide: usize,
    /// The second displacement of the mushroom planet (§5.2.0.1: "move the vertices to
    /// opposite directions creating a wide area at the top of the hill"): per ring, how far
    /// its vertices move away from the extension's axis, as a fraction of the extension's
    /// length (negative: towards it, thinning a stem). Empty: no widening.
    pub widen: Vec<f64>,
}

impl Default for OrganicParams {
    fn default() -> Self {
        OrganicParams { height: 0.05, bend: 0.3, rings: vec![1.0, 1.0 / 1.5, 0.5], subdivide: 0, widen: Vec::new() }
    }
}

impl Recipe {
    /// Reads and checks a recipe file.
    ///
    /// # Errors
    /// [`crate::Error::Parse`] naming the file and line for malformed TOML, unknown keys or
    /// invalid values; [`crate::Error::Io`] if the file cannot be read.
    pub fn read(path: &Path) -> Result<Recipe> {
        crate::io::text::read_toml_file(path, Recipe::parse)
    }

    /// Parses and checks recipe text; errors carry the 1-based line when known.
    pub fn parse(text: &str) -> std::result::Result<Recipe, (Option<usize>, String)> {
        crate::io::text::parse_toml(text, Recipe::check)
    }

    fn check(&self) -> std::result::Result<(), String> {
        for (i, step) in self.steps.iter().enumerate() {
            let op = format!("{:?}", step.op).to_lowercase();
            step.check().map_err(|m| format!("step {} ({op}): {m}", i + 1))?;
        }
        self.color.as_ref().map_or(Ok(()), ColorSection::check)
    }
}

impl Step {
    /// Refuses a parameter table the step's operator does not read (a table left at its
    /// defaults is accepted): a `smooth` table on a noise step would otherwise be ignored.
    fn check_tables_apply(&self) -> std::result::Result<(), String> {
        use OperatorKind as Op;
        let op = self.op;
        let tables = [
            (
                "noise",
                self.noise != NoiseParams::default(),
                matches!(op, Op::Noise | Op::Variation | Op::Feature | Op::Organic),
            ),
            ("geometric", self.geometric != GeometricParams::default(), matches!(op, Op::Taper | Op::Twist)),
            ("smooth", self.smooth != SmoothParams::default(), op == Op::Smooth),
            ("subdivide", self.subdivide != SubdivideParams::default(), op == Op::Subdivide),
            ("organic", self.organic != OrganicParams::default(), op == Op::Organic),
        ];
        match tables.iter().find(|(_, given, read)| *given && !read) {
            Some((name, _, _)) => {
                Err(format!("the {name} table does not apply to op = \"{}\"", format!("{op:?}").to_lowercase()))
            }
            None => Ok(()),
        }
    }

    fn check(&self) -> std::result::Result<(), String> {
        let n = &self.noise;
        let finite = [n.amplitude, n.frequency, n.lacunarity, n.gain, n.offset, n.k, n.a, n.f0, n.omega, n.impulses];
        if finite.iter().any(|v| !v.is_finite()) {
            return Err("noise parameters must be finite".into());
        }
        if n.frequency <= 0.0 || n.octaves == 0 || n.octaves > 16 {
            return Err("noise needs frequency > 0 and 1 to 16 octaves".into());
        }
        n.check_kind_parameters()?;
        if n.rings.iter().any(|r| !(r.influence.is_finite() && r.influence >= 0.0)) {
            return Err("ring influence must be a non-negative number".into());
        }
        if !(self.geometric.scale.is_finite() && self.geometric.offset.is_finite())
            || (self.op == OperatorKind::Taper && self.geometric.scale == 0.0)
        {
            return Err("geometric scale must be finite (and non-zero for a taper)".into());
        }
        if self.op == OperatorKind::Feature && self.select.features.is_none() {
            return Err("the feature operator needs select.features".into());
        }
        if self.smooth.iterations > 1000 || self.subdivide.steps > 8 || self.organic.subdivide > 8 {
            return Err("at most 1000 smoothing passes and 8 subdivision steps".into());
        }
        self.check_tables_apply()?;
        let o = &self.organic;
        if !(o.height.is_finite() && o.bend.is_finite()) || o.rings.iter().chain(&o.widen).any(|w| !w.is_finite()) {
            return Err("organic parameters must be finite".into());
        }
        if o.widen.len() > o.rings.len() {
            return Err(format!(
                "organic widen has {} weights for {} rings: one per ring at most",
                o.widen.len(),
                o.rings.len()
            ));
        }
        if let Some(s) = &self.select.sphere
            && (s.radius.is_nan() || s.radius <= 0.0)
        {
            return Err("sphere radius must be positive".into());
        }
        Ok(())
    }
}
