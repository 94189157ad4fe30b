//! A partitioned build's stages: each part built with its border fenced ([`build_part`],
//! in any process), then the parts' bases joined and the build continued on them
//! ([`join_parts`]); [`build_partitioned`] runs both in one process, the parts in
//! parallel.

use std::borrow::Cow;
use std::time::Instant;

use rayon::prelude::*;

use glam::DVec3;
use rustc_hash::{FxHashMap, FxHashSet};

use super::{Part, Partition};
use crate::analysis::Quadric;
use crate::error::{Error, Result};
use crate::hierarchy::simplify::Continuation;
use crate::hierarchy::{
    BOUNDARY_WEIGHT, Hierarchy, Obstacles, ParamPoint, Removal, SimplifyOptions, VertexClass, face_key,
};
use crate::mesh::Mesh;

/// How much of a part's inside its build keeps, as a multiple of the share of the input
/// the target keeps (at most all of it): the joined build then chooses among 4 times the
/// vertices it keeps, across the borders the parts could not simplify over.
const PART_HEADROOM: f64 = 4.0;

/// What a part's build hands to the join, in input vertex ids: its base domain, its
/// removals by its own steps, and where its removed vertices lie on its base.
#[derive(Debug, Clone, PartialEq)]
pub struct PartBuild {
    /// The part's base domain.
    pub base_triangles: Vec<[u32; 3]>,
    /// Its removals in order (`step` counts the part's own steps).
    pub removals: Vec<Removal>,
    /// The link edges the removals' refinement flips (see [`Removal::restore`]).
    pub restore: Vec<[u32; 2]>,
    /// `removals[step_starts[s]..step_starts[s + 1]]` were removed by the part's step s.
    pub step_starts: Vec<usize>,
    /// Each removed vertex's point on the part's base domain.
    pub seeds: Vec<(u32, ParamPoint)>,
    /// The feature class the part found for each vertex of its base (a border vertex once
    /// per copy), which the continuation takes instead of classifying the input again.
    pub classes: Vec<(u32, VertexClass)>,
    /// Each vertex of its base (a border vertex once per copy) with its share of the
    /// quadric a one-piece build would have for it there ([`Part::border_quadrics`],
    /// `handed_over_quadrics`): the continuation sums the shares.
    pub quadrics: Vec<(u32, Quadric)>,
}

impl PartBuild {
    /// The part's steps.
    pub fn steps(&self) -> usize {
        self.step_starts.len().saturating_sub(1)
    }
}

/// The vertices a part's build keeps: its border, and `PART_HEADROOM` times the share of
/// the input's `input_vertices` that the `target` keeps of its inside (at least one).
pub fn part_goal(part: &Part, target: usize, input_vertices: usize) -> usize {
    let keep_share = (PART_HEADROOM * target as f64 / input_vertices.max(1) as f64).min(1.0);
    let inside = part.mesh.vertex_count() - part.border.len();
    let goal = part.border.len() + ((inside as f64 * keep_share).ceil() as usize).max(1);
    goal.min(part.mesh.vertex_count())
}

/// Builds `part` of an input of `input_vertices` vertices with its border fenced, to its
/// [`part_goal`] for `options`' vertex target and within its error bound (the input's
/// vertices it marks kept are kept). The error bound is a fraction of the input's diagonal
/// ([`Part::input_frame`]), so the part's, a fraction of its own, is scaled to match.
///
/// # Errors
/// [`Error::InvalidInput`] without a vertex target or an error bound; as
/// [`crate::hierarchy::build`].
pub fn build_part(part: &Part, options: &SimplifyOptions, input_vertices: usize) -> Result<PartBuild> {
    build_part_beside(part, options, input_vertices, Obstacles::default())
}

