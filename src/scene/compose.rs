//! Seed 002's environment in one scene: a smooth midpoint-displacement terrain, water at
//! sea level, trees placed on land by height and slope, a cabin on a flat spot near the
//! middle with smoke rising from its chimney, and butterflies around it — meshes and one
//! glTF animation, all from one seed.

use glam::{DQuat, DVec2, DVec3};
use serde::{Deserialize, Serialize};

use super::butterflies::{ButterflyParams, Flight, body_mesh, fly, wing_mesh};
use super::cabin::cabin;
use super::flora::{FloraPreset, plant};
use super::smoke::{SmokeParams, smoke_frames};
use super::water::{WaterParams, opacity, surface_on, water_floor, waves_from_seed};
use crate::error::{Error, Result};
use crate::io::glb_scene::{GlbScene, Keys, SceneNode, Track};
use crate::mesh::Mesh;
use crate::noise::hash::{Stream, derive_seed};
use crate::terrain::{Method, Palette, Rect, TerrainParams, ramp_color};

/// Parameters of the scene: the request `asperity scene` flattens into its flags (#38;
/// the extent and relief are the library's alone), checked by [`compose`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
pub struct SceneParams {
    /// Seed of everything.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = 0))]
    pub seed: u64,
    /// Terrain grid points per side, 2^n + 1.
    #[cfg_attr(feature = "cli", arg(long = "size", value_name = "SIZE", default_value_t = SceneParams::default().terrain_size))]
    pub terrain_size: u64,
    /// Terrain side length, world units (metres).
    #[cfg_attr(feature = "cli", arg(skip = SceneParams::default().extent))]
    pub extent: f64,
    /// Height from the lowest to the highest terrain point.
    #[cfg_attr(feature = "cli", arg(skip = SceneParams::default().relief))]
    pub relief: f64,
    /// Share of the terrain under the sea (0 to 1).
    #[cfg_attr(feature = "cli", arg(long, default_value_t = SceneParams::default().sea_fraction))]
    pub sea_fraction: f64,
    /// Trees wanted (fewer where land is scarce).
    #[cfg_attr(feature = "cli", arg(long, default_value_t = SceneParams::default().trees))]
    pub trees: usize,
    /// Steepest ground a tree stands on, degrees.
    #[cfg_attr(feature = "cli", arg(long = "max-slope", value_name = "MAX_SLOPE", default_value_t = SceneParams::default().max_slope_deg))]
    pub max_slope_deg: f64,
    /// Animation frames (water and smoke meshes; butterfly keys between them).
    #[cfg_attr(feature = "cli", arg(long, default_value_t = SceneParams::default().frames))]
    pub frames: usize,
    /// Frames per second.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = SceneParams::default().fps))]
    pub fps: f64,
    /// Butterflies.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = SceneParams::default().butterflies))]
    pub butterflies: usize,
}

impl Default for SceneParams {
    fn default() -> Self {
        SceneParams {
            seed: 0,
            terrain_size: 129,
            extent: 100.0,
            relief: 22.0,
            sea_fraction: 0.3,
            trees: 24,
            max_slope_deg: 25.0,
            frames: 24,
            fps: 12.0,
            butterflies: 8,
        }
    }
}

impl SceneParams {
    /// Depth at which the water's opacity has risen by 1 − 1/e: 8 % of the relief.
    pub fn water_clarity(&self) -> f64 {
        0.08 * self.relief
    }

    fn check(&self) -> Result<()> {
        let bad = |msg: &str| Err(Error::InvalidInput(format!("scene: {msg}")));
        if !(17..=1025).contains(&self.terrain_size) || !(self.terrain_size - 1).is_power_of_two() {
            return bad("terrain size must be 2^n + 1 from 17 to 1025");
        }
        if !(self.extent.is_finite() && self.extent > 0.0 && self.relief.is_finite() && self.relief > 0.0) {
            return bad("extent and relief must be positive");
        }
        if !(0.0..1.0).contains(&self.sea_fraction) {
            return bad("sea fraction must be in [0, 1)");
        }
        if self.trees > 10_000 || !(0.0..=90.0).contains(&self.max_slope_deg) {
            return bad("at most 10000 trees, maximum slope 0 to 90 degrees");
        }
        if !((1..=240).contains(&self.frames) && self.fps.is_finite() && self.fps > 0.0) {
            return bad("1 to 240 frames at a positive frame rate");
        }
        if self.butterflies > 1000 {
            return bad("at most 1000 butterflies");
        }
        Ok(())
    }
}

