//! Every flag of every subcommand does something or is refused (#24 item 11): each flag
//! is run against a base command, and either what the command writes (its files, and for
//! the commands that report on stdout, their JSON report without timings) differs, or the
//! command refuses it with exit 2. A flag missing from the table fails the test, so a new
//! flag needs a case.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

use rayon::prelude::*;

use crate::common::{shared_meshes, temp_dir};

/// One flag's case: the base command and the same with the flag; `may_fix` when the base
/// may be refused and the flag is what makes it work (`--repair`, `--force`).
struct Case {
    sub: &'static str,
    flag: &'static str,
    base: Vec<String>,
    with: Vec<String>,
    may_fix: bool,
}

/// Flags whose effect is not in the output, with the test that checks what they do.
const EXEMPT: [(&str, &str, &str); 15] = [
    (
        "render",
        "--texture",
        "needs a mesh with UVs and a PNG: `uv::the_command_line_keeps_uvs_through_simplify_and_draws_them`",
    ),
    ("demo", "--out", "slow; `demo_writes_its_meshes` checks the folder it names"),
    (
        "terrain",
        "--stream",
        "the same bytes by design, in bounded memory: `streaming_equals_whole_grids` and the memory test",
    ),
    ("terrain", "--band", "the same bytes by design: `streaming_equals_whole_grids` runs several bands"),
    (
        "terrain",
        "--plan",
        "runs a plan's tile: `terrain_scale::planned_tiles_through_gnu_parallel_and_xargs_equal_the_whole_grid`",
    ),
    ("terrain", "--tile-index", "`terrain_scale::the_tile_index_comes_from_the_flag_then_kubernetes_then_slurm`"),
    ("terrain plan", "--tile-size", "required: every plan names it"),
    (
        "simplify",
        "--plan",
        "builds a plan's chunk: `simplify_plan::chunks_run_as_processes_in_any_order_give_the_threaded_build`",
    ),
    (
        "simplify",
        "--chunk-index",
        "`simplify_plan::chunks_run_as_processes_in_any_order_give_the_threaded_build` (and the job runners' variables)",
    ),
    ("simplify plan", "--chunks", "required: every plan names it"),
    (
        "simplify merge",
        "--param-out",
        "needs built chunks: `simplify_plan::chunks_run_as_processes_in_any_order_give_the_threaded_build`",
    ),
    (
        "simplify merge",
        "--levels-out",
        "needs built chunks: `simplify_plan::chunks_run_as_processes_in_any_order_give_the_threaded_build`",
    ),
    (
        "simplify merge",
        "--lod-out",
        "needs built chunks: `simplify_plan::chunks_run_as_processes_in_any_order_give_the_threaded_build`",
    ),
    (
        "simplify merge",
        "--force",
        "needs built chunks: `simplify_plan::chunks_run_as_processes_in_any_order_give_the_threaded_build`",
    ),
    (
        "simplify merge",
        "--input",
        "needs built chunks: `simplify_plan::chunks_run_as_processes_in_any_order_give_the_threaded_build`",
    ),
];

fn owned(args: &[&str]) -> Vec<String> {
    args.iter().map(|s| s.to_string()).collect()
}

