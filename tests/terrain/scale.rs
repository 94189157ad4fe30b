//! Terrain at world scale (#23): plans run by real job runners (GNU parallel, xargs, the
//! Slurm and Kubernetes examples' command lines), the GDAL mosaic, whole-file formats,
//! engine presets and sidecars, and thermal erosion identical in tiles.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use asperity::terrain::erosion::steepest_slope_degrees;
use asperity::terrain::{Rect, TerrainParams, ThermalErosion, heights, tile_rect};

use crate::common::temp_dir;

fn asperity<S: AsRef<std::ffi::OsStr> + std::fmt::Debug>(args: &[S], cwd: &Path) -> Output {
    let out = Command::new(env!("CARGO_BIN_EXE_asperity")).args(args).current_dir(cwd).output().expect("run asperity");
    assert!(out.status.success(), "asperity {args:?}: {}", String::from_utf8_lossy(&out.stderr));
    out
}

/// A Debian tool the test needs, or a failure naming the package and the script that
/// installs it.
fn tool(name: &str, package: &str) -> PathBuf {
    let found = std::env::var_os("PATH")
        .and_then(|paths| std::env::split_paths(&paths).map(|p| p.join(name)).find(|p| p.is_file()));
    found.unwrap_or_else(|| {
        panic!("`{name}` is missing: install Debian's {package} (scripts/install-deps.sh --test does, as `make test`)")
    })
}

/// A folder holding `asperity` for job runners that find it on the PATH, and that PATH.
fn path_with_asperity(dir: &Path) -> String {
    let bin = dir.join("bin");
    std::fs::create_dir_all(&bin).unwrap();
    let link = bin.join("asperity");
    if !link.exists() {
        std::os::unix::fs::symlink(env!("CARGO_BIN_EXE_asperity"), &link).unwrap();
    }
    format!("{}:{}", bin.display(), std::env::var("PATH").unwrap_or_default())
}

fn shell(script: &str, cwd: &Path) {
    let out = Command::new("bash")
        .args(["-c", script])
        .current_dir(cwd)
        .env("PATH", path_with_asperity(cwd))
        .output()
        .expect("run bash");
    assert!(out.status.success(), "{script}: {}", String::from_utf8_lossy(&out.stderr));
}

/// The plan's tiles (index, output, command) from its manifest.
fn planned_tiles(dir: &Path) -> Vec<(u64, String, Vec<String>)> {
    let plan: serde_json::Value = serde_json::from_slice(&std::fs::read(dir.join("plan.json")).unwrap()).unwrap();
    plan["tiles"]
        .as_array()
        .unwrap()
        .iter()
        .map(|t| {
            let command = t["command"].as_array().unwrap().iter().map(|c| c.as_str().unwrap().to_string()).collect();
            (t["index"].as_u64().unwrap(), t["output"].as_str().unwrap().to_string(), command)
        })
        .collect()
}

/// The whole grid assembled from a plan's headerless tiles of `bytes` bytes per sample.
fn assemble(dir: &Path, size: usize, tile: usize, bytes: usize) -> Vec<u8> {
    let per_side = (size - 1) / (tile - 1);
    let mut whole = vec![0u8; size * size * bytes];
    for (index, output, _) in planned_tiles(dir) {
        let (ti, tj) = (index as usize % per_side, index as usize / per_side);
        let data = std::fs::read(dir.join(&output)).unwrap_or_else(|e| panic!("{output}: {e}"));
        assert_eq!(data.len(), tile * tile * bytes, "{output}");
        for r in 0..tile {
            let y = tj * (tile - 1) + r;
            let x = ti * (tile - 1);
            whole[(y * size + x) * bytes..(y * size + x + tile) * bytes]
                .copy_from_slice(&data[r * tile * bytes..(r + 1) * tile * bytes]);
        }
    }
    whole
}

const GENERATION: [&str; 8] = ["--size", "129", "--seed", "5", "--erode", "thermal", "--erode-iterations", "12"];

/// `asperity terrain` with [`GENERATION`], written to `output`.
fn whole_args(output: &str) -> Vec<String> {
    ["terrain"].iter().chain(&GENERATION).chain(&["-o", output]).map(|s| s.to_string()).collect()
}

/// `asperity terrain plan` with [`GENERATION`] in 33² tiles of `format` into `dir`.
fn plan_args(format: &str, dir: &str) -> Vec<String> {
    let tail = ["--tile-size", "33", "--format", format, "-o", dir];
    ["terrain", "plan"].iter().chain(&GENERATION).chain(&tail).map(|s| s.to_string()).collect()
}

