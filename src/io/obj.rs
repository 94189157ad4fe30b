//! Wavefront OBJ, read by our own small reader: `tobj` numbers vertices in order of first
//! use per `o`/`g` group and drops unreferenced `v` lines and faces with fewer than three
//! corners without a word, so a user's per-vertex data would no longer line up (#24). Here
//! every `v` line is a vertex, in file order; faces (`f`, any corner form `i`, `i/t`,
//! `i//n`, `i/t/n`, negative indices relative to the vertices so far) are triangulated;
//! errors name the line and quote the token. Texture coordinates are kept per corner
//! (`f v/vt`, see [`crate::mesh::uv`]) when every corner has one, and `mtllib`/`usemtl`
//! are kept per face and written back. Statements without geometry for a triangle mesh
//! (`o`, `g`, `s`, lines, points, free-form) are skipped with a note.

use std::borrow::Cow;
use std::collections::BTreeMap;
use std::io::Write;
use std::path::Path;

use glam::DVec3;

use super::text::{coordinate, decode, numbered_lines, shorten};
use super::{ReadOutcome, repeated_vertex_note, without_repeated_corners};
use crate::error::{Error, Location, Result};
use crate::mesh::uv::{CornerUvs, Materials};
use crate::mesh::{Mesh, triangulate_polygon};

/// Statements that describe no triangle-mesh geometry and are skipped without a note.
const SILENT: [&str; 5] = ["o", "g", "s", "vp", "shadow_obj"];

/// Parses an OBJ file (material libraries are named, not read).
pub fn parse(bytes: &[u8], path: &Path) -> Result<ReadOutcome> {
    let text = decode(bytes, path)?;
    // Positive indices may refer forward, to any element of the file.
    let mut totals = [0usize; 3];
    for (_, line) in logical_lines(&text) {
        if let Some(k) = ["v", "vt", "vn"].iter().position(|&h| line.split_whitespace().next() == Some(h)) {
            totals[k] += 1;
        }
    }
    let mut reader = Reader { totals, normals_consistent: true, current_material: u32::MAX, ..Reader::default() };
    for (line, content) in logical_lines(&text) {
        let content = content.split('#').next().unwrap_or("");
        reader.statement(content).map_err(|msg| Error::parse(path, Location::Line(line), msg))?;
    }
    Ok(reader.finish())
}

/// Lines with `\`-continuations joined, numbered by their first physical line.
fn logical_lines(text: &str) -> impl Iterator<Item = (usize, Cow<'_, str>)> {
    let mut lines = numbered_lines(text);
    std::iter::from_fn(move || {
        let (number, first) = lines.next()?;
        if !first.trim_end().ends_with('\\') {
            return Some((number, Cow::Borrowed(first)));
        }
        let mut joined = String::from(first.trim_end().trim_end_matches('\\'));
        for (_, next) in lines.by_ref() {
            let more = next.trim_end().ends_with('\\');
            joined.push(' ');
            joined.push_str(next.trim_end().trim_end_matches('\\'));
            if !more {
                break;
            }
        }
        Some((number, Cow::Owned(joined)))
    })
}

/// What the reader has gathered so far.
#[derive(Default)]
struct Reader {
    /// How many `v`, `vt` and `vn` lines the file has.
    totals: [usize; 3],
    positions: Vec<DVec3>,
    colors: Vec<[u8; 3]>,
    uncoloured: usize,
    weights: usize,
    normals: Vec<DVec3>,
    texcoords: Vec<[f64; 2]>,
    /// `vt` lines with a third coordinate other than 0.
    texcoords_3d: usize,
    /// Each corner's texture coordinate index (`u32::MAX`: none given).
    corner_texcoords: Vec<u32>,
    libraries: Vec<String>,
    materials: Vec<String>,
    /// The material of the faces that follow (`u32::MAX`: none yet).
    current_material: u32,
    /// Each face's material.
    face_materials: Vec<u32>,
    corner_normals: BTreeMap<u32, DVec3>,
    normals_consistent: bool,
    normals_seen: bool,
    corners_without_normal: bool,
    /// Faces' corners, one after another (triangulated at the end: corners may refer to
    /// vertices further down the file).
    corners: Vec<u32>,
    face_ends: Vec<usize>,
    /// Each normal index read, with the vertex it was given for (checked at the end, when
    /// every normal is known).
    corner_normal_indices: Vec<(u32, u32)>,
    skipped: BTreeMap<String, usize>,
}

