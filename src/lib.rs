//! asperity — controllable procedural detail on 3D surfaces.
//!
//! Two pipelines share this library: fractal terrain generation and adaptive hierarchical
//! detail mapping on arbitrary meshes (Dembogurski 2014). This crate root wires the
//! modules together; see `docs/ARCHITECTURE.md` for the data flow and
//! `docs/references.md` for the full reference of every paper a doc comment cites.
#![warn(missing_docs)]
#![deny(unsafe_code)]

pub mod analysis;
#[cfg(feature = "cli")]
pub mod cli;
pub mod detail;
pub mod error;
#[allow(unsafe_code)]
pub mod ffi;
#[doc(hidden)]
pub mod fuzzing;
pub mod hierarchy;
mod ids;
pub mod io;
pub mod memory;
pub mod mesh;
pub mod noise;
pub mod progress;
pub mod render;
pub mod request;
pub mod scene;
pub mod terrain;

pub use error::{Error, Location, Result};
pub use mesh::{FaceId, Mesh, VertexId};

/// Without the `cli` feature the integration tests (`tests/main.rs`, which drive the
/// binary) are not built: `cargo test` alone would pass on the unit tests and say nothing.
/// This one fails instead, saying how to run them all.
#[cfg(all(test, not(feature = "cli")))]
mod without_the_command_line {
    #[test]
    fn the_integration_tests_need_the_cli_feature() {
        panic!(
            "the integration tests (tests/main.rs) drive the command line, the `cli` feature: run `make test`, \
             or `cargo test --features cli`"
        );
    }
}
