//! Detail mapping (thesis §4.5, §4.7, chapter 5): the deformation operator D(VS, l, f)
//! (eq. 4.4) applied at chosen levels of the 4-k hierarchy while it is refined back to
//! full resolution. Each recipe step runs when refinement reaches its level: VS comes from
//! the step's selection, f from its operator (procedural noise, variation, feature-based,
//! organic, taper, twist, smoothing, local subdivision). Vertices inserted by later levels
//! are placed on the deformed surface (the parametrization update of §4.5.1, see
//! [`Refiner::set_follow_deformation`]). After the last level, CGAL counts
//! self-intersections and, when asked, displacements are damped until there are none.

mod displace;
mod geometric;
mod intersections;
mod level;
mod organic;
mod recipe;
mod select;
mod smooth;
mod subdivide;

use std::time::Instant;

use glam::DVec3;
use serde::Serialize;

pub use displace::{LevelNoise, noise_displacements, tangent_frame};
pub use geometric::{taper, twist};
pub use intersections::{IntersectionReport, resolve_self_intersections};
pub use level::{BoxFrame, LevelView};
pub use organic::organic_displacements;
pub use recipe::*;
pub use select::{independent_set, select};
pub use smooth::{laplacian_energy, loop_beta, loop_smooth};
pub use subdivide::{Subdivision, subdivide_around};

use crate::analysis::{AnalysisOptions, FeatureClass, analyze};
use crate::error::{Error, Result};
use crate::hierarchy::{Hierarchy, LevelMesh, Refiner, Removal, SimplifyOptions, build};
use crate::mesh::Mesh;
use crate::noise::hash::derive_seed;

/// Options of [`apply`] beyond the recipe.
#[derive(Debug, Clone, PartialEq)]
pub struct DetailOptions {
    /// How the hierarchy is built.
    pub simplify: SimplifyOptions,
    /// Damp displacements until the result has no self-intersections (the default: a
    /// recipe's result is free of them unless asked otherwise).
    pub no_self_intersections: bool,
    /// Place later insertions on the deformed surface (§4.5.1); off only to show why.
    pub follow_deformation: bool,
}

impl Default for DetailOptions {
    fn default() -> Self {
        DetailOptions { simplify: SimplifyOptions::default(), no_self_intersections: true, follow_deformation: true }
    }
}

/// What one recipe step did.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StepReport {
    /// 1-based index in the recipe.
    pub step: usize,
    /// Operator name.
    pub op: String,
    /// Level it ran at (0: base domain).
    pub level: usize,
    /// Vertices in the level's mesh.
    pub level_vertices: usize,
    /// Vertices selected.
    pub selected: usize,
    /// Vertices moved or created.
    pub touched: usize,
    /// Time, seconds.
    pub seconds: f64,
}

/// The result of [`apply`].
#[derive(Debug, Clone)]
pub struct DetailOutcome {
    /// The detailed mesh at full resolution, with each vertex's id.
    pub result: LevelMesh,
    /// Undeformed position of each vertex of `result` (input position, or the subdivided
    /// undeformed surface for vertices made by subdivision).
    pub rest: Vec<DVec3>,
    /// One report per step, in the order they ran.
    pub steps: Vec<StepReport>,
    /// The self-intersection stage.
    pub intersections: IntersectionReport,
    /// Hierarchy levels.
    pub levels: usize,
    /// Base-domain vertices.
    pub base_vertices: usize,
    /// Stage times, seconds: hierarchy build, steps, refinement, self-intersections.
    pub seconds: StageSeconds,
    /// What of the input's attributes the result could not carry, one note each.
    pub attribute_notes: Vec<String>,
}

/// Time per stage.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct StageSeconds {
    /// Hierarchy build.
    pub hierarchy: f64,
    /// All detail steps.
    pub detail: f64,
    /// Refinement (without the steps).
    pub refine: f64,
    /// Self-intersection detection and damping.
    pub intersections: f64,
}

