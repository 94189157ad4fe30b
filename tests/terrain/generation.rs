//! Classic terrain: determinism, streaming equals in-memory, seamless tiles, the Hurst
//! exponent and per-level variance, thread independence.

use asperity::io::{self, WriteOptions};
use asperity::terrain::stream::{StreamFormat, write_terrain};
use asperity::terrain::{Rect, TerrainParams, heights, mesh, tile_rect, whole};

use crate::common::temp_dir;

fn params(size: u64, hurst: f64, seed: u64) -> TerrainParams {
    TerrainParams { size, hurst, seed, ..TerrainParams::default() }
}

fn full(p: &TerrainParams) -> Rect {
    Rect { x0: 0, y0: 0, x1: p.size - 1, y1: p.size - 1 }
}

fn streamed(p: &TerrainParams, format: StreamFormat, band: usize) -> Vec<u8> {
    let mut bytes = Vec::new();
    write_terrain(p, full(p), format, (-3.0, 3.0), band, &mut bytes).unwrap();
    bytes
}

#[test]
fn same_seed_same_bytes_other_seed_different() {
    let a = streamed(&params(129, 0.7, 1), StreamFormat::F32, 129);
    assert_eq!(a, streamed(&params(129, 0.7, 1), StreamFormat::F32, 129));
    assert_ne!(a, streamed(&params(129, 0.7, 2), StreamFormat::F32, 129));
}

#[test]
fn streaming_writes_the_same_bytes_as_the_whole_grid() {
    let p = TerrainParams { sea_level: Some(-0.2), ..params(129, 0.6, 5) };
    let dir = temp_dir();
    let path = dir.path().join("whole.ply");
    io::write(&mesh(&p, full(&p)).unwrap(), &path, WriteOptions::default()).unwrap();
    let whole_bytes = std::fs::read(&path).unwrap();
    for band in [1, 5, 64, 129] {
        assert_eq!(streamed(&p, StreamFormat::Ply, band), whole_bytes, "ply, band {band}");
    }
    let obj_path = dir.path().join("whole.obj");
    io::write(&mesh(&p, full(&p)).unwrap(), &obj_path, WriteOptions::default()).unwrap();
    assert_eq!(streamed(&p, StreamFormat::Obj, 6), std::fs::read(&obj_path).unwrap(), "obj");
    for format in [StreamFormat::Raw16, StreamFormat::F32, StreamFormat::Png16] {
        assert_eq!(streamed(&p, format, 3), streamed(&p, format, 129), "{format:?}");
    }
}

#[test]
fn tiles_share_borders_and_their_union_is_the_whole_grid() {
    let p = TerrainParams { sea_level: Some(0.0), ..params(129, 0.8, 9) };
    let grid = whole(&p).unwrap();
    let whole_mesh = mesh(&p, full(&p)).unwrap();
    let tile_size = 33;
    for j in 0..4 {
        for i in 0..4 {
            let rect = tile_rect(&p, i, j, tile_size).unwrap();
            let tile = mesh(&p, rect).unwrap();
            let cols = rect.width();
            for (k, position) in tile.positions.iter().enumerate() {
                let (x, y) = (rect.x0 + (k % cols) as u64, rect.y0 + (k / cols) as u64);
                let w = (y * p.size + x) as usize;
                assert_eq!(position.z, grid.at(x, y));
                assert_eq!(*position, whole_mesh.positions[w], "tile {i},{j} point {x},{y}");
                assert_eq!(tile.normals.as_ref().unwrap()[k], whole_mesh.normals.as_ref().unwrap()[w]);
                assert_eq!(tile.colors.as_ref().unwrap()[k], whole_mesh.colors.as_ref().unwrap()[w]);
            }
        }
    }
    assert!(tile_rect(&p, 4, 0, tile_size).is_err());
    assert!(tile_rect(&p, 0, 0, 30).is_err());
}

