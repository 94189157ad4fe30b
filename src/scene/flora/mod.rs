//! Flora by stochastic Lindenmayer systems (Lindenmayer 1968; seed 002, "Flora"): an
//! n-ary tree of nodes, each annotated with a length, a radius, and a yaw and pitch
//! relative to its parent, grown from an axiom by production rules chosen at random by
//! weight. Internal nodes become branches — tapered tubes, a node's most upright internal
//! child continuing its tube through a shared ring and the others starting tubes of their
//! own sunk into it, so no gap shows — and leaf nodes become clusters of leaves (or a whorl
//! of petals or fronds). Rules are TOML; the presets are the seed's three examples.

mod tube;

use std::collections::BTreeMap;
use std::path::Path;

use glam::{DQuat, DVec3};
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::mesh::{Mesh, Rgb};
use crate::noise::hash::{Stream, derive_seed};

/// The most nodes a plant may have (rules that grow past it are refused).
pub const MAX_NODES: usize = 200_000;

/// The most leaves a plant may have.
pub const MAX_LEAVES: usize = 4_000_000;

/// The plant request (#38): what `asperity flora` asks for, a preset's rules or a rules
/// file's, grown with a seed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
pub struct FloraRequest {
    /// A preset from seed 002: a cottonwood-like tree, a palm (a chain) or a flower.
    #[cfg_attr(feature = "cli", arg(long, required_unless_present = "rules", conflicts_with = "rules"))]
    pub preset: Option<FloraPreset>,
    /// Rules as TOML (the presets' format: src/scene/flora/*.toml).
    #[cfg_attr(feature = "cli", arg(long))]
    pub rules: Option<std::path::PathBuf>,
    /// Seed of the productions and annotations.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = 0))]
    pub seed: u64,
    /// Vertices around each branch ring (3 to 64).
    #[cfg_attr(feature = "cli", arg(long, default_value_t = FloraRequest::default().sides))]
    pub sides: u32,
}

impl Default for FloraRequest {
    fn default() -> Self {
        FloraRequest { preset: None, rules: None, seed: 0, sides: 8 }
    }
}

impl FloraRequest {
    /// The rules grown: the rules file's, or the preset's.
    ///
    /// # Errors
    /// Both or neither given; a rules file that cannot be read ([`FloraRules::read`]).
    pub fn rules(&self) -> Result<FloraRules> {
        match (&self.rules, self.preset) {
            (Some(path), None) => FloraRules::read(path),
            (None, Some(preset)) => Ok(preset.rules()),
            _ => Err(Error::InvalidInput("a plant grows from a preset or from rules: give one".into())),
        }
    }

    /// What the plant grows from, as the report names it: the rules file, or the preset.
    pub fn source(&self) -> String {
        match (&self.rules, self.preset) {
            (Some(path), _) => path.display().to_string(),
            (None, Some(preset)) => format!("{preset:?}").to_lowercase(),
            (None, None) => String::new(),
        }
    }

    /// The plant ([`plant`]).
    ///
    /// # Errors
    /// As [`FloraRequest::rules`] and [`plant`].
    pub fn plant(&self) -> Result<Plant> {
        plant(&self.rules()?, self.seed, self.sides)
    }
}

/// A named preset: the seed's cottonwood, palm and flower.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum FloraPreset {
    /// A broadleaf tree: a trunk with boughs and twigs.
    Cottonwood,
    /// A chain of stem nodes crowned by fronds.
    Palm,
    /// Several stems sharing a root, each ending in a head of petals.
    Flower,
}

impl FloraPreset {
    /// The preset's rules as TOML text.
    pub fn text(self) -> &'static str {
        match self {
            FloraPreset::Cottonwood => include_str!("cottonwood.toml"),
            FloraPreset::Palm => include_str!("palm.toml"),
            FloraPreset::Flower => include_str!("flower.toml"),
        }
    }

    /// The preset's rules.
    pub fn rules(self) -> FloraRules {
        FloraRules::parse(self.text()).expect("the presets parse")
    }
}

/// How the leaves of a leaf node are placed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Arrangement {
    /// Along the leaf node, at random turns.
    Scattered,
    /// All at the node's base, evenly turned (petals, palm fronds).
    Whorl,
}

/// The leaves of leaf nodes.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LeafStyle {
    /// Leaf length.
    pub size: f64,
    /// Half the leaf's width, relative to its length.
    #[serde(default = "default_leaf_width")]
    pub width: f64,
    /// Leaves per leaf node.
    pub count: u32,
    /// Leaf colour.
    pub color: Rgb,
    /// Angle between a leaf and its node's axis, degrees.
    pub droop: f64,
    /// Placement.
    pub arrangement: Arrangement,
}