/// Where a plant stands.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    /// Index into [`Scene::plants`].
    pub variant: usize,
    /// Its foot.
    pub position: DVec3,
    /// Turn about +z, radians.
    pub yaw: f64,
    /// Uniform scale.
    pub scale: f64,
    /// Slope of the ground there, degrees.
    pub slope_deg: f64,
}

/// The composed scene.
pub struct Scene {
    /// The parameters.
    pub params: SceneParams,
    /// The terrain, coloured, z up.
    pub terrain: Mesh,
    /// Sea level.
    pub sea_level: f64,
    /// Water surface per frame (scalar `depth`).
    pub water: Vec<Mesh>,
    /// The cabin, placed.
    pub cabin: Mesh,
    /// Plant meshes (variants), standing on the origin.
    pub plants: Vec<Mesh>,
    /// Where each plant stands.
    pub placements: Vec<Placement>,
    /// Smoke surface per frame, in the unit cube of the particle system.
    pub smoke: Vec<Mesh>,
    /// Where the unit cube's (½, ½, 0) goes (the chimney's top), and its scale.
    pub smoke_frame: (DVec3, f64),
    /// The butterflies' flights in the unit cube.
    pub flights: Vec<Flight>,
    /// The box the unit cube of the flights maps to.
    pub butterfly_box: (DVec3, DVec3),
    /// Butterfly steps per animation frame.
    pub butterfly_steps_per_frame: usize,
}

/// Plant variants: cottonwoods (uplands), palms (near the shore), flowers (by the cabin).
const VARIANTS: [(FloraPreset, u64); 6] = [
    (FloraPreset::Cottonwood, 1),
    (FloraPreset::Cottonwood, 2),
    (FloraPreset::Cottonwood, 3),
    (FloraPreset::Palm, 1),
    (FloraPreset::Palm, 2),
    (FloraPreset::Flower, 1),
];

/// Composes the scene.
///
/// # Errors
/// [`Error::InvalidInput`] for parameters out of range or a terrain with no land.
pub fn compose(params: &SceneParams) -> Result<Scene> {
    params.check()?;
    let (mut terrain, sea_level) = terrain(params)?;
    let slopes = slopes_deg(&terrain);
    let site = cabin_site(&terrain, &slopes, sea_level, params)?;
    let house = cabin(5.0);
    let mut cabin_mesh = house.mesh.clone();
    for p in &mut cabin_mesh.positions {
        *p += site - DVec3::Z * 0.3;
    }
    let chimney = house.chimney_top + site - DVec3::Z * 0.3;
    let frames = params.frames;
    let ((plants, smoke), (water, flights)) = rayon::join(
        || {
            rayon::join(
                || {
                    VARIANTS
                        .iter()
                        .map(|&(preset, k)| plant(&preset.rules(), params.seed.wrapping_add(k), 8).map(|p| p.mesh()))
                        .collect::<Result<Vec<_>>>()
                },
                || {
                    smoke_frames(
                        SmokeParams { seed: params.seed, resolution: 40, ..SmokeParams::default() },
                        40,
                        1,
                        frames,
                    )
                },
            )
        },
        || {
            rayon::join(
                || -> Result<Vec<Mesh>> {
                    let water = WaterParams {
                        level: sea_level,
                        cells: 96,
                        waves: waves_from_seed(params.seed, 4, params.extent),
                        clarity: params.water_clarity(),
                    };
                    let floor = water_floor(&terrain, &water)?;
                    Ok((0..frames).map(|k| surface_on(&floor, &water, k as f64 / params.fps)).collect())
                },
                || {
                    let steps = (frames.max(2) - 1) * BUTTERFLY_STEPS_PER_FRAME;
                    fly(&ButterflyParams {
                        seed: params.seed,
                        count: params.butterflies.max(1),
                        steps,
                        ..Default::default()
                    })
                },
            )
        },
    );
    let (plants, smoke, water, mut flights) = (plants?, smoke?, water?, flights?);
    flights.truncate(params.butterflies);
    let placements = place_plants(&terrain, &slopes, sea_level, site, params);
    terrain.normals = None;
    let smoke_scale = 8.0;
    let butterfly_box = (site + DVec3::new(-10.0, -10.0, 0.5), site + DVec3::new(10.0, 10.0, 6.0));
    Ok(Scene {
        params: *params,
        terrain,
        sea_level,
        water,
        cabin: cabin_mesh,
        plants,
        placements,
        smoke,
        smoke_frame: (chimney, smoke_scale),
        flights,
        butterfly_box,
        butterfly_steps_per_frame: BUTTERFLY_STEPS_PER_FRAME,
    })
}

