//! OFF (Object File Format): `[ST][C][N]OFF`, counts, vertices, polygons. Vertex and face
//! colours and vertex normals are skipped with a note; polygons are triangulated.

use std::io::Write;
use std::path::Path;

use glam::DVec3;

use super::text::{coordinate, decode, significant_lines, unsigned};
use super::{ReadOutcome, check_polygon, repeated_vertex_note, without_repeated_corners};
use crate::error::{Error, Location, Result};
use crate::mesh::{Mesh, triangulate_polygon};

/// Smallest text a vertex ("0 0 0\n") and a face ("3 0 1 2\n") can take.
const MIN_VERTEX_BYTES: usize = 6;
const MIN_FACE_BYTES: usize = 8;

/// Parses an OFF file.
pub fn parse(bytes: &[u8], path: &Path) -> Result<ReadOutcome> {
    let text = decode(bytes, path)?;
    let err = |line: usize, msg: String| Error::parse(path, Location::Line(line), msg);
    let mut lines = significant_lines(&text);

    let (header_line, header) = lines.next().ok_or_else(|| Error::parse(path, Location::File, "no OFF header"))?;
    let keyword = header[0];
    let Some(prefix) = keyword.strip_suffix("OFF") else {
        return Err(err(header_line, format!("expected the OFF keyword, found `{}`", super::text::shorten(keyword))));
    };
    if !matches!(prefix, "" | "C" | "N" | "NC" | "CN" | "ST" | "STC" | "STN" | "STNC" | "STCN") {
        return Err(err(header_line, format!("unsupported OFF variant `{keyword}` (only 3D OFF is read)")));
    }
    if header.get(1) == Some(&"BINARY") {
        return Err(err(header_line, "binary OFF is not supported".into()));
    }
    let (count_line, counts) = if header.len() > 1 {
        (header_line, header[1..].to_vec())
    } else {
        lines.next().ok_or_else(|| err(header_line, "the file ends before the element counts".into()))?
    };
    if counts.len() < 2 {
        return Err(err(count_line, "expected vertex, face and edge counts".into()));
    }
    let nv = unsigned(counts[0], "vertex count").map_err(|m| err(count_line, m))?;
    let nf = unsigned(counts[1], "face count").map_err(|m| err(count_line, m))?;
    // Counts come from the file: reserve no more than the file could hold, so an absurd
    // count costs nothing and is reported where the data runs out.
    let vertex_capacity = nv.min(bytes.len() / MIN_VERTEX_BYTES);
    let face_capacity = nf.min(bytes.len() / MIN_FACE_BYTES);

    let mut notes = Vec::new();
    let mut last_line = count_line;
    let mut positions = Vec::with_capacity(vertex_capacity);
    let mut extra_vertex_values = false;
    for i in 0..nv {
        let (n, tokens) =
            lines.next().ok_or_else(|| err(last_line, format!("the file ends after {i} of {nv} vertices")))?;
        last_line = n;
        if tokens.len() < 3 {
            return Err(err(n, format!("vertex {i} needs 3 coordinates, found {}", tokens.len())));
        }
        let c = |k: usize| coordinate(tokens[k]).map_err(|m| err(n, format!("vertex {i}: {m}")));
        positions.push(DVec3::new(c(0)?, c(1)?, c(2)?));
        extra_vertex_values |= tokens.len() > 3;
    }
    if extra_vertex_values {
        notes.push("OFF vertex colours/normals ignored".to_string());
    }

    let mut triangles = Vec::with_capacity(face_capacity);
    let mut triangulated = 0;
    let mut dropped = 0;
    let mut face_colours = false;
    let mut polygon = Vec::new();
    for f in 0..nf {
        let (n, tokens) =
            lines.next().ok_or_else(|| err(last_line, format!("the file ends after {f} of {nf} faces")))?;
        last_line = n;
        let k = unsigned(tokens[0], "corner count").map_err(|m| err(n, format!("face {f}: {m}")))?;
        if tokens.len() < k + 1 {
            return Err(err(n, format!("face {f} declares {k} corners but lists {}", tokens.len() - 1)));
        }
        polygon.clear();
        for t in &tokens[1..=k] {
            let v = unsigned(t, "vertex index").map_err(|m| err(n, format!("face {f}: {m}")))?;
            polygon.push(u32::try_from(v).unwrap_or(u32::MAX));
        }
        check_polygon(&polygon, nv).map_err(|m| err(n, format!("face {f}: {m}")))?;
        face_colours |= tokens.len() > k + 1;
        if !without_repeated_corners(&mut polygon) {
            dropped += 1;
            continue;
        }
        if k > 3 {
            triangulated += 1;
        }
        triangulate_polygon(&positions, &polygon, &mut triangles);
    }
    if face_colours {
        notes.push("OFF face colours ignored".to_string());
    }
    notes.extend(repeated_vertex_note(dropped));
    Ok(ReadOutcome { mesh: Mesh::new(positions, triangles), triangulated_polygons: triangulated, notes })
}

/// Writes an OFF file (positions and triangles; attributes are not part of OFF).
pub fn write(mesh: &Mesh, w: &mut dyn Write) -> std::io::Result<()> {
    writeln!(w, "OFF")?;
    writeln!(w, "{} {} 0", mesh.positions.len(), mesh.triangles.len())?;
    for p in &mesh.positions {
        writeln!(w, "{} {} {}", p.x, p.y, p.z)?;
    }
    for t in &mesh.triangles {
        writeln!(w, "3 {} {} {}", t[0], t[1], t[2])?;
    }
    Ok(())
}
