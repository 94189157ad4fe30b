//! The command line as a user meets it: exit codes, one-line errors, no partial output.

use std::path::Path;
use std::process::{Command, Output};

use crate::common::{shared_meshes, shared_meshes_present, temp_dir};

fn asperity(args: &[&str], cwd: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_asperity")).args(args).current_dir(cwd).output().expect("run asperity")
}

fn assert_one_line_error(out: &Output, code: i32, phrases: &[&str]) {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(code), "stderr: {stderr}");
    assert_eq!(stderr.lines().count(), 1, "one line: {stderr}");
    assert!(!stderr.contains("panicked") && !stderr.contains("RUST_BACKTRACE"), "{stderr}");
    for p in phrases {
        assert!(stderr.contains(p), "`{stderr}` should contain `{p}`");
    }
}

#[test]
fn info_json_reports_the_required_keys() {
    let dir = shared_meshes();
    let tmp = temp_dir();
    let out = asperity(&["info", dir.join("3torus.off").to_str().unwrap(), "--json"], tmp.path());
    assert!(out.status.success());
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for key in [
        "vertices",
        "faces",
        "edges",
        "boundary_loops",
        "non_manifold_edges",
        "non_manifold_vertices",
        "components",
        "euler",
        "genus",
        "degenerate_faces",
        "unreferenced_vertices",
        "triangulated_polygons",
        "bbox_min",
        "bbox_max",
    ] {
        assert!(json.get(key).is_some(), "missing {key}");
    }
    assert_eq!(json["genus"], 3);
    assert_eq!(json["triangulated_polygons"], 23);
}

#[test]
fn a_truncated_file_exits_2_with_one_line_naming_file_and_line() {
    let tmp = temp_dir();
    std::fs::write(tmp.path().join("cut.off"), "OFF\n4 2 0\n0 0 0\n1 0 0\n").unwrap();
    let out = asperity(&["info", "cut.off"], tmp.path());
    assert_one_line_error(&out, 2, &["cut.off", "line 4"]);
}

#[test]
fn convert_writes_the_output_and_nothing_on_failure() {
    let tmp = temp_dir();
    std::fs::write(tmp.path().join("tri.off"), "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").unwrap();
    let out = asperity(&["convert", "tri.off", "tri.ply"], tmp.path());
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stdout).starts_with("convert: tri.off (3 vertices, 1 tris)"));
    assert!(tmp.path().join("tri.ply").is_file());

    std::fs::write(tmp.path().join("bad.off"), "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 9\n").unwrap();
    let out = asperity(&["convert", "bad.off", "bad.stl"], tmp.path());
    assert_one_line_error(&out, 2, &["bad.off", "line 6"]);
    let files: Vec<_> = std::fs::read_dir(tmp.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(files.len(), 3, "no output, no temporary file: {files:?}");
}

#[test]
fn no_command_overwrites_its_input_without_force() {
    let tmp = temp_dir();
    let original = "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    std::fs::write(tmp.path().join("tet.off"), original).unwrap();
    // Also through another spelling of the same path.
    let runs: [&[&str]; 6] = [
        &["convert", "tet.off", "tet.off"],
        &["convert", "tet.off", "./tet.off", "--repair"],
        &["analyze", "tet.off", "-o", "tet.off"],
        &["simplify", "tet.off", "--target-vertices", "4", "-o", "tet.off"],
        &["simplify", "tet.off", "--target-vertices", "4", "-o", "b.ply", "--param-out", "tet.off"],
        &["detail", "tet.off", "-o", "tet.off"],
    ];
    for args in runs {
        let out = asperity(args, tmp.path());
        assert_one_line_error(&out, 2, &["--force"]);
        assert_eq!(std::fs::read_to_string(tmp.path().join("tet.off")).unwrap(), original, "{args:?}");
    }
    assert_eq!(std::fs::read_dir(tmp.path()).unwrap().count(), 1, "nothing else written");
    let out = asperity(&["convert", "tet.off", "tet.off", "--force"], tmp.path());
    assert!(out.status.success());
}

/// A usage error from the argument parser: exit 2, a first line that says everything
/// (what is wrong, with the missing arguments or the valid values), then clap's usage line
/// and tips (#24 item 13).
fn assert_usage_error(out: &Output, first_line: &[&str], later: &[&str]) {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "stderr: {stderr}");
    let first = stderr.lines().next().unwrap_or("");
    assert!(first.starts_with("asperity: "), "{stderr}");
    for p in first_line {
        assert!(first.contains(p), "first line `{first}` should contain `{p}`");
    }
    for p in later {
        assert!(stderr.contains(p), "`{stderr}` should contain `{p}`");
    }
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn usage_errors_exit_2_with_clap_s_whole_message() {
    let tmp = temp_dir();
    assert_usage_error(&asperity(&["frobnicate"], tmp.path()), &["frobnicate"], &["Usage: asperity"]);
    assert_usage_error(&asperity(&["info"], tmp.path()), &["required", "<FILE>"], &["Usage: asperity info <FILE>"]);
    assert_usage_error(
        &asperity(&["terrain"], tmp.path()),
        &["required", "--output <OUTPUT>"],
        &["Usage: asperity terrain"],
    );
    assert_usage_error(
        &asperity(&["terrain", "--method", "x", "-o", "a.ply"], tmp.path()),
        &["'x'", "possible values: classic, smooth, dual"],
        &[],
    );
    assert_usage_error(
        &asperity(&["terrain", "--sizee", "3", "-o", "a.ply"], tmp.path()),
        &["'--sizee'"],
        &["a similar argument exists: '--size'"],
    );
    // Negative numbers need no `=`: they reach validation, which names the flag.
    assert_one_line_error(
        &asperity(&["noise", "--kind", "gabor", "--k", "-1", "-o", "x.png"], tmp.path()),
        2,
        &["K", "positive"],
    );
    assert_one_line_error(&asperity(&["convert", "a.off", "b.xyz"], tmp.path()), 2, &["b.xyz", "unknown mesh format"]);
    assert!(asperity(&["--help"], tmp.path()).status.success());
}

