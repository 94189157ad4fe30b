//! `asperity simplify IN (--target-vertices V | --levels L | --max-error E) -o BASE`: the 4-k
//! hierarchy's base domain, optionally every level and the parametrization; with
//! `simplify plan`, `--plan DIR --chunk-index K` and `simplify merge`, a partitioned build
//! whose chunks job runners run (`cli::simplify_plan`).

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::{Args, Subcommand};
use glam::DVec3;
use serde_json::json;

use crate::error::Result;
use crate::hierarchy::{BuildReport, Hierarchy, HierarchyRequest, LevelMesh, build};
use crate::io::glb::{GlbPart, write_glb_parts};
use crate::io::{self, WriteOptions};
use crate::request::Spelling;

/// The subcommand's flags (`SimplifyArgs`).
#[derive(Debug, Args)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct SimplifyArgs {
    #[command(subcommand)]
    command: Option<SimplifyCommand>,
    /// Input mesh.
    #[arg(required_unless_present = "plan")]
    input: Option<PathBuf>,
    /// Base domain output (format by extension).
    #[arg(short, long, required_unless_present = "plan")]
    output: Option<PathBuf>,
    #[command(flatten)]
    hierarchy: HierarchyRequest,
    /// Write every level as DIR/level_NN.ply (00 = base domain).
    #[arg(long)]
    levels_out: Option<PathBuf>,
    /// Write every level into one glTF binary (.glb), one node per level side by side,
    /// base domain first, node extras naming the level.
    #[arg(long)]
    lod_out: Option<PathBuf>,
    /// Write the input mesh as PLY with each vertex's base face, barycentric coordinates
    /// and level as vertex properties.
    #[arg(long)]
    param_out: Option<PathBuf>,
    /// Allow an output to overwrite the input.
    #[arg(long)]
    force: bool,
    #[command(flatten)]
    repair: super::input::RepairArg,
    /// Build one chunk of the plan in DIR (made by `asperity simplify plan`): the chunk
    /// given by --chunk-index, else $JOB_COMPLETION_INDEX (Kubernetes Indexed Jobs), else
    /// $SLURM_ARRAY_TASK_ID (Slurm job arrays). A chunk already complete is skipped.
    #[arg(
        long,
        value_name = "DIR",
        conflicts_with_all = [
            "input", "output", "target_vertices", "levels", "max_error", "keep_features", "feature_vertices",
            "removal_weight", "swap_weight", "intersection_guard", "levels_out", "lod_out", "param_out", "chunks",
            "force", "repair"
        ]
    )]
    plan: Option<PathBuf>,
    /// The plan's chunk to build, 0-based (with --plan; wins over the job runners'
    /// variables).
    #[arg(long, requires = "plan")]
    chunk_index: Option<u64>,
}

#[derive(Debug, Subcommand)]
enum SimplifyCommand {
    /// Cut a mesh into chunks for a job runner: writes DIR/plan.json (every chunk's index,
    /// files and command) and DIR/chunks/ (each chunk's part); build each chunk with
    /// `asperity simplify --plan DIR --chunk-index K`, then join them with `asperity
    /// simplify merge DIR -o BASE`.
    Plan(Box<super::simplify_plan::PlanArgs>),
    /// Join the built chunks of the plan in DIR and continue the build to the plan's
    /// target: writes what `simplify` writes (base domain, --param-out).
    Merge(super::simplify_plan::MergeArgs),
}

/// Runs the subcommand.
pub fn run(args: SimplifyArgs, ctx: super::Context) -> Result<()> {
    match args.command {
        Some(SimplifyCommand::Plan(plan)) => return super::simplify_plan::plan(*plan, ctx),
        Some(SimplifyCommand::Merge(merge)) => return super::simplify_plan::merge(merge, ctx),
        None => {}
    }
    if let Some(dir) = &args.plan {
        return super::simplify_plan::run_chunk(dir, args.chunk_index, ctx);
    }
    // Clap's `requires` does not hold beside the subcommands' settings: checked here.
    if args.chunk_index.is_some() {
        return Err(crate::Error::InvalidInput(
            "--chunk-index belongs to --plan DIR (building one chunk of a plan): give --plan, or drop --chunk-index"
                .into(),
        ));
    }
    let start = Instant::now();
    let (Some(input_path), Some(output)) = (args.input.as_deref(), args.output.as_deref()) else {
        return Err(crate::Error::InvalidInput("simplify needs an input mesh and -o".into()));
    };
    let written = Written { input: input_path, output, param_out: args.param_out.as_deref(), repair: json!(null) };
    written.check(args.lod_out.as_deref(), args.levels_out.as_deref(), args.force)?;
    let input = super::input::read_input(input_path, args.repair, ctx)?;
    let mesh = &input.read.mesh;
    let record = args.levels_out.is_some() || args.lod_out.is_some();
    let options = args.hierarchy.options(mesh.vertex_count(), record, Spelling::Flag)?;
    let hierarchy = ctx
        .spin("simplify", "building the 4-k hierarchy", || build(mesh, &options))
        .map_err(|e| super::input::after_repair(e, args.repair).about_file(input_path))?;
    let written = Written { repair: input.repair_json(), ..written };
    let faces = InputFaces { positions: &mesh.positions, triangles: &mesh.triangles };
    write_results(faces, &hierarchy, &written, start, ctx, || {
        if let Some(dir) = &args.levels_out {
            write_levels(&hierarchy, input_path, dir)?;
        }
        if let Some(p) = &args.lod_out {
            write_lods(&hierarchy, p)?;
        }
        Ok(())
    })
}

