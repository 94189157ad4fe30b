//! The cabin of seed 002's scene: a log-coloured box with a gable roof and a chimney, each
//! a closed mesh, standing on the origin with its ridge along x. The chimney's top is where
//! the smoke starts.

use glam::DVec3;

use crate::mesh::Mesh;
use crate::mesh::primitives::cube;

/// A cabin `width` long (x); its depth is 0.7 and its wall height 0.55 of the width.
pub struct Cabin {
    /// Walls, roof and chimney, coloured.
    pub mesh: Mesh,
    /// The centre of the chimney's top.
    pub chimney_top: DVec3,
}

/// Builds a cabin of the given width.
pub fn cabin(width: f64) -> Cabin {
    let (w, d, h) = (width, 0.7 * width, 0.55 * width);
    let mut mesh = coloured(cube(DVec3::new(-w / 2.0, -d / 2.0, 0.0), DVec3::new(w / 2.0, d / 2.0, h), 1), [120, 82, 50]);
    mesh.append(&coloured(roof(w * 1.1, d * 1.15, h, 0.35 * width), [90, 40, 35]));
    let chimney_lo = DVec3::new(0.25 * w, 0.05 * d, 0.5 * h);
    let chimney_hi = DVec3::new(0.25 * w + 0.14 * w, 0.05 * d + 0.14 * w, h + 0.55 * width);
    mesh.append(&coloured(cube(chimney_lo, chimney_hi, 1), [110, 105, 100]));
    let chimney_top = DVec3::new((chimney_lo.x + chimney_hi.x) / 2.0, (chimney_lo.y + chimney_hi.y) / 2.0, chimney_hi.z);
    Cabin { mesh, chimney_top }
}

/// A closed triangular prism: eaves at height `eaves`, ridge `rise` above, along x.
fn roof(length: f64, depth: f64, eaves: f64, rise: f64) -> Mesh {
    let (x, y) = (length / 2.0, depth / 2.0);
    let positions = vec![
        DVec3::new(-x, -y, eaves),
        DVec3::new(-x, y, eaves),
        DVec3::new(-x, 0.0, eaves + rise),
        DVec3::new(x, -y, eaves),
        DVec3::new(x, y, eaves),
        DVec3::new(x, 0.0, eaves + rise),
    ];
    let triangles = vec![
        [0, 2, 1],
        [3, 4, 5],
        [0, 3, 5],
        [0, 5, 2],
        [1, 2, 5],
        [1, 5, 4],
        [0, 1, 4],
        [0, 4, 3],
    ];
    Mesh::new(positions, triangles)
}

fn coloured(mut mesh: Mesh, color: [u8; 3]) -> Mesh {
    mesh.colors = Some(vec![color; mesh.vertex_count()]);
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cabin_is_three_closed_outward_parts_with_the_chimney_on_top() {
        let c = cabin(4.0);
        let report = c.mesh.validate();
        assert!(report.is_closed_manifold(), "{report:?}");
        assert_eq!(report.components, 3);
        assert_eq!(report.inconsistently_oriented_edges, 0);
        assert!(c.mesh.signed_volume() > 0.0);
        let top = c.mesh.positions.iter().map(|p| p.z).fold(f64::MIN, f64::max);
        assert!((c.chimney_top.z - top).abs() < 1e-12, "the chimney is the highest point");
    }
}