/// Builds the hierarchy of `mesh` and applies `recipe` while refining it.
///
/// # Errors
/// Those of [`build`] and [`apply_to`].
pub fn apply(mesh: &Mesh, recipe: &Recipe, options: &DetailOptions) -> Result<DetailOutcome> {
    let hierarchy = build(mesh, &options.simplify)?;
    let mut outcome = apply_to(&hierarchy, mesh, recipe, options)?;
    outcome.seconds.hierarchy = hierarchy.seconds;
    Ok(outcome)
}

/// Per-run state the steps share: the input's frame and feature classes, each vertex's
/// undeformed position and "noised" mark (§4.5), by id.
struct RunState {
    frame: BoxFrame,
    classes: Vec<FeatureClass>,
    rest: Vec<DVec3>,
    noised: Vec<bool>,
    /// Closed 1-rings changed by local subdivision (see [`subdivide_around`]).
    frozen: Vec<bool>,
    /// The refinement level each vertex id first belongs to (eq. 4.5's per-vertex l).
    appear: Vec<u32>,
    /// The edge each vertex made by local subdivision split, in order of ids.
    splits: Vec<[u32; 2]>,
}

/// The input vertices a selection picks, evaluated on the input itself (its own frame,
/// curvatures and feature classes): the region of [`crate::hierarchy::region::refine_region`].
///
/// # Errors
/// As [`select()`]; analysis errors when the selection asks for feature classes.
pub fn input_selection(input: &Mesh, selection: &Selection, seed: u64) -> Result<Vec<bool>> {
    let classes = if selection.features.is_some() {
        analyze(input, &AnalysisOptions::default())?.classes
    } else {
        Vec::new()
    };
    let ids = (0..input.vertex_count() as u32).collect();
    let view = LevelView::new(0, 0, LevelMesh { mesh: input.clone(), ids });
    select(selection, &view, &BoxFrame::of(input), &classes, seed)
}

/// Applies `recipe` to an already built hierarchy of `input`.
///
/// # Errors
/// [`crate::Error::InvalidInput`] for a step whose selection names a missing vertex or
/// whose noise parameters are invalid; native errors from OpenMesh and CGAL.
pub fn apply_to(
    hierarchy: &Hierarchy,
    input: &Mesh,
    recipe: &Recipe,
    options: &DetailOptions,
) -> Result<DetailOutcome> {
    apply_with(hierarchy, input, recipe, &[], options)
}

/// A step whose f is a Rust function (eq. 4.4 allows any function of position, level and
/// vertex attributes): called with the level's view and a selected vertex's local index,
/// it returns that vertex's new position. Runs after the recipe's steps of its level.
pub struct FunctionStep<'a> {
    /// Level, as in recipes (negative: from the input's level back).
    pub level: i64,
    /// Which vertices.
    pub select: Selection,
    /// The function.
    pub f: &'a (dyn Fn(&LevelView, usize) -> DVec3 + Sync),
}