/// [`build_part`], its new faces kept from cutting `beside` (faces of the input's
/// `positions` in input ids: the other parts' bases) as from cutting its own.
///
/// # Errors
/// As [`build_part`].
pub fn build_part_among(
    part: &Part,
    options: &SimplifyOptions,
    positions: &[DVec3],
    beside: &[[u32; 3]],
) -> Result<PartBuild> {
    build_part_beside(part, options, positions.len(), obstacles_for(part, positions, beside))
}

/// The faces of `beside` (input ids over `positions`) whose boxes meet `part`'s, as the
/// part's obstacles: a corner on the part (a border vertex) is the part's vertex, any other
/// a point of its own. A new face of the part lies within the part's box, so no other face
/// can cut it.
fn obstacles_for(part: &Part, positions: &[DVec3], beside: &[[u32; 3]]) -> Obstacles {
    let (low, high) =
        part.mesh.positions.iter().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &p| (lo.min(p), hi.max(p)));
    let on_part: FxHashMap<u32, u32> = part.border.iter().rev().map(|&b| (part.ids[b as usize], b)).collect();
    let n = part.mesh.vertex_count() as u32;
    let mut obstacles = Obstacles::default();
    let mut points: FxHashMap<u32, u32> = FxHashMap::default();
    for t in beside {
        let corners = t.map(|v| positions[v as usize]);
        let (lo, hi) = (corners[0].min(corners[1]).min(corners[2]), corners[0].max(corners[1]).max(corners[2]));
        if lo.cmpgt(high).any() || hi.cmplt(low).any() {
            continue;
        }
        obstacles.faces.push(t.map(|v| match on_part.get(&v) {
            Some(&local) => local,
            None => *points.entry(v).or_insert_with(|| {
                obstacles.points.push(positions[v as usize]);
                n + obstacles.points.len() as u32 - 1
            }),
        }));
    }
    obstacles
}

fn build_part_beside(
    part: &Part,
    options: &SimplifyOptions,
    input_vertices: usize,
    obstacles: Obstacles,
) -> Result<PartBuild> {
    require_stop(options)?;
    let max_error = match options.max_error {
        Some(e) => Some(e * part.input_frame.diagonal / crate::mesh::UnitFrame::of(&part.mesh)?.diagonal),
        None => None,
    };
    let marked: std::collections::HashSet<u32> = options.keep_vertices.iter().copied().collect();
    let keep_vertices = (0..part.ids.len() as u32).filter(|&v| marked.contains(&part.ids[v as usize])).collect();
    let mut copies: FxHashMap<u32, Vec<u32>> = FxHashMap::default();
    for &b in &part.border {
        copies.entry(part.ids[b as usize]).or_default().push(b);
    }
    let mut border_copies: Vec<Vec<u32>> = copies.into_values().filter(|g| g.len() > 1).collect();
    border_copies.sort_unstable();
    let part_options = SimplifyOptions {
        target_vertices: options.target_vertices.map(|target| part_goal(part, target, input_vertices)),
        max_error,
        keep_vertices,
        border_vertices: part.border.clone(),
        border_copies,
        obstacles,
        chunks: None,
        // The part's goal is a staging point: stuck short of it, the part stops, and the
        // continuation gives way with the whole mesh in view.
        give_way: false,
        ..options.clone()
    };
    let h = crate::hierarchy::build(&part.mesh, &part_options)?;
    let quadrics = handed_over_quadrics(part, &h)?;
    let id = |v: u32| part.ids[v as usize];
    let mut records = Records::default();
    for step in 0..h.steps() {
        records.push(&h.removals[h.step_starts[step]..h.step_starts[step + 1]], &h.restore, id, step);
        records.step_starts.push(records.removals.len());
    }
    let seeds = (0..h.params.len())
        .filter_map(|v| h.params[v].map(|p| (id(v as u32), ParamPoint { face: p.face.map(id), bary: p.bary })))
        .collect();
    Ok(PartBuild {
        base_triangles: part.input_triangles(&h.base_triangles),
        removals: records.removals,
        restore: records.restore,
        step_starts: records.step_starts,
        seeds,
        classes: h.classes.iter().map(|&(v, class)| (id(v), class)).collect(),
        quadrics,
    })
}

