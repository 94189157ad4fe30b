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
