//! asperity's integration tests, in one binary so the C++ libraries are linked once.

mod analysis;
mod bad_input;
mod cli;
mod cli_flags;
mod common;
mod detail;
mod determinism;
mod ffi;
mod fuzz_regressions;
mod glb;
mod gltf_read;
mod hierarchy;
mod hierarchy_quality;
mod hierarchy_targets;
mod interrupt;
mod io_roundtrip;
mod noise;
mod readme;
mod region;
mod render;
mod repair;
mod scene;
mod terrain;
mod terrain_scale;
mod uv;
mod validation;
