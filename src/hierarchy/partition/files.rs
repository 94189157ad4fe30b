//! A part and a part's build as files, for builds whose parts run as separate processes
//! (`asperity simplify plan`, `--plan DIR --chunk-index K`, `merge`).
//!
//! Layout (little-endian): a 16-byte tag naming the kind and layout version, the arrays
//! each as a u64 count and its elements, then an FNV-1a 64 hash of every byte before it.
//! Positions are f64, so a part read back is the part written, bit for bit, and a build
//! in another process gives the bytes a thread gives. A file cut short, changed or of
//! another kind is refused by name and byte before anything is allocated from its counts.

use std::path::Path;

use glam::DVec3;

use super::{Part, PartBuild};
use crate::analysis::{FeatureClass, Quadric};
use crate::error::{Error, Location, Result};
use crate::hierarchy::{ParamPoint, Removal, VertexClass};
use crate::io::manifest::{FNV_OFFSET, fnv1a};
use crate::mesh::uv::{CornerUvs, Materials};
use crate::mesh::{Mesh, UnitFrame};

/// The tag of a part's mesh file (layout 4: the input's unit frame first; corner UVs and
/// face materials, empty arrays where the input has none, then the border quadrics).
const PART_TAG: &[u8; 16] = b"asperity-part-4\n";
/// The tag of a part's build file (layout 2: its base vertices' feature classes and
/// quadrics last).
const BUILD_TAG: &[u8; 16] = b"asperity-built2\n";

/// Writes `part` to `path` (atomically: a reader never sees half a file).
///
/// # Errors
/// [`Error::Io`] naming the file.
pub fn write_part(part: &Part, path: &Path) -> Result<()> {
    let mut out = Out::new(PART_TAG);
    part.input_frame.centre.to_array().into_iter().for_each(|c| out.f64(c));
    out.f64(part.input_frame.diagonal);
    out.array(&part.mesh.positions, |o, p| p.to_array().into_iter().for_each(|c| o.f64(c)));
    out.array(&part.mesh.triangles, |o, t| t.iter().for_each(|&v| o.u32(v)));
    out.array(&part.ids, |o, &v| o.u32(v));
    out.array(&part.border, |o, &v| o.u32(v));
    let uvs = part.mesh.uvs.as_ref();
    out.array(uvs.map_or(&[][..], |u| &u.values), |o, uv| uv.iter().for_each(|&c| o.f64(c)));
    out.array(uvs.map_or(&[][..], |u| &u.corners), |o, c| c.iter().for_each(|&i| o.u32(i)));
    out.array(part.mesh.materials.as_ref().map_or(&[][..], |m| &m.faces), |o, &i| o.u32(i));
    out.array(&part.border_quadrics, |o, q| q.0.iter().for_each(|&x| o.f64(x)));
    out.write(path).map(|_| ())
}

