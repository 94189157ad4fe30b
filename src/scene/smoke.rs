//! Smoke (seed 002, "Smoke"): a particle system drawn as Blinn's metaballs and meshed by
//! marching tetrahedra.
//!
//! - Particles are added every [`SmokeParams::emit_every`] steps in batches, at random
//!   points of the xy-plane (z = 0) with zero velocity.
//! - A uniform random vector field is made once: one vector per cell of a coarse lattice
//!   over the unit cube, x and y uniform in ±`swirl`, z fixed at `rise` > 0.
//! - Forward Euler: x ← x + Δt·v, v ← v + Δt·F(x), both from the step's old values.
//! - Particles that leave the unit cube are removed.
//!
//! Each particle is a blob of Blinn (1982): D(r) = exp(B − B·r²/R²), so a lone particle's
//! surface D = 1 is the sphere of radius R, and B (the blobbiness) sets how far blobs
//! reach out to merge. The field is summed only within the radius where a blob falls below
//! 10⁻³ of the threshold, and — past the seed, which visited every cube and wished it
//! did not — marching tetrahedra visits only the cubes inside some particle's reach.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::tetrahedra::{ScalarGrid, Visited, marching_tetrahedra};
use crate::error::{Error, Result};
use crate::mesh::Mesh;
use crate::noise::hash::{Stream, derive_seed};

/// Parameters of the smoke plume: the request `asperity smoke` flattens into its flags
/// (#38), checked by [`SmokeParams::check`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
pub struct SmokeParams {
    /// Seed of the emission points and the vector field.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = 0))]
    pub seed: u64,
    /// Particles per batch.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = SmokeParams::default().batch))]
    pub batch: usize,
    /// Steps between batches.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = SmokeParams::default().emit_every))]
    pub emit_every: usize,
    /// Time step Δt of forward Euler.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = SmokeParams::default().dt))]
    pub dt: f64,
    /// Cells of the random vector field's lattice per side of the unit cube.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = SmokeParams::default().field_cells))]
    pub field_cells: usize,
    /// Largest sideways component (|x|, |y|) of the field's vectors.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = SmokeParams::default().swirl))]
    pub swirl: f64,
    /// The field's fixed upward component.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = SmokeParams::default().rise))]
    pub rise: f64,
    /// Half-width of the emission square on the xy-plane, around (½, ½).
    #[cfg_attr(feature = "cli", arg(long, default_value_t = SmokeParams::default().spread))]
    pub spread: f64,
    /// Radius R of one particle's blob.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = SmokeParams::default().radius))]
    pub radius: f64,
    /// Blinn's blobbiness B (larger: blobs reach less far and merge less).
    #[cfg_attr(feature = "cli", arg(long, default_value_t = SmokeParams::default().blobbiness))]
    pub blobbiness: f64,
    /// Grid points per unit length of the marching-tetrahedra grid.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = SmokeParams::default().resolution))]
    pub resolution: usize,
}

impl Default for SmokeParams {
    fn default() -> Self {
        SmokeParams {
            seed: 0,
            batch: 10,
            emit_every: 2,
            dt: 0.05,
            field_cells: 6,
            swirl: 1.0,
            rise: 1.2,
            spread: 0.08,
            radius: 0.055,
            blobbiness: 0.8,
            resolution: 64,
        }
    }
}

impl SmokeParams {
    /// Checks every parameter.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] naming the parameter out of range.
    pub fn check(&self) -> Result<()> {
        let bad = |what: &str, range: &str| Err(Error::InvalidInput(format!("smoke {what}: must be {range}")));
        if self.batch == 0 || self.batch > 10_000 {
            return bad("batch", "1 to 10000 particles");
        }
        if self.emit_every == 0 {
            return bad("emit interval", "at least 1 step");
        }
        if !(self.dt.is_finite() && self.dt > 0.0 && self.dt <= 1.0) {
            return bad("time step", "in (0, 1]");
        }
        if !(1..=256).contains(&self.field_cells) {
            return bad("field cells", "1 to 256 per side");
        }
        if !(self.swirl.is_finite() && self.swirl >= 0.0) {
            return bad("swirl", "finite and at least 0");
        }
        if !(self.rise.is_finite() && self.rise > 0.0) {
            return bad("rise", "positive (the seed's field has a fixed positive z)");
        }
        if !(self.spread.is_finite() && (0.0..=0.5).contains(&self.spread)) {
            return bad("spread", "in [0, 0.5]");
        }
        if !(self.radius.is_finite() && self.radius > 0.0 && self.radius <= 0.5) {
            return bad("radius", "in (0, 0.5]");
        }
        if !(self.blobbiness.is_finite() && self.blobbiness >= 0.1 && self.blobbiness <= 50.0) {
            return bad("blobbiness", "in [0.1, 50]");
        }
        if !(8..=512).contains(&self.resolution) {
            return bad("resolution", "8 to 512 grid points per unit");
        }
        // Particles stay in the unit cube: the grid spans it plus every blob's reach.
        let side = ((1.0 + 2.0 * self.reach()) * self.resolution as f64).ceil() + 6.0;
        if side.powi(3) > MAX_GRID_POINTS as f64 {
            return Err(Error::InvalidInput(format!(
                "smoke grid of {side}³ points (radius {}, blobbiness {}, resolution {}): at most {MAX_GRID_POINTS}; lower the resolution or the radius",
                self.radius, self.blobbiness, self.resolution
            )));
        }
        Ok(())
    }

