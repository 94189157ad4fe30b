//! The GLB reader on arbitrary bytes (see `asperity::fuzzing::read`).
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| asperity::fuzzing::read(asperity::io::Format::Glb, data));