#[test]
fn planned_tiles_through_gnu_parallel_and_xargs_equal_the_whole_grid() {
    let tmp = temp_dir();
    let dir = tmp.path();
    tool("parallel", "parallel");
    tool("xargs", "findutils");
    asperity(&whole_args("whole.raw16"), dir);
    asperity(&whole_args("whole.f32"), dir);
    for (format, runner, bytes) in [("raw16", "parallel -j 2", 2), ("f32", "xargs -P 2 -I{}", 4)] {
        let plan = format!("plan-{format}");
        asperity(&plan_args(format, &plan), dir);
        let tiles = planned_tiles(&dir.join(&plan));
        assert_eq!(tiles.len(), 16);
        // Each tile's command exactly as the manifest gives it.
        let lines: Vec<String> = tiles.iter().map(|(_, _, command)| command.join(" ")).collect();
        std::fs::write(dir.join("commands"), lines.join("\n") + "\n").unwrap();
        let script = if runner.starts_with("parallel") {
            format!("{runner} < commands")
        } else {
            format!("{runner} sh -c '{{}}' < commands")
        };
        shell(&script, dir);
        let whole = std::fs::read(dir.join(format!("whole.{format}"))).unwrap();
        assert!(
            assemble(&dir.join(&plan), 129, 33, bytes) == whole,
            "{format} tiles by {runner} differ from the whole grid"
        );
    }
}

#[test]
fn the_slurm_and_kubernetes_examples_run_the_plan_unchanged() {
    let tmp = temp_dir();
    let dir = tmp.path();
    tool("parallel", "parallel");
    let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scale-out");
    asperity(&whole_args("whole.raw16"), dir);
    // Slurm: the array script as sbatch would run it, task K given SLURM_ARRAY_TASK_ID=K.
    asperity(&plan_args("raw16", "slurm"), dir);
    let slurm = examples.join("slurm-array.sh");
    shell(&format!("seq 0 15 | parallel -j 2 'SLURM_ARRAY_TASK_ID={{}} PLAN_DIR=slurm bash {}'", slurm.display()), dir);
    let whole = std::fs::read(dir.join("whole.raw16")).unwrap();
    assert!(assemble(&dir.join("slurm"), 129, 33, 2) == whole, "the Slurm array's tiles differ from the whole grid");
    // Kubernetes: the Indexed Job's container command, pod K given JOB_COMPLETION_INDEX=K,
    // with the plan's volume mounted where the manifest says.
    let manifest = std::fs::read_to_string(examples.join("kubernetes-indexed-job.yaml")).unwrap();
    let line = manifest.lines().find(|l| l.trim_start().starts_with("command:")).expect("the Job names a command");
    let command: Vec<String> = serde_json::from_str(line.trim_start().trim_start_matches("command:").trim()).unwrap();
    let mount = manifest.lines().find_map(|l| l.trim().strip_prefix("mountPath:")).unwrap().trim().to_string();
    assert!(manifest.contains("completionMode: Indexed") && manifest.contains("completions: 16"));
    let planned = command.last().unwrap().replacen(&mount, "plans", 1);
    std::fs::create_dir_all(dir.join("plans")).unwrap();
    asperity(&plan_args("raw16", &planned), dir);
    let command = [&command[..command.len() - 1], std::slice::from_ref(&planned)].concat().join(" ");
    shell(&format!("seq 0 15 | parallel -j 2 'JOB_COMPLETION_INDEX={{}} {command}'"), dir);
    assert!(assemble(&dir.join(&planned), 129, 33, 2) == whole, "the Indexed Job's tiles differ from the whole grid");
    // The GNU parallel example.
    asperity(&plan_args("raw16", "local"), dir);
    shell(&format!("PLAN_DIR=local bash {}", examples.join("parallel.sh").display()), dir);
    assert!(assemble(&dir.join("local"), 129, 33, 2) == whole);
}

#[test]
fn the_mosaic_opens_in_gdal_and_translates_to_the_whole_grid() {
    let tmp = temp_dir();
    let dir = tmp.path();
    let gdal_translate = tool("gdal_translate", "gdal-bin");
    let gdalinfo = tool("gdalinfo", "gdal-bin");
    let generation = ["--size", "65", "--seed", "9", "--sea-level", "-0.5"];
    let with = |extra: &[&str]| -> Vec<String> { generation.iter().chain(extra).map(|s| s.to_string()).collect() };
    asperity(&[vec!["terrain".to_string()], with(&["-o", "whole.raw16"])].concat(), dir);
    asperity(&[vec!["terrain".to_string()], with(&["-o", "whole.f32"])].concat(), dir);
    for (format, whole) in
        [("png", "whole.raw16"), ("raw16", "whole.raw16"), ("tif", "whole.f32"), ("f32", "whole.f32")]
    {
        let plan = format!("plan-{format}");
        let args = with(&["--tile-size", "17", "--format", format, "-o", &plan]);
        asperity(&[vec!["terrain".to_string(), "plan".to_string()], args].concat(), dir);
        for k in 0..16 {
            asperity(&["terrain", "--plan", &plan, "--tile-index", &k.to_string(), "-q"], dir);
        }
        let vrt = dir.join(&plan).join("mosaic.vrt");
        let info = Command::new(&gdalinfo).arg(&vrt).output().unwrap();
        let text = String::from_utf8_lossy(&info.stdout);
        assert!(info.status.success() && text.contains("Size is 65, 65"), "gdalinfo {format}: {text}");
        let kind = if format == "png" || format == "raw16" { "Type=UInt16" } else { "Type=Float32" };
        assert!(text.contains(kind), "{format}: {text}");
        if kind == "Type=UInt16" {
            assert!(text.contains("Offset:") && text.contains("Scale:"), "16-bit mosaics map back to heights: {text}");
        }
        let out = dir.join(format!("{format}.bin"));
        let status = Command::new(&gdal_translate).args(["-q", "-of", "ENVI"]).arg(&vrt).arg(&out).status().unwrap();
        assert!(status.success());
        assert!(
            std::fs::read(&out).unwrap() == std::fs::read(dir.join(whole)).unwrap(),
            "{format}: the mosaic differs from the whole grid"
        );
    }
}

