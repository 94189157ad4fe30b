//! STL, ASCII and binary. STL stores each facet's corners separately: bit-identical
//! corners are welded into shared vertices (−0.0 and 0.0 count as equal). Binary STL
//! stores single-precision floats, so writing rounds positions to `f32`.

use std::collections::HashMap;
use std::io::Write;
use std::path::Path;

use glam::DVec3;

use super::text::{coordinate, decode, shorten, significant_lines};
use super::{ReadOutcome, weld_key};
use crate::error::{Error, Location, Result};
use crate::mesh::Mesh;

const HEADER_BYTES: usize = 80;
const FACET_BYTES: usize = 50;

/// Parses an STL file, binary or ASCII.
pub fn parse(bytes: &[u8], path: &Path) -> Result<ReadOutcome> {
    let binary_count = (bytes.len() >= HEADER_BYTES + 4)
        .then(|| u32::from_le_bytes(bytes[80..84].try_into().expect("4 bytes")) as usize);
    let is_binary_size = binary_count.is_some_and(|n| Some(HEADER_BYTES + 4 + n * FACET_BYTES) == Some(bytes.len()));
    let looks_ascii = {
        let start = bytes.strip_prefix("\u{feff}".as_bytes()).unwrap_or(bytes);
        let trimmed = start.iter().position(|b| !b.is_ascii_whitespace()).map_or(&[][..], |i| &start[i..]);
        trimmed.starts_with(b"solid") && std::str::from_utf8(bytes).is_ok()
    };
    let mut welder = Welder::default();
    let mut triangles = Vec::new();
    let mut dropped = 0;
    let mut solids = 1;
    if is_binary_size {
        let n = binary_count.unwrap_or(0);
        triangles.reserve(n);
        for f in 0..n {
            let at = HEADER_BYTES + 4 + f * FACET_BYTES;
            let facet = bytes[at..at + FACET_BYTES].try_into().expect("a facet's bytes");
            read_facet(facet, f, path, &mut welder, &mut triangles, &mut dropped)?;
        }
    } else if looks_ascii {
        solids = parse_ascii(&decode(bytes, path)?, path, &mut welder, &mut triangles, &mut dropped)?;
    } else if let Some(n) = binary_count {
        return Err(Error::parse(
            path,
            Location::Byte(80),
            format!(
                "binary STL declares {n} facets ({} bytes) but the file has {} bytes",
                (HEADER_BYTES + 4).saturating_add(n.saturating_mul(FACET_BYTES)),
                bytes.len()
            ),
        ));
    } else {
        return Err(Error::parse(path, Location::File, "too short to be a binary STL and does not start with `solid`"));
    }
    Ok(outcome(welder, triangles, dropped, solids))
}

/// Reads a binary STL as its facets come (a plan's lean read: the file's bytes are never
/// held whole); `None` for a file that [`parse`] would not read as binary. The mesh, notes
/// and errors are [`parse`]'s.
///
/// # Errors
/// As [`parse`]; [`Error::Io`] if the file cannot be opened or read.
pub fn read_lean(path: &Path) -> Result<Option<ReadOutcome>> {
    use std::io::Read;
    let (file, size) = super::open_regular_file(path)?;
    let mut reader = std::io::BufReader::with_capacity(1 << 20, file);
    let mut head = [0u8; HEADER_BYTES + 4];
    if size < head.len() as u64 {
        return Ok(None);
    }
    reader.read_exact(&mut head).map_err(|e| Error::io(path, e))?;
    let n = u32::from_le_bytes(head[80..84].try_into().expect("4 bytes")) as usize;
    if (HEADER_BYTES + 4) as u64 + n as u64 * FACET_BYTES as u64 != size {
        return Ok(None);
    }
    let (mut welder, mut triangles, mut dropped) = (Welder::default(), Vec::with_capacity(n), 0);
    let mut facet = [0u8; FACET_BYTES];
    for f in 0..n {
        reader.read_exact(&mut facet).map_err(|e| Error::io(path, e))?;
        read_facet(&facet, f, path, &mut welder, &mut triangles, &mut dropped)?;
    }
    Ok(Some(outcome(welder, triangles, dropped, 1)))
}

/// Facet `f` of a binary STL: its corners welded, the facet kept or dropped.
fn read_facet(
    facet: &[u8; FACET_BYTES],
    f: usize,
    path: &Path,
    welder: &mut Welder,
    triangles: &mut Vec<[u32; 3]>,
    dropped: &mut usize,
) -> Result<()> {
    let mut corners = [0u32; 3];
    for (k, corner) in corners.iter_mut().enumerate() {
        let base = 12 + 12 * k;
        let c =
            |i: usize| f32::from_le_bytes(facet[base + 4 * i..base + 4 * i + 4].try_into().expect("4 bytes")) as f64;
        let p = DVec3::new(c(0), c(1), c(2));
        if !p.is_finite() {
            return Err(Error::parse(path, Location::Element("facet", f), "a corner coordinate is not finite"));
        }
        *corner = welder.vertex(p);
    }
    push_facet(corners, triangles, dropped);
    Ok(())
}

/// The mesh of the welded corners and kept facets, with the reader's notes.
fn outcome(welder: Welder, triangles: Vec<[u32; 3]>, dropped: usize, solids: usize) -> ReadOutcome {
    // Every position came from a corner read, those of dropped facets included.
    let corners = 3 * (triangles.len() + dropped);
    let welded = corners - welder.positions.len();
    let mut notes = if welded > 0 { vec![format!("STL: {welded} duplicate corners welded")] } else { Vec::new() };
    if solids > 1 {
        notes.push(format!("STL: {solids} solids read into one mesh"));
    }
    notes.extend(super::repeated_vertex_note(dropped));
    ReadOutcome { mesh: Mesh::new(welder.positions, triangles), triangulated_polygons: 0, notes }
}