/// Where a build's results go and what its report says of its input.
pub(super) struct Written<'a> {
    pub input: &'a Path,
    pub output: &'a Path,
    pub param_out: Option<&'a Path>,
    pub repair: serde_json::Value,
}

impl Written<'_> {
    /// Checks the outputs before anything is read: formats known by extension, no path
    /// given twice, none overwriting the input unless `force`.
    pub(super) fn check(&self, lod_out: Option<&Path>, levels_out: Option<&Path>, force: bool) -> Result<()> {
        io::Format::from_path(self.output)?;
        super::guard_overwrite(self.input, self.output, force)?;
        let mut outputs = vec![("-o", self.output)];
        outputs.extend(self.param_out.map(|p| ("--param-out", p)));
        outputs.extend(lod_out.map(|p| ("--lod-out", p)));
        outputs.extend(levels_out.map(|p| ("--levels-out", p)));
        super::distinct_outputs(&outputs)?;
        // Before the build, not at the end: a file cannot replace a folder, nor a folder a
        // file.
        for &(_, path) in outputs.iter().filter(|(flag, _)| *flag != "--levels-out") {
            io::refuse_folder(path)?;
        }
        if let Some(dir) = levels_out.filter(|d| d.exists() && !d.is_dir()) {
            return Err(crate::Error::InvalidInput(format!("--levels-out {}: is a file, not a folder", dir.display())));
        }
        if let Some(p) = self.param_out {
            super::guard_overwrite(self.input, p, force)?;
            // Only PLY holds the parametrization's vertex properties.
            super::require_extension(p, &["ply"])?;
        }
        if let Some(p) = lod_out {
            super::require_extension(p, &["glb"])?;
            super::guard_overwrite(self.input, p, force)?;
        }
        Ok(())
    }
}

/// The input a build was made from, as its report and parametrization read it.
#[derive(Clone, Copy)]
pub(super) struct InputFaces<'a> {
    pub positions: &'a [DVec3],
    pub triangles: &'a [[u32; 3]],
}

/// Writes the base domain, then what `more` writes (levels), the parametrization when
/// asked, and the report.
pub(super) fn write_results(
    input: InputFaces<'_>,
    hierarchy: &Hierarchy,
    written: &Written<'_>,
    start: Instant,
    ctx: super::Context,
    more: impl FnOnce() -> Result<()>,
) -> Result<()> {
    let mut base = hierarchy.with_attributes(hierarchy.base_mesh())?.mesh;
    crate::io::obj::relocate_material_libraries(&mut base, written.input, written.output);
    io::write(&base, written.output, WriteOptions::default())?;
    more()?;
    if let Some(p) = written.param_out {
        write_parametrization(input, hierarchy, p)?;
    }
    let report = BuildReport::of_faces(input.positions, input.triangles, hierarchy, &base)?;
    if ctx.json {
        let mut json = serde_json::to_value(&report).expect("report serialises");
        let fields = json.as_object_mut().expect("a struct serialises to an object");
        fields.insert("input".into(), json!(written.input.display().to_string()));
        fields.insert("output".into(), json!(written.output.display().to_string()));
        fields.insert("repair".into(), written.repair.clone());
        fields.insert("total_seconds".into(), json!(start.elapsed().as_secs_f64()));
        println!("{}", serde_json::to_string_pretty(&json).expect("report serialises"));
    } else if !ctx.quiet {
        println!("simplify: {} in {} ms", report.line(), super::millis(start));
        for line in report.target_lines() {
            println!("{line}");
        }
    }
    Ok(())
}

