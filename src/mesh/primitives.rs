//! Meshes made in code, for tests, demos and benchmarks: all closed (except the grid),
//! consistently oriented counter-clockwise seen from outside.

use std::collections::HashMap;
use std::f64::consts::TAU;

use glam::DVec3;

use super::Mesh;

/// Torus around the z axis with tube centre radius `major`, tube radius `minor`, `rings`
/// segments around the axis and `sides` around the tube (genus 1, χ = 0).
pub fn torus(major: f64, minor: f64, rings: u32, sides: u32) -> Mesh {
    let mut positions = Vec::with_capacity((rings * sides) as usize);
    for i in 0..rings {
        let u = TAU * f64::from(i) / f64::from(rings);
        for j in 0..sides {
            let v = TAU * f64::from(j) / f64::from(sides);
            let r = major + minor * v.cos();
            positions.push(DVec3::new(r * u.cos(), r * u.sin(), minor * v.sin()));
        }
    }
    let id = |i: u32, j: u32| (i % rings) * sides + (j % sides);
    let mut triangles = Vec::with_capacity((2 * rings * sides) as usize);
    for i in 0..rings {
        for j in 0..sides {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
    }
    Mesh::new(positions, triangles)
}

/// Sphere of radius `radius` from an icosahedron subdivided `level` times (each level
/// splits every triangle in four and projects to the sphere): 10·4ˡ + 2 vertices.
pub fn icosphere(radius: f64, level: u32) -> Mesh {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut positions: Vec<DVec3> = [
        (-1.0, t, 0.0),
        (1.0, t, 0.0),
        (-1.0, -t, 0.0),
        (1.0, -t, 0.0),
        (0.0, -1.0, t),
        (0.0, 1.0, t),
        (0.0, -1.0, -t),
        (0.0, 1.0, -t),
        (t, 0.0, -1.0),
        (t, 0.0, 1.0),
        (-t, 0.0, -1.0),
        (-t, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| DVec3::new(x, y, z).normalize())
    .collect();
    let mut triangles: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..level {
        let mut midpoints: HashMap<(u32, u32), u32> = HashMap::new();
        let mut midpoint = |a: u32, b: u32, positions: &mut Vec<DVec3>| {
            *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                positions.push(((positions[a as usize] + positions[b as usize]) * 0.5).normalize());
                (positions.len() - 1) as u32
            })
        };
        let mut next = Vec::with_capacity(triangles.len() * 4);
        for [a, b, c] in triangles {
            let ab = midpoint(a, b, &mut positions);
            let bc = midpoint(b, c, &mut positions);
            let ca = midpoint(c, a, &mut positions);
            next.extend_from_slice(&[[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        triangles = next;
    }
    for p in &mut positions {
        *p *= radius;
    }
    Mesh::new(positions, triangles)
}

/// Axis-aligned box from `min` to `max`, each side split into `n`×`n` squares of two
/// triangles (vertices shared along edges): 6n² + 2 vertices, 12n² faces.
pub fn cube(min: DVec3, max: DVec3, n: u32) -> Mesh {
    let n = n.max(1);
    let mut index: HashMap<[i64; 3], u32> = HashMap::new();
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    let mut vertex = |g: [i64; 3], positions: &mut Vec<DVec3>| {
        *index.entry(g).or_insert_with(|| {
            let f = |k: usize| min[k] + (max[k] - min[k]) * g[k] as f64 / f64::from(n);
            positions.push(DVec3::new(f(0), f(1), f(2)));
            (positions.len() - 1) as u32
        })
    };
    let n = i64::from(n);
    // Each side: the fixed axis, its grid value, and two in-plane axes ordered so the
    // side's outward normal is u × v.
    for (axis, at, u, v) in [(0, 0, 2, 1), (0, n, 1, 2), (1, 0, 0, 2), (1, n, 2, 0), (2, 0, 1, 0), (2, n, 0, 1)] {
        for i in 0..n {
            for j in 0..n {
                let corner = |di: i64, dj: i64| {
                    let mut g = [0i64; 3];
                    g[axis] = at;
                    g[u] = i + di;
                    g[v] = j + dj;
                    g
                };
                let a = vertex(corner(0, 0), &mut positions);
                let b = vertex(corner(1, 0), &mut positions);
                let c = vertex(corner(1, 1), &mut positions);
                let d = vertex(corner(0, 1), &mut positions);
                triangles.push([a, b, c]);
                triangles.push([a, c, d]);
            }
        }
    }
    Mesh::new(positions, triangles)
}

/// Flat `n`×`n`-cell grid over the unit square in the z = 0 plane (open, one boundary loop).
pub fn grid(n: u32) -> Mesh {
    let n = n.max(1);
    let mut positions = Vec::with_capacity(((n + 1) * (n + 1)) as usize);
    for j in 0..=n {
        for i in 0..=n {
            positions.push(DVec3::new(f64::from(i) / f64::from(n), f64::from(j) / f64::from(n), 0.0));
        }
    }
    let id = |i: u32, j: u32| j * (n + 1) + i;
    let mut triangles = Vec::with_capacity((2 * n * n) as usize);
    for j in 0..n {
        for i in 0..n {
            triangles.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            triangles.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    Mesh::new(positions, triangles)
}
