//! Every input the fuzzers (`make fuzz`) ever failed on, saved under
//! `tests/data/fuzz/<target>/`, replayed through the target's body in `asperity::fuzzing`;
//! plus the hostile corpus through every reader and small meshes through the pipeline.

use std::path::{Path, PathBuf};

use asperity::fuzzing;
use asperity::io::Format;

const READERS: [(&str, Format); 5] = [
    ("read_obj", Format::Obj),
    ("read_ply", Format::Ply),
    ("read_off", Format::Off),
    ("read_stl", Format::Stl),
    ("read_glb", Format::Glb),
];

fn files(dir: &Path) -> Vec<PathBuf> {
    let Ok(entries) = std::fs::read_dir(dir) else { return Vec::new() };
    let mut files: Vec<PathBuf> = entries.map(|e| e.unwrap().path()).filter(|p| p.is_file()).collect();
    files.sort();
    files
}

fn data(folder: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data").join(folder)
}

/// Runs `body` on every saved input of `target`.
fn replay(target: &str, body: impl Fn(&[u8])) -> usize {
    let inputs = files(&data("fuzz").join(target));
    for path in &inputs {
        eprintln!("replaying {}", path.display());
        body(&std::fs::read(path).unwrap());
    }
    inputs.len()
}

#[test]
fn saved_fuzz_finds_stay_fixed() {
    let known = ["read_obj", "read_ply", "read_off", "read_stl", "read_glb", "recipe", "pipeline"];
    for entry in std::fs::read_dir(data("fuzz")).into_iter().flatten() {
        let name = entry.unwrap().file_name().to_string_lossy().to_string();
        assert!(known.contains(&name.as_str()), "tests/data/fuzz/{name} is no fuzz target");
    }
    let mut replayed = 0;
    for (target, format) in READERS {
        replayed += replay(target, |bytes| fuzzing::read(format, bytes));
    }
    replayed += replay("recipe", fuzzing::recipe);
    replayed += replay("pipeline", fuzzing::pipeline);
    eprintln!("{replayed} saved fuzz inputs replayed");
}

#[test]
fn every_reader_survives_every_hostile_file() {
    for path in files(&data("bad")) {
        let bytes = std::fs::read(&path).unwrap();
        for (_, format) in READERS {
            fuzzing::read(format, &bytes);
        }
        fuzzing::recipe(&bytes);
        fuzzing::pipeline(&bytes);
    }
}

#[test]
fn the_pipeline_body_survives_simple_byte_patterns() {
    // A tetrahedron (the fuzz seed), then deterministic pseudo-random byte strings.
    let tetrahedron =
        b"\x01\x08\x08\x08\x09\x08\x08\x08\x09\x08\x08\x08\x09\x00\x02\x01\x00\x01\x03\x00\x03\x02\x01\x02\x03";
    fuzzing::pipeline(tetrahedron);
    let mut state = 0x9e37_79b9_7f4a_7c15_u64;
    for len in 0..300 {
        let bytes: Vec<u8> = (0..len)
            .map(|_| {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                (state >> 24) as u8
            })
            .collect();
        fuzzing::pipeline(&bytes);
    }
}