fn default_leaf_width() -> f64 {
    0.18
}

/// One child a production makes: its symbol, and ranges its annotations are drawn from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Child {
    /// The child's symbol (a symbol without rules is a leaf).
    pub symbol: String,
    /// Turn around the parent's axis, degrees (a range drawn uniformly).
    pub yaw: [f64; 2],
    /// Tilt away from the parent's axis, degrees.
    pub pitch: [f64; 2],
    /// Length relative to the parent's.
    pub length: [f64; 2],
    /// Radius relative to the parent's.
    pub radius: f64,
}

/// One alternative of a symbol's rule, chosen with probability proportional to `weight`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Production {
    /// Relative probability.
    pub weight: f64,
    /// The children it makes.
    pub children: Vec<Child>,
}

/// A stochastic L-system for a plant.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FloraRules {
    /// The root node's symbol.
    pub axiom: String,
    /// Production steps; nodes at this depth are leaves.
    pub depth: u32,
    /// The root node's length.
    pub length: f64,
    /// The root node's radius.
    pub radius: f64,
    /// A tube's end radius relative to its last node's.
    pub taper: f64,
    /// Branch colour.
    pub bark: Rgb,
    /// Leaves.
    pub leaf: LeafStyle,
    /// Each symbol's alternatives.
    pub rules: BTreeMap<String, Vec<Production>>,
}

impl FloraRules {
    /// Reads rules from a TOML file; errors name the file and line.
    ///
    /// # Errors
    /// [`Error::Io`] or [`Error::Parse`].
    pub fn read(path: &Path) -> Result<Self> {
        crate::io::text::read_toml_file(path, Self::parse)
    }

    /// Parses and checks rules; errors carry the 1-based line when known.
    pub fn parse(text: &str) -> std::result::Result<Self, (Option<usize>, String)> {
        crate::io::text::parse_toml(text, Self::check)
    }

    fn check(&self) -> std::result::Result<(), String> {
        let positive = |v: f64| v.is_finite() && v > 0.0;
        if self.axiom.is_empty() {
            return Err("the axiom is empty".into());
        }
        if self.depth > 64 {
            return Err(format!("depth {}: at most 64", self.depth));
        }
        if !positive(self.length) || !positive(self.radius) || !positive(self.taper) {
            return Err("length, radius and taper must be positive".into());
        }
        let leaf = &self.leaf;
        if !positive(leaf.size) || !positive(leaf.width) || leaf.count > 1000 || !(0.0..=180.0).contains(&leaf.droop) {
            return Err("leaf: size and width must be positive, count at most 1000, droop 0 to 180 degrees".into());
        }
        for (symbol, productions) in &self.rules {
            if productions.is_empty() || productions.iter().any(|p| !positive(p.weight)) {
                return Err(format!("rules.{symbol}: every alternative needs a positive weight"));
            }
            for child in productions.iter().flat_map(|p| &p.children) {
                let ordered = |r: [f64; 2]| r[0].is_finite() && r[1].is_finite() && r[0] <= r[1];
                if !ordered(child.yaw) || !ordered(child.pitch) || !ordered(child.length) {
                    return Err(format!("rules.{symbol}: child `{}`: ranges must be finite [low, high]", child.symbol));
                }
                if child.length[0] <= 0.0 || !positive(child.radius) {
                    return Err(format!(
                        "rules.{symbol}: child `{}`: length and radius factors must be positive",
                        child.symbol
                    ));
                }
            }
        }
        Ok(())
    }
}

/// A node of the grown tree.
#[derive(Debug, Clone, PartialEq)]
pub struct Node {
    /// Its symbol.
    pub symbol: String,
    /// Where it starts (its parent's end).
    pub base: DVec3,
    /// Its orientation: local +z is its axis.
    pub orientation: DQuat,
    /// Length.
    pub length: f64,
    /// Radius at its base.
    pub radius: f64,
    /// Yaw relative to the parent, degrees.
    pub yaw: f64,
    /// Pitch relative to the parent, degrees.
    pub pitch: f64,
    /// Depth below the root.
    pub depth: u32,
    /// Children (indices into the tree's nodes).
    pub children: Vec<usize>,
}

impl Node {
    /// Unit axis.
    pub fn axis(&self) -> DVec3 {
        self.orientation * DVec3::Z
    }

    /// Where it ends.
    pub fn tip(&self) -> DVec3 {
        self.base + self.axis() * self.length
    }
}