/// Reads a part written by [`write_part`], its input ids checked against the input's
/// `input_vertices`.
///
/// # Errors
/// [`Error::Io`] naming the file; [`Error::Parse`] naming the file and byte for another
/// kind of file, one cut short or changed, or an index out of range.
pub fn read_part(path: &Path, input_vertices: usize) -> Result<Part> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    let mut r = In::new(&bytes, path, PART_TAG)?;
    let centre = DVec3::new(r.f64()?, r.f64()?, r.f64()?);
    let diagonal = r.f64()?;
    if !(diagonal > 0.0 && diagonal.is_finite() && centre.is_finite()) {
        return Err(r.fault("the input's frame is not a finite centre and a positive diagonal"));
    }
    let positions = r.array(24, |r| Ok(DVec3::new(r.f64()?, r.f64()?, r.f64()?)))?;
    let n = positions.len();
    let triangles = r.array(12, |r| Ok([r.index(n)?, r.index(n)?, r.index(n)?]))?;
    let ids = r.array(4, |r| r.index(input_vertices))?;
    if ids.len() != n {
        return Err(r.fault(&format!("{} input ids for {n} vertices", ids.len())));
    }
    let border = r.array(4, |r| r.index(n))?;
    let faces = triangles.len();
    let values = r.array(16, |r| Ok([r.f64()?, r.f64()?]))?;
    let corners = r.array(12, |r| Ok([r.index(values.len())?, r.index(values.len())?, r.index(values.len())?]))?;
    if corners.len() != if values.is_empty() { 0 } else { faces } {
        return Err(r.fault(&format!("UVs for {} of {faces} faces ({} coordinates)", corners.len(), values.len())));
    }
    // A part numbers its materials in order of first use (`Partition::part`).
    let mut used = 0u32;
    let material = r.array(4, |r| {
        let at = r.at;
        let i = r.u32()?;
        match i {
            u32::MAX => {}
            i if i < used => {}
            i if i == used => used += 1,
            i => {
                r.at = at;
                return Err(r.fault(&format!("material {i} before material {used}")));
            }
        }
        Ok(i)
    })?;
    if !material.is_empty() && material.len() != faces {
        return Err(r.fault(&format!("materials for {} of {faces} faces", material.len())));
    }
    let border_quadrics = r.array(80, |r| r.quadric())?;
    if border_quadrics.len() != border.len() {
        return Err(r.fault(&format!(
            "{} border quadrics for {} border vertices",
            border_quadrics.len(),
            border.len()
        )));
    }
    r.end()?;
    let mut mesh = Mesh::new(positions, triangles);
    mesh.uvs = (!corners.is_empty()).then_some(CornerUvs { values, corners });
    mesh.materials = (!material.is_empty()).then(|| Materials {
        libraries: Vec::new(),
        names: (0..used).map(|i| i.to_string()).collect(),
        faces: material,
    });
    Ok(Part { mesh, ids, border, input_frame: UnitFrame { centre, diagonal }, border_quadrics })
}

/// Writes a part's build to `path` (atomically); returns the file's size in bytes.
///
/// # Errors
/// [`Error::Io`] naming the file.
pub fn write_build(build: &PartBuild, path: &Path) -> Result<u64> {
    let mut out = Out::new(BUILD_TAG);
    out.array(&build.base_triangles, |o, t| t.iter().for_each(|&v| o.u32(v)));
    out.array(&build.removals, |o, r| {
        [r.vertex, r.step, r.degree, u32::from(r.boundary)].into_iter().for_each(|v| o.u32(v));
        o.point(&r.local);
        r.diagonal.into_iter().chain(r.restore).for_each(|v| o.u32(v));
    });
    out.array(&build.restore, |o, e| e.iter().for_each(|&v| o.u32(v)));
    out.array(&build.step_starts, |o, &s| o.u64(s as u64));
    out.array(&build.seeds, |o, (v, p)| {
        o.u32(*v);
        o.point(p);
    });
    out.array(&build.classes, |o, (v, c)| {
        o.u32(*v);
        o.u32(c.class as u32);
        o.f64(c.strength);
        c.direction.to_array().into_iter().for_each(|x| o.f64(x));
    });
    out.array(&build.quadrics, |o, (v, q)| {
        o.u32(*v);
        q.0.iter().for_each(|&x| o.f64(x));
    });
    out.write(path)
}

/// Reads a part's build written by [`write_build`], every vertex id checked against the
/// input's `input_vertices` and every range against its arrays.
///
/// # Errors
/// As [`read_part`].
pub fn read_build(path: &Path, input_vertices: usize) -> Result<PartBuild> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    let mut r = In::new(&bytes, path, BUILD_TAG)?;
    let n = input_vertices;
    let base_triangles = r.array(12, |r| Ok([r.index(n)?, r.index(n)?, r.index(n)?]))?;
    let removals = r.array(4 * 4 + POINT_BYTES + 4 * 4, |r| {
        let [vertex, step, degree, boundary] = [r.index(n)?, r.u32()?, r.u32()?, r.index(2)?];
        let local = r.point(n)?;
        let diagonal = [r.index(n)?, r.index(n)?];
        let restore = [r.u32()?, r.u32()?];
        Ok(Removal { vertex, step, degree, boundary: boundary == 1, local, diagonal, restore })
    })?;
    let restore = r.array(8, |r| Ok([r.index(n)?, r.index(n)?]))?;
    if let Some(k) = removals.iter().position(|x| x.restore[0] > x.restore[1] || x.restore[1] as usize > restore.len())
    {
        return Err(r.fault(&format!("removal {k}'s link edges lie outside the {} recorded", restore.len())));
    }
    let step_starts = r.array(8, |r| r.offset(removals.len() + 1))?;
    if step_starts.first() != Some(&0)
        || step_starts.last() != Some(&removals.len())
        || step_starts.windows(2).any(|w| w[0] > w[1])
    {
        return Err(r.fault("the steps do not cover the removals in order"));
    }
    let seeds = r.array(4 + POINT_BYTES, |r| Ok((r.index(n)?, r.point(n)?)))?;
    let classes = r.array(8 + 32, |r| {
        let v = r.index(n)?;
        let class = match r.index(4)? {
            0 => FeatureClass::Face,
            1 => FeatureClass::Weak,
            2 => FeatureClass::StrongEdge,
            _ => FeatureClass::Corner,
        };
        let strength = r.f64()?;
        let direction = DVec3::new(r.f64()?, r.f64()?, r.f64()?);
        Ok((v, VertexClass { class, strength, direction }))
    })?;
    let quadrics = r.array(4 + 80, |r| Ok((r.index(n)?, r.quadric()?)))?;
    r.end()?;
    removed_once_each(&removals, &seeds).map_err(|msg| r.fault(&msg))?;
    Ok(PartBuild { base_triangles, removals, restore, step_starts, seeds, classes, quadrics })
}

