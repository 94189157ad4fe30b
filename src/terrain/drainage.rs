//! Drainage measures of a square heightfield (row-major, `n` per row), for telling what
//! erosion did to a landscape: pit filling (Barnes, Lehman & Mulla 2014) and the drainage
//! density of D8 flow accumulation (O'Callaghan & Mark 1984).

/// `h` with its pits filled so that every point drains to the grid's border: Barnes,
/// Lehman & Mulla 2014's priority flood, each point raised to at least its spill point
/// plus a step of 1e-9 of the height range, so flats drain too.
pub fn pit_filled(h: &[f64], n: usize) -> Vec<f64> {
    use std::cmp::Reverse;
    use std::collections::BinaryHeap;
    #[derive(PartialEq)]
    struct Key(f64);
    impl Eq for Key {}
    impl PartialOrd for Key {
        fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
            Some(self.cmp(other))
        }
    }
    impl Ord for Key {
        fn cmp(&self, other: &Self) -> std::cmp::Ordering {
            self.0.total_cmp(&other.0)
        }
    }
    let (lo, hi) = h.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, u), &v| (l.min(v), u.max(v)));
    let step = (hi - lo) * 1e-9;
    let mut out = h.to_vec();
    let mut done = vec![false; h.len()];
    let mut open = BinaryHeap::new();
    for c in 0..h.len() {
        let (i, j) = (c % n, c / n);
        if i == 0 || j == 0 || i == n - 1 || j == n - 1 {
            done[c] = true;
            open.push(Reverse((Key(out[c]), c)));
        }
    }
    while let Some(Reverse((Key(level), c))) = open.pop() {
        let (i, j) = ((c % n) as i64, (c / n) as i64);
        for (di, dj) in [(-1, -1), (0, -1), (1, -1), (-1, 0), (1, 0), (-1, 1), (0, 1), (1, 1)] {
            let (x, y) = (i + di, j + dj);
            if x < 0 || y < 0 || x >= n as i64 || y >= n as i64 {
                continue;
            }
            let m = y as usize * n + x as usize;
            if !done[m] {
                done[m] = true;
                out[m] = out[m].max(level + step);
                open.push(Reverse((Key(out[m]), m)));
            }
        }
    }
    out
}

/// The share of points whose D8 flow accumulation (O'Callaghan & Mark 1984: each point
/// drains to its steepest lower neighbour of eight, on the pit-filled heights) exceeds
/// 0.1 % of the points.
pub fn drainage_density(h: &[f64], n: usize) -> f64 {
    let h = &pit_filled(h, n);
    let mut order: Vec<usize> = (0..h.len()).collect();
    order.sort_unstable_by(|&a, &b| h[b].total_cmp(&h[a]).then(a.cmp(&b)));
    let mut accumulation = vec![1.0f64; h.len()];
    for &c in &order {
        let (i, j) = ((c % n) as i64, (c / n) as i64);
        let mut best: Option<(f64, usize)> = None;
        for (di, dj) in [(-1, -1), (0, -1), (1, -1), (-1, 0), (1, 0), (-1, 1), (0, 1), (1, 1)] {
            let (x, y) = (i + di, j + dj);
            if x < 0 || y < 0 || x >= n as i64 || y >= n as i64 {
                continue;
            }
            let m = y as usize * n + x as usize;
            let slope = (h[c] - h[m]) / f64::hypot(di as f64, dj as f64);
            if slope > 0.0 && best.is_none_or(|(s, _)| slope > s) {
                best = Some((slope, m));
            }
        }
        if let Some((_, m)) = best {
            accumulation[m] += accumulation[c];
        }
    }
    let threshold = h.len() as f64 * 0.001;
    accumulation.iter().filter(|&&a| a > threshold).count() as f64 / h.len() as f64
}
