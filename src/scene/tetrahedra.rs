//! Marching tetrahedra (Payne & Toga 1990, as seed 002 uses it): every cube of a scalar
//! grid is cut into six tetrahedra sharing the cube's main diagonal, and each tetrahedron's
//! 16 inside/outside cases give no triangle (all inside or all outside), one triangle (one
//! corner apart from the other three) or two (two and two). Surface vertices are linearly
//! interpolated along grid edges and shared between neighbouring cells, so a surface that
//! stays inside the grid is closed and manifold. Vertex normals follow the seed: the
//! field's gradient at grid points by central differences (forward or backward at the
//! grid's faces), interpolated like the positions.

use glam::DVec3;
use rustc_hash::FxHashMap;

use crate::mesh::Mesh;

/// A scalar field sampled on a regular grid.
#[derive(Debug, Clone)]
pub struct ScalarGrid {
    /// Position of grid point (0, 0, 0).
    pub origin: DVec3,
    /// Distance between neighbouring grid points.
    pub spacing: f64,
    /// Points along x, y and z.
    pub dims: [usize; 3],
    /// Values, x fastest, then y, then z.
    pub values: Vec<f64>,
}

impl ScalarGrid {
    /// A grid of zeros.
    pub fn zeros(origin: DVec3, spacing: f64, dims: [usize; 3]) -> Self {
        ScalarGrid { origin, spacing, dims, values: vec![0.0; dims[0] * dims[1] * dims[2]] }
    }

    /// Index of grid point (x, y, z).
    pub fn index(&self, x: usize, y: usize, z: usize) -> usize {
        (z * self.dims[1] + y) * self.dims[0] + x
    }

    /// Position of the grid point with index `i`.
    pub fn position(&self, i: usize) -> DVec3 {
        let [x, y, z] = self.coords(i);
        self.origin + DVec3::new(x as f64, y as f64, z as f64) * self.spacing
    }

    fn coords(&self, i: usize) -> [usize; 3] {
        [i % self.dims[0], (i / self.dims[0]) % self.dims[1], i / (self.dims[0] * self.dims[1])]
    }

    /// The field's gradient at grid point `i`: central differences inside, forward or
    /// backward differences on the grid's faces.
    pub fn gradient(&self, i: usize) -> DVec3 {
        let c = self.coords(i);
        let mut g = [0.0; 3];
        for (axis, slot) in g.iter_mut().enumerate() {
            let stride = [1, self.dims[0], self.dims[0] * self.dims[1]][axis];
            let (lo, hi) = (c[axis] > 0, c[axis] + 1 < self.dims[axis]);
            *slot = match (lo, hi) {
                (true, true) => (self.values[i + stride] - self.values[i - stride]) / (2.0 * self.spacing),
                (false, true) => (self.values[i + stride] - self.values[i]) / self.spacing,
                (true, false) => (self.values[i] - self.values[i - stride]) / self.spacing,
                (false, false) => 0.0,
            };
        }
        DVec3::from(g)
    }

    /// Cubes of the grid (indexed by their lowest corner), in index order.
    pub fn all_cubes(&self) -> Vec<usize> {
        let [nx, ny, nz] = self.dims;
        (0..nz.saturating_sub(1))
            .flat_map(|z| (0..ny.saturating_sub(1)).flat_map(move |y| (0..nx.saturating_sub(1)).map(move |x| (x, y, z))))
            .map(|(x, y, z)| self.index(x, y, z))
            .collect()
    }
}

/// The six tetrahedra of a cube, as corner numbers (bit 0: +x, bit 1: +y, bit 2: +z), all
/// sharing the diagonal from corner 0 to corner 7: one per monotone path 0 → 7.
pub const CUBE_TETRAHEDRA: [[usize; 4]; 6] =
    [[0, 1, 3, 7], [0, 1, 5, 7], [0, 2, 3, 7], [0, 2, 6, 7], [0, 4, 5, 7], [0, 4, 6, 7]];

/// What [`marching_tetrahedra`] visited.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Visited {
    /// Cubes examined.
    pub cubes: usize,
    /// Tetrahedra with a piece of surface (the 14 non-degenerate cases).
    pub crossed: usize,
}

