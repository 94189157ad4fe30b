//! A partitioned build whose chunks job runners run (#40): `simplify plan`, `simplify
//! --plan DIR --chunk-index K` (or the job runners' variables) and `simplify merge` give
//! the bytes `simplify --chunks K` gives, in any order and at any thread count; a rerun
//! skips complete chunks and builds stale or broken ones again; the walkthrough's scripts
//! run unchanged.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use crate::common::{shared_meshes, temp_dir};

fn run(args: &[&str], cwd: &Path, env: &[(&str, &str)]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_asperity")).args(args).envs(env.iter().copied()).current_dir(cwd).output().unwrap()
}

fn ok(args: &[&str], cwd: &Path, env: &[(&str, &str)]) -> String {
    let out = run(args, cwd, env);
    assert!(out.status.success(), "asperity {args:?}: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn refused(args: &[&str], cwd: &Path, env: &[(&str, &str)], phrases: &[&str]) {
    let out = run(args, cwd, env);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "asperity {args:?}: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    for p in phrases {
        assert!(stderr.lines().next().unwrap_or("").contains(p), "asperity {args:?}: `{stderr}` lacks `{p}`");
    }
}

fn read(dir: &Path, file: &str) -> Vec<u8> {
    std::fs::read(dir.join(file)).unwrap_or_else(|e| panic!("{file}: {e}"))
}

const TARGET: [&str; 4] = ["--target-vertices", "1%", "--keep-features", "none"];