/// The quadrics `part` hands over for the vertices of its base `h`, in input ids: what a
/// one-piece build accumulates there (Garland & Heckbert's quadrics of the input's faces
/// in the input's unit frame, each removed vertex's shared by its diagonal's ends as
/// `Planner::apply_level` shares it), split between the parts by linearity. An inside
/// vertex's star is whole in the part and has no cut edge, so its quadric is the input's; a
/// border vertex's own quadric is its [`Part::border_quadrics`] entry (in one part only), to
/// which every part adds what its removals gave the vertex.
///
/// # Errors
/// As [`crate::ffi::vertex_quadrics`].
fn handed_over_quadrics(part: &Part, h: &Hierarchy) -> Result<Vec<(u32, Quadric)>> {
    let mut quadrics = crate::ffi::vertex_quadrics(&part.input_frame.apply(&part.mesh), BOUNDARY_WEIGHT)?;
    for (&b, &own) in part.border.iter().zip(&part.border_quadrics) {
        quadrics[b as usize] = own;
    }
    for r in &h.removals {
        crate::analysis::share_removed_quadric(&mut quadrics, r.vertex, r.diagonal);
    }
    Ok(h.classes.iter().map(|&(v, _)| (part.ids[v as usize], quadrics[v as usize])).collect())
}