/// The cases of every subcommand. `M` is the meshes folder, `B` a broken mesh (repairable).
fn cases(meshes: &Path, broken: &Path) -> Vec<Case> {
    let eight = meshes.join("eight.off").display().to_string();
    let fandisk = meshes.join("fandisk.off").display().to_string();
    let broken = broken.display().to_string();
    let mut cases = Vec::new();
    // A flag the base already gives has its value replaced (given twice, clap would refuse
    // it, and the case would pass without testing anything).
    let mut add = |sub: &'static str, flag: &'static str, base: &[&str], extra: &[&str]| {
        let base = owned(base);
        let mut with = base.clone();
        match (extra, base.iter().position(|a| a == extra[0])) {
            ([_, value], Some(at)) if at + 1 < base.len() => with[at + 1] = value.to_string(),
            _ => with.extend(owned(extra)),
        }
        cases.push(Case { sub, flag, base, with, may_fix: false });
    };
    // analyze
    let a = ["analyze", &eight, "-o", "a.ply"];
    add("analyze", "--normals", &a, &["--normals", "uniform"]);
    add("analyze", "--corner", &a, &["--corner", "0.001"]);
    add("analyze", "--face", &a, &["--face", "0.3"]);
    add("analyze", "--strong", &a, &["--strong", "0.001"]);
    add("analyze", "--ascii", &a, &["--ascii"]);
    // clouds
    let c = ["clouds", "--size", "33", "-o", "c.png"];
    add("clouds", "--size", &c, &["--size", "65"]);
    add("clouds", "--hurst", &c, &["--hurst", "0.2"]);
    add("clouds", "--seed", &c, &["--seed", "1"]);
    add("clouds", "--threshold", &c, &["--threshold", "0.2"]);
    add("clouds", "--sky", &c, &["--sky", "0,0,0"]);
    add("clouds", "--cloud", &c, &["--cloud", "255,0,0"]);
    // compare (its report is its output)
    let k = ["compare", &eight, "--methods", "asperity,meshoptimizer", "--json"];
    add("compare", "--target-vertices", &k, &["--target-vertices", "100"]);
    add("compare", "--methods", &k, &["--methods", "asperity"]);
    let kf = ["compare", &fandisk, "--methods", "asperity", "--target-vertices", "400", "--json"];
    add("compare", "--keep-features", &kf, &["--keep-features", "none"]);
    add("compare", "--feature-vertices", &kf, &["--feature-vertices", "keep"]);
    // convert
    add("convert", "--ascii", &["convert", &eight, "v.ply"], &["--ascii"]);
    // detail, with a recipe whose relief makes self-intersections
    let d = ["detail", &eight, "-o", "d.ply", "--recipe", "relief.toml"];
    add("detail", "--recipe", &["detail", &eight, "-o", "d.ply"], &["--recipe", "relief.toml"]);
    add("detail", "--allow-self-intersections", &d, &["--allow-self-intersections"]);
    add("detail", "--target-vertices", &d, &["--target-vertices", "150"]);
    add("detail", "--levels", &d, &["--levels", "2"]);
    add("detail", "--max-error", &d, &["--max-error", "0.001"]);
    add("detail", "--removal-weight", &d, &["--removal-weight", "0.1"]);
    add("detail", "--swap-weight", &d, &["--swap-weight", "3"]);
    add("detail", "--no-intersection-guard", &d, &["--no-intersection-guard"]);
    // The guard turned back on over a recipe's table that turns it off.
    let du = ["detail", &eight, "-o", "d.ply", "--recipe", "unguarded.toml"];
    add("detail", "--intersection-guard", &du, &["--intersection-guard"]);
    let df = ["detail", &fandisk, "-o", "d.ply", "--recipe", "relief.toml", "--target-vertices", "400"];
    add("detail", "--keep-features", &df, &["--keep-features", "none"]);
    add("detail", "--feature-vertices", &df, &["--feature-vertices", "keep"]);
    add("detail", "--chunks", &df, &["--chunks", "2"]);
    // noise
    let n = ["noise", "--size", "32", "-o", "n.png"];
    add("noise", "--kind", &n, &["--kind", "fbm"]);
    add("noise", "--size", &n, &["--size", "40"]);
    add("noise", "--scale", &n, &["--scale", "0.1"]);
    add("noise", "--seed", &n, &["--seed", "2"]);
    add("noise", "--precision", &n, &["--precision", "f32"]);
    add("noise", "--range", &n, &["--range", "-2,2"]);
    let nf = ["noise", "--size", "32", "-o", "n.png", "--kind", "fbm"];
    add("noise", "--octaves", &nf, &["--octaves", "2"]);
    add("noise", "--lacunarity", &nf, &["--lacunarity", "3"]);
    add("noise", "--gain", &nf, &["--gain", "0.8"]);
    add("noise", "--offset", &["noise", "--size", "32", "-o", "n.png", "--kind", "multifractal"], &["--offset", "0.5"]);
    let ng = ["noise", "--size", "32", "-o", "n.png", "--kind", "gabor"];
    add("noise", "--k", &ng, &["--k", "2"]);
    add("noise", "--a", &ng, &["--a", "0.08"]);
    add("noise", "--f0", &ng, &["--f0", "0.1"]);
    add("noise", "--omega", &ng, &["--omega", "0.3"]);
    add("noise", "--impulses", &ng, &["--impulses", "16"]);
    add("noise", "--isotropic", &ng, &["--isotropic"]);
    add("noise", "--profile", &["noise", "--size", "32", "-o", "n.png", "--kind", "phasor"], &["--profile", "square"]);
    // render
    let r = ["render", &eight, "-o", "r.png", "--size", "64,48"];
    add("render", "--size", &r, &["--size", "80,60"]);
    add("render", "--mode", &r, &["--mode", "wireframe"]);
    add("render", "--yaw", &r, &["--yaw", "100"]);
    add("render", "--pitch", &r, &["--pitch", "70"]);
    add("render", "--up", &r, &["--up", "x"]);
    add("render", "--colors", &r, &["--colors", "height"]);
    add("render", "--background", &r, &["--background", "#000000"]);
    add("render", "--samples", &r, &["--samples", "1"]);
    add("render", "--crease", &r, &["--crease", "1"]);
    add("render", "--edges", &r, &["--edges"]);
    add("render", "--water-level", &r, &["--water-level", "0"]);
    let rw = ["render", &eight, "-o", "r.png", "--size", "64,48", "--water-level", "0"];
    add("render", "--water-clarity", &rw, &["--water-clarity", "0.5"]);
    // refine: the eight's upper half at full resolution
    let half = "half_space = { axis = \"z\", above = 0.5 }";
    let rf = ["refine", &eight, "--region", half, "-o", "rf.ply"];
    add("refine", "--region", &rf, &["--region", "half_space = { axis = \"z\", above = 0.7 }"]);
    add("refine", "--base-level", &rf, &["--base-level", "12"]);
    let independent = "independent = { exclusion = 3, shuffle = true }";
    add("refine", "--seed", &["refine", &eight, "--region", independent, "-o", "rf.ply"], &["--seed", "5"]);
    add("refine", "--target-vertices", &rf, &["--target-vertices", "150"]);
    add("refine", "--levels", &rf, &["--levels", "2"]);
    add("refine", "--max-error", &rf, &["--max-error", "0.001"]);
    add("refine", "--removal-weight", &rf, &["--removal-weight", "0.1"]);
    add("refine", "--swap-weight", &rf, &["--swap-weight", "3"]);
    add("refine", "--no-intersection-guard", &rf, &["--no-intersection-guard"]);
    let rff = ["refine", &fandisk, "--region", half, "-o", "rf.ply", "--target-vertices", "400"];
    add("refine", "--keep-features", &rff, &["--keep-features", "none"]);
    add("refine", "--feature-vertices", &rff, &["--feature-vertices", "keep"]);
    add("refine", "--chunks", &rff, &["--chunks", "2"]);
    // seed 002's generators
    let rules =
        |name: &str| Path::new(env!("CARGO_MANIFEST_DIR")).join("src/scene/flora").join(name).display().to_string();
    let (palm_rules, flower_rules) = (rules("palm.toml"), rules("flower.toml"));
    let b = ["butterflies", "--count", "2", "--steps", "20", "-o", "b.glb"];
    add("butterflies", "--count", &b, &["--count", "3"]);
    add("butterflies", "--steps", &b, &["--steps", "21"]);
    add("butterflies", "--seed", &b, &["--seed", "1"]);
    add("butterflies", "--speed", &b, &["--speed", "0.02"]);
    add("butterflies", "--wander", &b, &["--wander", "0.05"]);
    add(
        "butterflies",
        "--catch-radius",
        &["butterflies", "--count", "2", "--steps", "400", "-o", "b.glb"],
        &["--catch-radius", "0.1"],
    );
    add("butterflies", "--flap", &b, &["--flap", "5"]);
    add("butterflies", "--flap-limit", &b, &["--flap-limit", "30"]);
    add("butterflies", "--fps", &b, &["--fps", "24"]);
    let f = ["flora", "--preset", "palm", "-o", "f.ply"];
    add("flora", "--preset", &f, &["--preset", "flower"]);
    add("flora", "--rules", &["flora", "--rules", &flower_rules, "-o", "f.ply"], &["--rules", &palm_rules]);
    add("flora", "--seed", &f, &["--seed", "1"]);
    add("flora", "--sides", &f, &["--sides", "5"]);
    add("flora", "--ascii", &f, &["--ascii"]);
    let m = ["menger", "--level", "1", "-o", "m.ply"];
    add("menger", "--level", &m, &["--level", "2"]);
    add("menger", "--edge", &m, &["--edge", "3"]);
    add("menger", "--ascii", &m, &["--ascii"]);
    let sc = ["scene", "--size", "33", "--frames", "2", "--trees", "4", "--butterflies", "1", "-o", "sc.glb"];
    add("scene", "--seed", &sc, &["--seed", "1"]);
    add("scene", "--size", &sc, &["--size", "65"]);
    add("scene", "--sea-fraction", &sc, &["--sea-fraction", "0.1"]);
    add("scene", "--trees", &sc, &["--trees", "2"]);
    add("scene", "--max-slope", &sc, &["--max-slope", "5"]);
    add("scene", "--butterflies", &sc, &["--butterflies", "2"]);
    add("scene", "--frames", &sc, &["--frames", "3"]);
    add("scene", "--fps", &sc, &["--fps", "24"]);
    add("scene", "--preview", &sc, &["--preview", "sc.png"]);
    let k = ["smoke", "--frames", "1", "--resolution", "24", "-o", "k.glb"];
    add("smoke", "--seed", &k, &["--seed", "1"]);
    add("smoke", "--frames", &k, &["--frames", "2"]);
    add("smoke", "--warmup", &k, &["--warmup", "30"]);
    add(
        "smoke",
        "--steps-per-frame",
        &["smoke", "--frames", "2", "--resolution", "24", "-o", "k.glb"],
        &["--steps-per-frame", "3"],
    );
    add("smoke", "--fps", &["smoke", "--frames", "2", "--resolution", "24", "-o", "k.glb"], &["--fps", "24"]);
    add("smoke", "--batch", &k, &["--batch", "3"]);
    add("smoke", "--emit-every", &k, &["--emit-every", "3"]);
    add("smoke", "--dt", &k, &["--dt", "0.04"]);
    add("smoke", "--field-cells", &k, &["--field-cells", "3"]);
    add("smoke", "--swirl", &k, &["--swirl", "2"]);
    add("smoke", "--rise", &k, &["--rise", "1.5"]);
    add("smoke", "--spread", &k, &["--spread", "0.1"]);
    add("smoke", "--radius", &k, &["--radius", "0.06"]);
    add("smoke", "--blobbiness", &k, &["--blobbiness", "1.5"]);
    add("smoke", "--resolution", &k, &["--resolution", "32"]);
    add("smoke", "--ascii", &["smoke", "--frames", "1", "--resolution", "24", "-o", "k.ply"], &["--ascii"]);
    // Just above the eight (its top is at z = 0.5), so the water has depth everywhere.
    let w = ["water", &eight, "--level", "0.6", "--frames", "2", "--cells", "16", "-o", "w.glb"];
    add("water", "--level", &w, &["--level", "0.7"]);
    add("water", "--cells", &w, &["--cells", "20"]);
    add("water", "--waves", &w, &["--waves", "2"]);
    add("water", "--seed", &w, &["--seed", "1"]);
    add("water", "--clarity", &w, &["--clarity", "0.5"]);
    add("water", "--frames", &w, &["--frames", "3"]);
    add("water", "--fps", &w, &["--fps", "30"]);
    add(
        "water",
        "--ascii",
        &["water", &eight, "--level", "0", "--frames", "1", "--cells", "16", "-o", "w.ply"],
        &["--ascii"],
    );
    // simplify
    let s = ["simplify", &eight, "-o", "s.ply"];
    add("simplify", "--target-vertices", &s, &["--target-vertices", "100"]);
    add("simplify", "--levels", &s, &["--levels", "2"]);
    add("simplify", "--max-error", &s, &["--max-error", "0.001"]);
    add("simplify", "--removal-weight", &s, &["--removal-weight", "0.1"]);
    add("simplify", "--swap-weight", &s, &["--swap-weight", "3"]);
    add("simplify", "--no-intersection-guard", &s, &["--no-intersection-guard"]);
    add("simplify", "--levels-out", &s, &["--levels-out", "levels"]);
    add("simplify", "--lod-out", &s, &["--lod-out", "l.glb"]);
    add("simplify", "--param-out", &s, &["--param-out", "p.ply"]);
    let sf = ["simplify", &fandisk, "-o", "s.ply", "--target-vertices", "400"];
    add("simplify", "--keep-features", &sf, &["--keep-features", "none"]);
    add("simplify", "--feature-vertices", &sf, &["--feature-vertices", "keep"]);
    add("simplify", "--chunks", &sf, &["--chunks", "4"]);
    // simplify plan: each build setting is the plan's (plan.json records it; what a chunk
    // makes of it is simplify's case), --target-vertices is what makes a plan.
    let sp = ["simplify", "plan", &fandisk, "--chunks", "2", "-o", "p", "--target-vertices", "400"];
    add("simplify plan", "--levels", &sp, &["--levels", "2"]);
    add("simplify plan", "--max-error", &sp, &["--max-error", "0.001"]);
    add("simplify plan", "--removal-weight", &sp, &["--removal-weight", "0.1"]);
    add("simplify plan", "--swap-weight", &sp, &["--swap-weight", "3"]);
    add("simplify plan", "--no-intersection-guard", &sp, &["--no-intersection-guard"]);
    add("simplify plan", "--keep-features", &sp, &["--keep-features", "none"]);
    add("simplify plan", "--feature-vertices", &sp, &["--feature-vertices", "keep"]);
    // terrain
    let t = ["terrain", "--size", "33", "-o", "t.ply"];
    add("terrain", "--method", &t, &["--method", "smooth"]);
    add("terrain", "--size", &t, &["--size", "17"]);
    add("terrain", "--iterations", &["terrain", "-o", "t.ply"], &["--iterations", "4"]);
    add("terrain", "--hurst", &t, &["--hurst", "0.3"]);
    add("terrain", "--roughness", &t, &["--roughness", "1.5"]);
    add("terrain", "--sigma", &t, &["--sigma", "2"]);
    add("terrain", "--seed", &t, &["--seed", "1"]);
    add("terrain", "--distribution", &t, &["--distribution", "uniform"]);
    add("terrain", "--mean", &t, &["--mean", "0.5"]);
    add("terrain", "--variance", &t, &["--variance", "2"]);
    add("terrain", "--corners", &t, &["--corners", "1,1,1,1"]);
    add("terrain", "--applet", &t, &["--applet"]);
    add("terrain", "--width", &t, &["--width", "5"]);
    add("terrain", "--depth", &t, &["--depth", "5"]);
    add("terrain", "--max-height", &t, &["--max-height", "3"]);
    add("terrain", "--sea-level", &t, &["--sea-level", "0"]);
    add("terrain", "--colors", &t, &["--colors", "0,0,1;0,1,0;1,1,0;1,0,0;1,1,1"]);
    add("terrain", "--peak-height", &t, &["--peak-height", "0.2"]);
    add("terrain", "--grid", &t, &["--grid", "triangle"]);
    add("terrain", "--tile", &t, &["--tile", "1,0", "--tile-size", "17"]);
    add("terrain", "--tile-size", &t, &["--tile-size", "17"]);
    add("terrain", "--range", &["terrain", "--size", "33", "-o", "t.png"], &["--range", "-1,1"]);
    add("terrain", "--preview", &t, &["--preview", "p.png"]);
    add("terrain", "--erode", &t, &["--erode", "thermal"]);
    let eroded = ["terrain", "--size", "33", "-o", "t.ply", "--erode", "thermal"];
    add("terrain", "--erode-iterations", &eroded, &["--erode-iterations", "5"]);
    add("terrain", "--talus", &eroded, &["--talus", "10"]);
    let rained = ["terrain", "--size", "33", "-o", "t.ply", "--erode", "hydraulic", "--erode-iterations", "10"];
    add("terrain", "--rain", &rained, &["--rain", "0.03"]);
    add("terrain", "--evaporation", &rained, &["--evaporation", "5"]);
    add("terrain", "--capacity", &rained, &["--capacity", "2"]);
    add("terrain", "--dissolving", &rained, &["--dissolving", "0.8"]);
    add("terrain", "--deposition", &rained, &["--deposition", "0.8"]);
    add("terrain", "--time-step", &rained, &["--time-step", "0.1"]);
    let rained_heightmap =
        ["terrain", "--size", "33", "-o", "t.png", "--erode", "hydraulic", "--erode-iterations", "10"];
    add("terrain", "--layers", &rained_heightmap, &["--layers", "flow"]);
    add("terrain", "--preset", &["terrain", "--size", "33", "-o", "t.raw"], &["--preset", "unity"]);
    add("terrain", "--sidecar", &["terrain", "--size", "33", "-o", "t.png"], &["--sidecar"]);
    let dual = ["terrain", "--method", "dual", "--levels", "3", "-o", "t.ply"];
    add("terrain", "--x", &dual, &["--x", "2,0,0"]);
    add("terrain", "--y", &dual, &["--y", "0,2,0.5"]);
    add("terrain", "--levels", &dual, &["--levels", "4"]);
    add("terrain", "--deterministic", &dual, &["--deterministic"]);
    add("terrain", "--cross-product", &dual, &["--cross-product"]);
    add("terrain", "--no-mean-correction", &dual, &["--no-mean-correction"]);
    add("terrain", "--steps", &dual, &["--steps", "steps"]);
    // --format makes an output name without a telling extension work.
    cases.push(Case {
        sub: "terrain",
        flag: "--format",
        base: owned(&["terrain", "--size", "33", "-o", "t.out"]),
        with: owned(&["terrain", "--size", "33", "-o", "t.out", "--format", "f32"]),
        may_fix: true,
    });
    // terrain plan: each generation flag as in terrain's case, on a plan (the plan refuses
    // what a tile would refuse; what a tile makes of a flag is terrain's case).
    let without_output = |args: &[String]| -> Vec<String> {
        let mut kept = Vec::new();
        let mut skip = false;
        for a in &args[1..] {
            if std::mem::take(&mut skip) {
                continue;
            }
            if a == "-o" {
                skip = true;
                continue;
            }
            kept.push(a.clone());
        }
        kept
    };
    let plan = owned(&["terrain", "plan", "--tile-size", "17", "-o", "p"]);
    let terrain_cases: Vec<(&'static str, Vec<String>, Vec<String>)> = cases
        .iter()
        .filter(|c| {
            c.sub == "terrain" && !["--format", "--tile-size", "--tile", "--stream", "--band"].contains(&c.flag)
        })
        .map(|c| {
            if c.base.iter().any(|a| a == "dual") {
                // A plan tiles heightfields: dual's flags are tried alone on a classic plan.
                let added = if c.with.len() > c.base.len() {
                    c.with[c.base.len()..].to_vec()
                } else {
                    // The flag's value replaced in place: the flag and its new value.
                    let at = c.with.iter().zip(&c.base).position(|(a, b)| a != b).expect("a changed value");
                    c.with[at - 1..=at].to_vec()
                };
                (c.flag, Vec::new(), added)
            } else {
                (c.flag, without_output(&c.base), without_output(&c.with))
            }
        })
        .collect();
    for (flag, base, with) in terrain_cases {
        cases.push(Case {
            sub: "terrain plan",
            flag,
            base: plan.iter().cloned().chain(base).collect(),
            with: plan.iter().cloned().chain(with).collect(),
            may_fix: false,
        });
    }
    let p = owned(&["terrain", "plan", "--size", "33", "--tile-size", "17", "-o", "p"]);
    let with_format = p.iter().cloned().chain(owned(&["--format", "f32"])).collect();
    cases.push(Case { sub: "terrain plan", flag: "--format", base: p, with: with_format, may_fix: false });
    // --repair and --force make a refused base work.
    let mut fixes = |sub: &'static str, flag: &'static str, base: Vec<String>| {
        let mut with = base.clone();
        with.push(flag.to_string());
        cases.push(Case { sub, flag, base, with, may_fix: true });
    };
    for (sub, base) in [
        ("analyze", owned(&["analyze", &broken, "-o", "a.ply"])),
        ("compare", owned(&["compare", &broken, "--methods", "asperity", "--target-vertices", "4", "--json"])),
        ("convert", owned(&["convert", &broken, "v.off"])),
        ("detail", owned(&["detail", &broken, "-o", "d.ply"])),
        ("info", owned(&["info", &broken, "--json"])),
        (
            "refine",
            owned(&["refine", &broken, "--region", "box = { min = [0, 0, 0], max = [1, 1, 1] }", "-o", "rf.ply"]),
        ),
        // The picture of a repaired mesh can look the same: the report says what changed.
        ("render", owned(&["render", &broken, "-o", "r.png", "--size", "64,48", "--json"])),
        ("simplify", owned(&["simplify", &broken, "-o", "s.ply"])),
        ("simplify plan", owned(&["simplify", "plan", &broken, "--chunks", "1", "--target-vertices", "4", "-o", "p"])),
    ] {
        fixes(sub, "--repair", base);
    }
    for (sub, base) in [
        ("analyze", owned(&["analyze", "in.ply", "-o", "in.ply"])),
        ("convert", owned(&["convert", "in.ply", "in.ply"])),
        ("detail", owned(&["detail", "in.ply", "-o", "in.ply"])),
        (
            "refine",
            owned(&["refine", "in.ply", "--region", "box = { min = [0, 0, 0], max = [1, 1, 1] }", "-o", "in.ply"]),
        ),
        ("simplify", owned(&["simplify", "in.ply", "-o", "in.ply"])),
    ] {
        fixes(sub, "--force", base);
    }
    let plan = ["simplify", "plan", &fandisk, "--chunks", "2", "-o", "p", "--target-vertices", "400"];
    cases.push(Case {
        sub: "simplify plan",
        flag: "--target-vertices",
        base: owned(&plan[..7]),
        with: owned(&plan),
        may_fix: true,
    });
    cases
}

/// What a run leaves: its exit code, every file in its folder (the inputs it was given
/// removed) and, for the commands that report on stdout, the JSON report without timings.
#[derive(Debug, PartialEq)]
struct Outcome {
    code: Option<i32>,
    files: BTreeMap<PathBuf, Vec<u8>>,
    report: Option<serde_json::Value>,
    stderr: String,
}

fn run(args: &[String], meshes: &Path) -> Outcome {
    let dir = temp_dir();
    let relief = "seed = 3\n\n[[step]]\nop = \"noise\"\nlevel = -1\n\
                  noise = { kind = \"fbm\", amplitude = 0.4, frequency = 12.0, attenuate = false }\n";
    std::fs::write(dir.path().join("relief.toml"), relief).unwrap();
    let unguarded = format!("{relief}\n[hierarchy]\nintersection_guard = false\n");
    std::fs::write(dir.path().join("unguarded.toml"), unguarded).unwrap();
    std::fs::copy(meshes.join("eight.off"), dir.path().join("in.ply.off")).unwrap();
    let eight = asperity::io::read(&meshes.join("eight.off")).unwrap().mesh;
    asperity::io::write(&eight, &dir.path().join("in.ply"), Default::default()).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_asperity"))
        .args(args)
        .current_dir(dir.path())
        .env("RAYON_NUM_THREADS", "1")
        .output()
        .expect("run asperity");
    let mut files = BTreeMap::new();
    let mut stack = vec![dir.path().to_path_buf()];
    while let Some(folder) = stack.pop() {
        for entry in std::fs::read_dir(&folder).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else {
                files.insert(path.strip_prefix(dir.path()).unwrap().to_path_buf(), std::fs::read(&path).unwrap());
            }
        }
    }
    files.remove(Path::new("relief.toml"));
    files.remove(Path::new("unguarded.toml"));
    files.remove(Path::new("in.ply.off"));
    let report = args.iter().any(|a| a == "--json").then(|| {
        let mut value: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap_or(serde_json::Value::Null);
        strip_timings(&mut value);
        value
    });
    Outcome { code: out.status.code(), files, report, stderr: String::from_utf8_lossy(&out.stderr).into_owned() }
}