#[test]
fn chunks_run_as_processes_in_any_order_give_the_threaded_build() {
    let tmp = temp_dir();
    let dir = tmp.path();
    let input = shared_meshes().join("bunny00.off");
    let input = input.to_str().unwrap();
    let mut threaded = vec!["simplify", input, "--chunks", "4", "-o", "threaded.ply", "--param-out", "threaded-p.ply"];
    threaded.extend(["--levels-out", "threaded-levels", "--lod-out", "threaded.glb"]);
    threaded.extend(TARGET);
    let threaded_report = ok(&[&["--json"], &threaded[..]].concat(), dir, &[]);
    let mut plan = vec!["simplify", "plan", input, "--chunks", "4", "-o", "plan"];
    plan.extend(TARGET);
    ok(&plan, dir, &[]);
    // Merging before the chunks are built names them and the command that builds them.
    refused(&["simplify", "merge", "plan", "-o", "m.ply"], dir, &[], &["4 of 4 chunks are not built (0, 1, 2, 3)"]);
    // Backwards, on one thread and two, chunk 1 as Kubernetes and chunk 0 as Slurm give it.
    ok(&["simplify", "--plan", "plan", "--chunk-index", "3"], dir, &[("RAYON_NUM_THREADS", "1")]);
    ok(&["simplify", "--plan", "plan", "--chunk-index", "2"], dir, &[("RAYON_NUM_THREADS", "2")]);
    ok(&["simplify", "--plan", "plan"], dir, &[("JOB_COMPLETION_INDEX", "1")]);
    ok(&["simplify", "--plan", "plan"], dir, &[("SLURM_ARRAY_TASK_ID", "0")]);
    let merge = ["simplify", "merge", "plan", "-o", "merged.ply", "--param-out", "merged-p.ply"];
    let merged_report = ok(
        &[&["--json"], &merge[..], &["--levels-out", "merged-levels", "--lod-out", "merged.glb"]].concat(),
        dir,
        &[],
    );
    // The reports measure the same base against the same input alike (the Hausdorff
    // distance's samples do not depend on how the input was read or held).
    let report = |json: &str| -> serde_json::Value { serde_json::from_str(json).expect("a JSON report") };
    let (threaded_report, merged_report) = (report(&threaded_report), report(&merged_report));
    for key in ["hausdorff", "output_vertices", "output_faces", "levels", "input_faces", "min_angle_deg"] {
        assert_eq!(threaded_report[key], merged_report[key], "{key}");
    }
    assert!(read(dir, "merged.ply") == read(dir, "threaded.ply"), "the merged base differs from the threaded one");
    assert!(read(dir, "merged-p.ply") == read(dir, "threaded-p.ply"), "the merged parametrization differs");
    assert!(read(dir, "merged.glb") == read(dir, "threaded.glb"), "the merged levels' glTF differs");
    let levels = std::fs::read_dir(dir.join("threaded-levels")).unwrap().count();
    assert!(levels > 20, "{levels} levels");
    for k in 0..levels {
        let file = format!("level_{k:02}.ply");
        assert!(read(&dir.join("merged-levels"), &file) == read(&dir.join("threaded-levels"), &file), "{file} differs");
    }
    // A complete chunk is skipped; a chunk cut short is built again.
    let json = ok(&["--json", "simplify", "--plan", "plan", "--chunk-index", "2"], dir, &[]);
    assert!(json.contains("\"skipped\": true"), "{json}");
    let built = dir.join("plan/chunks/chunk-0003.built");
    let bytes = std::fs::read(&built).unwrap();
    std::fs::write(&built, &bytes[..bytes.len() / 2]).unwrap();
    refused(&["simplify", "merge", "plan", "-o", "m.ply"], dir, &[], &["1 of 4 chunks are not built (3)"]);
    assert!(!dir.join("m.ply").exists(), "a refused merge left its output");
    let json = ok(&["--json", "simplify", "--plan", "plan", "--chunk-index", "3"], dir, &[]);
    assert!(json.contains("\"skipped\": false"), "{json}");
    assert!(std::fs::read(&built).unwrap() == bytes);
    // A chunk changed behind its sidecar's back (same size) is refused by the merge by
    // file and byte.
    let mut flipped = bytes.clone();
    flipped[100] ^= 1;
    std::fs::write(&built, &flipped).unwrap();
    refused(
        &["simplify", "merge", "plan", "-o", "m.ply"],
        dir,
        &[],
        &["chunk-0003.built: byte", "hash does not match"],
    );
    std::fs::write(&built, &bytes).unwrap();
    // Planned again with another target, every chunk is stale.
    let mut again = vec!["simplify", "plan", input, "--chunks", "4", "-o", "plan", "--target-vertices", "2%"];
    again.extend(&TARGET[2..]);
    ok(&again, dir, &[]);
    refused(&["simplify", "merge", "plan", "-o", "m.ply"], dir, &[], &["4 of 4 chunks are not built"]);
    // The merge's input must be the mesh the plan cut; a copy elsewhere is found by --input.
    for k in 0..4 {
        ok(&["simplify", "--plan", "plan", "--chunk-index", &k.to_string(), "-q"], dir, &[]);
    }
    let other = shared_meshes().join("fandisk.off");
    let merge_other = ["simplify", "merge", "plan", "--input", other.to_str().unwrap(), "-o", "m.ply"];
    refused(&merge_other, dir, &[], &["not the mesh this plan cut"]);
    std::fs::copy(shared_meshes().join("bunny00.off"), dir.join("moved.off")).unwrap();
    ok(&["simplify", "merge", "plan", "--input", "moved.off", "-o", "moved.ply"], dir, &[]);
    let over = ["simplify", "merge", "plan", "--input", "moved.off", "-o", "moved.off"];
    refused(&over, dir, &[], &["is both input and output; pass --force"]);
    ok(&[&over[..], &["--force"]].concat(), dir, &[]);
}

