//! An interrupted run (SIGINT, SIGTERM) leaves no partial output file: the temporary file
//! being written is removed and the process dies by the signal, as shells expect.

use std::os::unix::process::ExitStatusExt;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use crate::common::temp_dir;

/// Names of the files in `dir`.
fn listing(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect()
}

/// Starts a long streamed terrain, waits until its temporary output holds data, sends
/// `signal`, and checks that the folder is empty once the process has died by it.
fn interrupt_a_streamed_terrain(signal: &str, number: i32, output: &str) {
    let tmp = temp_dir();
    let mut child = Command::new(env!("CARGO_BIN_EXE_asperity"))
        .args(["terrain", "--size", "16385", "--stream", "-o", output])
        .current_dir(tmp.path())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let started = Instant::now();
    loop {
        let writing = listing(tmp.path()).iter().any(|name| {
            name.starts_with(".asperity-") && std::fs::metadata(tmp.path().join(name)).is_ok_and(|m| m.len() > 0)
        });
        if writing {
            break;
        }
        assert!(child.try_wait().unwrap().is_none(), "the run ended before it was interrupted");
        assert!(started.elapsed() < Duration::from_secs(60), "no temporary output appeared");
        std::thread::sleep(Duration::from_millis(5));
    }
    let sent = Command::new("kill").args([&format!("-{signal}"), &child.id().to_string()]).status().unwrap();
    assert!(sent.success());
    let status = child.wait().unwrap();
    assert_eq!(status.signal(), Some(number), "{status:?}");
    assert_eq!(listing(tmp.path()), Vec::<String>::new(), "left behind after SIG{signal}");
}

#[test]
fn sigint_leaves_no_partial_output() {
    interrupt_a_streamed_terrain("INT", 2, "terrain.ply");
}

#[test]
fn sigterm_leaves_no_partial_output() {
    interrupt_a_streamed_terrain("TERM", 15, "terrain.obj");
}

/// A progress callback sees the build's reports on the calling thread and, by returning
/// false, stops it with `Error::Cancelled` naming where; the same build without a stop is
/// unchanged by being watched.
#[test]
fn a_progress_callback_watches_and_cancels_a_hierarchy_build() {
    use std::sync::{Arc, Mutex};

    use asperity::hierarchy::{SimplifyOptions, build};
    use asperity::mesh::primitives::icosphere;
    use asperity::progress::cancellable;

    let mesh = icosphere(1.0, 4);
    let options = SimplifyOptions { target_vertices: Some(40), ..SimplifyOptions::default() };
    let seen: Arc<Mutex<Vec<(String, u64, u64)>>> = Arc::default();
    let log = Arc::clone(&seen);
    let watched = cancellable(
        Box::new(move |stage, done, total| {
            log.lock().unwrap().push((stage.to_string(), done, total));
            true
        }),
        || build(&mesh, &options),
    )
    .unwrap();
    let reports = seen.lock().unwrap().clone();
    assert!(reports.len() >= 3, "{reports:?}");
    assert!(reports.iter().all(|(_, done, total)| done <= total), "{reports:?}");
    let plain = build(&mesh, &options).unwrap();
    assert_eq!(watched.base_triangles, plain.base_triangles, "watching changed the build");

    // Stop at the third report.
    let calls = Arc::new(Mutex::new(0));
    let counter = Arc::clone(&calls);
    let stopped = cancellable(
        Box::new(move |_, _, _| {
            let mut n = counter.lock().unwrap();
            *n += 1;
            *n < 3
        }),
        || build(&mesh, &options),
    );
    match stopped {
        Err(e @ asperity::Error::Cancelled { .. }) => {
            assert_eq!(e.exit_code(), 130);
            assert!(e.to_string().starts_with("cancelled by the progress callback at "), "{e}");
        }
        other => panic!("expected a cancellation, got {:?}", other.map(|h| h.base_triangles.len())),
    }
    assert_eq!(*calls.lock().unwrap(), 3, "the build stopped at the report that said stop");
}

/// A callback's own reports and `cancellable` calls (a progress bar that runs a quick
/// measure, say) see no callback of the outer call's: no recursion, no double borrow.
#[test]
fn a_progress_callback_may_run_cancellable_work_of_its_own() {
    use std::cell::Cell;
    use std::rc::Rc;

    use asperity::progress::{cancellable, report};

    let outer_calls = Rc::new(Cell::new(0));
    let inner_calls = Rc::new(Cell::new(0));
    let (outer, inner) = (Rc::clone(&outer_calls), Rc::clone(&inner_calls));
    let result = cancellable(
        Box::new(move |_, _, _| {
            outer.set(outer.get() + 1);
            report("inside the callback", 1, 2); // not back to this callback
            let inner = Rc::clone(&inner);
            cancellable(
                Box::new(move |_, _, _| {
                    inner.set(inner.get() + 1);
                    true
                }),
                || {
                    report("nested", 1, 1);
                    Ok(())
                },
            )
            .is_ok()
        }),
        || {
            report("outer", 1, 3);
            report("outer", 2, 3);
            Ok(7)
        },
    );
    assert_eq!(result.unwrap(), 7);
    assert_eq!((outer_calls.get(), inner_calls.get()), (2, 2));
}
