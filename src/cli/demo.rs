//! `asperity demo [--out DIR]`: the main job on built-in inputs. It builds a torus and an
//! icosphere in code, round-trips them through OpenMesh, measures them with CGAL, and
//! writes under `DIR`, each with a picture: a noise panel, terrains of every method
//! (hillshaded maps, renderings, seed 001's three views), clouds, the feature analysis of
//! fandisk (of the torus when the shared meshes are absent), 4-k hierarchy levels, and the
//! results of several detail recipes next to their inputs.

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;
use serde_json::json;

use super::Context;
use crate::analysis::{AnalysisOptions, analyze};
use crate::detail::{self, DetailOptions, Recipe};
use crate::error::{Error, Result};
use crate::ffi::{self, HalfEdgeMesh, HausdorffOptions};
use crate::hierarchy::{HierarchyRequest, Refiner, SimplifyOptions, build, connectivity_match};
use crate::io::image::{value_range, write_png16};
use crate::io::{self, WriteOptions};
use crate::mesh::{Mesh, primitives};
use crate::noise::{Fractal, NoiseField, NoiseKind, NoiseSpec};
use crate::render::{ColorSource, Mode, Picture, RenderOptions, UpAxis, render};
use crate::request::Spelling;

#[derive(Debug, Args)]
pub struct DemoArgs {
    /// Output folder.
    #[arg(long, default_value_os_t = super::default_out())]
    out: PathBuf,
}

/// The demo's output folder, report settings and the files written so far.
struct Demo {
    out: PathBuf,
    ctx: Context,
    written: Vec<PathBuf>,
}

/// Panels of several views use this size per view.
const PANEL: (usize, usize) = (400, 300);
/// Single views use this size.
const VIEW: (usize, usize) = (640, 448);
/// Background between panels.
const WHITE: [u8; 3] = [255, 255, 255];

pub fn run(args: DemoArgs, ctx: Context) -> Result<()> {
    let start = Instant::now();
    crate::io::create_output_dir(&args.out)?;
    let mut demo = Demo { out: args.out, ctx, written: Vec::new() };
    let torus = primitives::torus(1.0, 0.35, 96, 48);
    let sphere = primitives::icosphere(1.0, 4);
    for (name, mesh) in [("torus", &torus), ("icosphere", &sphere)] {
        demo.openmesh_round_trip(name, mesh)?;
    }
    demo.cgal_measures(&torus, &sphere)?;
    demo.mesh(&torus, "torus.ply")?;
    demo.mesh(&sphere, "icosphere.obj")?;
    demo.mesh(&primitives::icosphere(1.0, 2), "icosphere-coarse.off")?;

    demo.hierarchy("torus", &torus, UpAxis::Z)?;
    demo.noise_panel()?;
    demo.terrains()?;
    demo.clouds()?;
    match shared_mesh("fandisk.off") {
        Some(path) => {
            let mesh = demo.read(&path)?;
            demo.openmesh_round_trip("fandisk", &mesh)?;
            demo.features("fandisk", &mesh)?;
            demo.hierarchy("fandisk", &mesh, UpAxis::Z)?;
        }
        None => demo.features("torus", &torus)?,
    }
    demo.detail_recipes()?;
    demo.environment()?;
    let ctx = demo.ctx;
    ctx.report(
        || format!("demo: {} files in {} in {} ms", demo.written.len(), demo.out.display(), super::millis(start)),
        || json!({ "out": demo.out, "files": demo.written, "seconds": start.elapsed().as_secs_f64() }),
    );
    Ok(())
}

/// A view of `mesh` at `size`, `up` axis, with the given colours and mode.
fn view(
    mesh: &Mesh,
    size: (usize, usize),
    up: UpAxis,
    colors: ColorSource,
    mode: Mode,
    edges: bool,
) -> Result<Picture> {
    let options = RenderOptions { width: size.0, height: size.1, up, colors, mode, edges, ..RenderOptions::default() };
    render(mesh, &options)
}

impl Demo {
    fn line(&self, line: impl FnOnce() -> String) {
        self.ctx.line(line);
    }

