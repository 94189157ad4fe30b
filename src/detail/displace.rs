//! Procedural displacement (thesis §4.5, §4.7.3, §4.7.5.2): p ← p + (nl/l)·d(p) with nl a
//! noise value, l the level number (eq. 4.5) and d the normal, its opposite (eq. 4.14), the
//! diffusion direction or normal × diffusion (§5.2.2). Noise spreads from the selected
//! centres over k rings with per-ring influence and per-ring Gabor parameters (Table 5.1),
//! attenuated by distance (eq. 4.15). Parameters follow the level (§4.7.3.1): the fractal
//! kinds take lacunarity 1.1 + (l+1)/10 and gain 0.8/(l+1); Gabor noise doubles its impulse
//! density per coarser level, up to four times. Gabor kernels are oriented by each vertex's
//! diffusion direction in its tangent plane (§4.7.3.2).

use glam::DVec3;

use super::level::{BoxFrame, LevelView};
use super::recipe::{Attenuation, Direction, NoiseParams, OperatorKind};
use crate::error::Result;
use crate::noise::hash::{Stream, derive_seed, hash_coords};
use crate::noise::{
    Fractal, FractalKind, Frame, GaborParams, NoiseField, NoiseKind, NoiseSpec, Precision, ScaledPerlin,
    WOOD_RING_FALL, fill_parallel, wood_ring, wood_ring_falling_over,
};

/// The Gabor frequency F0 at which a step's `frequency` is its cycles per bounding-box
/// diagonal: the default F0 ([`GaborParams::default`]).
pub const REFERENCE_F0: f64 = 0.0625;

/// A noise evaluated on a level in the recipe's units: coordinates scaled so that
/// `frequency` features span the bounding-box diagonal.
pub struct LevelNoise {
    field: NoiseField,
    origin: DVec3,
    scale: f64,
    /// Marble's sine term in radians per unit length along x, when the step sets
    /// `stripes` (otherwise eq. 4.11's p_x, the noise-space x).
    stripe_scale: Option<f64>,
}

impl LevelNoise {
    /// The noise of `params` at `depth` levels above the input, optionally with Gabor
    /// parameters overridden (one propagation ring of Table 5.1).
    ///
    /// # Errors
    /// [`crate::Error::InvalidInput`] for invalid Gabor parameters.
    pub fn new(
        params: &NoiseParams,
        modulate: bool,
        level: usize,
        depth: usize,
        frame: &BoxFrame,
        seed: u64,
    ) -> Result<Self> {
        let mut fractal = Fractal {
            kind: fractal_kind(params.kind),
            octaves: params.octaves,
            lacunarity: params.lacunarity,
            gain: params.gain,
            offset: params.offset,
        };
        let mut impulses = params.impulses;
        if modulate {
            fractal = fractal.for_level(level as u32);
            impulses *= f64::from(1u32 << depth.min(2));
        }
        let gabor = GaborParams {
            k: params.k,
            a: params.a,
            f0: params.f0,
            omega0: params.omega,
            impulses_per_kernel: impulses,
            isotropic: params.isotropic,
        };
        let field = NoiseField::new(&NoiseSpec {
            kind: params.kind,
            fractal,
            gabor,
            profile: params.profile,
            seed,
            precision: Precision::F64,
        })?;
        let per_unit = params.frequency / frame.diagonal;
        // Gabor and phasor noise: `frequency` counts the cycles of the reference F0 per
        // diagonal, so F0 itself scales the cycles and a the kernel's width, independently
        // (#37: dividing by the step's own F0 cancelled it, leaving only a/F0).
        let scale = if params.kind.is_spectral() { per_unit / REFERENCE_F0 } else { per_unit };
        let stripe_scale = params.stripes.map(|cycles| std::f64::consts::TAU * cycles / frame.diagonal);
        Ok(LevelNoise { field, origin: frame.min, scale, stripe_scale })
    }

    /// The noise value at `p` with the tangent frame `frame` (Gabor orientation), as a
    /// fraction of the kind's peak ([`NoiseField::unit`]).
    pub fn at(&self, p: DVec3, frame: Frame) -> f64 {
        match (&self.field, self.stripe_scale) {
            (NoiseField::Perlin { fractal: Some(f), .. }, Some(_)) => self.fractal_at(f, p),
            _ => self.field.unit(self.field.sample3((p - self.origin) * self.scale, frame)),
        }
    }

    /// [`LevelNoise::at`] at many points, through the field's batch form (Perlin and fBm four
    /// points at a time, #42), the same values bit for bit. Only for kinds without an
    /// orientation (the frames are the default).
    pub fn at_batch(&self, points: &[DVec3]) -> Vec<f64> {
        if let (NoiseField::Perlin { fractal: Some(f), .. }, Some(_)) = (&self.field, self.stripe_scale) {
            return points.iter().map(|&p| self.fractal_at(f, p)).collect();
        }
        let local: Vec<DVec3> = points.iter().map(|&p| (p - self.origin) * self.scale).collect();
        self.field.sample3_batch(&local, &[]).into_iter().map(|v| self.field.unit(v)).collect()
    }

