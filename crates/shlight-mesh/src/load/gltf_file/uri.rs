//! The bytes a glTF URI names: a base64 `data:` URI, or a file relative to
//! the glTF file's directory (percent-decoded, as glTF URIs are encoded).

use std::path::{Path, PathBuf};

use base64::Engine as _;

/// Where a URI's bytes come from, for messages.
pub(crate) enum Origin {
    /// A `data:` URI.
    Data,
    /// A file.
    File(PathBuf),
}

/// The bytes of `uri`, resolved against the directory of `gltf` (the
/// glTF file), and where they came from; an error says why not, naming
/// the file.
pub(crate) fn read(gltf: &Path, uri: &str) -> Result<(Vec<u8>, Origin), String> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let (_, data) = rest
            .split_once(";base64,")
            .ok_or("only base64 data URIs are supported")?;
        return base64::engine::general_purpose::STANDARD
            .decode(data)
            .map(|bytes| (bytes, Origin::Data))
            .map_err(|e| format!("bad base64 data: {e}"));
    }
    if uri.contains("://") {
        return Err(format!(
            "{uri} is not a relative file name (no network access)"
        ));
    }
    let file = gltf
        .parent()
        .unwrap_or(Path::new("."))
        .join(percent_decode(uri));
    match std::fs::read(&file) {
        Ok(bytes) => Ok((bytes, Origin::File(file))),
        Err(e) => Err(format!("cannot read {}: {e}", file.display())),
    }
}

/// `%XX` escapes of a relative URI decoded (glTF URIs are percent-encoded).
fn percent_decode(uri: &str) -> String {
    let b = uri.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        let hex = |c: u8| (c as char).to_digit(16);
        if b[i] == b'%'
            && i + 2 < b.len()
            && let (Some(h), Some(l)) = (hex(b[i + 1]), hex(b[i + 2]))
        {
            out.push((h * 16 + l) as u8);
            i += 3;
            continue;
        }
        out.push(b[i]);
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escapes_are_decoded() {
        assert_eq!(percent_decode("my%20data.bin"), "my data.bin");
        assert_eq!(percent_decode("a%C3%A9%2"), "a\u{e9}%2");
    }
}