#[test]
fn demo_writes_its_meshes() {
    let tmp = temp_dir();
    let out = asperity(&["demo", "--out", "results"], tmp.path());
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    for file in [
        "torus.ply",
        "icosphere.obj",
        "icosphere-coarse.off",
        "noise-gabor.png",
        "noise-marble.png",
        "terrain.ply",
        "terrain-height.png",
        "clouds.png",
        "torus-base.ply",
        // The feature analysis uses fandisk when the shared meshes are there.
        if shared_meshes_present() { "fandisk-features.ply" } else { "torus-features.ply" },
    ] {
        assert!(tmp.path().join("results").join(file).is_file(), "{file}");
    }
    // Every picture is a real picture: decodable, and not one flat colour.
    let mut pictures = 0;
    for entry in std::fs::read_dir(tmp.path().join("results")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "png") {
            let mut reader =
                png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&path).unwrap())).read_info().unwrap();
            let mut data = vec![0; reader.output_buffer_size().unwrap()];
            reader.next_frame(&mut data).unwrap();
            let distinct: std::collections::HashSet<&[u8]> = data.chunks(3).collect();
            assert!(distinct.len() > 16, "{} is nearly flat", path.display());
            pictures += 1;
        }
    }
    let expected = if shared_meshes_present() { 23 } else { 20 };
    assert!(pictures >= expected, "{pictures} pictures");
    for file in
        ["noise-panel.png", "terrain-map.png", "terrain-views.png", "torus-hierarchy.png", "detail-sphere-marble.png"]
    {
        assert!(tmp.path().join("results").join(file).is_file(), "{file}");
    }
    let stdout = String::from_utf8_lossy(&out.stdout);
    for stage in [
        "round trip exact",
        "hausdorff",
        "noise:",
        "terrain:",
        "clouds:",
        "analyze:",
        "simplify: torus",
        "positions exact",
    ] {
        assert!(stdout.contains(stage), "missing `{stage}` in {stdout}");
    }
}

#[test]
fn noise_writes_png16_and_raw_f32_deterministically() {
    let tmp = temp_dir();
    let run = |args: &[&str], threads: &str| {
        Command::new(env!("CARGO_BIN_EXE_asperity"))
            .args(args)
            .env("RAYON_NUM_THREADS", threads)
            .current_dir(tmp.path())
            .output()
            .expect("run asperity")
    };
    for kind in ["perlin", "fbm", "turbulence", "marble", "multifractal", "wood", "gabor"] {
        let out = run(&["noise", "--kind", kind, "--size", "64", "--seed", "5", "-o", "a.png"], "1");
        assert!(out.status.success(), "{kind}: {}", String::from_utf8_lossy(&out.stderr));
        let out = run(&["noise", "--kind", kind, "--size", "64", "--seed", "5", "-o", "b.png"], "2");
        assert!(out.status.success());
        let a = std::fs::read(tmp.path().join("a.png")).unwrap();
        assert_eq!(a, std::fs::read(tmp.path().join("b.png")).unwrap(), "{kind}: 1 vs 2 threads");
        let decoder = png::Decoder::new(std::io::Cursor::new(a));
        let info = decoder.read_info().unwrap().info().clone();
        assert_eq!((info.width, info.height, info.bit_depth), (64, 64, png::BitDepth::Sixteen));
    }
    let out = run(&["noise", "--kind", "gabor", "--size", "32", "-o", "g.f32"], "2");
    assert!(out.status.success());
    assert_eq!(std::fs::metadata(tmp.path().join("g.f32")).unwrap().len(), 32 * 32 * 4);
    assert_one_line_error(&run(&["noise", "--size", "8", "-o", "x.jpg"], "1"), 2, &["x.jpg", ".png or .f32"]);
    assert_one_line_error(&run(&["noise", "--kind", "gabor", "--a", "0", "-o", "x.png"], "1"), 2, &["gabor"]);
    assert!(!tmp.path().join("x.png").exists());
    // A flag of another kind would be ignored: it is refused, naming the kinds it belongs to.
    for (args, words) in [
        (&["--kind", "perlin", "--k", "2"][..], &["--k", "gabor", "perlin"][..]),
        (&["--kind", "gabor", "--octaves", "3"], &["--octaves", "fractal", "gabor"]),
        (&["--kind", "fbm", "--offset", "0.5"], &["--offset", "multifractal", "fbm"]),
        (&["--kind", "perlin", "--gain", "0.4"], &["--gain", "perlin"]),
        (&["--kind", "marble", "--isotropic"], &["--isotropic", "gabor", "marble"]),
    ] {
        let mut all = vec!["noise", "--size", "8", "-o", "x.png"];
        all.extend_from_slice(args);
        assert_one_line_error(&run(&all, "1"), 2, words);
        assert!(!tmp.path().join("x.png").exists());
    }
    // Octaves past the coordinates' precision are refused at once (#36: 10⁹ ran for good).
    for octaves in ["0", "33", "1000000000"] {
        let out = run(&["noise", "--kind", "fbm", "--size", "8", "--octaves", octaves, "-o", "x.png"], "1");
        assert_one_line_error(&out, 2, &["--octaves", octaves, "1 to 32"]);
        assert!(!tmp.path().join("x.png").exists());
    }
    // Gabor impulses beyond the documented maximum are refused (#36: they were capped).
    let out = run(&["noise", "--kind", "gabor", "--size", "8", "--impulses", "1e9", "-o", "x.png"], "1");
    assert_one_line_error(&out, 2, &["--impulses 1000000000", "at most 10000"]);
    assert!(!tmp.path().join("x.png").exists());
    // --range is a PNG's grey mapping: raw values have none.
    assert_one_line_error(
        &run(&["noise", "--size", "8", "--range", "-1,1", "-o", "x.f32"], "1"),
        2,
        &["x.f32", "--range"],
    );
    assert!(!tmp.path().join("x.f32").exists());
}

#[test]
fn noise_gabor_k_scales_and_wood_defaults_show_rings() {
    let tmp = temp_dir();
    let values = |args: &[&str], name: &str| -> Vec<f32> {
        let out = asperity(&[&["noise", "--size", "128", "-o", name][..], args].concat(), tmp.path());
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        std::fs::read(tmp.path().join(name))
            .unwrap()
            .chunks(4)
            .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
            .collect()
    };
    let one = values(&["--kind", "gabor", "--k", "1"], "k1.f32");
    let five = values(&["--kind", "gabor", "--k", "5"], "k5.f32");
    for (a, b) in one.iter().zip(&five) {
        assert!((b - 5.0 * a).abs() <= 1e-4 * (1.0 + b.abs()), "--k 5 gave {b}, not 5 × {a}");
    }
    // Wood (eq. 4.13) is the contour bands of one noise: at its defaults neighbouring
    // pixels mostly differ little (rings a few pixels wide, each rising over three
    // quarters and falling over the last), where white static would differ by a third of
    // the range on average.
    let wood = values(&["--kind", "wood"], "wood.f32");
    let mut steps: Vec<f32> = wood.chunks(128).flat_map(|row| row.windows(2).map(|w| (w[1] - w[0]).abs())).collect();
    steps.sort_by(f32::total_cmp);
    let median = steps[steps.len() / 2];
    assert!(median < 0.08, "median step between neighbouring wood pixels {median}: static, not rings");
}

