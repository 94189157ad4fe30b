//! A partitioned build that job runners run (#40): `asperity simplify plan` cuts the mesh
//! ([`MeshPlan::make`]: its parts' files and `plan.json`, every chunk's exact command), one
//! process per chunk builds its part ([`run_chunk`]: Kubernetes Indexed Jobs, Slurm job
//! arrays, GNU parallel), and `asperity simplify merge` joins them ([`join_plan`]). The
//! chunks' builds are the ones [`super::build_partitioned`] runs in threads, so the merged
//! hierarchy is byte for byte the in-process one.
//!
//! A chunk is complete when its build file exists and its sidecar names the plan's
//! fingerprint and the file's size: a rerun skips it, and builds again a chunk whose file
//! is missing, stale (another plan) or cut short.

use std::borrow::Cow;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::files::{read_build, read_part, write_build, write_part};
use super::{PartBuild, Partition, build::check_partitioned_settings, build_part};
use crate::error::{Error, Result};
use crate::hierarchy::{Hierarchy, HierarchyRequest, SimplifyOptions};
use crate::io::manifest::{FNV_OFFSET, fingerprint, fnv1a, read_plan};
use crate::mesh::Mesh;
use crate::request::Spelling;

/// The manifest's layout version.
pub const MESH_PLAN_VERSION: u32 = 1;

/// The manifest (`plan.json`): what every chunk's process and the merge need.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeshPlan {
    /// The manifest's layout version.
    pub version: u32,
    /// A hash of what the chunks are built from (the mesh, the request, the cut); the
    /// chunks' sidecars record it.
    pub fingerprint: String,
    /// The input file, as the plan read it.
    pub input: PathBuf,
    /// Whether the input was repaired after reading (the merge repairs it again).
    pub repair: bool,
    /// A hash of the mesh the plan cut (positions and faces, after any repair).
    pub mesh_fingerprint: String,
    /// The input's vertices.
    pub input_vertices: usize,
    /// The input's faces.
    pub input_faces: usize,
    /// The build's settings, as the plan was given them.
    pub hierarchy: HierarchyRequest,
    /// Every chunk, by index.
    pub chunks: Vec<PlannedChunk>,
}

/// One chunk of the plan.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlannedChunk {
    /// Its index: what --chunk-index, $JOB_COMPLETION_INDEX or $SLURM_ARRAY_TASK_ID names.
    pub index: usize,
    /// Its part's file, relative to the plan's folder.
    pub part: String,
    /// Its build's file, relative to the plan's folder.
    pub build: String,
    /// The part's faces.
    pub faces: usize,
    /// The part's vertices, and of them on its border.
    pub vertices: usize,
    /// The part's border vertices.
    pub border: usize,
    /// The command that builds it.
    pub command: Vec<String>,
}

/// The sidecar of a chunk's build: the plan it belongs to and the file's size.
#[derive(Debug, Serialize, Deserialize)]
struct ChunkSidecar {
    plan: String,
    chunk: usize,
    bytes: u64,
}

/// A hash of `mesh`'s positions (their bits) and faces.
pub fn mesh_fingerprint(mesh: &Mesh) -> String {
    let mut hash = FNV_OFFSET;
    for p in &mesh.positions {
        for c in p.to_array() {
            hash = fnv1a(hash, &c.to_le_bytes());
        }
    }
    for t in &mesh.triangles {
        for v in t {
            hash = fnv1a(hash, &v.to_le_bytes());
        }
    }
    format!("{hash:016x}")
}

/// The fingerprint of what a plan's chunks are built from.
fn plan_fingerprint(mesh: &str, request: &HierarchyRequest, chunks: usize) -> Result<String> {
    let text = serde_json::to_string(&(mesh, request, chunks)).map_err(|e| Error::Internal(e.to_string()))?;
    Ok(fingerprint(&format!("asperity simplify plan v{MESH_PLAN_VERSION} {text}")))
}

/// The plan's names for chunk `k`'s files.
fn chunk_files(k: usize) -> (String, String) {
    (format!("chunks/chunk-{k:04}.part"), format!("chunks/chunk-{k:04}.built"))
}

