//! `asperity demo [--out DIR]`: the main job on built-in inputs. It builds a torus and an
//! icosphere in code, round-trips them through OpenMesh, measures them with CGAL, writes a
//! panel of noise images, a terrain, and the feature analysis of fandisk (or of the torus
//! when the shared meshes are absent), the 4-k hierarchies, and the results of several
//! detail recipes under `DIR`.

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;

use crate::analysis::{AnalysisOptions, analyze};
use crate::detail::{self, DetailOptions, Recipe};
use crate::error::{Error, Result};
use crate::ffi::{self, HalfEdgeMesh, HausdorffOptions};
use crate::hierarchy::{Refiner, SimplifyOptions, build, connectivity_match};
use crate::io::image::{value_range, write_png16};
use crate::io::{self, WriteOptions};
use crate::mesh::{Mesh, primitives};
use crate::noise::{NoiseField, NoiseKind, NoiseSpec};

#[derive(Debug, Args)]
pub struct DemoArgs {
    /// Output folder.
    #[arg(long, default_value_os_t = super::default_out())]
    out: PathBuf,
}

pub fn run(args: DemoArgs) -> Result<()> {
    std::fs::create_dir_all(&args.out).map_err(|e| Error::io(&args.out, e))?;
    let torus = primitives::torus(1.0, 0.35, 96, 48);
    let sphere = primitives::icosphere(1.0, 4);

    for (name, mesh) in [("torus", &torus), ("icosphere", &sphere)] {
        openmesh_round_trip(name, mesh)?;
    }

    let start = Instant::now();
    let coarse = primitives::icosphere(1.0, 2);
    let d = ffi::hausdorff_distance(&sphere, &coarse, HausdorffOptions::default())?;
    println!(
        "cgal: hausdorff(icosphere {} tris, icosphere {} tris) = {d:.5} ({:.2}% of the diameter) in {} ms",
        sphere.face_count(),
        coarse.face_count(),
        100.0 * d / 2.0,
        super::millis(start)
    );

    let start = Instant::now();
    let pairs = ffi::self_intersections(&torus)?;
    println!("cgal: torus self-intersections: {} face pairs in {} ms", pairs.len(), super::millis(start));

    let start = Instant::now();
    let quadrics = ffi::vertex_quadrics(&torus, 100.0)?;
    let lifted: Vec<_> = torus.positions.iter().map(|p| *p * 1.01).collect();
    let errors = ffi::quadric_errors(&quadrics, &lifted)?;
    let mean = errors.iter().sum::<f64>() / errors.len() as f64;
    println!(
        "cgal: garland-heckbert quadrics of {} vertices, mean error after 1% scaling {mean:.3e} in {} ms",
        quadrics.len(),
        super::millis(start)
    );

    write_result(&torus, &args.out.join("torus.ply"))?;
    write_result(&sphere, &args.out.join("icosphere.obj"))?;
    write_result(&coarse, &args.out.join("icosphere-coarse.off"))?;

    write_hierarchy("torus", &torus, &args.out)?;
    write_noise_panel(&args.out)?;
    write_terrain(&args.out)?;

    if let Some(fandisk) = shared_mesh("fandisk.off") {
        let start = Instant::now();
        let outcome = io::read(&fandisk)?;
        let report = outcome.mesh.validate();
        println!(
            "read: {} ({} vertices, {} tris, genus {}) in {} ms",
            fandisk.display(),
            report.vertices,
            report.faces,
            report.genus.map_or("n/a".into(), |g| g.to_string()),
            super::millis(start)
        );
        openmesh_round_trip("fandisk", &outcome.mesh)?;
        write_features(&outcome.mesh, &args.out.join("fandisk-features.ply"))?;
        write_hierarchy("fandisk", &outcome.mesh, &args.out)?;
    } else {
        write_features(&torus, &args.out.join("torus-features.ply"))?;
    }
    write_detail_recipes(&args.out)?;
    println!("demo: results in {}", args.out.display());
    Ok(())
}