/// Joins the parts' bases of `input` and continues the build on them to `options`' target
/// with the parts' removed vertices carried on it (MAPS). The parts' levels, in step order
/// (the parts' removals of one step are independent: they lie in different parts), then
/// the continuation's make one hierarchy of the input: its base domain, removal records and
/// parametrization are those of a one-piece build, so refinement restores the input
/// exactly. Its `seconds` count from `started`; its `stages`, `target` report and kept
/// vertices are the continuation's. An input given to keep (`Cow::Owned`) becomes the
/// hierarchy's positions and faces, not a copy of them.
///
/// The continuation runs on the joined bases' vertices alone, numbered apart
/// (`ContinuedIds`), so its rings, plan cache, store and feature arrays are the size of
/// the joined bases, not of the input; the parts' records and points are moved, never held
/// twice (#40: the merge's peak).
///
/// A part's intersection guard sees only its own faces, so two parts close in space can
/// cut each other (the two sheets of a thin plate cut apart). With the guard on, parts
/// whose bases cut another part's are built again beside the others ([`separate_parts`];
/// `part_of(k)` gives part k).
///
/// # Errors
/// As [`crate::hierarchy::build`] for the continuation ([`Error::InvalidInput`] for parts
/// whose seeds do not cover the vertices their bases left) and as [`separate_parts`].
pub fn join_parts(
    input: Cow<'_, Mesh>,
    mut parts: Vec<PartBuild>,
    part_of: impl Fn(usize) -> Result<Part>,
    options: &SimplifyOptions,
    started: Instant,
) -> Result<Hierarchy> {
    let mesh = input.as_ref();
    if options.prevent_intersections {
        separate_parts(mesh, &mut parts, part_of, options)?;
    }
    let n = mesh.vertex_count();
    // The parts' records are moved into the hierarchy's (room for every vertex's: the
    // continuation's follow without copying them again), then their seeds into the
    // continuation's points: the parts are gone before the continuation starts.
    let mut records = parts_records(&mut parts, n);
    let steps = records.step_starts.len() - 1;
    let (ids, seeds, to_compact) = ContinuedIds::with_seeds(&mut parts, n)?;
    let compact = |v: u32| to_compact[v as usize];
    let joined = parts.iter().flat_map(|p| p.base_triangles.iter().map(|t| t.map(compact))).collect();
    let positions = ids.to_input[..ids.on_faces].iter().map(|&v| mesh.positions[v as usize]).collect();
    let joined = Mesh::new(positions, joined);
    let classes: Vec<(u32, VertexClass)> =
        handed_over_classes(&parts).into_iter().map(|(v, c)| (compact(v), c)).collect();
    let quadrics: Vec<(u32, Quadric)> = summed_quadrics(&parts).into_iter().map(|(v, q)| (compact(v), q)).collect();
    drop(parts);
    // The user's marked vertices that the parts kept, by the continuation's ids.
    let keep_vertices = options.keep_vertices.iter().filter_map(|&v| to_compact.get(v as usize).copied());
    let keep_vertices = keep_vertices.filter(|&c| (c as usize) < ids.on_faces).collect();
    drop(to_compact);
    // Levels are made by refinement afterwards (`build_partitioned`).
    let options = SimplifyOptions { keep_vertices, record_levels: false, ..options.clone() };
    let continuation = Continuation { input: mesh, to_input: &ids.to_input, quadrics: &quadrics, classes: &classes };
    let continued = crate::hierarchy::simplify::build_seeded(&joined, &options, seeds, continuation)?;
    drop(joined);
    let to_input = |v: u32| ids.to_input[v as usize];
    records.restore.reserve_exact(continued.restore.len());
    for step in 0..continued.steps() {
        let removals = &continued.removals[continued.step_starts[step]..continued.step_starts[step + 1]];
        records.push(removals, &continued.restore, to_input, steps + step);
        records.step_starts.push(records.removals.len());
    }
    let mut kept = vec![false; n];
    for (c, &k) in continued.kept.iter().enumerate() {
        kept[ids.to_input[c] as usize] = k;
    }
    // An input given to keep gives its positions and faces up, not a copy of them.
    let (positions, input_triangles) = match input {
        Cow::Owned(mesh) => (mesh.positions, mesh.triangles),
        Cow::Borrowed(mesh) => (mesh.positions.clone(), mesh.triangles.clone()),
    };
    Ok(Hierarchy {
        positions,
        input_triangles,
        base_triangles: continued.base_triangles.iter().map(|t| t.map(to_input)).collect(),
        removals: records.removals,
        restore: records.restore,
        step_starts: records.step_starts,
        params: ids.params_by_input(continued.params),
        kept,
        classes: continued.classes.iter().map(|&(v, c)| (to_input(v), c)).collect(),
        seconds: started.elapsed().as_secs_f64(),
        levels: Vec::new(),
        ..continued
    })
}

/// The ids of a partitioned build's continuation (#40): the joined bases' vertices first,
/// in ascending input order (so every order the build takes among them is a one-piece
/// build's), then the parts' removed vertices, part after part. Arrays the planning sizes
/// by its ids then hold only the joined bases' vertices, not every input vertex.
struct ContinuedIds {
    /// Each id's input vertex.
    to_input: Vec<u32>,
    /// How many ids are vertices of the joined bases' faces.
    on_faces: usize,
}

/// An input vertex without an id yet.
const NO_ID: u32 = u32::MAX;

