//! The detail recipe parser on arbitrary text (see `asperity::fuzzing::recipe`).
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| asperity::fuzzing::recipe(data));
