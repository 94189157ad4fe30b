//! Polygon triangulation: ear clipping in the plane of the polygon's Newell normal, so
//! non-convex polygons (as in OFF and OBJ files) are cut correctly.

use glam::{DVec2, DVec3};

/// Polygons above this size are fanned: ear clipping is quadratic.
const MAX_EAR_CLIPPED: usize = 256;

/// Appends the triangles of `polygon` (vertex indices into `positions`, counter-clockwise)
/// to `out`. Triangles pass through unchanged. Returns the number of triangles added.
pub fn triangulate_polygon(positions: &[DVec3], polygon: &[u32], out: &mut Vec<[u32; 3]>) -> usize {
    let n = polygon.len();
    if n < 3 {
        return 0;
    }
    if n == 3 || n > MAX_EAR_CLIPPED {
        fan(polygon, out);
        return n - 2;
    }
    let flat = project_to_plane(positions, polygon);
    let mut ring: Vec<usize> = (0..n).collect();
    while ring.len() > 3 {
        match find_ear(&flat, &ring) {
            Some(i) => {
                let m = ring.len();
                out.push([polygon[ring[(i + m - 1) % m]], polygon[ring[i]], polygon[ring[(i + 1) % m]]]);
                ring.remove(i);
            }
            None => break, // self-intersecting or degenerate: fan what is left
        }
    }
    let rest: Vec<u32> = ring.iter().map(|&i| polygon[i]).collect();
    fan(&rest, out);
    n - 2
}

/// Triangulates every polygon; returns the triangles and how many polygons (more than
/// three corners) were split.
pub fn triangulate_polygons<'a>(
    positions: &[DVec3],
    polygons: impl IntoIterator<Item = &'a [u32]>,
) -> (Vec<[u32; 3]>, usize) {
    let mut out = Vec::new();
    let mut split = 0;
    for p in polygons {
        if p.len() > 3 {
            split += 1;
        }
        triangulate_polygon(positions, p, &mut out);
    }
    (out, split)
}

fn fan(polygon: &[u32], out: &mut Vec<[u32; 3]>) {
    for k in 1..polygon.len().saturating_sub(1) {
        out.push([polygon[0], polygon[k], polygon[k + 1]]);
    }
}

/// Drops the dominant axis of the Newell normal. Each Newell component is twice the signed
/// area of the projection on the matching coordinate plane ((y,z), (z,x), (x,y)), so a
/// negative component means the projection is clockwise: mirroring one axis fixes that.
fn project_to_plane(positions: &[DVec3], polygon: &[u32]) -> Vec<DVec2> {
    let pts: Vec<DVec3> = polygon.iter().map(|&v| positions[v as usize]).collect();
    let mut normal = DVec3::ZERO;
    for (i, a) in pts.iter().enumerate() {
        let b = pts[(i + 1) % pts.len()];
        normal += DVec3::new((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
    }
    let abs = normal.abs();
    let (axis_u, axis_v, sign) = if abs.x >= abs.y && abs.x >= abs.z {
        (1, 2, normal.x.signum())
    } else if abs.y >= abs.z {
        (2, 0, normal.y.signum())
    } else {
        (0, 1, normal.z.signum())
    };
    pts.iter().map(|p| DVec2::new(sign * p[axis_u], p[axis_v])).collect()
}

fn cross2(o: DVec2, a: DVec2, b: DVec2) -> f64 {
    (a - o).perp_dot(b - o)
}

/// A convex corner whose triangle contains no other polygon vertex.
fn find_ear(flat: &[DVec2], ring: &[usize]) -> Option<usize> {
    let m = ring.len();
    (0..m).find(|&i| {
        let (a, b, c) = (flat[ring[(i + m - 1) % m]], flat[ring[i]], flat[ring[(i + 1) % m]]);
        if cross2(a, b, c) <= 0.0 {
            return false;
        }
        ring.iter().enumerate().all(|(j, &r)| {
            if j == i || j == (i + m - 1) % m || j == (i + 1) % m {
                return true;
            }
            let p = flat[r];
            !(cross2(a, b, p) >= 0.0 && cross2(b, c, p) >= 0.0 && cross2(c, a, p) >= 0.0)
        })
    })
}