/// Every level as DIR/level_NN.ply, or in the input's format when it carries UVs or
/// materials (an OBJ's levels keep its `vt` and `usemtl`). A folder holding level files
/// this build does not write (another hierarchy's levels, which would pass for this
/// one's) is refused, naming one.
pub(super) fn write_levels(hierarchy: &Hierarchy, input: &Path, dir: &Path) -> Result<()> {
    let steps = hierarchy.steps();
    let extension = match (&hierarchy.wedges, input.extension().and_then(|e| e.to_str())) {
        (Some(_), Some(ext)) if ["obj", "ply", "glb"].contains(&ext.to_ascii_lowercase().as_str()) => {
            ext.to_ascii_lowercase()
        }
        _ => "ply".to_string(),
    };
    let name = |k: usize| format!("level_{:02}.{extension}", steps - k);
    let written: std::collections::HashSet<String> = (0..hierarchy.levels.len()).map(name).collect();
    let is_level = |n: &str| {
        n.strip_prefix("level_")
            .and_then(|rest| rest.split_once('.'))
            .is_some_and(|(number, _)| !number.is_empty() && number.bytes().all(|b| b.is_ascii_digit()))
    };
    if let Ok(entries) = std::fs::read_dir(dir) {
        let names = entries.filter_map(|e| e.ok()).map(|e| e.file_name().to_string_lossy().into_owned());
        if let Some(stale) = names.filter(|n| is_level(n) && !written.contains(n)).min() {
            return Err(crate::Error::InvalidInput(format!(
                "--levels-out {}: holds {stale}, which this build does not write (its levels are level_00 to \
                 level_{steps:02}): give an empty folder",
                dir.display()
            )));
        }
    }
    crate::io::create_output_dir(dir)?;
    for (k, level) in hierarchy.levels.iter().enumerate() {
        let path = dir.join(name(k));
        let mut mesh = hierarchy.with_attributes(level.clone())?.mesh;
        crate::io::obj::relocate_material_libraries(&mut mesh, input, &path);
        io::write(&mesh, &path, WriteOptions::default())?;
    }
    Ok(())
}

/// Every level as a node of one `.glb`, base domain (level 0) first, with `TEXCOORD_0`
/// when the input has UVs.
pub(super) fn write_lods(hierarchy: &Hierarchy, path: &Path) -> Result<()> {
    let steps = hierarchy.steps();
    let levels: Vec<LevelMesh> =
        hierarchy.levels.iter().map(|l| hierarchy.with_attributes(l.clone())).collect::<Result<_>>()?;
    let parts: Vec<GlbPart> = levels
        .iter()
        .enumerate()
        .rev()
        .map(|(k, level)| GlbPart {
            mesh: &level.mesh,
            name: format!("level {:02}", steps - k),
            extras: json!({
                "level": steps - k,
                "vertices": level.mesh.vertex_count(),
                "faces": level.mesh.face_count(),
            }),
        })
        .collect();
    write_glb_parts(&parts, path)
}

/// The parametrization's vertex properties, in the order a PLY writer of a mesh's
/// scalars writes them (by name).
const PARAMETRIZATION_PROPERTIES: [&str; 7] = ["bary0", "bary1", "bary2", "base_v0", "base_v1", "base_v2", "level"];

/// Writes the input mesh as binary PLY carrying the parametrization as vertex properties:
/// `level`, `base_v0..2` (base face, input vertex ids) and `bary0..2`; −1 for
/// unparametrized vertices. Written vertex by vertex, so neither the input nor the
/// properties are copied whole (#40: a merge's peak).
fn write_parametrization(input: InputFaces<'_>, hierarchy: &Hierarchy, path: &Path) -> Result<()> {
    use crate::io::ply::{PlyLayout, write_header, write_triangle, write_vertex};
    let points = hierarchy.base_points();
    let layout = PlyLayout {
        vertices: input.positions.len(),
        faces: input.triangles.len(),
        normals: false,
        colors: false,
        scalars: PARAMETRIZATION_PROPERTIES.map(String::from).to_vec(),
        ascii: false,
    };
    io::write_atomically(path, |w| {
        write_header(w, &layout)?;
        for (v, p) in input.positions.iter().enumerate() {
            let properties = points.get(v).map_or([-1.0; 7], |b| {
                let [b0, b1, b2] = b.point.bary;
                let [v0, v1, v2] = b.point.face.map(f64::from);
                [b0, b1, b2, v0, v1, v2, f64::from(b.level)]
            });
            write_vertex(w, false, *p, None, None, &properties)?;
        }
        input.triangles.iter().try_for_each(|&t| write_triangle(w, false, t))
    })
}

#[cfg(test)]
mod tests {
    use clap::Args as _;

    /// `--plan DIR` takes every setting from the plan: each other simplify flag is refused
    /// beside it (so one added to `simplify` must be added to --plan's conflicts).
    #[test]
    fn every_other_simplify_flag_conflicts_with_plan() {
        let mut command = super::SimplifyArgs::augment_args(clap::Command::new("simplify"));
        command.build();
        let plan = command.get_arguments().find(|a| a.get_id() == "plan").expect("--plan").clone();
        let conflicts: Vec<String> =
            command.get_arg_conflicts_with(&plan).iter().map(|a| a.get_id().to_string()).collect();
        for arg in command.get_arguments().filter(|a| !["plan", "chunk_index", "help"].contains(&a.get_id().as_str())) {
            assert!(conflicts.contains(&arg.get_id().to_string()), "--{} does not conflict with --plan", arg.get_id());
        }
    }
}
