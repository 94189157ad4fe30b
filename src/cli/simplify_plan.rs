//! `asperity simplify plan`, `asperity simplify --plan DIR` and `asperity simplify merge`:
//! a partitioned build whose chunks job runners run, one process per chunk
//! ([`crate::hierarchy::partition::plan`]: the manifest, the parts' files, completeness).
//! This file parses, finds the chunk index (the flag, or the job runner's variable) and
//! reports.

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;

use super::simplify::{InputFaces, Written, write_levels, write_lods, write_results};
use crate::error::Result;
use crate::hierarchy::HierarchyRequest;
use crate::hierarchy::partition::plan::{ChunkRun, MeshPlan, join_plan, run_chunk as build_chunk};

#[derive(Debug, Args)]
pub(crate) struct PlanArgs {
    /// Input mesh.
    input: PathBuf,
    #[command(flatten)]
    hierarchy: HierarchyRequest,
    /// The plan's folder: plan.json and chunks/.
    #[arg(short, long, value_name = "DIR")]
    output: PathBuf,
    #[command(flatten)]
    repair: super::input::RepairArg,
}

#[derive(Debug, Args)]
pub(crate) struct MergeArgs {
    /// The plan's folder (made by `asperity simplify plan`, its chunks built).
    plan: PathBuf,
    /// The plan's input mesh where it is now (on another machine, another mount)
    /// [default: the path the plan read it from]. It must be the mesh the plan cut.
    #[arg(long)]
    input: Option<PathBuf>,
    /// Base domain output (format by extension).
    #[arg(short, long)]
    output: PathBuf,
    /// Write the input mesh as PLY with each vertex's base face, barycentric coordinates
    /// and level as vertex properties.
    #[arg(long)]
    param_out: Option<PathBuf>,
    /// Write every level as DIR/level_NN.ply (00 = base domain), made by refining the
    /// merged hierarchy.
    #[arg(long)]
    levels_out: Option<PathBuf>,
    /// Write every level into one glTF binary (.glb), one node per level side by side,
    /// base domain first, node extras naming the level.
    #[arg(long)]
    lod_out: Option<PathBuf>,
    /// Allow an output to overwrite the input.
    #[arg(long)]
    force: bool,
}

/// `asperity simplify plan`: reads the input (binary PLY and STL as a stream, keeping only
/// what the parts need: [`crate::io::read_lean`]), checks the settings as the chunks will,
/// cuts it and writes the parts and the manifest.
pub(super) fn plan(args: PlanArgs, ctx: super::Context) -> Result<()> {
    let start = Instant::now();
    if args.hierarchy.chunks.is_none() {
        return Err(crate::Error::InvalidInput(
            "simplify plan needs --chunks K (the parts to cut the mesh into)".into(),
        ));
    }
    let (input, streamed) = super::input::read_for_build(&args.input, args.repair, ctx)?;
    let mesh = &input.read.mesh;
    let plan = MeshPlan::make(mesh, &args.input, args.repair.repair, &args.hierarchy, &args.output)
        .map_err(|e| super::input::after_repair(e, args.repair).about_file(&args.input))?;
    let dir = args.output.display();
    let count = plan.chunks.len();
    ctx.report(
        || {
            let faces: Vec<usize> = plan.chunks.iter().map(|c| c.faces).collect();
            let border: usize = plan.chunks.iter().map(|c| c.border).sum();
            format!(
                "simplify plan: {count} chunks of {}–{} faces ({border} border vertices) of {}{} => {dir}/plan.json in {} ms; build each with: asperity simplify --plan {dir} --chunk-index K (K = 0..{}), then: asperity simplify merge {dir} -o BASE",
                faces.iter().min().unwrap_or(&0),
                faces.iter().max().unwrap_or(&0),
                args.input.display(),
                if streamed { ", read as a stream" } else { "" },
                super::millis(start),
                count - 1,
            )
        },
        || {
            serde_json::json!({
                "plan": args.output.join("plan.json"), "chunks": count, "fingerprint": plan.fingerprint,
                "input": args.input, "streamed": streamed, "input_vertices": plan.input_vertices, "input_faces": plan.input_faces,
                "chunk_faces": plan.chunks.iter().map(|c| c.faces).collect::<Vec<_>>(),
                "chunk_border_vertices": plan.chunks.iter().map(|c| c.border).collect::<Vec<_>>(),
            })
        },
    );
    Ok(())
}

/// `asperity simplify --plan DIR`: builds one chunk of the plan, unless it is complete.
pub(super) fn run_chunk(dir: &Path, flag: Option<u64>, ctx: super::Context) -> Result<()> {
    let start = Instant::now();
    let index = super::job_index(flag, "chunk")?;
    let index = usize::try_from(index).map_err(|_| crate::Error::InvalidInput(format!("chunk index {index}")))?;
    let (run, output) = ctx.spin("simplify", "building a chunk", || build_chunk(dir, index))?;
    let skipped = run == ChunkRun::Skipped;
    ctx.report(
        || match skipped {
            true => format!("simplify: chunk {index} is already complete: {}", output.display()),
            false => format!("simplify: chunk {index} => {} in {} ms", output.display(), super::millis(start)),
        },
        || serde_json::json!({ "chunk": index, "output": output, "skipped": skipped }),
    );
    Ok(())
}

/// `asperity simplify merge`: reads the plan's input again, joins the built chunks,
/// continues the build to the target and writes what `simplify` writes.
pub(super) fn merge(args: MergeArgs, ctx: super::Context) -> Result<()> {
    let start = Instant::now();
    let plan = MeshPlan::read(&args.plan)?;
    // Before the input is read: a large input is not read for nothing.
    plan.check_built(&args.plan)?;
    plan.check_merge_memory()?;
    let input_path = args.input.clone().unwrap_or_else(|| plan.input.clone());
    let written = Written {
        input: &input_path,
        output: &args.output,
        param_out: args.param_out.as_deref(),
        repair: serde_json::Value::Null,
    };
    written.check(args.lod_out.as_deref(), args.levels_out.as_deref(), args.force)?;
    let repair = super::input::RepairArg { repair: plan.repair };
    let (input, _) = super::input::read_for_build(&input_path, repair, ctx)?;
    let written = Written { repair: input.repair_json(), ..written };
    // The input is given to the hierarchy, which keeps its positions and faces: the
    // report and the parametrization read them there.
    let mut hierarchy = ctx
        .spin("simplify", "joining the chunks", || {
            join_plan(&args.plan, &plan, std::borrow::Cow::Owned(input.read.mesh))
        })
        .map_err(|e| super::input::after_repair(e, repair).about_file(&input_path))?;
    if args.levels_out.is_some() || args.lod_out.is_some() {
        hierarchy.levels = ctx.spin("simplify", "making the levels", || hierarchy.levels_by_refinement())?;
    }
    let faces = InputFaces { positions: &hierarchy.positions, triangles: &hierarchy.input_triangles };
    write_results(faces, &hierarchy, &written, start, ctx, || {
        if let Some(dir) = &args.levels_out {
            write_levels(&hierarchy, &input_path, dir)?;
        }
        if let Some(p) = &args.lod_out {
            write_lods(&hierarchy, p)?;
        }
        Ok(())
    })
}