impl Reader {
    fn statement(&mut self, content: &str) -> std::result::Result<(), String> {
        let mut tokens = content.split_whitespace();
        let Some(head) = tokens.next() else { return Ok(()) };
        let values: Vec<&str> = tokens.collect();
        match head {
            "v" => self.vertex(&values),
            "vn" => {
                let n = three(&values, "vn")?;
                self.normals.push(n);
                Ok(())
            }
            "vt" => {
                if values.is_empty() || values.len() > 3 {
                    return Err(format!("a `vt` line has 1 to 3 coordinates, this one has {}", values.len()));
                }
                let mut uvw = [0.0; 3];
                for (slot, v) in uvw.iter_mut().zip(&values) {
                    *slot = coordinate(v)?;
                }
                self.texcoords_3d += usize::from(uvw[2] != 0.0);
                self.texcoords.push([uvw[0], uvw[1]]);
                Ok(())
            }
            "mtllib" => {
                // A library name may contain spaces: the rest of the line.
                let name = values.join(" ");
                if !name.is_empty() && !self.libraries.contains(&name) {
                    self.libraries.push(name);
                }
                Ok(())
            }
            "usemtl" => {
                let name = values.join(" ");
                let index = match self.materials.iter().position(|m| *m == name) {
                    Some(i) => i,
                    None => {
                        self.materials.push(name);
                        self.materials.len() - 1
                    }
                };
                self.current_material = index as u32;
                Ok(())
            }
            "f" => self.face(&values),
            _ if SILENT.contains(&head) => Ok(()),
            _ => {
                *self.skipped.entry(shorten(head)).or_default() += 1;
                Ok(())
            }
        }
    }

    /// `v x y z`, with an optional weight `w` or colour `r g b` (0 to 1).
    fn vertex(&mut self, values: &[&str]) -> std::result::Result<(), String> {
        let p = three(values, "v")?;
        match values.len() {
            3 => self.uncoloured += 1,
            4 => {
                coordinate(values[3])?;
                self.weights += 1;
                self.uncoloured += 1;
            }
            6 => {
                let mut rgb = [0u8; 3];
                for (slot, v) in rgb.iter_mut().zip(&values[3..6]) {
                    *slot = (coordinate(v)? * 255.0).round().clamp(0.0, 255.0) as u8;
                }
                self.colors.push(rgb);
            }
            n => {
                return Err(format!("a `v` line has x y z, then a weight or an r g b colour; this one has {n} values"));
            }
        }
        self.positions.push(p);
        Ok(())
    }

    /// `f` with at least three corners, each `v`, `v/t`, `v//n` or `v/t/n`.
    fn face(&mut self, corners: &[&str]) -> std::result::Result<(), String> {
        if corners.len() < 3 {
            return Err(format!("a face needs at least 3 vertices, this one has {}", corners.len()));
        }
        let [vertices, texcoords, normals] = self.totals;
        for corner in corners {
            let quoted = shorten(corner);
            let at = |m: String| format!("face corner `{quoted}`: {m}");
            let mut parts = corner.split('/');
            let v = index(parts.next().unwrap_or(""), self.positions.len(), vertices, "vertex").map_err(at)?;
            let t = match parts.next().filter(|t| !t.is_empty()) {
                Some(t) => index(t, self.texcoords.len(), texcoords, "texture coordinate").map_err(at)?,
                None => u32::MAX,
            };
            self.corner_texcoords.push(t);
            match parts.next().filter(|n| !n.is_empty()) {
                Some(n) => {
                    let n = index(n, self.normals.len(), normals, "normal").map_err(at)?;
                    self.corner_normal_indices.push((v, n));
                }
                None => self.corners_without_normal = true,
            }
            if parts.next().is_some() {
                return Err(format!("face corner `{quoted}` has more than three parts (v/t/n)"));
            }
            self.corners.push(v);
        }
        self.face_ends.push(self.corners.len());
        self.face_materials.push(self.current_material);
        Ok(())
    }