/// [`apply_to`] with function steps besides the recipe's.
///
/// # Errors
/// As [`apply_to`].
pub fn apply_with(
    hierarchy: &Hierarchy,
    input: &Mesh,
    recipe: &Recipe,
    functions: &[FunctionStep],
    options: &DetailOptions,
) -> Result<DetailOutcome> {
    // Feature classes of the input, computed only when a selection asks for them.
    let wants_features = recipe.steps.iter().map(|s| &s.select).chain(functions.iter().map(|f| &f.select));
    let classes = if wants_features.into_iter().any(|s| s.features.is_some()) {
        analyze(input, &AnalysisOptions::default())?.classes
    } else {
        Vec::new()
    };
    let mut state = RunState {
        frame: BoxFrame::of(input),
        classes,
        rest: hierarchy.positions.clone(),
        noised: vec![false; hierarchy.positions.len()],
        frozen: vec![false; hierarchy.positions.len()],
        appear: hierarchy.appearance_levels(),
        splits: Vec::new(),
    };
    let steps = hierarchy.steps();
    let levels = recipe.steps.iter().map(|s| s.level).chain(functions.iter().map(|f| f.level));
    let mut order: Vec<(usize, usize)> = levels.enumerate().map(|(i, l)| (resolve_level(l, steps), i)).collect();
    order.sort_unstable();
    let mut refiner = Refiner::new(hierarchy)?;
    refiner.set_follow_deformation(options.follow_deformation);
    let mut seconds = StageSeconds::default();
    let mut reports = Vec::new();
    let mut next = order.iter().peekable();
    loop {
        let level = refiner.level();
        while let Some(&&(_, i)) = next.peek().filter(|(l, _)| *l == level) {
            next.next();
            let start = Instant::now();
            let seed = derive_seed(recipe.seed, &format!("step {i}"));
            let report = match recipe.steps.get(i) {
                Some(step) => run_step(step, &mut refiner, &mut state, steps, step.seed.unwrap_or(seed)),
                None => run_function(&functions[i - recipe.steps.len()], &mut refiner, &state, steps, seed),
            };
            // A step's error names the step (#36: a non-finite coordinate named neither).
            let mut report = report.map_err(|e| match e {
                Error::InvalidInput(m) => Error::InvalidInput(format!("recipe step {}: {m}", i + 1)),
                e => e,
            })?;
            report.step = i + 1;
            report.seconds = start.elapsed().as_secs_f64();
            seconds.detail += report.seconds;
            reports.push(report);
        }
        if refiner.is_finished() {
            break;
        }
        let start = Instant::now();
        // The removals the next level re-inserts.
        let records = hierarchy.step(hierarchy.steps() - 1 - refiner.level());
        let allowed = insertable(hierarchy, records, &refiner, &state.frozen);
        refiner.refine_level(&|v| allowed.binary_search(&v).is_ok())?;
        inherit_noised_marks(records, &refiner, &mut state.noised);
        seconds.refine += start.elapsed().as_secs_f64();
    }
    let mut result = refiner.mesh()?;
    let rest: Vec<DVec3> = result.ids.iter().map(|&id| state.rest[id as usize]).collect();
    let start = Instant::now();
    let intersections = resolve_self_intersections(&mut result.mesh, &rest, options.no_self_intersections)?;
    seconds.intersections = start.elapsed().as_secs_f64();
    let mut attribute_notes = carry_attributes(hierarchy, input, &state.splits, &mut result);
    if let Some(color) = &recipe.color {
        if input.colors.is_some() {
            attribute_notes.push("the recipe's [color] replaced the input's vertex colours".into());
        }
        result.mesh.colors = Some(color.colors(&result.mesh.positions, &rest));
    }
    Ok(DetailOutcome {
        result,
        rest,
        steps: reports,
        intersections,
        levels: steps,
        base_vertices: hierarchy.base_vertex_count(),
        seconds,
        attribute_notes,
    })
}