    /// Distance beyond which a blob adds less than 10⁻³ of the threshold:
    /// exp(B − B·r²/R²) = 10⁻³.
    pub fn reach(&self) -> f64 {
        self.radius * (1.0 + 1000f64.ln() / self.blobbiness).sqrt()
    }
}

/// The most grid points a metaball surface is sampled on (2²⁶: half a gigabyte of values).
pub const MAX_GRID_POINTS: usize = 1 << 26;

/// One smoke particle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Particle {
    /// Position in the unit cube.
    pub position: DVec3,
    /// Velocity.
    pub velocity: DVec3,
}

/// The particle system of seed 002.
#[derive(Debug, Clone)]
pub struct ParticleSystem {
    params: SmokeParams,
    field: Vec<DVec3>,
    /// The live particles, oldest first.
    pub particles: Vec<Particle>,
    steps: u64,
    emission: Stream,
}

impl ParticleSystem {
    /// A system with no particles and its random vector field drawn.
    ///
    /// # Errors
    /// As [`SmokeParams::check`].
    pub fn new(params: SmokeParams) -> Result<Self> {
        params.check()?;
        let mut draw = Stream::new(derive_seed(params.seed, "smoke field"));
        let cells = params.field_cells.pow(3);
        let field = (0..cells)
            .map(|_| {
                DVec3::new(
                    draw.uniform(-params.swirl, params.swirl),
                    draw.uniform(-params.swirl, params.swirl),
                    params.rise,
                )
            })
            .collect();
        Ok(ParticleSystem {
            params,
            field,
            particles: Vec::new(),
            steps: 0,
            emission: Stream::new(derive_seed(params.seed, "smoke emission")),
        })
    }

    /// The field's vector in the cell holding `p` (clamped to the unit cube).
    pub fn force(&self, p: DVec3) -> DVec3 {
        let n = self.params.field_cells;
        let cell = |c: f64| ((c * n as f64).floor().max(0.0) as usize).min(n - 1);
        self.field[(cell(p.z) * n + cell(p.y)) * n + cell(p.x)]
    }

    /// Steps taken so far.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// One step: a batch is emitted when the step number is a multiple of the interval,
    /// every particle moves by forward Euler, and those outside the unit cube are removed.
    pub fn step(&mut self) {
        let p = self.params;
        if self.steps.is_multiple_of(p.emit_every as u64) {
            for _ in 0..p.batch {
                let x = self.emission.uniform(0.5 - p.spread, 0.5 + p.spread);
                let y = self.emission.uniform(0.5 - p.spread, 0.5 + p.spread);
                self.particles.push(Particle { position: DVec3::new(x, y, 0.0), velocity: DVec3::ZERO });
            }
        }
        for i in 0..self.particles.len() {
            let Particle { position, velocity } = self.particles[i];
            let force = self.force(position);
            self.particles[i] = Particle { position: position + p.dt * velocity, velocity: velocity + p.dt * force };
        }
        self.particles.retain(|q| q.position.cmpge(DVec3::ZERO).all() && q.position.cmple(DVec3::ONE).all());
        self.steps += 1;
    }

    /// The metaball surface of the particles now.
    ///
    /// # Errors
    /// As [`metaball_surface`] (not for particles in the unit cube with checked parameters).
    pub fn surface(&self) -> Result<(Mesh, Visited)> {
        metaball_surface(&self.particles.iter().map(|q| q.position).collect::<Vec<_>>(), &self.params)
    }
}

