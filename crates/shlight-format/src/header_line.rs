//! What shlight's binary files share (`.shprt`, `.shvol`): one line of JSON
//! naming the format, then little-endian `f32` data.

use std::path::Path;

use serde_json::Value;

use crate::{FormatError, Result};

/// The file's bytes, or [`FormatError::Read`] naming it.
pub(crate) fn read_file(path: &Path) -> Result<Vec<u8>> {
    std::fs::read(path).map_err(|source| FormatError::Read {
        path: path.to_path_buf(),
        source,
    })
}

/// The header line as JSON (checked to be an object whose `format` is
/// `format`) and the bytes after it; `extension` names the kind of file in
/// the error for a missing line, which is looked for in the first
/// `max_header` bytes.
pub(crate) fn split<'a>(
    bytes: &'a [u8],
    name: &str,
    format: &str,
    extension: &str,
    max_header: usize,
) -> Result<(Value, &'a [u8])> {
    let bad = |message: String| FormatError::invalid(name, message);
    let end = bytes
        .iter()
        .take(max_header)
        .position(|&b| b == b'\n')
        .ok_or_else(|| {
            bad(format!(
                "not a {extension} file (no header line ending in a newline)"
            ))
        })?;
    let header: Value = serde_json::from_slice(&bytes[..end])
        .map_err(|e| bad(format!("bad header (not JSON: {e})")))?;
    if header.get("format").and_then(Value::as_str) != Some(format) {
        return Err(bad(format!("bad header (\"format\" is not \"{format}\")")));
    }
    Ok((header, &bytes[end + 1..]))
}

/// The header's `key` as a whole number; the error names the file
/// `name` and the key.
pub(crate) fn uint(header: &Value, key: &str, name: &str) -> Result<u64> {
    header.get(key).and_then(Value::as_u64).ok_or_else(|| {
        FormatError::invalid(
            name,
            format!("bad header (\"{key}\" is missing or not an integer)"),
        )
    })
}

/// The header's `key` as a string; the error names the file `name` and
/// the key.
pub(crate) fn text(header: &Value, key: &str, name: &str) -> Result<String> {
    header
        .get(key)
        .and_then(Value::as_str)
        .map(str::to_string)
        .ok_or_else(|| {
            FormatError::invalid(
                name,
                format!("bad header (\"{key}\" is missing or not a string)"),
            )
        })
}

/// The header's `key`, `fnv1a64:` and 16 hex digits, as a number.
pub(crate) fn hash(header: &Value, key: &str, name: &str) -> Result<u64> {
    header
        .get(key)
        .and_then(Value::as_str)
        .and_then(|s| s.strip_prefix("fnv1a64:"))
        .and_then(|h| u64::from_str_radix(h, 16).ok())
        .ok_or_else(|| {
            FormatError::invalid(name, format!("bad header (\"{key}\" is not fnv1a64:HEX)"))
        })
}

/// A hash as the header writes it.
pub(crate) fn hash_text(hash: u64) -> String {
    format!("fnv1a64:{hash:016x}")
}

/// The header line and `values` as little-endian `f32`.
pub(crate) fn to_bytes<'a>(header: &Value, values: impl IntoIterator<Item = &'a f32>) -> Vec<u8> {
    let mut out = serde_json::to_vec(header).expect("JSON values serialise");
    out.push(b'\n');
    for x in values {
        out.extend(x.to_le_bytes());
    }
    out
}

/// Little-endian `f32`s (a length that is a multiple of 4).
pub(crate) fn f32s(data: &[u8]) -> Vec<f32> {
    data.chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect()
}
