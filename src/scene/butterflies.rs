//! Butterflies (seed 002, "Butterflies"): each butterfly chases an invisible target on a
//! random walk along a pursuit curve. Butterfly and target start uniformly in the unit
//! cube; at each step the butterfly moves towards where the target will be at the next
//! step (at most its speed, never past it); a target that leaves the unit cube or is
//! caught is placed anew. The wings turn by a fixed angle per step, back and forth between
//! two limits, and the body follows the Euler angles (yaw, pitch) of its direction. Each
//! butterfly's colouring — monarch, blue morpho or white morpho — is a fair die's roll.

use glam::{DQuat, DVec3};
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::mesh::{Mesh, Rgb};
use crate::noise::hash::{Stream, derive_seed};

/// Parameters of a flight: the request `asperity butterflies` flattens into its flags
/// (#38), checked when the butterflies fly.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
pub struct ButterflyParams {
    /// Seed.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = 0))]
    pub seed: u64,
    /// Butterflies.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = ButterflyParams::default().count))]
    pub count: usize,
    /// Steps simulated (one keyframe each).
    #[cfg_attr(feature = "cli", arg(long, default_value_t = ButterflyParams::default().steps))]
    pub steps: usize,
    /// A butterfly's step length, in units of the unit cube they fly in.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = ButterflyParams::default().speed))]
    pub speed: f64,
    /// The target's random-walk step length.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = ButterflyParams::default().wander))]
    pub wander: f64,
    /// Distance at which a target counts as caught.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = ButterflyParams::default().catch_radius))]
    pub catch_radius: f64,
    /// Wing turn per step, degrees.
    #[cfg_attr(feature = "cli", arg(long = "flap", value_name = "FLAP", default_value_t = ButterflyParams::default().flap_deg))]
    pub flap_deg: f64,
    /// Wings turn between −limit and +limit, degrees.
    #[cfg_attr(feature = "cli", arg(long = "flap-limit", value_name = "FLAP_LIMIT", default_value_t = ButterflyParams::default().flap_limit_deg))]
    pub flap_limit_deg: f64,
}

impl Default for ButterflyParams {
    fn default() -> Self {
        ButterflyParams {
            seed: 0,
            count: 8,
            steps: 240,
            speed: 0.012,
            wander: 0.02,
            catch_radius: 0.02,
            flap_deg: 15.0,
            flap_limit_deg: 60.0,
        }
    }
}

impl ButterflyParams {
    fn check(&self) -> Result<()> {
        let positive = |v: f64| v.is_finite() && v > 0.0;
        if !(1..=10_000).contains(&self.count) || !(1..=1_000_000).contains(&self.steps) {
            return Err(Error::InvalidInput("butterflies: 1 to 10000 butterflies and 1 to 10⁶ steps".into()));
        }
        if self.count * self.steps > 10_000_000 {
            return Err(Error::InvalidInput(format!(
                "butterflies: {} butterflies × {} steps exceed 10⁷ keyframes",
                self.count, self.steps
            )));
        }
        if !(positive(self.speed) && positive(self.catch_radius) && self.wander.is_finite() && self.wander >= 0.0) {
            return Err(Error::InvalidInput("butterflies: speed and catch radius positive, wander at least 0".into()));
        }
        if !(self.flap_deg.is_finite() && self.flap_deg >= 0.0 && (0.0..90.0).contains(&self.flap_limit_deg)) {
            return Err(Error::InvalidInput("butterflies: flap at least 0, flap limit in [0, 90) degrees".into()));
        }
        Ok(())
    }
}

/// The three colourings of the seed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Colouring {
    /// Orange with black veins (die 1–2).
    Monarch,
    /// Iridescent blue (die 3–4).
    BlueMorpho,
    /// White (die 5–6).
    WhiteMorpho,
}

impl Colouring {
    /// The colouring a die roll (1 to 6) gives.
    pub fn of_die(roll: u64) -> Colouring {
        match roll {
            1 | 2 => Colouring::Monarch,
            3 | 4 => Colouring::BlueMorpho,
            _ => Colouring::WhiteMorpho,
        }
    }

    /// Wing colours: inner and outer.
    pub fn colors(self) -> (Rgb, Rgb) {
        match self {
            Colouring::Monarch => ([235, 120, 20], [30, 20, 15]),
            Colouring::BlueMorpho => ([40, 120, 240], [15, 30, 70]),
            Colouring::WhiteMorpho => ([245, 245, 240], [190, 190, 200]),
        }
    }
}