#[test]
fn a_rerun_skips_complete_tiles_and_redoes_stale_or_broken_ones() {
    let tmp = temp_dir();
    let dir = tmp.path();
    let plan = |seed: &str| {
        asperity(&["terrain", "plan", "--size", "33", "--tile-size", "17", "--seed", seed, "-o", "p"], dir)
    };
    let run = |k: &str| {
        String::from_utf8_lossy(&asperity(&["terrain", "--plan", "p", "--tile-index", k], dir).stdout).into_owned()
    };
    plan("1");
    assert!(!run("3").contains("already complete"));
    let tile = dir.join("p/tiles/terrain_x1_y1.png");
    let first = std::fs::read(&tile).unwrap();
    assert!(run("3").contains("already complete"), "a complete tile is skipped");
    // A tile cut short (a killed process cannot leave one, but a copy can) is made again.
    std::fs::write(&tile, &first[..first.len() / 2]).unwrap();
    assert!(!run("3").contains("already complete"));
    assert_eq!(std::fs::read(&tile).unwrap(), first);
    // A new plan in the same folder (another seed) makes new tiles.
    plan("2");
    assert!(!run("3").contains("already complete"), "a stale tile is made again");
    assert_ne!(std::fs::read(&tile).unwrap(), first);
}

#[test]
fn the_tile_index_comes_from_the_flag_then_kubernetes_then_slurm() {
    let tmp = temp_dir();
    let dir = tmp.path();
    asperity(&["terrain", "plan", "--size", "33", "--tile-size", "17", "-o", "p"], dir);
    let run = |flag: Option<&str>, env: &[(&str, &str)]| {
        let mut command = Command::new(env!("CARGO_BIN_EXE_asperity"));
        command.args(["terrain", "--plan", "p", "--json"]).current_dir(dir);
        command.env_remove("JOB_COMPLETION_INDEX").env_remove("SLURM_ARRAY_TASK_ID");
        if let Some(k) = flag {
            command.args(["--tile-index", k]);
        }
        command.envs(env.iter().copied());
        command.output().unwrap()
    };
    let output_of = |out: Output| {
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        report["output"].as_str().unwrap().to_string()
    };
    assert!(output_of(run(None, &[("SLURM_ARRAY_TASK_ID", "1")])).ends_with("terrain_x1_y0.png"));
    assert!(
        output_of(run(None, &[("JOB_COMPLETION_INDEX", "2"), ("SLURM_ARRAY_TASK_ID", "1")]))
            .ends_with("terrain_x0_y1.png")
    );
    assert!(output_of(run(Some("3"), &[("JOB_COMPLETION_INDEX", "2")])).ends_with("terrain_x1_y1.png"));
    let refused = |out: Output, phrase: &str| {
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{stderr}");
        assert!(stderr.contains(phrase) && stderr.lines().count() == 1, "{stderr}");
    };
    refused(run(None, &[]), "needs a tile index");
    refused(run(None, &[("SLURM_ARRAY_TASK_ID", "x")]), "$SLURM_ARRAY_TASK_ID");
    refused(run(Some("4"), &[]), "outside the plan's 4 tiles");
    let manifest = std::fs::read_to_string(dir.join("p/plan.json")).unwrap();
    std::fs::write(dir.join("p/plan.json"), manifest.replace("tiles/terrain_x0_y0.png", "../../escaped.png")).unwrap();
    refused(run(Some("0"), &[]), "is not the plan's name for tile 0,0");
    assert!(!dir.join("escaped.png").exists() && !dir.parent().unwrap().join("escaped.png").exists());
    std::fs::write(dir.join("p/plan.json"), "{ not json").unwrap();
    refused(run(Some("0"), &[]), "plan.json: not an asperity terrain plan");
}