    fn finish(mut self) -> ReadOutcome {
        let mut notes = Vec::new();
        let n = self.positions.len();
        let (mut triangles, mut triangulated, mut dropped) = (Vec::new(), 0, 0);
        // Per triangle: its corners' texture coordinates and its face's material.
        let (mut triangle_texcoords, mut triangle_materials) = (Vec::new(), Vec::new());
        let mut start = 0;
        let mut polygon = Vec::new();
        for (face, &end) in self.face_ends.iter().enumerate() {
            polygon.clear();
            polygon.extend_from_slice(&self.corners[start..end]);
            let corners = start..end;
            start = end;
            if without_repeated_corners(&mut polygon) {
                triangulated += usize::from(polygon.len() > 3);
                let first = triangles.len();
                triangulate_polygon(&self.positions, &polygon, &mut triangles);
                // A vertex's texture coordinate is that of its first corner in the face
                // (looked up by a table in large faces: a search per triangle corner made
                // one face of 100k corners take seconds, #36).
                let first_corner: Option<rustc_hash::FxHashMap<u32, usize>> = (corners.len() > 32).then(|| {
                    let mut table = rustc_hash::FxHashMap::default();
                    for k in corners.clone() {
                        table.entry(self.corners[k]).or_insert(k);
                    }
                    table
                });
                let texcoord_of = |v: u32| {
                    let k = match &first_corner {
                        Some(table) => table[&v],
                        None => corners.clone().find(|&k| self.corners[k] == v).expect("a corner of the face"),
                    };
                    self.corner_texcoords[k]
                };
                for t in &triangles[first..] {
                    triangle_texcoords.push(t.map(texcoord_of));
                    triangle_materials.push(self.face_materials[face]);
                }
            } else {
                dropped += 1;
            }
        }
        for &(v, k) in &self.corner_normal_indices {
            let normal = self.normals[k as usize];
            self.normals_seen = true;
            if *self.corner_normals.entry(v).or_insert(normal) != normal {
                self.normals_consistent = false;
            }
        }
        let mut mesh = Mesh::new(self.positions, triangles);
        if self.uncoloured == 0 && n > 0 {
            mesh.colors = Some(self.colors);
        } else if !self.colors.is_empty() {
            notes.push(format!("OBJ colours on only {} of {n} vertices: ignored", self.colors.len()));
        }
        if self.weights > 0 {
            notes.push(format!("OBJ vertex weights (v x y z w) on {} vertices: ignored", self.weights));
        }
        let corners_with_uv = triangle_texcoords.iter().flatten().filter(|&&t| t != u32::MAX).count();
        if corners_with_uv == 3 * triangle_texcoords.len() && !triangle_texcoords.is_empty() {
            mesh.uvs = Some(CornerUvs { values: self.texcoords, corners: triangle_texcoords });
            if self.texcoords_3d > 0 {
                notes.push(format!(
                    "{} OBJ texture coordinates have a third coordinate: kept as u v",
                    self.texcoords_3d
                ));
            }
        } else if corners_with_uv > 0 {
            notes.push(format!(
                "OBJ texture coordinates on {corners_with_uv} of {} triangle corners: ignored (every corner needs one)",
                3 * triangle_texcoords.len()
            ));
        } else if !self.texcoords.is_empty() {
            notes.push(format!("{} OBJ texture coordinates no face uses: ignored", self.texcoords.len()));
        }
        if !self.materials.is_empty() || !self.libraries.is_empty() {
            mesh.materials =
                Some(Materials { libraries: self.libraries, names: self.materials, faces: triangle_materials });
        }
        if self.normals_seen {
            let every_vertex = self.corner_normals.len() == n && !self.corners_without_normal;
            if self.normals_consistent && every_vertex {
                mesh.normals = Some(self.corner_normals.into_values().collect());
            } else {
                notes.push("OBJ normals are per corner or partial, not per vertex: ignored".to_string());
            }
        }
        for (statement, count) in &self.skipped {
            notes.push(format!("{count} OBJ `{statement}` statement(s) skipped (no triangle geometry)"));
        }
        notes.extend(repeated_vertex_note(dropped));
        ReadOutcome { mesh, triangulated_polygons: triangulated, notes }
    }
}

/// Three finite coordinates from the start of `values`.
fn three(values: &[&str], what: &str) -> std::result::Result<DVec3, String> {
    if values.len() < 3 {
        return Err(format!("a `{what}` line needs 3 coordinates, this one has {}", values.len()));
    }
    Ok(DVec3::new(coordinate(values[0])?, coordinate(values[1])?, coordinate(values[2])?))
}

/// A 1-based OBJ index (negative: relative to the `so_far` elements before the statement;
/// positive: any of the file's `total`) as a 0-based one.
fn index(token: &str, so_far: usize, total: usize, what: &str) -> std::result::Result<u32, String> {
    let plural = match what {
        "vertex" => "vertices".to_string(),
        other => format!("{other}s"),
    };
    let i: i64 = token.parse().map_err(|_| format!("{what} index `{}` is not an integer", shorten(token)))?;
    let resolved = match i {
        0 => return Err(format!("{what} index 0 is invalid (OBJ counts from 1)")),
        i if i > 0 => (i as u64 - 1) as usize,
        i => match so_far.checked_sub(i.unsigned_abs() as usize) {
            Some(r) => r,
            None => return Err(format!("{what} index {i} reaches before the first {what} ({so_far} {plural} so far)")),
        },
    };
    let limit = if i > 0 { total } else { so_far };
    if resolved >= limit || resolved > u32::MAX as usize {
        let place = if i > 0 { "" } else { " so far" };
        return Err(format!("{what} index {i} is out of range (there are {limit} {plural}{place})"));
    }
    Ok(resolved as u32)
}

/// The header comment of OBJ files written by asperity.
pub fn write_header(w: &mut dyn Write) -> std::io::Result<()> {
    writeln!(w, "# written by asperity {}", env!("CARGO_PKG_VERSION"))
}

