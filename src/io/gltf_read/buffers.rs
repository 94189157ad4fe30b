//! A glTF document's buffers (glTF 2.0 §3.6.1 "Buffers and Buffer Views", §4.4 "GLB File
//! Format"): the GLB binary chunk, base64 `data:` URIs, and files beside the document named
//! by relative URIs. Each is loaded when first used, and must hold the bytes its
//! `byteLength` declares.

use std::borrow::Cow;
use std::cell::OnceCell;
use std::path::Path;

use base64::Engine as _;

/// The buffers of one document, loaded on first use.
pub(super) struct Buffers<'a> {
    /// The document's own path: relative URIs are resolved beside it.
    path: &'a Path,
    /// The GLB binary chunk, if the document came in a GLB container.
    bin: Option<&'a [u8]>,
    loaded: Vec<OnceCell<Cow<'a, [u8]>>>,
}

impl<'a> Buffers<'a> {
    pub(super) fn new(root: &gltf::json::Root, path: &'a Path, bin: Option<&'a [u8]>) -> Self {
        Buffers { path, bin, loaded: root.buffers.iter().map(|_| OnceCell::new()).collect() }
    }

    /// The bytes of buffer view `view` and its declared `byteStride`, both checked against
    /// the buffer.
    pub(super) fn view(&self, root: &gltf::json::Root, view: usize) -> Result<(&[u8], Option<usize>), String> {
        let v = root
            .buffer_views
            .get(view)
            .ok_or_else(|| format!("buffer view {view} does not exist (the file has {})", root.buffer_views.len()))?;
        let buffer = v.buffer.value();
        let data = self.buffer(root, buffer)?;
        let offset = v.byte_offset.map_or(0, |o| o.0);
        let end = offset.checked_add(v.byte_length.0);
        match end {
            Some(end) if end <= data.len() as u64 => {}
            _ => {
                return Err(format!(
                    "buffer view {view} spans bytes {offset} to {} of buffer {buffer}, which has {}",
                    offset.saturating_add(v.byte_length.0),
                    data.len()
                ));
            }
        }
        let stride = v.byte_stride.map(|s| s.0);
        Ok((&data[offset as usize..(offset + v.byte_length.0) as usize], stride))
    }

    /// Buffer `index`'s bytes, its declared `byteLength` of them.
    fn buffer(&self, root: &gltf::json::Root, index: usize) -> Result<&[u8], String> {
        let declared = root
            .buffers
            .get(index)
            .ok_or_else(|| format!("buffer {index} does not exist (the file has {})", root.buffers.len()))?;
        let cell = &self.loaded[index];
        if cell.get().is_none() {
            let bytes = self.load(index, declared)?;
            let _ = cell.set(bytes);
        }
        let bytes = cell.get().map(|b| &b[..]).unwrap_or_default();
        let length = usize::try_from(declared.byte_length.0).unwrap_or(usize::MAX);
        if bytes.len() < length {
            return Err(format!("buffer {index} declares {length} bytes but holds {}", bytes.len()));
        }
        Ok(&bytes[..length])
    }

    fn load(&self, index: usize, declared: &gltf::json::Buffer) -> Result<Cow<'a, [u8]>, String> {
        let Some(uri) = declared.uri.as_deref() else {
            return match self.bin {
                Some(bin) if index == 0 => Ok(Cow::Borrowed(bin)),
                Some(_) => Err(format!("buffer {index} has no uri, and only buffer 0 is the GLB binary chunk")),
                None => Err(format!("buffer {index} has no uri, and there is no GLB binary chunk")),
            };
        };
        if let Some(data) = uri.strip_prefix("data:") {
            return decode_data_uri(data).map(Cow::Owned).map_err(|m| format!("buffer {index}'s data: URI {m}"));
        }
        let shown = super::super::text::shorten(uri);
        if has_scheme(uri) || uri.starts_with('/') || uri.starts_with('\\') {
            return Err(format!(
                "buffer {index}'s uri `{shown}` is not a path relative to the glTF file (only such files and data: URIs are read)"
            ));
        }
        let relative = percent_decode(uri).map_err(|m| format!("buffer {index}'s uri `{shown}`: {m}"))?;
        let file = self.path.parent().unwrap_or(Path::new("")).join(relative);
        super::super::read_regular_file(&file).map(Cow::Owned).map_err(|e| {
            let why = match e {
                crate::Error::Io { source, .. } => source.to_string(),
                other => other.to_string(),
            };
            format!("buffer {index} is the file `{shown}` beside the glTF, which cannot be read: {why}")
        })
    }
}

/// Whether a URI reference starts with a scheme (`http:`, `file:`, ...; RFC 3986 §3.1).
fn has_scheme(uri: &str) -> bool {
    match uri.split_once(':') {
        Some((scheme, _)) => {
            let mut chars = scheme.chars();
            chars.next().is_some_and(|c| c.is_ascii_alphabetic())
                && chars.all(|c| c.is_ascii_alphanumeric() || matches!(c, '+' | '-' | '.'))
        }
        None => false,
    }
}

/// A relative URI's path with its `%XX` escapes decoded (RFC 3986 §2.1).
fn percent_decode(uri: &str) -> Result<String, String> {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = bytes.get(i + 1..i + 3).and_then(|h| std::str::from_utf8(h).ok());
            let value = hex.and_then(|h| u8::from_str_radix(h, 16).ok());
            let Some(value) = value else {
                return Err(format!("a `%` at byte {i} is not followed by two hexadecimal digits"));
            };
            out.push(value);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).map_err(|_| "its escapes do not decode to UTF-8".to_string())
}

/// The bytes of a `data:` URI after its `data:`: `[<media type>];base64,<data>` (RFC 2397);
/// glTF embeds buffers only in base64.
fn decode_data_uri(data: &str) -> Result<Vec<u8>, String> {
    let Some((header, payload)) = data.split_once(',') else {
        return Err("has no `,` before its data".into());
    };
    if !header.ends_with(";base64") {
        return Err(format!(
            "is not base64 (`{}`): glTF embeds buffers in base64",
            super::super::text::shorten(header)
        ));
    }
    let engine = base64::engine::GeneralPurpose::new(
        &base64::alphabet::STANDARD,
        base64::engine::GeneralPurposeConfig::new()
            .with_decode_padding_mode(base64::engine::DecodePaddingMode::Indifferent),
    );
    engine.decode(payload.trim_end()).map_err(|e| format!("is not valid base64: {e}"))
}

/// A buffer's bytes as a base64 `data:` URI, for `.gltf` files written in one piece.
pub(crate) fn data_uri(bytes: &[u8]) -> String {
    format!("data:application/octet-stream;base64,{}", base64::engine::general_purpose::STANDARD.encode(bytes))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative_uris_decode_and_others_are_recognised() {
        assert_eq!(percent_decode("my%20mesh.bin").unwrap(), "my mesh.bin");
        assert!(percent_decode("bad%2").is_err());
        assert!(has_scheme("http://example.com/a.bin"));
        assert!(has_scheme("file:a.bin"));
        assert!(!has_scheme("a.bin"));
        assert!(!has_scheme("dir/a:b.bin"));
        assert_eq!(decode_data_uri(&data_uri(b"\x00\x01\xff")["data:".len()..]).unwrap(), b"\x00\x01\xff");
        assert!(decode_data_uri("text/plain,abc").unwrap_err().contains("not base64"));
    }
}