    fn path(&self, name: &str) -> PathBuf {
        self.out.join(name)
    }

    fn mesh(&mut self, mesh: &Mesh, name: &str) -> Result<()> {
        io::write(mesh, &self.path(name), WriteOptions::default())?;
        self.written.push(self.path(name));
        Ok(())
    }

    fn picture(&mut self, picture: &Picture, name: &str) -> Result<()> {
        picture.write_png(&self.path(name))?;
        self.written.push(self.path(name));
        Ok(())
    }

    fn read(&self, path: &Path) -> Result<Mesh> {
        let start = Instant::now();
        let outcome = io::read(path)?;
        let report = outcome.mesh.validate();
        self.line(|| {
            format!(
                "read: {} ({} vertices, {} tris, genus {}) in {} ms",
                path.display(),
                report.vertices,
                report.faces,
                report.genus.map_or("n/a".into(), |g| g.to_string()),
                super::millis(start)
            )
        });
        Ok(outcome.mesh)
    }

    fn openmesh_round_trip(&self, name: &str, mesh: &Mesh) -> Result<()> {
        let start = Instant::now();
        let he = HalfEdgeMesh::from_mesh(mesh)?;
        let counts = he.counts()?;
        let back = he.export()?.mesh;
        if back.positions != mesh.positions || back.triangles != mesh.triangles {
            return Err(Error::Internal(format!("{name}: the OpenMesh round trip changed the mesh")));
        }
        self.line(|| {
            format!(
                "openmesh: {name} {} vertices, {} edges, {} tris round trip exact in {} ms",
                counts.vertices,
                counts.edges,
                counts.faces,
                super::millis(start)
            )
        });
        Ok(())
    }

    fn cgal_measures(&self, torus: &Mesh, sphere: &Mesh) -> Result<()> {
        let start = Instant::now();
        let coarse = primitives::icosphere(1.0, 2);
        let d = ffi::hausdorff_distance(sphere, &coarse, HausdorffOptions::default())?;
        self.line(|| {
            format!(
                "cgal: hausdorff(icosphere {} tris, icosphere {} tris) = {d:.5} ({:.2}% of the diameter) in {} ms",
                sphere.face_count(),
                coarse.face_count(),
                100.0 * d / 2.0,
                super::millis(start)
            )
        });
        let start = Instant::now();
        let pairs = ffi::self_intersections(torus)?;
        self.line(|| {
            format!("cgal: torus self-intersections: {} face pairs in {} ms", pairs.len(), super::millis(start))
        });
        let start = Instant::now();
        let quadrics = ffi::vertex_quadrics(torus, 100.0)?;
        let lifted: Vec<_> = torus.positions.iter().map(|p| *p * 1.01).collect();
        let errors = ffi::quadric_errors(&quadrics, &lifted)?;
        let mean = errors.iter().sum::<f64>() / errors.len() as f64;
        self.line(|| {
            format!(
                "cgal: garland-heckbert quadrics of {} vertices, mean error after 1% scaling {mean:.3e} in {} ms",
                quadrics.len(),
                super::millis(start)
            )
        });
        Ok(())
    }

