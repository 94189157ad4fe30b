//! Feature-sensitive four-face-cluster simplification (thesis §3.1.7, §4.4.1, Algorithm 2
//! of §3.1.7): per level, vertices ranked by E(v) (eq. 4.1), a maximal independent set of
//! clusters chosen greedily, each brought to degree 4 by spoke flips and removed by an edge
//! weld, all carried out on the Rust rings; [`build_with_openmesh_replay`] also carries them
//! out on OpenMesh, one batched call per operation, as the build's check.

use std::time::Instant;

use rayon::prelude::*;

use rustc_hash::{FxHashMap, FxHashSet};
use smallvec::SmallVec;

use super::cluster::{ClusterRules, LevelGeometry, plan_cluster};
use super::crossings::KnownCrossings;
use super::give_way::{GiveWay, Rung, topological_floor};
use super::guard::guard_plans;
use super::lines::FeatureLines;
use super::param::{ParamBuckets, ParamPoint, PointPositions};
use super::plan::{ClusterPlan, apply_plan, plan_still_applies};
use super::plan_cache::{PlanCache, Planned, kept_within, ring_is_roomy};
use super::record::{Recorded, Recorder};
use super::rings::Rings;
use super::sliver_budget::SliverBudget;
use super::store::exported_triangles;
use super::vertex_class::{VertexClass, vertex_classes};
use super::vertex_table::VertexTable;
use super::wedges::Wedges;
use super::{BuildStages, FeatureVertices, Hierarchy, KeepFeatures, SimplifyOptions, used_vertices};
use crate::analysis::{FeatureClass, FeatureOptions, Quadric};
use crate::error::{Error, Result};
use crate::ffi::{self, HalfEdgeMesh};
use crate::mesh::{FaceId, Mesh, TopologyCounts, UnitFrame, ValidationReport, is_degenerate_face};
use glam::DVec3;

/// Builds the 4-k hierarchy of `mesh`: simplification down to the base domain, with the
/// parametrization of every removed vertex.
///
/// # Errors
/// [`Error::InvalidInput`] for an inconsistent mesh or options; [`Error::Topology`] for a
/// non-manifold mesh; [`Error::Native`] if OpenMesh or CGAL refuse it.
pub fn build(mesh: &Mesh, options: &SimplifyOptions) -> Result<Hierarchy> {
    let hierarchy = match options.chunks {
        Some(parts) => {
            // A partitioned build (#40) records no levels while it builds: refinement
            // makes them afterwards when asked.
            let inner = SimplifyOptions { chunks: None, record_levels: false, ..options.clone() };
            super::partition::build_partitioned(mesh, parts, &inner).and_then(|mut hierarchy| {
                if options.record_levels {
                    hierarchy.levels = hierarchy.levels_by_refinement()?;
                }
                Ok(hierarchy)
            })
        }
        None => build_with(mesh, options, cfg!(debug_assertions), None),
    };
    // The build's working sets (rings, plans, parameter buckets) were freed on its worker
    // threads, where they would stay resident: their pages go back before the caller goes
    // on (refinement at full resolution is the bench's peak otherwise, #35).
    crate::memory::trim();
    hierarchy
}

/// [`build`] continuing a hierarchy whose removed vertices lie on `mesh`'s faces: the
/// vertices with a point in `seeds` are on no face of `mesh` and are carried, as MAPS
/// carries the build's own removed vertices, to the base domain; every cluster's error
/// measures them too. `mesh` holds only the vertices of its faces: a seeded vertex's id
/// follows them (`seeds` has one entry per id, `None` for the mesh's own), so no array of
/// the planning's is sized by the vertices removed before (#40: a partitioned build's
/// merge). What the earlier builds found for the vertices they left is handed over in
/// [`Continuation`], so the continuation neither classifies nor measures the input again.
///
/// # Errors
/// As [`build`]; [`Error::InvalidInput`] for seeds of another length than the ids, a seed
/// on a vertex of a face or an id with neither.
pub(super) fn build_seeded(
    mesh: &Mesh,
    options: &SimplifyOptions,
    seeds: Vec<Option<ParamPoint>>,
    continuation: Continuation<'_>,
) -> Result<Hierarchy> {
    build_with(mesh, options, cfg!(debug_assertions), Some((seeds, continuation)))
}

/// What a continued build ([`build_seeded`]) starts from besides the removed vertices'
/// points on the mesh (which the parametrization takes over): the input those removals
/// simplified, whose seams and unit frame the build keeps, and what the earlier builds
/// found.
#[derive(Clone, Copy)]
pub(super) struct Continuation<'a> {
    /// The input the earlier builds simplified.
    pub input: &'a Mesh,
    /// The input's vertex of each of the continued build's ids: the mesh's vertices in
    /// ascending input order, then the seeded vertices.
    pub to_input: &'a [u32],
    /// The quadrics of the vertices the earlier builds left (the input's, accumulated along
    /// the earlier removals, in the input's unit frame), by the mesh's vertex id.
    pub quadrics: &'a [(u32, Quadric)],
    /// The classes of the vertices the earlier builds left, by the mesh's vertex id.
    pub classes: &'a [(u32, VertexClass)],
}

/// [`build`], with every level's plans also carried out on an OpenMesh store (flips and
/// welds, one batched call each) and the store's base domain checked against the planning
/// rings' (#20: the build plans on the rings alone; this replay is its check, run by the
/// tests and by debug builds).
///
/// # Errors
/// As [`build`]; [`Error::Internal`] if OpenMesh refuses a planned operation or ends with
/// other faces than the rings.
pub fn build_with_openmesh_replay(mesh: &Mesh, options: &SimplifyOptions) -> Result<Hierarchy> {
    if options.chunks.is_some() {
        return Err(Error::InvalidInput("the OpenMesh replay checks one-piece builds: set no chunks".into()));
    }
    build_with(mesh, options, true, None)
}

/// CGAL's discontinuity multiplier for the quadrics' boundary planes (its default):
/// every build's quadrics, and the ones a partitioned build's parts hand over.
pub const BOUNDARY_WEIGHT: f64 = 100.0;