    /// The fractal value at `p` with a shifted lacunarity (variation operator); plain
    /// noise and Gabor noise ignore the shift.
    fn at_shifted(&self, p: DVec3, frame: Frame, lacunarity_shift: f64) -> f64 {
        match &self.field {
            NoiseField::Perlin { fractal: Some(f), .. } if lacunarity_shift != 0.0 => {
                let shifted = Fractal { lacunarity: (f.lacunarity + lacunarity_shift).max(1.0), ..*f };
                self.fractal_at(&shifted, p)
            }
            _ => self.at(p, frame),
        }
    }

    /// `fractal` (this field's, or a shifted copy) at `p` as a fraction of its peak, with
    /// marble's sine term along x at the step's `stripes` when set (eq. 4.11 with its p_x
    /// measured at its own frequency: the turbulence term 4·T(p/2) has a phase gradient
    /// several times p_x's at every frequency, so with the literal p_x no stripe forms, #37).
    fn fractal_at(&self, fractal: &Fractal, p: DVec3) -> f64 {
        let NoiseField::Perlin { basis, .. } = &self.field else { unreachable!("fractal_at needs a Perlin field") };
        let q = (p - self.origin) * self.scale;
        let x = self.stripe_scale.map_or(q.x, |radians| (p.x - self.origin.x) * radians);
        self.field.unit(fractal.eval(x, ScaledPerlin { perlin: basis, point: q }))
    }
}

impl LevelNoise {
    /// `value` (this field's unit value at `p`) with wood's rings faded to their mean where
    /// they are denser than a mesh with edges of `edge` can show: kept whole where a ring
    /// spans eight edges or more, replaced by the mean ½ where it spans four or fewer, a
    /// smoothstep between. Rings finer than the mesh alias into serrated cliffs (#26 B9);
    /// this is clamping (Norton, Rockwood & Skolmoski 1982), the ring density taken as the
    /// change of 10·|F| per edge over half an edge to two along each axis. A ring's fall, a
    /// quarter of it, is also spread over at least three edges (`WOOD_FALL_EDGES`) where
    /// the ring is narrower than twelve: at six to eight edges a quarter is under two, and
    /// a fall of half the peak per edge reads as a notch (#37: 365 edges of the sphere-wood
    /// recipe jumped by more than 0.3 of the peak). Other kinds are returned unchanged.
    pub fn clamped(&self, value: f64, p: DVec3, edge: f64) -> f64 {
        let NoiseField::Perlin { basis, fractal: Some(f) } = &self.field else { return value };
        if f.kind != FractalKind::Wood || edge.is_nan() || edge <= 0.0 {
            return value;
        }
        let fbm = Fractal { kind: FractalKind::Fbm, ..*f };
        let rings = |q: DVec3| 10.0 * fbm.eval(q.x, ScaledPerlin { perlin: basis, point: q }).abs();
        let q = (p - self.origin) * self.scale;
        let ring = rings(q);
        // Rings an edge near `p` crosses: per axis the largest change of the ring coordinate
        // per edge over half an edge, one and two either way (half: the coordinate may rise
        // and fall back within an edge; two: neighbouring vertices see overlapping windows,
        // so the fade does not switch within one edge). Not the gradient: at a critical
        // point of F it is zero while an edge away the rings are dense, and such a vertex
        // kept its whole ring value among neighbours faded to ½ (#37: edges jumping by half
        // the peak).
        let h = self.scale * edge;
        let crossed = |axis: DVec3| {
            let per_edge = |s: f64| (rings(q + axis * s * h) - ring).abs() / s.abs().max(1.0);
            [0.5, -0.5, 1.0, -1.0, 2.0, -2.0].into_iter().map(per_edge).fold(0.0, f64::max)
        };
        let rings_per_edge = DVec3::new(crossed(DVec3::X), crossed(DVec3::Y), crossed(DVec3::Z)).length();
        let fall = (WOOD_FALL_EDGES * rings_per_edge).min(0.5);
        // Only this field's own ring is re-profiled (a variation step's shifted lacunarity
        // gives another value, kept as it is).
        let value = if fall > WOOD_RING_FALL && (value - wood_ring(ring)).abs() <= 1e-12 {
            wood_ring_falling_over(ring, fall)
        } else {
            value
        };
        let t = ((rings_per_edge - 1.0 / 8.0) * 8.0).clamp(0.0, 1.0);
        let shown = 1.0 - t * t * (3.0 - 2.0 * t);
        shown * value + (1.0 - shown) * 0.5
    }
}

