//! The hierarchy for C++: a built hierarchy (levels, parametrization, region refinement)
//! and a refinement driven level by level from C++, where a user's operator moves each
//! level's vertices between two calls (the thesis' D(VS, l, f), eq. 4.4, with f in C++).

use asperity::detail::LevelView;

use crate::bridge::ProgressCallback;
use crate::progress::watched;
use asperity::hierarchy::region::refine_region;
use asperity::hierarchy::{FeatureVertices, Hierarchy, HierarchyRequest, Refiner, SimplifyOptions, build};
use asperity::request::Spelling;
use asperity::{Error, Mesh, Result};

use crate::arrays::{analysis_arrays, corner_uvs_of, flat, level_arrays, mask_of, mesh_of, vectors_of};
use crate::bridge::{Analysis, HierarchyOptions, LevelArrays, Parametrization, RegionOutcome, Report, ViewArrays};
use crate::guarded;
use crate::pipeline::{named, target_of};

/// A hierarchy with every level recorded, and its input.
pub struct BuiltHierarchy {
    input: Mesh,
    inner: Hierarchy,
}

pub fn default_hierarchy_options() -> HierarchyOptions {
    let d = SimplifyOptions::default();
    HierarchyOptions {
        has_target_vertices: false,
        target_vertices: 0,
        has_levels: false,
        levels: 0,
        has_max_error: false,
        max_error: 0.0,
        keep_features: "strong".into(),
        feature_vertices: "along-lines".into(),
        keep_vertices: Vec::new(),
        removal_weight: d.removal_weight,
        swap_weight: d.swap_weight,
        fix_threshold_degrees: d.fix_threshold_degrees,
        intersection_guard: d.prevent_intersections,
        chunks: 0,
    }
}

/// The library's options from the C++ struct: its settings as the hierarchy's request
/// (checked and named as `option .name`), then what only C++ gives (kept vertices,
/// Algorithm 3's threshold).
fn simplify_options(o: &HierarchyOptions, vertices: usize) -> Result<SimplifyOptions> {
    let request = HierarchyRequest {
        target_vertices: o.has_target_vertices.then(|| target_of(o.target_vertices)).transpose()?,
        levels: o.has_levels.then_some(o.levels),
        max_error: o.has_max_error.then_some(o.max_error),
        keep_features: Some(named("keep_features", &o.keep_features)?),
        // The member always holds a name: its default counts as unset, so that it is not
        // refused beside keep_features = "none" (where it has nothing to apply to).
        feature_vertices: Some(named::<FeatureVertices>("feature_vertices", &o.feature_vertices)?)
            .filter(|f| *f != FeatureVertices::default()),
        removal_weight: Some(o.removal_weight),
        swap_weight: Some(o.swap_weight),
        intersection_guard: Some(o.intersection_guard),
        chunks: (o.chunks > 0).then_some(o.chunks),
    };
    let options = SimplifyOptions {
        keep_vertices: o.keep_vertices.clone(),
        fix_threshold_degrees: o.fix_threshold_degrees,
        ..request.options(vertices, true, Spelling::Member)?
    };
    options.check()?;
    Ok(options)
}

pub fn build_hierarchy(
    positions: &[f64],
    triangles: &[u32],
    corner_uvs: &[f64],
    options: &HierarchyOptions,
    progress: &ProgressCallback,
) -> Result<Box<BuiltHierarchy>, String> {
    guarded(|| {
        let mut input = mesh_of(positions, triangles)?;
        input.uvs = corner_uvs_of(corner_uvs, input.face_count())?;
        let options = simplify_options(options, input.vertex_count())?;
        let inner = watched(progress, || build(&input, &options))?;
        Ok(Box::new(BuiltHierarchy { input, inner }))
    })
}

impl BuiltHierarchy {
    pub fn level_count(&self) -> usize {
        self.inner.steps() + 1
    }

    pub fn level(&self, l: usize) -> Result<LevelArrays, String> {
        guarded(|| {
            let count = self.level_count();
            if l >= count {
                return Err(Error::InvalidInput(format!(
                    "level {l} is outside the hierarchy's {count} levels (0..{})",
                    count - 1
                )));
            }
            // Recorded levels run from the input (first) to the base domain (last); level 0
            // is listed in the base triangles' order, which parametrization indices count in.
            let level = match l {
                0 => self.inner.base_mesh(),
                _ => self.inner.levels[count - 1 - l].clone(),
            };
            Ok(level_arrays(&self.inner.with_attributes(level)?))
        })
    }

    pub fn parametrization(&self) -> Result<Parametrization, String> {
        guarded(|| {
            let points = self.inner.indexed_parametrization()?;
            let mut out = Parametrization {
                level: Vec::with_capacity(points.len()),
                base_face: Vec::with_capacity(points.len()),
                barycentric: Vec::with_capacity(3 * points.len()),
            };
            for point in points {
                let (face, bary, level) =
                    point.map_or((-1, [f64::NAN; 3], 0), |p| (p.face as i64, p.barycentric, p.level));
                out.level.push(level);
                out.base_face.push(face);
                out.barycentric.extend(bary);
            }
            Ok(out)
        })
    }

    pub fn report(&self) -> Report {
        Report {
            input_vertices: self.input.vertex_count(),
            output_vertices: self.inner.base_vertex_count(),
            levels: self.inner.steps(),
            seconds: self.inner.seconds,
        }
    }