/// Peak bytes of a build (and its refinement) per input triangle, rounded up from the
/// measured 336–374 (`cargo bench --bench hierarchy`, #35).
pub const BUILD_BYTES_PER_TRIANGLE: u64 = 400;

fn build_with(
    mesh: &Mesh,
    options: &SimplifyOptions,
    replay: bool,
    continuing: Option<(Vec<Option<ParamPoint>>, Continuation<'_>)>,
) -> Result<Hierarchy> {
    let (seeds, continuing) = match continuing {
        Some((seeds, c)) => (Some(seeds), Some(c)),
        None => (None, None),
    };
    let started = Instant::now();
    let mut stages = BuildStages::default();
    let mut clock = Instant::now();
    // Validation, the store and the quadrics are independent: the first error reported
    // is validation's, as if it had run alone.
    options.check()?;
    mesh.check()?;
    crate::memory::ensure_available(
        (mesh.triangles.len() as u64).saturating_mul(BUILD_BYTES_PER_TRIANGLE),
        &format!("a hierarchy of {} triangles", mesh.triangles.len()),
        "simplify a smaller mesh, or set a larger --max-memory where the machine has it",
    )?;
    // Every geometric decision is made in the unit frame (bounding box centred, diagonal
    // 1), so none depends on the model's units and no product of coordinates overflows;
    // the hierarchy keeps the input's own positions. A continued build's frame is its
    // input's, as the earlier builds' was.
    let unit = UnitFrame::of(continuing.map_or(mesh, |c| c.input))?;
    let working = unit.apply(mesh);
    // A continued build takes the quadrics the earlier builds handed over (below, once
    // its live vertices are known).
    let (prepared, (store, quadrics)) = rayon::join(
        || prepare_input(mesh, seeds.as_deref()),
        || {
            rayon::join(
                || HalfEdgeMesh::from_mesh(mesh),
                || match continuing {
                    Some(_) => Ok(None),
                    None => ffi::vertex_quadrics(&working, BOUNDARY_WEIGHT).map(Some),
                },
            )
        },
    );
    prepared?;
    let (store, quadrics) = (store?, quadrics?);
    let n = mesh.vertex_count();
    // Texture seams and material borders: lines of the build, and what each level's
    // faces take their UVs by (found once for both).
    let (seams, wedges) = seams_and_wedges(mesh, continuing)?;
    // A continued build takes the classes handed over, for the vertices they name.
    let Features { feature, kept, lines, give_way, class, directions } = match continuing {
        _ if options.keep_features == KeepFeatures::None => {
            features_and_kept(&working, std::iter::empty(), options, &seams)?
        }
        Some(c) => features_and_kept(&working, c.classes.iter().copied(), options, &seams)?,
        None => {
            let classes = vertex_classes(&working).into_iter().enumerate().map(|(v, c)| (v as u32, c));
            features_and_kept(&working, classes, options, &seams)?
        }
    };
    // Planning needs only the working positions; the copy's faces go now. A continued
    // build's seeded vertices are found in its input as they are needed.
    let working_positions = working.positions;
    let points = match (continuing, &seeds) {
        (Some(c), Some(seeds)) => seeded_positions(&working_positions, c, n..seeds.len(), unit)?,
        _ => PointPositions { own: &working_positions, seeded: None },
    };
    let referenced = used_vertices(n, &mesh.triangles);
    let live: Vec<u32> = (0..n as u32).filter(|&v| referenced[v as usize]).collect();
    let quadrics = match (continuing, quadrics) {
        (Some(c), _) => VertexTable::sparse(n, c.quadrics, &live, "quadric")?,
        (None, Some(computed)) => VertexTable::dense(computed),
        (None, None) => return Err(Error::Internal("a one-piece build without its quadrics".into())),
    };
    let mut rings = Rings::fetch(&store, &live, n)?;
    rings.fence(&options.border_vertices);
    rings.twin(&options.border_copies);
    let recorder = Recorder::new(&mesh.positions, &mesh.triangles, replay.then_some(store), options.record_levels);
    // The seeds become the parametrization's points (no second copy of them).
    let params = match seeds {
        Some(seeds) => {
            // In input order, whatever order the ids were given in (ties between equally
            // far points then fall as in a build over the input's ids).
            let mut order: Vec<u32> = (0..seeds.len() as u32).collect();
            if let Some(c) = continuing {
                order.sort_unstable_by_key(|&v| c.to_input[v as usize]);
            }
            ParamBuckets::seeded(seeds, points, order.into_iter())
        }
        None => ParamBuckets::new(n),
    };
    lap(&mut clock, &mut stages.prepare);

    // The guard decides on the input's own positions, then the obstacles' points.
    let obstacles = &options.obstacles;
    let corners = n + obstacles.points.len();
    if let Some(f) = obstacles.faces.iter().position(|t| t.iter().any(|&c| c as usize >= corners)) {
        return Err(Error::InvalidInput(format!("obstacle face {f} names a corner beyond the {corners} there are")));
    }
    let guard_positions: std::borrow::Cow<[DVec3]> = match obstacles.points.is_empty() {
        true => std::borrow::Cow::Borrowed(&mesh.positions),
        false => mesh.positions.iter().chain(&obstacles.points).copied().collect(),
    };
    let mut planner = Planner {
        points,
        model_positions: &guard_positions,
        options,
        kept,
        give_way,
        stopped_by: None,
        quadrics,
        rings,
        live,
        locked: vec![false; n],
        lines,
        params,
        slivers: SliverBudget::new(&working_positions, &mesh.triangles),
        cache: PlanCache::new(n),
        crossings: KnownCrossings::new(options.obstacles.faces.is_empty()),
    };
    // Planning runs here; the record (the removal records, and the OpenMesh replay when
    // asked) follows a level behind on its own thread. The channel holds nothing: a level's
    // plans are handed over when the recorder is free, so at most two levels of plans
    // exist at once.
    let (planned, recorded) = std::thread::scope(|scope| {
        let (sender, receiver) = std::sync::mpsc::sync_channel::<LevelPlans>(0);
        let worker = scope.spawn(move || -> Result<Recorded> {
            let mut recorder = recorder;
            for (plans, faces) in receiver {
                recorder.record(&plans, faces.as_deref())?;
            }
            Ok(recorder.finish())
        });
        let planned = planner.plan_levels(&mut stages, &mut clock, |plans| sender.send(plans).is_ok());
        drop(sender);
        let recorded = worker.join().unwrap_or_else(|_| Err(Error::Internal("the recorder thread panicked".into())));
        (planned, recorded)
    });
    let recorded = recorded?;
    planned?;
    [stages.store, stages.records, stages.export] = recorded.seconds;
    let base_triangles = planner.rings.faces(&planner.live);
    if let Some(store) = &recorded.store {
        check_agreement(&exported_triangles(store)?, &base_triangles)?;
    }
    let feature_vertices = planner.live.iter().filter(|&&v| feature[v as usize]).count();
    // A build that ended without saying why stopped at its level limit.
    let stopped_by = planner
        .stopped_by
        .take()
        .or_else(|| options.levels.map(|l| format!("the level limit (levels = {l}) came first")));
    let target = planner.give_way.report(
        options.target_vertices,
        planner.live.len(),
        // The levels keep the input's topology, so the base's few faces give its floor.
        topological_floor(n, &base_triangles),
        stopped_by,
    );
    let kept = std::mem::take(&mut planner.kept);
    let classes = planner
        .live
        .iter()
        .map(|&v| {
            let class = VertexClass {
                class: class.get(v as usize).copied().unwrap_or(FeatureClass::Face),
                strength: planner.give_way.strength(v),
                direction: directions.get(&v).copied().unwrap_or(DVec3::ZERO),
            };
            (v, class)
        })
        .collect();
    lap(&mut clock, &mut stages.export);
    Ok(Hierarchy {
        positions: mesh.positions.clone(),
        input_triangles: mesh.triangles.clone(),
        base_triangles,
        removals: recorded.removals,
        restore: recorded.restore,
        step_starts: recorded.step_starts,
        params: std::mem::take(&mut planner.params).into_points(),
        kept,
        feature_vertices,
        levels: recorded.levels,
        fix_threshold: options.fix_threshold_degrees.to_radians(),
        seconds: started.elapsed().as_secs_f64(),
        stages,
        wedges,
        target,
        classes,
    })
}

/// The seam edges of `mesh` and the wedges its levels take their UVs and materials by. A
/// continued build's mesh is a level of its input (a partitioned build's joined parts, #40,
/// its ids mapped to the input's by `to_input`): its seams are the input's seams as they
/// run along its edges, and its levels take the input's attributes.
fn seams_and_wedges(mesh: &Mesh, continuing: Option<Continuation>) -> Result<(Vec<[u32; 2]>, Option<Wedges>)> {
    match continuing {
        None => {
            let seams = crate::mesh::uv::seam_edges(mesh);
            let wedges = Wedges::of(mesh, &seams);
            Ok((seams, wedges))
        }
        Some(c) => {
            let wedges = Wedges::of(c.input, &crate::mesh::uv::seam_edges(c.input));
            let Some(w) = &wedges else { return Ok((Vec::new(), None)) };
            // The mesh's vertices are the input's in ascending order (`to_input`), so
            // ascending ids stay ascending and the seams stay sorted.
            let own = &c.to_input[..mesh.vertex_count().min(c.to_input.len())];
            let in_input: Vec<[u32; 3]> = mesh.triangles.iter().map(|t| t.map(|v| own[v as usize])).collect();
            let local = |v: u32| match own.binary_search(&v) {
                Ok(i) => Ok(i as u32),
                Err(_) => Err(Error::Internal(format!("seam vertex {v} is not the continued mesh's"))),
            };
            let seams = w.level_seam_edges(&in_input)?.into_iter().map(|[a, b]| Ok([local(a)?, local(b)?]));
            Ok((seams.collect::<Result<_>>()?, wedges))
        }
    }
}

/// The positions of a continued build's ids: the mesh's (`own`, in the `unit` frame), then
/// the seeded vertices' (`seeded`, ids after them), read from its input as needed.
///
/// # Errors
/// [`Error::InvalidInput`] for seeded ids `to_input` does not map, or maps beyond the input.
fn seeded_positions<'a>(
    own: &'a [DVec3],
    c: Continuation<'a>,
    seeded: std::ops::Range<usize>,
    unit: UnitFrame,
) -> Result<PointPositions<'a>> {
    let ids = c.to_input.get(seeded.clone()).ok_or_else(|| {
        Error::InvalidInput(format!("{} input ids for {} continued vertices", c.to_input.len(), seeded.end))
    })?;
    if let Some(&v) = ids.iter().find(|&&v| v as usize >= c.input.positions.len()) {
        return Err(Error::InvalidInput(format!("seeded vertex {v} is beyond the input's")));
    }
    Ok(PointPositions { own, seeded: Some((c.to_input, &c.input.positions, unit)) })
}

