//! Stanford PLY, ASCII and binary little-endian, written by hand: the
//! format is small, and the crates for it are either unmaintained or read
//! every element into dynamic maps.
//!
//! Read: the `vertex` element's `x y z` (any numeric type), optional
//! `nx ny nz` and `red green blue` (integer colours are 8-bit sRGB, decoded
//! to linear; float colours are taken as linear), and the `face` element's
//! `vertex_indices` (or `vertex_index`) list; polygons are fanned from their
//! first corner (`a b c d` gives `a b c`, `a c d`). Other elements and
//! properties are skipped. Vertices keep the file's order; triangles follow
//! the faces' order. Big-endian binary files are refused.

use std::path::Path;

use glam::Vec3;

use crate::{LoadOptions, Mesh, MeshError};

#[derive(Clone, Copy, Debug, PartialEq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(name: &str) -> Option<Self> {
        Some(match name {
            "char" | "int8" => Self::I8,
            "uchar" | "uint8" => Self::U8,
            "short" | "int16" => Self::I16,
            "ushort" | "uint16" => Self::U16,
            "int" | "int32" => Self::I32,
            "uint" | "uint32" => Self::U32,
            "float" | "float32" => Self::F32,
            "double" | "float64" => Self::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Self::I8 | Self::U8 => 1,
            Self::I16 | Self::U16 => 2,
            Self::I32 | Self::U32 | Self::F32 => 4,
            Self::F64 => 8,
        }
    }

    fn is_integer(self) -> bool {
        !matches!(self, Self::F32 | Self::F64)
    }

    /// Reads one little-endian value from the front of `b`.
    fn read_le(self, b: &[u8]) -> f64 {
        match self {
            Self::I8 => f64::from(b[0] as i8),
            Self::U8 => f64::from(b[0]),
            Self::I16 => f64::from(i16::from_le_bytes([b[0], b[1]])),
            Self::U16 => f64::from(u16::from_le_bytes([b[0], b[1]])),
            Self::I32 => f64::from(i32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Self::U32 => f64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Self::F32 => f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Self::F64 => f64::from_le_bytes(b[..8].try_into().expect("8 bytes")),
        }
    }
}

#[derive(Debug)]
enum Property {
    Scalar {
        name: String,
        ty: Scalar,
    },
    List {
        name: String,
        count: Scalar,
        item: Scalar,
    },
}

impl Property {
    fn name(&self) -> &str {
        match self {
            Self::Scalar { name, .. } | Self::List { name, .. } => name,
        }
    }
}

#[derive(Debug)]
struct Element {
    name: String,
    count: usize,
    properties: Vec<Property>,
}

/// Where each value of one element comes from: a property holds either a
/// scalar or a list.
enum Value {
    Scalar(f64),
    List(Vec<f64>),
}