/// Slope of log D(h) against log h for the variogram D(h) = E[(z(x + h) − z(x))²], both axes.
fn variogram_hurst(p: &TerrainParams) -> f64 {
    let z = whole(p).unwrap();
    let n = p.size;
    // Log-spaced lags (not powers of two) from 3 to 90 points.
    let lags = [3u64, 5, 9, 13, 21, 30, 45, 63, 90];
    let points: Vec<(f64, f64)> = lags
        .iter()
        .map(|&h| {
            let (mut sum, mut count) = (0.0, 0.0);
            for y in (0..n).step_by(2) {
                for x in (0..n - h).step_by(2) {
                    sum += (z.at(x + h, y) - z.at(x, y)).powi(2) + (z.at(y, x + h) - z.at(y, x)).powi(2);
                    count += 2.0;
                }
            }
            ((h as f64).ln(), (sum / count).ln())
        })
        .collect();
    let m = points.len() as f64;
    let (sx, sy) = points.iter().fold((0.0, 0.0), |(a, b), (x, y)| (a + x, b + y));
    let (mx, my) = (sx / m, sy / m);
    let slope = points.iter().map(|(x, y)| (x - mx) * (y - my)).sum::<f64>()
        / points.iter().map(|(x, _)| (x - mx).powi(2)).sum::<f64>();
    slope / 2.0
}

#[test]
fn the_variogram_recovers_the_hurst_exponent() {
    for hurst in [0.3, 0.5, 0.8] {
        // Diamond-square is not exactly fBm: its variogram slope runs a little low at high H
        // (about 0.73 for H = 0.8), hence the average over four terrains.
        let estimates: Vec<f64> = (0..4).map(|seed| variogram_hurst(&params(1025, hurst, 40 + seed))).collect();
        let mean = estimates.iter().sum::<f64>() / estimates.len() as f64;
        eprintln!("H {hurst}: variogram estimates {estimates:?}");
        assert!((mean - hurst).abs() <= 0.1, "H {hurst}: estimated {mean:.3}");
    }
}

#[test]
fn displacement_variance_falls_by_two_to_the_minus_two_h_per_level() {
    let hurst = 0.7;
    let p = params(1025, hurst, 3);
    let z = whole(&p).unwrap();
    // A square centre's displacement is its height minus the mean of its four corners
    // (classic points never move once created).
    let variance = |d: u64| {
        let (mut sum, mut count) = (0.0, 0.0);
        let mut y = d;
        while y + d < p.size {
            let mut x = d;
            while x + d < p.size {
                let mean = (z.at(x - d, y - d) + z.at(x + d, y - d) + z.at(x - d, y + d) + z.at(x + d, y + d)) / 4.0;
                sum += (z.at(x, y) - mean).powi(2);
                count += 1.0;
                x += 2 * d;
            }
            y += 2 * d;
        }
        sum / count
    };
    let expected = (-2.0 * hurst).exp2();
    for d in [2u64, 4, 8, 16] {
        let ratio = variance(d / 2) / variance(d);
        assert!((ratio / expected - 1.0).abs() < 0.1, "spacing {d}: ratio {ratio:.4}, expected {expected:.4}");
    }
}

#[test]
fn heights_are_identical_at_one_and_two_threads() {
    let p = params(257, 0.8, 4);
    let run =
        |threads| rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap().install(|| whole(&p).unwrap());
    assert_eq!(run(1), run(2));
    let region = Rect { x0: 17, y0: 100, x1: 200, y1: 131 };
    let part = heights(&p, region).unwrap();
    let all = run(2);
    for y in region.y0..=region.y1 {
        for x in region.x0..=region.x1 {
            assert_eq!(part.at(x, y), all.at(x, y));
        }
    }
}

#[test]
fn sea_level_flattens_and_colours_the_sea() {
    let p = TerrainParams { sea_level: Some(0.1), ..params(65, 0.5, 6) };
    let m = mesh(&p, full(&p)).unwrap();
    let colors = m.colors.as_ref().unwrap();
    let normals = m.normals.as_ref().unwrap();
    let n = p.size as usize;
    let (mut sea, mut open_sea) = (0, 0);
    for (k, position) in m.positions.iter().enumerate() {
        assert!(position.z >= 0.1);
        if position.z == 0.1 {
            sea += 1;
            assert_eq!(colors[k], p.color(0.1));
            let (x, y) = (k % n, k / n);
            let inner = x > 0 && y > 0 && x + 1 < n && y + 1 < n;
            if inner && [k - 1, k + 1, k - n, k + n].iter().all(|&w| m.positions[w].z == 0.1) {
                open_sea += 1;
                assert_eq!(normals[k], glam::DVec3::Z, "flat sea faces up");
            }
        }
    }
    assert!(sea > 0 && open_sea > 0, "some of the terrain lies under the sea");
}

