//! `asperity simplify IN (--target-vertices V | --levels L | --max-error E) -o BASE`: the 4-k
//! hierarchy's base domain, optionally every level and the parametrization.

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;
use serde_json::json;

use crate::error::Result;
use crate::hierarchy::partition::build_partitioned;
use crate::hierarchy::{BuildReport, Hierarchy, HierarchyRequest, LevelMesh, build};
use crate::io::glb::{GlbPart, write_glb_parts};
use crate::io::{self, WriteOptions};
use crate::mesh::Mesh;
use crate::request::Spelling;

/// The subcommand's flags (`SimplifyArgs`).
#[derive(Debug, Args)]
pub struct SimplifyArgs {
    /// Input mesh.
    input: PathBuf,
    /// Base domain output (format by extension).
    #[arg(short, long)]
    output: PathBuf,
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
    /// Build in K parts along the Morton curve of the faces, in parallel, their borders
    /// fenced, then continue on their joined bases to the target (#40; needs
    /// --target-vertices; levels are not recorded, so not with --levels-out or --lod-out).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    chunks: Option<u32>,
    /// Allow an output to overwrite the input.
    #[arg(long)]
    force: bool,
    #[command(flatten)]
    repair: super::input::RepairArg,
}

/// Runs the subcommand.
pub fn run(args: SimplifyArgs, ctx: super::Context) -> Result<()> {
    let start = Instant::now();
    io::Format::from_path(&args.output)?;
    super::guard_overwrite(&args.input, &args.output, args.force)?;
    let mut outputs = vec![("-o", args.output.as_path())];
    outputs.extend(args.param_out.as_deref().map(|p| ("--param-out", p)));
    outputs.extend(args.lod_out.as_deref().map(|p| ("--lod-out", p)));
    outputs.extend(args.levels_out.as_deref().map(|p| ("--levels-out", p)));
    super::distinct_outputs(&outputs)?;
    if let Some(p) = &args.param_out {
        io::Format::from_path(p)?;
        super::guard_overwrite(&args.input, p, args.force)?;
    }
    if let Some(p) = &args.lod_out {
        super::require_extension(p, &["glb"])?;
        super::guard_overwrite(&args.input, p, args.force)?;
    }
    if args.chunks.is_some() {
        check_chunks(&args)?;
    }
    let input = super::input::read_input(&args.input, args.repair, ctx)?;
    let mesh = &input.read.mesh;
    let record = args.levels_out.is_some() || args.lod_out.is_some();
    let options = args.hierarchy.options(mesh.vertex_count(), record, Spelling::Flag)?;
    let hierarchy = ctx
        .spin("simplify", "building the 4-k hierarchy", || match args.chunks {
            Some(parts) => build_partitioned(mesh, parts as usize, &options),
            None => build(mesh, &options),
        })
        .map_err(|e| super::input::after_repair(e, args.repair).about_file(&args.input))?;
    let mut base = hierarchy.with_attributes(hierarchy.base_mesh())?.mesh;
    crate::io::obj::relocate_material_libraries(&mut base, &args.input, &args.output);
    io::write(&base, &args.output, WriteOptions::default())?;
    if let Some(dir) = &args.levels_out {
        write_levels(&hierarchy, &args.input, dir)?;
    }
    if let Some(p) = &args.lod_out {
        write_lods(&hierarchy, p)?;
    }
    if let Some(p) = &args.param_out {
        io::write(&parametrization_mesh(mesh, &hierarchy), p, WriteOptions::default())?;
    }
    let report = BuildReport::of(mesh, &hierarchy, &base)?;
    if ctx.json {
        let mut json = serde_json::to_value(&report).expect("report serialises");
        let fields = json.as_object_mut().expect("a struct serialises to an object");
        fields.insert("input".into(), json!(args.input.display().to_string()));
        fields.insert("output".into(), json!(args.output.display().to_string()));
        fields.insert("repair".into(), input.repair_json());
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

/// What `--chunks` does not take yet, refused by flag before the input is read.
fn check_chunks(args: &SimplifyArgs) -> Result<()> {
    let refuse = |msg: &str| Err(crate::Error::InvalidInput(msg.to_string()));
    if args.hierarchy.target_vertices.is_none() {
        return refuse("--chunks needs --target-vertices");
    }
    if args.hierarchy.levels.is_some() {
        return refuse("--chunks does not take --levels yet");
    }
    if args.levels_out.is_some() || args.lod_out.is_some() {
        return refuse("--chunks records no levels yet: drop --levels-out and --lod-out");
    }
    Ok(())
}

/// Every level as DIR/level_NN.ply, or in the input's format when it carries UVs or
/// materials (an OBJ's levels keep its `vt` and `usemtl`).
fn write_levels(hierarchy: &Hierarchy, input: &Path, dir: &Path) -> Result<()> {
    crate::io::create_output_dir(dir)?;
    let steps = hierarchy.steps();
    let extension = match (&hierarchy.wedges, input.extension().and_then(|e| e.to_str())) {
        (Some(_), Some(ext)) if ["obj", "ply", "glb"].contains(&ext.to_ascii_lowercase().as_str()) => {
            ext.to_ascii_lowercase()
        }
        _ => "ply".to_string(),
    };
    for (k, level) in hierarchy.levels.iter().enumerate() {
        let path = dir.join(format!("level_{:02}.{extension}", steps - k));
        let mut mesh = hierarchy.with_attributes(level.clone())?.mesh;
        crate::io::obj::relocate_material_libraries(&mut mesh, input, &path);
        io::write(&mesh, &path, WriteOptions::default())?;
    }
    Ok(())
}

/// Every level as a node of one `.glb`, base domain (level 0) first, with `TEXCOORD_0`
/// when the input has UVs.
fn write_lods(hierarchy: &Hierarchy, path: &Path) -> Result<()> {
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

/// The input mesh carrying the parametrization as vertex properties: `level`,
/// `base_v0..2` (base face, input vertex ids) and `bary0..2`; −1 for unparametrized vertices.
fn parametrization_mesh(mesh: &Mesh, hierarchy: &Hierarchy) -> Mesh {
    let points = hierarchy.base_parametrization();
    let mut out = Mesh::new(mesh.positions.clone(), mesh.triangles.clone());
    let column = |f: &dyn Fn(&crate::hierarchy::BasePoint) -> f64| -> Vec<f64> {
        points.iter().map(|p| p.as_ref().map_or(-1.0, f)).collect()
    };
    out.scalars.insert("level".into(), column(&|p| f64::from(p.level)));
    for i in 0..3 {
        out.scalars.insert(format!("base_v{i}"), column(&|p| f64::from(p.point.face[i])));
        out.scalars.insert(format!("bary{i}"), column(&|p| p.point.bary[i]));
    }
    out
}