#[test]
fn exr_and_tiff_hold_the_f32_heights() {
    let tmp = temp_dir();
    let dir = tmp.path();
    for name in ["t.f32", "t.exr", "t.tif"] {
        asperity(&["terrain", "--size", "65", "--seed", "4", "-o", name], dir);
    }
    let f32s: Vec<f32> = std::fs::read(dir.join("t.f32"))
        .unwrap()
        .chunks(4)
        .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
        .collect();
    let exr = exr::prelude::read_first_flat_layer_from_file(dir.join("t.exr")).unwrap();
    assert_eq!((exr.layer_data.size.0, exr.layer_data.size.1), (65, 65));
    let channel = &exr.layer_data.channel_data.list[0];
    assert_eq!(channel.name.to_string(), "Y");
    let values: Vec<f32> = channel.sample_data.values_as_f32().collect();
    assert!(values == f32s, "EXR samples differ from the f32 heights");
    let file = std::fs::File::open(dir.join("t.tif")).unwrap();
    let mut decoder = tiff::decoder::Decoder::new(std::io::BufReader::new(file)).unwrap();
    assert_eq!(decoder.dimensions().unwrap(), (65, 65));
    match decoder.read_image().unwrap() {
        tiff::decoder::DecodingResult::F32(values) => assert!(values == f32s, "TIFF samples differ"),
        other => panic!("TIFF holds {:?}, not 32-bit floats", std::mem::discriminant(&other)),
    }
    // Written whole: --stream is refused with the formats that stream.
    let out = Command::new(env!("CARGO_BIN_EXE_asperity"))
        .args(["terrain", "--size", "65", "--stream", "-o", "s.exr"])
        .current_dir(dir)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("written whole"));
    assert!(!dir.join("s.exr").exists());
}

#[test]
fn presets_refuse_sizes_their_engine_cannot_import_and_name_tiles() {
    let tmp = temp_dir();
    let dir = tmp.path();
    let refused = |args: &[&str], phrase: &str| {
        let out = Command::new(env!("CARGO_BIN_EXE_asperity")).args(args).current_dir(dir).output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(phrase), "{args:?}: {stderr}");
    };
    refused(&["terrain", "--preset", "unity", "--size", "8193", "-o", "u.raw"], "nearest: 4097");
    refused(&["terrain", "--preset", "unity", "--size", "17", "-o", "u.raw"], "nearest: 33");
    refused(&["terrain", "--preset", "unreal", "--size", "1025", "-o", "u.png"], "nearest: 1009");
    refused(
        &["terrain", "--preset", "unreal", "--size", "4033", "--tile", "0,0", "--tile-size", "1025", "-o", "u.png"],
        "nearest: 1009",
    );
    refused(&["terrain", "--preset", "unity", "--size", "65", "-o", "u.png"], ".raw");
    refused(&["terrain", "--preset", "unity", "--size", "65", "--grid", "triangle", "-o", "u.raw"], "square grids");
    refused(
        &["terrain", "--size", "65", "--sidecar", "--format", "raw16", "-o", "/dev/null"],
        "is written beside a file",
    );
    // Unity: RAW16 little-endian, tiles named _x{X}_y{Y}, a sidecar that maps back.
    asperity(
        &[
            "terrain",
            "--preset",
            "unity",
            "--size",
            "129",
            "--seed",
            "2",
            "--tile",
            "1,0",
            "--tile-size",
            "65",
            "-o",
            "land.raw",
        ],
        dir,
    );
    let raw = std::fs::read(dir.join("land_x1_y0.raw")).unwrap();
    assert_eq!(raw.len(), 65 * 65 * 2);
    let sidecar: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("land_x1_y0.raw.json")).unwrap()).unwrap();
    let (offset, scale) =
        (sidecar["encoding"]["offset"].as_f64().unwrap(), sidecar["encoding"]["scale"].as_f64().unwrap());
    assert_eq!(sidecar["byte_order"], "little-endian");
    let params = TerrainParams { size: 129, seed: 2, ..TerrainParams::default() };
    let truth = heights(&params, tile_rect(&params, 1, 0, 65).unwrap()).unwrap();
    for (k, pair) in raw.chunks(2).enumerate() {
        let back = offset + f64::from(u16::from_le_bytes([pair[0], pair[1]])) * scale;
        assert!((back - truth.heights[k]).abs() <= scale * 0.5 + 1e-12, "point {k}: {back} vs {}", truth.heights[k]);
    }
    let (lo, hi) = truth.heights.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &h| (a.min(h), b.max(h)));
    assert_eq!((sidecar["heights"]["min"].as_f64().unwrap(), sidecar["heights"]["max"].as_f64().unwrap()), (lo, hi));
    // Unreal: a 1009² PNG16, the first 1009 points of the 1025 grid.
    asperity(&["terrain", "--preset", "unreal", "--size", "1009", "--seed", "2", "-o", "ue.png"], dir);
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(dir.join("ue.png")).unwrap()));
    let info = decoder.read_info().unwrap().info().clone();
    assert_eq!((info.width, info.height, info.bit_depth), (1009, 1009, png::BitDepth::Sixteen));
    let sidecar: serde_json::Value = serde_json::from_slice(&std::fs::read(dir.join("ue.png.json")).unwrap()).unwrap();
    assert_eq!(sidecar["grid"]["size"], 1025);
    assert_eq!(sidecar["grid"]["x1"], 1008);
    // The world extent is the window's: 1008 steps span the default width 10.
    assert!((sidecar["world"]["spacing_x"].as_f64().unwrap() * 1008.0 - 10.0).abs() < 1e-9);
}

fn eroded(size: u64, iterations: u32, talus: f64) -> TerrainParams {
    TerrainParams {
        size,
        seed: 1,
        erosion: Some(ThermalErosion { iterations, talus_degrees: talus }),
        ..TerrainParams::default()
    }
}

