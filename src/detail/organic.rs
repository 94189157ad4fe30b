//! The organic operator (thesis §4.7.5.1, Algorithm 5): extensions grown at the selected
//! centres. Each centre moves along its normal bent towards the normal of a randomly
//! chosen vertex ("choosing a random point and pick its normal to guide this new
//! direction"), by a height modulated by the noise at the centre; its 1-ring and 2-ring
//! follow with falling weights (the mushroom planet's 1/1.5 and 1/2, §5.2.0.1). The level
//! attenuation of eq. 4.5 applies when the noise table asks for it. Local subdivision
//! beforehand (the `subdivide` parameter) gives the extensions more vertices. The
//! mushroom planet's second displacement (`widen`, §5.2.0.1) then moves each ring's
//! vertices away from the extension's axis, by a share of its length that the noise at
//! each vertex varies ("this area will vary from vertex to vertex"): a wide cap on a stem.

use glam::DVec3;

use super::displace::{LevelNoise, free_centres, tangent_frame};
use super::level::{BoxFrame, LevelView};
use super::recipe::{NoiseParams, OrganicParams};
use crate::error::Result;
use crate::noise::hash::{derive_seed, hash_coords};

/// New positions of the vertices the extensions move (local indices, ascending).
///
/// # Errors
/// [`crate::Error::InvalidInput`] for invalid noise parameters.
pub fn organic_displacements(
    params: &OrganicParams,
    noise: &NoiseParams,
    view: &LevelView,
    frame: &BoxFrame,
    selected: &[bool],
    noised: &[bool],
    seed: u64,
) -> Result<Vec<(usize, DVec3)>> {
    let n = view.ids.len();
    let free = |v: usize| noise.accumulate || !noised[v];
    let centres = free_centres(selected, noised, noise.accumulate);
    if centres.is_empty() || params.rings.is_empty() {
        return Ok(Vec::new());
    }
    let field = LevelNoise::new(noise, false, view.level, view.depth, frame, seed)?;
    let height = params.height * frame.diagonal;
    let pick = derive_seed(seed, "organic direction");
    let mut growth = vec![DVec3::ZERO; n];
    for &c in &centres {
        let normal = view.normals[c];
        let value = field.at(view.mesh.positions[c], tangent_frame(normal, None, false));
        let other = (hash_coords(pick, &[i64::from(view.ids[c])]) % n as u64) as usize;
        let bent = (normal + params.bend * view.normals[other]).normalize_or_zero();
        let direction = if bent == DVec3::ZERO { normal } else { bent };
        let scale = height / view.attenuation_level(c, noise.attenuate);
        growth[c] = direction * scale * (0.5 + value.abs());
    }
    let mut reach = view.rings_from(&centres, params.rings.len() - 1);
    super::displace::close_reach(view, &mut reach);
    let positions = &view.mesh.positions;
    Ok((0..n)
        .filter_map(|v| {
            let (ring, centre) = reach[v].filter(|_| free(v))?;
            let grown = positions[v] + growth[centre] * params.rings[ring];
            let moved = match params.widen.get(ring).copied().unwrap_or(0.0) {
                0.0 => grown,
                w => grown + outward(positions[v] - positions[centre], growth[centre]) * w * wobble(&field, v, view),
            };
            Some((v, moved))
        })
        .collect())
}

/// The widening of a vertex `offset` from its centre, for an extension `growth`: the
/// offset's part across the extension, with the extension's length (zero at the centre).
fn outward(offset: DVec3, growth: DVec3) -> DVec3 {
    let axis = growth.normalize_or_zero();
    (offset - axis * offset.dot(axis)).normalize_or_zero() * growth.length()
}

/// How much of its ring's widening a vertex takes: 0.5 + |noise| at it, the same
/// modulation as the extension's height.
fn wobble(field: &LevelNoise, v: usize, view: &LevelView) -> f64 {
    0.5 + field.at(view.mesh.positions[v], tangent_frame(view.normals[v], None, false)).abs()
}