/// A binary PLY is read as a stream (neither its bytes nor its normals held whole) and
/// cut into the parts a whole read cuts; a mesh the build refuses is refused with the
/// whole mesh's counts, the plan's topology checked part by part.
#[test]
fn a_plan_streams_a_binary_ply_into_the_parts_a_whole_read_makes() {
    let tmp = temp_dir();
    let dir = tmp.path();
    let off = shared_meshes().join("bunny00.off");
    let off = off.to_str().unwrap();
    ok(&["convert", off, "bunny.ply"], dir, &[]);
    let plan = |input: &str, out: &str| {
        let mut args = vec!["simplify", "plan", input, "--chunks", "4", "-o", out];
        args.extend(TARGET);
        ok(&args, dir, &[])
    };
    let whole = plan(off, "whole");
    let streamed = plan("bunny.ply", "streamed");
    assert!(streamed.contains("bunny.ply, read as a stream =>") && !whole.contains("stream"), "{whole}\n{streamed}");
    for k in 0..4 {
        let file = format!("chunks/chunk-{k:04}.part");
        assert!(read(&dir.join("whole"), &file) == read(&dir.join("streamed"), &file), "{file} differs");
    }
    let json = |d: &str| -> serde_json::Value { serde_json::from_slice(&read(&dir.join(d), "plan.json")).unwrap() };
    assert_eq!(json("whole")["fingerprint"], json("streamed")["fingerprint"], "the plans' fingerprints");
    // Chunks of the streamed plan merge over the input the plan read.
    for k in 0..4 {
        ok(&["simplify", "--plan", "streamed", "--chunk-index", &k.to_string(), "-q"], dir, &[]);
    }
    ok(&["simplify", "merge", "streamed", "-o", "merged.ply", "-q"], dir, &[]);
    // A turned-over face, found by the part that holds it or by the border's stars.
    let mut mesh = asperity::io::read(&dir.join("bunny.ply")).unwrap().mesh;
    for f in [10, mesh.face_count() / 2] {
        mesh.triangles[f].swap(1, 2);
    }
    asperity::io::write(&mesh, &dir.join("flipped.ply"), Default::default()).unwrap();
    let expected = asperity::mesh::ValidationReport::of(&mesh).inconsistently_oriented_edges;
    let counts = format!("0 non-manifold edges, 0 non-manifold vertices, {expected} inconsistently oriented edges");
    let args = ["simplify", "plan", "flipped.ply", "--chunks", "4", "--target-vertices", "1%", "-o", "bad"];
    refused(&args, dir, &[], &["flipped.ply: the mesh is not an oriented manifold", &counts]);
    assert!(!dir.join("bad").exists(), "a refused plan left its folder");
}

#[test]
fn a_plan_refuses_what_its_chunks_would_refuse() {
    let tmp = temp_dir();
    let dir = tmp.path();
    let input = shared_meshes().join("eight.off");
    let input = input.to_str().unwrap();
    refused(&["simplify", "plan", input, "--chunks", "2", "-o", "p"], dir, &[], &["needs a vertex target"]);
    refused(&["simplify", "plan", input, "--target-vertices", "50", "-o", "p"], dir, &[], &["needs --chunks K"]);
    let levels = ["simplify", "plan", input, "--chunks", "2", "--target-vertices", "50", "--levels", "2", "-o", "p"];
    refused(&levels, dir, &[], &["takes no level limit yet (--levels 2)"]);
    let too_many = ["simplify", "plan", input, "--chunks", "100000", "--target-vertices", "50", "-o", "p"];
    refused(&too_many, dir, &[], &["100000 parts"]);
    assert!(!dir.join("p").exists(), "a refused plan left its folder");
    ok(&["simplify", "plan", input, "--chunks", "2", "--target-vertices", "50", "-o", "p"], dir, &[]);
    // --plan takes every setting from the plan.
    refused(
        &["simplify", "--plan", "p", "--chunk-index", "0", "--target-vertices", "9"],
        dir,
        &[],
        &["cannot be used"],
    );
    refused(&["simplify", "--plan", "p", "--chunk-index", "2"], dir, &[], &["outside the plan's 2 chunks (0..1)"]);
    refused(&["simplify", "--plan", "p"], dir, &[], &["--chunk-index K, $JOB_COMPLETION_INDEX"]);
    refused(&["simplify", "--plan", "p"], dir, &[("SLURM_ARRAY_TASK_ID", "one")], &["$SLURM_ARRAY_TASK_ID is \"one\""]);
    refused(&["simplify", "--plan", "nowhere", "--chunk-index", "0"], dir, &[], &["plan.json"]);
    refused(&["simplify", "merge", "nowhere", "-o", "m.ply"], dir, &[], &["plan.json"]);
    std::fs::write(dir.join("p/plan.json"), "{\"version\": 1}").unwrap();
    refused(&["simplify", "merge", "p", "-o", "m.ply"], dir, &[], &["not an asperity simplify plan"]);
}