/// One level's plans for the recorder, with the level's faces after them when levels are
/// recorded.
type LevelPlans = (Vec<ClusterPlan>, Option<Vec<[u32; 3]>>);

/// The planning side of [`build`]: the level's rings, quadrics and live vertices.
struct Planner<'a> {
    /// Positions in the unit frame (the build's working copy: `points.own`), then a
    /// continued build's seeded vertices'.
    points: PointPositions<'a>,
    /// The input's own positions, which every level keeps, then the obstacles' points
    /// ([`SimplifyOptions::obstacles`]): the intersection guard decides on them, since the
    /// unit frame's rounding can part faces that touch in the model (#34: a Menger
    /// sponge's coplanar faces met at 21 face pairs of the result though the guard,
    /// deciding in the unit frame, had found none).
    model_positions: &'a [DVec3],
    options: &'a SimplifyOptions,
    /// Vertices not removed (features not on a line, boundary junctions, user marks) until
    /// the give-way ladder releases them.
    kept: Vec<bool>,
    give_way: GiveWay,
    /// Why the build stopped short of its target, when it did.
    stopped_by: Option<String>,
    quadrics: VertexTable<crate::analysis::Quadric>,
    rings: Rings,
    live: Vec<u32>,
    locked: Vec<bool>,
    /// The level's feature lines.
    lines: FeatureLines,
    /// Where every removed vertex lies on the current level (MAPS).
    params: ParamBuckets,
    /// How many slivers clusters under the angle floor may still make.
    slivers: SliverBudget,
    /// Each vertex's plan while nothing it reads has changed.
    cache: PlanCache,
    /// The level's faces that intersect one another, for the guard.
    crossings: KnownCrossings,
}