    /// The build's report as `simplify --json` prints it ([`asperity::hierarchy::BuildReport`]).
    pub fn report_json(&self) -> Result<String, String> {
        guarded(|| {
            let report = asperity::hierarchy::BuildReport::of(&self.input, &self.inner, &self.inner.base_mesh().mesh)?;
            Ok(serde_json::to_string(&report).expect("a report serialises"))
        })
    }

    pub fn stages_json(&self) -> String {
        serde_json::to_string(&self.inner.stages).expect("stages serialise")
    }

    pub fn refine_region(
        &self,
        inside: &[u8],
        base_level: usize,
        progress: &ProgressCallback,
    ) -> Result<RegionOutcome, String> {
        guarded(|| {
            let start = std::time::Instant::now();
            let mask = mask_of(inside, self.input.vertex_count())?;
            let mut region = watched(progress, || refine_region(&self.inner, base_level, &|v| mask[v as usize]))?;
            // A face whose wedge is not found (a seam vertex placed off its seam by
            // Algorithm 2's search) leaves the UVs out: the C++ result then has no
            // texcoords, as `hierarchy.hpp` documents.
            let _ = self.inner.attach_attributes(&mut region.mesh, &[]);
            let report = Report {
                input_vertices: self.input.vertex_count(),
                output_vertices: region.mesh.ids.len(),
                levels: region.reports.len(),
                seconds: start.elapsed().as_secs_f64(),
            };
            Ok(RegionOutcome { level: level_arrays(&region.mesh), missing: region.missing, report })
        })
    }
}

/// A refinement in progress and the current level's view (made when first asked for,
/// dropped when the level's positions change or the next level is refined).
pub struct Refinement<'a> {
    hierarchy: &'a BuiltHierarchy,
    refiner: Refiner<'a>,
    appear: Vec<u32>,
    view: Option<LevelView>,
}

/// Starts refining `hierarchy`.
///
/// # Safety
/// Nothing unsafe happens here: the bridge marks the function unsafe because C++ receives
/// a refinement that borrows `hierarchy`, which C++ must keep alive.
pub unsafe fn start_refinement(hierarchy: &BuiltHierarchy) -> Result<Box<Refinement<'_>>, String> {
    guarded(|| {
        let mut refiner = Refiner::new(&hierarchy.inner)?;
        refiner.set_follow_deformation(true);
        let appear = hierarchy.inner.appearance_levels();
        Ok(Box::new(Refinement { hierarchy, refiner, appear, view: None }))
    })
}

impl Refinement<'_> {
    pub fn current_level(&self) -> usize {
        self.refiner.level()
    }

    pub fn finished(&self) -> bool {
        self.refiner.is_finished()
    }

    /// The current level's view, made once.
    fn current_view(&mut self) -> Result<&LevelView> {
        if self.view.is_none() {
            let level = self.refiner.level();
            let depth = self.hierarchy.inner.steps() - level;
            self.view = Some(LevelView::new(level, depth, self.refiner.mesh()?).with_appearance(&self.appear));
        }
        Ok(self.view.as_ref().expect("made above"))
    }

    pub fn view(&mut self) -> Result<ViewArrays, String> {
        guarded(|| {
            let view = self.current_view()?;
            let level = LevelArrays {
                mesh: crate::arrays::arrays_of(&view.mesh),
                ids: view.ids.clone(),
                corner_uvs: Vec::new(),
            };
            Ok(ViewArrays { level, normals: flat(&view.normals), vertex_levels: view.appear.clone() })
        })
    }

    pub fn view_analysis(&mut self) -> Result<Analysis, String> {
        guarded(|| Ok(analysis_arrays(self.current_view()?.analysis()?)))
    }

    pub fn set_positions(&mut self, positions: &[f64]) -> Result<(), String> {
        guarded(|| {
            let ids = self.current_view()?.ids.clone();
            if positions.len() != 3 * ids.len() {
                return Err(Error::InvalidInput(format!(
                    "level {}: {} coordinates for {} vertices",
                    self.refiner.level(),
                    positions.len(),
                    ids.len()
                )));
            }
            let moved = vectors_of(positions);
            if let Some(k) = moved.iter().position(|p| !p.is_finite()) {
                return Err(Error::InvalidInput(format!("level {}: position {k} is not finite", self.refiner.level())));
            }
            let view = self.view.as_ref().expect("made above");
            if view.mesh.positions == moved {
                return Ok(());
            }
            let all = self.refiner.positions_mut();
            for (&id, p) in ids.iter().zip(moved) {
                all[id as usize] = p;
            }
            self.view = None;
            Ok(())
        })
    }

    pub fn refine_next(&mut self, inside: &[u8]) -> Result<(), String> {
        guarded(|| {
            if self.refiner.is_finished() {
                return Err(Error::InvalidInput("the refinement has reached the input's level".into()));
            }
            if inside.is_empty() {
                self.refiner.refine_level(&|_| true)?;
            } else {
                let mask = mask_of(inside, self.hierarchy.input.vertex_count())?;
                self.refiner.refine_level(&|v| mask[v as usize])?;
            }
            self.view = None;
            Ok(())
        })
    }

    pub fn result(&self) -> Result<LevelArrays, String> {
        guarded(|| {
            let mut level = self.refiner.mesh()?;
            // As in `refine_region`: UVs left out where a wedge is not found.
            let _ = self.hierarchy.inner.attach_attributes(&mut level, &[]);
            Ok(level_arrays(&level))
        })
    }
}