/// Gives the detailed mesh the input's attributes (#22 B3): colours and scalars by vertex
/// (a vertex made by local subdivision takes the mean of its edge's ends), UVs and
/// materials per face corner through [`Hierarchy::attach_attributes`] (a made
/// vertex's UV is the mean of its edge's ends' on each side), and normals recomputed on
/// the deformed surface when the input had normals. Returns a note for what could not be
/// carried.
fn carry_attributes(hierarchy: &Hierarchy, input: &Mesh, splits: &[[u32; 2]], result: &mut LevelMesh) -> Vec<String> {
    let n = input.vertex_count();
    let mut notes = Vec::new();
    // Values for every id, made ones after the input's, each the mean of its edge's ends.
    let extend = |values: &[f64]| -> Vec<f64> {
        let mut all = values.to_vec();
        for &[a, b] in splits {
            all.push(0.5 * (all[a as usize] + all[b as usize]));
        }
        all
    };
    let by_id = |all: &[f64]| -> Vec<f64> { result.ids.iter().map(|&id| all[id as usize]).collect() };
    for (name, values) in &input.scalars {
        let all = extend(values);
        result.mesh.scalars.insert(name.clone(), by_id(&all));
    }
    if let Some(colors) = &input.colors {
        let channels: Vec<Vec<f64>> =
            (0..3).map(|c| extend(&colors.iter().map(|rgb| f64::from(rgb[c])).collect::<Vec<_>>())).collect();
        result.mesh.colors = Some(
            result.ids.iter().map(|&id| [0, 1, 2].map(|c| channels[c][id as usize].round() as u8)).collect(),
        );
    }
    // A wedge not found is a bug; the detailed mesh is still good, so it is written
    // without UVs and the note says why rather than the whole run failing.
    if let Err(e) = hierarchy.attach_attributes(result, splits) {
        notes.push(format!("UVs and materials not carried: {e}"));
    }
    if input.normals.is_some() {
        let adjacency = crate::mesh::Adjacency::of(&result.mesh);
        let faces = crate::analysis::FaceGeometry::of(&result.mesh);
        result.mesh.normals = Some(crate::analysis::vertex_normals(
            &result.mesh,
            &adjacency,
            &faces,
            crate::analysis::NormalWeighting::Angle,
        ));
    }
    debug_assert!(result.ids.iter().all(|&id| (id as usize) < n + splits.len()));
    notes
}

/// The vertices of `records` (the removals the next refinement level re-inserts) it may
/// insert (sorted): those whose parameter face and recorded degree-fix flips only involve
/// vertices that are present and outside the subdivided regions (so every insertion
/// restores its recorded neighbourhood exactly).
fn insertable(hierarchy: &Hierarchy, records: &[Removal], refiner: &Refiner, frozen: &[bool]) -> Vec<u32> {
    let mut allowed: Vec<u32> = records
        .iter()
        .filter(|r| {
            let f = r.local.face;
            let whole = |v: u32| refiner.is_present(v) && !frozen[v as usize];
            f.iter().all(|&v| whole(v)) && hierarchy.restore_of(r).iter().flatten().all(|&v| whole(v))
        })
        .map(|r| r.vertex)
        .collect();
    allowed.sort_unstable();
    allowed
}

/// §4.5's noised region carried through refinement: a vertex a level inserted is noised
/// when at least two corners of the coarser face it was inserted into are (its parameter
/// face, [`crate::hierarchy::Removal::local`]). A region noised at a coarse level thus
/// stays a region as the levels fill it in, instead of dissolving into isolated marked
/// base vertices among unmarked inserted ones (#37: the torus variation's fine step
/// covered both halves, fine roughness 0.117 on the varied half vs 0.115).
fn inherit_noised_marks(records: &[Removal], refiner: &Refiner, noised: &mut [bool]) {
    for r in records.iter().filter(|r| refiner.is_present(r.vertex)) {
        let marked = r.local.face.iter().filter(|&&c| noised[c as usize]).count();
        noised[r.vertex as usize] = marked >= 2;
    }
}

/// A recipe level (negative: from the input's level back) as a refinement level.
pub fn resolve_level(level: i64, steps: usize) -> usize {
    let steps = steps as i64;
    (if level < 0 { steps + 1 + level } else { level }).clamp(0, steps) as usize
}