/// Grows the n-ary tree of `rules` from the seed: breadth first, each node below `depth`
/// with rules for its symbol replaced by one of its alternatives (drawn by weight), every
/// annotation drawn from its range. Node 0 is the root, standing on the origin along +z.
///
/// # Errors
/// [`Error::InvalidInput`] when the tree would exceed [`MAX_NODES`].
pub fn grow(rules: &FloraRules, seed: u64) -> Result<Vec<Node>> {
    let mut draw = Stream::new(derive_seed(seed, "flora"));
    let mut nodes = vec![Node {
        symbol: rules.axiom.clone(),
        base: DVec3::ZERO,
        orientation: DQuat::IDENTITY,
        length: rules.length,
        radius: rules.radius,
        yaw: 0.0,
        pitch: 0.0,
        depth: 0,
        children: Vec::new(),
    }];
    let mut next = 0;
    while next < nodes.len() {
        let parent = nodes[next].clone();
        if let Some(alternatives) = rules.rules.get(&parent.symbol).filter(|_| parent.depth < rules.depth) {
            let total: f64 = alternatives.iter().map(|p| p.weight).sum();
            let mut pick = draw.uniform(0.0, total);
            let production = alternatives
                .iter()
                .find(|p| {
                    pick -= p.weight;
                    pick < 0.0
                })
                .unwrap_or(&alternatives[alternatives.len() - 1]);
            for child in &production.children {
                if nodes.len() >= MAX_NODES {
                    return Err(Error::InvalidInput(format!(
                        "the rules grow more than {MAX_NODES} nodes by depth {}: lower the depth or the children",
                        parent.depth + 1
                    )));
                }
                let yaw = draw.uniform(child.yaw[0], child.yaw[1]);
                let pitch = draw.uniform(child.pitch[0], child.pitch[1]);
                let length = parent.length * draw.uniform(child.length[0], child.length[1]);
                let orientation = (parent.orientation
                    * DQuat::from_rotation_z(yaw.to_radians())
                    * DQuat::from_rotation_x(pitch.to_radians()))
                .normalize();
                let index = nodes.len();
                nodes[next].children.push(index);
                nodes.push(Node {
                    symbol: child.symbol.clone(),
                    base: parent.tip(),
                    orientation,
                    length,
                    radius: parent.radius * child.radius,
                    yaw,
                    pitch,
                    depth: parent.depth + 1,
                    children: Vec::new(),
                });
            }
        }
        next += 1;
    }
    Ok(nodes)
}

/// A plant's meshes.
#[derive(Debug, Clone)]
pub struct Plant {
    /// The grown tree.
    pub nodes: Vec<Node>,
    /// The branches: closed tubes, one per chain of internal nodes.
    pub branches: Mesh,
    /// The leaves (thin two-sided quads).
    pub leaves: Mesh,
}

impl Plant {
    /// Branches and leaves in one mesh, coloured.
    pub fn mesh(&self) -> Mesh {
        let mut mesh = self.branches.clone();
        mesh.append(&self.leaves);
        mesh
    }
}

/// Grows and meshes a plant: `sides` vertices around each tube ring (3 to 64).
///
/// # Errors
/// As [`grow`]; [`Error::InvalidInput`] for `sides` out of range or a plant with no
/// branch and no leaf.
pub fn plant(rules: &FloraRules, seed: u64, sides: u32) -> Result<Plant> {
    if !(3..=64).contains(&sides) {
        return Err(Error::InvalidInput(format!("{sides} sides per branch ring: use 3 to 64")));
    }
    let nodes = grow(rules, seed)?;
    let leaf_nodes = nodes.iter().filter(|n| n.children.is_empty()).count();
    if leaf_nodes * rules.leaf.count as usize > MAX_LEAVES {
        return Err(Error::InvalidInput(format!(
            "{leaf_nodes} leaf nodes × {} leaves exceed {MAX_LEAVES} leaves: lower the depth or the leaf count",
            rules.leaf.count
        )));
    }
    let branches = tube::branches(&nodes, rules, sides);
    let leaves = leaves(&nodes, rules, seed);
    if branches.triangles.is_empty() && leaves.triangles.is_empty() {
        return Err(Error::InvalidInput("the rules grow nothing to draw".into()));
    }
    Ok(Plant { nodes, branches, leaves })
}

