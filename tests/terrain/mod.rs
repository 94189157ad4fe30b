//! Terrain: generation, smoothing, erosion and formats; tiles, streaming and scale.

mod generation;
mod request;
mod scale;