#[test]
fn invalid_sizes_and_parameters_are_errors() {
    for size in [0, 1, 2, 100, 258] {
        assert!(params(size, 0.5, 0).generator().is_err(), "size {size}");
    }
    assert!(TerrainParams { hurst: f64::NAN, ..TerrainParams::default() }.generator().is_err());
    assert!(TerrainParams { width: 0.0, ..TerrainParams::default() }.generator().is_err());
}

#[test]
fn the_smooth_method_stays_in_range_smooths_and_tiles() {
    use asperity::terrain::Method;
    let p = TerrainParams { method: Method::Smooth, sea_level: None, ..params(129, 0.5, 12) };
    let smooth = whole(&p).unwrap();
    let raw = p.generator().unwrap().heights(full(&p));
    // Uniform draws within the parents' range never leave the corners' range, and a
    // weighted average cannot either.
    let corners = [raw[0], raw[128], raw[128 * 129], raw[129 * 129 - 1]];
    let (lo, hi) = corners.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &c| (a.min(c), b.max(c)));
    assert!(raw.iter().chain(&smooth.heights).all(|&h| h >= lo - 1e-12 && h <= hi + 1e-12));
    // Two Gaussian passes lower the roughness.
    let roughness = |z: &[f64]| z.windows(2).map(|w| (w[1] - w[0]).abs()).sum::<f64>();
    assert!(
        roughness(&smooth.heights) < 0.7 * roughness(&raw),
        "{} vs {}",
        roughness(&smooth.heights),
        roughness(&raw)
    );
    // Tiles and streams still agree with the whole grid.
    let rect = tile_rect(&p, 1, 2, 33).unwrap();
    let tile = heights(&p, rect).unwrap();
    for y in rect.y0..=rect.y1 {
        for x in rect.x0..=rect.x1 {
            assert_eq!(tile.at(x, y), smooth.at(x, y));
        }
    }
    assert_eq!(streamed(&p, StreamFormat::Ply, 7), streamed(&p, StreamFormat::Ply, 129));
}

mod dual {
    use asperity::terrain::{DualParams, QuadSurface, dual_midpoint_displacement};
    use glam::DVec3;

    fn surface(params: &DualParams) -> QuadSurface {
        dual_midpoint_displacement(params, |_, _| {}).unwrap()
    }

    /// Mean |second difference along the diagonals| of the height along the quad normal —
    /// |h − mean of the four diagonal neighbours|, a stencil the correction does not use —
    /// at the last division's originals (even, even) and at the quad centres (odd, odd).
    fn diagonal_peaks_at_originals_and_centres(s: &QuadSurface, z: DVec3) -> (f64, f64) {
        let h = |i: usize, j: usize| s.points[i * s.n + j].dot(z);
        let (mut originals, mut centres, mut n_orig, mut n_centre) = (0.0, 0.0, 0.0, 0.0);
        for i in 1..s.m - 1 {
            for j in 1..s.n - 1 {
                let peak =
                    (h(i, j) - (h(i - 1, j - 1) + h(i + 1, j - 1) + h(i - 1, j + 1) + h(i + 1, j + 1)) / 4.0).abs();
                match (i % 2, j % 2) {
                    (0, 0) => (originals, n_orig) = (originals + peak, n_orig + 1.0),
                    (1, 1) => (centres, n_centre) = (centres + peak, n_centre + 1.0),
                    _ => {}
                }
            }
        }
        (originals / n_orig, centres / n_centre)
    }

    #[test]
    fn the_surface_keeps_its_corners_and_is_deterministic() {
        let params = DualParams {
            x: DVec3::new(2.0, 0.0, 0.5),
            y: DVec3::new(0.3, 1.5, 0.0),
            levels: 6,
            seed: 4,
            ..DualParams::default()
        };
        let s = surface(&params);
        assert_eq!((s.m, s.n), (65, 65));
        assert_eq!(s.points[0], DVec3::ZERO);
        assert_eq!(s.points[64], params.y);
        assert_eq!(s.points[64 * 65], params.x);
        assert_eq!(s.points[65 * 65 - 1], params.x + params.y);
        assert_eq!(s, surface(&params));
        assert_ne!(s, surface(&DualParams { seed: 5, ..params }));
        assert_ne!(s, surface(&DualParams { cross_product: true, ..params }));
        let mut levels = Vec::new();
        dual_midpoint_displacement(&params, |level, step| levels.push((level, step.m))).unwrap();
        assert_eq!(levels, vec![(0, 2), (1, 3), (2, 5), (3, 9), (4, 17), (5, 33), (6, 65)]);
        let mesh = s.to_mesh();
        assert!(mesh.validate().is_manifold());
        assert!(dual_midpoint_displacement(&DualParams { y: params.x * 2.0, ..params }, |_, _| {}).is_err());
    }