/// Blinn's metaball surface of blobs at `centres` (radius and blobbiness from `params`),
/// on a grid of `params.resolution` points per unit that covers every blob's reach, so the
/// surface is closed. Only the cubes within some blob's reach are visited.
///
/// # Errors
/// [`Error::InvalidInput`] for non-finite centres or a grid of more than
/// [`MAX_GRID_POINTS`].
pub fn metaball_surface(centres: &[DVec3], params: &SmokeParams) -> Result<(Mesh, Visited)> {
    if centres.is_empty() {
        return Ok((Mesh::default(), Visited::default()));
    }
    if !centres.iter().all(|c| c.is_finite()) {
        return Err(Error::InvalidInput("metaball centres must be finite".into()));
    }
    let reach = params.reach();
    let spacing = 1.0 / params.resolution as f64;
    let (lo, hi) = centres.iter().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(a, b), &c| (a.min(c), b.max(c)));
    let origin = lo - DVec3::splat(reach + 2.0 * spacing);
    let far = hi + DVec3::splat(reach + 2.0 * spacing);
    let extent = ((far - origin) / spacing).ceil();
    if extent.x * extent.y * extent.z > MAX_GRID_POINTS as f64 {
        return Err(Error::InvalidInput(format!(
            "the metaballs span {}×{}×{} grid points: at most {MAX_GRID_POINTS}",
            extent.x, extent.y, extent.z
        )));
    }
    let dims = extent.as_uvec3().to_array().map(|d| d as usize + 1);
    let mut grid = ScalarGrid::zeros(origin, spacing, dims);
    let (b, inverse_r2) = (params.blobbiness, 1.0 / (params.radius * params.radius));
    // The cubes with a corner within some blob's reach, listed from the blobs' boxes (every
    // other cube has eight zero corners and no surface): the grid is never swept.
    let mut cubes = Vec::new();
    for &c in centres {
        let first = ((c - reach - origin) / spacing).floor().max(DVec3::ZERO).as_uvec3();
        let last =
            ((c + reach - origin) / spacing).ceil().as_uvec3().min(glam::UVec3::from_array(dims.map(|d| d as u32 - 1)));
        for z in first.z..=last.z {
            for y in first.y..=last.y {
                for x in first.x..=last.x {
                    let i = grid.index(x as usize, y as usize, z as usize);
                    let r2 = (grid.position(i) - c).length_squared();
                    grid.values[i] += (b - b * r2 * inverse_r2).exp();
                }
            }
        }
        // Every cube with a corner in the box: lowest corners from one below the box to its
        // last point (the grid's last cube at most).
        let lowest = first.saturating_sub(glam::UVec3::ONE);
        let highest = last.min(glam::UVec3::from_array(dims.map(|d| d as u32 - 2)));
        for z in lowest.z..=highest.z {
            for y in lowest.y..=highest.y {
                for x in lowest.x..=highest.x {
                    cubes.push(grid.index(x as usize, y as usize, z as usize));
                }
            }
        }
    }
    cubes.sort_unstable();
    cubes.dedup();
    Ok(marching_tetrahedra(&grid, 1.0, &cubes))
}

