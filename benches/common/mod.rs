//! Timing and memory measures shared by the benchmarks (each uses a subset).
#![allow(dead_code)]

use std::time::Instant;

/// The best of eleven runs of `f`, in seconds: this kind of machine is noisy, and the best
/// run is the one least disturbed by other work.
pub fn best_of(mut f: impl FnMut()) -> f64 {
    (0..11)
        .map(|_| {
            let start = Instant::now();
            f();
            start.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min)
}

/// The process's peak resident set size (VmHWM) in KiB, on Linux.
pub fn peak_rss_kib() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// Resets the peak resident set size to the current one (Linux: `5` into clear_refs), so
/// that a later [`peak_rss_kib`] measures one stage; false where the kernel refuses.
pub fn reset_peak_rss() -> bool {
    std::fs::write("/proc/self/clear_refs", "5").is_ok()
}

/// An icosphere with fBm relief along the normals (seed 7, 0.08 of the radius): curved
/// everywhere, no symmetry to exploit, every vertex removable — the hierarchy benchmarks'
/// sphere.
pub fn displaced_sphere(level: u32) -> asperity::Mesh {
    use asperity::noise::{Frame, NoiseField, NoiseKind, NoiseSpec};
    use glam::DVec3;
    let mut mesh = asperity::mesh::primitives::icosphere(1.0, level);
    let field = NoiseField::new(&NoiseSpec { kind: NoiseKind::Fbm, seed: 7, ..NoiseSpec::default() }).expect("fbm");
    let frame = Frame { tangent: DVec3::X, bitangent: DVec3::Y };
    for p in &mut mesh.positions {
        let n = p.normalize();
        *p = n * (1.0 + 0.08 * field.sample3(n * 4.0, frame));
    }
    mesh
}