/// One butterfly's flight: a pose per step (the start included).
#[derive(Debug, Clone, PartialEq)]
pub struct Flight {
    /// Its colouring.
    pub colouring: Colouring,
    /// Positions.
    pub positions: Vec<DVec3>,
    /// Body orientations (local +x forward, +z up).
    pub orientations: Vec<DQuat>,
    /// Wing angles, degrees.
    pub wings: Vec<f64>,
    /// Targets caught.
    pub catches: usize,
}

/// One pursuit step: from `butterfly` towards `target_next` by at most `speed`.
pub fn pursue(butterfly: DVec3, target_next: DVec3, speed: f64) -> DVec3 {
    let to = target_next - butterfly;
    let distance = to.length();
    if distance <= speed { target_next } else { butterfly + to * (speed / distance) }
}

fn in_unit_cube(p: DVec3) -> bool {
    p.cmpge(DVec3::ZERO).all() && p.cmple(DVec3::ONE).all()
}

fn uniform_point(draw: &mut Stream) -> DVec3 {
    DVec3::new(draw.unit(), draw.unit(), draw.unit())
}

/// A uniformly random unit vector (Marsaglia's method on the sphere by z and angle).
fn random_direction(draw: &mut Stream) -> DVec3 {
    let z = draw.uniform(-1.0, 1.0);
    let angle = draw.uniform(0.0, std::f64::consts::TAU);
    let r = (1.0 - z * z).max(0.0).sqrt();
    DVec3::new(r * angle.cos(), r * angle.sin(), z)
}

/// Flies every butterfly for `steps` steps.
///
/// # Errors
/// [`Error::InvalidInput`] for parameters out of range.
pub fn fly(params: &ButterflyParams) -> Result<Vec<Flight>> {
    params.check()?;
    (0..params.count)
        .map(|i| {
            let mut draw = Stream::new(derive_seed(params.seed ^ (i as u64).wrapping_mul(0x9e37_79b9), "butterfly"));
            let colouring = Colouring::of_die(draw.next_u64() % 6 + 1);
            let start = uniform_point(&mut draw);
            let target = uniform_point(&mut draw);
            Ok(fly_one(params, colouring, start, target, &mut draw))
        })
        .collect()
}

/// One flight from `start` chasing a target first at `target`.
pub fn fly_one(
    params: &ButterflyParams,
    colouring: Colouring,
    start: DVec3,
    target: DVec3,
    draw: &mut Stream,
) -> Flight {
    let mut flight = Flight {
        colouring,
        positions: vec![start],
        orientations: Vec::with_capacity(params.steps + 1),
        wings: vec![0.0],
        catches: 0,
    };
    let (mut butterfly, mut target) = (start, target);
    let mut heading = heading_towards(target - start, DQuat::IDENTITY);
    flight.orientations.push(heading);
    let (mut wing, mut flap) = (0.0, params.flap_deg);
    for _ in 0..params.steps {
        let target_next = target + random_direction(draw) * params.wander;
        let next = pursue(butterfly, target_next, params.speed);
        heading = heading_towards(next - butterfly, heading);
        butterfly = next;
        target = target_next;
        if (butterfly - target).length() <= params.catch_radius || !in_unit_cube(target) {
            if in_unit_cube(target) {
                flight.catches += 1;
            }
            target = uniform_point(draw);
        }
        if (wing + flap).abs() > params.flap_limit_deg {
            flap = -flap;
        }
        wing += flap;
        flight.positions.push(butterfly);
        flight.orientations.push(heading);
        flight.wings.push(wing);
    }
    flight
}

/// The body orientation for moving along `direction`: yaw about +z, then pitch (nose up
/// positive); the previous heading when the butterfly did not move.
fn heading_towards(direction: DVec3, previous: DQuat) -> DQuat {
    let Some(d) = direction.try_normalize() else { return previous };
    let yaw = d.y.atan2(d.x);
    let pitch = d.z.clamp(-1.0, 1.0).asin();
    DQuat::from_rotation_z(yaw) * DQuat::from_rotation_y(-pitch)
}

/// The body: a slender closed double cone along +x, `length` long.
pub fn body_mesh(length: f64) -> Mesh {
    let sides = 6;
    let radius = 0.08 * length;
    let mut positions = vec![DVec3::new(-0.5 * length, 0.0, 0.0), DVec3::new(0.5 * length, 0.0, 0.0)];
    for k in 0..sides {
        let a = std::f64::consts::TAU * f64::from(k) / f64::from(sides);
        positions.push(DVec3::new(0.0, radius * a.cos(), radius * a.sin()));
    }
    let ring = |k: u32| 2 + k % sides;
    let mut triangles = Vec::new();
    for k in 0..sides {
        triangles.push([0, ring(k + 1), ring(k)]);
        triangles.push([1, ring(k), ring(k + 1)]);
    }
    let mut mesh = Mesh::new(positions, triangles);
    mesh.colors = Some(vec![[25, 20, 18]; mesh.vertex_count()]);
    mesh
}