impl MeshPlan {
    /// Cuts `mesh` (read from `input`, repaired if `repair`) into the request's `chunks`
    /// parts ([`Partition::of`]) and writes each part and the manifest into `dir`: the
    /// settings are checked as the build will check them first, so a plan whose chunks
    /// would be refused is refused itself.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for a request without chunks; as
    /// [`super::build_partitioned`]'s checks and [`Partition::of`]; a file that cannot be
    /// written.
    pub fn make(mesh: &Mesh, input: &Path, repair: bool, request: &HierarchyRequest, dir: &Path) -> Result<MeshPlan> {
        let options = request.options(mesh.vertex_count(), false, Spelling::Flag)?;
        let chunks = options.chunks.ok_or_else(|| Error::InvalidInput("a plan needs chunks".into()))?;
        // The build's checks (`check_partitioned`) without a table of the whole mesh's
        // edges: `Partition::of` checks the mesh part by part.
        check_partitioned_settings(&options)?;
        if mesh.face_count() == 0 {
            return Err(Error::InvalidInput("the mesh has no faces to simplify".into()));
        }
        let partition = Partition::of(mesh, chunks)?;
        crate::io::create_output_dir(&dir.join("chunks"))?;
        let mesh_fingerprint = mesh_fingerprint(mesh);
        let fingerprint = plan_fingerprint(&mesh_fingerprint, request, chunks)?;
        let input = std::path::absolute(input).map_err(|e| Error::io(input, e))?;
        let mut planned = Vec::with_capacity(chunks);
        for k in 0..chunks {
            let part = partition.part(mesh, k)?;
            let (part_file, build) = chunk_files(k);
            write_part(&part, &dir.join(&part_file))?;
            let command = ["asperity", "simplify", "--plan", &dir.to_string_lossy(), "--chunk-index", &k.to_string()];
            planned.push(PlannedChunk {
                index: k,
                part: part_file,
                build,
                faces: part.mesh.face_count(),
                vertices: part.mesh.vertex_count(),
                border: part.border.len(),
                command: command.map(String::from).to_vec(),
            });
        }
        let plan = MeshPlan {
            version: MESH_PLAN_VERSION,
            fingerprint,
            input,
            repair,
            mesh_fingerprint,
            input_vertices: mesh.vertex_count(),
            input_faces: mesh.face_count(),
            hierarchy: request.clone(),
            chunks: planned,
        };
        let text = serde_json::to_string_pretty(&plan).map_err(|e| Error::Internal(e.to_string()))?;
        crate::io::write_atomically(&dir.join("plan.json"), |w| w.write_all(text.as_bytes()))?;
        Ok(plan)
    }

    /// The plan in `dir`, read from its manifest.
    ///
    /// # Errors
    /// No manifest, not a mesh plan, or a plan of another layout version.
    pub fn read(dir: &Path) -> Result<MeshPlan> {
        read_plan(dir, "simplify", MESH_PLAN_VERSION, |p: &MeshPlan| p.version)
    }

    /// The build options every chunk and the merge use.
    ///
    /// # Errors
    /// As [`HierarchyRequest::options`].
    pub fn options(&self) -> Result<SimplifyOptions> {
        self.hierarchy.options(self.input_vertices, false, Spelling::Flag)
    }

    /// Chunk `index`, and the fingerprint its sidecar must name: recomputed from the plan,
    /// not read, so an edited manifest makes new chunks and never skips stale ones; its
    /// files must be the plan's own names for them, so an edited manifest cannot send a
    /// chunk outside the plan's folder.
    ///
    /// # Errors
    /// An index outside the plan; files that are not the plan's names.
    pub fn chunk(&self, index: usize, dir: &Path) -> Result<(&PlannedChunk, String)> {
        let count = self.chunks.len();
        let chunk = self.chunks.get(index).filter(|c| c.index == index).ok_or_else(|| {
            Error::InvalidInput(format!(
                "chunk index {index} is outside the plan's {count} chunks (0..{})",
                count.saturating_sub(1)
            ))
        })?;
        let (part, build) = chunk_files(index);
        if chunk.part != part || chunk.build != build {
            return Err(Error::InvalidInput(format!(
                "{}: chunk {index}'s files are not the plan's names for them ({part}, {build}): make the plan again",
                dir.join("plan.json").display()
            )));
        }
        Ok((chunk, plan_fingerprint(&self.mesh_fingerprint, &self.hierarchy, count)?))
    }
}