/// The 4-k hierarchy of `mesh` to 5 % of its vertices: the base domain and the level
/// halfway, then the round trip back to the input.
fn write_hierarchy(name: &str, mesh: &Mesh, out: &Path) -> Result<()> {
    let start = Instant::now();
    let target = (mesh.vertex_count() / 20).max(4);
    let options = SimplifyOptions { target_vertices: Some(target), record_levels: true, ..SimplifyOptions::default() };
    let h = build(mesh, &options)?;
    let base = h.base_mesh().mesh;
    let hausdorff = super::simplify::relative_hausdorff(mesh, &base)?;
    println!(
        "simplify: {name} {} tris => {} tris, {} levels (hausdorff {:.2}%) in {} ms",
        mesh.face_count(),
        base.face_count(),
        h.steps(),
        100.0 * hausdorff,
        super::millis(start)
    );
    write_result(&base, &out.join(format!("{name}-base.ply")))?;
    if let Some(middle) = h.levels.get(h.steps() / 2) {
        write_result(&middle.mesh, &out.join(format!("{name}-level-{}.ply", h.steps() - h.steps() / 2)))?;
    }
    let start = Instant::now();
    let mut refiner = Refiner::new(&h)?;
    refiner.refine_all()?;
    let back = refiner.mesh()?;
    let exact = back.has_input_positions(mesh);
    println!(
        "refine: {name} {} tris => {} tris, positions {}, {:.2}% faces restored in {} ms",
        base.face_count(),
        back.mesh.face_count(),
        if exact { "exact" } else { "moved" },
        100.0 * connectivity_match(&mesh.triangles, &back.triangles_in_ids()),
        super::millis(start)
    );
    Ok(())
}

fn openmesh_round_trip(name: &str, mesh: &Mesh) -> Result<()> {
    let start = Instant::now();
    let he = HalfEdgeMesh::from_mesh(mesh)?;
    let counts = he.counts()?;
    let back = he.export()?.mesh;
    if back.positions != mesh.positions || back.triangles != mesh.triangles {
        return Err(Error::Internal(format!("{name}: the OpenMesh round trip changed the mesh")));
    }
    println!(
        "openmesh: {name} {} vertices, {} edges, {} tris round trip exact in {} ms",
        counts.vertices,
        counts.edges,
        counts.faces,
        super::millis(start)
    );
    Ok(())
}

/// A 257² classic terrain with a sea, as a coloured mesh and a 16-bit heightmap.
fn write_terrain(out: &Path) -> Result<()> {
    use crate::terrain::stream::{StreamFormat, write_terrain};
    use crate::terrain::{Rect, TerrainParams, mesh, whole};
    let start = Instant::now();
    let params = TerrainParams { size: 257, hurst: 0.6, seed: 2, sea_level: Some(-0.8), ..TerrainParams::default() };
    let rect = Rect { x0: 0, y0: 0, x1: 256, y1: 256 };
    io::write(&mesh(&params, rect)?, &out.join("terrain.ply"), WriteOptions::default())?;
    // A preview uses the terrain's own range (tiles and streams use a fixed one instead).
    let range = value_range(&whole(&params)?.heights).ok_or_else(|| Error::Internal("empty terrain".into()))?;
    let path = out.join("terrain-height.png");
    crate::io::write_atomically(&path, |w| {
        write_terrain(&params, rect, StreamFormat::Png16, range, 257, w).map_err(std::io::Error::other)
    })?;
    println!(
        "terrain: classic 257x257 (H 0.6, sea -0.8) => {}/terrain.ply, terrain-height.png in {} ms",
        out.display(),
        super::millis(start)
    );
    write_clouds(out)
}

/// Seed 001's clouds: a 257² plasma, thresholded and coloured.
fn write_clouds(out: &Path) -> Result<()> {
    use crate::terrain::{CloudParams, TerrainParams, clouds};
    let start = Instant::now();
    let params = CloudParams {
        plasma: TerrainParams { size: 257, hurst: 0.7, seed: 4, ..TerrainParams::default() },
        ..Default::default()
    };
    let (rgb, cover) = clouds(&params)?;
    crate::io::image::write_png_rgb8(&out.join("clouds.png"), &rgb, 257)?;
    println!(
        "clouds: 257x257 => {:.0}% cover => {}/clouds.png in {} ms",
        cover * 100.0,
        out.display(),
        super::millis(start)
    );
    Ok(())
}