#[test]
fn analyze_writes_every_property_and_a_json_report() {
    let dir = shared_meshes();
    let tmp = temp_dir();
    let input = dir.join("fandisk.off");
    let out = asperity(&["analyze", input.to_str().unwrap(), "-o", "f.ply", "--json"], tmp.path());
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let classes = &json["classes"];
    let total: u64 = ["face", "weak", "strong_edge", "corner"].iter().map(|k| classes[k].as_u64().unwrap()).sum();
    assert_eq!(total, 6475);
    assert!(classes["corner"].as_u64().unwrap() > 0);
    let mesh = asperity::io::read(&tmp.path().join("f.ply")).unwrap().mesh;
    for key in [
        "mean_curvature",
        "gaussian_curvature",
        "k1",
        "k2",
        "feature_class",
        "diffusion_x",
        "diffusion_y",
        "diffusion_z",
    ] {
        assert_eq!(mesh.scalars[key].len(), 6475, "{key}");
    }
    assert!(mesh.colors.is_some() && mesh.normals.is_some());
}

#[test]
fn terrain_streams_tiles_and_refuses_bad_sizes() {
    let tmp = temp_dir();
    let run = |args: &[&str]| asperity(args, tmp.path());
    let out = run(&["terrain", "--size", "129", "--seed", "3", "--sea-level", "0", "-o", "a.ply"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(
        run(&["terrain", "--size", "129", "--seed", "3", "--sea-level", "0", "--stream", "--band", "9", "-o", "b.ply"])
            .status
            .success()
    );
    assert_eq!(std::fs::read(tmp.path().join("a.ply")).unwrap(), std::fs::read(tmp.path().join("b.ply")).unwrap());
    for ext in ["png", "raw16", "f32", "obj"] {
        let out = run(&["terrain", "--size", "65", "-o", &format!("t.{ext}")]);
        assert!(out.status.success(), "{ext}: {}", String::from_utf8_lossy(&out.stderr));
    }
    assert_eq!(std::fs::metadata(tmp.path().join("t.raw16")).unwrap().len(), 65 * 65 * 2);
    let out = run(&["terrain", "--size", "129", "--tile", "1,2", "--tile-size", "33", "-o", "tile.ply"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(asperity::io::read(&tmp.path().join("tile.ply")).unwrap().mesh.vertex_count(), 33 * 33);
    assert_one_line_error(&run(&["terrain", "--size", "100", "-o", "x.ply"]), 2, &["2^n + 1"]);
    assert_one_line_error(
        &run(&["terrain", "--size", "129", "--tile", "9,9", "--tile-size", "33", "-o", "x.ply"]),
        2,
        &["tile 9,9"],
    );
    assert!(run(&["terrain", "--size", "65", "--seed", "2", "-o", "m.obj"]).status.success());
    assert!(
        run(&["terrain", "--size", "65", "--seed", "2", "--stream", "--band", "4", "-o", "s.obj"]).status.success()
    );
    assert_eq!(std::fs::read(tmp.path().join("m.obj")).unwrap(), std::fs::read(tmp.path().join("s.obj")).unwrap());
    assert_one_line_error(&run(&["terrain", "--size", "65", "-o", "x.stl"]), 2, &["x.stl"]);
    assert!(
        run(&["terrain", "--grid", "hex", "--size", "33", "--sea-level", "-0.2", "-o", "hex.obj"]).status.success()
    );
    assert_one_line_error(
        &run(&["terrain", "--grid", "hex", "--tile", "0,0", "--tile-size", "17", "-o", "x.ply"]),
        2,
        &["hexagonal"],
    );
    let out = run(&[
        "terrain", "--method", "dual", "--x", "2,0,0.3", "--y", "0,1,0", "--levels", "4", "--steps", "steps", "-o",
        "dual.ply",
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(asperity::io::read(&tmp.path().join("dual.ply")).unwrap().mesh.vertex_count(), 17 * 17);
    assert!(tmp.path().join("steps/level-04.ply").is_file());
    assert_one_line_error(
        &run(&["terrain", "--method", "dual", "--x", "1,0,0", "--y", "2,0,0", "-o", "x.ply"]),
        2,
        &["non-parallel"],
    );
    assert!(!tmp.path().join("x.ply").exists() && !tmp.path().join("x.stl").exists());
    // A flag another mode uses would be ignored here: refused, naming where it belongs.
    for (args, words) in [
        (&["--levels", "4", "-o", "x.ply"][..], &["--levels", "--method dual"][..]),
        (&["--x", "1,0,0", "-o", "x.ply"], &["--x", "--method dual"]),
        (&["--deterministic", "-o", "x.ply"], &["--deterministic", "dual"]),
        (&["--method", "dual", "--size", "65", "-o", "x.ply"], &["--size", "classic and smooth"]),
        (&["--method", "dual", "--width", "5", "-o", "x.ply"], &["--width", "classic and smooth"]),
        (&["--method", "dual", "--grid", "hex", "-o", "x.ply"], &["--grid"]),
        (&["--method", "dual", "--stream", "-o", "x.ply"], &["--stream"]),
        (&["--method", "smooth", "--hurst", "0.5", "-o", "x.ply"], &["--hurst", "smooth"]),
        (&["--method", "smooth", "--applet", "-o", "x.ply"], &["--applet", "classic"]),
        (&["--size", "65", "--band", "8", "-o", "x.ply"], &["--band", "--stream"]),
        (&["--size", "65", "--tile-size", "33", "-o", "x.ply"], &["--tile-size", "--tile"]),
        (&["--size", "65", "--range", "-1,1", "-o", "x.ply"], &["--range", "16-bit"]),
        (&["--size", "65", "--range", "-1,1", "-o", "x.f32"], &["--range", "16-bit"]),
        (&["--size", "65", "--peak-height", "2", "-o", "x.png"], &["--peak-height", "coloured"]),
        (&["--size", "65", "--colors", "0,0,1;0,1,0;1,1,0;1,0,0;1,1,1", "-o", "x.raw16"], &["--colors", "coloured"]),
    ] {
        let mut all = vec!["terrain"];
        all.extend_from_slice(args);
        assert_one_line_error(&run(&all), 2, words);
    }
    for name in ["x.ply", "x.f32", "x.png", "x.raw16"] {
        assert!(!tmp.path().join(name).exists(), "{name} written by a refused command");
    }
    // Seed 001's own controls: iterations k is size 2^k + 1, roughness r is H = log2 r,
    // max height is the highest point exactly; each refused with its equivalent.
    let f32s = |name: &str| -> Vec<f32> {
        std::fs::read(tmp.path().join(name))
            .unwrap()
            .chunks(4)
            .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
            .collect()
    };
    for (a, b) in [
        (&["--size", "65", "-o", "s.f32"][..], &["--iterations", "6", "-o", "i.f32"][..]),
        (&["--size", "65", "--hurst", "1", "-o", "s.f32"], &["--size", "65", "--roughness", "2", "-o", "i.f32"]),
    ] {
        assert!(run(&[&["terrain"][..], a].concat()).status.success());
        assert!(run(&[&["terrain"][..], b].concat()).status.success());
        assert_eq!(f32s("s.f32"), f32s("i.f32"), "{a:?} vs {b:?}");
    }
    for method in ["classic", "smooth"] {
        let out = run(&[
            "terrain",
            "--method",
            method,
            "--size",
            "65",
            "--max-height",
            "3",
            "--sea-level",
            "-1",
            "-o",
            "m.f32",
        ]);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let heights = f32s("m.f32");
        let top = heights.iter().copied().fold(f32::MIN, f32::max);
        assert!((top - 3.0).abs() < 1e-6, "{method}: highest point {top}, asked 3");
        assert!(heights.iter().all(|&h| h >= -1.0), "{method}: the sea clamp still holds");
    }
    for (args, words) in [
        (&["--size", "65", "--iterations", "6", "-o", "x.f32"][..], &["--iterations", "--size"][..]),
        (&["--hurst", "1", "--roughness", "2", "-o", "x.f32"], &["--roughness", "--hurst"]),
        (&["--max-height", "3", "--sigma", "2", "-o", "x.f32"], &["--max-height", "--sigma"]),
        (&["--max-height", "3", "--corners", "0,0,0,0", "-o", "x.f32"], &["--max-height", "--corners"]),
    ] {
        assert_usage_error(&run(&[&["terrain"][..], args].concat()), words, &["Usage:"]);
    }
    for (args, words) in [
        (&["--max-height", "3", "--stream", "-o", "x.f32"][..], &["--max-height", "whole grid"][..]),
        (&["--method", "smooth", "--roughness", "2", "-o", "x.f32"], &["--roughness", "smooth"]),
        (&["--roughness", "0", "-o", "x.f32"], &["--roughness", "positive"]),
        (&["--max-height", "-1", "-o", "x.f32"], &["max height", "positive"]),
        (&["--iterations", "40", "-o", "x.f32"], &["--iterations", "31"]),
    ] {
        assert_one_line_error(&run(&[&["terrain"][..], args].concat()), 2, words);
    }
    assert!(!tmp.path().join("x.f32").exists());
    // A streamed terrain's preview comes from the streamed rows: the same picture as the
    // whole grid's where it fits in 1024 pixels, every k-th point beyond (#24 item 4).
    assert!(run(&["terrain", "--size", "129", "-o", "w.f32", "--preview", "whole.png"]).status.success());
    assert!(
        run(&["terrain", "--size", "129", "--stream", "-o", "s.f32", "--preview", "streamed.png"]).status.success()
    );
    assert_eq!(
        std::fs::read(tmp.path().join("whole.png")).unwrap(),
        std::fs::read(tmp.path().join("streamed.png")).unwrap()
    );
    assert!(
        run(&["terrain", "--size", "2049", "--stream", "-o", "big.raw16", "--preview", "big.png"]).status.success()
    );
    let info = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(tmp.path().join("big.png")).unwrap()))
        .read_info()
        .unwrap()
        .info()
        .clone();
    assert_eq!((info.width, info.height), (683, 683), "2049 points at every 3rd");
    // Where they apply, the same flags are taken.
    for args in [
        &["--size", "65", "--range", "-1,1", "-o", "r.png"][..],
        &["--size", "65", "--peak-height", "2", "-o", "p.png", "--preview", "p-preview.png"],
        &["--size", "65", "--stream", "--band", "8", "-o", "b.f32"],
        &["--method", "dual", "--levels", "3", "--colors", "0,0,1;0,1,0;1,1,0;1,0,0;1,1,1", "-o", "d3.ply"],
    ] {
        let mut all = vec!["terrain"];
        all.extend_from_slice(args);
        let out = run(&all);
        assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
    }
}

#[test]
fn simplify_writes_the_base_levels_and_parametrization_and_reports_json() {
    let dir = shared_meshes();
    let tmp = temp_dir();
    let input = dir.join("elephant.off");
    let out = asperity(
        &[
            "simplify",
            input.to_str().unwrap(),
            "--target-vertices",
            "10%",
            "-o",
            "base.ply",
            "--levels-out",
            "levels",
            "--param-out",
            "param.ply",
            "--json",
        ],
        tmp.path(),
    );
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for key in ["input_vertices", "output_vertices", "levels", "seconds", "feature_vertices_kept", "hausdorff"] {
        assert!(json.get(key).is_some(), "missing {key}");
    }
    let levels = json["levels"].as_u64().unwrap();
    let base = asperity::io::read(&tmp.path().join("base.ply")).unwrap().mesh;
    assert_eq!(base.vertex_count() as u64, json["output_vertices"].as_u64().unwrap());
    assert!((0.0..0.2).contains(&json["hausdorff"].as_f64().unwrap()));
    assert_eq!(std::fs::read_dir(tmp.path().join("levels")).unwrap().count() as u64, levels + 1);
    let param = asperity::io::read(&tmp.path().join("param.ply")).unwrap().mesh;
    for key in ["level", "base_v0", "base_v1", "base_v2", "bary0", "bary1", "bary2"] {
        assert!(param.scalars.contains_key(key), "param.ply lacks {key}");
    }
    let bad = asperity(&["simplify", input.to_str().unwrap(), "--target-vertices", "0%", "-o", "x.ply"], tmp.path());
    assert_usage_error(&bad, &["--target-vertices", "above 0%"], &[]);
    assert!(!tmp.path().join("x.ply").exists());
}

#[test]
fn simplify_in_chunks_reaches_the_target_alike_at_any_thread_count() {
    // #40: --chunks K builds K parts in parallel and continues on their joined bases; the
    // base domain is the same bytes on one thread and on all.
    let tmp = temp_dir();
    let input = shared_meshes().join("bunny00.off");
    let run_with = |threads: &str, out: &str| {
        let out = Command::new(env!("CARGO_BIN_EXE_asperity"))
            .args(["--json", "simplify", input.to_str().unwrap(), "--target-vertices", "1%", "--chunks", "6"])
            .args(["--keep-features", "none", "-o", out, "--param-out", &format!("param-{out}")])
            .env("RAYON_NUM_THREADS", threads)
            .current_dir(tmp.path())
            .output()
            .unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        serde_json::from_slice::<serde_json::Value>(&out.stdout).unwrap()
    };
    let json = run_with("1", "one.ply");
    run_with("2", "two.ply");
    assert_eq!(json["output_vertices"].as_u64(), Some(377), "{json}");
    assert_eq!(json["target"]["reached"].as_bool(), Some(true), "{json}");
    assert!((0.0..0.02).contains(&json["hausdorff"].as_f64().unwrap()), "{json}");
    for (a, b) in [("one.ply", "two.ply"), ("param-one.ply", "param-two.ply")] {
        let read = |f: &str| std::fs::read(tmp.path().join(f)).unwrap();
        assert!(read(a) == read(b), "{a} and {b} differ");
    }
    let refused = [
        (
            &["--levels", "3"][..],
            "--chunks 4 needs a vertex target (--target-vertices) or an error bound (--max-error)",
        ),
        (&["--target-vertices", "100", "--levels", "3"][..], "--chunks 4 takes no level limit yet (--levels 3)"),
    ];
    for (extra, phrase) in refused {
        let mut args = vec!["simplify", input.to_str().unwrap(), "--chunks", "4", "-o", "x.ply"];
        args.extend_from_slice(extra);
        assert_usage_error(&asperity(&args, tmp.path()), &[phrase], &[]);
        assert!(!tmp.path().join("x.ply").exists());
    }
    let zero = asperity(&["simplify", input.to_str().unwrap(), "--chunks", "0", "-o", "x.ply"], tmp.path());
    assert_eq!(zero.status.code(), Some(2));
    // An error bound instead of a target: the build stops at it (the report says so).
    let bounded = Command::new(env!("CARGO_BIN_EXE_asperity"))
        .args(["--json", "simplify", input.to_str().unwrap(), "--max-error", "0.004", "--chunks", "4"])
        .args(["--keep-features", "none", "-o", "bounded.ply"])
        .current_dir(tmp.path())
        .output()
        .unwrap();
    assert!(bounded.status.success(), "{}", String::from_utf8_lossy(&bounded.stderr));
    let json = serde_json::from_slice::<serde_json::Value>(&bounded.stdout).unwrap();
    let vertices = json["output_vertices"].as_u64().unwrap();
    assert!((500..1000).contains(&vertices), "{json}");
    assert!(json["hausdorff"].as_f64().unwrap() <= 0.005, "{json}");
}

#[test]
fn simplify_without_the_intersection_guard_is_asked_for_by_name() {
    let tmp = temp_dir();
    let input = tmp.path().join("pancake.off");
    asperity::io::write(&crate::common::thin_pancake(), &input, Default::default()).unwrap();
    let intersecting_pairs = |extra: &[&str], dir: &str| {
        let mut args = vec!["simplify", "pancake.off", "--target-vertices", "20", "--keep-features", "none"];
        args.extend(["-o", "base.ply", "--levels-out", dir]);
        args.extend(extra);
        let out = asperity(&args, tmp.path());
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let mut pairs = 0;
        for entry in std::fs::read_dir(tmp.path().join(dir)).unwrap() {
            let level = asperity::io::read(&entry.unwrap().path()).unwrap().mesh;
            pairs += asperity::ffi::self_intersections(&level).unwrap().len();
        }
        pairs
    };
    assert_eq!(intersecting_pairs(&[], "guarded"), 0);
    assert!(intersecting_pairs(&["--no-intersection-guard"], "unguarded") > 0);
}

#[test]
fn detail_without_a_recipe_gives_the_input_back() {
    let dir = shared_meshes();
    let tmp = temp_dir();
    let input = dir.join("femur.off");
    let out = asperity(&["detail", input.to_str().unwrap(), "-o", "back.off", "--json"], tmp.path());
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["positions_exact"], true);
    assert_eq!(json["faces_matched"].as_f64(), Some(1.0));
    let original = asperity::io::read(&input).unwrap().mesh;
    let back = asperity::io::read(&tmp.path().join("back.off")).unwrap().mesh;
    assert_eq!(back.positions, original.positions);
}

#[test]
fn compare_runs_every_method_to_the_same_budget() {
    let dir = shared_meshes();
    let tmp = temp_dir();
    let out = asperity(
        &["compare", dir.join("elephant.off").to_str().unwrap(), "--target-vertices", "600", "--json"],
        tmp.path(),
    );
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(report["target_vertices"], 600);
    let rows = report["at_target"].as_array().unwrap();
    let methods: Vec<&str> = rows.iter().map(|r| r["method"].as_str().unwrap()).collect();
    assert_eq!(methods, ["asperity", "openmesh", "cgal", "meshoptimizer"]);
    for r in rows {
        let v = r["vertices"].as_u64().unwrap();
        assert!((560..=640).contains(&v), "{r}");
        for key in ["seconds", "hausdorff", "rms", "min_angle_deg", "features_kept"] {
            assert!(r[key].is_number(), "{key} in {r}");
        }
        assert!(r["hausdorff"].as_f64().unwrap() < 0.1, "{r}");
    }
}

#[test]
fn the_cli_reference_in_docs_is_current() {
    let tmp = temp_dir();
    let out = asperity(&["reference"], tmp.path());
    assert!(out.status.success());
    let generated = String::from_utf8(out.stdout).unwrap();
    let committed = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/cli.md")).unwrap();
    assert!(generated == committed, "docs/cli.md is stale: run `asperity reference > docs/cli.md`");
    for command in
        ["render", "terrain", "simplify", "detail", "compare", "noise", "clouds", "convert", "info", "analyze"]
    {
        assert!(generated.contains(&format!("## asperity {command}")), "{command}");
    }
}

#[test]
fn every_subcommand_prints_a_json_report() {
    let tmp = temp_dir();
    std::fs::write(
        tmp.path().join("tri.off"),
        "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n",
    )
    .unwrap();
    let runs: [&[&str]; 8] = [
        &["info", "tri.off"],
        &["convert", "tri.off", "tri.glb"],
        &["analyze", "tri.off", "-o", "a.ply"],
        &["render", "tri.off", "-o", "r.png", "--size", "64,48"],
        &["noise", "--size", "16", "-o", "n.png"],
        &["clouds", "--size", "17", "-o", "c.png"],
        &["terrain", "--size", "17", "-o", "t.ply"],
        &["terrain", "--method", "dual", "--levels", "3", "-o", "d.ply"],
    ];
    for args in runs {
        let mut with_json = args.to_vec();
        with_json.push("--json");
        let out = asperity(&with_json, tmp.path());
        assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
        let report: serde_json::Value = serde_json::from_slice(&out.stdout)
            .unwrap_or_else(|e| panic!("{args:?}: not JSON ({e}): {}", String::from_utf8_lossy(&out.stdout)));
        assert!(report.is_object(), "{args:?}");
        // --quiet prints nothing at all.
        let mut quiet = args.to_vec();
        quiet.push("--quiet");
        let out = asperity(&quiet, tmp.path());
        assert!(out.status.success() && out.stdout.is_empty() && out.stderr.is_empty(), "{args:?}");
    }
}

#[test]
fn a_closed_stdout_ends_the_program_quietly() {
    use std::os::fd::FromRawFd;
    use std::os::unix::process::ExitStatusExt;
    // A pipe whose reading end is already closed, as after `asperity … | head` has exited.
    let mut fds = [0i32; 2];
    assert_eq!(unsafe { libc::pipe(fds.as_mut_ptr()) }, 0);
    unsafe { libc::close(fds[0]) };
    let writer = unsafe { std::fs::File::from_raw_fd(fds[1]) };
    let input = shared_meshes().join("eight.off");
    let out = Command::new(env!("CARGO_BIN_EXE_asperity"))
        .args(["info", "--json", input.to_str().unwrap()])
        .stdout(writer)
        .output()
        .unwrap();
    assert!(out.stderr.is_empty(), "{}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(out.status.signal(), Some(libc::SIGPIPE), "{:?}", out.status);
}

#[test]
fn a_terrain_that_cannot_fit_in_memory_is_refused_before_allocating() {
    // #24 item 4: under a 1 GB address-space limit a whole 16385² heightmap used to abort
    // with Rust's allocation-failure message; it is refused in one line, nothing written.
    use std::os::unix::process::CommandExt;
    let tmp = temp_dir();
    let limited = |args: &[&str]| {
        let mut command = Command::new(env!("CARGO_BIN_EXE_asperity"));
        command.args(args).current_dir(tmp.path());
        // SAFETY: setrlimit is async-signal-safe; it only lowers this child's own limit.
        unsafe {
            command.pre_exec(|| {
                let limit = libc::rlimit { rlim_cur: 1 << 30, rlim_max: 1 << 30 };
                if libc::setrlimit(libc::RLIMIT_AS, &limit) == 0 {
                    Ok(())
                } else {
                    Err(std::io::Error::last_os_error())
                }
            });
        }
        command.output().unwrap()
    };
    let out = limited(&["terrain", "--size", "16385", "-o", "big.png"]);
    assert_one_line_error(&out, 2, &["needs about", "in memory", "--stream", "--tile"]);
    assert!(!tmp.path().join("big.png").exists());
    let streamed = limited(&["terrain", "--size", "4097", "--stream", "-o", "streamed.raw16"]);
    assert!(streamed.status.success(), "{}", String::from_utf8_lossy(&streamed.stderr));
    // #36: the documented largest picture, and a smoke plume of 10^9 frames, aborted on
    // their allocation; both are refused by estimate.
    let input = shared_meshes().join("eight.off");
    let out = limited(&["render", input.to_str().unwrap(), "--size", "16384,16384", "-o", "huge.png"]);
    assert_one_line_error(&out, 2, &["16384x16384", "needs about", "in memory", "--size", "--samples"]);
    assert!(!tmp.path().join("huge.png").exists());
    let small = limited(&["render", input.to_str().unwrap(), "--size", "64,64", "-o", "small.png"]);
    assert!(small.status.success(), "{}", String::from_utf8_lossy(&small.stderr));
    let out = limited(&["smoke", "--frames", "1000000000", "--resolution", "24", "-o", "plume.glb"]);
    assert_one_line_error(&out, 2, &["1000000000 frames", "needs about", "--frames"]);
    assert!(!tmp.path().join("plume.glb").exists());
}

#[test]
fn feature_vertices_chooses_between_lines_and_the_literal_rule_and_needs_features() {
    // #19: --feature-vertices changes what simplify keeps, and is refused (naming the
    // flag it needs) where no vertex is a feature; compare takes it too.
    let tmp = temp_dir();
    let fandisk = shared_meshes().join("fandisk.off");
    let input = fandisk.to_str().unwrap();
    let kept = |extra: &[&str]| {
        let mut args = vec!["simplify", input, "--target-vertices", "1000", "-o", "base.ply", "--json"];
        args.extend(extra);
        let out = asperity(&args, tmp.path());
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        json["feature_vertices_kept"].as_u64().unwrap()
    };
    let (along, literal) = (kept(&[]), kept(&["--feature-vertices", "keep"]));
    assert_eq!(along, kept(&["--feature-vertices", "along-lines"]), "along-lines is the default");
    assert!(along < literal, "simplified along their lines, fewer feature vertices stay: {along} vs {literal}");
    for command in [
        vec!["simplify", input, "--keep-features", "none", "--feature-vertices", "keep", "-o", "x.ply"],
        vec!["compare", input, "--keep-features", "none", "--feature-vertices", "keep"],
    ] {
        let out = asperity(&command, tmp.path());
        assert_one_line_error(&out, 2, &["--feature-vertices", "--keep-features corners, strong or all"]);
    }
    assert!(!tmp.path().join("x.ply").exists());
}

#[test]
fn flags_that_would_be_ignored_are_refused() {
    // Every flag does something or is refused, naming where it applies (#24 item 11).
    let tmp = temp_dir();
    let input = shared_meshes().join("eight.off");
    let input = input.to_str().unwrap();
    for (args, words) in [
        (
            &["render", input, "-o", "x.png", "--mode", "points", "--crease", "30"][..],
            &["--crease", "faces", "points"][..],
        ),
        (&["render", input, "-o", "x.png", "--mode", "wireframe", "--edges"], &["--edges", "faces", "wireframe"]),
        (&["convert", input, "x.obj", "--ascii"], &["x.obj", "--ascii", ".ply and .stl"]),
        (&["convert", input, "x.glb", "--ascii"], &["x.glb", "--ascii"]),
        (&["analyze", input, "-o", "x.off", "--ascii"], &["x.off", "--ascii"]),
    ] {
        assert_one_line_error(&asperity(args, tmp.path()), 2, words);
    }
    for name in ["x.png", "x.obj", "x.glb", "x.off"] {
        assert!(!tmp.path().join(name).exists(), "{name} written by a refused command");
    }
    for args in [
        &["render", input, "-o", "f.png", "--size", "64,48", "--crease", "30", "--edges"][..],
        &["convert", input, "a.ply", "--ascii"],
        &["convert", input, "a.stl", "--ascii"],
    ] {
        let out = asperity(args, tmp.path());
        assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
    }
}

#[test]
fn long_stages_show_progress_bars_on_a_terminal_only() {
    // #24 item 14: position, rate and time left on a terminal; nothing with --quiet or
    // --json, or when stderr is not a terminal. `script` (util-linux, in every Debian)
    // gives the command a terminal.
    let tmp = temp_dir();
    let bin = env!("CARGO_BIN_EXE_asperity");
    let on_terminal = |args: &str| -> String {
        let out = Command::new("script")
            .args(["-qec", &format!("{bin} {args}"), "/dev/null"])
            .current_dir(tmp.path())
            .output()
            .expect("`script` (util-linux) runs a command on a terminal; install bsdutils");
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        String::from_utf8_lossy(&out.stdout).into_owned()
    };
    let shown = on_terminal("terrain --size 8193 --stream -o t.raw16");
    assert!(shown.contains("terrain [") && shown.contains("left") && shown.contains("/8193"), "{shown}");
    for quiet in ["--quiet", "--json"] {
        let shown = on_terminal(&format!("{quiet} terrain --size 4097 --stream -o q.raw16"));
        assert!(!shown.contains("left"), "{quiet}: {shown}");
    }
    let piped = asperity(&["terrain", "--size", "4097", "--stream", "-o", "p.raw16"], tmp.path());
    assert!(!String::from_utf8_lossy(&piped.stderr).contains("left"), "no bars when stderr is not a terminal");
}

#[test]
fn a_target_that_would_remove_nothing_or_means_nothing_is_refused() {
    // #36: `--target-vertices 0` acted as no target and 10⁹ removed nothing, both exit 0.
    let tmp = temp_dir();
    asperity::io::write(&asperity::mesh::primitives::icosphere(1.0, 2), &tmp.path().join("s.off"), Default::default())
        .unwrap();
    for (target, words) in [
        ("0", &["--target-vertices", "'0'", "at least 1"][..]),
        ("1000000000", &["--target-vertices 1000000000", "162 vertices", "nothing would be removed"]),
        ("163", &["--target-vertices 163", "162 vertices"]),
    ] {
        for args in [
            &["simplify", "s.off", "--target-vertices", target, "-o", "b.ply"][..],
            &["compare", "s.off", "--target-vertices", target],
        ] {
            let out = asperity(args, tmp.path());
            let stderr = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
            // The message is the first line (a usage error adds clap's hint after a blank line).
            let first = stderr.lines().next().unwrap_or("");
            for word in words {
                assert!(first.contains(word), "{args:?}: `{word}` in {stderr}");
            }
            assert!(!tmp.path().join("b.ply").exists());
        }
    }
    // The input's own count and 100 % remove nothing, as asked.
    for target in ["162", "100%"] {
        let out = asperity(&["simplify", "s.off", "--target-vertices", target, "-o", "b.ply"], tmp.path());
        assert!(out.status.success(), "{target}: {}", String::from_utf8_lossy(&out.stderr));
    }
}

#[test]
fn overflowing_octaves_negative_sizes_and_shared_output_paths_are_usage_errors() {
    let tmp = temp_dir();
    // #36: a gain whose powers overflow over the octaves was an internal error (exit 1).
    let out = asperity(&["noise", "--kind", "fbm", "--gain", "1e300", "--size", "8", "-o", "g.png"], tmp.path());
    assert_one_line_error(&out, 2, &["gain 1e300", "overflow"]);
    let out = asperity(&["noise", "--kind", "fbm", "--lacunarity", "1e300", "--size", "8", "-o", "g.png"], tmp.path());
    assert_one_line_error(&out, 2, &["lacunarity 1e300", "overflow"]);
    assert!(!tmp.path().join("g.png").exists());
    // A negative number is a value of its flag, refused as such (it was "unexpected argument").
    let out = asperity(&["noise", "--size", "-5", "-o", "g.png"], tmp.path());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.lines().next().unwrap_or("").contains("invalid value '-5' for '--size"), "{stderr}");
    // Two outputs at one path: one would overwrite the other.
    let out = asperity(&["terrain", "--size", "33", "-o", "t.png", "--preview", "./t.png"], tmp.path());
    assert_one_line_error(&out, 2, &["-o and --preview", "t.png"]);
    assert!(!tmp.path().join("t.png").exists());
    asperity::io::write(&asperity::mesh::primitives::icosphere(1.0, 2), &tmp.path().join("s.off"), Default::default())
        .unwrap();
    let out =
        asperity(&["simplify", "s.off", "--target-vertices", "50", "-o", "b.ply", "--param-out", "b.ply"], tmp.path());
    assert_one_line_error(&out, 2, &["-o and --param-out", "b.ply"]);
    assert!(!tmp.path().join("b.ply").exists());
}

#[test]
fn a_command_whose_writes_fail_part_way_leaves_no_file_and_no_folder() {
    // #36 item 4: on a full disk `simplify --levels-out` and `smoke` (a file per frame) left
    // the files written before the failure. A file-size limit makes the large writes fail
    // (EFBIG, with SIGXFSZ ignored) after the small ones succeeded.
    use std::os::unix::process::CommandExt;
    let tmp = temp_dir();
    let limited = |args: &[&str], bytes: u64| {
        let mut command = Command::new(env!("CARGO_BIN_EXE_asperity"));
        command.args(args).current_dir(tmp.path());
        // SAFETY: setrlimit and signal are async-signal-safe; they change this child only.
        unsafe {
            command.pre_exec(move || {
                libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
                let limit = libc::rlimit { rlim_cur: bytes, rlim_max: bytes };
                if libc::setrlimit(libc::RLIMIT_FSIZE, &limit) == 0 {
                    Ok(())
                } else {
                    Err(std::io::Error::last_os_error())
                }
            });
        }
        command.output().unwrap()
    };
    let input = shared_meshes().join("fandisk.off");
    // The base (a few kB at 200 vertices) is written first and fits; the finest level does not.
    let simplify = [
        "simplify",
        input.to_str().unwrap(),
        "--target-vertices",
        "200",
        "-o",
        "base.ply",
        "--levels-out",
        "levels/all",
    ];
    let out = limited(&simplify, 64 << 10);
    assert_one_line_error(&out, 2, &["levels/all/level_"]);
    // These frames are 265, 289 and 277 kB: the first fits, the second does not.
    let smoke = ["smoke", "--frames", "3", "--warmup", "41", "--resolution", "20", "-o", "plume.ply"];
    let out = limited(&smoke, 280_000);
    assert_eq!(out.status.code(), Some(2), "{}", String::from_utf8_lossy(&out.stderr));
    let left: Vec<_> = std::fs::read_dir(tmp.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert!(left.is_empty(), "left behind: {left:?}");
    // Without the limit both write everything.
    let out = limited(&simplify, u64::MAX);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(tmp.path().join("base.ply").is_file() && tmp.path().join("levels/all/level_00.ply").is_file());
}

#[test]
fn messages_name_the_parameter_or_step_that_went_too_far() {
    use std::os::unix::process::CommandExt;
    let tmp = temp_dir();
    // #36: `--sigma 1e308` ended in "vertex 1 has a non-finite coordinate", naming nothing.
    let out = asperity(&["terrain", "--sigma", "1e308", "--size", "33", "-o", "t.obj"], tmp.path());
    assert_one_line_error(&out, 2, &["terrain heights could reach", "sigma 1e308", "lower sigma"]);
    // 100000 erosion iterations on a whole grid need no halo: they were refused as 8965.8 GB.
    let out = asperity(
        &["terrain", "--size", "9", "--erode", "thermal", "--erode-iterations", "100000", "-o", "e.png"],
        tmp.path(),
    );
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    // A grid the tiles cannot cover names the sizes they can.
    let out = asperity(
        &["terrain", "plan", "--preset", "unreal", "--size", "2000", "--tile-size", "505", "-o", "p"],
        tmp.path(),
    );
    assert_one_line_error(&out, 2, &["tiles of 505 points do not cover a grid of 2000", "nearest sizes 1513 or 2017"]);
    assert!(!tmp.path().join("p").exists());
    // A recipe step that throws vertices past any mesh names the step.
    let recipe = "[hierarchy]\ntarget_vertices = \"500\"\n\n[[step]]\nop = \"noise\"\nlevel = -1\n\
                  noise = { kind = \"perlin\", amplitude = 1e300, frequency = 2.0 }\n";
    std::fs::write(tmp.path().join("far.toml"), recipe).unwrap();
    let out = asperity(&["detail", "builtin:sphere", "--recipe", "far.toml", "-o", "far.ply"], tmp.path());
    assert_one_line_error(
        &out,
        2,
        &["recipe step 1: the noise step at level", "amplitude, scale or frequency is too large"],
    );
    // A flag replaces its recipe key, which is then not read: a table target above the
    // input's count was refused though --target-vertices replaced it.
    std::fs::write(tmp.path().join("big.toml"), "[hierarchy]\ntarget_vertices = 99999\n").unwrap();
    let out = asperity(
        &["detail", "builtin:torus", "--recipe", "big.toml", "--target-vertices", "300", "-o", "t.ply"],
        tmp.path(),
    );
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    std::fs::remove_file(tmp.path().join("t.ply")).unwrap();
    std::fs::remove_file(tmp.path().join("big.toml")).unwrap();
    // Twelve subdivisions of the whole sphere are refused by estimate, before the memory runs out.
    let step = "[[step]]\nop = \"subdivide\"\nlevel = -1\nsubdivide = { steps = 8 }\n\n";
    std::fs::write(
        tmp.path().join("deep.toml"),
        format!("[hierarchy]\ntarget_vertices = \"500\"\n\n{}", step.repeat(12)),
    )
    .unwrap();
    let mut command = Command::new(env!("CARGO_BIN_EXE_asperity"));
    command.args(["detail", "builtin:sphere", "--recipe", "deep.toml", "-o", "deep.ply"]).current_dir(tmp.path());
    // SAFETY: setrlimit is async-signal-safe; it only lowers this child's own limit.
    unsafe {
        command.pre_exec(|| {
            let limit = libc::rlimit { rlim_cur: 1 << 30, rlim_max: 1 << 30 };
            if libc::setrlimit(libc::RLIMIT_AS, &limit) == 0 { Ok(()) } else { Err(std::io::Error::last_os_error()) }
        });
    }
    let out = command.output().unwrap();
    assert_one_line_error(&out, 2, &["recipe step", "subdividing", "needs about", "subdivide fewer times"]);
    let left: Vec<_> = std::fs::read_dir(tmp.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(left.len(), 3, "only e.png and the two recipes: {left:?}");
}

#[test]
fn a_memory_budget_refuses_work_before_it_starts() {
    // #36 item 1: one budget for every command, `--max-memory`, checked by each estimate.
    let tmp = temp_dir();
    let fandisk = shared_meshes().join("fandisk.off");
    let out = asperity(&["--max-memory", "1M", "terrain", "--size", "1025", "-o", "t.png"], tmp.path());
    assert_one_line_error(
        &out,
        2,
        &["a 1025x1025 terrain built whole needs about", "the --max-memory budget of 1.0 MiB"],
    );
    let out = asperity(&["simplify", fandisk.to_str().unwrap(), "--max-memory", "2M", "-o", "b.ply"], tmp.path());
    assert_one_line_error(&out, 2, &["a hierarchy of 12946 triangles needs about", "--max-memory budget"]);
    let out = asperity(&["convert", fandisk.to_str().unwrap(), "f.glb"], tmp.path());
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let out = asperity(&["--max-memory", "100K", "info", "f.glb"], tmp.path());
    assert_one_line_error(&out, 2, &["f.glb", "reading 1 mesh instance(s) drawing 6475 vertices and 12946 triangles"]);
    let out = asperity(&["--max-memory", "lots", "info", "f.glb"], tmp.path());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.lines().next().unwrap_or("").contains("invalid value 'lots' for '--max-memory"), "{stderr}");
    // Within the budget, the same work runs.
    let out = asperity(
        &["--max-memory", "1G", "simplify", fandisk.to_str().unwrap(), "--target-vertices", "1000", "-o", "b.ply"],
        tmp.path(),
    );
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
}

/// `--param-out` is written as PLY vertex properties: another format, which would drop
/// them, is refused before anything is built or written (it was written without them).
#[test]
fn a_parametrization_in_a_format_without_vertex_properties_is_refused() {
    let tmp = temp_dir();
    let input = shared_meshes().join("eight.off");
    for param in ["p.obj", "p.off", "p.stl", "p.glb"] {
        let args =
            ["simplify", input.to_str().unwrap(), "--target-vertices", "10%", "-o", "b.ply", "--param-out", param];
        let out = asperity(&args, tmp.path());
        assert_eq!(out.status.code(), Some(2), "{param}: {}", String::from_utf8_lossy(&out.stderr));
        assert!(String::from_utf8_lossy(&out.stderr).contains("the output must end in .ply"), "{param}");
        assert!(!tmp.path().join("b.ply").exists() && !tmp.path().join(param).exists(), "{param} left a file");
    }
}