/// Reads `bytes` as a PLY file; `path` names it in errors.
pub(crate) fn read(path: &Path, bytes: &[u8], options: &LoadOptions) -> Result<Mesh, MeshError> {
    let parse = |message: String| MeshError::Parse {
        path: path.to_path_buf(),
        message,
    };
    let end = find(bytes, b"end_header")
        .ok_or_else(|| parse("not a PLY file (no \"end_header\" line)".into()))?;
    let mut body = end + b"end_header".len();
    // The header ends with "\n" (or "\r\n").
    while body < bytes.len() && bytes[body] != b'\n' {
        body += 1;
    }
    body += 1;
    let header = std::str::from_utf8(&bytes[..end])
        .map_err(|_| parse("the PLY header is not text".into()))?;
    let mut lines = header.lines().map(str::trim);
    if lines.next() != Some("ply") {
        return Err(parse(
            "not a PLY file (the first line is not \"ply\")".into(),
        ));
    }
    let mut binary = None;
    let mut elements: Vec<Element> = Vec::new();
    for (n, line) in lines.enumerate() {
        let line_no = n + 2;
        let words: Vec<&str> = line.split_whitespace().collect();
        match words.as_slice() {
            [] | ["comment", ..] | ["obj_info", ..] => {}
            ["format", "ascii", _] => binary = Some(false),
            ["format", "binary_little_endian", _] => binary = Some(true),
            ["format", other, ..] => {
                return Err(parse(format!(
                    "PLY format \"{other}\" is not supported (ascii and binary_little_endian are)"
                )));
            }
            ["element", name, count] => elements.push(Element {
                name: (*name).to_string(),
                count: count.parse().map_err(|_| {
                    parse(format!(
                        "header line {line_no}: bad element count \"{count}\""
                    ))
                })?,
                properties: Vec::new(),
            }),
            ["property", rest @ ..] => {
                let element = elements.last_mut().ok_or_else(|| {
                    parse(format!(
                        "header line {line_no}: a property before any element"
                    ))
                })?;
                let ty = |s: &str| {
                    Scalar::parse(s).ok_or_else(|| {
                        parse(format!(
                            "header line {line_no}: unknown property type \"{s}\""
                        ))
                    })
                };
                element.properties.push(match rest {
                    ["list", count, item, name] => Property::List {
                        name: (*name).to_string(),
                        count: ty(count)?,
                        item: ty(item)?,
                    },
                    [t, name] => Property::Scalar {
                        name: (*name).to_string(),
                        ty: ty(t)?,
                    },
                    _ => {
                        return Err(parse(format!(
                            "header line {line_no}: bad property \"{line}\""
                        )));
                    }
                });
            }
            _ => {
                return Err(parse(format!(
                    "header line {line_no}: cannot read \"{line}\""
                )));
            }
        }
    }
    let binary = binary.ok_or_else(|| parse("the PLY header has no \"format\" line".into()))?;

    let mut reader: Box<dyn ValueReader> = if binary {
        Box::new(Binary {
            bytes: &bytes[body.min(bytes.len())..],
            at: 0,
        })
    } else {
        let text = std::str::from_utf8(&bytes[body.min(bytes.len())..])
            .map_err(|_| parse("the PLY body is not text".into()))?;
        Box::new(Ascii {
            words: text.split_ascii_whitespace(),
            failure: None,
        })
    };

    let (mut positions, mut normals, mut colors, mut triangles) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let mut has_normals = false;
    let mut has_colors = false;
    let mut vertex_count = None;
    for element in &elements {
        let index = |name: &str| element.properties.iter().position(|p| p.name() == name);
        let is_vertex = element.name == "vertex";
        let is_face = element.name == "face";
        let xyz = [index("x"), index("y"), index("z")];
        let nxyz = [index("nx"), index("ny"), index("nz")];
        let rgb = [index("red"), index("green"), index("blue")];
        let list = index("vertex_indices").or_else(|| index("vertex_index"));
        if element.properties.is_empty() {
            // Its rows hold nothing: there is nothing to read, whatever
            // the count says.
            continue;
        }
        if is_vertex {
            options.check_vertices(path, element.count)?;
            if xyz.iter().any(Option::is_none) {
                return Err(parse("the vertex element lacks x, y or z".into()));
            }
            has_normals = nxyz.iter().all(Option::is_some);
            has_colors = rgb.iter().all(Option::is_some);
            vertex_count = Some(element.count);
        }
        if is_face && list.is_none() {
            return Err(parse("the face element has no vertex_indices list".into()));
        }
        if is_face {
            // Every face makes at least one triangle.
            options.check_triangles(path, element.count)?;
        }
        let color_scale = rgb[0]
            .and_then(|i| match element.properties[i] {
                Property::Scalar { ty, .. } if ty.is_integer() => Some(ty),
                _ => None,
            })
            .map(|ty| match ty {
                Scalar::U16 => 65535.0,
                _ => 255.0,
            });
        let mut values = Vec::with_capacity(element.properties.len());
        for row in 0..element.count {
            values.clear();
            for p in &element.properties {
                let v = match *p {
                    Property::Scalar { ty, .. } => Value::Scalar(reader.next(ty)),
                    Property::List { count, item, .. } => {
                        let n = reader.next(count);
                        if !(0.0..=1e6).contains(&n) {
                            return Err(parse(format!(
                                "{} {row}: bad list length {n}",
                                element.name
                            )));
                        }
                        Value::List((0..n as usize).map(|_| reader.next(item)).collect())
                    }
                };
                values.push(v);
            }
            if let Some(e) = reader.error() {
                return Err(parse(format!("{} {row}: {e}", element.name)));
            }
            let scalar = |i: Option<usize>| match i.map(|i| &values[i]) {
                Some(Value::Scalar(v)) => *v as f32,
                _ => 0.0,
            };
            if is_vertex {
                positions.push(Vec3::from_array(xyz.map(scalar)));
                if has_normals {
                    normals.push(Vec3::from_array(nxyz.map(scalar)));
                }
                if has_colors {
                    let c = rgb.map(scalar);
                    colors.push(Vec3::from_array(match color_scale {
                        Some(s) => c.map(|v| shlight_io::srgb_to_linear(v / s)),
                        None => c,
                    }));
                }
            } else if is_face {
                let Some(Value::List(corners)) = list.map(|i| &values[i]) else {
                    return Err(parse(format!("face {row}: vertex_indices is not a list")));
                };
                if corners.len() < 3 {
                    return Err(parse(format!("face {row} has {} corners", corners.len())));
                }
                let idx = |v: f64| {
                    if v >= 0.0 && v <= f64::from(u32::MAX) && v.fract() == 0.0 {
                        Ok(v as u32)
                    } else {
                        Err(parse(format!("face {row}: bad vertex index {v}")))
                    }
                };
                let first = idx(corners[0])?;
                for w in corners[1..].windows(2) {
                    triangles.push([first, idx(w[0])?, idx(w[1])?]);
                }
                options.check_triangles(path, triangles.len())?;
            }
        }
    }
    if vertex_count.is_none() {
        return Err(parse("the PLY file has no vertex element".into()));
    }
    Mesh::new(
        path,
        positions,
        triangles,
        has_normals.then_some(normals),
        has_colors.then_some(colors),
    )
}

fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}

/// The body's values in order; a failure is latched and reported once per row.
trait ValueReader {
    fn next(&mut self, ty: Scalar) -> f64;
    fn error(&mut self) -> Option<String>;
}

struct Binary<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl ValueReader for Binary<'_> {
    fn next(&mut self, ty: Scalar) -> f64 {
        let n = ty.size();
        match self.bytes.get(self.at..self.at + n) {
            Some(b) => {
                self.at += n;
                ty.read_le(b)
            }
            None => {
                self.at = usize::MAX / 2;
                0.0
            }
        }
    }

    fn error(&mut self) -> Option<String> {
        (self.at > self.bytes.len()).then(|| "the file ends early (truncated binary data)".into())
    }
}

struct Ascii<'a> {
    words: std::str::SplitAsciiWhitespace<'a>,
    failure: Option<String>,
}

impl ValueReader for Ascii<'_> {
    fn next(&mut self, _ty: Scalar) -> f64 {
        match self.words.next() {
            Some(w) => w.parse().unwrap_or_else(|_| {
                self.failure
                    .get_or_insert_with(|| format!("\"{w}\" is not a number"));
                0.0
            }),
            None => {
                self.failure
                    .get_or_insert_with(|| "the file ends early".into());
                0.0
            }
        }
    }

    fn error(&mut self) -> Option<String> {
        self.failure.take()
    }
}
