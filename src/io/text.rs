//! Text input helpers: UTF-8 decoding with a clear error, BOM removal, and lines numbered
//! from 1 whatever the line ending (`\n`, `\r\n` or a lone `\r`).

use std::borrow::Cow;
use std::path::Path;

use crate::error::{Error, Location, Result};

/// The file as text, without a UTF-8 byte order mark. Bytes that are not UTF-8 are
/// accepted inside `#` comments, read there as Latin-1 (#36: a comment written by a
/// Latin-1 exporter refused the whole OBJ file); anywhere else they are an error naming
/// the first such byte.
pub fn decode<'a>(bytes: &'a [u8], path: &Path) -> Result<Cow<'a, str>> {
    let file_len = bytes.len();
    let bytes = bytes.strip_prefix(b"\xef\xbb\xbf").unwrap_or(bytes);
    if let Ok(text) = std::str::from_utf8(bytes) {
        return Ok(Cow::Borrowed(text));
    }
    let mut text = String::with_capacity(bytes.len());
    // Byte offsets count from the file's first byte, the mark included.
    let mut start = file_len - bytes.len();
    for line in bytes.split_inclusive(|&b| b == b'\n' || b == b'\r') {
        let hash = line.iter().position(|&b| b == b'#').unwrap_or(line.len());
        let (content, comment) = line.split_at(hash);
        let content = std::str::from_utf8(content).map_err(|e| {
            Error::parse(path, Location::Byte((start + e.valid_up_to()) as u64), "not a text file (invalid UTF-8)")
        })?;
        text.push_str(content);
        match std::str::from_utf8(comment) {
            Ok(comment) => text.push_str(comment),
            Err(_) => text.extend(comment.iter().map(|&b| char::from(b))),
        }
        start += line.len();
    }
    Ok(Cow::Owned(text))
}

/// Numbered lines, any line ending.
pub fn numbered_lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    let mut rest = text;
    let mut number = 0;
    std::iter::from_fn(move || {
        if rest.is_empty() {
            return None;
        }
        number += 1;
        let end = rest.find(['\n', '\r']).unwrap_or(rest.len());
        let line = &rest[..end];
        let skip = match rest.as_bytes().get(end) {
            Some(b'\r') if rest.as_bytes().get(end + 1) == Some(&b'\n') => 2,
            Some(_) => 1,
            None => 0,
        };
        rest = &rest[end + skip..];
        Some((number, line))
    })
}

/// Numbered lines with `#` comments removed, blank lines skipped, split into tokens.
pub fn significant_lines(text: &str) -> impl Iterator<Item = (usize, Vec<&str>)> {
    numbered_lines(text).filter_map(|(n, line)| {
        let content = line.split('#').next().unwrap_or("");
        let tokens: Vec<&str> = content.split_whitespace().collect();
        (!tokens.is_empty()).then_some((n, tokens))
    })
}

/// Parses a finite coordinate.
pub fn coordinate(token: &str) -> std::result::Result<f64, String> {
    match token.parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        Ok(_) => Err(format!("coordinate `{token}` is not finite")),
        Err(_) => Err(format!("`{}` is not a number", shorten(token))),
    }
}

/// Parses a non-negative integer (count or index).
pub fn unsigned(token: &str, what: &str) -> std::result::Result<usize, String> {
    token.parse::<usize>().map_err(|_| format!("{what} `{}` is not a non-negative integer", shorten(token)))
}

/// A token cut to a printable length for messages.
pub fn shorten(token: &str) -> String {
    if token.chars().count() > 32 {
        format!("{}...", token.chars().take(32).collect::<String>())
    } else {
        token.to_string()
    }
}

/// A TOML document checked by `check`; errors carry the 1-based line when known (recipes,
/// flora rules), and a value's error names its key (`intersection_guard: invalid type`).
pub fn parse_toml<T: serde::de::DeserializeOwned>(
    text: &str,
    check: impl FnOnce(&T) -> std::result::Result<(), String>,
) -> std::result::Result<T, (Option<usize>, String)> {
    let value: T = toml::from_str(text).map_err(|e| {
        let Some(span) = e.span() else { return (None, e.message().to_string()) };
        let at = span.start.min(text.len());
        let line_start = text[..at].rfind('\n').map_or(0, |i| i + 1);
        let line = text[..at].matches('\n').count() + 1;
        match value_key(&text[line_start..at], &text[at..]) {
            Some(key) => (Some(line), format!("{key}: {}", e.message())),
            None => (Some(line), e.message().to_string()),
        }
    })?;
    check(&value).map_err(|msg| (None, msg))?;
    Ok(value)
}