/// What the level loop carries from one level to the next.
struct LevelLoop {
    rules: ClusterRules,
    /// Levels planned.
    steps: usize,
    /// Tries of the current level whose every plan offended the guard.
    retries: usize,
    /// Vertices whose plans the guard dropped on the last level (or the last tries).
    waiting: FxHashSet<u32>,
    /// Whether the waiting vertices were planned again once before stopping.
    waiting_retried: bool,
}

/// Whether the level loop goes on after a level that planned nothing.
enum Next {
    /// Plan the level again (without the offenders, or after something gave way).
    Retry,
    /// Stop: the target, a bound or an invariant is reached (`stopped_by` says which).
    Stop,
}

impl Planner<'_> {
    /// Plans level after level until a limit is reached, handing each level's plans to
    /// `record` (which returns false when the record has stopped). Each level: rank the
    /// candidates and set the level's error limit ([`Planner::rank_level`]), select and
    /// guard its clusters ([`Planner::plan_level`]), then either apply them
    /// ([`Planner::apply_level`]) or, with none left, give something way or stop
    /// ([`Planner::after_empty_level`]).
    fn plan_levels(
        &mut self,
        stages: &mut BuildStages,
        clock: &mut Instant,
        mut record: impl FnMut(LevelPlans) -> bool,
    ) -> Result<()> {
        let options = self.options;
        let mut state = LevelLoop {
            rules: ClusterRules {
                removal_weight: options.removal_weight,
                swap_weight: options.swap_weight,
                min_angle: self.give_way.floor().to_radians(),
                under_floor: false,
            },
            steps: 0,
            retries: 0,
            waiting: FxHashSet::default(),
            waiting_retried: false,
        };
        let first_live = self.live.len();
        let to_remove = first_live.saturating_sub(options.target_vertices.unwrap_or(0)).max(1) as u64;
        crate::progress::report("simplify", 0, to_remove);
        if let Some(target) = options.target_vertices.filter(|_| options.max_error.is_none() && options.give_way) {
            self.give_way.release_to_budget(target, &self.live, &mut self.kept, &mut self.lines, &self.rings);
        }
        while options.levels.is_none_or(|l| state.steps < l) {
            if options.target_vertices.is_some_and(|t| self.live.len() <= t) {
                break;
            }
            let (mut ranked, limit) = self.rank_level(&mut state);
            lap(clock, &mut stages.ranking);
            let (plans, offenders) = self.plan_level(&mut ranked, &state.rules, limit, stages, clock)?;
            self.cache.give_back(ranked);
            if plans.is_empty() {
                match self.after_empty_level(&mut state, offenders) {
                    Next::Retry => continue,
                    Next::Stop => break,
                }
            }
            state.retries = 0;
            state.waiting_retried = false;
            state.waiting = offenders;
            self.apply_level(&plans);
            self.cache.forget_after_level(&plans, &self.rings);
            state.steps += 1;
            crate::progress::report("simplify", (first_live - self.live.len()) as u64, to_remove);
            lap(clock, &mut stages.planning);
            self.params.apply_removals(&plans, self.points);
            lap(clock, &mut stages.parametrization);
            let faces = options.record_levels.then(|| self.rings.faces(&self.live));
            let recording = record((plans, faces));
            // What the level freed goes back to the system before the next one allocates:
            // freed in the workers' arenas, it would stay resident beside it. Only while the
            // mesh is at least half its size: the peak is in the first levels (#35), and a
            // trim walks the whole heap's free pages whatever the level's size.
            if self.live.len() * 2 >= first_live {
                crate::memory::trim();
            }
            lap(clock, &mut stages.handoff);
            if !recording {
                break;
            }
        }
        crate::progress::report("simplify", to_remove, to_remove);
        Ok(())
    }

    /// Ranks the level's candidates (the last level's offenders wait a level: planned again
    /// at once they would likely offend again and take the place of clusters that can go)
    /// and sets its error limit; with a vertex target, kept vertices that are nearly free to
    /// remove are released to join them.
    fn rank_level(&mut self, state: &mut LevelLoop) -> (Vec<Candidate>, f64) {
        let options = self.options;
        let geometry = level_geometry(self.points, &self.quadrics, &self.params, &self.lines);
        state.rules.under_floor = self.slivers.has_room();
        let need = options.target_vertices.map_or(usize::MAX, |t| self.live.len().saturating_sub(t));
        let mut ranked = ranked_candidates(
            &self.live,
            &state.waiting,
            &self.rings,
            &self.kept,
            geometry,
            &state.rules,
            need,
            &mut self.cache,
        );
        let max_error = options.max_error.map(|f| f * f);
        let limit = level_error_limit(&ranked, need, PLAN_TOLERANCE).min(max_error.unwrap_or(f64::INFINITY));
        if options.target_vertices.is_none() || options.max_error.is_some() || !options.give_way || !limit.is_finite() {
            return (ranked, limit);
        }
        let cheap = self.give_way.cheap_to_release(
            &self.live,
            &state.waiting,
            &self.kept,
            &self.rings,
            geometry,
            &state.rules,
            limit,
        );
        if !cheap.is_empty() {
            self.give_way.release_planned(&cheap, &mut self.kept, &mut self.lines, &self.rings);
            // A release changes the lines of the vertex and of its ring: their plans are
            // made again by selection, on the lines as they now are.
            let touched: FxHashSet<u32> =
                cheap.iter().flat_map(|&(_, v)| self.rings.ring(v).iter().copied().chain([v])).collect();
            self.cache.forget_around(touched.iter().copied(), &self.rings);
            for candidate in &mut ranked {
                if touched.contains(&candidate.vertex) {
                    candidate.plan = None;
                }
            }
            ranked.extend(cheap.into_iter().map(|(error, vertex)| Candidate { error, vertex, plan: None }));
            ranked.par_sort_unstable_by(|a, b| a.error.total_cmp(&b.error).then(a.vertex.cmp(&b.vertex)));
        }
        (ranked, limit)
    }

    /// Selects the level's clusters under `limit` and, with the guard on, drops the plans
    /// whose new faces would cut the surface: the plans kept and the vertices of those
    /// dropped.
    fn plan_level(
        &mut self,
        ranked: &mut [Candidate],
        rules: &ClusterRules,
        limit: f64,
        stages: &mut BuildStages,
        clock: &mut Instant,
    ) -> Result<(Vec<ClusterPlan>, FxHashSet<u32>)> {
        let options = self.options;
        let geometry = level_geometry(self.points, &self.quadrics, &self.params, &self.lines);
        // The obstacles stand beside the level's faces: new faces must not cut them either.
        let mut level_faces = Vec::new();
        if options.prevent_intersections {
            level_faces = self.rings.faces(&self.live);
            level_faces.extend_from_slice(&options.obstacles.faces);
        }
        lap(clock, &mut stages.guard);
        self.rings.checkpoint();
        let mut plans = select_clusters(
            ranked,
            &mut self.rings,
            geometry,
            rules,
            &mut self.locked,
            self.live.len(),
            options,
            limit,
            &self.slivers,
        )?;
        for &v in &self.live {
            self.locked[v as usize] = false;
        }
        lap(clock, &mut stages.planning);
        let mut offenders = FxHashSet::default();
        if options.prevent_intersections {
            (plans, offenders) =
                guard_plans(self.model_positions, &level_faces, plans, &mut self.rings, &mut self.crossings)?;
            lap(clock, &mut stages.guard);
        }
        self.rings.commit();
        Ok((plans, offenders))
    }

    /// A level that planned nothing: retried without its offenders (a few times), else
    /// short of the target something gives way (`give_way`), else the build stops and
    /// says why.
    fn after_empty_level(&mut self, state: &mut LevelLoop, offenders: FxHashSet<u32>) -> Next {
        let options = self.options;
        if !offenders.is_empty() && state.retries < MAX_RETRIES {
            state.retries += 1;
            state.waiting.extend(offenders);
            return Next::Retry;
        }
        let Some(target) = options.target_vertices.filter(|&t| self.live.len() > t) else { return Next::Stop };
        if options.max_error.is_some() {
            self.stopped_by = Some("the error bound (max_error) is reached first".to_string());
            return Next::Stop;
        }
        let need = self.live.len() - target;
        let rung = match options.give_way {
            true => self.give_way.next(need, &self.live, &mut self.kept, &mut self.lines, &self.rings),
            false => None,
        };
        // A release changes lines and kept vertices anywhere (a floor changes the rules,
        // which the plan cache watches itself).
        if matches!(rung, Some(Rung::Released(_))) {
            self.cache.forget_all();
        }
        match rung {
            Some(Rung::Floor(degrees)) => state.rules.min_angle = degrees.to_radians(),
            Some(Rung::Released(_)) => state.rules.min_angle = self.give_way.floor().to_radians(),
            // The last level's offenders sat this level out: before stopping, they are
            // planned again once (the level has changed around them).
            None if !state.waiting.is_empty() && !state.waiting_retried => {
                state.waiting_retried = true;
                state.waiting.clear();
                return Next::Retry;
            }
            None => {
                self.stopped_by = Some(self.why_stopped(!offenders.is_empty() || !state.waiting.is_empty()));
                return Next::Stop;
            }
        }
        state.retries = 0;
        state.waiting.clear();
        Next::Retry
    }

    /// What stops the build short of its target: the guard (when the last tries' offenders
    /// still had plans) or no valid cluster; and the vertices that never give way.
    fn why_stopped(&self, by_guard: bool) -> String {
        let fixed = self.live.iter().filter(|&&v| self.give_way.is_fixed(v)).count();
        let held = match fixed {
            0 => String::new(),
            n => format!(
                "; {n} vertices that never give way are kept (--feature-vertices keep, texture seams, marked vertices)"
            ),
        };
        let cause = if by_guard {
            "the intersection guard: every remaining cluster would make the surface cut itself"
        } else {
            "no valid cluster is left: every remaining removal would flip or fold a face, make an edge that exists (genus, manifoldness) or close a boundary loop"
        };
        cause.to_string() + &held
    }

    /// Carries out a level's plans on the planner's state: the sliver budget, each removed
    /// vertex's quadric shared by its diagonal's ends, feature lines merged along their
    /// line, the removed vertices off the live list.
    fn apply_level(&mut self, plans: &[ClusterPlan]) {
        self.give_way.under_floor += plans.iter().filter(|p| p.under_floor).count();
        self.slivers.apply(plans, self.points.own);
        for plan in plans {
            crate::analysis::share_removed_quadric(&mut self.quadrics, plan.vertex, plan.diagonal);
        }
        for plan in plans {
            if let Some((ends, bound)) = plan.along_line {
                self.lines.merge(plan.vertex, ends, bound);
            }
        }
        let removed: FxHashSet<u32> = plans.iter().map(|p| p.vertex).collect();
        self.live.retain(|v| !removed.contains(v));
    }
}