/// Runs the system for `warmup` steps, then returns one surface every `steps_per_frame`
/// steps, `frames` of them.
///
/// # Errors
/// As [`SmokeParams::check`]; [`Error::InvalidInput`] for no frames or no steps per frame.
pub fn smoke_frames(params: SmokeParams, warmup: usize, steps_per_frame: usize, frames: usize) -> Result<Vec<Mesh>> {
    if frames == 0 || steps_per_frame == 0 {
        return Err(Error::InvalidInput("smoke needs at least one frame and one step per frame".into()));
    }
    let mut system = ParticleSystem::new(params)?;
    for _ in 0..warmup {
        system.step();
    }
    let mut out = Vec::new();
    for frame in 0..frames {
        if frame > 0 {
            for _ in 0..steps_per_frame {
                system.step();
            }
        }
        let mesh = system.surface()?.0;
        // The frames are held until written: the first frame's size, times the frames
        // asked, is refused where the machine has not that much (#36: 10^9 frames
        // aborted on a 240 GB allocation).
        if frame == 0 {
            let bytes = (std::mem::size_of::<Mesh>()
                + mesh.positions.len() * std::mem::size_of::<DVec3>()
                + mesh.triangles.len() * std::mem::size_of::<[u32; 3]>()) as u64;
            crate::memory::ensure_available(
                bytes.saturating_mul(frames as u64),
                &format!("smoke's {frames} frames ({bytes} bytes the first)"),
                "ask for fewer frames (--frames)",
            )?;
        }
        out.push(mesh);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn particles_follow_the_seeds_rules_stepped_by_hand() {
        let params = SmokeParams { batch: 2, emit_every: 2, dt: 0.1, ..SmokeParams::default() };
        let mut system = ParticleSystem::new(params).unwrap();
        system.step();
        assert_eq!(system.particles.len(), 2, "a batch at step 0");
        // Emitted on the xy-plane with zero velocity: Euler moves them by Δt·0, then the
        // velocity takes Δt·F.
        for q in &system.particles {
            assert_eq!(q.position.z, 0.0);
            assert!((q.position.x - 0.5).abs() <= params.spread && (q.position.y - 0.5).abs() <= params.spread);
            assert_eq!(q.velocity, params.dt * system.force(q.position));
            assert_eq!(q.velocity.z, params.dt * params.rise);
        }
        let before = system.particles.clone();
        system.step();
        assert_eq!(system.particles.len(), 2, "no batch at step 1");
        for (q, p) in system.particles.iter().zip(&before) {
            assert_eq!(q.position, p.position + params.dt * p.velocity);
            assert_eq!(q.velocity, p.velocity + params.dt * system.force(p.position));
        }
        system.step();
        assert_eq!(system.particles.len(), 4, "a batch at step 2");
    }

    #[test]
    fn particles_leaving_the_unit_cube_are_removed() {
        let params = SmokeParams { batch: 1, emit_every: 1_000_000, dt: 0.5, rise: 4.0, ..SmokeParams::default() };
        let mut system = ParticleSystem::new(params).unwrap();
        let mut seen = 0;
        for _ in 0..20 {
            system.step();
            seen = seen.max(system.particles.len());
            assert!(system.particles.iter().all(|q| q.position.cmple(DVec3::ONE).all()));
        }
        assert_eq!(seen, 1);
        assert!(system.particles.is_empty(), "the rising particle left through the top");
    }

    #[test]
    fn one_metaball_is_a_closed_sphere_of_its_radius_within_one_percent() {
        let params = SmokeParams { radius: 0.2, resolution: 64, ..SmokeParams::default() };
        let centre = DVec3::new(0.5, 0.5, 0.3);
        let (mesh, visited) = metaball_surface(&[centre], &params).unwrap();
        let report = mesh.validate();
        assert!(report.is_closed_manifold(), "{report:?}");
        assert_eq!(report.genus, Some(0));
        let mean = mesh.positions.iter().map(|p| (*p - centre).length()).sum::<f64>() / mesh.vertex_count() as f64;
        assert!((mean / 0.2 - 1.0).abs() < 0.01, "mean radius {mean}");
        for p in &mesh.positions {
            assert!(((*p - centre).length() / 0.2 - 1.0).abs() < 0.02);
        }
        // Only cubes near the particle are visited, not the whole grid's.
        let side = (2.0 * params.reach() * 64.0).ceil() as usize + 6;
        assert!(visited.cubes <= side.pow(3), "{} cubes", visited.cubes);
    }

    #[test]
    fn every_frame_is_a_closed_manifold_and_the_same_seed_gives_the_same_frames() {
        let params = SmokeParams { seed: 3, resolution: 48, ..SmokeParams::default() };
        let frames = smoke_frames(params, 10, 4, 3).unwrap();
        for (k, mesh) in frames.iter().enumerate() {
            assert!(mesh.face_count() > 0, "frame {k} is empty");
            let report = mesh.validate();
            assert!(report.is_closed_manifold(), "frame {k}: {report:?}");
            assert_eq!(report.inconsistently_oriented_edges, 0);
        }
        let again = smoke_frames(params, 10, 4, 3).unwrap();
        assert!(frames.iter().zip(&again).all(|(a, b)| a.positions == b.positions && a.triangles == b.triangles));
        let other = smoke_frames(SmokeParams { seed: 4, ..params }, 10, 4, 3).unwrap();
        assert_ne!(frames[2].positions, other[2].positions);
    }

    #[test]
    fn parameters_out_of_range_are_refused() {
        for bad in [
            SmokeParams { batch: 0, ..SmokeParams::default() },
            SmokeParams { rise: 0.0, ..SmokeParams::default() },
            SmokeParams { dt: f64::NAN, ..SmokeParams::default() },
            SmokeParams { resolution: 2, ..SmokeParams::default() },
            SmokeParams { resolution: 512, radius: 0.5, ..SmokeParams::default() },
        ] {
            assert!(ParticleSystem::new(bad).is_err(), "{bad:?}");
        }
    }
}