/// The fewest edges a wood ring's fall spans in a detail step ([`LevelNoise::clamped`]).
pub const WOOD_FALL_EDGES: f64 = 3.0;

fn fractal_kind(kind: NoiseKind) -> FractalKind {
    match kind {
        NoiseKind::Turbulence => FractalKind::Turbulence,
        NoiseKind::Marble => FractalKind::Marble,
        NoiseKind::Multifractal => FractalKind::Multifractal,
        NoiseKind::Wood => FractalKind::Wood,
        NoiseKind::Perlin | NoiseKind::Fbm | NoiseKind::Gabor | NoiseKind::Phasor => FractalKind::Fbm,
    }
}

/// The tangent frame at a vertex: the diffusion direction projected on the tangent plane,
/// or, where it vanishes or `follow` is off, `REFERENCE_DIRECTION` ((1, 2, 3)/√14) projected on it (as
/// Lagae et al. 2009 orient surface noise, §5: a 3D direction projected on the tangent
/// plane), and normal × that. Both vary continuously with the normal, so the noise has no
/// seam where the surface has none; the projection vanishes only where the normal is
/// parallel to the reference direction (any continuous tangent field on a sphere has such
/// points), and an oblique reference keeps them off axis-aligned surfaces.
pub fn tangent_frame(normal: DVec3, diffusion: Option<DVec3>, follow: bool) -> Frame {
    tangent_frame_toward(normal, diffusion.filter(|_| follow), REFERENCE_DIRECTION)
}

/// [`tangent_frame`] with the diffusion direction where given, else `reference` (a recipe's
/// `orientation`) projected on the tangent plane; where that vanishes too (the normal along
/// it: a crown), any tangent.
pub fn tangent_frame_toward(normal: DVec3, diffusion: Option<DVec3>, reference: DVec3) -> Frame {
    let n = if normal.length_squared() > 0.0 { normal } else { DVec3::Z };
    let project = |d: DVec3| (d - n * n.dot(d)).normalize_or_zero();
    let tangent = match diffusion.map(project) {
        Some(t) if t != DVec3::ZERO => t,
        _ => match project(reference) {
            t if t != DVec3::ZERO => t,
            _ => n.any_orthonormal_vector(),
        },
    };
    Frame { tangent, bitangent: n.cross(tangent).normalize_or_zero() }
}

/// The 3D direction whose projection orients surface noise where no diffusion direction
/// does: oblique to every axis, so no face of an axis-aligned part (CAD, terrain) has its
/// normal along it.
pub const REFERENCE_DIRECTION: DVec3 =
    DVec3::new(0.267_261_241_912_424_4, 0.534_522_483_824_848_8, 0.801_783_725_737_273_2);

/// Unit displacement directions of every vertex of the level.
///
/// # Errors
/// [`crate::Error::InvalidInput`] if the level's analysis fails.
pub fn directions(view: &LevelView, direction: Direction) -> Result<Vec<DVec3>> {
    Ok(match direction {
        Direction::Normal => view.normals.clone(),
        Direction::Inward => view.normals.iter().map(|n| -*n).collect(),
        Direction::Diffusion => view.analysis()?.oriented_diffusion(&view.adjacency),
        Direction::NormalCrossDiffusion => view.analysis()?.oriented_normal_cross_diffusion(&view.adjacency),
    })
}

