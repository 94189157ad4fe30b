//! Small meshes from arbitrary bytes through repair, simplify, refine and analyze (see
//! `asperity::fuzzing::pipeline`).
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| asperity::fuzzing::pipeline(data));