#[test]
fn eroded_tiles_equal_the_whole_grid_on_every_lattice_and_method() {
    use asperity::terrain::{Grid, Method};
    for (method, grid) in
        [(Method::Classic, Grid::Square), (Method::Smooth, Grid::Square), (Method::Classic, Grid::Triangle)]
    {
        let params = TerrainParams { method, grid, sea_level: Some(-0.3), ..eroded(129, 9, 25.0) };
        let whole = heights(&params, Rect { x0: 0, y0: 0, x1: 128, y1: 128 }).unwrap();
        for (i, j) in [(0, 0), (1, 2), (3, 3), (2, 1)] {
            let rect = tile_rect(&params, i, j, 33).unwrap();
            let tile = heights(&params, rect).unwrap();
            for y in rect.y0..=rect.y1 {
                for x in rect.x0..=rect.x1 {
                    assert_eq!(
                        tile.at(x, y).to_bits(),
                        whole.at(x, y).to_bits(),
                        "{method:?} {grid:?} tile {i},{j} at {x},{y}"
                    );
                }
            }
        }
        let plain = heights(&TerrainParams { erosion: None, ..params }, whole.rect).unwrap();
        assert_ne!(plain.heights, whole.heights, "erosion changes the heights");
    }
}

#[test]
fn erosion_conserves_mass_and_leaves_slopes_at_the_talus() {
    let rect = Rect { x0: 0, y0: 0, x1: 64, y1: 64 };
    let before = heights(&TerrainParams { erosion: None, ..eroded(65, 0, 20.0) }, rect).unwrap();
    let params = eroded(65, 3000, 20.0);
    let after = heights(&params, rect).unwrap();
    let mass = |h: &[f64]| h.iter().sum::<f64>();
    let magnitude: f64 = before.heights.iter().map(|h| h.abs()).sum();
    let drift = (mass(&after.heights) - mass(&before.heights)).abs() / magnitude;
    assert!(drift < 1e-9, "mass drift {drift:e}");
    let (steep, relaxed) = (steepest_slope_degrees(&before, &params), steepest_slope_degrees(&after, &params));
    assert!(steep > 40.0, "the test terrain is steep: {steep}°");
    // The documented tolerance: 0.05° after 3000 iterations of a 65² grid.
    assert!(relaxed <= 20.0 + 0.05, "steepest slope after erosion {relaxed}° (talus 20°)");
    // Fewer iterations relax less, never more than the talus allows.
    let partial = heights(&eroded(65, 100, 20.0), rect).unwrap();
    let partial = steepest_slope_degrees(&partial, &params);
    assert!(partial < steep && partial > relaxed, "{steep}° → {partial}° (100) → {relaxed}° (3000)");
}

#[test]
fn erosion_is_identical_at_one_and_two_threads() {
    let thermal_then_hydraulic = TerrainParams { hydraulic: rained(129, 20).hydraulic, ..eroded(129, 20, 30.0) };
    for params in [eroded(129, 20, 30.0), rained(129, 20), thermal_then_hydraulic] {
        let rect = Rect { x0: 0, y0: 0, x1: 128, y1: 128 };
        let at = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| heights(&params, rect).unwrap())
        };
        assert_eq!(
            at(1).heights.iter().map(|h| h.to_bits()).collect::<Vec<_>>(),
            at(2).heights.iter().map(|h| h.to_bits()).collect::<Vec<_>>()
        );
    }
}

#[test]
fn the_readme_world_walkthrough_runs_as_it_stands() {
    tool("parallel", "parallel");
    tool("gdal_translate", "gdal-bin");
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let start = readme.find("```sh\n# world-scale walkthrough\n").expect("README: the world-scale walkthrough block");
    let block = &readme[start + "```sh\n".len()..];
    let block = &block[..block.find("```").unwrap()];
    let tmp = temp_dir();
    let dir = tmp.path();
    std::os::unix::fs::symlink(root.join("examples"), dir.join("examples")).unwrap();
    let out = Command::new("bash")
        .args(["-euo", "pipefail", "-c", block])
        .current_dir(dir)
        .env("PATH", path_with_asperity(dir))
        .output()
        .unwrap();
    let printed = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{printed}\n{}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(printed.matches("is already complete").count(), 16, "the second run skips every tile: {printed}");
    assert!(printed.contains("Size is 2049, 2049"), "gdalinfo: {printed}");
    assert!(std::fs::metadata(dir.join("world.tif")).unwrap().len() > 2049 * 2049 * 2);
    for (plan, extension, side) in [("world", "png", 513), ("unity", "raw", 513), ("unreal", "png", 505)] {
        let tiles: Vec<PathBuf> = std::fs::read_dir(dir.join(plan).join("tiles"))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == extension))
            .collect();
        assert_eq!(tiles.len(), 16, "{plan}");
        for tile in tiles {
            let sidecar: serde_json::Value =
                serde_json::from_slice(&std::fs::read(asperity::terrain::sidecar::Sidecar::path_for(&tile)).unwrap())
                    .unwrap();
            assert_eq!(
                (sidecar["columns"].as_u64(), sidecar["rows"].as_u64()),
                (Some(side), Some(side)),
                "{}",
                tile.display()
            );
        }
    }
}