    #[test]
    fn the_non_random_mode_needs_no_seed() {
        let params = DualParams { levels: 5, deterministic: true, ..DualParams::default() };
        assert_eq!(surface(&DualParams { seed: 1, ..params }), surface(&DualParams { seed: 2, ..params }));
    }

    #[test]
    fn mean_correction_removes_the_peaks_and_pits_at_original_points() {
        let params = DualParams { levels: 7, seed: 9, hurst: 1.5, ..DualParams::default() };
        let (with_orig, with_centres) = diagonal_peaks_at_originals_and_centres(&surface(&params), DVec3::Z);
        let (without_orig, without_centres) = diagonal_peaks_at_originals_and_centres(
            &surface(&DualParams { mean_correction: false, ..params }),
            DVec3::Z,
        );
        let (corrected, uncorrected) = (with_orig / with_centres, without_orig / without_centres);
        eprintln!("diagonal peaks originals/centres: corrected {corrected:.3}, uncorrected {uncorrected:.3}");
        assert!(uncorrected > 1.5, "uncorrected originals stand out as peaks and pits: {uncorrected:.3}");
        assert!(corrected < 0.5 * uncorrected && corrected < 1.2, "corrected originals should not: {corrected:.3}");
    }
}

#[test]
fn clouds_cover_less_sky_as_the_threshold_rises() {
    use asperity::terrain::{CloudParams, clouds};
    let base = CloudParams {
        plasma: TerrainParams { size: 129, seed: 3, ..TerrainParams::default() },
        ..CloudParams::default()
    };
    let covers: Vec<f64> = [0.0, 0.3, 0.5, 0.7, 1.0]
        .iter()
        .map(|&threshold| clouds(&CloudParams { threshold, ..base }).unwrap().1)
        .collect();
    assert!(covers.windows(2).all(|w| w[0] >= w[1]), "{covers:?}");
    assert!(covers[0] > 0.99 && covers[4] == 0.0, "{covers:?}");
    let (sky_only, _) = clouds(&CloudParams { threshold: 1.0, ..base }).unwrap();
    assert!(sky_only.chunks(3).all(|c| c == base.sky));
    assert_eq!(clouds(&base).unwrap(), clouds(&base).unwrap());
    assert!(clouds(&CloudParams { threshold: 1.5, ..base }).is_err());
}