/// One 256×256 image per noise kind, seed 7.
fn write_noise_panel(out: &Path) -> Result<()> {
    let start = Instant::now();
    let kinds = [
        ("perlin", NoiseKind::Perlin, 1.0 / 32.0),
        ("fbm", NoiseKind::Fbm, 1.0 / 32.0),
        ("turbulence", NoiseKind::Turbulence, 1.0 / 32.0),
        ("marble", NoiseKind::Marble, 1.0 / 32.0),
        ("multifractal", NoiseKind::Multifractal, 1.0 / 32.0),
        ("wood", NoiseKind::Wood, 1.0 / 64.0),
        ("gabor", NoiseKind::Gabor, 1.0),
    ];
    for (name, kind, scale) in kinds {
        let field = NoiseField::new(&NoiseSpec { kind, seed: 7, ..NoiseSpec::default() })?;
        let values = field.grid2(0.0, 0.0, scale, 256, 256);
        let range = value_range(&values).ok_or_else(|| Error::Internal(format!("{name} noise has no finite value")))?;
        write_png16(&out.join(format!("noise-{name}.png")), &values, 256, range)?;
    }
    println!("noise: {} images 256x256 => {}/noise-*.png in {} ms", kinds.len(), out.display(), super::millis(start));
    Ok(())
}

/// Curvatures and feature classes, written as PLY properties and class colours.
fn write_features(mesh: &Mesh, path: &Path) -> Result<()> {
    let start = Instant::now();
    let analysis = analyze(mesh, &AnalysisOptions::default())?;
    let [face, weak, strong, corner] = analysis.class_counts();
    let mut coloured = mesh.clone();
    analysis.attach_to(&mut coloured);
    io::write(&coloured, path, WriteOptions::default())?;
    println!(
        "analyze: {} vertices => {corner} corners, {strong} strong edge, {weak} weak, {face} face => {} in {} ms",
        mesh.vertex_count(),
        path.display(),
        super::millis(start)
    );
    Ok(())
}

/// Example recipes the demo runs (the files of `recipes/`, built in).
const DEMO_RECIPES: [(&str, &str); 4] = [
    ("torus-variation", include_str!("../../recipes/torus-variation.toml")),
    ("sphere-marble", include_str!("../../recipes/sphere-marble.toml")),
    ("mushroom-planet", include_str!("../../recipes/mushroom-planet.toml")),
    ("femur-wearing", include_str!("../../recipes/femur-wearing.toml")),
];

/// Runs the demo recipes on the meshes their first line names (skipping shared meshes
/// that are absent), writing `detail-NAME.ply` with self-intersections damped away.
fn write_detail_recipes(out: &Path) -> Result<()> {
    for (name, text) in DEMO_RECIPES {
        let recipe = Recipe::parse(text)
            .map_err(|(line, msg)| Error::Internal(format!("built-in recipe {name} (line {line:?}): {msg}")))?;
        let mesh_name = text.lines().next().and_then(|l| l.strip_prefix("# mesh: ")).unwrap_or("sphere").trim();
        let mesh = match super::detail::builtin_mesh(Path::new(&format!("builtin:{mesh_name}"))) {
            Ok(Some(mesh)) => mesh,
            _ => match shared_mesh(mesh_name) {
                Some(path) => io::read(&path)?.mesh,
                None => continue,
            },
        };
        let start = Instant::now();
        let target = recipe
            .hierarchy
            .target_vertices
            .as_deref()
            .map(|t| super::resolve_target(t, mesh.vertex_count()))
            .transpose()?;
        let simplify = SimplifyOptions { target_vertices: target, ..SimplifyOptions::default() };
        let options = DetailOptions { simplify, no_self_intersections: true, ..DetailOptions::default() };
        let outcome = detail::apply(&mesh, &recipe, &options)?;
        let path = out.join(format!("detail-{name}.ply"));
        io::write(&outcome.result.mesh, &path, WriteOptions::default())?;
        let touched: usize = outcome.steps.iter().map(|s| s.touched).sum();
        println!(
            "detail: {name} on {mesh_name}: {} steps over {} levels, {touched} vertex moves, {} self-intersections damped ({} vertices) => {} in {} ms",
            outcome.steps.len(),
            outcome.levels,
            outcome.intersections.found,
            outcome.intersections.damped,
            path.display(),
            super::millis(start)
        );
    }
    Ok(())
}

fn write_result(mesh: &Mesh, path: &Path) -> Result<()> {
    io::write(mesh, path, WriteOptions::default())?;
    println!("write: {} ({} tris)", path.display(), mesh.face_count());
    Ok(())
}

/// A mesh of `../shared/data/meshes` (next to the working directory or the executable's
/// checkout), when present.
fn shared_mesh(name: &str) -> Option<PathBuf> {
    let candidates = [
        PathBuf::from("../shared/data/meshes"),
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/data/meshes"),
    ];
    candidates.iter().map(|dir| dir.join(name)).find(|p| p.is_file())
}