/// Checks that a build's removals remove each vertex once and that its seeds are the
/// removed vertices' points, one each (a file whose hash matches but whose records do not
/// would otherwise reach the refinement).
fn removed_once_each(removals: &[Removal], seeds: &[(u32, ParamPoint)]) -> std::result::Result<(), String> {
    let mut removed: Vec<u32> = removals.iter().map(|r| r.vertex).collect();
    removed.sort_unstable();
    if let Some(w) = removed.windows(2).find(|w| w[0] == w[1]) {
        return Err(format!("its removals remove vertex {} twice", w[0]));
    }
    let mut seeded: Vec<u32> = seeds.iter().map(|&(v, _)| v).collect();
    seeded.sort_unstable();
    if seeded != removed {
        let odd = seeded.iter().zip(&removed).find(|(s, r)| s != r).map_or_else(
            || format!("{} seeds for {} removed vertices", seeded.len(), removed.len()),
            |(s, r)| match s < r {
                true => format!("vertex {s} has a seed but is not removed"),
                false => format!("vertex {r} is removed without a seed"),
            },
        );
        return Err(format!("its seeds are not its removed vertices' points ({odd})"));
    }
    Ok(())
}

/// Whether the file at `path` is a part's build that [`read_build`] takes (its bytes match
/// their hash, its records hold together): what a rerun of its chunk checks before
/// skipping it, so that a build the merge refuses is built again.
pub fn build_intact(path: &Path, input_vertices: usize) -> bool {
    read_build(path, input_vertices).is_ok()
}

/// A [`ParamPoint`]'s bytes: three u32 and three f64.
const POINT_BYTES: usize = 12 + 24;

/// A file being written.
struct Out {
    bytes: Vec<u8>,
}

impl Out {
    fn new(tag: &[u8; 16]) -> Self {
        Out { bytes: tag.to_vec() }
    }

    fn u32(&mut self, v: u32) {
        self.bytes.extend(v.to_le_bytes());
    }

    fn u64(&mut self, v: u64) {
        self.bytes.extend(v.to_le_bytes());
    }

    fn f64(&mut self, v: f64) {
        self.bytes.extend(v.to_le_bytes());
    }

    fn point(&mut self, p: &ParamPoint) {
        p.face.iter().for_each(|&v| self.u32(v));
        p.bary.iter().for_each(|&b| self.f64(b));
    }

    fn array<T>(&mut self, items: &[T], mut each: impl FnMut(&mut Self, &T)) {
        self.u64(items.len() as u64);
        for item in items {
            each(self, item);
        }
    }

    /// Writes the bytes and their hash; returns the file's size.
    fn write(mut self, path: &Path) -> Result<u64> {
        let hash = fnv1a(FNV_OFFSET, &self.bytes);
        self.u64(hash);
        crate::io::write_atomically(path, |w| w.write_all(&self.bytes))?;
        Ok(self.bytes.len() as u64)
    }
}

