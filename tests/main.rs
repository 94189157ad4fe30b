//! asperity's integration tests, in one binary so the C++ libraries are linked once,
//! grouped by area.

mod analysis;
mod cli;
mod common;
mod detail;
mod determinism;
mod ffi;
mod front_ends;
mod hierarchy;
mod io;
mod noise;
mod render;
mod scene;
mod terrain;
