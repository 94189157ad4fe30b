//! The smoothing operator (thesis §4.7.1.2): Loop's vertex masks applied in place of a
//! subdivision (Loop 1987). An interior vertex of degree n moves to (1 − nβ)·p + β·Σ qᵢ with
//! β = (5/8 − (3/8 + cos(2π/n)/4)²)/n; a boundary vertex to 3/4·p + 1/8·(a + b), a and b its
//! boundary neighbours. All selected vertices move at once per pass (Jacobi order), so the
//! result does not depend on vertex order.

use glam::DVec3;

use super::level::LevelView;

/// β of Loop's interior mask for degree `n`.
pub fn loop_beta(n: usize) -> f64 {
    let n = n as f64;
    let c = 3.0 / 8.0 + (2.0 * std::f64::consts::PI / n).cos() / 4.0;
    (5.0 / 8.0 - c * c) / n
}

/// New positions of the selected vertices after `iterations` passes (local indices,
/// ascending); unselected vertices stay where they are.
pub fn loop_smooth(view: &LevelView, selected: &[bool], iterations: usize) -> Vec<(usize, DVec3)> {
    let mut positions = view.mesh.positions.clone();
    let chosen: Vec<usize> = (0..selected.len()).filter(|&v| selected[v]).collect();
    for _ in 0..iterations {
        let moved: Vec<DVec3> = chosen
            .iter()
            .map(|&v| {
                let p = positions[v];
                match view.adjacency.boundary_neighbours(&view.mesh, v).as_slice() {
                    [a, b] => 0.75 * p + 0.125 * (positions[*a as usize] + positions[*b as usize]),
                    [_, ..] => p,
                    [] => {
                        let ring = view.adjacency.neighbours(v);
                        if ring.len() < 3 {
                            return p;
                        }
                        let beta = loop_beta(ring.len());
                        let sum: DVec3 = ring.iter().map(|&q| positions[q as usize]).sum();
                        (1.0 - ring.len() as f64 * beta) * p + beta * sum
                    }
                }
            })
            .collect();
        for (&v, p) in chosen.iter().zip(moved) {
            positions[v] = p;
        }
    }
    chosen.into_iter().map(|v| (v, positions[v])).collect()
}

/// Σ over vertices of |p − mean of neighbours|²: the umbrella Laplacian's energy, which
/// smoothing lowers.
pub fn laplacian_energy(view_positions: &[DVec3], view: &LevelView) -> f64 {
    (0..view_positions.len())
        .map(|v| {
            let ring = view.adjacency.neighbours(v);
            if ring.is_empty() {
                return 0.0;
            }
            let mean: DVec3 = ring.iter().map(|&q| view_positions[q as usize]).sum::<DVec3>() / ring.len() as f64;
            view_positions[v].distance_squared(mean)
        })
        .sum()
}