fn rained(size: u64, iterations: u32) -> TerrainParams {
    TerrainParams {
        size,
        seed: 3,
        hydraulic: Some(asperity::terrain::HydraulicErosion { iterations, ..Default::default() }),
        ..TerrainParams::default()
    }
}

#[test]
fn hydraulic_tiles_equal_the_whole_grid_bit_for_bit() {
    // #41: 2 x 2 tiles of a 257² terrain after 50 iterations, and a lattice of triangles
    // with thermal erosion first, each tile computed on itself grown by its halo.
    use asperity::terrain::{Grid, HydraulicErosion};
    let thermal_first = TerrainParams {
        grid: Grid::Triangle,
        erosion: Some(ThermalErosion { iterations: 4, talus_degrees: 30.0 }),
        hydraulic: Some(HydraulicErosion { iterations: 12, ..Default::default() }),
        ..rained(129, 12)
    };
    for (params, tile_size) in [(rained(257, 50), 129), (thermal_first, 65)] {
        let last = params.size - 1;
        let whole = heights(&params, Rect { x0: 0, y0: 0, x1: last, y1: last }).unwrap();
        let tiles = last / (tile_size - 1);
        for j in 0..tiles {
            for i in 0..tiles {
                let rect = tile_rect(&params, i, j, tile_size).unwrap();
                let tile = heights(&params, rect).unwrap();
                for y in rect.y0..=rect.y1 {
                    for x in rect.x0..=rect.x1 {
                        assert_eq!(tile.at(x, y).to_bits(), whole.at(x, y).to_bits(), "tile {i},{j} at {x},{y}");
                    }
                }
            }
        }
        let plain = heights(&TerrainParams { hydraulic: None, ..params }, whole.rect).unwrap();
        assert_ne!(plain.heights, whole.heights, "hydraulic erosion changes the heights");
    }
}

#[test]
fn hydraulic_erosion_accounts_for_water_and_sediment_and_lowers_the_hypsometric_integral() {
    use asperity::terrain::hydraulic;
    let params = rained(129, 120);
    let rect = Rect { x0: 0, y0: 0, x1: 128, y1: 128 };
    let before = heights(&TerrainParams { hydraulic: None, ..params }, rect).unwrap();
    let mut field = before.clone();
    let budget = hydraulic::erode(&mut field, &params, &params.hydraulic.unwrap());
    // The terrain plus the settled sediment keeps its volume; the water that fell has
    // evaporated or still stands.
    let cell = (10.0 / 128.0) * (10.0 / 128.0);
    let volume = |h: &[f64]| h.iter().sum::<f64>() * cell;
    let magnitude: f64 = before.heights.iter().map(|h| h.abs()).sum::<f64>() * cell;
    let drift = (volume(&field.heights) - volume(&before.heights)).abs() / magnitude;
    assert!(drift < 1e-12, "terrain volume drift {drift:e}");
    let water = (budget.rained - budget.evaporated - budget.water_left).abs() / budget.rained;
    assert!(water < 1e-12, "water unaccounted for: {water:e} of the rain ({budget:?})");
    assert!(budget.sediment_settled > 0.0 && budget.evaporated > 0.0, "{budget:?}");
    // Erosion moves material from heights down into valleys: the hypsometric integral
    // (mean − min)/(max − min) falls (Strahler 1952: it falls as a landscape matures).
    let integral = |h: &[f64]| {
        let (lo, hi) = h.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, u), &v| (l.min(v), u.max(v)));
        (h.iter().sum::<f64>() / h.len() as f64 - lo) / (hi - lo)
    };
    let (from, to) = (integral(&before.heights), integral(&field.heights));
    assert!(to < from - 0.02, "hypsometric integral {from:.4} -> {to:.4}");
}

#[test]
fn every_hydraulic_parameter_has_its_effect_and_its_range() {
    use asperity::terrain::HydraulicErosion;
    let rect = Rect { x0: 0, y0: 0, x1: 64, y1: 64 };
    let base = HydraulicErosion { iterations: 30, ..Default::default() };
    let run = |h: HydraulicErosion| {
        let params = TerrainParams { hydraulic: Some(h), ..rained(65, 30) };
        heights(&params, rect).unwrap().heights
    };
    let plain = heights(&TerrainParams { hydraulic: None, ..rained(65, 30) }, rect).unwrap().heights;
    let moved = |h: &[f64]| h.iter().zip(&plain).map(|(a, b)| (a - b).abs()).sum::<f64>();
    let reference = moved(&run(base));
    // More rain, more capacity, faster dissolving: more material moved; more evaporation:
    // less. Deposition and the time step change the result.
    let more = |h: HydraulicErosion, name: &str| {
        let m = moved(&run(h));
        assert!(m > reference * 1.05, "{name}: {m} moved against {reference}");
    };
    more(HydraulicErosion { rain: base.rain * 4.0, ..base }, "rain");
    more(HydraulicErosion { capacity: base.capacity * 2.0, ..base }, "capacity");
    more(HydraulicErosion { dissolving: 0.9, ..base }, "dissolving");
    let drier = moved(&run(HydraulicErosion { evaporation: 15.0, ..base }));
    assert!(drier < reference * 0.95, "evaporation: {drier} moved against {reference}");
    for (name, h) in [
        ("deposition", HydraulicErosion { deposition: 0.9, ..base }),
        ("time step", HydraulicErosion { time_step: 0.1, ..base }),
    ] {
        assert_ne!(run(h), run(base), "{name} changed nothing");
    }
    // Each refused outside its range, by name.
    for (flag, h) in [
        ("--rain", HydraulicErosion { rain: 0.0, ..base }),
        ("--evaporation", HydraulicErosion { evaporation: 20.0, ..base }),
        ("--capacity", HydraulicErosion { capacity: -1.0, ..base }),
        ("--dissolving", HydraulicErosion { dissolving: 1.5, ..base }),
        ("--deposition", HydraulicErosion { deposition: 0.0, ..base }),
        ("--time-step", HydraulicErosion { time_step: f64::NAN, ..base }),
    ] {
        let error = h.validate().unwrap_err().to_string();
        assert!(error.contains(flag), "{flag}: {error}");
    }
}