/// One `v` line, with the colour as `v x y z r g b` when given.
pub fn write_vertex(w: &mut dyn Write, p: DVec3, color: Option<[u8; 3]>) -> std::io::Result<()> {
    match color {
        Some(c) => {
            let [r, g, b] = c.map(|v| f64::from(v) / 255.0);
            writeln!(w, "v {} {} {} {r} {g} {b}", p.x, p.y, p.z)
        }
        None => writeln!(w, "v {} {} {}", p.x, p.y, p.z),
    }
}

/// One `vn` line.
pub fn write_normal(w: &mut dyn Write, n: DVec3) -> std::io::Result<()> {
    writeln!(w, "vn {} {} {}", n.x, n.y, n.z)
}

/// One `f` line (1-based), referring to the normal of the same index when `with_normals`.
pub fn write_face(w: &mut dyn Write, t: [u32; 3], with_normals: bool) -> std::io::Result<()> {
    let [a, b, c] = t.map(|v| u64::from(v) + 1);
    if with_normals { writeln!(w, "f {a}//{a} {b}//{b} {c}//{c}") } else { writeln!(w, "f {a} {b} {c}") }
}

/// Writes an OBJ file: positions (with colours as `v x y z r g b` when present), normals,
/// texture coordinates per corner (`f v/vt`), the material libraries and each face's
/// `usemtl`, and 1-based triangles.
pub fn write(mesh: &Mesh, w: &mut dyn Write) -> std::io::Result<()> {
    write_header(w)?;
    if let Some(m) = &mesh.materials {
        for library in &m.libraries {
            writeln!(w, "mtllib {library}")?;
        }
    }
    for (i, p) in mesh.positions.iter().enumerate() {
        write_vertex(w, *p, mesh.colors.as_ref().map(|c| c[i]))?;
    }
    for n in mesh.normals.iter().flatten() {
        write_normal(w, *n)?;
    }
    if let Some(uvs) = &mesh.uvs {
        for [u, v] in &uvs.values {
            writeln!(w, "vt {u} {v}")?;
        }
    }
    // Faces with no material can only come before the first `usemtl`: where one follows a
    // material's face (a level's faces are in any order), they are written first.
    let unnamed = |f: usize| mesh.materials.as_ref().is_some_and(|m| m.faces[f] == u32::MAX);
    let mut order: Vec<usize> = (0..mesh.face_count()).collect();
    if order.windows(2).any(|w| !unnamed(w[0]) && unnamed(w[1])) {
        order.sort_by_key(|&f| !unnamed(f));
    }
    let mut material = u32::MAX;
    for f in order {
        let t = &mesh.triangles[f];
        if let Some(m) = &mesh.materials
            && m.faces[f] != material
            && m.faces[f] != u32::MAX
        {
            material = m.faces[f];
            writeln!(w, "usemtl {}", m.names[material as usize])?;
        }
        match &mesh.uvs {
            Some(uvs) => write_textured_face(w, *t, uvs.corners[f], mesh.normals.is_some())?,
            None => write_face(w, *t, mesh.normals.is_some())?,
        }
    }
    Ok(())
}

/// One `f v/vt` line (or `v/vt/vn` with normals of the vertices' indices), 1-based.
fn write_textured_face(w: &mut dyn Write, t: [u32; 3], uv: [u32; 3], with_normals: bool) -> std::io::Result<()> {
    write!(w, "f")?;
    for k in 0..3 {
        let (v, vt) = (u64::from(t[k]) + 1, u64::from(uv[k]) + 1);
        if with_normals { write!(w, " {v}/{vt}/{v}")? } else { write!(w, " {v}/{vt}")? }
    }
    writeln!(w)
}

/// `mesh` (read from `input`) about to be written to `output`: each material library it
/// names relative to the input's folder is named relative to the output's instead, or by
/// its absolute path where no relative path leads there, so that the written OBJ still
/// finds it. Names already absolute, and libraries that do not exist, are left as they are.
pub fn relocate_material_libraries(mesh: &mut crate::mesh::Mesh, input: &std::path::Path, output: &std::path::Path) {
    let Some(materials) = &mut mesh.materials else { return };
    let folder = |p: &std::path::Path| {
        let parent = p.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(std::path::Path::new("."));
        parent.canonicalize().ok()
    };
    let (Some(from), Some(to)) = (folder(input), folder(output)) else { return };
    if from == to {
        return;
    }
    for library in &mut materials.libraries {
        let path = std::path::Path::new(library.as_str());
        if path.is_absolute() {
            continue;
        }
        let Ok(found) = from.join(path).canonicalize() else { continue };
        *library = match found.strip_prefix(&to) {
            Ok(inside) => inside.display().to_string(),
            Err(_) => found.display().to_string(),
        };
    }
}
