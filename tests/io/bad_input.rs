//! Hostile files (`tests/data/bad/`, outcomes in its `expected.toml`): readers give
//! `Error::Parse` naming the file and where, never a panic, and refuse absurd counts before
//! allocating; files the readers accept but the hierarchy cannot take are typed topology
//! errors (mended by `--repair`). Through the CLI every refused one exits 2 with one line and
//! writes nothing; tolerated ones (BOM, mixed line endings) convert.

use asperity::io;
use asperity::{Error, Location};

use std::path::{Path, PathBuf};

use crate::common::temp_dir;

/// `tests/data/bad/expected.toml`: every hostile file and its expected outcome.
#[derive(Debug, serde::Deserialize)]
struct Manifest {
    file: Vec<Expected>,
}

#[derive(Debug, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Expected {
    name: String,
    /// Where a reader's error points: `file`, `line N` or `byte N` (reader errors only).
    at: Option<String>,
    /// A phrase of the message.
    says: String,
    /// `simplify`: the readers accept the file and simplify must refuse it; `convert-stl`,
    /// `convert-glb`: the readers accept it and converting to that format must refuse it;
    /// `accept`: the readers take it (`says` is then part of convert's report). Default:
    /// readers refuse.
    command: Option<String>,
    /// What `--repair` reports when it makes the file acceptable to the command.
    repair: Option<String>,
}

fn bad_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/bad")
}

fn manifest() -> Vec<Expected> {
    let text = std::fs::read_to_string(bad_dir().join("expected.toml")).unwrap();
    toml::from_str::<Manifest>(&text).unwrap().file
}

fn location(at: &str) -> Location {
    match at.split_once(' ') {
        None if at == "file" => Location::File,
        Some(("line", n)) => Location::Line(n.parse().unwrap()),
        Some(("byte", n)) => Location::Byte(n.parse().unwrap()),
        Some(("mesh", n)) => Location::Element("mesh", n.parse().unwrap()),
        Some(("node", n)) => Location::Element("node", n.parse().unwrap()),
        _ => panic!("bad `at` in expected.toml: {at}"),
    }
}

#[test]
fn the_corpus_has_every_file_and_nothing_else() {
    let listed: std::collections::BTreeSet<String> = manifest().into_iter().map(|e| e.name).collect();
    let present: std::collections::BTreeSet<String> = std::fs::read_dir(bad_dir())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n != "expected.toml")
        .collect();
    assert_eq!(listed, present);
    assert!(listed.len() >= 30, "{} hostile files", listed.len());
}

#[test]
fn every_bad_file_is_a_located_parse_error() {
    for c in manifest().into_iter().filter(|c| c.command.is_none()) {
        let path = bad_dir().join(&c.name);
        match io::read(&path) {
            Err(e @ Error::Parse { .. }) => {
                let Error::Parse { path: p, at, msg } = &e else { unreachable!() };
                assert_eq!(p, &path, "{}", c.name);
                assert_eq!(at, &location(c.at.as_deref().expect("reader cases say where")), "{}: {e}", c.name);
                assert!(msg.contains(&c.says), "{}: `{msg}` should say `{}`", c.name, c.says);
                let shown = e.to_string();
                assert!(shown.contains(&c.name) && !shown.contains('\n'), "{shown}");
                assert_eq!(e.exit_code(), 2);
            }
            other => panic!("{}: expected a parse error, got {other:?}", c.name),
        }
    }
}

#[test]
fn the_cli_refuses_every_bad_file_with_one_line_and_writes_nothing() {
    let tmp = temp_dir();
    for c in manifest() {
        let input = bad_dir().join(&c.name);
        let input = input.to_str().unwrap();
        let args: Vec<&str> = match c.command.as_deref() {
            None => vec!["convert", input, "out.ply"],
            Some("simplify") => vec!["simplify", input, "--target-vertices", "3", "-o", "out.ply"],
            Some("convert-stl") => vec!["convert", input, "out.stl"],
            Some("convert-glb") => vec!["convert", input, "out.glb"],
            Some("accept") => continue,
            Some(other) => panic!("unknown command {other} in expected.toml"),
        };
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_asperity"))
            .args(&args)
            .current_dir(tmp.path())
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{}: {stderr}", c.name);
        assert_eq!(stderr.lines().count(), 1, "{}: one line: {stderr}", c.name);
        assert!(stderr.contains(&c.name) && stderr.contains(&c.says), "{}: {stderr}", c.name);
        assert!(!stderr.contains("panicked"), "{stderr}");
        let left: Vec<_> = std::fs::read_dir(tmp.path()).unwrap().collect();
        assert!(left.is_empty(), "{}: left {left:?}", c.name);
    }
}

