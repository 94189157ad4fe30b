//! Wavefront OBJ through `tobj`. `tobj` splits a file into one model per `o`/`g` group,
//! each indexing only the vertices it uses, in order of first use; groups are merged back
//! by welding bit-identical positions shared across groups. Errors from `tobj` carry no
//! line, so a small locator finds the offending line for the message.

use std::collections::HashMap;
use std::io::Write;
use std::path::Path;

use glam::DVec3;

use super::text::{decode, numbered_lines};
use super::{ReadOutcome, check_polygon, repeated_vertex_note, weld_key, without_repeated_corners};
use crate::error::{Error, Location, Result};
use crate::mesh::{Mesh, triangulate_polygon};

/// Parses an OBJ file (materials are not read).
pub fn parse(bytes: &[u8], path: &Path) -> Result<ReadOutcome> {
    let text = super::text::lone_cr_as_lf(decode(bytes, path)?);
    let text = text.as_ref();
    let options =
        tobj::LoadOptions { single_index: false, triangulate: false, ignore_points: true, ignore_lines: true };
    let mut reader = std::io::Cursor::new(text.as_bytes());
    let (models, _materials) = tobj::load_obj_buf(&mut reader, &options, |_| Err(tobj::LoadError::OpenFileFailed))
        .map_err(|e| Error::parse(path, locate(text, &e), format!("{e}")))?;

    let mut notes = Vec::new();
    if models.len() > 1 {
        notes.push(format!("OBJ: {} objects/groups merged, shared vertices welded", models.len()));
    }
    let mut positions: Vec<DVec3> = Vec::new();
    let mut colors: Vec<[u8; 3]> = Vec::new();
    let mut normals: Vec<Option<DVec3>> = Vec::new();
    let mut normals_consistent = true;
    let mut triangles = Vec::new();
    let mut triangulated = 0;
    let mut dropped = 0;
    let mut earlier: HashMap<[u64; 3], u32> = HashMap::new();
    let mut face_ordinal = 0;
    let all_have_colors = models.iter().all(|m| !m.mesh.vertex_color.is_empty());

    for model in &models {
        let m = &model.mesh;
        let base = positions.len();
        let mut local_to_global = Vec::with_capacity(m.positions.len() / 3);
        for (i, c) in m.positions.chunks_exact(3).enumerate() {
            let p = DVec3::new(c[0], c[1], c[2]);
            if !p.is_finite() {
                let at = first_nonfinite_vertex_line(text).map_or(Location::File, Location::Line);
                return Err(Error::parse(path, at, format!("vertex {}: a coordinate is not finite", base + i)));
            }
            let global = match earlier.get(&weld_key(p)) {
                Some(&g) => g,
                _ => {
                    positions.push(p);
                    if all_have_colors {
                        let k = 3 * i;
                        colors.push([0, 1, 2].map(|j| (m.vertex_color[k + j] * 255.0).round().clamp(0.0, 255.0) as u8));
                    }
                    normals.push(None);
                    (positions.len() - 1) as u32
                }
            };
            local_to_global.push(global);
        }
        // Later groups may weld onto this group's vertices (never within a group).
        for &global in &local_to_global {
            earlier.entry(weld_key(positions[global as usize])).or_insert(global);
        }
        let arities: Vec<u32> =
            if m.face_arities.is_empty() { vec![3; m.indices.len() / 3] } else { m.face_arities.clone() };
        let mut start = 0;
        let mut polygon = Vec::new();
        for arity in arities {
            let end = start + arity as usize;
            polygon.clear();
            polygon.extend(m.indices[start..end].iter().map(|&i| local_to_global[i as usize]));
            check_polygon(&polygon, positions.len()).map_err(|msg| {
                let line = nth_keyword_line(text, "f", face_ordinal).unwrap_or(0);
                Error::parse(path, Location::Line(line), format!("face {face_ordinal}: {msg}"))
            })?;
            let keep = without_repeated_corners(&mut polygon);
            dropped += usize::from(!keep);
            if !m.normal_indices.is_empty() && m.normal_indices.len() == m.indices.len() {
                for k in start..end {
                    let n = 3 * m.normal_indices[k] as usize;
                    let normal = DVec3::new(m.normals[n], m.normals[n + 1], m.normals[n + 2]);
                    let slot = &mut normals[local_to_global[m.indices[k] as usize] as usize];
                    match slot {
                        Some(existing) if *existing != normal => normals_consistent = false,
                        _ => *slot = Some(normal),
                    }
                }
            }
            if keep {
                triangulated += usize::from(arity > 3);
                triangulate_polygon(&positions, &polygon, &mut triangles);
            }
            face_ordinal += 1;
            start = end;
        }
    }
    let mut mesh = Mesh::new(positions, triangles);
    if all_have_colors && !models.is_empty() {
        mesh.colors = Some(colors);
    }
    if normals.iter().any(Option::is_some) {
        if normals_consistent && normals.iter().all(Option::is_some) {
            mesh.normals = Some(normals.into_iter().map(|n| n.unwrap_or(DVec3::ZERO)).collect());
        } else {
            notes.push("OBJ normals are per corner, not per vertex: ignored".to_string());
        }
    }
    notes.extend(repeated_vertex_note(dropped));
    Ok(ReadOutcome { mesh, triangulated_polygons: triangulated, notes })
}