/// Butterfly keyframes per animation frame.
const BUTTERFLY_STEPS_PER_FRAME: usize = 4;

/// Seed 002's terrain (`--method smooth`) scaled to the extent and relief, its sea level
/// at the requested share of points, coloured: sand to seabed under the sea, the smooth
/// method's logistic ramp above.
fn terrain(params: &SceneParams) -> Result<(Mesh, f64)> {
    let t = TerrainParams {
        method: Method::Smooth,
        size: params.terrain_size,
        seed: params.seed,
        width: params.extent,
        depth: params.extent,
        ..TerrainParams::default()
    };
    let last = t.size - 1;
    let mut mesh = crate::terrain::mesh(&t, Rect { x0: 0, y0: 0, x1: last, y1: last })?;
    let (lo, hi) = mesh.positions.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p.z), b.max(p.z)));
    if hi.partial_cmp(&lo) != Some(std::cmp::Ordering::Greater) {
        return Err(Error::InvalidInput("the terrain is flat: try another seed".into()));
    }
    for p in &mut mesh.positions {
        p.z = (p.z - lo) / (hi - lo) * params.relief;
    }
    let mut heights: Vec<f64> = mesh.positions.iter().map(|p| p.z).collect();
    heights.sort_by(f64::total_cmp);
    let sea = heights[((heights.len() - 1) as f64 * params.sea_fraction) as usize];
    let palette = Palette::default();
    mesh.colors = Some(
        mesh.positions
            .iter()
            .map(|p| {
                if p.z < sea {
                    let d = ((sea - p.z) / (0.25 * params.relief)).clamp(0.0, 1.0);
                    [0, 1, 2].map(|k| {
                        let (sand, bed) = ([196.0, 180.0, 130.0][k], [70.0, 80.0, 70.0][k]);
                        (sand + (bed - sand) * d).round() as u8
                    })
                } else {
                    ramp_color(&palette, (p.z - sea) / (params.relief - sea).max(1e-9), true)
                }
            })
            .collect(),
    );
    Ok((mesh, sea))
}

/// Ground slope at every vertex (degrees from horizontal), from area-weighted normals.
fn slopes_deg(terrain: &Mesh) -> Vec<f64> {
    let mut normals = vec![DVec3::ZERO; terrain.vertex_count()];
    for t in &terrain.triangles {
        let [a, b, c] = t.map(|v| terrain.positions[v as usize]);
        let n = (b - a).cross(c - a);
        for &v in t {
            normals[v as usize] += n;
        }
    }
    normals.iter().map(|n| n.normalize_or(DVec3::Z).z.abs().clamp(0.0, 1.0).acos().to_degrees()).collect()
}