/// One wing on the +y side (mirror it for the other): a fan of a fore- and a hindwing,
/// `span` long, hinged on the body's axis, inner colour near the hinge, outer at the rim.
pub fn wing_mesh(span: f64, colouring: Colouring, side: f64) -> Mesh {
    let outline = [(0.25, 0.0), (0.45, 0.55), (0.2, 1.0), (-0.15, 0.85), (-0.4, 0.45), (-0.35, 0.1)];
    let mut positions = vec![DVec3::ZERO];
    positions.extend(outline.iter().map(|&(x, y)| DVec3::new(x * span, side * y * span, 0.0)));
    let mut triangles: Vec<[u32; 3]> = (1..outline.len() as u32).map(|k| [0, k, k + 1]).collect();
    if side < 0.0 {
        for t in &mut triangles {
            t.swap(1, 2);
        }
    }
    let (inner, outer) = colouring.colors();
    let mut mesh = Mesh::new(positions, triangles);
    mesh.colors = Some(std::iter::once(inner).chain(std::iter::repeat_n(outer, outline.len())).collect());
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_still_target_is_caught_within_distance_over_speed_steps() {
        let params = ButterflyParams { wander: 0.0, steps: 200, speed: 0.01, catch_radius: 1e-9, ..Default::default() };
        let (start, target) = (DVec3::new(0.1, 0.2, 0.3), DVec3::new(0.9, 0.7, 0.6));
        let bound = ((target - start).length() / params.speed).ceil() as usize;
        let mut draw = Stream::new(1);
        let flight = fly_one(&params, Colouring::Monarch, start, target, &mut draw);
        let reached = flight.positions.iter().position(|p| *p == target).expect("caught");
        assert!(reached <= bound, "caught after {reached} steps, bound {bound}");
        assert!(flight.catches >= 1);
        // Every step is at most the speed long.
        assert!(flight.positions.windows(2).all(|w| (w[1] - w[0]).length() <= params.speed + 1e-12));
    }

    #[test]
    fn pursuit_heads_for_the_targets_next_position() {
        let next = pursue(DVec3::ZERO, DVec3::new(3.0, 4.0, 0.0), 0.5);
        assert!((next - DVec3::new(0.3, 0.4, 0.0)).length() < 1e-12);
        assert_eq!(pursue(DVec3::ZERO, DVec3::new(0.1, 0.0, 0.0), 0.5), DVec3::new(0.1, 0.0, 0.0));
    }

    #[test]
    fn wings_flap_by_a_fixed_angle_within_their_limits_and_bodies_face_their_way() {
        let params = ButterflyParams { count: 30, steps: 100, ..Default::default() };
        let flights = fly(&params).unwrap();
        for f in &flights {
            for w in f.wings.windows(2) {
                assert!(((w[1] - w[0]).abs() - params.flap_deg).abs() < 1e-9);
            }
            assert!(f.wings.iter().all(|w| w.abs() <= params.flap_limit_deg + 1e-9));
            for (k, w) in f.positions.windows(2).enumerate() {
                if let Some(d) = (w[1] - w[0]).try_normalize() {
                    assert!((f.orientations[k + 1] * DVec3::X).dot(d) > 1.0 - 1e-9);
                }
            }
            assert!(f.positions.iter().all(|p| in_unit_cube(*p)), "pursuit stays in the cube's hull");
        }
        // A fair die: every colouring appears among 30.
        for c in [Colouring::Monarch, Colouring::BlueMorpho, Colouring::WhiteMorpho] {
            assert!(flights.iter().any(|f| f.colouring == c), "{c:?}");
        }
        assert_eq!(flights, fly(&params).unwrap(), "the same seed flies the same way");
    }

    #[test]
    fn the_body_is_closed_and_wings_face_up_on_both_sides() {
        let report = body_mesh(1.0).validate();
        assert!(report.is_closed_manifold() && report.genus == Some(0), "{report:?}");
        for side in [1.0, -1.0] {
            let wing = wing_mesh(1.0, Colouring::BlueMorpho, side);
            for t in &wing.triangles {
                let [a, b, c] = t.map(|v| wing.positions[v as usize]);
                assert!((b - a).cross(c - a).z > 0.0);
            }
        }
    }
}