/// The level's geometry as cluster planning reads it (from the planner's fields, borrowed
/// apart so that the planner's other fields stay free).
fn level_geometry<'g>(
    points: PointPositions<'g>,
    quadrics: &'g VertexTable<crate::analysis::Quadric>,
    params: &'g ParamBuckets,
    lines: &'g FeatureLines,
) -> LevelGeometry<'g> {
    LevelGeometry { points, quadrics, tolerance: PLAN_TOLERANCE, params, lines }
}

/// Planning is in the unit frame (diagonal 1): fractions of the input's diagonal are
/// distances there, and errors (squared distances) below this are ties.
const PLAN_TOLERANCE: f64 = 1e-9 * 1e-9;

/// The store's faces must be the rings' faces: planning edits the rings, OpenMesh carries
/// out the same operations (checking each), so a difference is a bug.
fn check_agreement(store_faces: &[[u32; 3]], ring_faces: &[[u32; 3]]) -> Result<()> {
    let sorted = |faces: &[[u32; 3]]| {
        let mut keys: Vec<[u32; 3]> = faces.iter().map(|&t| super::face_key(t)).collect();
        keys.sort_unstable();
        keys
    };
    if sorted(store_faces) != sorted(ring_faces) {
        return Err(Error::Internal(format!(
            "OpenMesh holds {} faces and the planning rings {} different ones",
            store_faces.len(),
            ring_faces.len()
        )));
    }
    Ok(())
}