impl ContinuedIds {
    /// The ids of `parts` over an input of `n` vertices and the parts' seeds by them, each
    /// part's moved out and freed before the next part's (so they are never held twice);
    /// the seeds are `None` for the joined bases' vertices, and have room for every input
    /// vertex so that the continuation's points come back by input id in place
    /// ([`ContinuedIds::params_by_input`]). Also each input vertex's id.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for a vertex of a base face that a part also removed, a
    /// vertex two parts removed, or an input vertex neither on a base face nor removed.
    fn with_seeds(parts: &mut [PartBuild], n: usize) -> Result<(Self, Vec<Option<ParamPoint>>, Vec<u32>)> {
        let mut to_compact = vec![NO_ID; n];
        for t in parts.iter().flat_map(|p| &p.base_triangles) {
            t.iter().for_each(|&v| to_compact[v as usize] = 0);
        }
        let mut to_input: Vec<u32> = (0..n as u32).filter(|&v| to_compact[v as usize] == 0).collect();
        for (c, &v) in to_input.iter().enumerate() {
            to_compact[v as usize] = c as u32;
        }
        let on_faces = to_input.len();
        let mut seeds: Vec<Option<ParamPoint>> = Vec::with_capacity(n);
        seeds.resize(on_faces, None);
        for part in parts {
            for (v, point) in std::mem::take(&mut part.seeds) {
                let id = &mut to_compact[v as usize];
                if *id != NO_ID {
                    let what = if (*id as usize) < on_faces {
                        "a vertex of a part's base face has a seed (another part removed it)"
                    } else {
                        "two parts removed one vertex"
                    };
                    return Err(Error::InvalidInput(format!("the parts' builds disagree: {what}: vertex {v}")));
                }
                *id = seeds.len() as u32;
                to_input.push(v);
                let face = point.face.map(|f| to_compact[f as usize]);
                if face.iter().any(|&f| f as usize >= on_faces) {
                    return Err(Error::InvalidInput(format!("vertex {v}'s seed is on no face of the joined bases")));
                }
                seeds.push(Some(ParamPoint { face, ..point }));
            }
        }
        if let Some(v) = to_compact.iter().position(|&c| c == NO_ID) {
            return Err(Error::InvalidInput(format!(
                "the parts' builds disagree: a vertex no part kept has no seed: vertex {v}"
            )));
        }
        Ok((ContinuedIds { to_input, on_faces }, seeds, to_compact))
    }

    /// The continuation's final points (by these ids, faces too) by input vertex, moved in
    /// place.
    fn params_by_input(&self, mut params: Vec<Option<ParamPoint>>) -> Vec<Option<ParamPoint>> {
        params.resize(self.to_input.len(), None);
        for point in params.iter_mut().flatten() {
            point.face = point.face.map(|c| self.to_input[c as usize]);
        }
        move_to_places(&mut params, &self.to_input);
        params
    }
}

/// Moves `items[i]` to `items[to[i]]` for every i, in place (`to` a permutation), along
/// the permutation's cycles.
fn move_to_places<T>(items: &mut [T], to: &[u32]) {
    let mut placed = vec![false; items.len()];
    for start in 0..items.len() {
        let mut at = start;
        while !placed[at] {
            placed[at] = true;
            let next = to[at] as usize;
            if next == start {
                break;
            }
            // `items[start]` holds what belongs at `next`'s source's place: swap it there.
            items.swap(start, next);
            at = next;
        }
    }
}

/// The parts' removal records as one hierarchy's: the parts' steps in order, within a step
/// the parts in order (their removals of one step lie in different parts, so they are
/// independent). Each part's records are moved out and freed before the next part's, then
/// put in step order in place; the removals have room for `capacity` (every vertex's).
fn parts_records(parts: &mut [PartBuild], capacity: usize) -> Records {
    let steps = parts.iter().map(PartBuild::steps).max().unwrap_or(0);
    // Where each part's removals of each of its steps go.
    let mut block_starts: Vec<Vec<usize>> = vec![Vec::new(); parts.len()];
    let mut step_starts = vec![0];
    for step in 0..steps {
        let mut at = *step_starts.last().expect("a start");
        for (starts, part) in block_starts.iter_mut().zip(parts.iter()).filter(|(_, p)| step < p.steps()) {
            starts.push(at);
            at += part.step_starts[step + 1] - part.step_starts[step];
        }
        step_starts.push(at);
    }
    let mut removals = Vec::with_capacity(capacity.max(step_starts[steps]));
    let mut restore = Vec::with_capacity(parts.iter().map(|p| p.restore.len()).sum());
    let mut to = Vec::with_capacity(step_starts[steps]);
    for (part, starts) in parts.iter_mut().zip(&block_starts) {
        let offset = restore.len() as u32;
        restore.append(&mut part.restore);
        for (step, &start) in starts.iter().enumerate() {
            let (first, last) = (part.step_starts[step], part.step_starts[step + 1]);
            to.extend((first..last).map(|j| (start + j - first) as u32));
            removals.extend(part.removals[first..last].iter().map(|r| Removal {
                step: step as u32,
                restore: r.restore.map(|i| i + offset),
                ..*r
            }));
        }
        (part.removals, part.restore) = (Vec::new(), Vec::new());
    }
    move_to_places(&mut removals, &to);
    // Each removal's link edges, in removal order.
    let mut ordered = Vec::with_capacity(restore.len());
    for r in &mut removals {
        let start = ordered.len() as u32;
        ordered.extend_from_slice(&restore[r.restore[0] as usize..r.restore[1] as usize]);
        r.restore = [start, ordered.len() as u32];
    }
    Records { removals, restore: ordered, step_starts }
}