#[test]
fn plans_written_before_hydraulic_erosion_still_run_and_erode_takes_each_model_once() {
    let tmp = temp_dir();
    let dir = tmp.path();
    let plan =
        ["terrain", "plan", "--size", "33", "--erode", "thermal", "--tile-size", "17", "--format", "f32", "-o", "p"];
    assert!(asperity(&plan, dir).status.success());
    // A plan of the version before wrote `erode` as one model, or null, and no rain.
    let path = dir.join("p/plan.json");
    let mut json: serde_json::Value = serde_json::from_slice(&std::fs::read(&path).unwrap()).unwrap();
    let parameters = json["parameters"].as_object_mut().unwrap();
    parameters.insert("erode".into(), serde_json::json!("thermal"));
    for key in ["rain", "evaporation", "capacity", "dissolving", "deposition", "time_step"] {
        parameters.remove(key);
    }
    std::fs::write(&path, serde_json::to_vec(&json).unwrap()).unwrap();
    asperity(&["terrain", "--plan", "p", "--tile-index", "0"], dir);
    for erode in ["hydraulic,hydraulic", "hydraulic,thermal", "thermal,thermal"] {
        let out = Command::new(env!("CARGO_BIN_EXE_asperity"))
            .args(["terrain", "--size", "33", "--erode", erode, "-o", "t.f32"])
            .current_dir(dir)
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "--erode {erode}");
        assert!(String::from_utf8_lossy(&out.stderr).contains("each once, thermal first"), "--erode {erode}");
    }
}

#[test]
fn erosion_layers_equal_the_whole_grids_on_tiles_and_are_masks() {
    // #41: the layers, like the heights, are the whole grid's on a tile grown by its halo;
    // heights_and_layers gives heights() bit for bit.
    use asperity::terrain::{ErosionLayer, heights_and_layers};
    let params = rained(129, 12);
    let whole_rect = Rect { x0: 0, y0: 0, x1: 128, y1: 128 };
    let (whole, layers) = heights_and_layers(&params, whole_rect, &ErosionLayer::ALL).unwrap();
    assert_eq!(whole, heights(&params, whole_rect).unwrap());
    for layer in &layers {
        assert!(layer.heights.iter().all(|v| (0.0..=1.0).contains(v)), "a mask in [0, 1]");
        assert!(layer.heights.iter().any(|&v| v > 0.0), "a layer that is 0 everywhere");
    }
    for (i, j) in [(0, 0), (1, 0), (1, 1)] {
        let rect = tile_rect(&params, i, j, 65).unwrap();
        let (tile, tile_layers) = heights_and_layers(&params, rect, &ErosionLayer::ALL).unwrap();
        assert_eq!(tile.heights, heights(&params, rect).unwrap().heights);
        for (k, layer) in tile_layers.iter().enumerate() {
            for y in rect.y0..=rect.y1 {
                for x in rect.x0..=rect.x1 {
                    let (a, b) = (layer.at(x, y), layers[k].at(x, y));
                    assert_eq!(a.to_bits(), b.to_bits(), "{:?} tile {i},{j} at {x},{y}", ErosionLayer::ALL[k]);
                }
            }
        }
    }
    let dry = TerrainParams { hydraulic: None, ..params };
    assert!(heights_and_layers(&dry, whole_rect, &[ErosionLayer::Flow]).unwrap_err().to_string().contains("hydraulic"));
}