    /// The 4-k hierarchy of `mesh` to 5 % of its vertices: the base domain and the level
    /// halfway, the round trip back to the input, and a panel input | middle | base.
    fn hierarchy(&mut self, name: &str, mesh: &Mesh, up: UpAxis) -> Result<()> {
        let start = Instant::now();
        let target = (mesh.vertex_count() / 20).max(4);
        let options =
            SimplifyOptions { target_vertices: Some(target), record_levels: true, ..SimplifyOptions::default() };
        let h = self.ctx.spin("simplify", name, || build(mesh, &options))?;
        let base = h.base_mesh().mesh;
        let hausdorff = crate::hierarchy::compare::relative_hausdorff(mesh, &base)?;
        self.line(|| {
            format!(
                "simplify: {name} {} tris => {} tris, {} levels (hausdorff {:.2}%) in {} ms",
                mesh.face_count(),
                base.face_count(),
                h.steps(),
                100.0 * hausdorff,
                super::millis(start)
            )
        });
        self.mesh(&base, &format!("{name}-base.ply"))?;
        let middle = h.levels.get(h.steps() / 2).map(|l| &l.mesh).unwrap_or(&base);
        self.mesh(middle, &format!("{name}-level-{}.ply", h.steps() - h.steps() / 2))?;
        let views = [mesh, middle, &base].map(|m| view(m, PANEL, up, ColorSource::None, Mode::Faces, true));
        let views: Vec<Picture> = views.into_iter().collect::<Result<_>>()?;
        self.picture(&Picture::side_by_side(&views, 8, WHITE)?, &format!("{name}-hierarchy.png"))?;

        let start = Instant::now();
        let mut refiner = Refiner::new(&h)?;
        refiner.refine_all()?;
        let back = refiner.mesh()?;
        let exact = back.has_input_positions(mesh);
        self.line(|| {
            format!(
                "refine: {name} {} tris => {} tris, positions {}, {:.2}% faces restored in {} ms",
                base.face_count(),
                back.mesh.face_count(),
                if exact { "exact" } else { "moved" },
                100.0 * connectivity_match(&mesh.triangles, &back.triangles_in_ids()),
                super::millis(start)
            )
        });
        Ok(())
    }

    /// Terrains: a classic 257² with a sea (mesh, 16-bit heightmap, hillshaded map and a
    /// rendering), a smoothed one (seed 002), Janeczek's dual surface over a tilted
    /// quadrilateral, and seed 001's three views of a small grid.
    fn terrains(&mut self) -> Result<()> {
        use crate::terrain::stream::{StreamFormat, write_terrain};
        use crate::terrain::{Method, Rect, TerrainParams, mesh, whole};
        let start = Instant::now();
        let params =
            TerrainParams { size: 257, hurst: 0.6, seed: 2, sea_level: Some(-0.8), ..TerrainParams::default() };
        let rect = Rect { x0: 0, y0: 0, x1: 256, y1: 256 };
        let classic = mesh(&params, rect)?;
        self.mesh(&classic, "terrain.ply")?;
        // The heightmap uses the terrain's own range (tiles and streams use a fixed one).
        let field = whole(&params)?;
        let range = value_range(&field.heights).ok_or_else(|| Error::Internal("empty terrain".into()))?;
        let path = self.path("terrain-height.png");
        crate::io::write_atomically(&path, |w| {
            write_terrain(&params, rect, StreamFormat::Png16, range, 257, w).map_err(std::io::Error::other)
        })?;
        self.written.push(path);
        self.picture(&terrain_map(&params, &field.heights), "terrain-map.png")?;
        self.picture(&view(&classic, VIEW, UpAxis::Z, ColorSource::Attribute, Mode::Faces, false)?, "terrain.png")?;

        let smooth = TerrainParams { method: Method::Smooth, seed: 5, ..params };
        self.picture(&terrain_map(&smooth, &whole(&smooth)?.heights), "terrain-smooth-map.png")?;
        let small = TerrainParams { size: 33, hurst: 0.7, seed: 9, sea_level: None, ..TerrainParams::default() };
        let grid = mesh(&small, Rect { x0: 0, y0: 0, x1: 32, y1: 32 })?;
        let views = [Mode::Faces, Mode::Wireframe, Mode::Points]
            .map(|mode| view(&grid, PANEL, UpAxis::Z, ColorSource::Attribute, mode, false));
        let views: Vec<Picture> = views.into_iter().collect::<Result<_>>()?;
        self.picture(&Picture::side_by_side(&views, 8, WHITE)?, "terrain-views.png")?;
        self.dual_terrain()?;
        self.line(|| {
            format!(
                "terrain: classic 257x257 (H 0.6, sea -0.8), smooth, dual and 33x33 views => {}/terrain*.png, terrain.ply in {} ms",
                self.out.display(),
                super::millis(start)
            )
        });
        self.eroded_terrain()
    }

