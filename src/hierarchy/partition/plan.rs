//! A partitioned build that job runners run (#40): `asperity simplify plan` cuts the mesh
//! ([`MeshPlan::make`]: its parts' files and `plan.json`, every chunk's exact command), one
//! process per chunk builds its part ([`run_chunk`]: Kubernetes Indexed Jobs, Slurm job
//! arrays, GNU parallel), and `asperity simplify merge` joins them ([`join_plan`]). The
//! chunks' builds are the ones [`super::build_partitioned`] runs in threads, so the merged
//! hierarchy is byte for byte the in-process one.
//!
//! A chunk is complete when its build file exists and its sidecar names the plan's
//! fingerprint, the chunk and the file's size: a rerun skips it when the file also reads as
//! the merge reads it, and builds again a chunk whose file is missing, stale (another
//! plan), cut short or changed.

use std::borrow::Cow;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::files::{build_intact, read_build, read_part, write_build, write_part};
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

/// The fingerprint of what a plan's chunks are built from: the mesh, its counts (a chunk's
/// share of the target is read from them), the request and the cut.
fn plan_fingerprint(plan: &MeshPlan) -> Result<String> {
    let what = (&plan.mesh_fingerprint, plan.input_vertices, plan.input_faces, &plan.hierarchy, plan.chunks.len());
    let text = serde_json::to_string(&what).map_err(|e| Error::Internal(e.to_string()))?;
    Ok(fingerprint(&format!("asperity simplify plan v{MESH_PLAN_VERSION} {text}")))
}

/// The most chunks an error lists by index.
const LISTED_CHUNKS: usize = 10;

/// Peak bytes of a plan per input triangle, the mesh read included, rounded up from the
/// measured 40–45 (`simplify plan` at 3.3M and 53M triangles, #40).
pub const PLAN_BYTES_PER_TRIANGLE: u64 = 48;

