//! The organic operator (thesis §4.7.5.1, Algorithm 5): extensions grown at the selected
//! centres. Each centre moves along its normal bent towards the normal of a randomly
//! chosen vertex ("choosing a random point and pick its normal to guide this new
//! direction"), by a height modulated by the noise at the centre; its 1-ring and 2-ring
//! follow with falling weights (the mushroom planet's 1/1.5 and 1/2, §5.2.0.1). The level
//! attenuation of eq. 4.5 applies when the noise table asks for it. Local subdivision
//! beforehand (the `subdivide` parameter) gives the extensions more vertices.

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
    Ok((0..n)
        .filter_map(|v| {
            let (ring, centre) = reach[v]?;
            free(v).then(|| (v, view.mesh.positions[v] + growth[centre] * params.rings[ring]))
        })
        .collect())
}