/// Removes every field that holds a time (its name mentions seconds or milliseconds).
fn strip_timings(value: &mut serde_json::Value) {
    match value {
        serde_json::Value::Object(map) => {
            map.retain(|k, _| !k.contains("second") && !k.contains("milli"));
            map.values_mut().for_each(strip_timings);
        }
        serde_json::Value::Array(items) => items.iter_mut().for_each(strip_timings),
        _ => {}
    }
}

#[test]
fn every_flag_changes_the_output_or_is_refused() {
    let meshes = shared_meshes();
    let broken = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/bad/nonmanifold-edge.off");
    let cases = cases(&meshes, &broken);
    // The table covers every flag the command line has.
    for (sub, flags) in asperity::cli::subcommand_flags() {
        for flag in flags.iter().filter(|f| !["--output", "--version"].contains(&f.as_str())) {
            let covered = cases.iter().any(|c| c.sub == sub && c.flag == flag)
                || EXEMPT.iter().any(|&(s, f, _)| s == sub && f == flag);
            assert!(
                covered,
                "asperity {sub} {flag} has no case: add one (or an exemption saying which test covers it)"
            );
        }
    }
    let failures: Vec<String> = cases
        .par_iter()
        .filter_map(|c| {
            let (base, with) = (run(&c.base, &meshes), run(&c.with, &meshes));
            let name = format!("asperity {} {}", c.sub, c.flag);
            let differ = with.files != base.files || with.report != base.report;
            match (base.code, with.code) {
                (Some(0), Some(2)) => None,
                (Some(0), Some(0)) if differ => None,
                (Some(2), Some(0)) if c.may_fix => None,
                (Some(0), Some(0)) => Some(format!("{name}: the output is byte-identical with and without it")),
                (Some(0), code) => Some(format!("{name}: exit {code:?}: {}", with.stderr)),
                (code, _) => Some(format!("{name}: the base command gave exit {code:?}: {}", base.stderr)),
            }
        })
        .collect();
    assert!(failures.is_empty(), "{} flag(s) do nothing:\n{}", failures.len(), failures.join("\n"));
}