/// The isosurface `value = iso` of `grid` through the `cubes` given (lowest-corner grid
/// indices; cubes whose corners are all on one side add nothing). Points with a value above
/// `iso` are inside; triangles face outwards (towards lower values) and the mesh carries
/// vertex normals from the gradient.
pub fn marching_tetrahedra(grid: &ScalarGrid, iso: f64, cubes: &[usize]) -> (Mesh, Visited) {
    let [nx, ny, _] = grid.dims;
    let corner_offset: [usize; 8] = std::array::from_fn(|k| (k & 1) + ((k >> 1) & 1) * nx + ((k >> 2) & 1) * nx * ny);
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    let mut on_edge: FxHashMap<(usize, usize), u32> = FxHashMap::default();
    let mut triangles = Vec::new();
    let mut visited = Visited::default();
    let mut vertex = |a: usize, b: usize, positions: &mut Vec<DVec3>| -> u32 {
        let key = if a < b { (a, b) } else { (b, a) };
        *on_edge.entry(key).or_insert_with(|| {
            let (fa, fb) = (grid.values[key.0], grid.values[key.1]);
            // A value exactly at `iso` counts as outside; the clamp keeps the vertex off
            // the grid point, so no two edges give the same position.
            let t = ((iso - fa) / (fb - fa)).clamp(1e-6, 1.0 - 1e-6);
            let (pa, pb) = (grid.position(key.0), grid.position(key.1));
            positions.push(pa.lerp(pb, t));
            let n = grid.gradient(key.0).lerp(grid.gradient(key.1), t);
            normals.push((-n).try_normalize().unwrap_or((pb - pa).normalize() * (fa - fb).signum()));
            (positions.len() - 1) as u32
        })
    };
    for &cube in cubes {
        visited.cubes += 1;
        let corners = corner_offset.map(|o| cube + o);
        let inside = corners.map(|c| grid.values[c] > iso);
        if inside.iter().all(|&i| i) || inside.iter().all(|&i| !i) {
            continue;
        }
        for tet in CUBE_TETRAHEDRA {
            let points = tet.map(|k| corners[k]);
            let (ins, outs): (Vec<usize>, Vec<usize>) = points.iter().partition(|&&p| grid.values[p] > iso);
            if ins.is_empty() || outs.is_empty() {
                continue;
            }
            visited.crossed += 1;
            let centroid = |ps: &[usize]| ps.iter().map(|&p| grid.position(p)).sum::<DVec3>() / ps.len() as f64;
            let outward = centroid(&outs) - centroid(&ins);
            let pieces: Vec<[(usize, usize); 3]> = match (ins.len(), outs.len()) {
                (1, 3) => vec![[(ins[0], outs[0]), (ins[0], outs[1]), (ins[0], outs[2])]],
                (3, 1) => vec![[(ins[0], outs[0]), (ins[1], outs[0]), (ins[2], outs[0])]],
                _ => {
                    // Two and two: the four crossed edges form the cycle a–c, a–d, b–d, b–c.
                    let (a, b, c, d) = (ins[0], ins[1], outs[0], outs[1]);
                    vec![[(a, c), (a, d), (b, d)], [(a, c), (b, d), (b, c)]]
                }
            };
            for piece in pieces {
                let mut t = piece.map(|(p, q)| vertex(p, q, &mut positions));
                let [p0, p1, p2] = t.map(|v| positions[v as usize]);
                if (p1 - p0).cross(p2 - p0).dot(outward) < 0.0 {
                    t.swap(1, 2);
                }
                triangles.push(t);
            }
        }
    }
    let mut mesh = Mesh::new(positions, triangles);
    mesh.normals = Some(normals);
    (mesh, visited)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A signed distance-like field of a sphere, positive inside.
    fn sphere_grid(radius: f64, n: usize) -> ScalarGrid {
        let spacing = 2.6 * radius / (n - 1) as f64;
        let mut grid = ScalarGrid::zeros(DVec3::splat(-1.3 * radius), spacing, [n; 3]);
        for i in 0..grid.values.len() {
            grid.values[i] = radius - grid.position(i).length();
        }
        grid
    }

    #[test]
    fn a_sphere_becomes_a_closed_outward_genus_zero_surface() {
        let grid = sphere_grid(1.0, 21);
        let (mesh, visited) = marching_tetrahedra(&grid, 0.0, &grid.all_cubes());
        let report = mesh.validate();
        assert!(report.is_closed_manifold(), "{report:?}");
        assert_eq!(report.genus, Some(0));
        assert_eq!(report.inconsistently_oriented_edges, 0);
        assert_eq!(visited.cubes, 20 * 20 * 20);
        assert!(visited.crossed > 0);
        let volume = mesh.signed_volume();
        assert!(volume > 0.0, "outward faces give a positive volume, got {volume}");
        // Normals point away from the centre.
        let normals = mesh.normals.as_ref().unwrap();
        for (p, n) in mesh.positions.iter().zip(normals) {
            assert!(p.normalize().dot(*n) > 0.95);
        }
    }

    #[test]
    fn the_six_tetrahedra_fill_the_cube() {
        let corner = |k: usize| DVec3::new((k & 1) as f64, ((k >> 1) & 1) as f64, ((k >> 2) & 1) as f64);
        let total: f64 = CUBE_TETRAHEDRA
            .iter()
            .map(|t| {
                let [a, b, c, d] = t.map(corner);
                ((b - a).dot((c - a).cross(d - a)) / 6.0).abs()
            })
            .sum();
        assert!((total - 1.0).abs() < 1e-12);
    }

    #[test]
    fn gradients_use_one_sided_differences_on_the_faces() {
        let mut grid = ScalarGrid::zeros(DVec3::ZERO, 0.5, [3, 2, 2]);
        for i in 0..grid.values.len() {
            let p = grid.position(i);
            grid.values[i] = p.x * p.x + 2.0 * p.y;
        }
        // x = 0: forward (0.25 − 0)/0.5; x = 0.5: central (1 − 0)/1; x = 1: backward.
        assert_eq!(grid.gradient(grid.index(0, 0, 0)), DVec3::new(0.5, 2.0, 0.0));
        assert_eq!(grid.gradient(grid.index(1, 1, 1)), DVec3::new(1.0, 2.0, 0.0));
        assert_eq!(grid.gradient(grid.index(2, 0, 0)), DVec3::new(1.5, 2.0, 0.0));
    }
}