/// What a user or a job runner can do to a plan's folder between its steps: a build
/// changed behind its sidecar's back is built again by a rerun, a sidecar copied from
/// another chunk does not pass for its own, an edited manifest is refused by name, a
/// forged build (hash made good) is refused by file and byte, and an output that cannot
/// be written is refused before the build, leaving nothing.
#[test]
fn a_damaged_or_edited_plan_is_built_again_or_refused() {
    let tmp = temp_dir();
    let dir = tmp.path();
    let input = shared_meshes().join("eight.off");
    let input = input.to_str().unwrap();
    ok(&["simplify", "plan", input, "--chunks", "4", "--target-vertices", "10%", "-o", "p", "-q"], dir, &[]);
    for k in 0..4 {
        ok(&["simplify", "--plan", "p", "--chunk-index", &k.to_string(), "-q"], dir, &[]);
    }
    ok(&["simplify", "merge", "p", "-o", "first.ply", "-q"], dir, &[]);
    let chunk = |k: usize| dir.join(format!("p/chunks/chunk-{k:04}.built"));
    let sidecar = |k: usize| dir.join(format!("p/chunks/chunk-{k:04}.built.json"));
    // A byte changed, the sidecar intact: the merge refuses it, and a rerun builds it again.
    let bytes = std::fs::read(chunk(2)).unwrap();
    let mut flipped = bytes.clone();
    flipped[200] ^= 0x10;
    std::fs::write(chunk(2), &flipped).unwrap();
    refused(&["simplify", "merge", "p", "-o", "m.ply"], dir, &[], &["chunk-0002.built: byte", "run its chunk again"]);
    let json = ok(&["--json", "simplify", "--plan", "p", "--chunk-index", "2"], dir, &[]);
    assert!(json.contains("\"skipped\": false"), "{json}");
    assert!(std::fs::read(chunk(2)).unwrap() == bytes, "the rebuilt chunk differs");
    // Another chunk's build and sidecar copied over chunk 0's: not chunk 0's.
    let chunk0 = (std::fs::read(chunk(0)).unwrap(), std::fs::read(sidecar(0)).unwrap());
    std::fs::copy(chunk(1), chunk(0)).unwrap();
    std::fs::copy(sidecar(1), sidecar(0)).unwrap();
    refused(&["simplify", "merge", "p", "-o", "m.ply"], dir, &[], &["p: 1 of 4 chunks are not built (0)", "--plan p "]);
    std::fs::write(chunk(0), &chunk0.0).unwrap();
    std::fs::write(sidecar(0), &chunk0.1).unwrap();
    // A forged build whose hash is made good: a removal's vertex repeated.
    let n = asperity::io::read(std::path::Path::new(input)).unwrap().mesh.vertex_count();
    let mut build = asperity::hierarchy::partition::files::read_build(&chunk(3), n).unwrap();
    let original = std::fs::read(chunk(3)).unwrap();
    build.removals[1].vertex = build.removals[0].vertex;
    let size = asperity::hierarchy::partition::files::write_build(&build, &chunk(3)).unwrap();
    assert_eq!(size, std::fs::metadata(chunk(3)).unwrap().len());
    refused(
        &["simplify", "merge", "p", "-o", "m.ply", "--levels-out", "lv"],
        dir,
        &[],
        &["chunk-0003.built: byte", "twice"],
    );
    // ... and built again by a rerun.
    let json = ok(&["--json", "simplify", "--plan", "p", "--chunk-index", "3"], dir, &[]);
    assert!(json.contains("\"skipped\": false"), "{json}");
    assert!(std::fs::read(chunk(3)).unwrap() == original, "the rebuilt chunk differs");
    // Outputs that cannot be written, refused before anything is built or written.
    std::fs::create_dir(dir.join("taken.ply")).unwrap();
    let to_folder = ["simplify", "merge", "p", "-o", "m.ply", "--param-out", "taken.ply", "--levels-out", "lv"];
    refused(&to_folder, dir, &[], &["taken.ply: is a directory"]);
    assert!(!dir.join("m.ply").exists() && !dir.join("lv").exists(), "a refused merge left an output");
    std::fs::create_dir(dir.join("old-levels")).unwrap();
    std::fs::write(dir.join("old-levels/level_99.ply"), "another build's").unwrap();
    refused(
        &["simplify", "merge", "p", "-o", "m.ply", "--levels-out", "old-levels"],
        dir,
        &[],
        &["holds level_99.ply"],
    );
    assert!(
        !dir.join("m.ply").exists() && !dir.join("old-levels/level_00.ply").exists(),
        "a refused merge left an output"
    );
    // --max-memory holds for the plan, the merge (before it reads the input) and --chunks.
    let plan_budget =
        ["simplify", "plan", input, "--chunks", "4", "--target-vertices", "10%", "-o", "q", "--max-memory", "1K"];
    refused(&plan_budget, dir, &[], &["a plan of 634 triangles needs about", "--max-memory budget"]);
    assert!(!dir.join("q").exists(), "a refused plan left its folder");
    refused(&["simplify", "merge", "p", "-o", "m.ply", "--max-memory", "3K"], dir, &[], &["merging a plan of 634"]);
    let chunks_budget =
        ["simplify", input, "--chunks", "4", "--target-vertices", "10%", "-o", "c.ply", "--max-memory", "8K"];
    refused(&chunks_budget, dir, &[], &["a hierarchy of 634 triangles in 4 chunks needs about"]);
    // --chunk-index belongs to --plan.
    let stray = ["simplify", input, "--chunk-index", "2", "--target-vertices", "10%", "-o", "x.ply"];
    refused(&stray, dir, &[], &["--chunk-index belongs to --plan"]);
    // A subcommand's flags given before its name.
    let early = ["simplify", "--chunks", "4", "plan", input, "--target-vertices", "10%", "-o", "q"];
    refused(&early, dir, &[], &["cannot be used with", "a subcommand's flags go after its name"]);
    // An edited manifest: counts (part of the fingerprint: every chunk is stale), the chunk
    // list, the settings.
    let manifest = dir.join("p/plan.json");
    let text = std::fs::read_to_string(&manifest).unwrap();
    let edit = |from: &str, to: &str| {
        assert!(text.contains(from), "plan.json lacks {from}");
        std::fs::write(&manifest, text.replacen(from, to, 1)).unwrap();
    };
    edit(&format!("\"input_vertices\": {n}"), &format!("\"input_vertices\": {}", n + 85));
    refused(&["simplify", "merge", "p", "-o", "m.ply"], dir, &[], &["4 of 4 chunks are not built"]);
    edit("\"index\": 1,", "\"index\": 5,");
    refused(&["simplify", "--plan", "p", "--chunk-index", "2"], dir, &[], &["plan.json: its chunk 1 is not chunk 1"]);
    edit("\"chunks\": 4", "\"chunks\": 3");
    refused(
        &["simplify", "merge", "p", "-o", "m.ply"],
        dir,
        &[],
        &["plan.json: it lists 4 chunks where its settings ask for 3"],
    );
    std::fs::write(&manifest, &text).unwrap();
    ok(&["simplify", "merge", "p", "-o", "again.ply", "-q"], dir, &[]);
    assert!(read(dir, "again.ply") == read(dir, "first.ply"), "the restored plan merges to another base");
}