    /// A terrain before and after hydraulic erosion (#41) and the erosion's flow layer.
    fn eroded_terrain(&mut self) -> Result<()> {
        use crate::terrain::{ErosionLayer, HydraulicErosion, Rect, TerrainParams, heights, heights_and_layers};
        let start = Instant::now();
        let plain = TerrainParams {
            size: 257,
            hurst: 1.0,
            sigma: 2.0,
            seed: 4,
            corners: Some([1.5, 0.5, 2.0, 1.0]),
            sea_level: Some(0.0),
            ..TerrainParams::default()
        };
        let eroded = TerrainParams {
            hydraulic: Some(HydraulicErosion { iterations: 200, ..HydraulicErosion::default() }),
            ..plain
        };
        let rect = Rect { x0: 0, y0: 0, x1: 256, y1: 256 };
        let before = heights(&plain, rect)?;
        let (after, layers) = heights_and_layers(&eroded, rect, &[ErosionLayer::Flow])?;
        let flow = Picture::grey(&layers[0].heights, 257, (0.0, 1.0));
        let panels = [terrain_map(&plain, &before.heights), terrain_map(&eroded, &after.heights), flow];
        self.picture(&Picture::side_by_side(&panels, 8, WHITE)?, "terrain-eroded.png")?;
        self.line(|| {
            format!(
                "terrain: 257x257 before and after 200 iterations of hydraulic erosion, and its flow layer => {}/terrain-eroded.png in {} ms",
                self.out.display(),
                super::millis(start)
            )
        });
        Ok(())
    }

    fn dual_terrain(&mut self) -> Result<()> {
        use crate::terrain::{DualParams, dual_mesh, dual_midpoint_displacement};
        let params = DualParams {
            x: glam::DVec3::new(1.0, 0.0, 0.25),
            y: glam::DVec3::new(0.0, 1.0, 0.0),
            levels: 7,
            seed: 3,
            ..DualParams::default()
        };
        let surface = dual_midpoint_displacement(&params, |_, _| {})?;
        let m = dual_mesh(&surface, &params, &crate::terrain::Palette::default());
        self.mesh(&m, "terrain-dual.ply")?;
        self.picture(&view(&m, VIEW, UpAxis::Z, ColorSource::Attribute, Mode::Faces, false)?, "terrain-dual.png")
    }

    /// Seed 001's clouds: a 257² plasma, thresholded and coloured.
    fn clouds(&mut self) -> Result<()> {
        use crate::terrain::{CloudParams, TerrainParams, clouds};
        let start = Instant::now();
        let params = CloudParams {
            plasma: TerrainParams { size: 257, hurst: 0.7, seed: 4, ..TerrainParams::default() },
            ..Default::default()
        };
        let (rgb, cover) = clouds(&params)?;
        crate::io::image::write_png_rgb8(&self.path("clouds.png"), &rgb, 257)?;
        self.written.push(self.path("clouds.png"));
        self.line(|| {
            format!(
                "clouds: 257x257 => {:.0}% cover => {}/clouds.png in {} ms",
                cover * 100.0,
                self.out.display(),
                super::millis(start)
            )
        });
        Ok(())
    }

    /// Seed 002's environment: the animated scene (seed 7) and its still, and the
    /// generators one by one — a cottonwood, a palm, a flower, a smoke frame and a level-3
    /// Menger sponge — side by side.
    fn environment(&mut self) -> Result<()> {
        use crate::scene::{compose, flora, menger, smoke};
        let start = Instant::now();
        let scene = compose::compose(&compose::SceneParams { seed: 7, ..Default::default() })?;
        let glb = self.path("scene.glb");
        crate::io::glb_scene::write_scene_glb(&scene.glb(), &glb)?;
        self.written.push(glb);
        self.picture(&render(&scene.still(), &scene.preview_options(VIEW.0 * 2, VIEW.1 * 2))?, "scene.png")?;
        let mut parts = Vec::new();
        for (preset, name) in [
            (flora::FloraPreset::Cottonwood, "flora-cottonwood.ply"),
            (flora::FloraPreset::Palm, "flora-palm.ply"),
            (flora::FloraPreset::Flower, "flora-flower.ply"),
        ] {
            let plant = flora::plant(&preset.rules(), 3, 8)?.mesh();
            self.mesh(&plant, name)?;
            parts.push(plant);
        }
        let puff = smoke::smoke_frames(smoke::SmokeParams::default(), 40, 1, 1)?.remove(0);
        self.mesh(&puff, "smoke.ply")?;
        parts.push(puff);
        let sponge = menger::menger_sponge(3, 1.0)?;
        self.mesh(&sponge, "menger-3.ply")?;
        parts.push(sponge);
        let views = parts
            .iter()
            .map(|m| view(m, (PANEL.0 * 3 / 4, PANEL.1), UpAxis::Z, ColorSource::Attribute, Mode::Faces, false))
            .collect::<Result<Vec<_>>>()?;
        self.picture(&Picture::side_by_side(&views, 8, WHITE)?, "scene-generators.png")?;
        self.line(|| {
            format!(
                "scene: seed 7 => {} plants, {} frames => {}/scene.glb, scene.png, scene-generators.png in {} ms",
                scene.placements.len(),
                scene.params.frames,
                self.out.display(),
                super::millis(start)
            )
        });
        Ok(())
    }