/// Adds the time since `clock` to `stage` and restarts the clock.
fn lap(clock: &mut Instant, stage: &mut f64) {
    let now = Instant::now();
    *stage += (now - *clock).as_secs_f64();
    *clock = now;
}

/// Input preparation (§4.3): the mesh must be a consistently oriented manifold triangle
/// mesh without degenerate faces or unreferenced vertices (polygons are triangulated by the
/// readers; [`crate::mesh::repair`] fixes the rest); degree-4 clusters are then made by
/// flips during simplification. [`build`] has run `Mesh::check` (indices in range) first.
pub(super) fn prepare_input(mesh: &Mesh, seeds: Option<&[Option<ParamPoint>]>) -> Result<()> {
    if mesh.face_count() == 0 {
        return Err(Error::InvalidInput("the mesh has no faces to simplify".into()));
    }
    let report = ValidationReport::of(mesh);
    check_oriented_manifold(&TopologyCounts::of_report(&report), Some(report.orientable))?;
    check_faces_and_vertices(mesh, seeds)
}

/// Refuses a mesh whose `counts` make it other than an oriented manifold; `orientable`,
/// where it is known, tells a Möbius-like twist from faces merely flipped.
pub(crate) fn check_oriented_manifold(counts: &TopologyCounts, orientable: Option<bool>) -> Result<()> {
    if counts.is_manifold() && orientable == Some(false) {
        let msg = "the surface is not orientable (a Möbius-like twist): the hierarchy needs an oriented manifold, and no orientation of its faces exists".to_string();
        return Err(Error::Topology { msg, faces: Vec::new() });
    }
    if !counts.is_manifold() || counts.inconsistently_oriented_edges > 0 {
        let msg = format!(
            "the mesh is not an oriented manifold ({} non-manifold edges, {} non-manifold vertices, {} inconsistently oriented edges); --repair splits and orients it where the surface is orientable",
            counts.non_manifold_edges, counts.non_manifold_vertices, counts.inconsistently_oriented_edges
        );
        return Err(Error::Topology { msg, faces: Vec::new() });
    }
    Ok(())
}

/// Refuses faces of zero area and vertices on no face (a continued build's seeded vertices
/// excepted, which must be exactly those).
pub(crate) fn check_faces_and_vertices(mesh: &Mesh, seeds: Option<&[Option<ParamPoint>]>) -> Result<()> {
    let refuse =
        |msg: String, faces: Vec<FaceId>| Err(Error::Topology { msg: format!("{msg}; --repair fixes it"), faces });
    let degenerate: Vec<FaceId> =
        (0..mesh.face_count()).filter(|&f| is_degenerate_face(mesh, f)).map(|f| FaceId(f as u32)).collect();
    if let Some(first) = degenerate.first() {
        return refuse(
            format!(
                "{} face(s) have zero area, first face {} (the hierarchy cannot parametrize over them)",
                degenerate.len(),
                first.0
            ),
            degenerate,
        );
    }
    let used = used_vertices(mesh.vertex_count(), &mesh.triangles);
    // A continued build's seeded vertices may also follow the mesh's (`build_seeded`).
    if let Some(seeds) = seeds {
        if seeds.len() < mesh.vertex_count() {
            return Err(Error::InvalidInput(format!("{} seeds for {} vertices", seeds.len(), mesh.vertex_count())));
        }
        let on_face = |v: usize| used.get(v).copied().unwrap_or(false);
        if let Some(v) = (0..seeds.len()).find(|&v| seeds[v].is_some() == on_face(v)) {
            let what = if on_face(v) { "a vertex of a face has a seed" } else { "a vertex on no face has no seed" };
            return Err(Error::InvalidInput(format!("{what}: vertex {v}")));
        }
        return Ok(());
    }
    let unreferenced = used.iter().filter(|&&u| !u).count();
    if unreferenced > 0 {
        let first = used.iter().position(|u| !u).expect("an unreferenced vertex");
        return refuse(format!("{unreferenced} vertex/vertices belong to no face, first vertex {first}"), Vec::new());
    }
    Ok(())
}

/// The feature vertices (§4.4.1.1, Algorithm 1 classes chosen by `keep_features`), their
/// lines, the boundary loops and the texture `seams`, and the vertices kept until the
/// give-way ladder releases them (see `give_way`):
/// corners, the feature, boundary and seam vertices not on a line (every one with
/// [`FeatureVertices::Keep`]) and those the user marked. The classes are found on
/// `classified` (the mesh itself, or the input a continued build's mesh simplifies: its
/// coarser faces would make more features), the lines on `mesh`'s edges.
fn features_and_kept(
    mesh: &Mesh,
    classes: impl Iterator<Item = (u32, VertexClass)>,
    options: &SimplifyOptions,
    seams: &[[u32; 2]],
) -> Result<Features> {
    let n = mesh.vertex_count();
    let mut feature = vec![false; n];
    let mut corner = vec![false; n];
    let mut strength = vec![0.0; n];
    let mut directions: FxHashMap<u32, DVec3> = FxHashMap::default();
    let mut class = Vec::new();
    if options.keep_features != KeepFeatures::None {
        class = vec![VertexClass::FLAT.class; n];
        for (v, c) in classes {
            let slot = class
                .get_mut(v as usize)
                .ok_or_else(|| Error::InvalidInput(format!("a class handed over for vertex {v} of {n}")))?;
            *slot = c.class;
            let v = v as usize;
            strength[v] = c.strength;
            feature[v] = match options.keep_features {
                KeepFeatures::None => false,
                KeepFeatures::Corners => c.class == FeatureClass::Corner,
                KeepFeatures::Strong => c.class.is_sharp(),
                KeepFeatures::All => c.class != FeatureClass::Face,
            };
            corner[v] = c.class == FeatureClass::Corner;
            match feature[v] && !corner[v] {
                true => directions.insert(v as u32, c.direction),
                false => directions.remove(&(v as u32)),
            };
        }
    }
    let along = options.feature_vertices == FeatureVertices::AlongLines;
    let follows = follows_feature(mesh, &corner, &directions);
    let lines = FeatureLines::new(&feature, &corner, &mesh.triangles, along, seams, follows);
    let line_like = |v: u32| feature[v as usize] || lines.is_boundary(v) || lines.is_on_seam(v);
    let mut kept: Vec<bool> = (0..n as u32).map(|v| line_like(v) && !lines.is_on_line(v)).collect();
    // What never gives way to the target: texture seams, the user's marks, and the
    // feature vertices `--feature-vertices keep` asks to keep.
    let mut fixed: Vec<bool> = (0..n as u32).map(|v| lines.is_on_seam(v) || (!along && feature[v as usize])).collect();
    for &v in options.keep_vertices.iter().chain(&options.border_vertices) {
        let slot = kept
            .get_mut(v as usize)
            .ok_or_else(|| Error::InvalidInput(format!("vertex {v} marked to keep is out of range ({n} vertices)")))?;
        *slot = true;
        fixed[v as usize] = true;
    }
    Ok(Features { feature, kept, lines, give_way: GiveWay::new(strength, fixed), class, directions })
}

