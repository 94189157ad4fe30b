//! Seed 002's environment (#25): the generators through the command line — closed meshes
//! where they should be, animated glTF files the Khronos validator accepts, one file per
//! frame for mesh formats, and the flags that do not apply refused.

use std::path::Path;
use std::process::Command;

use crate::common::temp_dir;
use crate::io::glb::khronos_validate;

fn asperity(dir: &Path, args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_asperity")).args(args).current_dir(dir).output().unwrap()
}

fn ok(dir: &Path, args: &[&str]) -> String {
    let out = asperity(dir, args);
    assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn refused(dir: &Path, args: &[&str], says: &str) {
    let out = asperity(dir, args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
    let first = stderr.lines().next().unwrap_or_default();
    assert!(first.starts_with("asperity: ") && first.contains(says), "the first line says it all: {stderr}");
}

#[test]
fn the_scene_and_every_animated_generator_pass_the_khronos_validator() {
    let tmp = temp_dir();
    let dir = tmp.path();
    ok(dir, &["scene", "--seed", "7", "--size", "65", "--frames", "4", "-o", "scene.glb", "--preview", "scene.png"]);
    ok(dir, &["smoke", "--frames", "3", "--resolution", "40", "-o", "smoke.glb"]);
    ok(dir, &["butterflies", "--count", "4", "--steps", "30", "-o", "butterflies.glb"]);
    ok(dir, &["flora", "--preset", "palm", "-o", "palm.glb"]);
    let files: Vec<_> = ["scene.glb", "smoke.glb", "butterflies.glb", "palm.glb"].iter().map(|f| dir.join(f)).collect();
    // The animation reads back: every channel's node exists, and the scene holds nodes
    // for the terrain, the water and smoke frames, the plants and the butterflies.
    let (document, _, _) = gltf::import(dir.join("scene.glb")).unwrap();
    let animation = document.animations().next().expect("an animation");
    assert!(animation.channels().count() > 0);
    let names: Vec<String> = document.nodes().filter_map(|n| n.name().map(str::to_string)).collect();
    for wanted in ["terrain", "cabin", "water_frame_003", "plume_frame_000", "butterfly_0", "plant_000"] {
        assert!(names.iter().any(|n| n == wanted), "no node {wanted} in {names:?}");
    }
    let png = std::fs::read(dir.join("scene.png")).unwrap();
    assert!(png.starts_with(b"\x89PNG"));
    khronos_validate(&files);
}

#[test]
fn mesh_formats_get_one_closed_file_per_frame() {
    let tmp = temp_dir();
    let dir = tmp.path();
    let report = ok(dir, &["smoke", "--frames", "3", "--resolution", "40", "-o", "puff.ply", "--json"]);
    let report: serde_json::Value = serde_json::from_str(&report).unwrap();
    assert_eq!(report["frames"], 3, "{report}");
    for k in 0..3 {
        let mesh = asperity::io::read(&dir.join(format!("puff_{k:03}.ply"))).unwrap().mesh;
        assert!(mesh.validate().is_closed_manifold(), "frame {k}");
    }
    ok(dir, &["menger", "--level", "2", "-o", "sponge.off"]);
    let sponge = asperity::io::read(&dir.join("sponge.off")).unwrap().mesh.validate();
    assert!(sponge.is_closed_manifold());
    assert_eq!(sponge.faces as u64, 2 * asperity::scene::menger::square_count(2));
    ok(dir, &["terrain", "--method", "smooth", "--size", "65", "-o", "land.ply"]);
    ok(dir, &["water", "land.ply", "--level", "0", "--frames", "1", "--cells", "16", "-o", "sea.ply"]);
    let sea = asperity::io::read(&dir.join("sea.ply")).unwrap().mesh;
    assert!(sea.scalars.contains_key("depth"), "PLY keeps the depth: {:?}", sea.scalars.keys());
}

#[test]
fn flags_outside_their_mode_and_bad_rules_are_refused() {
    let tmp = temp_dir();
    let dir = tmp.path();
    refused(dir, &["smoke", "--frames", "2", "--fps", "24", "-o", "s.ply"], "--fps applies to animated .glb");
    refused(dir, &["butterflies", "-o", "b.ply"], ".glb");
    refused(dir, &["scene", "-o", "s.ply"], ".glb");
    refused(dir, &["menger", "--level", "9", "-o", "m.ply"], "9");
    refused(dir, &["flora", "--preset", "palm", "--rules", "r.toml", "-o", "p.ply"], "cannot be used with");
    std::fs::write(dir.join("bad.toml"), "axiom = \"a\"\ndepth = 2\nlength = \"long\"\n").unwrap();
    refused(dir, &["flora", "--rules", "bad.toml", "-o", "p.ply"], "bad.toml");
    refused(dir, &["flora", "--rules", "bad.toml", "-o", "p.ply"], "line 3");
    refused(dir, &["render", "x.ply", "-o", "x.png", "--water-clarity", "0.1"], "--water-level");
    // Sizes that would exhaust memory are refused before any work.
    refused(dir, &["butterflies", "--count", "10000", "--steps", "1000000", "-o", "b.glb"], "keyframes");
    refused(dir, &["smoke", "--resolution", "512", "--radius", "0.5", "-o", "s.glb"], "at most");
    let greedy = asperity::scene::flora::FloraPreset::Cottonwood.text().replace("count = 7", "count = 1000").replace("depth = 6", "depth = 14");
    std::fs::write(dir.join("greedy.toml"), greedy).unwrap();
    refused(dir, &["flora", "--rules", "greedy.toml", "-o", "g.ply"], "leaves");
    refused(dir, &["scene", "--frames", "100000", "-o", "s.glb"], "frames");
    for never in ["p.ply", "s.ply", "s.glb", "b.glb", "g.ply"] {
        assert!(!dir.join(never).exists(), "no output file on refusal: {never}");
    }
}

#[test]
fn the_water_pass_shows_the_ground_through_shallow_water_and_the_sky_at_grazing_angles() {
    use asperity::render::{RenderOptions, WaterView, render};
    // A ramp from 1 below the water to 1 above it, grey.
    let mut ground = asperity::mesh::primitives::grid(32);
    for p in &mut ground.positions {
        p.z = 2.0 * p.x - 1.0;
    }
    ground.colors = Some(vec![[200, 60, 60]; ground.vertex_count()]);
    let options = |pitch: f64| RenderOptions {
        width: 120,
        height: 90,
        yaw_deg: 0.0,
        pitch_deg: pitch,
        background: None,
        water: Some(WaterView { level: 0.0, clarity: 0.05 }),
        ..RenderOptions::default()
    };
    let steep = render(&ground, &options(80.0)).unwrap();
    let redness = |p: [u8; 4]| f64::from(p[0]) - f64::from(p[2]);
    // Looking down along +y (x grows to the right): along the row through the middle,
    // the ground's red fades into the water's blue with depth (towards x = 0, the left).
    let row: Vec<f64> = (0..steep.width).map(|x| redness(steep.pixel(x, steep.height / 2))).collect();
    let (shallow, deep) = (row[steep.width / 2 - 8], row[steep.width / 8]);
    assert!(shallow > deep + 20.0, "shallow {shallow} vs deep {deep}: {row:?}");
    let grazing = render(&ground, &options(8.0)).unwrap();
    let bright = |p: [u8; 4]| f64::from(p[0]) + f64::from(p[1]) + f64::from(p[2]);
    let mean = |pic: &asperity::render::Picture| {
        let water: Vec<f64> = (0..pic.height)
            .flat_map(|y| (0..pic.width / 3).map(move |x| (x, y)))
            .map(|(x, y)| pic.pixel(x, y))
            .filter(|p| p[3] == 255 && p[2] > p[0])
            .map(bright)
            .collect();
        water.iter().sum::<f64>() / water.len().max(1) as f64
    };
    assert!(mean(&grazing) > mean(&steep) + 40.0, "the sky reflects at grazing angles");
}

/// The generators' requests (#38) read strictly, and their rules hold in the library, not
/// only behind the command line's flags.
#[test]
fn the_generators_requests_are_strict_and_checked_in_the_library() {
    use asperity::scene::flora::{FloraPreset, FloraRequest};
    use asperity::scene::water::WaterRequest;
    let water: WaterRequest = serde_json::from_str(r#"{"level": 0.5, "frames": 3}"#).unwrap();
    assert_eq!((water.level, water.frames, water.cells), (0.5, 3, WaterRequest::default().cells));
    assert!(serde_json::from_str::<WaterRequest>(r#"{"level": 0.5, "frame": 3}"#).is_err());
    let no_frames = WaterRequest { frames: 0, ..WaterRequest::default() };
    assert!(no_frames.check().unwrap_err().to_string().contains("1 to 1000 frames"));
    let terrain = asperity::mesh::primitives::grid(8);
    let request = WaterRequest { level: 0.1, frames: 2, cells: 16, ..WaterRequest::default() };
    let (params, frames) = request.frames_over(&terrain, 12.0).unwrap();
    assert_eq!(frames.len(), 2);
    assert!(frames[0].positions.iter().all(|p| (p.z - params.level).abs() < 1.0));
    let neither = FloraRequest::default().plant().unwrap_err().to_string();
    assert!(neither.contains("a preset or from rules"), "{neither}");
    let palm = FloraRequest { preset: Some(FloraPreset::Palm), ..FloraRequest::default() };
    assert_eq!(palm.source(), "palm");
    assert!(!palm.plant().unwrap().nodes.is_empty());
}
