//! The faces of the level that intersect one another, kept across levels for the guard's
//! question "did the level before already cross here?" ([`super::guard`]'s
//! `crossings_before`) (#35).
//!
//! On an assembly whose parts interpenetrate, every try of a level plans clusters along the
//! parts' crossings, their new triangles cut the other part as the faces they replace did,
//! and the guard asked CGAL again, for every such pair, whether some face of the star
//! crossed the other face: samurai-monastery's build made 28.6M such exact tests over its
//! 863 tries, most of them the same tests again. Whether two triangles of fixed vertices
//! intersect is a fact of their vertex ids alone (positions never move and the rules are
//! the guard's own), so it is remembered: once it pays, the pairs of the level's faces that
//! intersect are listed with the guard's own test, and from then on every intersecting
//! pair a guard round finds is added. That keeps the list complete for every level: a face
//! a level makes is a planned triangle of a kept plan, and every intersecting pair it is in
//! is found by a round (against the faces its level keeps and the other planned triangles in
//! the first round, against a face that comes back in the round that restores it).
//! Pairs of faces no longer in the level stay listed: they are still facts, never asked.

use rustc_hash::FxHashMap;
use smallvec::SmallVec;

use super::face_key;
use super::intersections::{AddedPairs, AddedRuns, triangle_intersections_across};
use crate::error::Result;

/// Each face (its key) with the faces it intersects.
type CrossingLists = FxHashMap<[u32; 3], SmallVec<[[u32; 3]; 2]>>;

/// Intersecting pairs of faces (by their [`face_key`]s), complete for the level's faces once
/// listed.
pub(super) struct KnownCrossings {
    /// Each face with the faces it intersects; `None` until listed.
    by_face: Option<CrossingLists>,
    /// Whether listing is allowed: not with obstacles, whose faces are not the level's and
    /// may share a planned vertex, so a round need not test them against a plan's triangles.
    allowed: bool,
    /// Exact pair tests asked for while not listed.
    asked: usize,
}

impl KnownCrossings {
    pub(super) fn new(allowed: bool) -> Self {
        KnownCrossings { by_face: None, allowed, asked: 0 }
    }

    /// Whether the list is complete for the level's faces (else the caller tests).
    pub(super) fn listed(&self) -> bool {
        self.by_face.is_some()
    }

    /// Counts `tests` exact tests made without the list.
    pub(super) fn asked(&mut self, tests: usize) {
        self.asked += tests;
    }

    /// Lists the intersecting pairs of `level_faces` once the tests asked for without the
    /// list outnumber the faces (listing costs about one guard pass over them; a mesh
    /// that never crosses itself never pays it).
    pub(super) fn list_when_it_pays(&mut self, positions: &[glam::DVec3], level_faces: &[[u32; 3]]) -> Result<()> {
        // Debug builds list at once, so that every build that tests a crossing checks the
        // list against the tests (`guard::crossings_before`).
        let pays = if cfg!(debug_assertions) { self.asked > 0 } else { self.asked > level_faces.len() };
        if self.by_face.is_some() || !self.allowed || !pays {
            return Ok(());
        }
        let pairs = triangle_intersections_across(positions, &[], level_faces, AddedPairs::Tested, AddedRuns::Single)?;
        self.by_face = Some(FxHashMap::default());
        for [a, b] in pairs {
            self.add(level_faces[a as usize], level_faces[b as usize]);
        }
        Ok(())
    }

    /// Adds an intersecting pair (when listed; else nothing is kept).
    pub(super) fn add(&mut self, a: [u32; 3], b: [u32; 3]) {
        let Some(by_face) = self.by_face.as_mut() else { return };
        let (a, b) = (face_key(a), face_key(b));
        for (x, y) in [(a, b), (b, a)] {
            let crossing = by_face.entry(x).or_default();
            if !crossing.contains(&y) {
                crossing.push(y);
            }
        }
    }

    /// The listed faces that `t` intersects (keys).
    pub(super) fn crossing(&self, t: [u32; 3]) -> &[[u32; 3]] {
        self.by_face.as_ref().and_then(|m| m.get(&face_key(t))).map_or(&[], |c| c.as_slice())
    }
}