#[test]
fn a_missing_file_is_an_io_error_naming_it() {
    let err = io::read(std::path::Path::new("/nonexistent/mesh.off")).unwrap_err();
    assert!(matches!(err, Error::Io { .. }));
    assert!(err.to_string().contains("/nonexistent/mesh.off"));
    assert_eq!(err.exit_code(), 2);
}

#[test]
fn tolerated_files_read_and_convert() {
    let tmp = temp_dir();
    for c in manifest().into_iter().filter(|c| c.command.as_deref() == Some("accept")) {
        let input = bad_dir().join(&c.name);
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_asperity"))
            .args(["convert", input.to_str().unwrap(), "out.ply"])
            .current_dir(tmp.path())
            .output()
            .unwrap();
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(out.status.success(), "{}: {}", c.name, String::from_utf8_lossy(&out.stderr));
        assert!(stdout.contains(&c.says), "{}: {stdout}", c.name);
        let converted = io::read(&tmp.path().join("out.ply")).unwrap().mesh;
        assert_eq!(converted, io::read(&input).unwrap().mesh, "{}", c.name);
    }
}

#[test]
fn repair_makes_every_repairable_file_simplify() {
    let tmp = temp_dir();
    for c in manifest().into_iter().filter(|c| c.repair.is_some()) {
        let input = bad_dir().join(&c.name);
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_asperity"))
            .args(["simplify", "--repair", input.to_str().unwrap(), "--target-vertices", "3", "-o", "out.ply"])
            .current_dir(tmp.path())
            .output()
            .unwrap();
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(out.status.success(), "{}: {}", c.name, String::from_utf8_lossy(&out.stderr));
        let said = c.repair.as_deref().unwrap();
        assert!(stdout.lines().any(|l| l.starts_with("repair: ") && l.contains(said)), "{}: {stdout}", c.name);
        let report = io::read(&tmp.path().join("out.ply")).unwrap().mesh.validate();
        assert!(report.is_manifold() && report.inconsistently_oriented_edges == 0, "{}: {report:?}", c.name);
        assert_eq!((report.degenerate_faces, report.unreferenced_vertices), (0, 0), "{}", c.name);
        std::fs::remove_file(tmp.path().join("out.ply")).unwrap();
    }
}

#[test]
fn without_repair_topology_errors_say_how_to_fix_them() {
    for c in manifest().into_iter().filter(|c| c.repair.is_some()) {
        let mesh = io::read(&bad_dir().join(&c.name)).unwrap().mesh;
        let err = asperity::hierarchy::build(&mesh, &Default::default()).unwrap_err();
        assert!(matches!(err, Error::Topology { .. }), "{}: {err:?}", c.name);
        assert!(err.to_string().contains("--repair"), "{}: {err}", c.name);
    }
}

