//! Seed 002's procedurally generated environment as meshes and one animated glTF scene:
//! flora by stochastic L-systems ([`flora`]), smoke from a particle system, Blinn's
//! metaballs and marching tetrahedra ([`smoke`], [`tetrahedra`]), water with directional
//! waves and a depth attribute ([`water`]), butterflies on pursuit curves
//! ([`butterflies`]), the Menger sponge ([`menger`]), a cabin ([`cabin`]), and their
//! composition over a terrain ([`compose`]). Every generator is deterministic from its
//! seed.

pub mod butterflies;
pub mod cabin;
pub mod compose;
pub mod flora;
pub mod menger;
pub mod smoke;
pub mod tetrahedra;
pub mod water;
