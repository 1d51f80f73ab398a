//! Wavefront MTL material libraries (`.mtl`), the files an OBJ's `mtllib`
//! names, through `tobj`: of each `newmtl` the OBJ reader keeps the name,
//! the diffuse albedo `Kd` and the emitted radiance `Ke`.

use std::path::Path;

use glam::Vec3;

use crate::MeshError;

/// One material of an MTL file: what shlight's OBJ reader takes from it.
#[derive(Clone, Debug, PartialEq)]
pub struct MtlMaterial {
    /// The `newmtl` name (what `usemtl` refers to).
    pub name: String,
    /// `Kd`: the diffuse albedo (linear RGB), when the material gives one.
    pub diffuse: Option<Vec3>,
    /// `Ke`: the emitted radiance, when the material gives one.
    pub emission: Option<Vec3>,
}

/// The colour keys tobj reads as three floats.
const COLOURS: [&str; 4] = ["Ka", "Kd", "Ks", "Ke"];

/// What tobj would panic on, found first: a colour line with fewer than
/// three values (tobj 4 unwraps its conversion to `[f32; 3]`, in any
/// build). Lines as tobj reads them (`BufRead::lines`), up to the first
/// that is not UTF-8, where tobj stops with an error of its own.
pub(super) fn check(bytes: &[u8]) -> Result<(), String> {
    let body = bytes.strip_suffix(b"\n").unwrap_or(bytes);
    for (k, line) in body.split(|&b| b == b'\n').enumerate() {
        let Ok(line) = std::str::from_utf8(line.strip_suffix(b"\r").unwrap_or(line)) else {
            return Ok(());
        };
        let mut words = line.split_whitespace();
        if let Some(key) = words.next().filter(|w| COLOURS.contains(w)) {
            let n = words.count();
            if n < 3 {
                return Err(format!("line {}: {key} needs 3 values, has {n}", k + 1));
            }
        }
    }
    Ok(())
}

/// tobj's parse of an MTL file held in memory, once [`check`] has passed:
/// what the OBJ reader hands tobj for each `mtllib` it finds.
pub(super) fn parse(bytes: &[u8]) -> tobj::MTLLoadResult {
    tobj::load_mtl_buf(&mut std::io::Cursor::new(bytes))
}

/// Parses an MTL material library held in memory, as the OBJ reader does
/// for each file its `mtllib` lines name; `path` names it in errors. The
/// materials come in file order. Memory and time grow with the file's
/// size (docs/limits.md).
///
/// ```
/// use std::path::Path;
/// let m = shlight_mesh::parse_mtl_bytes(Path::new("m.mtl"), b"newmtl lamp\nKd 0 0 0\nKe 5 4 3\n")
///     .unwrap();
/// assert_eq!(m[0].name, "lamp");
/// assert_eq!(m[0].emission, Some(glam::Vec3::new(5.0, 4.0, 3.0)));
/// ```
///
/// # Errors
/// [`MeshError::Parse`] naming `path`: a line tobj cannot parse or a
/// colour (`Ka`, `Kd`, `Ks`, `Ke`) of fewer than three values ("not a
/// valid MTL file"), or tobj panicking on the input ("the MTL reader
/// failed").
pub fn parse_mtl_bytes(path: &Path, bytes: &[u8]) -> Result<Vec<MtlMaterial>, MeshError> {
    let invalid = |message: String| MeshError::Parse {
        path: path.to_path_buf(),
        message: format!("not a valid MTL file: {message}"),
    };
    check(bytes).map_err(invalid)?;
    super::caught(path, "MTL", || {
        let (materials, _) = parse(bytes).map_err(|e| invalid(e.to_string()))?;
        Ok(materials
            .into_iter()
            .map(|m| MtlMaterial {
                name: m.name,
                diffuse: m.diffuse.map(Vec3::from_array),
                emission: m.emissive.map(Vec3::from_array),
            })
            .collect())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn materials_in_file_order_with_albedo_and_emission() {
        let m = parse_mtl_bytes(
            Path::new("m.mtl"),
            b"# two\nnewmtl red\nKd 0.8 0.1 0.1\nNs 10\n\nnewmtl lamp\nKd 0 0 0\nKe 5 4 3\nnewmtl bare\n",
        )
        .unwrap();
        let want = |name: &str, kd: Option<[f32; 3]>, ke: Option<[f32; 3]>| MtlMaterial {
            name: name.into(),
            diffuse: kd.map(Vec3::from_array),
            emission: ke.map(Vec3::from_array),
        };
        assert_eq!(
            m,
            [
                want("red", Some([0.8, 0.1, 0.1]), None),
                want("lamp", Some([0.0; 3]), Some([5.0, 4.0, 3.0])),
                want("bare", None, None),
            ]
        );
        assert!(parse_mtl_bytes(Path::new("e.mtl"), b"").unwrap().is_empty());
    }

    #[test]
    fn a_bad_line_is_an_error_naming_the_file() {
        let e = parse_mtl_bytes(Path::new("bad.mtl"), b"newmtl a\nKd 1 x 0\n").unwrap_err();
        assert!(
            e.to_string().starts_with("bad.mtl: not a valid MTL file"),
            "{e}"
        );
        // Colours of fewer than three values (tobj would panic), with CRLF
        // lines counted as tobj reads them.
        for (src, want) in [
            (
                &b"newmtl a\r\nKd 1 2\r\n"[..],
                "line 2: Kd needs 3 values, has 2",
            ),
            (
                b"# c\n\nnewmtl a\n  Ke\n",
                "line 4: Ke needs 3 values, has 0",
            ),
            (b"newmtl a\nKs 1\tx", "line 2: Ks needs 3 values, has 2"),
        ] {
            let e = parse_mtl_bytes(Path::new("c.mtl"), src).unwrap_err();
            assert_eq!(
                e.to_string(),
                format!("c.mtl: not a valid MTL file: {want}")
            );
        }
        // Three or more values are tobj's to judge (it reads the first three).
        let m = parse_mtl_bytes(Path::new("d.mtl"), b"newmtl a\nKa 1 2 3 4\n").unwrap();
        assert_eq!(m.len(), 1);
    }
}