/// Whether the edge a–b between two feature vertices runs along their feature (#34): within
/// NVC's "along" angle (`nvc_along_degrees`, 30°) of the principal diffusion direction —
/// the crease's direction — at each end that is not a corner, and, between two corners,
/// over a dihedral angle of at least [`CORNER_EDGE_DEGREES`]. An edge across a face between
/// two creases (a CAD fan joining the two rims of an annulus) is no feature edge: counted as
/// one, it made every rim vertex a junction, kept until the target forced it out.
fn follows_feature<'a>(
    mesh: &'a Mesh,
    corner: &'a [bool],
    direction: &'a FxHashMap<u32, DVec3>,
) -> impl Fn(u32, u32) -> bool + 'a {
    let cos_along = FeatureOptions::default().nvc_along_degrees.to_radians().cos();
    let mut corner_edges: FxHashMap<[u32; 2], SmallVec<[DVec3; 2]>> = FxHashMap::default();
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|v| mesh.positions[v as usize]);
        let normal = (b - a).cross(c - a).normalize_or_zero();
        for k in 0..3 {
            let (u, w) = (t[k], t[(k + 1) % 3]);
            if corner[u as usize] && corner[w as usize] {
                corner_edges.entry([u.min(w), u.max(w)]).or_default().push(normal);
            }
        }
    }
    let cos_corner = CORNER_EDGE_DEGREES.to_radians().cos();
    move |a, b| {
        let along = (mesh.positions[b as usize] - mesh.positions[a as usize]).normalize_or_zero();
        match (direction.get(&a).copied(), direction.get(&b).copied()) {
            (None, None) => {
                corner_edges.get(&[a.min(b), a.max(b)]).is_some_and(|n| n.len() == 2 && n[0].dot(n[1]) <= cos_corner)
            }
            (da, db) => [da, db].into_iter().flatten().all(|d| d.dot(along).abs() >= cos_along),
        }
    }
}

/// The smallest dihedral angle (between face normals) of an edge joining two corners that
/// makes it a feature edge, degrees.
const CORNER_EDGE_DEGREES: f64 = 20.0;

/// What [`features_and_kept`] finds.
struct Features {
    feature: Vec<bool>,
    kept: Vec<bool>,
    lines: FeatureLines,
    /// The ladder of what may give way to the target, with each vertex's feature strength.
    give_way: GiveWay,
    /// Each vertex's class (empty when features are not asked for), and the crease's
    /// direction at each feature vertex off a corner: with the strength, what the build
    /// reports of its base vertices ([`Hierarchy::classes`]).
    class: Vec<FeatureClass>,
    directions: FxHashMap<u32, DVec3>,
}

/// How often a level whose every plan offended the intersection guard is tried again.
const MAX_RETRIES: usize = 4;

/// Share of a level's candidates, cheapest first, whose errors set the level's limit.
const LEVEL_QUANTILE: f64 = 0.2;

/// A removable vertex with the E(v) of the cluster it would be on this level's rings, and
/// the plan itself when ranking kept it (#35: each plan computed once per level).
pub(super) struct Candidate {
    pub(super) error: f64,
    pub(super) vertex: u32,
    pub(super) plan: Option<Box<ClusterPlan>>,
}

/// Stars sampled to estimate which plans ranking keeps ([`plan_bound`]).
const BOUND_SAMPLE: usize = 2048;

/// The largest E(v) whose plan ranking keeps for selection: a level selects only
/// candidates within its limit ([`level_error_limit`]), so ranking keeps the plans up to an
/// estimate of it, from every k-th eligible vertex planned first (the sample's quantile at
/// the level's goal, with a margin of 1.25 in rank and 3 in error). A limit above the
/// estimate costs only time: the candidates between are planned again by selection. Meshes
/// of up to four samples keep every plan.
fn plan_bound(
    eligible: &[u32],
    rings: &Rings,
    geometry: LevelGeometry<'_>,
    rules: &ClusterRules,
    need: usize,
    cache: &PlanCache,
) -> f64 {
    if eligible.len() <= 4 * BOUND_SAMPLE {
        return f64::INFINITY;
    }
    let stride = eligible.len().div_ceil(BOUND_SAMPLE);
    let mut errors: Vec<f64> = eligible
        .par_iter()
        .step_by(stride)
        .filter_map(|&v| cache.error(v).unwrap_or_else(|| plan_cluster(v, rings, geometry, rules).map(|p| p.error)))
        .collect();
    if errors.is_empty() {
        return f64::INFINITY;
    }
    errors.sort_unstable_by(f64::total_cmp);
    let ranked = (errors.len() * stride) as f64;
    let goal = (need as f64 / ranked).min(LEVEL_QUANTILE) * 1.25;
    let at = ((goal * errors.len() as f64) as usize).min(errors.len() - 1);
    3.0 * 1.5 * errors[at] + geometry.tolerance
}