/// Runs one function step on the refiner's current level.
fn run_function(
    step: &FunctionStep,
    refiner: &mut Refiner,
    state: &RunState,
    steps: usize,
    seed: u64,
) -> Result<StepReport> {
    let level = refiner.level();
    let view = LevelView::new(level, steps - level, refiner.mesh()?).with_appearance(&state.appear);
    let selected = select(&step.select, &view, &state.frame, &state.classes, seed)?;
    let chosen: Vec<usize> = (0..selected.len()).filter(|&v| selected[v]).collect();
    let moved: Vec<DVec3> = {
        use rayon::prelude::*;
        chosen.par_iter().map(|&v| (step.f)(&view, v)).collect()
    };
    let moves: Vec<(usize, DVec3)> = chosen.iter().copied().zip(moved).collect();
    check_moves(&moves, &view, &format!("the function step at level {level}"))?;
    let touched = write_moves(refiner, &view, &moves, None);
    Ok(StepReport {
        step: 0,
        op: "function".into(),
        level,
        level_vertices: view.ids.len(),
        selected: chosen.len(),
        touched,
        seconds: 0.0,
    })
}

/// Writes a step's new positions (local indices of `view`) into the refiner, marking the
/// moved vertices noised when given the marks; returns how many positions changed.
fn write_moves(
    refiner: &mut Refiner,
    view: &LevelView,
    moves: &[(usize, DVec3)],
    mut noised: Option<&mut Vec<bool>>,
) -> usize {
    let positions = refiner.positions_mut();
    let mut touched = 0;
    for &(v, p) in moves {
        let id = view.ids[v] as usize;
        touched += usize::from(positions[id] != p);
        positions[id] = p;
        if let Some(marks) = noised.as_deref_mut() {
            marks[id] = true;
        }
    }
    touched
}

/// §4.5's "only where nothing was noised before", read as regions (#26 B7): the vertices
/// noised by earlier steps, with every vertex whose mark differs from all of its
/// neighbours' taking theirs. A base vertex noised at a coarse level and now alone among
/// inserted vertices leaves the noised set (its neighbours move, so does it); a vertex
/// inserted among noised ones joins it. Each such change turns all of the vertex's edges
/// from disagreeing to agreeing, so the passes end; the order is fixed, so the result is
/// deterministic. The marks themselves are left as they are.
fn noised_regions(view: &LevelView, mut region: Vec<bool>) -> Vec<bool> {
    loop {
        let mut changed = false;
        for v in 0..region.len() {
            let ring = view.adjacency.neighbours(v);
            if !ring.is_empty() && ring.iter().all(|&u| region[u as usize] != region[v]) {
                region[v] = !region[v];
                changed = true;
            }
        }
        if !changed {
            return region;
        }
    }
}

/// Refuses moves to a non-finite place or past [`crate::mesh::MAX_COORDINATE`], naming the
/// vertex (by input id) and `what` made them.
fn check_moves(moves: &[(usize, DVec3)], view: &LevelView, what: &str) -> Result<()> {
    match moves.iter().find(|(_, p)| !(p.is_finite() && p.abs().max_element() <= crate::mesh::MAX_COORDINATE)) {
        None => Ok(()),
        Some(&(v, p)) => Err(Error::InvalidInput(format!(
            "{what} moves vertex {} to ({:e}, {:e}, {:e}): its amplitude, scale or frequency is too large",
            view.ids[v], p.x, p.y, p.z
        ))),
    }
}

/// Bytes a vertex of the refiner holds with everything a detail run keeps beside it (the
/// OpenMesh store's vertex, its three edges and two faces, the level view's copy, the run's
/// per-vertex state), rounded up.
const DETAIL_BYTES_PER_VERTEX: u64 = 640;

/// Refuses a subdivision whose vertices the memory cannot hold, before making them (#36: a
/// recipe subdividing 12 times ran 46 s into 3.2 GB and aborted). Concentric 4-8 steps
/// double a centre's ring each step, so a centre of degree d makes at most d·2^(steps+1)
/// vertices.
fn check_subdivision_fits(refiner: &Refiner, centres: &[u32], steps: usize, level: usize) -> Result<()> {
    let rings = refiner.rings();
    let ring_sum: u64 = centres.iter().map(|&c| rings.degree(c) as u64).sum();
    let made = ring_sum.saturating_mul(1u64.checked_shl(steps as u32 + 1).unwrap_or(u64::MAX));
    let vertices = (refiner.vertex_slots() as u64).saturating_add(made);
    crate::memory::ensure_available(
        vertices.saturating_mul(DETAIL_BYTES_PER_VERTEX),
        &format!("subdividing {} centres {steps} times at level {level} (up to {vertices} vertices)", centres.len()),
        "subdivide fewer times or around fewer vertices",
    )
}