#[test]
fn erosion_layers_show_where_water_runs_stands_and_settles() {
    // Water runs down into valleys and stands and settles there: each layer is higher on
    // the lowest quarter of the eroded terrain than on its highest quarter.
    use asperity::terrain::{ErosionLayer, heights_and_layers};
    let params = rained(129, 120);
    let rect = Rect { x0: 0, y0: 0, x1: 128, y1: 128 };
    let (field, layers) = heights_and_layers(&params, rect, &ErosionLayer::ALL).unwrap();
    let mut sorted = field.heights.clone();
    sorted.sort_by(f64::total_cmp);
    let (low, high) = (sorted[sorted.len() / 4], sorted[3 * sorted.len() / 4]);
    let mean_where = |values: &[f64], keep: &dyn Fn(f64) -> bool| {
        let picked: Vec<f64> = values.iter().zip(&field.heights).filter(|(_, h)| keep(**h)).map(|(v, _)| *v).collect();
        picked.iter().sum::<f64>() / picked.len() as f64
    };
    for (k, layer) in layers.iter().enumerate() {
        let valleys = mean_where(&layer.heights, &|h| h <= low);
        let heights = mean_where(&layer.heights, &|h| h >= high);
        assert!(
            valleys > heights,
            "{:?}: {valleys:.4} in the valleys, {heights:.4} on the heights",
            ErosionLayer::ALL[k]
        );
    }
}

#[test]
fn hydraulic_erosion_smooths_the_terrain_at_the_point_scale() {
    // With a point emptying into its neighbours each step, dissolving and deposition
    // alternated from point to point and the heights' Laplacian grew 4.7 times in 50
    // iterations (a hatching one point wide); erosion smooths it instead.
    let params = TerrainParams { size: 257, hurst: 1.0, sigma: 2.0, ..rained(257, 50) };
    let rect = Rect { x0: 0, y0: 0, x1: 256, y1: 256 };
    let laplacian_rms = |h: &[f64]| {
        let n = 257;
        let mut sum = 0.0;
        for y in 1..n - 1 {
            for x in 1..n - 1 {
                let c = y * n + x;
                let l = h[c] - 0.25 * (h[c - 1] + h[c + 1] + h[c - n] + h[c + n]);
                sum += l * l;
            }
        }
        (sum / ((n - 2) * (n - 2)) as f64).sqrt()
    };
    let before = laplacian_rms(&heights(&TerrainParams { hydraulic: None, ..params }, rect).unwrap().heights);
    let after = laplacian_rms(&heights(&params, rect).unwrap().heights);
    assert!(after < before, "the Laplacian's RMS grew {before:.5} -> {after:.5}");
}

#[test]
fn terrain_layers_are_written_whole_streamed_and_in_plans_with_sidecars_and_mosaics() {
    let tmp = temp_dir();
    let dir = tmp.path();
    let generation = ["--size", "129", "--erode", "hydraulic", "--erode-iterations", "8"];
    let run = |extra: &[&str]| {
        let args: Vec<&str> = ["terrain"].iter().chain(&generation).chain(extra).copied().collect();
        asperity(&args, dir)
    };
    let out = run(&["--layers", "flow,water", "--sidecar", "-o", "whole.png"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stdout).contains("whole.flow.png, whole.water.png"));
    let sidecar: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("whole.flow.png.json")).unwrap()).unwrap();
    assert_eq!(sidecar["layer"], "flow");
    assert_eq!(sidecar["encoding"]["hi"], 1.0);
    // Streamed in bands of 16 rows, each band eroding again on its halo: the same bytes.
    let out = run(&["--layers", "flow,water", "--stream", "--band", "16", "-o", "streamed.png"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    for name in ["", ".flow", ".water"] {
        let (a, b) = (format!("whole{name}.png"), format!("streamed{name}.png"));
        assert_eq!(std::fs::read(dir.join(&a)).unwrap(), std::fs::read(dir.join(&b)).unwrap(), "{a} != {b}");
    }
    assert!(!dir.join("streamed.sediment.png").exists());
    // Refused: without hydraulic erosion (naming it), and beside a mesh.
    let refused = |args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_asperity")).args(args).current_dir(dir).output().expect("run asperity")
    };
    let out = refused(&["terrain", "--size", "33", "--erode", "thermal", "--layers", "flow", "-o", "t.png"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--erode hydraulic"));
    let out = refused(&["terrain", "--size", "33", "--erode", "hydraulic", "--layers", "flow", "-o", "t.ply"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(!dir.join("t.ply").exists() && !dir.join("t.flow.ply").exists());
    // A plan: each layer's tiles beside the heights' and a mosaic per layer, naming them.
    let args: Vec<&str> = ["terrain", "plan"]
        .iter()
        .chain(&generation)
        .chain(&["--layers", "sediment", "--tile-size", "65", "--format", "raw16", "-o", "p"])
        .copied()
        .collect();
    assert!(asperity(&args, dir).status.success());
    for k in 0..4 {
        assert!(asperity(&["terrain", "--plan", "p", "--tile-index", &k.to_string()], dir).status.success());
    }
    let mosaic = std::fs::read_to_string(dir.join("p/mosaic.sediment.vrt")).unwrap();
    assert!(mosaic.contains("tiles/terrain_x1_y1.sediment.raw16.vrt"), "{mosaic}");
    assert!(dir.join("p/tiles/terrain_x1_y1.sediment.raw16").exists());
    assert!(dir.join("p/tiles/terrain_x1_y1.sediment.raw16.json").exists());
    let plan: serde_json::Value = serde_json::from_slice(&std::fs::read(dir.join("p/plan.json")).unwrap()).unwrap();
    assert_eq!(plan["layer_mosaics"]["sediment"], "mosaic.sediment.vrt");
}