/// The cabin's spot: the land vertex (2 m above the sea, slope under 12°) nearest the
/// terrain's middle; the flattest land vertex when none is that flat.
fn cabin_site(terrain: &Mesh, slopes: &[f64], sea: f64, params: &SceneParams) -> Result<DVec3> {
    let middle = DVec2::splat(params.extent / 2.0);
    let land: Vec<usize> = (0..terrain.vertex_count()).filter(|&v| terrain.positions[v].z > sea + 2.0).collect();
    let margin = 0.1 * params.extent;
    let inside =
        |p: DVec3| p.x > margin && p.y > margin && p.x < params.extent - margin && p.y < params.extent - margin;
    let best = land
        .iter()
        .copied()
        .filter(|&v| slopes[v] < 12.0 && inside(terrain.positions[v]))
        .min_by(|&a, &b| {
            let d = |v: usize| (terrain.positions[v].truncate() - middle).length();
            d(a).total_cmp(&d(b)).then(a.cmp(&b))
        })
        .or_else(|| land.iter().copied().min_by(|&a, &b| slopes[a].total_cmp(&slopes[b]).then(a.cmp(&b))));
    best.map(|v| terrain.positions[v]).ok_or_else(|| {
        Error::InvalidInput("the terrain has no land 2 m above the sea for the cabin: lower the sea fraction".into())
    })
}

/// Plants on a jittered grid of candidate spots, kept where the ground is above the sea
/// and no steeper than the limit and away from the cabin: palms within 3 m of the sea
/// level, flowers within 12 m of the cabin, cottonwoods elsewhere.
fn place_plants(terrain: &Mesh, slopes: &[f64], sea: f64, cabin: DVec3, params: &SceneParams) -> Vec<Placement> {
    let mut draw = Stream::new(derive_seed(params.seed, "scene plants"));
    let side = params.terrain_size as usize;
    let cells = ((params.trees as f64 * 4.0).sqrt().ceil() as usize).max(1);
    let mut placements = Vec::new();
    for cy in 0..cells {
        for cx in 0..cells {
            let (u, v) = ((cx as f64 + draw.unit()) / cells as f64, (cy as f64 + draw.unit()) / cells as f64);
            let (yaw, scale) = (draw.uniform(0.0, std::f64::consts::TAU), draw.uniform(0.8, 1.2));
            let (gx, gy) = ((u * (side - 1) as f64).round() as usize, (v * (side - 1) as f64).round() as usize);
            let vertex = gy * side + gx;
            let p = terrain.positions[vertex];
            let away = (p.truncate() - cabin.truncate()).length();
            if p.z <= sea + 0.5 || slopes[vertex] > params.max_slope_deg || away < 6.0 {
                continue;
            }
            let variant = if away < 12.0 {
                5
            } else if p.z < sea + 3.0 {
                3 + (draw.next_u64() % 2) as usize
            } else {
                (draw.next_u64() % 3) as usize
            };
            placements.push(Placement { variant, position: p, yaw, scale, slope_deg: slopes[vertex] });
        }
    }
    // The wanted number, chosen evenly from the candidates in grid order.
    if placements.len() > params.trees {
        let keep = params.trees;
        let all = std::mem::take(&mut placements);
        placements = (0..keep).map(|k| all[k * all.len() / keep]).collect();
    }
    placements
}

/// The smoke node's transform: the unit cube scaled, (½, ½, 0) on the chimney.
fn smoke_transform(frame: (DVec3, f64)) -> (DVec3, f64) {
    let (top, scale) = frame;
    (top - DVec3::new(0.5, 0.5, 0.0) * scale, scale)
}