#[test]
fn triangle_and_hex_grids_are_lattices_that_tile_and_stream() {
    use asperity::terrain::Grid;
    let tri = TerrainParams { grid: Grid::Triangle, sea_level: Some(0.0), ..params(129, 0.7, 8) };
    let m = mesh(&tri, full(&tri)).unwrap();
    let report = m.validate();
    assert!(report.is_manifold() && report.genus == Some(0) && report.boundary_loops == 1);
    assert_eq!(report.inconsistently_oriented_edges, 0);
    // Every triangle is equilateral in the plane and faces up.
    for f in 0..m.face_count() {
        let [a, b, c] = m.triangle_points(f).map(|p| glam::DVec2::new(p.x, p.y));
        let (ab, bc, ca) = ((b - a).length(), (c - b).length(), (a - c).length());
        assert!((ab - bc).abs() < 1e-9 && (bc - ca).abs() < 1e-9);
        assert!((b - a).perp_dot(c - a) > 0.0);
    }
    assert_eq!(streamed(&tri, StreamFormat::Ply, 7), streamed(&tri, StreamFormat::Ply, 129));
    let rect = tile_rect(&tri, 2, 1, 33).unwrap();
    let tile = mesh(&tri, rect).unwrap();
    for (k, p) in tile.positions.iter().enumerate() {
        let (x, y) = (rect.x0 + (k % 33) as u64, rect.y0 + (k / 33) as u64);
        let w = (y * tri.size + x) as usize;
        assert_eq!(*p, m.positions[w]);
        assert_eq!(tile.normals.as_ref().unwrap()[k], m.normals.as_ref().unwrap()[w]);
    }
    // Edge midpoints: displacement variance falls by 2^(−2H) per level.
    let z = whole(&tri).unwrap();
    let raw = TerrainParams { sea_level: None, ..tri };
    let z_raw = whole(&raw).unwrap();
    let variance = |d: u64| {
        let (mut sum, mut count) = (0.0, 0.0);
        for y in (0..tri.size).step_by(2 * d as usize) {
            for x in (d..tri.size - d).step_by(2 * d as usize) {
                sum += (z_raw.at(x, y) - (z_raw.at(x - d, y) + z_raw.at(x + d, y)) / 2.0).powi(2);
                count += 1.0;
            }
        }
        sum / count
    };
    let expected = (-2.0 * tri.hurst).exp2();
    for d in [2u64, 4] {
        let ratio = variance(d / 2) / variance(d);
        assert!((ratio / expected - 1.0).abs() < 0.15, "spacing {d}: ratio {ratio:.3}, expected {expected:.3}");
    }
    assert!(z.heights.iter().all(|&h| h >= 0.0));

    let hex = TerrainParams { grid: Grid::Hex, ..tri };
    let h = mesh(&hex, full(&hex)).unwrap();
    let side = 64usize;
    assert_eq!(h.vertex_count(), 3 * side * side + 3 * side + 1, "a centred hexagonal number of vertices");
    assert_eq!(h.face_count(), 6 * side * side);
    let report = h.validate();
    assert!(report.is_manifold() && report.boundary_loops == 1 && report.unreferenced_vertices == 0);
    let mut sink = Vec::new();
    assert!(write_terrain(&hex, full(&hex), StreamFormat::Ply, (-1.0, 1.0), 8, &mut sink).is_err());
}

#[test]
fn the_colour_ramp_is_configurable() {
    use asperity::terrain::Palette;
    let palette =
        Palette { sea: [0, 0, 255], low: [0, 255, 0], mid: [255, 255, 0], high: [255, 0, 0], peak: [255, 255, 255] };
    let p = TerrainParams { sea_level: Some(0.0), palette, peak_height: Some(2.0), ..params(65, 0.5, 1) };
    assert_eq!(p.color(-1.0), palette.sea);
    assert_eq!(p.color(0.0), palette.sea);
    assert_eq!(p.color(1e-9), palette.low);
    assert_eq!(p.color(0.7 * 2.0), palette.high);
    assert_eq!(p.color(2.0), palette.peak);
    assert_eq!(p.color(50.0), palette.peak);
}

#[test]
fn every_distribution_has_the_requested_mean_and_variance() {
    use asperity::terrain::{Displacements, Distribution};
    for distribution in [Distribution::Normal, Distribution::Uniform, Distribution::Exponential, Distribution::Laplace]
    {
        let d = Displacements::new(5, distribution, 0.3, 2.0);
        let values: Vec<f64> = (0..200_000u64).map(|k| d.sample(3, k % 1000, k / 1000)).collect();
        let mean = values.iter().sum::<f64>() / values.len() as f64;
        let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / values.len() as f64;
        assert!(
            (mean - 0.3).abs() < 0.02 && (var / 2.0 - 1.0).abs() < 0.03,
            "{distribution:?}: mean {mean}, variance {var}"
        );
    }
}

#[test]
fn corners_set_the_grid_corner_heights_exactly() {
    // #24 item 12: seed 001's applet sets the corners; they are not added to a random draw.
    let p = TerrainParams { corners: Some([5.0, 5.0, -5.0, -5.0]), ..params(65, 0.8, 3) };
    let h = asperity::terrain::heights(&p, asperity::terrain::Rect { x0: 0, y0: 0, x1: 64, y1: 64 }).unwrap();
    assert_eq!([h.at(0, 0), h.at(64, 0), h.at(0, 64), h.at(64, 64)], [5.0, 5.0, -5.0, -5.0]);
    let drawn = asperity::terrain::heights(&params(65, 0.8, 3), asperity::terrain::Rect { x0: 0, y0: 0, x1: 0, y1: 0 })
        .unwrap();
    assert_ne!(drawn.at(0, 0), 0.0, "without --corners each corner is a random draw");
}
