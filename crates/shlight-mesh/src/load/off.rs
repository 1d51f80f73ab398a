//! Object File Format (`.off`), written by hand (a dozen lines of grammar).
//!
//! Read: the keyword `OFF`, `COFF` (a colour after each vertex's
//! coordinates), `NOFF` (a normal after them) or `CNOFF`/`NCOFF` (normal then
//! colour), on its own line or followed by the counts; then `vertices faces
//! edges`; then one vertex per line and one face per line (`n i_1 .. i_n`,
//! 0-based, any trailing face colour ignored). `#` starts a comment. Integer
//! colours (any component above 1) are 8-bit sRGB, decoded to linear; others
//! are taken as linear; a fourth (alpha) value is ignored. Polygons are fanned
//! from their first corner. Vertices keep the file's order; triangles follow
//! the faces' order.

use std::path::Path;

use glam::Vec3;

use crate::{LoadOptions, Mesh, MeshError};

/// Reads `bytes` as an OFF file; `path` names it in errors.
pub(crate) fn read(path: &Path, bytes: &[u8], options: &LoadOptions) -> Result<Mesh, MeshError> {
    let parse = |message: String| MeshError::Parse {
        path: path.to_path_buf(),
        message,
    };
    let text =
        std::str::from_utf8(bytes).map_err(|_| parse("not an OFF file (not text)".into()))?;
    // (line number, words) of every line with content.
    let mut lines = text.lines().enumerate().filter_map(|(n, line)| {
        let content = line.split('#').next().unwrap_or("");
        let words: Vec<&str> = content.split_whitespace().collect();
        (!words.is_empty()).then_some((n + 1, words))
    });
    let (_, first) = lines
        .next()
        .ok_or_else(|| parse("not an OFF file (it is empty)".into()))?;
    let keyword = first[0];
    let (normals_given, colors_given) = match keyword {
        "OFF" => (false, false),
        "COFF" => (false, true),
        "NOFF" => (true, false),
        "CNOFF" | "NCOFF" => (true, true),
        _ => {
            return Err(parse(format!(
                "not an OFF file (it starts with \"{keyword}\", not OFF, COFF, NOFF or CNOFF)"
            )));
        }
    };
    let counts_line = if first.len() > 1 {
        (1, first[1..].to_vec())
    } else {
        lines
            .next()
            .ok_or_else(|| parse("the file ends before the counts".into()))?
    };
    let number = |line: usize, w: &str| -> Result<f64, MeshError> {
        w.parse()
            .map_err(|_| parse(format!("line {line}: \"{w}\" is not a number")))
    };
    let count = |line: usize, w: Option<&&str>| -> Result<usize, MeshError> {
        let w =
            w.ok_or_else(|| parse(format!("line {line}: expected the vertex and face counts")))?;
        w.parse()
            .map_err(|_| parse(format!("line {line}: \"{w}\" is not a count")))
    };
    let nv = count(counts_line.0, counts_line.1.first())?;
    let nf = count(counts_line.0, counts_line.1.get(1))?;
    options.check_vertices(path, nv)?;
    options.check_triangles(path, nf)?;

    let need = 3 + if normals_given { 3 } else { 0 } + if colors_given { 3 } else { 0 };
    // A vertex line takes at least 6 bytes ("0 0 0\n"): reserve no more
    // than the file can hold, whatever its counts say.
    let (mut positions, mut normals, mut raw_colors) = (
        Vec::with_capacity(nv.min(text.len() / 6)),
        Vec::new(),
        Vec::new(),
    );
    for v in 0..nv {
        let (line, words) = lines
            .next()
            .ok_or_else(|| parse(format!("the file ends at vertex {v} of {nv}")))?;
        if words.len() < need {
            return Err(parse(format!(
                "line {line}: vertex {v} has {} numbers, {keyword} needs {need}",
                words.len()
            )));
        }
        let mut at = 0;
        let mut vec3 = || -> Result<Vec3, MeshError> {
            let mut c = [0.0f32; 3];
            for x in &mut c {
                *x = number(line, words[at])? as f32;
                at += 1;
            }
            Ok(Vec3::from_array(c))
        };
        positions.push(vec3()?);
        if normals_given {
            normals.push(vec3()?);
        }
        if colors_given {
            raw_colors.push(vec3()?);
        }
    }
    let mut triangles = Vec::new();
    for f in 0..nf {
        let (line, words) = lines
            .next()
            .ok_or_else(|| parse(format!("the file ends at face {f} of {nf}")))?;
        let n = count(line, words.first())?;
        if n < 3 || words.len() - 1 < n {
            return Err(parse(format!(
                "line {line}: face {f} has {n} corners and lists {} (a face needs at least 3)",
                words.len() - 1
            )));
        }
        let corners = words[1..=n]
            .iter()
            .map(|w| {
                w.parse::<u32>()
                    .map_err(|_| parse(format!("line {line}: \"{w}\" is not a vertex index")))
            })
            .collect::<Result<Vec<u32>, _>>()?;
        for w in corners[1..].windows(2) {
            triangles.push([corners[0], w[0], w[1]]);
        }
        options.check_triangles(path, triangles.len())?;
    }
    let colors = colors_given.then(|| {
        let integer = raw_colors.iter().any(|c| c.max_element() > 1.0);
        raw_colors
            .into_iter()
            .map(|c| {
                if integer {
                    c.to_array()
                        .map(|v| shlight_io::srgb_to_linear(v / 255.0))
                        .into()
                } else {
                    c
                }
            })
            .collect()
    });
    Mesh::new(
        path,
        positions,
        triangles,
        normals_given.then_some(normals),
        colors,
    )
}