/// Peak bytes of `simplify merge` per input triangle, the report included, rounded up from
/// the measured 97–107 (at 3.3M and 53M triangles, #40).
pub const MERGE_BYTES_PER_TRIANGLE: u64 = 120;

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
        crate::memory::ensure_available(
            (mesh.face_count() as u64).saturating_mul(PLAN_BYTES_PER_TRIANGLE),
            &format!("a plan of {} triangles", mesh.face_count()),
            "set a larger --max-memory where the machine has it",
        )?;
        let partition = Partition::of(mesh, chunks)?;
        crate::io::create_output_dir(&dir.join("chunks"))?;
        let mesh_fingerprint = mesh_fingerprint(mesh);
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
        let mut plan = MeshPlan {
            version: MESH_PLAN_VERSION,
            fingerprint: String::new(),
            input,
            repair,
            mesh_fingerprint,
            input_vertices: mesh.vertex_count(),
            input_faces: mesh.face_count(),
            hierarchy: request.clone(),
            chunks: planned,
        };
        plan.fingerprint = plan_fingerprint(&plan)?;
        let text = serde_json::to_string_pretty(&plan).map_err(|e| Error::Internal(e.to_string()))?;
        crate::io::write_atomically(&dir.join("plan.json"), |w| w.write_all(text.as_bytes()))?;
        Ok(plan)
    }

    /// The plan in `dir`, read from its manifest and checked as a whole: settings a build
    /// takes, as many chunks as they ask for, each at its own index under the plan's names
    /// for its files.
    ///
    /// # Errors
    /// No manifest, not a mesh plan, a plan of another layout version, or one whose fields
    /// disagree (named, with plan.json's path).
    pub fn read(dir: &Path) -> Result<MeshPlan> {
        let plan: MeshPlan = read_plan(dir, "simplify", MESH_PLAN_VERSION, |p: &MeshPlan| p.version)?;
        plan.validate(dir)?;
        Ok(plan)
    }

    /// Checks the plan as a whole, as [`MeshPlan::read`] does (for a plan made or read
    /// otherwise: its fields are public).
    ///
    /// # Errors
    /// [`Error::InvalidInput`] naming `dir`'s plan.json and the first field that disagrees.
    pub fn validate(&self, dir: &Path) -> Result<()> {
        let fault = |msg: String| {
            Error::InvalidInput(format!("{}: {msg}: make the plan again", dir.join("plan.json").display()))
        };
        if self.input_vertices == 0 || self.input_faces == 0 {
            return Err(fault("the input has no vertices or no faces".into()));
        }
        let options = self.options().map_err(|e| fault(format!("its settings are refused ({e})")))?;
        let count = self.chunks.len();
        if options.chunks != Some(count) {
            let asked = options.chunks.map_or("none".into(), |k| k.to_string());
            return Err(fault(format!("it lists {count} chunks where its settings ask for {asked}")));
        }
        for (k, chunk) in self.chunks.iter().enumerate() {
            let (part, build) = chunk_files(k);
            if chunk.index != k || chunk.part != part || chunk.build != build {
                return Err(fault(format!(
                    "its chunk {k} is not chunk {k} under the plan's names for its files ({part}, {build})"
                )));
            }
        }
        Ok(())
    }

    /// The build options every chunk and the merge use.
    ///
    /// # Errors
    /// As [`HierarchyRequest::options`].
    pub fn options(&self) -> Result<SimplifyOptions> {
        self.hierarchy.options(self.input_vertices, false, Spelling::Flag)
    }

    /// Chunk `index`, and the fingerprint its sidecar must name: recomputed from the plan,
    /// not read, so an edited manifest makes new chunks and never skips stale ones (its
    /// files are the plan's own names for them: [`MeshPlan::read`] checks them).
    ///
    /// # Errors
    /// An index outside the plan.
    pub fn chunk(&self, index: usize) -> Result<(&PlannedChunk, String)> {
        let count = self.chunks.len();
        let chunk = self.chunks.get(index).ok_or_else(|| {
            Error::InvalidInput(format!(
                "chunk index {index} is outside the plan's {count} chunks (0..{})",
                count.saturating_sub(1)
            ))
        })?;
        Ok((chunk, plan_fingerprint(self)?))
    }

    /// Refuses a merge of this plan that needs more memory than there is, by estimate
    /// ([`MERGE_BYTES_PER_TRIANGLE`]), before the input is read.
    ///
    /// # Errors
    /// As [`crate::memory::ensure_available`].
    pub fn check_merge_memory(&self) -> Result<()> {
        crate::memory::ensure_available(
            (self.input_faces as u64).saturating_mul(MERGE_BYTES_PER_TRIANGLE),
            &format!("merging a plan of {} triangles", self.input_faces),
            "merge on a machine with more memory, or set a larger --max-memory where this one has it",
        )
    }

    /// Checks that every chunk of the plan in `dir` is complete, before the merge reads
    /// anything large.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] naming the chunks that are not (the first
    /// ten) and the command that builds them, with `dir` as given.
    pub fn check_built(&self, dir: &Path) -> Result<()> {
        self.validate(dir)?;
        let fingerprint = plan_fingerprint(self)?;
        let missing: Vec<usize> = (0..self.chunks.len())
            .filter(|&k| !chunk_complete(&dir.join(&self.chunks[k].build), &fingerprint, k))
            .collect();
        if missing.is_empty() {
            return Ok(());
        }
        let mut listed: Vec<String> = missing.iter().take(LISTED_CHUNKS).map(|k| k.to_string()).collect();
        if missing.len() > LISTED_CHUNKS {
            listed.push("…".into());
        }
        Err(Error::InvalidInput(format!(
            "{}: {} of {} chunks are not built ({}): run `asperity simplify --plan {} --chunk-index K` for each first",
            dir.display(),
            missing.len(),
            self.chunks.len(),
            listed.join(", "),
            dir.display()
        )))
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
    let (chunk, fingerprint) = plan.chunk(index)?;
    let output = dir.join(&chunk.build);
    if chunk_complete(&output, &fingerprint, index) && build_intact(&output, plan.input_vertices) {
        return Ok((ChunkRun::Skipped, output));
    }
    let part = read_part(&dir.join(&chunk.part), plan.input_vertices)?;
    let built = build_part(&part, &plan.options()?, plan.input_vertices)
        .map_err(|e| with_plan_advice(e, plan.repair).about_file(&dir.join(&chunk.part)))?;
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

/// Whether the build of chunk `index` at `output` is complete for the plan `fingerprint`:
/// its sidecar names the plan, the chunk and the file's size in bytes (the bytes
/// themselves are checked against their hash where they are read).
pub fn chunk_complete(output: &Path, fingerprint: &str, index: usize) -> bool {
    let Ok(text) = std::fs::read_to_string(sidecar_path(output)) else { return false };
    let Ok(sidecar) = serde_json::from_str::<ChunkSidecar>(&text) else { return false };
    let size = std::fs::metadata(output).map(|m| m.len()).ok();
    sidecar.plan == fingerprint && sidecar.chunk == index && size == Some(sidecar.bytes)
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
    let counts = (mesh.vertex_count(), mesh.face_count());
    if counts != (plan.input_vertices, plan.input_faces) || mesh_fingerprint(mesh) != plan.mesh_fingerprint {
        return Err(Error::InvalidInput(format!(
            "{}: the input is not the mesh this plan cut ({} changed since `simplify plan`): make the plan again",
            dir.join("plan.json").display(),
            plan.input.display()
        )));
    }
    // (Its memory is checked before the input is read: `check_merge_memory`.)
    plan.check_built(dir)?;
    let mut builds: Vec<PartBuild> = Vec::with_capacity(plan.chunks.len());
    for chunk in &plan.chunks {
        builds.push(read_build(&dir.join(&chunk.build), plan.input_vertices)?);
    }
    let part_of = |k: usize| read_part(&dir.join(&plan.chunks[k].part), plan.input_vertices);
    super::join_parts(input, builds, part_of, &plan.options()?, started).map_err(|e| with_plan_advice(e, plan.repair))
}

/// An error about a plan's part or its joined builds, whose advice to run `--repair` is
/// replaced by the plan's (a chunk and the merge take no `--repair`: the plan does).
fn with_plan_advice(error: Error, repaired: bool) -> Error {
    error.with_repair_advice(match repaired {
        true => " (left after the plan's --repair)",
        false => "; make the plan again with --repair",
    })
}
