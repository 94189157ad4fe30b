//! Every subcommand gives byte-identical files (and reports, timings aside) on a second run
//! and with one or two worker threads (`RAYON_NUM_THREADS=1` vs `2`).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

use asperity::io::{WriteOptions, write};
use asperity::mesh::primitives::torus;

use crate::common::temp_dir;

/// One run of every subcommand in a fresh folder: every file written (by relative path)
/// and the reports printed on stdout.
fn run_everything(threads: &str) -> BTreeMap<String, Vec<u8>> {
    let tmp = temp_dir();
    let dir = tmp.path();
    let mesh = torus(2.0, 0.7, 64, 32);
    write(&mesh, &dir.join("torus.off"), WriteOptions::default()).unwrap();
    let recipe = Path::new(env!("CARGO_MANIFEST_DIR")).join("recipes/sphere-virus.toml");
    let recipe = recipe.to_str().unwrap();
    let runs: Vec<Vec<&str>> = vec![
        vec!["info", "torus.off", "--json"],
        vec!["convert", "torus.off", "torus.glb"],
        vec!["convert", "torus.off", "torus.obj"],
        vec!["convert", "torus.off", "torus.stl"],
        vec!["analyze", "torus.off", "-o", "analysis.ply", "--repair"],
        vec!["render", "torus.off", "-o", "faces.png", "--size", "160,120", "--edges"],
        vec!["render", "torus.off", "-o", "wire.png", "--size", "160,120", "--mode", "wireframe"],
        vec!["render", "torus.off", "-o", "points.png", "--size", "160,120", "--mode", "points"],
        vec!["noise", "--kind", "fbm", "--size", "64", "-o", "fbm.png"],
        vec!["noise", "--kind", "gabor", "--isotropic", "--size", "64", "-o", "gabor.f32"],
        vec!["noise", "--kind", "multifractal", "--size", "64", "-o", "multifractal.png"],
        vec!["clouds", "--size", "65", "-o", "clouds.png"],
        vec!["terrain", "--size", "129", "--seed", "3", "-o", "classic.ply", "--preview", "classic.png"],
        vec!["terrain", "--size", "129", "--seed", "3", "--stream", "-o", "stream.ply"],
        vec!["terrain", "--size", "129", "--seed", "3", "--tile", "1,0", "--tile-size", "65", "-o", "tile.ply"],
        vec!["terrain", "--size", "129", "--grid", "hex", "-o", "hex.obj"],
        vec!["terrain", "--size", "129", "--method", "smooth", "-o", "smooth.raw16"],
        vec!["terrain", "--method", "dual", "--levels", "5", "--steps", "dual-steps", "-o", "dual.ply"],
        vec!["menger", "--level", "2", "-o", "sponge.ply"],
        vec!["flora", "--preset", "cottonwood", "--seed", "3", "-o", "tree.glb"],
        vec!["smoke", "--frames", "3", "--resolution", "40", "-o", "smoke.glb"],
        vec!["water", "classic.ply", "--level", "0", "--frames", "2", "--cells", "32", "-o", "water.ply"],
        vec!["butterflies", "--count", "3", "--steps", "40", "-o", "butterflies.glb"],
        vec!["scene", "--size", "65", "--frames", "3", "--trees", "8", "-o", "scene.glb", "--preview", "scene.png"],
        vec![
            "simplify",
            "torus.off",
            "--target-vertices",
            "5%",
            "-o",
            "base.ply",
            "--levels-out",
            "levels",
            "--param-out",
            "param.ply",
            "--lod-out",
            "lod.glb",
        ],
        vec!["detail", "torus.off", "-o", "round-trip.ply"],
        vec!["detail", "builtin:sphere", "--recipe", recipe, "-o", "virus.ply"],
        vec!["compare", "torus.off", "--target-vertices", "10%", "--json"],
        vec!["demo", "--out", "demo"],
        vec!["reference"],
    ];
    let mut outputs = BTreeMap::new();
    for args in &runs {
        let out = Command::new(env!("CARGO_BIN_EXE_asperity"))
            .args(args)
            .current_dir(dir)
            .env("RAYON_NUM_THREADS", threads)
            .output()
            .unwrap();
        assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
        if args.contains(&"--json") || args[0] == "reference" {
            outputs.insert(format!("stdout of {}", args.join(" ")), without_timings(&out.stdout));
        }
    }
    for path in files_under(dir) {
        let name = path.strip_prefix(dir).unwrap().display().to_string();
        if name != "torus.off" {
            outputs.insert(name, std::fs::read(&path).unwrap());
        }
    }
    outputs
}

/// A JSON report with every `seconds`/`milliseconds` field removed; other text as it is.
fn without_timings(stdout: &[u8]) -> Vec<u8> {
    fn strip(value: &mut serde_json::Value) {
        match value {
            serde_json::Value::Object(map) => {
                map.retain(|k, _| !k.contains("seconds") && k != "milliseconds");
                map.values_mut().for_each(strip);
            }
            serde_json::Value::Array(items) => items.iter_mut().for_each(strip),
            _ => {}
        }
    }
    match serde_json::from_slice::<serde_json::Value>(stdout) {
        Ok(mut v) => {
            strip(&mut v);
            v.to_string().into_bytes()
        }
        Err(_) => stdout.to_vec(),
    }
}

fn files_under(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() { stack.push(path) } else { files.push(path) }
        }
    }
    files
}

#[test]
fn every_subcommand_is_byte_identical_across_runs_and_thread_counts() {
    let one = run_everything("1");
    let two = run_everything("2");
    let again = run_everything("2");
    assert!(one.len() > 40, "{} outputs: {:?}", one.len(), one.keys().collect::<Vec<_>>());
    assert_eq!(one.keys().collect::<Vec<_>>(), two.keys().collect::<Vec<_>>());
    for (name, bytes) in &one {
        assert!(!bytes.is_empty(), "{name} is empty");
        assert!(*bytes == two[name], "{name} differs between 1 and 2 threads");
        assert!(two[name] == again[name], "{name} differs between two runs");
    }
}