    /// One 256×256 image per noise kind (seed 7), and all of them side by side.
    fn noise_panel(&mut self) -> Result<()> {
        let start = Instant::now();
        let kinds = [
            ("perlin", NoiseKind::Perlin, 1.0 / 32.0),
            ("fbm", NoiseKind::Fbm, 1.0 / 32.0),
            ("turbulence", NoiseKind::Turbulence, 1.0 / 32.0),
            ("marble", NoiseKind::Marble, 1.0 / 32.0),
            ("multifractal", NoiseKind::Multifractal, 1.0 / 32.0),
            ("wood", NoiseKind::Wood, 1.0 / 64.0),
            ("gabor", NoiseKind::Gabor, 1.0),
            ("phasor", NoiseKind::Phasor, 1.0),
        ];
        let mut tiles = Vec::new();
        for (name, kind, scale) in kinds {
            let fractal = Fractal { octaves: kind.default_octaves(), ..Fractal::default() };
            let field = NoiseField::new(&NoiseSpec { kind, fractal, seed: 7, ..NoiseSpec::default() })?;
            let values = field.grid2(0.0, 0.0, scale, 256, 256);
            let range =
                value_range(&values).ok_or_else(|| Error::Internal(format!("{name} noise has no finite value")))?;
            let path = self.path(&format!("noise-{name}.png"));
            write_png16(&path, &values, 256, range)?;
            self.written.push(path);
            // The panel shows the same square at 160 pixels a side.
            let tile = field.grid2(0.0, 0.0, scale * 256.0 / 160.0, 160, 160);
            tiles.push(Picture::grey(&tile, 160, range));
        }
        self.picture(&Picture::side_by_side(&tiles, 6, WHITE)?, "noise-panel.png")?;
        self.line(|| {
            format!(
                "noise: {} images 256x256 => {}/noise-*.png, noise-panel.png in {} ms",
                kinds.len(),
                self.out.display(),
                super::millis(start)
            )
        });
        Ok(())
    }

    /// Curvatures and feature classes, written as PLY properties and class colours, with a
    /// panel: classes | mean curvature.
    fn features(&mut self, name: &str, mesh: &Mesh) -> Result<()> {
        let start = Instant::now();
        let analysis = analyze(mesh, &AnalysisOptions::default())?;
        let [face, weak, strong, corner] = analysis.class_counts();
        let mut coloured = mesh.clone();
        analysis.attach_to(&mut coloured);
        self.mesh(&coloured, &format!("{name}-features.ply"))?;
        let views = [ColorSource::Attribute, ColorSource::Scalar("mean_curvature".into())]
            .map(|colors| view(&coloured, PANEL, UpAxis::Z, colors, Mode::Faces, false));
        let views: Vec<Picture> = views.into_iter().collect::<Result<_>>()?;
        self.picture(&Picture::side_by_side(&views, 8, WHITE)?, &format!("{name}-features.png"))?;
        self.line(|| {
            format!(
                "analyze: {name} {} vertices => {corner} corners, {strong} strong edge, {weak} weak, {face} face => {name}-features.ply, .png in {} ms",
                mesh.vertex_count(),
                super::millis(start)
            )
        });
        Ok(())
    }

