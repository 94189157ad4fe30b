//! The subcommands of seed 002's procedural environment: `flora`, `smoke`, `water`,
//! `butterflies`, `menger` and `scene`. Animated outputs are one `.glb` with an animation;
//! mesh formats get one file per frame (`NAME_000.ply`, …).

pub mod butterflies;
pub mod flora;
pub mod menger;
pub mod smoke;
pub mod water;
pub mod whole;

use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::io::glb_scene::{GlbScene, write_scene_glb};
use crate::io::{Format, WriteOptions};
use crate::mesh::Mesh;

/// Whether `output` is a `.glb`.
fn is_glb(output: &Path) -> Result<bool> {
    Ok(Format::from_path(output)? == Format::Glb)
}

/// Refuses `--fps` (or another animation flag) for outputs that are not `.glb`.
fn refuse_for_meshes(output: &Path, flag: &str, given: bool) -> Result<()> {
    if given && !is_glb(output)? {
        return Err(Error::InvalidInput(format!(
            "{flag} applies to animated .glb outputs; {} is written as one mesh file per frame",
            output.display()
        )));
    }
    Ok(())
}

/// The file of frame `k` of `count` for a mesh-format output: the output itself for one
/// frame, `STEM_KKK.EXT` beside it otherwise.
pub fn frame_path(output: &Path, k: usize, count: usize) -> PathBuf {
    if count == 1 {
        return output.to_path_buf();
    }
    let stem = output.file_stem().map_or("frame".into(), |s| s.to_string_lossy().into_owned());
    let ext = output.extension().map_or(String::new(), |e| format!(".{}", e.to_string_lossy()));
    output.with_file_name(format!("{stem}_{k:03}{ext}"))
}

/// Writes `frames`: one animated `.glb` (frames shown one at a time at `fps`, translucent
/// by `opacity` per vertex when given), or one mesh file per frame. Returns the files
/// written.
fn write_frames(
    frames: &[Mesh],
    name: &str,
    output: &Path,
    fps: f64,
    ascii: bool,
    opacity: Option<&Opacity<'_>>,
) -> Result<Vec<PathBuf>> {
    if is_glb(output)? {
        let mut doc = GlbScene::default();
        let meshes: Vec<Option<usize>> = frames
            .iter()
            .enumerate()
            .map(|(k, m)| Some(doc.add_mesh(m, format!("{name}_{k:03}"), opacity.map(|f| f(m)))))
            .collect();
        doc.add_frames(name, &meshes, fps, None);
        write_scene_glb(&doc, output)?;
        return Ok(vec![output.to_path_buf()]);
    }
    let mut written = Vec::with_capacity(frames.len());
    for (k, mesh) in frames.iter().enumerate() {
        let path = frame_path(output, k, frames.len());
        crate::io::write(mesh, &path, WriteOptions { ascii })?;
        written.push(path);
    }
    Ok(written)
}

/// Per-vertex opacity of a frame.
type Opacity<'a> = dyn Fn(&Mesh) -> Vec<f32> + 'a;

/// Refuses an empty frame (nothing a mesh file or glTF mesh can hold).
fn refuse_empty_frames(frames: &[Mesh], what: &str, hint: &str) -> Result<()> {
    match frames.iter().position(|m| m.triangles.is_empty()) {
        Some(k) => Err(Error::InvalidInput(format!("{what} frame {k} has no surface: {hint}"))),
        None => Ok(()),
    }
}

/// Frames per second of an animation: `--fps`, 12 by default; positive and finite.
fn checked_fps(fps: Option<f64>) -> Result<f64> {
    let fps = fps.unwrap_or(DEFAULT_FPS);
    if !(fps.is_finite() && fps > 0.0 && fps <= 1000.0) {
        return Err(Error::InvalidInput(format!("--fps {fps}: use a rate in (0, 1000]")));
    }
    Ok(fps)
}

/// Frames per second when `--fps` is not given.
pub const DEFAULT_FPS: f64 = 12.0;