/// The classes the parts found for their bases' vertices, by vertex: where a vertex is on
/// several parts' borders (each classified it seeing only its own side), the sharpest.
fn handed_over_classes(parts: &[PartBuild]) -> Vec<(u32, VertexClass)> {
    let mut all: Vec<(u32, VertexClass)> = parts.iter().flat_map(|p| p.classes.iter().copied()).collect();
    // A stable sort: a vertex's classes stay in part order, for `sharpest`'s ties.
    all.sort_by_key(|&(v, _)| v);
    all.chunk_by(|a, b| a.0 == b.0)
        .map(|group| (group[0].0, VertexClass::sharpest(group.iter().map(|&(_, c)| c)).expect("a group has a class")))
        .collect()
}

/// The quadrics the parts handed over, summed by vertex in part order.
fn summed_quadrics(parts: &[PartBuild]) -> Vec<(u32, Quadric)> {
    let mut all: Vec<(u32, Quadric)> = parts.iter().flat_map(|p| p.quadrics.iter().copied()).collect();
    all.sort_by_key(|&(v, _)| v);
    all.chunk_by(|a, b| a.0 == b.0)
        .map(|group| {
            let mut sum = group[0].1;
            group[1..].iter().for_each(|(_, q)| sum.add_scaled(q, 1.0));
            (group[0].0, sum)
        })
        .collect()
}

/// Builds again, one after the other in order, each part whose base cuts another part's,
/// beside the other parts' current bases and input faces (those whose boxes meet its own):
/// its guard then sees faces that no longer change, and faces another part keeps. Rounds
/// repeat while they change which faces cut each other (at most `SEPARATION_ROUNDS`);
/// what remains is what the guards allow, crossings the input made there. Returns the
/// parts rebuilt, in order of rebuilding.
///
/// # Errors
/// As CGAL's self-intersection test, `part_of` and [`build_part_among`].
pub fn separate_parts(
    mesh: &Mesh,
    parts: &mut [PartBuild],
    part_of: impl Fn(usize) -> Result<Part>,
    options: &SimplifyOptions,
) -> Result<Vec<usize>> {
    let mut rebuilt = Vec::new();
    let mut crossing = crossing_pairs(mesh, parts)?;
    if crossing.is_empty() {
        return Ok(rebuilt);
    }
    // Two faces of the input that cross cross in the input (an assembly's parts): no
    // build made that crossing, and no rebuild would undo it.
    let input: FxHashSet<[u32; 3]> = mesh.triangles.iter().map(|&t| face_key(t)).collect();
    let made = |pairs: Vec<[PartFace; 2]>| -> Vec<[PartFace; 2]> {
        pairs.into_iter().filter(|pair| !pair.iter().all(|(_, t)| input.contains(&face_key(*t)))).collect()
    };
    crossing = made(crossing);
    if crossing.is_empty() {
        return Ok(rebuilt);
    }
    // Each part's input faces, in input ids, once.
    let inputs: Vec<Vec<[u32; 3]>> =
        (0..parts.len()).map(|j| part_of(j).map(|p| p.input_triangles(&p.mesh.triangles))).collect::<Result<_>>()?;
    for _ in 0..SEPARATION_ROUNDS {
        let cutting: std::collections::BTreeSet<usize> = crossing.iter().flat_map(|p| p.map(|(k, _)| k)).collect();
        if cutting.is_empty() {
            break;
        }
        for &k in &cutting {
            let mut beside: Vec<[u32; 3]> = Vec::new();
            for j in (0..parts.len()).filter(|&j| j != k) {
                beside.extend(&inputs[j]);
                beside.extend(&parts[j].base_triangles);
            }
            parts[k] = build_part_among(&part_of(k)?, options, &mesh.positions, &beside)?;
            rebuilt.push(k);
        }
        let after = made(crossing_pairs(mesh, parts)?);
        if after == crossing {
            break;
        }
        crossing = after;
    }
    Ok(rebuilt)
}

