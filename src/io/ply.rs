//! Stanford PLY: ASCII, binary little- and big-endian. Reads positions, normals
//! (`nx ny nz`), colours (`red green blue`, 8-bit or float), texture coordinates (`s t`,
//! `u v`, `texture_u texture_v` or `texture_s texture_t`) and every other scalar vertex
//! property (kept by name); faces from `vertex_indices` / `vertex_index`; other elements
//! are skipped. Writes binary little-endian by default, with all attributes (UVs as `s t`,
//! seam vertices split).

use std::collections::BTreeMap;
use std::io::Write;
use std::path::Path;

use glam::DVec3;

use super::text::{numbered_lines, shorten};
use super::{ReadOutcome, check_count_fits, check_polygon, repeated_vertex_note, without_repeated_corners};
use crate::error::{Error, Location, Result};
use crate::mesh::{Mesh, triangulate_polygon};

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Encoding {
    Ascii,
    LittleEndian,
    BigEndian,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum ScalarType {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl ScalarType {
    fn parse(name: &str) -> Option<Self> {
        Some(match name {
            "char" | "int8" => ScalarType::I8,
            "uchar" | "uint8" => ScalarType::U8,
            "short" | "int16" => ScalarType::I16,
            "ushort" | "uint16" => ScalarType::U16,
            "int" | "int32" => ScalarType::I32,
            "uint" | "uint32" => ScalarType::U32,
            "float" | "float32" => ScalarType::F32,
            "double" | "float64" => ScalarType::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            ScalarType::I8 | ScalarType::U8 => 1,
            ScalarType::I16 | ScalarType::U16 => 2,
            ScalarType::I32 | ScalarType::U32 | ScalarType::F32 => 4,
            ScalarType::F64 => 8,
        }
    }

    fn is_integer(self) -> bool {
        !matches!(self, ScalarType::F32 | ScalarType::F64)
    }
}

#[derive(Debug, Clone)]
enum Property {
    Scalar { name: String, ty: ScalarType },
    List { name: String, count: ScalarType, item: ScalarType },
}

impl Property {
    fn name(&self) -> &str {
        match self {
            Property::Scalar { name, .. } | Property::List { name, .. } => name,
        }
    }
}

#[derive(Debug, Clone)]
struct Element {
    name: String,
    count: usize,
    properties: Vec<Property>,
    line: usize,
}

impl Element {
    /// Smallest encoding of one element: every scalar and every list count (lists may be empty).
    fn min_bytes(&self, encoding: Encoding) -> usize {
        self.properties
            .iter()
            .map(|p| match (encoding, p) {
                (Encoding::Ascii, _) => 2,
                (_, Property::Scalar { ty, .. }) => ty.size(),
                (_, Property::List { count, .. }) => count.size(),
            })
            .sum()
    }
}

struct Header {
    encoding: Encoding,
    elements: Vec<Element>,
    /// Byte offset of the body.
    body: usize,
    /// Number of header lines (ASCII body lines are numbered after them).
    lines: usize,
}

/// Longest header we look for `end_header` in.
const MAX_HEADER_BYTES: usize = 1 << 20;

fn parse_header(bytes: &[u8], path: &Path) -> Result<Header> {
    let err = |line: usize, msg: String| Error::parse(path, Location::Line(line), msg);
    let window = &bytes[..bytes.len().min(MAX_HEADER_BYTES)];
    let end = find_subslice(window, b"end_header").ok_or_else(|| {
        let msg = if bytes.len() > MAX_HEADER_BYTES {
            format!(
                "no `end_header` in the first {} MiB: a PLY header longer than that is refused",
                MAX_HEADER_BYTES >> 20
            )
        } else {
            "no `end_header` line: not a PLY file or truncated header".to_string()
        };
        Error::parse(path, Location::File, msg)
    })?;
    let mut body = end + b"end_header".len();
    match (bytes.get(body), bytes.get(body + 1)) {
        (Some(b'\r'), Some(b'\n')) => body += 2,
        (Some(b'\n' | b'\r'), _) => body += 1,
        (None, _) => {}
        _ => return Err(Error::parse(path, Location::File, "`end_header` is not followed by a line break")),
    }
    let text = std::str::from_utf8(&bytes[..end])
        .map_err(|e| Error::parse(path, Location::Byte(e.valid_up_to() as u64), "the PLY header is not text"))?;
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);

    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    let mut line_count = 0;
    for (n, line) in numbered_lines(text) {
        line_count = n;
        let tokens: Vec<&str> = line.split_whitespace().collect();
        match tokens.as_slice() {
            [] => {}
            ["ply"] if n == 1 => {}
            _ if n == 1 => return Err(err(1, "not a PLY file (the first line is not `ply`)".into())),
            ["format", kind, version] => {
                if *version != "1.0" {
                    return Err(err(n, format!("unsupported PLY version `{}`", shorten(version))));
                }
                encoding = Some(match *kind {
                    "ascii" => Encoding::Ascii,
                    "binary_little_endian" => Encoding::LittleEndian,
                    "binary_big_endian" => Encoding::BigEndian,
                    other => return Err(err(n, format!("unknown PLY format `{}`", shorten(other)))),
                });
            }
            ["comment", ..] | ["obj_info", ..] => {}
            ["element", name, count] => {
                let count =
                    count.parse::<usize>().map_err(|_| err(n, format!("bad element count `{}`", shorten(count))))?;
                elements.push(Element { name: name.to_string(), count, properties: Vec::new(), line: n });
            }
            ["property", "list", count, item, name] => {
                let element = elements.last_mut().ok_or_else(|| err(n, "property before any element".into()))?;
                let count =
                    ScalarType::parse(count).ok_or_else(|| err(n, format!("unknown PLY type `{}`", shorten(count))))?;
                let item =
                    ScalarType::parse(item).ok_or_else(|| err(n, format!("unknown PLY type `{}`", shorten(item))))?;
                if !count.is_integer() {
                    return Err(err(n, "a list count must have an integer type".into()));
                }
                refuse_repeated_property(element, name).map_err(|m| err(n, m))?;
                element.properties.push(Property::List { name: name.to_string(), count, item });
            }
            ["property", ty, name] => {
                let element = elements.last_mut().ok_or_else(|| err(n, "property before any element".into()))?;
                let ty = ScalarType::parse(ty).ok_or_else(|| err(n, format!("unknown PLY type `{}`", shorten(ty))))?;
                refuse_repeated_property(element, name).map_err(|m| err(n, m))?;
                element.properties.push(Property::Scalar { name: name.to_string(), ty });
            }
            _ => return Err(err(n, format!("malformed header line `{}`", shorten(line)))),
        }
    }
    let encoding = encoding.ok_or_else(|| Error::parse(path, Location::File, "the PLY header has no `format` line"))?;
    Ok(Header { encoding, elements, body, lines: line_count + 1 })
}

/// A property named twice in one element would be read twice, the last value winning
/// silently (#36: `x` declared twice): refused.
fn refuse_repeated_property(element: &Element, name: &str) -> std::result::Result<(), String> {
    match element.properties.iter().any(|p| p.name() == name) {
        true => Err(format!("property `{}` is declared twice in element `{}`", shorten(name), shorten(&element.name))),
        false => Ok(()),
    }
}

fn find_subslice(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    haystack.windows(needle.len()).position(|w| w == needle)
}

/// Where values come from: ASCII lines, one element each, or binary with byte offsets.
enum Body<'a> {
    /// `lines` yields the body's numbered lines; `tokens` are what is left of `line`, the
    /// current element's (#36: values were read across lines, so a vertex missing a value
    /// took the next line's and the error surfaced lines later).
    Ascii { lines: Box<dyn Iterator<Item = (usize, &'a str)> + 'a>, tokens: std::str::SplitWhitespace<'a>, line: usize },
    Binary {
        src: Source<'a>,
        /// Bytes read of the body, and the body's length.
        pos: usize,
        len: usize,
        base: usize,
        big_endian: bool,
    },
}

/// Where a binary body's bytes come from: the file in memory, or the file read as the
/// elements are ([`read_lean`], a plan's read, which never holds the file's bytes).
enum Source<'a> {
    Slice(&'a [u8]),
    Stream(std::io::BufReader<std::fs::File>),
}

impl<'a> Body<'a> {
    fn location(&self) -> Location {
        match self {
            Body::Ascii { line, .. } => Location::Line(*line),
            Body::Binary { pos, base, .. } => Location::Byte((base + pos) as u64),
        }
    }

    /// Starts the next element: in ASCII, its line (blank lines are skipped).
    fn begin_element(&mut self) -> std::result::Result<(), String> {
        if let Body::Ascii { lines, tokens, line } = self {
            let (n, text) = lines.find(|(_, l)| !l.trim().is_empty()).ok_or("the file ends early")?;
            *line = n;
            *tokens = text.split_whitespace();
        }
        Ok(())
    }

    /// Ends an element: in ASCII, its line must hold nothing more.
    fn end_element(&mut self) -> std::result::Result<(), String> {
        match self {
            Body::Ascii { tokens, .. } => match tokens.next() {
                Some(extra) => Err(format!(
                    "`{}` is one value more than the element's properties declare (one element per line)",
                    shorten(extra)
                )),
                None => Ok(()),
            },
            Body::Binary { .. } => Ok(()),
        }
    }

    /// In ASCII, the first line after the last element that is not blank.
    fn trailing_line(&mut self) -> Option<usize> {
        match self {
            Body::Ascii { lines, .. } => lines.find(|(_, l)| !l.trim().is_empty()).map(|(n, _)| n),
            Body::Binary { .. } => None,
        }
    }

    fn read(&mut self, ty: ScalarType) -> std::result::Result<f64, String> {
        match self {
            Body::Ascii { tokens, .. } => {
                let token =
                    tokens.next().ok_or("the line ends before the element's last value (one element per line)")?;
                let value = if ty.is_integer() {
                    token
                        .parse::<i64>()
                        .map(|v| v as f64)
                        .map_err(|_| format!("`{}` is not an integer", shorten(token)))?
                } else {
                    token.parse::<f64>().map_err(|_| format!("`{}` is not a number", shorten(token)))?
                };
                let (lo, hi) = match ty {
                    ScalarType::I8 => (i8::MIN as f64, i8::MAX as f64),
                    ScalarType::U8 => (0.0, u8::MAX as f64),
                    ScalarType::I16 => (i16::MIN as f64, i16::MAX as f64),
                    ScalarType::U16 => (0.0, u16::MAX as f64),
                    ScalarType::I32 => (i32::MIN as f64, i32::MAX as f64),
                    ScalarType::U32 => (0.0, u32::MAX as f64),
                    ScalarType::F32 | ScalarType::F64 => (f64::NEG_INFINITY, f64::INFINITY),
                };
                if ty.is_integer() && !(lo..=hi).contains(&value) {
                    return Err(format!("{value} is out of range for its type"));
                }
                Ok(value)
            }
            Body::Binary { src, pos, len, big_endian, .. } => {
                let size = ty.size();
                if *pos + size > *len {
                    return Err("the file ends early".into());
                }
                let mut buf = [0u8; 8];
                match src {
                    Source::Slice(bytes) => buf[..size].copy_from_slice(&bytes[*pos..*pos + size]),
                    Source::Stream(reader) => std::io::Read::read_exact(reader, &mut buf[..size])
                        .map_err(|e| format!("cannot be read: {e}"))?,
                }
                *pos += size;
                if *big_endian {
                    buf[..size].reverse();
                }
                Ok(match ty {
                    ScalarType::I8 => buf[0] as i8 as f64,
                    ScalarType::U8 => buf[0] as f64,
                    ScalarType::I16 => i16::from_le_bytes([buf[0], buf[1]]) as f64,
                    ScalarType::U16 => u16::from_le_bytes([buf[0], buf[1]]) as f64,
                    ScalarType::I32 => i32::from_le_bytes([buf[0], buf[1], buf[2], buf[3]]) as f64,
                    ScalarType::U32 => u32::from_le_bytes([buf[0], buf[1], buf[2], buf[3]]) as f64,
                    ScalarType::F32 => f32::from_le_bytes([buf[0], buf[1], buf[2], buf[3]]) as f64,
                    ScalarType::F64 => f64::from_le_bytes(buf),
                })
            }
        }
    }

    fn remaining_bytes(&self, total: usize) -> usize {
        match self {
            Body::Ascii { .. } => total,
            Body::Binary { pos, len, .. } => len - pos,
        }
    }
}

/// What a vertex property feeds.
enum VertexSlot {
    Position(usize),
    Normal(usize),
    Color(usize, ScalarType),
    Scalar(usize),
    Ignored,
}

/// Parses a PLY file: the header, then each element in order — vertices
/// (`read_vertices`), faces (`read_faces`), anything else skipped (`skip_element`) —
/// then the check that nothing follows, and the polygons triangulated.
pub fn parse(bytes: &[u8], path: &Path) -> Result<ReadOutcome> {
    let header = parse_header(bytes, path)?;
    let body = open_body(bytes, &header, path)?;
    read_elements(&header, body, path, bytes.len(), false)
}

/// Reads a binary PLY file as its elements come, keeping what a plan cuts (positions,
/// faces and UVs): the file's bytes are never held whole, nor normals, colours or other
/// scalars. `None` for an ASCII file, which [`parse`] reads. The mesh, notes and errors are
/// [`parse`]'s.
///
/// # Errors
/// As [`parse`]; [`Error::Io`] if the file cannot be opened.
pub fn read_lean(path: &Path) -> Result<Option<ReadOutcome>> {
    use std::io::{Read, Seek};
    let (mut file, size) = super::open_regular_file(path)?;
    let mut prefix = Vec::new();
    Read::by_ref(&mut file).take(MAX_HEADER_BYTES as u64).read_to_end(&mut prefix).map_err(|e| Error::io(path, e))?;
    let header = parse_header(&prefix, path)?;
    if header.encoding == Encoding::Ascii {
        return Ok(None);
    }
    let total = usize::try_from(size)
        .map_err(|_| Error::parse(path, Location::File, "larger than this machine's addresses"))?;
    file.seek(std::io::SeekFrom::Start(header.body as u64)).map_err(|e| Error::io(path, e))?;
    let body = Body::Binary {
        src: Source::Stream(std::io::BufReader::with_capacity(1 << 20, file)),
        pos: 0,
        len: total.saturating_sub(header.body),
        base: header.body,
        big_endian: header.encoding == Encoding::BigEndian,
    };
    read_elements(&header, body, path, total, true).map(Some)
}

/// Reads each element in order — vertices (`read_vertices`), faces (`read_faces`,
/// triangulated as they come), anything else skipped (`skip_element`) — then checks that
/// nothing follows. `total` is the file's length; `lean` keeps only positions and UVs.
fn read_elements(header: &Header, mut body: Body, path: &Path, total: usize, lean: bool) -> Result<ReadOutcome> {
    let mut vertices: Option<VertexData> = None;
    let mut faces = Faces::default();
    let mut notes = Vec::new();
    for element in &header.elements {
        // Binary sizes are exact: refuse counts the rest of the file cannot hold. Text is
        // checked as it is read; either way capacity is capped by what the file could hold.
        let remaining = body.remaining_bytes(total - header.body);
        let min_bytes = element.min_bytes(header.encoding);
        if header.encoding != Encoding::Ascii {
            check_count_fits(element.count, min_bytes, remaining, &format!("{} elements", element.name))
                .map_err(|m| Error::parse(path, Location::Line(element.line), m))?;
        }
        let capacity = element.count.min(remaining / min_bytes.max(1));
        match element.name.as_str() {
            "vertex" => vertices = Some(read_vertices(element, &mut body, path, capacity, lean, &mut notes)?),
            "face" => {
                let positions = vertices.as_ref().map(|v| &v.positions[..]).ok_or_else(|| {
                    Error::parse(path, Location::Line(element.line), "the face element comes before the vertex element")
                })?;
                read_faces(element, &mut body, path, positions, capacity, total, &mut faces, &mut notes)?;
            }
            other => {
                notes.push(format!("PLY element `{other}` skipped"));
                skip_element(element, &mut body, path)?;
            }
        }
    }
    let Some(VertexData { positions, normals, colors, scalars }) = vertices else {
        return Err(Error::parse(path, Location::File, "the PLY file has no vertex element"));
    };
    if let Some(line) = body.trailing_line() {
        let declared: Vec<String> = header.elements.iter().map(|e| format!("{} {}", e.count, e.name)).collect();
        return Err(Error::parse(
            path,
            Location::Line(line),
            format!("data after the last element (the header declares {})", declared.join(", ")),
        ));
    }
    notes.extend(repeated_vertex_note(faces.dropped));
    let mut mesh = Mesh { positions, triangles: faces.triangles, normals, colors, scalars, ..Mesh::default() };
    uvs_from_scalars(&mut mesh);
    if lean {
        mesh.scalars.clear();
    }
    Ok(ReadOutcome { mesh, triangulated_polygons: faces.triangulated, notes })
}

/// The body after the header: text lines numbered on from the header's, or bytes.
fn open_body<'a>(bytes: &'a [u8], header: &Header, path: &Path) -> Result<Body<'a>> {
    Ok(match header.encoding {
        Encoding::Ascii => {
            let text = std::str::from_utf8(&bytes[header.body..]).map_err(|e| {
                Error::parse(path, Location::Byte((header.body + e.valid_up_to()) as u64), "the ASCII body is not text")
            })?;
            let offset = header.lines;
            let lines = numbered_lines(text).map(move |(n, l)| (n + offset, l));
            Body::Ascii { lines: Box::new(lines), tokens: "".split_whitespace(), line: header.lines }
        }
        enc => Body::Binary {
            src: Source::Slice(&bytes[header.body..]),
            pos: 0,
            len: bytes.len() - header.body,
            base: header.body,
            big_endian: enc == Encoding::BigEndian,
        },
    })
}

/// What the vertex element holds: positions, and normals, colours and other scalar
/// properties where it declares them.
struct VertexData {
    positions: Vec<DVec3>,
    normals: Option<Vec<DVec3>>,
    colors: Option<Vec<[u8; 3]>>,
    scalars: BTreeMap<String, Vec<f64>>,
}

/// The face element's polygons, triangulated as they are read: the triangles, how many
/// polygons had more than three corners, and how many were dropped for having fewer than
/// three distinct corners.
#[derive(Default)]
struct Faces {
    triangles: Vec<[u32; 3]>,
    triangulated: usize,
    dropped: usize,
    /// The polygon being read.
    polygon: Vec<u32>,
}

/// Reads the vertex element; a non-finite coordinate is an error naming the vertex.
fn read_vertices(
    element: &Element,
    body: &mut Body,
    path: &Path,
    capacity: usize,
    lean: bool,
    notes: &mut Vec<String>,
) -> Result<VertexData> {
    let slots = vertex_slots(element, path, lean, notes)?;
    let mut positions = Vec::with_capacity(capacity);
    let mut normals = slots.iter().any(|s| matches!(s, VertexSlot::Normal(_))).then(|| Vec::with_capacity(capacity));
    let mut colors = slots.iter().any(|s| matches!(s, VertexSlot::Color(..))).then(|| Vec::with_capacity(capacity));
    let scalar_names: Vec<&str> = element
        .properties
        .iter()
        .zip(&slots)
        .filter(|(_, s)| matches!(s, VertexSlot::Scalar(_)))
        .map(|(p, _)| p.name())
        .collect();
    let mut scalar_values = vec![Vec::with_capacity(capacity); scalar_names.len()];
    for i in 0..element.count {
        let (mut position, mut normal, mut color) = (DVec3::ZERO, DVec3::ZERO, [0u8; 3]);
        let at = |body: &Body, m: String| Error::parse(path, body.location(), format!("vertex {i}: {m}"));
        body.begin_element().map_err(|m| at(body, m))?;
        for (property, slot) in element.properties.iter().zip(&slots) {
            let value = match property {
                Property::Scalar { ty, .. } => body.read(*ty).map_err(|m| at(body, m))?,
                Property::List { count, item, .. } => {
                    skip_list(body, *count, *item).map_err(|m| at(body, m))?;
                    continue;
                }
            };
            match *slot {
                VertexSlot::Position(k) => {
                    if !value.is_finite() {
                        return Err(at(body, format!("coordinate {value} is not finite")));
                    }
                    position[k] = value;
                }
                VertexSlot::Normal(k) => normal[k] = value,
                VertexSlot::Color(k, ty) => {
                    let c = if ty.is_integer() { value } else { value * 255.0 };
                    color[k] = c.round().clamp(0.0, 255.0) as u8;
                }
                VertexSlot::Scalar(k) => scalar_values[k].push(value),
                VertexSlot::Ignored => {}
            }
        }
        body.end_element().map_err(|m| at(body, m))?;
        positions.push(position);
        if let Some(normals) = &mut normals {
            normals.push(normal);
        }
        if let Some(colors) = &mut colors {
            colors.push(color);
        }
    }
    let scalars = scalar_names.into_iter().map(str::to_string).zip(scalar_values).collect();
    Ok(VertexData { positions, normals, colors, scalars })
}

/// Reads the face element's `vertex_indices` lists into `faces`, each polygon triangulated
/// on `positions` as it is read (its other properties are skipped, with a note); an index
/// outside the vertices is an error naming the face, and a polygon with repeated corners
/// keeps its distinct ones (or is dropped).
#[allow(clippy::too_many_arguments)]
fn read_faces(
    element: &Element,
    body: &mut Body,
    path: &Path,
    positions: &[DVec3],
    capacity: usize,
    total_bytes: usize,
    faces: &mut Faces,
    notes: &mut Vec<String>,
) -> Result<()> {
    let index_property = element
        .properties
        .iter()
        .position(|p| matches!(p, Property::List { name, .. } if name == "vertex_indices" || name == "vertex_index"))
        .ok_or_else(|| Error::parse(path, Location::Line(element.line), "faces have no `vertex_indices` list"))?;
    if element.properties.len() > 1 {
        notes.push("PLY face properties other than vertex_indices ignored".to_string());
    }
    faces.triangles.reserve(capacity);
    for f in 0..element.count {
        let at = |body: &Body, m: String| Error::parse(path, body.location(), format!("face {f}: {m}"));
        body.begin_element().map_err(|m| at(body, m))?;
        for (k, property) in element.properties.iter().enumerate() {
            match property {
                Property::Scalar { ty, .. } => {
                    body.read(*ty).map_err(|m| at(body, m))?;
                }
                Property::List { count, item, .. } if k == index_property => {
                    let len = body.read(*count).map_err(|m| at(body, m))?;
                    let len = list_length(len, body, total_bytes, *item).map_err(|m| at(body, m))?;
                    let polygon = &mut faces.polygon;
                    polygon.clear();
                    for _ in 0..len {
                        let v = body.read(*item).map_err(|m| at(body, m))?;
                        if v < 0.0 || v.fract() != 0.0 || v > u32::MAX as f64 {
                            return Err(at(body, format!("bad vertex index {v}")));
                        }
                        polygon.push(v as u32);
                    }
                    check_polygon(polygon, positions.len()).map_err(|m| at(body, m))?;
                    let repeats = polygon.iter().enumerate().any(|(i, a)| polygon[i + 1..].contains(a));
                    if repeats && !without_repeated_corners(polygon) {
                        faces.dropped += 1;
                    } else {
                        faces.triangulated += usize::from(polygon.len() > 3);
                        triangulate_polygon(positions, polygon, &mut faces.triangles);
                    }
                }
                Property::List { count, item, .. } => {
                    skip_list(body, *count, *item).map_err(|m| at(body, m))?;
                }
            }
        }
        body.end_element().map_err(|m| at(body, m))?;
    }
    Ok(())
}

/// Reads past an element asperity does not use, checking that its data is well formed.
fn skip_element(element: &Element, body: &mut Body, path: &Path) -> Result<()> {
    let name = &element.name;
    // An element without properties has nothing on any line.
    let count = if element.properties.is_empty() { 0 } else { element.count };
    for i in 0..count {
        let at = |body: &Body, m: String| Error::parse(path, body.location(), format!("{name} {i}: {m}"));
        body.begin_element().map_err(|m| at(body, m))?;
        for property in &element.properties {
            let r = match property {
                Property::Scalar { ty, .. } => body.read(*ty).map(|_| ()),
                Property::List { count, item, .. } => skip_list(body, *count, *item),
            };
            r.map_err(|m| at(body, m))?;
        }
        body.end_element().map_err(|m| at(body, m))?;
    }
    Ok(())
}

/// What each vertex property feeds; `lean` ignores all but positions and UVs.
fn vertex_slots(element: &Element, path: &Path, lean: bool, notes: &mut Vec<String>) -> Result<Vec<VertexSlot>> {
    let mut slots = Vec::with_capacity(element.properties.len());
    let mut found = [false; 3];
    for p in &element.properties {
        let slot = match p {
            Property::Scalar { name, ty } => match name.as_str() {
                "x" | "y" | "z" => {
                    let k = (name.as_bytes()[0] - b'x') as usize;
                    found[k] = true;
                    VertexSlot::Position(k)
                }
                "nx" | "ny" | "nz" => VertexSlot::Normal((name.as_bytes()[1] - b'x') as usize),
                "red" | "diffuse_red" => VertexSlot::Color(0, *ty),
                "green" | "diffuse_green" => VertexSlot::Color(1, *ty),
                "blue" | "diffuse_blue" => VertexSlot::Color(2, *ty),
                _ => VertexSlot::Scalar(0),
            },
            Property::List { name, .. } => {
                notes.push(format!("PLY vertex list property `{name}` ignored"));
                VertexSlot::Ignored
            }
        };
        slots.push(slot);
    }
    if found != [true; 3] {
        return Err(Error::parse(path, Location::Line(element.line), "vertices lack x, y and z properties"));
    }
    if lean {
        for (p, s) in element.properties.iter().zip(&mut slots) {
            let uv = UV_PROPERTIES.iter().flatten().any(|&n| n == p.name());
            if matches!(s, VertexSlot::Normal(_) | VertexSlot::Color(..)) || (matches!(s, VertexSlot::Scalar(_)) && !uv)
            {
                *s = VertexSlot::Ignored;
            }
        }
    }
    let mut next = 0;
    for s in &mut slots {
        if let VertexSlot::Scalar(k) = s {
            *k = next;
            next += 1;
        }
    }
    Ok(slots)
}

/// Validates a list length against what the rest of the file can hold.
fn list_length(len: f64, body: &Body, total: usize, item: ScalarType) -> std::result::Result<usize, String> {
    let len = integral_length(len)?;
    let min = match body {
        Body::Ascii { .. } => 2,
        Body::Binary { .. } => item.size(),
    };
    check_count_fits(len, min, body.remaining_bytes(total), "list items")?;
    Ok(len)
}

/// A list length read as a number: a non-negative integer (NaN fails `fract`).
fn integral_length(len: f64) -> std::result::Result<usize, String> {
    if len < 0.0 || len.fract() != 0.0 {
        return Err(format!("bad list length {len}"));
    }
    Ok(len as usize)
}

fn skip_list(body: &mut Body, count: ScalarType, item: ScalarType) -> std::result::Result<(), String> {
    let len = integral_length(body.read(count)?)?;
    for _ in 0..len {
        body.read(item)?;
    }
    Ok(())
}

/// What a PLY file written by asperity holds per vertex, for [`write_header`].
#[derive(Debug, Clone)]
pub struct PlyLayout {
    /// Vertex count.
    pub vertices: usize,
    /// Triangle count.
    pub faces: usize,
    /// Whether `nx ny nz` follow the position.
    pub normals: bool,
    /// Whether `red green blue` follow.
    pub colors: bool,
    /// Names of the double scalar properties that follow, in order.
    pub scalars: Vec<String>,
    /// Text instead of binary little-endian.
    pub ascii: bool,
}

/// Writes the header of a PLY file with `layout`.
pub fn write_header(w: &mut dyn Write, layout: &PlyLayout) -> std::io::Result<()> {
    if layout.vertices > i32::MAX as usize {
        return Err(std::io::Error::new(std::io::ErrorKind::InvalidInput, "too many vertices for PLY int indices"));
    }
    writeln!(w, "ply")?;
    writeln!(w, "format {} 1.0", if layout.ascii { "ascii" } else { "binary_little_endian" })?;
    writeln!(w, "comment written by asperity {}", env!("CARGO_PKG_VERSION"))?;
    writeln!(w, "element vertex {}", layout.vertices)?;
    for axis in ["x", "y", "z"] {
        writeln!(w, "property double {axis}")?;
    }
    if layout.normals {
        for axis in ["nx", "ny", "nz"] {
            writeln!(w, "property double {axis}")?;
        }
    }
    if layout.colors {
        for c in ["red", "green", "blue"] {
            writeln!(w, "property uchar {c}")?;
        }
    }
    for name in &layout.scalars {
        writeln!(w, "property double {}", name.split_whitespace().collect::<Vec<_>>().join("_"))?;
    }
    writeln!(w, "element face {}", layout.faces)?;
    writeln!(w, "property list uchar int vertex_indices")?;
    writeln!(w, "end_header")
}

/// Writes one vertex record matching a [`PlyLayout`].
pub fn write_vertex(
    w: &mut dyn Write,
    ascii: bool,
    position: DVec3,
    normal: Option<DVec3>,
    color: Option<[u8; 3]>,
    scalars: &[f64],
) -> std::io::Result<()> {
    if ascii {
        let mut fields: Vec<String> = position.to_array().iter().map(|v| v.to_string()).collect();
        if let Some(n) = normal {
            fields.extend(n.to_array().iter().map(|v| v.to_string()));
        }
        if let Some(c) = color {
            fields.extend(c.iter().map(|v| v.to_string()));
        }
        fields.extend(scalars.iter().map(|v| v.to_string()));
        return writeln!(w, "{}", fields.join(" "));
    }
    let mut record = [0u8; 8 * 6 + 3];
    let mut len = 0;
    for v in position.to_array().into_iter().chain(normal.map(|n| n.to_array()).into_iter().flatten()) {
        record[len..len + 8].copy_from_slice(&v.to_le_bytes());
        len += 8;
    }
    if let Some(c) = color {
        record[len..len + 3].copy_from_slice(&c);
        len += 3;
    }
    w.write_all(&record[..len])?;
    for v in scalars {
        w.write_all(&v.to_le_bytes())?;
    }
    Ok(())
}

/// Writes one triangle record.
pub fn write_triangle(w: &mut dyn Write, ascii: bool, t: [u32; 3]) -> std::io::Result<()> {
    if ascii {
        return writeln!(w, "3 {} {} {}", t[0], t[1], t[2]);
    }
    let mut record = [3u8; 13];
    for (k, v) in t.iter().enumerate() {
        record[1 + 4 * k..5 + 4 * k].copy_from_slice(&(*v as i32).to_le_bytes());
    }
    w.write_all(&record)
}

/// The vertex property pairs read as texture coordinates, in order of preference (the
/// first is what asperity writes).
const UV_PROPERTIES: [[&str; 2]; 4] = [["s", "t"], ["u", "v"], ["texture_u", "texture_v"], ["texture_s", "texture_t"]];

/// Moves the first pair of UV properties from the scalars into per-vertex UVs.
fn uvs_from_scalars(mesh: &mut Mesh) {
    let Some([u, v]) =
        UV_PROPERTIES.iter().find(|[u, v]| mesh.scalars.contains_key(*u) && mesh.scalars.contains_key(*v))
    else {
        return;
    };
    let us = mesh.scalars.remove(*u).expect("found above");
    let vs = mesh.scalars.remove(*v).expect("found above");
    let values = us.into_iter().zip(vs).map(|(u, v)| [u, v]).collect();
    mesh.uvs = Some(crate::mesh::uv::CornerUvs::per_vertex(values, &mesh.triangles));
}

/// Writes a PLY file: binary little-endian, or ASCII with `ascii`. UVs are written as the
/// vertex properties `s t`, one vertex per distinct (vertex, UV) (PLY holds one UV per
/// vertex).
pub fn write(mesh: &Mesh, w: &mut dyn Write, ascii: bool) -> std::io::Result<()> {
    if mesh.uvs.is_some() {
        let (mut split, _) = crate::mesh::uv::split_by_uv(mesh);
        let values = split.uvs.take().map(|u| u.values).unwrap_or_default();
        let [u, v] = UV_PROPERTIES[0];
        split.scalars.insert(u.into(), values.iter().map(|uv| uv[0]).collect());
        split.scalars.insert(v.into(), values.iter().map(|uv| uv[1]).collect());
        return write_plain(&split, w, ascii);
    }
    write_plain(mesh, w, ascii)
}

fn write_plain(mesh: &Mesh, w: &mut dyn Write, ascii: bool) -> std::io::Result<()> {
    let layout = PlyLayout {
        vertices: mesh.positions.len(),
        faces: mesh.triangles.len(),
        normals: mesh.normals.is_some(),
        colors: mesh.colors.is_some(),
        scalars: mesh.scalars.keys().cloned().collect(),
        ascii,
    };
    write_header(w, &layout)?;
    let scalar_columns: Vec<&Vec<f64>> = mesh.scalars.values().collect();
    let mut extra = Vec::with_capacity(scalar_columns.len());
    for (i, p) in mesh.positions.iter().enumerate() {
        extra.clear();
        extra.extend(scalar_columns.iter().map(|c| c[i]));
        let normal = mesh.normals.as_ref().map(|n| n[i]);
        let color = mesh.colors.as_ref().map(|c| c[i]);
        write_vertex(w, ascii, *p, normal, color, &extra)?;
    }
    for t in &mesh.triangles {
        write_triangle(w, ascii, *t)?;
    }
    Ok(())
}