/// What [`run_chunk`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ChunkRun {
    /// The chunk was built and written.
    Built,
    /// The chunk was complete already.
    Skipped,
}

/// Builds chunk `index` of the plan in `dir` (unless it is complete) and writes its build
/// and then its sidecar, each atomically.
///
/// # Errors
/// As [`MeshPlan::read`], [`MeshPlan::chunk`], [`read_part`] and [`build_part`]; a file that
/// cannot be written.
pub fn run_chunk(dir: &Path, index: usize) -> Result<(ChunkRun, PathBuf)> {
    let plan = MeshPlan::read(dir)?;
    let (chunk, fingerprint) = plan.chunk(index, dir)?;
    let output = dir.join(&chunk.build);
    if chunk_complete(&output, &fingerprint) {
        return Ok((ChunkRun::Skipped, output));
    }
    let part = read_part(&dir.join(&chunk.part), plan.input_vertices)?;
    let built =
        build_part(&part, &plan.options()?, plan.input_vertices).map_err(|e| e.about_file(&dir.join(&chunk.part)))?;
    let bytes = write_build(&built, &output)?;
    let sidecar = ChunkSidecar { plan: fingerprint, chunk: index, bytes };
    let text = serde_json::to_string_pretty(&sidecar).map_err(|e| Error::Internal(e.to_string()))?;
    crate::io::write_atomically(&sidecar_path(&output), |w| w.write_all(text.as_bytes()))?;
    Ok((ChunkRun::Built, output))
}

fn sidecar_path(output: &Path) -> PathBuf {
    let mut name = output.as_os_str().to_owned();
    name.push(".json");
    PathBuf::from(name)
}

/// Whether the chunk build at `output` is complete for the plan `fingerprint`: its sidecar
/// names the plan and the file's size in bytes.
pub fn chunk_complete(output: &Path, fingerprint: &str) -> bool {
    let Ok(text) = std::fs::read_to_string(sidecar_path(output)) else { return false };
    let Ok(sidecar) = serde_json::from_str::<ChunkSidecar>(&text) else { return false };
    let size = std::fs::metadata(output).map(|m| m.len()).ok();
    sidecar.plan == fingerprint && size == Some(sidecar.bytes)
}

/// Joins the chunks of `plan` (read from `dir`) over `input` (the plan's input, read
/// again): checks that it is the mesh the plan cut and that every chunk is complete,
/// then continues the build on the joined bases ([`super::join_parts`]). An input given
/// to keep (`Cow::Owned`) becomes the hierarchy's positions and faces, not a copy of them.
///
/// # Errors
/// [`Error::InvalidInput`] for another mesh than the plan's, or chunks not complete (named,
/// with the command that builds them); as [`read_build`] and [`super::join_parts`].
pub fn join_plan(dir: &Path, plan: &MeshPlan, input: Cow<'_, Mesh>) -> Result<Hierarchy> {
    let started = std::time::Instant::now();
    let mesh = input.as_ref();
    if mesh_fingerprint(mesh) != plan.mesh_fingerprint {
        return Err(Error::InvalidInput(format!(
            "{}: the input is not the mesh this plan cut ({} changed since `simplify plan`): make the plan again",
            dir.join("plan.json").display(),
            plan.input.display()
        )));
    }
    let mut builds: Vec<PartBuild> = Vec::with_capacity(plan.chunks.len());
    let mut missing = Vec::new();
    for index in 0..plan.chunks.len() {
        let (chunk, fingerprint) = plan.chunk(index, dir)?;
        let output = dir.join(&chunk.build);
        if !chunk_complete(&output, &fingerprint) {
            missing.push(index);
            continue;
        }
        builds.push(read_build(&output, plan.input_vertices)?);
    }
    if let Some(&first) = missing.first() {
        return Err(Error::InvalidInput(format!(
            "{} of {} chunks are not built ({}): run `{}` for each first",
            missing.len(),
            plan.chunks.len(),
            missing.iter().map(|k| k.to_string()).collect::<Vec<_>>().join(", "),
            plan.chunks[first].command.join(" ").replace(&format!("--chunk-index {first}"), "--chunk-index K")
        )));
    }
    let part_of = |k: usize| read_part(&dir.join(&plan.chunks[k].part), plan.input_vertices);
    super::join_parts(input, builds, part_of, &plan.options()?, started)
}