/// How many rounds [`separate_parts`] makes at most: a round rebuilds every cutting part
/// beside faces that stay, so a second is needed only where a rebuilt part kept input
/// faces that a part not rebuilt cuts.
const SEPARATION_ROUNDS: usize = 3;

/// A face of a part's base: the part and the face's corners.
type PartFace = (usize, [u32; 3]);

/// The pairs of faces of different parts' bases that cut each other (the guard's test on
/// the joined bases; pairs within one part are its own guard's business), each face as
/// (part, its corners).
fn crossing_pairs(mesh: &Mesh, parts: &[PartBuild]) -> Result<Vec<[PartFace; 2]>> {
    let owner: Vec<usize> =
        (0..parts.len()).flat_map(|k| std::iter::repeat_n(k, parts[k].base_triangles.len())).collect();
    let faces: Vec<[u32; 3]> = parts.iter().flat_map(|p| p.base_triangles.iter().copied()).collect();
    // The guard's own test (CGAL's exact predicates, degenerate faces allowed).
    let pairs = crate::hierarchy::added_triangle_intersections(&mesh.positions, &[], &faces)?;
    Ok(pairs
        .into_iter()
        .map(|pair| pair.map(|f| (owner[f as usize], faces[f as usize])))
        .filter(|[a, b]| a.0 != b.0)
        .collect())
}

/// A partitioned build (#40) in one process: `mesh` cut into `parts` ([`Partition::of`]),
/// each part built in parallel ([`build_part`]) and the parts joined ([`join_parts`]).
///
/// It stops at a vertex target or an error bound (a fraction of the input's diagonal in
/// every part and in the continuation); a level limit alone is refused, levels are not
/// recorded (refinement makes them afterwards: [`Hierarchy::levels_by_refinement`]), and
/// parts whose bases cut each other are built again beside each other
/// ([`separate_parts`]). UVs and materials go with the parts, whose seams are the input's,
/// and the continuation simplifies the seams along themselves as they run on the joined
/// bases; every level takes the input's attributes.
///
/// # Errors
/// [`Error::InvalidInput`] for the limits above and as
/// [`Partition::of`]; as [`crate::hierarchy::build`] for each part and the continuation.
pub fn build_partitioned(mesh: &Mesh, parts: usize, options: &SimplifyOptions) -> Result<Hierarchy> {
    let started = Instant::now();
    check_partitioned(mesh, options)?;
    // The parts' builds are held until they are joined: about a one-piece build's memory.
    crate::memory::ensure_available(
        (mesh.triangles.len() as u64).saturating_mul(crate::hierarchy::simplify::BUILD_BYTES_PER_TRIANGLE),
        &format!("a hierarchy of {} triangles in {parts} chunks", mesh.triangles.len()),
        "simplify a smaller mesh, or set a larger --max-memory where the machine has it",
    )?;
    let partition = Partition::of(mesh, parts)?;
    let built: Vec<PartBuild> = (0..parts)
        .into_par_iter()
        .map(|k| build_part(&partition.part(mesh, k)?, options, mesh.vertex_count()))
        .collect::<Result<_>>()?;
    join_parts(Cow::Borrowed(mesh), built, |k| partition.part(mesh, k), options, started)
}