/// Line of the `n`-th statement with `keyword`.
fn nth_keyword_line(text: &str, keyword: &str, n: usize) -> Option<usize> {
    numbered_lines(text).filter(|(_, l)| l.split_whitespace().next() == Some(keyword)).nth(n).map(|(line, _)| line)
}

fn first_nonfinite_vertex_line(text: &str) -> Option<usize> {
    numbered_lines(text).find_map(|(n, l)| {
        let mut t = l.split_whitespace();
        (t.next() == Some("v") && t.take(3).any(|x| x.parse::<f64>().is_ok_and(|v| !v.is_finite()))).then_some(n)
    })
}

/// Finds the line `tobj` most likely failed on, from the error's kind.
fn locate(text: &str, error: &tobj::LoadError) -> Location {
    use tobj::LoadError as E;
    let (keyword, min_values) = match error {
        E::PositionParseError => ("v", 3),
        E::NormalParseError => ("vn", 3),
        E::TexcoordParseError => ("vt", 1),
        E::FaceParseError
        | E::InvalidPolygon
        | E::FaceVertexOutOfBounds
        | E::FaceNormalOutOfBounds
        | E::FaceTexCoordOutOfBounds => ("f", 3),
        _ => return Location::File,
    };
    let mut vertices_seen: i64 = 0;
    for (n, line) in numbered_lines(text) {
        let mut tokens = line.split_whitespace();
        let head = tokens.next();
        if head == Some("v") {
            vertices_seen += 1;
        }
        if head != Some(keyword) {
            continue;
        }
        let values: Vec<&str> = tokens.collect();
        let bad = if keyword == "f" {
            values.len() < min_values
                || values.iter().any(|v| {
                    let first = v.split('/').next().unwrap_or("");
                    match first.parse::<i64>() {
                        Ok(i) if i > 0 => i > vertices_seen,
                        Ok(i) if i < 0 => -i > vertices_seen,
                        _ => true,
                    }
                })
        } else {
            values.len() < min_values || values.iter().take(min_values).any(|v| v.parse::<f64>().is_err())
        };
        if bad {
            return Location::Line(n);
        }
    }
    Location::File
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
/// and 1-based triangles.
pub fn write(mesh: &Mesh, w: &mut dyn Write) -> std::io::Result<()> {
    write_header(w)?;
    for (i, p) in mesh.positions.iter().enumerate() {
        write_vertex(w, *p, mesh.colors.as_ref().map(|c| c[i]))?;
    }
    for n in mesh.normals.iter().flatten() {
        write_normal(w, *n)?;
    }
    for t in &mesh.triangles {
        write_face(w, *t, mesh.normals.is_some())?;
    }
    Ok(())
}