impl Scene {
    /// The scene as a glTF document with its animation.
    pub fn glb(&self) -> GlbScene<'_> {
        let mut doc = GlbScene::default();
        let fps = self.params.fps;
        let terrain = doc.add_mesh(&self.terrain, "terrain", None);
        doc.add_node(SceneNode::new("terrain", Some(terrain)), None);
        let cabin = doc.add_mesh(&self.cabin, "cabin", None);
        doc.add_node(SceneNode::new("cabin", Some(cabin)), None);
        let plants: Vec<usize> =
            self.plants.iter().enumerate().map(|(k, m)| doc.add_mesh(m, format!("plant_{k}"), None)).collect();
        let flora = doc.add_node(SceneNode::new("flora", None), None);
        for (k, p) in self.placements.iter().enumerate() {
            let mut node = SceneNode::new(format!("plant_{k:03}"), Some(plants[p.variant]));
            node.translation = p.position - DVec3::Z * 0.2;
            node.rotation = DQuat::from_rotation_z(p.yaw);
            node.scale = DVec3::splat(p.scale);
            doc.add_node(node, Some(flora));
        }
        // The floor is the same under every frame, so is each vertex's depth and opacity.
        let clarity = self.params.water_clarity();
        let alpha: Vec<f32> = self
            .water
            .first()
            .map_or_else(Vec::new, |m| m.scalars["depth"].iter().map(|&d| opacity(d, clarity) as f32).collect());
        let water: Vec<Option<usize>> = self
            .water
            .iter()
            .enumerate()
            .map(|(k, m)| Some(doc.add_mesh(m, format!("water_{k:03}"), Some(alpha.clone()))))
            .collect();
        doc.add_frames("water", &water, fps, None);
        let (origin, scale) = smoke_transform(self.smoke_frame);
        let mut holder = SceneNode::new("smoke", None);
        holder.translation = origin;
        holder.scale = DVec3::splat(scale);
        let holder = doc.add_node(holder, None);
        // A frame without particles is a frame node without a mesh.
        let smoke: Vec<Option<usize>> = self
            .smoke
            .iter()
            .enumerate()
            .map(|(k, m)| (!m.triangles.is_empty()).then(|| doc.add_mesh(m, format!("smoke_{k:03}"), None)))
            .collect();
        doc.add_frames("plume", &smoke, fps, Some(holder));
        let rate = fps * self.butterfly_steps_per_frame as f64;
        add_butterflies(&mut doc, &self.flights, self.butterfly_box, rate, None);
        doc
    }

    /// How a still of the scene is drawn: a high three-quarter view with the water at sea
    /// level (see [`crate::render::water`]).
    pub fn preview_options(&self, width: usize, height: usize) -> crate::render::RenderOptions {
        crate::render::RenderOptions {
            width,
            height,
            yaw_deg: 30.0,
            pitch_deg: 28.0,
            water: Some(crate::render::WaterView { level: self.sea_level, clarity: 0.01 }),
            ..Default::default()
        }
    }

    /// Frame 0 as one coloured mesh in world coordinates, without the water (the renderer
    /// draws it at [`Scene::sea_level`]).
    pub fn still(&self) -> Mesh {
        let mut out = self.terrain.clone();
        out.normals = None;
        out.append(&self.cabin);
        for p in &self.placements {
            let mut plant = self.plants[p.variant].clone();
            let turn = DQuat::from_rotation_z(p.yaw);
            for q in &mut plant.positions {
                *q = p.position - DVec3::Z * 0.2 + turn * (*q * p.scale);
            }
            out.append(&plant);
        }
        if let Some(smoke) = self.smoke.first().filter(|m| !m.triangles.is_empty()) {
            let (origin, scale) = smoke_transform(self.smoke_frame);
            let mut smoke = smoke.clone();
            smoke.normals = None;
            for q in &mut smoke.positions {
                *q = origin + *q * scale;
            }
            smoke.colors = Some(vec![[225, 225, 230]; smoke.vertex_count()]);
            out.append(&smoke);
        }
        out
    }
}