/// The leaves of every leaf node (a node without children): `count` diamonds of length
/// `size`, leaning `droop` degrees off the node's axis, scattered along the node at random
/// turns or in an even whorl at its base; colours vary by ±12 % per leaf.
fn leaves(nodes: &[Node], rules: &FloraRules, seed: u64) -> Mesh {
    let style = rules.leaf;
    let mut draw = Stream::new(derive_seed(seed, "leaves"));
    let mut mesh = Mesh::default();
    let mut colors = Vec::new();
    for node in nodes.iter().filter(|n| n.children.is_empty()) {
        for k in 0..style.count {
            let (turn, along) = match style.arrangement {
                Arrangement::Scattered => (draw.uniform(0.0, std::f64::consts::TAU), draw.uniform(0.0, 1.0)),
                Arrangement::Whorl => {
                    (std::f64::consts::TAU * f64::from(k) / f64::from(style.count) + draw.uniform(-0.1, 0.1), 0.0)
                }
            };
            let frame = node.orientation
                * DQuat::from_rotation_z(turn)
                * DQuat::from_rotation_x((style.droop + draw.uniform(-8.0, 8.0)).to_radians());
            let (axis, side) = (frame * DVec3::Z, frame * DVec3::X);
            let base = node.base + node.axis() * node.length * along;
            let half_width = style.width * style.size;
            let start = mesh.positions.len() as u32;
            mesh.positions.extend([
                base,
                base + axis * (0.4 * style.size) + side * half_width,
                base + axis * style.size,
                base + axis * (0.4 * style.size) - side * half_width,
            ]);
            mesh.triangles.push([start, start + 1, start + 2]);
            mesh.triangles.push([start, start + 2, start + 3]);
            let shade = draw.uniform(0.88, 1.12);
            let color = style.color.map(|c| (f64::from(c) * shade).round().clamp(0.0, 255.0) as u8);
            colors.extend([color; 4]);
        }
    }
    mesh.colors = Some(colors);
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_preset_grows_closed_branches_and_leaves_the_same_for_a_seed() {
        for preset in [FloraPreset::Cottonwood, FloraPreset::Palm, FloraPreset::Flower] {
            let rules = preset.rules();
            let plant = plant(&rules, 3, 8).unwrap();
            let report = plant.branches.validate();
            assert!(report.is_closed_manifold(), "{preset:?}: {report:?}");
            assert_eq!(report.inconsistently_oriented_edges, 0, "{preset:?}");
            assert!(plant.leaves.face_count() > 0, "{preset:?} has leaves");
            let again = super::plant(&rules, 3, 8).unwrap();
            assert_eq!(plant.mesh().positions, again.mesh().positions);
            let other = super::plant(&rules, 4, 8).unwrap();
            assert_ne!(plant.mesh().positions, other.mesh().positions, "{preset:?}: the seed matters");
        }
    }

    #[test]
    fn a_palm_is_a_chain_and_a_flower_shares_one_root() {
        let palm = grow(&FloraPreset::Palm.rules(), 1).unwrap();
        assert!(palm.iter().all(|n| n.children.len() <= 1), "a linked list");
        assert_eq!(palm.len(), 13);
        let flower = grow(&FloraPreset::Flower.rules(), 1).unwrap();
        assert!((3..=5).contains(&flower[0].children.len()));
        assert!(flower[1..].iter().all(|n| n.children.len() <= 1), "each stem is a chain");
    }

    #[test]
    fn children_follow_their_annotations() {
        let rules = FloraPreset::Cottonwood.rules();
        let nodes = grow(&rules, 9).unwrap();
        for parent in &nodes {
            for &c in &parent.children {
                let child = &nodes[c];
                assert!((child.base - parent.tip()).length() < 1e-12, "children start at the parent's end");
                let angle = parent.axis().dot(child.axis()).clamp(-1.0, 1.0).acos().to_degrees();
                assert!((angle - child.pitch).abs() < 1e-6, "pitch is the angle to the parent's axis");
                assert!(child.depth == parent.depth + 1 && child.depth <= rules.depth);
            }
        }
    }

    #[test]
    fn bad_rules_are_refused_with_their_line() {
        let (line, msg) = FloraRules::parse("axiom = \"a\"\ndepth = \"deep\"\n").unwrap_err();
        assert_eq!(line, Some(2), "{msg}");
        let mut text = FloraPreset::Palm.text().replace("weight = 0.7", "weight = -1");
        assert!(FloraRules::parse(&text).unwrap_err().1.contains("positive weight"));
        text = FloraPreset::Palm.text().replace("depth = 12", "depth = 12\ncolour = 3");
        assert!(FloraRules::parse(&text).is_err(), "unknown keys are refused");
        let mut explosive = FloraPreset::Cottonwood.rules();
        explosive.depth = 40;
        assert!(grow(&explosive, 0).unwrap_err().to_string().contains("nodes"));
    }
}