/// Runs asperity with `args` in `cwd`, failing the test if it takes more than 10 s.
fn run_within_ten_seconds(args: &[&str], cwd: &Path) -> std::process::Output {
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_asperity"))
        .args(args)
        .current_dir(cwd)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let start = std::time::Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > std::time::Duration::from_secs(10) {
            child.kill().unwrap();
            panic!("asperity {args:?} still running after 10 s");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

#[test]
fn special_files_are_refused_before_they_are_read() {
    // A FIFO would block the reader forever, a link to /dev/zero would be read until memory
    // runs out (#24 item 3).
    let tmp = temp_dir();
    let fifo = tmp.path().join("pipe.off");
    let name = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
    assert_eq!(unsafe { libc::mkfifo(name.as_ptr(), 0o600) }, 0);
    std::os::unix::fs::symlink("/dev/zero", tmp.path().join("zero.stl")).unwrap();
    std::fs::create_dir(tmp.path().join("folder.ply")).unwrap();
    for (file, kind) in [("pipe.off", "a FIFO"), ("zero.stl", "a character device"), ("folder.ply", "a directory")] {
        let out = run_within_ten_seconds(&["convert", file, "out.ply"], tmp.path());
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{file}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{file}: {stderr}");
        assert!(stderr.contains(file) && stderr.contains(kind) && stderr.contains("not a regular file"), "{stderr}");
        assert!(!tmp.path().join("out.ply").exists());
    }
}

#[test]
fn huge_coordinates_simplify_and_compare_as_unit_ones_do() {
    // ±1e90 crashed CGAL's Hausdorff sampler and ±1e300 was called zero-area (#24 item 1):
    // measures are taken in the unit frame, so only an overflowing extent is refused.
    let tmp = temp_dir();
    for name in ["huge-1e90.off", "huge-1e300.off"] {
        let input = bad_dir().join(name);
        for args in [
            vec!["simplify", input.to_str().unwrap(), "--target-vertices", "4", "-o", "out.ply"],
            vec!["compare", input.to_str().unwrap(), "--target-vertices", "4"],
        ] {
            let out = run_within_ten_seconds(&args, tmp.path());
            assert!(out.status.success(), "{name} {}: {}", args[0], String::from_utf8_lossy(&out.stderr));
            let stdout = String::from_utf8_lossy(&out.stdout);
            assert!(stdout.contains("hausdorff 0.000%") && !stdout.contains("NaN"), "{name}: {stdout}");
        }
    }
    let options = asperity::hierarchy::SimplifyOptions {
        keep_features: asperity::hierarchy::KeepFeatures::None,
        ..Default::default()
    };
    let sphere = asperity::mesh::primitives::icosphere(1.0, 3);
    let at_unit = asperity::hierarchy::compare::compare(&sphere, 60, &["asperity"], &options).unwrap();
    // Scaled by powers of two (exact), the unit-frame images are the same bits, so the
    // simplification and its measures are the same; other huge and tiny scales only have
    // to give finite, sensible measures (an icosphere's many exact ties may break apart).
    for scale in [2f64.powi(-600), 2f64.powi(600), 1e-200, 1e200] {
        let mut scaled = sphere.clone();
        scaled.positions.iter_mut().for_each(|p| *p *= scale);
        let rows = asperity::hierarchy::compare::compare(&scaled, 60, &["asperity"], &options).unwrap();
        assert_eq!(rows[0].vertices, 60, "scale {scale:e}");
        let (a, b) = (rows[0].hausdorff, at_unit[0].hausdorff);
        if scale.log2().fract() == 0.0 {
            assert_eq!(a, b, "scale {scale:e}: hausdorff {a} vs {b} at unit scale");
        } else {
            assert!(a.is_finite() && a < 2.0 * b, "scale {scale:e}: hausdorff {a} vs {b} at unit scale");
        }
    }
}

#[test]
fn an_error_left_after_repair_does_not_advise_repair() {
    // #24 item 10: a Möbius strip cannot be oriented; after --repair the message says so
    // instead of suggesting --repair again.
    let tmp = temp_dir();
    let input = bad_dir().join("mobius.off");
    for extra in [&[][..], &["--repair"][..]] {
        let mut args = vec!["simplify", input.to_str().unwrap(), "--target-vertices", "10", "-o", "out.ply"];
        args.extend(extra);
        let out = run_within_ten_seconds(&args, tmp.path());
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{stderr}");
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        assert!(stderr.contains("not orientable") && !stderr.contains("--repair"), "{extra:?}: {stderr}");
    }
    let zero_area = bad_dir().join("zero-area.off");
    let out = run_within_ten_seconds(
        &["simplify", zero_area.to_str().unwrap(), "--target-vertices", "3", "-o", "out.ply"],
        tmp.path(),
    );
    assert!(String::from_utf8_lossy(&out.stderr).contains("--repair fixes it"), "the advice stays where it helps");
}