/// A folder holding `asperity` for the scripts, which find it on the PATH, and that PATH.
fn path_with_asperity(dir: &Path) -> String {
    let bin = dir.join("bin");
    std::fs::create_dir_all(&bin).unwrap();
    std::os::unix::fs::symlink(env!("CARGO_BIN_EXE_asperity"), bin.join("asperity")).unwrap();
    format!("{}:{}", bin.display(), std::env::var("PATH").unwrap_or_default())
}

fn shell(script: &str, cwd: &Path, path: &str) {
    let out = Command::new("bash").args(["-c", script]).current_dir(cwd).env("PATH", path).output().unwrap();
    assert!(out.status.success(), "{script}: {}", String::from_utf8_lossy(&out.stderr));
}

#[test]
fn the_mesh_walkthrough_runs_through_gnu_parallel_slurm_and_kubernetes_unchanged() {
    let tmp = temp_dir();
    let dir = tmp.path();
    let found = std::env::var_os("PATH")
        .and_then(|paths| std::env::split_paths(&paths).map(|p| p.join("parallel")).find(|p| p.is_file()));
    assert!(found.is_some(), "GNU parallel is missing: scripts/install-deps.sh --test installs it (as `make test`)");
    let path = path_with_asperity(dir);
    let examples = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/scale-out");
    let input = shared_meshes().join("elephant.off");
    let input = input.to_str().unwrap();
    ok(&["simplify", input, "--chunks", "4", "--target-vertices", "2%", "-o", "threaded.ply"], dir, &[]);
    // GNU parallel: the three steps in one script.
    let script = examples.join("mesh-parallel.sh");
    shell(
        &format!("INPUT={input} TARGET=2% CHUNKS=4 PLAN_DIR=local BASE=local.ply bash {}", script.display()),
        dir,
        &path,
    );
    assert!(read(dir, "local.ply") == read(dir, "threaded.ply"), "mesh-parallel.sh's base differs");
    let plan =
        |name: &str| ok(&["simplify", "plan", input, "--chunks", "4", "--target-vertices", "2%", "-o", name], dir, &[]);
    // Slurm: the array script as sbatch would run it, task K given SLURM_ARRAY_TASK_ID=K.
    plan("slurm");
    let slurm = examples.join("mesh-slurm-array.sh");
    shell(
        &format!("seq 0 3 | parallel -j 2 'SLURM_ARRAY_TASK_ID={{}} PLAN_DIR=slurm bash {}'", slurm.display()),
        dir,
        &path,
    );
    ok(&["simplify", "merge", "slurm", "-o", "slurm.ply"], dir, &[]);
    assert!(read(dir, "slurm.ply") == read(dir, "threaded.ply"), "the Slurm array's base differs");
    // Kubernetes: the Indexed Job's container command, pod K given JOB_COMPLETION_INDEX=K,
    // with the plan's volume mounted where the manifest says.
    let manifest = std::fs::read_to_string(examples.join("mesh-kubernetes-indexed-job.yaml")).unwrap();
    let line = manifest.lines().find(|l| l.trim_start().starts_with("command:")).expect("the Job names a command");
    let command: Vec<String> = serde_json::from_str(line.trim_start().trim_start_matches("command:").trim()).unwrap();
    let mount = manifest.lines().find_map(|l| l.trim().strip_prefix("mountPath:")).unwrap().trim().to_string();
    assert!(manifest.contains("completionMode: Indexed"));
    let planned = command.last().unwrap().replacen(&mount, "plans", 1);
    std::fs::create_dir_all(dir.join("plans")).unwrap();
    plan(&planned);
    let command = [&command[..command.len() - 1], std::slice::from_ref(&planned)].concat().join(" ");
    shell(&format!("seq 0 3 | parallel -j 2 'JOB_COMPLETION_INDEX={{}} {command}'"), dir, &path);
    ok(&["simplify", "merge", &planned, "-o", "k8s.ply"], dir, &[]);
    assert!(read(dir, "k8s.ply") == read(dir, "threaded.ply"), "the Indexed Job's base differs");
}
