//! The Morton (Z-order) curve of a mesh's face centroids (Morton 1966), cut into runs of
//! equal length (Pilkington & Baden 1996) without sorting every face: a histogram of the
//! keys' leading bits finds the cells the cuts fall in, and only those cells' faces are
//! sorted. The runs are exactly those of a sort of every face by (key, face), in a few
//! bytes per face where the sort took sixteen.

use glam::DVec3;
use rayon::prelude::*;

use crate::mesh::UnitFrame;

/// Leading key bits a histogram cell has: seven levels of the octree, 2M cells.
const CELL_BITS: u32 = 21;
/// Bits of a key below its cell's.
const BELOW_CELL: u32 = 3 * 21 - CELL_BITS;

/// The part of each face of `mesh` when the faces, sorted by the Morton key of their
/// centroids in `unit` (then by face), are cut into `parts` runs: the face of rank i is in
/// part ⌊i·parts/faces⌋. `triangles` (over `positions`) are 1 to `u32::MAX` faces and at
/// least `parts`.
pub(in crate::hierarchy) fn morton_owners(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    unit: &UnitFrame,
    parts: usize,
) -> Vec<u32> {
    let faces = triangles.len();
    let key = |f: usize| face_key(positions, triangles[f], unit);
    let cell = |key: u64| (key >> BELOW_CELL) as usize;
    // The histogram, one per thread (at most four: 8 MB each) over a span of faces each,
    // summed.
    let threads = rayon::current_num_threads().clamp(1, 4);
    let span = faces.div_ceil(threads).max(1);
    let counts = (0..threads)
        .into_par_iter()
        .map(|i| {
            let mut counts = vec![0u32; 1 << CELL_BITS];
            (i * span..((i + 1) * span).min(faces)).for_each(|f| counts[cell(key(f))] += 1);
            counts
        })
        .reduce_with(|mut a, b| {
            a.iter_mut().zip(b).for_each(|(a, b)| *a += b);
            a
        })
        .expect("a thread");
    // The first rank of each part after the first, and the cell it falls in.
    let first_rank = |k: usize| ((k as u64 * faces as u64).div_ceil(parts as u64)) as usize;
    let mut cuts: Vec<(usize, usize)> = Vec::with_capacity(parts.saturating_sub(1));
    let mut before = 0;
    for (c, &n) in counts.iter().enumerate() {
        while cuts.len() + 1 < parts && first_rank(cuts.len() + 1) < before + n as usize {
            cuts.push((c, first_rank(cuts.len() + 1) - before));
        }
        before += n as usize;
    }
    drop(counts);
    let mut cut_cell = vec![false; 1 << CELL_BITS];
    cuts.iter().for_each(|&(c, _)| cut_cell[c] = true);
    let mut gathered: Vec<(u64, u32)> = (0..faces)
        .into_par_iter()
        .filter_map(|f| {
            let k = key(f);
            cut_cell[cell(k)].then_some((k, f as u32))
        })
        .collect();
    gathered.par_sort_unstable();
    let thresholds: Vec<(u64, u32)> =
        cuts.iter().map(|&(c, offset)| gathered[gathered.partition_point(|&(k, _)| cell(k) < c) + offset]).collect();
    drop(gathered);
    (0..faces).into_par_iter().map(|f| thresholds.partition_point(|&t| t <= (key(f), f as u32)) as u32).collect()
}

/// The Morton key of `face`'s centroid in `unit`.
fn face_key(positions: &[DVec3], face: [u32; 3], unit: &UnitFrame) -> u64 {
    let centroid = face.iter().map(|&v| unit.to_unit(positions[v as usize])).sum::<DVec3>() / 3.0;
    morton_key(centroid + DVec3::splat(0.5))
}

/// The Morton key of a point of the unit cube: its coordinates' 21 bits interleaved.
fn morton_key(p: DVec3) -> u64 {
    let bits = |c: f64| spread((c.clamp(0.0, 1.0) * f64::from((1u32 << 21) - 1)) as u64);
    bits(p.x) | bits(p.y) << 1 | bits(p.z) << 2
}

/// The low 21 bits of `x`, two zero bits after each.
fn spread(x: u64) -> u64 {
    let mut x = x & 0x1f_ffff;
    x = (x | x << 32) & 0x001f_0000_0000_ffff;
    x = (x | x << 16) & 0x001f_0000_ff00_00ff;
    x = (x | x << 8) & 0x100f_00f0_0f00_f00f;
    x = (x | x << 4) & 0x10c3_0c30_c30c_30c3;
    (x | x << 2) & 0x1249_2492_4924_9249
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Mesh;

    #[test]
    fn morton_keys_interleave_the_coordinates_bits() {
        assert_eq!(spread(0b1011), 0b001_000_001_001);
        let top = f64::from((1u32 << 21) - 1);
        let key = |x: f64, y: f64, z: f64| morton_key(DVec3::new(x, y, z) / top);
        assert_eq!(key(1.0, 0.0, 0.0), 0b001);
        assert_eq!(key(0.0, 1.0, 0.0), 0b010);
        assert_eq!(key(0.0, 0.0, 1.0), 0b100);
        assert_eq!(key(3.0, 0.0, 1.0), 0b001_101);
    }

    /// The owners of a sort of every face by (key, face), cut at ⌊i·parts/faces⌋.
    fn sorted_owners(mesh: &Mesh, unit: &UnitFrame, parts: usize) -> Vec<u32> {
        let mut keys: Vec<(u64, u32)> =
            mesh.triangles.iter().enumerate().map(|(f, &t)| (face_key(&mesh.positions, t, unit), f as u32)).collect();
        keys.sort_unstable();
        let mut owner = vec![0u32; keys.len()];
        keys.iter().enumerate().for_each(|(i, &(_, f))| owner[f as usize] = (i * parts / keys.len()) as u32);
        owner
    }

    #[test]
    fn the_histogram_cut_gives_the_runs_of_a_full_sort() {
        // Faces crowded into one cell (equal keys, ties by face), spread ones, and a lone
        // far vertex that makes the crowd's cell small: the cuts fall inside crowded cells.
        let mut positions = vec![DVec3::new(1000.0, 1000.0, 1000.0)];
        let mut triangles = Vec::new();
        let mut state = 12345u64;
        let mut next = || {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        for i in 0..3000u32 {
            let scale = if i % 3 == 0 { 1000.0 } else { 1e-3 };
            for _ in 0..3 {
                positions.push(DVec3::new(next(), next(), next()) * scale);
            }
            triangles.push([3 * i + 1, 3 * i + 2, 3 * i + 3]);
            if i % 5 == 0 {
                triangles.push([3 * i + 1, 3 * i + 2, 3 * i + 3]);
            }
        }
        let mesh = Mesh::new(positions, triangles);
        let unit = UnitFrame::of(&mesh).unwrap();
        for parts in [1, 2, 3, 7, 16, 100, mesh.face_count()] {
            assert_eq!(
                morton_owners(&mesh.positions, &mesh.triangles, &unit, parts),
                sorted_owners(&mesh, &unit, parts),
                "{parts} parts"
            );
        }
    }
}