    /// Runs the demo recipes on the meshes their first line names (skipping shared meshes
    /// that are absent), writing `detail-NAME.ply` (self-intersections damped away) and a
    /// picture input | result.
    fn detail_recipes(&mut self) -> Result<()> {
        for (name, text, up) in DEMO_RECIPES {
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
            // The recipe's whole [hierarchy] table, as `asperity detail` reads it.
            let simplify = HierarchyRequest::default().options_over(
                &recipe.hierarchy,
                mesh.vertex_count(),
                false,
                Spelling::Flag,
            )?;
            let options = DetailOptions { simplify, no_self_intersections: true, ..DetailOptions::default() };
            let outcome = self.ctx.spin("detail", name, || detail::apply(&mesh, &recipe, &options))?;
            self.mesh(&outcome.result.mesh, &format!("detail-{name}.ply"))?;
            // The result in its recipe's colours where it has a [color] table (Fig. 5.6).
            let views =
                [&mesh, &outcome.result.mesh].map(|m| view(m, PANEL, up, ColorSource::Attribute, Mode::Faces, false));
            let views: Vec<Picture> = views.into_iter().collect::<Result<_>>()?;
            self.picture(&Picture::side_by_side(&views, 8, WHITE)?, &format!("detail-{name}.png"))?;
            let touched: usize = outcome.steps.iter().map(|s| s.touched).sum();
            self.line(|| {
                format!(
                    "detail: {name} on {mesh_name}: {} steps over {} levels, {touched} vertex moves, {} self-intersections damped ({} vertices) => detail-{name}.ply, .png in {} ms",
                    outcome.steps.len(),
                    outcome.levels,
                    outcome.intersections.found,
                    outcome.intersections.damped,
                    super::millis(start)
                )
            });
        }
        Ok(())
    }
}

/// The hillshaded colour map of a whole terrain.
fn terrain_map(params: &crate::terrain::TerrainParams, heights: &[f64]) -> Picture {
    crate::terrain::preview::relief_picture(params, heights, params.size as usize, 1)
}

/// Example recipes the demo runs (the files of `recipes/`, built in), with the axis that
/// is up in their pictures.
const DEMO_RECIPES: [(&str, &str, UpAxis); 12] = [
    ("torus-variation", include_str!("../../recipes/torus-variation.toml"), UpAxis::Z),
    ("sphere-marble", include_str!("../../recipes/sphere-marble.toml"), UpAxis::Z),
    ("sphere-turbulence", include_str!("../../recipes/sphere-turbulence.toml"), UpAxis::Z),
    ("sphere-multifractal", include_str!("../../recipes/sphere-multifractal.toml"), UpAxis::Z),
    ("sphere-wood", include_str!("../../recipes/sphere-wood.toml"), UpAxis::Z),
    ("mushroom-planet", include_str!("../../recipes/mushroom-planet.toml"), UpAxis::Z),
    ("sphere-virus", include_str!("../../recipes/sphere-virus.toml"), UpAxis::Z),
    ("femur-wearing", include_str!("../../recipes/femur-wearing.toml"), UpAxis::Z),
    ("femur-wearing-strong", include_str!("../../recipes/femur-wearing-strong.toml"), UpAxis::Z),
    ("fandisk-erosion", include_str!("../../recipes/fandisk-erosion.toml"), UpAxis::Z),
    ("elephant-taper-twist", include_str!("../../recipes/elephant-taper-twist.toml"), UpAxis::Z),
    ("bunny-hair", include_str!("../../recipes/bunny-hair.toml"), UpAxis::Y),
];

/// A mesh of `../shared/data/meshes` (next to the working directory or the executable's
/// checkout), when present.
fn shared_mesh(name: &str) -> Option<PathBuf> {
    let candidates = [
        PathBuf::from("../shared/data/meshes"),
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/data/meshes"),
    ];
    candidates.iter().map(|dir| dir.join(name)).find(|p| p.is_file())
}