/// Keeps a facet, or counts it in `dropped` when two of its corners welded to one point
/// (CAD exports make such facets; they have no area).
fn push_facet(corners: [u32; 3], triangles: &mut Vec<[u32; 3]>, dropped: &mut usize) {
    if crate::mesh::repeats_a_vertex(corners) {
        *dropped += 1;
    } else {
        triangles.push(corners);
    }
}

/// Parses the solids of an ASCII STL (CAD exports write one per part, one after the
/// other) into one mesh; returns how many there were.
fn parse_ascii<'t>(
    text: &'t str,
    path: &Path,
    welder: &mut Welder,
    triangles: &mut Vec<[u32; 3]>,
    dropped: &mut usize,
) -> Result<usize> {
    let err = |line: usize, msg: String| Error::parse(path, Location::Line(line), msg);
    let mut lines = significant_lines(text);
    let mut last = 1;
    // The next line, where the end of the file would be an error: `expect` names what must come.
    let mut next = |lines: &mut dyn Iterator<Item = (usize, Vec<&'t str>)>, expect: &str| {
        let (n, tokens) = lines.next().ok_or_else(|| err(last, format!("the file ends before `{expect}`")))?;
        last = n;
        Ok::<_, Error>((n, tokens))
    };
    let (n, first) = next(&mut lines, "solid")?;
    if first[0] != "solid" {
        return Err(err(n, "an ASCII STL must start with `solid`".into()));
    }
    let mut solids = 1;
    loop {
        let (n, tokens) = next(&mut lines, "facet")?;
        match tokens[0] {
            // After a solid, the file ends or another solid begins.
            "endsolid" => match lines.next() {
                None => return Ok(solids),
                Some((_, tokens)) if tokens[0] == "solid" => {
                    solids += 1;
                    continue;
                }
                Some((n, tokens)) => {
                    return Err(err(
                        n,
                        format!(
                            "expected `solid` or the end of the file after `endsolid`, found `{}`",
                            shorten(tokens[0])
                        ),
                    ));
                }
            },
            "facet" => {}
            other => return Err(err(n, format!("expected `facet` or `endsolid`, found `{}`", shorten(other)))),
        }
        let (n, tokens) = next(&mut lines, "outer loop")?;
        if tokens != ["outer", "loop"] {
            return Err(err(n, "expected `outer loop`".into()));
        }
        let mut corners = [0u32; 3];
        for corner in &mut corners {
            let (n, tokens) = next(&mut lines, "vertex")?;
            if tokens.len() != 4 || tokens[0] != "vertex" {
                return Err(err(n, "expected `vertex x y z`".into()));
            }
            let c = |k: usize| coordinate(tokens[k]).map_err(|m| err(n, m));
            *corner = welder.vertex(DVec3::new(c(1)?, c(2)?, c(3)?));
        }
        let (n, tokens) = next(&mut lines, "endloop")?;
        if tokens != ["endloop"] {
            return Err(err(n, "expected `endloop` (only triangles are allowed)".into()));
        }
        let (n, tokens) = next(&mut lines, "endfacet")?;
        if tokens != ["endfacet"] {
            return Err(err(n, "expected `endfacet`".into()));
        }
        push_facet(corners, triangles, dropped);
    }
}

/// Welds bit-identical positions into one vertex, in first-seen order.
#[derive(Default)]
struct Welder {
    index: HashMap<[u64; 3], u32>,
    positions: Vec<DVec3>,
}

impl Welder {
    fn vertex(&mut self, p: DVec3) -> u32 {
        *self.index.entry(weld_key(p)).or_insert_with(|| {
            self.positions.push(p);
            (self.positions.len() - 1) as u32
        })
    }
}

fn facet_normal(mesh: &Mesh, f: usize) -> DVec3 {
    let [a, b, c] = mesh.triangle_points(f);
    (b - a).cross(c - a).normalize_or_zero()
}

/// Writes an STL file: binary, or ASCII with `ascii`.
pub fn write(mesh: &Mesh, w: &mut dyn Write, ascii: bool) -> std::io::Result<()> {
    if ascii {
        writeln!(w, "solid asperity")?;
        for f in 0..mesh.triangles.len() {
            let n = facet_normal(mesh, f);
            writeln!(w, "facet normal {} {} {}", n.x, n.y, n.z)?;
            writeln!(w, "outer loop")?;
            for p in mesh.triangle_points(f) {
                writeln!(w, "vertex {} {} {}", p.x, p.y, p.z)?;
            }
            writeln!(w, "endloop")?;
            writeln!(w, "endfacet")?;
        }
        writeln!(w, "endsolid asperity")?;
        return Ok(());
    }
    let count = u32::try_from(mesh.triangles.len())
        .map_err(|_| std::io::Error::new(std::io::ErrorKind::InvalidInput, "too many triangles for binary STL"))?;
    let mut header = [b' '; HEADER_BYTES];
    let title = b"binary STL written by asperity";
    header[..title.len()].copy_from_slice(title);
    w.write_all(&header)?;
    w.write_all(&count.to_le_bytes())?;
    for f in 0..mesh.triangles.len() {
        let n = facet_normal(mesh, f);
        for v in std::iter::once(n).chain(mesh.triangle_points(f)) {
            for c in v.to_array() {
                w.write_all(&(c as f32).to_le_bytes())?;
            }
        }
        w.write_all(&[0, 0])?;
    }
    Ok(())
}
