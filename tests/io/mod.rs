//! Reading, writing and checking meshes: every format's round trip, glTF and GLB, texture
//! coordinates, validation and repair, bad files and the fuzzers' saved inputs.

mod bad_input;
mod fuzz_regressions;
pub mod glb;
mod gltf_read;
mod lean;
mod repair;
mod roundtrip;
mod uv;
mod validation;
