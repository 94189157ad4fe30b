//! The 4-k hierarchy: its build and levels, quality against the reference decimators,
//! the vertex target and what gives way, region refinement.

mod build;
mod partition;
mod quality;
mod region;
mod targets;