/// The key whose value an error at the end of `before` (its line up to the error) is in:
/// the last `key =` outside strings, within the innermost inline table or list. `None` when
/// the error is at a key itself (`after` starts with the key and its `=`, as for an unknown
/// field) or no key precedes it on the line.
fn value_key<'t>(before: &'t str, after: &str) -> Option<&'t str> {
    let after = after.lines().next().unwrap_or("");
    let at_key = after.split_once('=').is_some_and(|(key, _)| {
        let key = key.trim();
        !key.is_empty() && key.chars().all(|c| c.is_alphanumeric() || matches!(c, '_' | '-' | '.'))
    });
    if at_key {
        return None;
    }
    // Scan outside strings: a key starts after the line's start, `{` or `,` and ends at `=`.
    let (mut quote, mut key_start, mut key) = (None::<char>, 0, None);
    for (i, c) in before.char_indices() {
        match (quote, c) {
            (Some(q), c) if c == q => quote = None,
            (Some(_), _) => {}
            (None, '"' | '\'') => quote = Some(c),
            (None, '{' | ',' | '[') => key_start = i + 1,
            (None, '=') => key = Some(before[key_start..i].trim()),
            _ => {}
        }
    }
    key.filter(|k| !k.is_empty())
}

/// Reads a TOML file with `parse` (such as [`parse_toml`]); errors name the file and line.
///
/// # Errors
/// [`Error::Io`] if the file cannot be read or is not UTF-8; [`Error::Parse`] naming the
/// file and line.
pub fn read_toml_file<T>(
    path: &Path,
    parse: impl FnOnce(&str) -> std::result::Result<T, (Option<usize>, String)>,
) -> Result<T> {
    let bytes = super::read_regular_file(path)?;
    let text = String::from_utf8(bytes)
        .map_err(|e| Error::io(path, std::io::Error::new(std::io::ErrorKind::InvalidData, e.utf8_error())))?;
    parse(&text).map_err(|(line, msg)| Error::Parse {
        path: path.to_path_buf(),
        at: line.map_or(Location::File, Location::Line),
        msg,
    })
}

#[cfg(test)]
mod tests {
    use super::parse_toml;

    #[derive(Debug, serde::Deserialize)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)]
    struct Doc {
        flag: Option<bool>,
        table: Option<std::collections::BTreeMap<String, u8>>,
        inner: Option<Inner>,
    }

    #[derive(Debug, serde::Deserialize)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)]
    struct Inner {
        kind: Option<String>,
        octaves: Option<u8>,
    }

    fn error(text: &str) -> (Option<usize>, String) {
        parse_toml::<Doc>(text, |_| Ok(())).unwrap_err()
    }

    #[test]
    fn a_value_error_names_its_line_and_key() {
        let (line, message) = error("\nflag = \"no\"\n");
        assert_eq!(line, Some(2));
        assert!(message.starts_with("flag: invalid type"), "{message}");
        let (_, message) = error("table = { a = 1, b = \"x\" }\n");
        assert!(message.starts_with("b: "), "{message}");
        // An `=` or `,` inside a string is not a key's.
        let (_, message) = error("table = { a = 1, \"c=d,e\" = -1 }\n");
        assert!(message.starts_with("\"c=d,e\": "), "{message}");
        let (line, message) = error("flag = true\nother = 1\n");
        assert_eq!(line, Some(2));
        assert!(message.starts_with("unknown field `other`"), "{message}");
        // An unknown key inside an inline table is named by the message alone, not
        // prefixed with the key before it.
        let (_, message) = error("inner = { kind = \"x\", octavs = 3 }\n");
        assert!(message.starts_with("unknown field `octavs`"), "{message}");
        let (_, message) = error("inner = { kind = \"x\", octaves = \"many\" }\n");
        assert!(message.starts_with("octaves: invalid type"), "{message}");
    }
}