/// The displacement of one noise step: new positions of the vertices it moves (local
/// indices, ascending). `selected` are the centres; `noised` (local) are skipped unless
/// the step accumulates.
///
/// # Errors
/// [`crate::Error::InvalidInput`] for invalid noise parameters.
pub fn noise_displacements(
    op: OperatorKind,
    params: &NoiseParams,
    view: &LevelView,
    frame: &BoxFrame,
    selected: &[bool],
    noised: &[bool],
    seed: u64,
) -> Result<Vec<(usize, DVec3)>> {
    let variation = op == OperatorKind::Variation;
    let modulate = params.modulate.unwrap_or(variation);
    let shift = params.shift.unwrap_or(if variation { 0.5 } else { 0.0 });
    let free = |v: usize| params.accumulate || !noised[v];
    let centres = free_centres(selected, noised, params.accumulate);
    let mut reach = view.rings_from(&centres, params.rings.len());
    close_reach(view, &mut reach);
    let targets: Vec<usize> = (0..reach.len()).filter(|&v| reach[v].is_some() && free(v)).collect();
    if targets.is_empty() {
        return Ok(Vec::new());
    }
    let ring_noise = ring_fields(params, modulate, view.level, view.depth, frame, seed)?;
    let dirs = directions(view, params.direction)?;
    let diffusion = if params.kind.is_spectral() && params.follows_diffusion() {
        Some(view.analysis()?.oriented_diffusion(&view.adjacency))
    } else {
        None
    };
    let amplitude = params.amplitude * frame.diagonal;
    let edge = view.mean_edge_length();
    let positions = &view.mesh.positions;
    // Unshifted noise of kinds without an orientation, evaluated per ring field in batches.
    let batched: Option<Vec<f64>> = (shift == 0.0 && !params.kind.is_spectral()).then(|| {
        let mut out = vec![0.0; targets.len()];
        for (r, field) in ring_noise.iter().enumerate() {
            let mine: Vec<usize> =
                (0..targets.len()).filter(|&i| reach[targets[i]].is_some_and(|(ring, _)| ring == r)).collect();
            let points: Vec<DVec3> = mine.iter().map(|&i| positions[targets[i]]).collect();
            for (&i, value) in mine.iter().zip(field.at_batch(&points)) {
                out[i] = value;
            }
        }
        out
    });
    let mut values = vec![0.0; targets.len()];
    fill_parallel(&mut values, |i| {
        let v = targets[i];
        let (ring, centre) = reach[v].expect("targets are reached");
        let field = &ring_noise[ring];
        let value = match &batched {
            Some(noise) => field.clamped(noise[i], positions[v], edge),
            None => {
                let tangent = tangent_frame_toward(
                    view.normals[v],
                    diffusion.as_ref().map(|d| d[v]),
                    params.orientation.map_or(REFERENCE_DIRECTION, DVec3::from),
                );
                let u = if shift != 0.0 { centre_shift(seed, view.ids[centre]) } else { 0.0 };
                field.clamped(field.at_shifted(positions[v], tangent, shift * u), positions[v], edge)
                    * (1.0 + shift * u)
            }
        };
        let influence = if ring == 0 { 1.0 } else { params.rings[ring - 1].influence };
        let falloff = match params.attenuation {
            Attenuation::InverseDistance if ring > 0 => {
                1.0 / (positions[v].distance(positions[centre]) / edge).max(1.0)
            }
            _ => 1.0,
        };
        value * influence * falloff
    });
    Ok(targets
        .iter()
        .zip(values)
        .map(|(&v, value)| {
            let level = view.attenuation_level(v, params.attenuate);
            (v, positions[v] + dirs[v] * (amplitude / level * value))
        })
        .collect())
}

/// Closes the rings' reach over single vertices (#26 B7): a vertex the rings missed while
/// every neighbour of it was reached is in a dent of the reach's front, and takes the
/// outermost ring and the centre of its first neighbour on it, so the step's displacement
/// is continuous there instead of leaving the vertex still among moving neighbours.
pub(super) fn close_reach(view: &LevelView, reach: &mut [Option<(usize, usize)>]) {
    let missed: Vec<(usize, (usize, usize))> = (0..reach.len())
        .filter(|&v| reach[v].is_none())
        .filter_map(|v| {
            let ring = view.adjacency.neighbours(v);
            if ring.is_empty() || ring.iter().any(|&u| reach[u as usize].is_none()) {
                return None;
            }
            let outer = ring.iter().filter_map(|&u| reach[u as usize]).max_by_key(|&(k, _)| k)?;
            Some((v, outer))
        })
        .collect();
    for (v, at) in missed {
        reach[v] = Some(at);
    }
}

/// The selected vertices a noise-family step may move: not noised before, unless the step
/// accumulates (§4.5).
pub fn free_centres(selected: &[bool], noised: &[bool], accumulate: bool) -> Vec<usize> {
    (0..selected.len()).filter(|&v| selected[v] && (accumulate || !noised[v])).collect()
}

/// One noise per ring: ring 0 uses the step's parameters, ring k those of Table 5.1's row k.
fn ring_fields(
    params: &NoiseParams,
    modulate: bool,
    level: usize,
    depth: usize,
    frame: &BoxFrame,
    seed: u64,
) -> Result<Vec<LevelNoise>> {
    let mut fields = vec![LevelNoise::new(params, modulate, level, depth, frame, seed)?];
    for ring in &params.rings {
        let p = NoiseParams {
            k: ring.k.unwrap_or(params.k),
            a: ring.a.unwrap_or(params.a),
            f0: ring.f0.unwrap_or(params.f0),
            ..params.clone()
        };
        fields.push(LevelNoise::new(&p, modulate, level, depth, frame, seed)?);
    }
    Ok(fields)
}

/// A centre's random shift in [-1, 1] (the variation operator's per-area shift).
pub fn centre_shift(seed: u64, id: u32) -> f64 {
    let mut s = Stream::new(hash_coords(derive_seed(seed, "variation shift"), &[i64::from(id)]));
    s.uniform(-1.0, 1.0)
}
