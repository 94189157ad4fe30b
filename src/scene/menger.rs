//! The Menger sponge (seed 002, "Menger Sponge in C++ using OpenGL"): a cube cut into 27,
//! the centre of each face and the centre cube removed, recursively. Where the seed draws
//! every small cube's six faces, this keeps only the faces between sponge and air — the
//! outer faces and the tunnel walls — so the result is one closed manifold with no
//! internal faces.

use glam::DVec3;
use rustc_hash::FxHashMap;
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::mesh::Mesh;

/// The deepest level built (level 5 has 6.6 million faces).
pub const MAX_LEVEL: u32 = 5;

/// Whether the small cube at integer position `(x, y, z)` (each in `0..3^level`) belongs to
/// the sponge: it does unless, at some digit of the base-3 expansions, at least two of the
/// three coordinates have a 1 (the cube sits in a removed face centre or centre cube).
pub fn is_solid(mut x: u32, mut y: u32, mut z: u32) -> bool {
    while x > 0 || y > 0 || z > 0 {
        let ones = u32::from(x % 3 == 1) + u32::from(y % 3 == 1) + u32::from(z % 3 == 1);
        if ones >= 2 {
            return false;
        }
        (x, y, z) = (x / 3, y / 3, z / 3);
    }
    true
}

/// Square faces of a level-`level` sponge (in cells of side 3^−level): the closed form of
/// its surface area, 2·20ⁿ + 4·8ⁿ (the top and bottom views each see 20ⁿ cells; the four
/// sides see 8ⁿ per tunnel-free column pattern, summed).
pub fn square_count(level: u32) -> u64 {
    2 * 20u64.pow(level) + 4 * 8u64.pow(level)
}

/// The Menger sponge request (#38): what `asperity menger` asks for.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
pub struct MengerRequest {
    /// Recursion level (0 is the cube).
    #[cfg_attr(
        feature = "cli",
        arg(long, default_value_t = 3, value_parser = clap::value_parser!(u32).range(0..=i64::from(MAX_LEVEL)))
    )]
    pub level: u32,
    /// Edge length of the whole sponge, centred at the origin.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = 1.0))]
    pub edge: f64,
}

impl Default for MengerRequest {
    fn default() -> Self {
        MengerRequest { level: 3, edge: 1.0 }
    }
}

impl MengerRequest {
    /// The sponge ([`menger_sponge`]).
    ///
    /// # Errors
    /// As [`menger_sponge`].
    pub fn sponge(&self) -> Result<Mesh> {
        menger_sponge(self.level, self.edge)
    }
}

/// The level-`level` sponge with edge length `edge`, centred at the origin: every square
/// between a solid cell and air, as two triangles, outward-facing, vertices shared.
///
/// # Errors
/// [`Error::InvalidInput`] for a level above [`MAX_LEVEL`] or a non-positive or
/// non-finite edge.
pub fn menger_sponge(level: u32, edge: f64) -> Result<Mesh> {
    if level > MAX_LEVEL {
        return Err(Error::InvalidInput(format!(
            "Menger level {level}: at most {MAX_LEVEL} ({} faces)",
            2 * square_count(MAX_LEVEL)
        )));
    }
    if !(edge.is_finite() && edge > 0.0) {
        return Err(Error::InvalidInput(format!("Menger edge length {edge}: must be positive and finite")));
    }
    let n = 3u32.pow(level);
    let solid = |x: i64, y: i64, z: i64| {
        let inside = |c: i64| (0..i64::from(n)).contains(&c);
        inside(x) && inside(y) && inside(z) && is_solid(x as u32, y as u32, z as u32)
    };
    let cell = edge / f64::from(n);
    let mut positions = Vec::new();
    let mut index: FxHashMap<[u32; 3], u32> = FxHashMap::default();
    let mut vertex = |corner: [u32; 3]| {
        *index.entry(corner).or_insert_with(|| {
            positions.push(DVec3::new(
                f64::from(corner[0]) * cell - edge * 0.5,
                f64::from(corner[1]) * cell - edge * 0.5,
                f64::from(corner[2]) * cell - edge * 0.5,
            ));
            (positions.len() - 1) as u32
        })
    };
    let mut triangles = Vec::with_capacity(2 * square_count(level) as usize);
    for z in 0..n {
        for y in 0..n {
            for x in 0..n {
                if !is_solid(x, y, z) {
                    continue;
                }
                for (axis, side) in [(0, 0), (0, 1), (1, 0), (1, 1), (2, 0), (2, 1)] {
                    let mut neighbour = [i64::from(x), i64::from(y), i64::from(z)];
                    neighbour[axis] += if side == 1 { 1 } else { -1 };
                    if solid(neighbour[0], neighbour[1], neighbour[2]) {
                        continue;
                    }
                    let square = face_square([x, y, z], axis, side).map(&mut vertex);
                    triangles.push([square[0], square[1], square[2]]);
                    triangles.push([square[0], square[2], square[3]]);
                }
            }
        }
    }
    Ok(Mesh::new(positions, triangles))
}

/// The four grid corners of the face of cell `c` normal to `axis` on `side` (0: low,
/// 1: high), counter-clockwise seen from outside the cell.
fn face_square(c: [u32; 3], axis: usize, side: u32) -> [[u32; 3]; 4] {
    let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
    let corner = |du: u32, dv: u32| {
        let mut p = c;
        p[axis] += side;
        p[u] += du;
        p[v] += dv;
        p
    };
    // (u, v, axis) is right-handed, so u then v runs counter-clockwise seen from +axis.
    if side == 1 {
        [corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)]
    } else {
        [corner(0, 0), corner(0, 1), corner(1, 1), corner(1, 0)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn level_one_is_a_closed_genus_five_surface_with_its_closed_form_face_count() {
        let sponge = menger_sponge(1, 1.0).unwrap();
        let report = sponge.validate();
        assert!(report.is_closed_manifold(), "{report:?}");
        assert_eq!(report.inconsistently_oriented_edges, 0);
        assert_eq!(report.genus, Some(5));
        assert_eq!(sponge.face_count() as u64, 2 * square_count(1));
        assert_eq!(square_count(1), 72);
    }

    #[test]
    fn every_level_up_to_three_is_closed_and_outward_with_the_closed_form_count() {
        for level in 0..=3 {
            let sponge = menger_sponge(level, 2.0).unwrap();
            let report = sponge.validate();
            assert!(report.is_closed_manifold(), "level {level}: {report:?}");
            assert_eq!(sponge.face_count() as u64, 2 * square_count(level), "level {level}");
            // Outward: the signed volume is the sponge's, (20/27)ⁿ of the cube's.
            let volume = sponge.signed_volume();
            let expected = 8.0 * (20.0f64 / 27.0).powi(level as i32);
            assert!((volume - expected).abs() < 1e-9, "level {level}: volume {volume}, expected {expected}");
        }
    }

    #[test]
    fn levels_and_edges_out_of_range_are_refused() {
        assert!(menger_sponge(MAX_LEVEL + 1, 1.0).is_err());
        assert!(menger_sponge(1, 0.0).is_err());
        assert!(menger_sponge(1, f64::NAN).is_err());
    }
}