/// Removable candidates with the E(v) of the cluster each would be on this level's rings,
/// cheapest first (ties by vertex id), each with its plan where its error is within
/// [`plan_bound`]; vertices with no valid cluster, and those `waiting`, are left out. Only
/// the vertices whose plans `cache` no longer holds are planned.
#[allow(clippy::too_many_arguments)]
fn ranked_candidates(
    live: &[u32],
    waiting: &FxHashSet<u32>,
    rings: &Rings,
    kept: &[bool],
    geometry: LevelGeometry<'_>,
    rules: &ClusterRules,
    need: usize,
    cache: &mut PlanCache,
) -> Vec<Candidate> {
    let eligible: Vec<u32> = live
        .par_iter()
        .copied()
        .filter(|&v| {
            !kept[v as usize] && !waiting.contains(&v) && rings.degree(v) >= if rings.is_boundary(v) { 3 } else { 4 }
        })
        .collect();
    cache.use_rules(rules);
    let bound = plan_bound(&eligible, rings, geometry, rules, need, cache);
    #[cfg(debug_assertions)]
    check_cached_plans(&eligible, rings, geometry, rules, cache);
    let stale: Vec<u32> = eligible.iter().copied().filter(|&v| cache.is_stale(v)).collect();
    let planned: Vec<(Planned, bool)> = stale
        .par_iter()
        .map(|&v| (kept_within(plan_cluster(v, rings, geometry, rules), bound), ring_is_roomy(v, rings)))
        .collect();
    for (v, (plan, roomy)) in stale.into_iter().zip(planned) {
        cache.store(v, plan, roomy);
    }
    let mut ranked: Vec<Candidate> = eligible.iter().filter_map(|&v| cache.candidate(v, bound)).collect();
    ranked.par_sort_unstable_by(|a, b| a.error.total_cmp(&b.error).then(a.vertex.cmp(&b.vertex)));
    ranked
}

/// Debug builds check the plan cache's premise: the vertices whose plans it kept (all of
/// them on small meshes, one in 16 beyond 4096 candidates), planned again, give the same
/// E(v) to the bit, and the same plan where the cache holds it.
#[cfg(debug_assertions)]
fn check_cached_plans(
    eligible: &[u32],
    rings: &Rings,
    geometry: LevelGeometry<'_>,
    rules: &ClusterRules,
    cache: &PlanCache,
) {
    let stride = if eligible.len() <= 4096 { 1 } else { 16 };
    eligible.par_iter().filter(|&&v| v % stride == 0).for_each(|&v| {
        if let Some(kept) = cache.error(v) {
            let fresh = plan_cluster(v, rings, geometry, rules);
            let error = fresh.as_ref().map(|p| p.error.to_bits());
            assert_eq!(kept.map(f64::to_bits), error, "the plan cache kept a stale plan of vertex {v}");
            if let Some(plan) = cache.plan(v) {
                assert_eq!(Some(plan), fresh.as_ref(), "the plan cache kept a stale plan of vertex {v}");
            }
        }
    });
}

/// The error limit of one level, after meshoptimizer's passes (Kapoulkine, `simplify`):
/// 1.5 times the error of the candidate at the goal, where the goal is the number of
/// vertices still to remove or [`LEVEL_QUANTILE`] of the candidates, whichever is
/// smaller. A level then removes only clusters among the cheap ones, so the expensive ones
/// wait for coarser levels, where their errors are measured again.
fn level_error_limit(ranked: &[Candidate], need: usize, tolerance: f64) -> f64 {
    let goal = need.min((ranked.len() as f64 * LEVEL_QUANTILE) as usize);
    ranked.get(goal).map_or(f64::INFINITY, |c| 1.5 * c.error + tolerance)
}

/// Greedy independent set of clusters (Velho & Gomes' marking) among the candidates whose
/// E(v) is within the level's `limit`: take the cheapest unmarked vertex, carry out its
/// cluster, and mark it and its ring. The clusters come planned from ranking, or are
/// planned in parallel on the level's rings first where ranking did not keep them; one that
/// no longer applies once cheaper ones changed its ring's neighbourhood is planned again.
#[allow(clippy::too_many_arguments)]
fn select_clusters(
    ranked: &mut [Candidate],
    rings: &mut Rings,
    geometry: LevelGeometry<'_>,
    rules: &ClusterRules,
    locked: &mut [bool],
    live: usize,
    options: &SimplifyOptions,
    limit: f64,
    slivers: &SliverBudget,
) -> Result<Vec<ClusterPlan>> {
    let mut slivers = slivers.clone();
    let within = ranked.partition_point(|c| c.error <= limit);
    {
        let rings: &Rings = rings;
        ranked[..within].par_iter_mut().filter(|c| c.plan.is_none()).for_each(|c| {
            c.plan = plan_cluster(c.vertex, rings, geometry, rules).map(Box::new);
        });
    }
    let mut plans: Vec<ClusterPlan> = Vec::new();
    let mut counted = 0;
    for candidate in &mut ranked[..within] {
        let (v, plan) = (candidate.vertex, candidate.plan.take().map(|p| *p));
        if options.target_vertices.is_some_and(|t| live - plans.len() <= t) {
            break;
        }
        if locked[v as usize] {
            continue;
        }
        let plan = match plan {
            Some(plan) if plan_still_applies(&plan, rings) => plan,
            _ => match plan_cluster(v, rings, geometry, rules) {
                Some(plan) if plan.error <= limit => plan,
                _ => continue,
            },
        };
        // Only a cluster under the angle floor asks the budget, so the others are counted
        // when one does (in the same order: the same counts), and not at all on a level
        // that has none.
        if plan.under_floor {
            for before in &plans[counted..] {
                slivers.take(before, geometry.points.own);
            }
            counted = plans.len();
            if !slivers.take(&plan, geometry.points.own) {
                continue;
            }
            counted += 1;
        }
        apply_plan(&plan, rings)?;
        locked[v as usize] = true;
        for &r in &plan.ring {
            locked[r as usize] = true;
        }
        plans.push(plan);
    }
    Ok(plans)
}