/// Adds `flights` (in the unit cube, mapped onto `region`) as animated nodes, one key per
/// step at `rate` steps per second: a body node moving and turning, with two wing nodes
/// flapping about its axis.
pub fn add_butterflies(
    doc: &mut GlbScene<'_>,
    flights: &[Flight],
    region: (DVec3, DVec3),
    rate: f64,
    parent: Option<usize>,
) {
    if flights.is_empty() {
        return;
    }
    let body = doc.add_mesh(&BODY, "butterfly_body", None);
    let group = doc.add_node(SceneNode::new("butterflies", None), parent);
    let (lo, hi) = region;
    let mut wing_meshes = [None; 3];
    for (i, flight) in flights.iter().enumerate() {
        let look = match flight.colouring {
            super::butterflies::Colouring::Monarch => 0,
            super::butterflies::Colouring::BlueMorpho => 1,
            super::butterflies::Colouring::WhiteMorpho => 2,
        };
        let (left, right) = *wing_meshes[look].get_or_insert_with(|| {
            let wings = &WINGS[look];
            (
                doc.add_mesh(&wings.0, format!("wing_left_{look}"), None),
                doc.add_mesh(&wings.1, format!("wing_right_{look}"), None),
            )
        });
        let node = doc.add_node(SceneNode::new(format!("butterfly_{i}"), Some(body)), Some(group));
        let left = doc.add_node(SceneNode::new(format!("butterfly_{i}_left"), Some(left)), Some(node));
        let right = doc.add_node(SceneNode::new(format!("butterfly_{i}_right"), Some(right)), Some(node));
        let world: Vec<DVec3> = flight.positions.iter().map(|p| lo + *p * (hi - lo)).collect();
        doc.nodes[node].translation = world[0];
        doc.nodes[node].rotation = flight.orientations[0];
        if world.len() < 2 {
            continue;
        }
        let times: Vec<f64> = (0..world.len()).map(|s| s as f64 / rate).collect();
        let flap = |sign: f64| flight.wings.iter().map(|w| DQuat::from_rotation_x(sign * w.to_radians())).collect();
        let track = |node: usize, keys: Keys| Track { node, times: times.clone(), keys, step: false };
        doc.tracks.push(track(node, Keys::Translation(world)));
        doc.tracks.push(track(node, Keys::Rotation(flight.orientations.clone())));
        doc.tracks.push(track(left, Keys::Rotation(flap(1.0))));
        doc.tracks.push(track(right, Keys::Rotation(flap(-1.0))));
    }
}

/// Side of the box a standalone flight's unit cube maps to, metres.
pub const BUTTERFLY_BOX: f64 = 10.0;

/// Flights alone as a scene: the unit cube mapped onto a [`BUTTERFLY_BOX`]-metre box.
pub fn butterfly_scene(flights: &[Flight], rate: f64) -> GlbScene<'static> {
    let mut doc = GlbScene::default();
    add_butterflies(&mut doc, flights, (DVec3::ZERO, DVec3::splat(BUTTERFLY_BOX)), rate, None);
    doc
}

static BODY: std::sync::LazyLock<Mesh> = std::sync::LazyLock::new(|| body_mesh(0.3));
static WINGS: std::sync::LazyLock<[(Mesh, Mesh); 3]> = std::sync::LazyLock::new(|| {
    use super::butterflies::Colouring::*;
    [Monarch, BlueMorpho, WhiteMorpho].map(|c| (wing_mesh(0.22, c, 1.0), wing_mesh(0.22, c, -1.0)))
});

#[cfg(test)]
mod tests {
    use super::*;

    fn small() -> SceneParams {
        SceneParams { terrain_size: 65, frames: 3, trees: 12, butterflies: 3, ..SceneParams::default() }
    }

    #[test]
    fn trees_stand_on_land_on_gentle_slopes() {
        let scene = compose(&small()).unwrap();
        assert!(!scene.placements.is_empty());
        for p in &scene.placements {
            assert!(p.position.z > scene.sea_level, "a plant in the sea: {p:?}");
            assert!(p.slope_deg <= scene.params.max_slope_deg, "a plant on a slope: {p:?}");
        }
        assert!(scene.cabin.positions.iter().map(|p| p.z).fold(f64::MAX, f64::min) > scene.sea_level);
        assert_eq!(scene.water.len(), 3);
        assert_eq!(scene.smoke.len(), 3);
        assert_eq!(scene.flights.len(), 3);
    }
}