/// Runs one step on the refiner's current level.
fn run_step(step: &Step, refiner: &mut Refiner, state: &mut RunState, steps: usize, seed: u64) -> Result<StepReport> {
    let level = refiner.level();
    let depth = steps - level;
    let mut view = LevelView::new(level, depth, refiner.mesh()?).with_appearance(&state.appear);
    let mut selected = select(&step.select, &view, &state.frame, &state.classes, seed)?;
    let mut touched = 0;
    let subdivide_steps = match step.op {
        OperatorKind::Subdivide => step.subdivide.steps,
        OperatorKind::Organic => step.organic.subdivide,
        _ => 0,
    };
    if subdivide_steps > 0 {
        let centres: Vec<u32> = (0..selected.len()).filter(|&v| selected[v]).map(|v| view.ids[v]).collect();
        check_subdivision_fits(refiner, &centres, subdivide_steps, level)?;
        let made = subdivide_around(refiner, &centres, subdivide_steps)?;
        for &([a, b], v) in &made.splits {
            debug_assert_eq!(v as usize, state.rest.len());
            state.rest.push((state.rest[a as usize] + state.rest[b as usize]) * 0.5);
            state.noised.push(state.noised[a as usize] && state.noised[b as usize]);
            state.frozen.push(true);
            state.appear.push(level as u32);
            state.splits.push([a, b]);
        }
        for &v in &made.region {
            state.frozen[v as usize] = true;
        }
        touched += made.splits.len();
        view = LevelView::new(level, depth, refiner.mesh()?).with_appearance(&state.appear);
        selected = view.ids.iter().map(|id| made.centres.binary_search(id).is_ok()).collect();
    }
    let marks: Vec<bool> = view.ids.iter().map(|&id| state.noised[id as usize]).collect();
    let noised = noised_regions(&view, marks);
    let moves: Vec<(usize, DVec3)> = match step.op {
        OperatorKind::Noise | OperatorKind::Variation | OperatorKind::Feature => {
            noise_displacements(step.op, &step.noise, &view, &state.frame, &selected, &noised, seed)?
        }
        OperatorKind::Organic => {
            organic_displacements(&step.organic, &step.noise, &view, &state.frame, &selected, &noised, seed)?
        }
        OperatorKind::Taper | OperatorKind::Twist => {
            let f = if step.op == OperatorKind::Taper { taper } else { twist };
            (0..selected.len())
                .filter(|&v| selected[v])
                .map(|v| (v, f(view.mesh.positions[v], &step.geometric, &state.frame)))
                .collect()
        }
        OperatorKind::Smooth => loop_smooth(&view, &selected, step.smooth.iterations),
        OperatorKind::Subdivide => Vec::new(),
    };
    check_moves(&moves, &view, &format!("the {:?} step at level {level}", step.op).to_lowercase())?;
    let marks_noise = matches!(
        step.op,
        OperatorKind::Noise | OperatorKind::Variation | OperatorKind::Feature | OperatorKind::Organic
    );
    touched += write_moves(refiner, &view, &moves, marks_noise.then_some(&mut state.noised));
    Ok(StepReport {
        step: 0,
        op: format!("{:?}", step.op).to_lowercase(),
        level,
        level_vertices: view.ids.len(),
        selected: selected.iter().filter(|&&s| s).count(),
        touched,
        seconds: 0.0,
    })
}