/// Refuses what a partitioned build of `mesh` does not take yet, and names the input's
/// faults as a one-piece build names them (not as a part's).
///
/// # Errors
/// [`Error::InvalidInput`] without a vertex target or an error bound, with a level limit,
/// recorded levels or fenced vertices; as
/// [`crate::hierarchy::build`]'s validation.
pub fn check_partitioned(mesh: &Mesh, options: &SimplifyOptions) -> Result<()> {
    check_partitioned_settings(options)?;
    mesh.check()?;
    crate::hierarchy::simplify::prepare_input(mesh, None)
}

/// Refuses settings a partitioned build does not take (as [`check_partitioned`], without
/// the mesh).
///
/// # Errors
/// As [`check_partitioned`].
pub fn check_partitioned_settings(options: &SimplifyOptions) -> Result<()> {
    require_stop(options)?;
    if options.levels.is_some() {
        return Err(Error::InvalidInput("a partitioned build takes no level limit yet".into()));
    }
    if options.record_levels
        || !options.border_vertices.is_empty()
        || !options.border_copies.is_empty()
        || !options.obstacles.faces.is_empty()
    {
        return Err(Error::InvalidInput(
            "a partitioned build records its levels by refinement and fences its own borders and obstacles".into(),
        ));
    }
    options.check()
}

/// Refuses `options` that give a partitioned build (or a part of one) nowhere to stop.
fn require_stop(options: &SimplifyOptions) -> Result<()> {
    if options.target_vertices.is_none() && options.max_error.is_none() {
        return Err(Error::InvalidInput(
            "a partitioned build needs a vertex target or an error bound (a level limit alone is not supported yet)"
                .into(),
        ));
    }
    Ok(())
}

/// Removal records gathered from several builds into one hierarchy's.
struct Records {
    removals: Vec<Removal>,
    restore: Vec<[u32; 2]>,
    step_starts: Vec<usize>,
}

impl Default for Records {
    fn default() -> Self {
        Records { removals: Vec::new(), restore: Vec::new(), step_starts: vec![0] }
    }
}

impl Records {
    /// Appends `removals` (with their link edges in `restore`) of a build over vertices
    /// whose input ids `id` gives, as removals of `step`.
    fn push(&mut self, removals: &[Removal], restore: &[[u32; 2]], id: impl Fn(u32) -> u32 + Copy, step: usize) {
        for r in removals {
            let start = self.restore.len() as u32;
            self.restore.extend(restore[r.restore[0] as usize..r.restore[1] as usize].iter().map(|e| e.map(id)));
            self.removals.push(Removal {
                vertex: id(r.vertex),
                step: step as u32,
                local: ParamPoint { face: r.local.face.map(id), bary: r.local.bary },
                diagonal: r.diagonal.map(id),
                restore: [start, self.restore.len() as u32],
                ..*r
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::move_to_places;

    #[test]
    fn items_move_to_their_places_along_every_cycle() {
        // Cycles of lengths 1, 2 and 4.
        let to = [0u32, 2, 1, 5, 6, 3, 4];
        let mut items: Vec<char> = "abcdefg".chars().collect();
        move_to_places(&mut items, &to);
        let mut expected = [' '; 7];
        for (i, c) in "abcdefg".chars().enumerate() {
            expected[to[i] as usize] = c;
        }
        assert_eq!(items, expected);
        assert_eq!(items.iter().collect::<String>(), "acbfgde");
    }
}