/// A file being read: its bytes up to the hash (checked first) and the read position.
struct In<'a> {
    bytes: &'a [u8],
    at: usize,
    path: &'a Path,
}

impl<'a> In<'a> {
    fn new(bytes: &'a [u8], path: &'a Path, tag: &[u8; 16]) -> Result<Self> {
        let fault = |at: usize, msg: &str| Error::parse(path, Location::Byte(at as u64), msg);
        if bytes.len() < 16 || &bytes[..16] != tag {
            let kind = if tag == PART_TAG { "a part of a partitioned build" } else { "a part's build" };
            return Err(fault(0, &format!("not {kind} (asperity simplify plan / --plan … --chunk-index)")));
        }
        let body = bytes.len().checked_sub(8).filter(|&b| b >= 16).ok_or_else(|| fault(16, "cut short"))?;
        let stored = u64::from_le_bytes(bytes[body..].try_into().expect("8 bytes"));
        if fnv1a(FNV_OFFSET, &bytes[..body]) != stored {
            let remedy = if tag == PART_TAG { "make the plan again" } else { "run its chunk again" };
            return Err(fault(body, &format!("its hash does not match its bytes (cut short or changed: {remedy})")));
        }
        Ok(In { bytes: &bytes[..body], at: 16, path })
    }

    fn fault(&self, msg: &str) -> Error {
        Error::parse(self.path, Location::Byte(self.at as u64), msg)
    }

    fn take<const N: usize>(&mut self) -> Result<[u8; N]> {
        let end = self.at + N;
        let bytes = self.bytes.get(self.at..end).ok_or_else(|| self.fault("cut short"))?;
        self.at = end;
        Ok(bytes.try_into().expect("N bytes"))
    }

    fn u32(&mut self) -> Result<u32> {
        self.take().map(u32::from_le_bytes)
    }

    fn u64(&mut self) -> Result<u64> {
        self.take().map(u64::from_le_bytes)
    }

    fn f64(&mut self) -> Result<f64> {
        let at = self.at;
        let v = self.take().map(f64::from_le_bytes)?;
        if !v.is_finite() {
            self.at = at;
            return Err(self.fault("a coordinate that is not a finite number"));
        }
        Ok(v)
    }

    /// A u32 index below `n`.
    fn index(&mut self, n: usize) -> Result<u32> {
        let at = self.at;
        let v = self.u32()?;
        self.below(u64::from(v), n, at)?;
        Ok(v)
    }

    /// A quadric's ten f64.
    fn quadric(&mut self) -> Result<Quadric> {
        let mut q = Quadric::default();
        for x in &mut q.0 {
            *x = self.f64()?;
        }
        Ok(q)
    }

    /// A u64 offset below `n`.
    fn offset(&mut self, n: usize) -> Result<usize> {
        let at = self.at;
        let v = self.u64()?;
        self.below(v, n, at)?;
        Ok(v as usize)
    }

    fn below(&mut self, v: u64, n: usize, at: usize) -> Result<()> {
        if v >= n as u64 {
            self.at = at;
            return Err(self.fault(&format!("index {v} out of range (below {n})")));
        }
        Ok(())
    }

    fn point(&mut self, n: usize) -> Result<ParamPoint> {
        Ok(ParamPoint {
            face: [self.index(n)?, self.index(n)?, self.index(n)?],
            bary: [self.f64()?, self.f64()?, self.f64()?],
        })
    }

    /// An array of elements of `size` bytes: its count is checked against the bytes left
    /// before anything is allocated.
    fn array<T>(&mut self, size: usize, mut each: impl FnMut(&mut Self) -> Result<T>) -> Result<Vec<T>> {
        let count = self.u64()?;
        let left = (self.bytes.len() - self.at) as u64;
        if count.checked_mul(size as u64).is_none_or(|b| b > left) {
            return Err(self.fault(&format!("{count} elements of {size} bytes, {left} bytes left")));
        }
        let mut items = Vec::with_capacity(count as usize);
        for _ in 0..count {
            items.push(each(self)?);
        }
        Ok(items)
    }

    fn end(&self) -> Result<()> {
        if self.at != self.bytes.len() {
            return Err(self.fault(&format!("{} bytes after the last array", self.bytes.len() - self.at)));
        }
        Ok(())
    }
}
