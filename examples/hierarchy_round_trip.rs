//! Builds the hierarchy of a mesh and refines it back, checking every refined level against
//! the level simplification recorded, and printing what each stage did.
//!
//! `cargo run --release --example hierarchy_round_trip -- [MESH|torus] [TARGET_VERTICES] [none]`
//! (`THR=degrees` sets Algorithm 3's angle threshold).
use std::time::Instant;

use asperity::hierarchy::{KeepFeatures, Refiner, SimplifyOptions, build, connectivity_match};

fn main() -> asperity::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let mesh = match args.get(1).map(String::as_str) {
        Some("torus") | None => asperity::mesh::primitives::torus(1.0, 0.35, 96, 48),
        Some(path) => asperity::io::read(std::path::Path::new(path))?.mesh,
    };
    let target = args.get(2).and_then(|s| s.parse().ok());
    let keep = if args.get(3).is_some_and(|s| s == "none") { KeepFeatures::None } else { KeepFeatures::Strong };
    let t = Instant::now();
    let thr: f64 = std::env::var("THR").ok().and_then(|s| s.parse().ok()).unwrap_or(90.0);
    let h = build(
        &mesh,
        &SimplifyOptions {
            target_vertices: target,
            keep_features: keep,
            fix_threshold_degrees: thr,
            record_levels: true,
            ..Default::default()
        },
    )?;
    println!(
        "simplify: {} => {} vertices, {} steps, {} features kept, in {:.0} ms",
        mesh.vertex_count(),
        h.base_vertex_count(),
        h.steps(),
        h.feature_vertices,
        t.elapsed().as_secs_f64() * 1e3
    );
    for s in 0..h.steps() {
        print!("{} ", h.step(s).len());
    }
    println!();
    let t = Instant::now();
    let mut r = Refiner::new(&h)?;
    let mut reports = Vec::new();
    while !r.is_finished() {
        reports.push(r.refine_level(&|_| true)?);
        let want = &h.levels[h.steps() - r.level()];
        let got = r.triangles()?;
        let want_t: Vec<[u32; 3]> = want.mesh.triangles.iter().map(|t| t.map(|v| want.ids[v as usize])).collect();
        let m = connectivity_match(&want_t, &got);
        if m < 1.0 {
            println!("level {} matches {:.4} {:?}", r.level(), m, reports.last());
        }
    }
    let m = r.mesh()?;
    let misses: usize = reports.iter().map(|r| r.degree_misses).sum();
    let relocated: usize = reports.iter().map(|r| r.relocated).sum();
    let same = m.mesh.positions.len() == mesh.positions.len()
        && m.mesh
            .positions
            .iter()
            .zip(&mesh.positions)
            .all(|(a, b)| a.to_array().map(f64::to_bits) == b.to_array().map(f64::to_bits));
    println!(
        "refine: {} vertices, positions exact {}, faces matched {:.3}%, misses {}, relocated {} in {:.0} ms",
        m.mesh.vertex_count(),
        same,
        100.0 * connectivity_match(&mesh.triangles, &m.mesh.triangles),
        misses,
        relocated,
        t.elapsed().as_secs_f64() * 1e3
    );
    Ok(())
}
