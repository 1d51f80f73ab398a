//! The one reader of glTF accessors: every component type, `normalized`
//! integers (`KHR_mesh_quantization`), byte strides, matrix column
//! padding and sparse substitution, with every offset checked against
//! its buffer view and buffer before a byte is read.
//!
//! The caller gives the most elements it accepts; the accessor's count is
//! checked against it before anything is allocated (a sparse accessor
//! needs no buffer, so a small file may claim any count). Errors are
//! phrases naming the accessor; the caller adds the file and what the
//! accessor was for.

use gltf::json;
use json::accessor::{ComponentType, Type};

/// The buffers' bytes (by buffer index) and the document that lays them out.
#[derive(Clone, Copy)]
pub(crate) struct Data<'a> {
    /// The validated document.
    pub root: &'a json::Root,
    /// Each buffer's bytes (at least its `byteLength`).
    pub buffers: &'a [Vec<u8>],
}

#[derive(Debug)]
/// Floats read from an accessor: `count x components` values, element
/// after element.
pub(crate) struct Floats {
    /// Values per element (3 for a `VEC3`).
    pub components: usize,
    /// The values, integers converted as the accessor says (`normalized`
    /// ones to `[0, 1]` or `[-1, 1]`, the others to their value).
    pub values: Vec<f32>,
}

impl Floats {
    /// The elements, `N` values each (`N` must be `components`).
    pub fn elements<const N: usize>(&self) -> impl Iterator<Item = [f32; N]> + '_ {
        self.values
            .chunks_exact(self.components)
            .map(|c| std::array::from_fn(|i| c[i]))
    }
}

/// The accessor `index`'s element count, for the caller's limit checks.
pub(super) fn count(data: Data, index: usize) -> Result<usize, String> {
    let accessor = data
        .root
        .accessors
        .get(index)
        .ok_or_else(|| format!("accessor {index} does not exist"))?;
    usize::try_from(accessor.count.0).map_err(|_| format!("accessor {index} has too many elements"))
}

/// Accessor `index`'s component type and whether it is normalized, in
/// glTF's words (`"normalized UNSIGNED_BYTE"`).
pub(super) fn component(data: Data, index: usize) -> Result<(ComponentType, bool, String), String> {
    let (accessor, component, _) = header(
        data,
        index,
        &[
            Type::Scalar,
            Type::Vec2,
            Type::Vec3,
            Type::Vec4,
            Type::Mat2,
            Type::Mat3,
            Type::Mat4,
        ],
    )?;
    let normalized = accessor.normalized && component != ComponentType::F32;
    Ok((component, normalized, component_name(component, normalized)))
}

/// Reads accessor `index` as floats: its type must be one of `types`, and
/// it may hold at most `max_count` elements.
pub(crate) fn read_floats(
    data: Data,
    index: usize,
    types: &[Type],
    max_count: usize,
) -> Result<Floats, String> {
    let (accessor, component, ty) = header(data, index, types)?;
    let normalized = accessor.normalized && component != ComponentType::F32;
    if normalized && component == ComponentType::U32 {
        return Err(format!(
            "accessor {index} is normalized UNSIGNED_INT, which glTF does not allow"
        ));
    }
    let decode = move |b: &[u8]| -> f32 {
        match (component, normalized) {
            (ComponentType::F32, _) => f32::from_le_bytes([b[0], b[1], b[2], b[3]]),
            (ComponentType::I8, false) => f32::from(b[0] as i8),
            (ComponentType::I8, true) => (f32::from(b[0] as i8) / 127.0).max(-1.0),
            (ComponentType::U8, false) => f32::from(b[0]),
            (ComponentType::U8, true) => f32::from(b[0]) / 255.0,
            (ComponentType::I16, false) => f32::from(i16::from_le_bytes([b[0], b[1]])),
            (ComponentType::I16, true) => {
                (f32::from(i16::from_le_bytes([b[0], b[1]])) / 32767.0).max(-1.0)
            }
            (ComponentType::U16, false) => f32::from(u16::from_le_bytes([b[0], b[1]])),
            (ComponentType::U16, true) => f32::from(u16::from_le_bytes([b[0], b[1]])) / 65535.0,
            (ComponentType::U32, _) => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f32,
        }
    };
    let values = walk(data, index, accessor, component, ty, max_count, decode)?;
    Ok(Floats {
        components: ty.multiplicity(),
        values,
    })
}

/// Reads accessor `index` as unsigned integers (a primitive's indices):
/// a `SCALAR` of `UNSIGNED_BYTE`, `UNSIGNED_SHORT` or `UNSIGNED_INT`, not
/// normalized, of at most `max_count` elements.
pub(super) fn read_indices(data: Data, index: usize, max_count: usize) -> Result<Vec<u32>, String> {
    let (accessor, component, ty) = header(data, index, &[Type::Scalar])?;
    if accessor.normalized
        || !matches!(
            component,
            ComponentType::U8 | ComponentType::U16 | ComponentType::U32
        )
    {
        return Err(format!(
            "accessor {index} holds indices as {}, not unsigned integers",
            component_name(component, accessor.normalized)
        ));
    }
    walk(
        data,
        index,
        accessor,
        component,
        ty,
        max_count,
        unsigned(component),
    )
}

/// The decoder of one unsigned integer component.
fn unsigned(component: ComponentType) -> impl Fn(&[u8]) -> u32 + Copy {
    move |b: &[u8]| match component {
        ComponentType::U8 => u32::from(b[0]),
        ComponentType::U16 => u32::from(u16::from_le_bytes([b[0], b[1]])),
        _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
    }
}

fn component_name(component: ComponentType, normalized: bool) -> String {
    let name = match component {
        ComponentType::I8 => "BYTE",
        ComponentType::U8 => "UNSIGNED_BYTE",
        ComponentType::I16 => "SHORT",
        ComponentType::U16 => "UNSIGNED_SHORT",
        ComponentType::U32 => "UNSIGNED_INT",
        ComponentType::F32 => "FLOAT",
    };
    if normalized {
        format!("normalized {name}")
    } else {
        name.to_string()
    }
}

fn type_name(ty: Type) -> &'static str {
    match ty {
        Type::Scalar => "SCALAR",
        Type::Vec2 => "VEC2",
        Type::Vec3 => "VEC3",
        Type::Vec4 => "VEC4",
        Type::Mat2 => "MAT2",
        Type::Mat3 => "MAT3",
        Type::Mat4 => "MAT4",
    }
}

/// The accessor, its component type and its type, which must be one of
/// `types`.
fn header<'a>(
    data: Data<'a>,
    index: usize,
    types: &[Type],
) -> Result<(&'a json::Accessor, ComponentType, Type), String> {
    let accessor = data
        .root
        .accessors
        .get(index)
        .ok_or_else(|| format!("accessor {index} does not exist"))?;
    let (json::validation::Checked::Valid(component), json::validation::Checked::Valid(ty)) =
        (&accessor.component_type, &accessor.type_)
    else {
        return Err(format!("accessor {index} has an unknown type"));
    };
    if !types.contains(ty) {
        let expected: Vec<&str> = types.iter().map(|&t| type_name(t)).collect();
        return Err(format!(
            "accessor {index} is a {}, expected {}",
            type_name(*ty),
            expected.join(" or ")
        ));
    }
    Ok((accessor, component.0, *ty))
}

/// The byte layout of one element: `columns` columns of `rows`
/// components, each column starting on a multiple of 4 bytes in a
/// matrix (glTF's alignment rule, which pads `MAT2` and `MAT3` of 1- and
/// 2-byte components).
#[derive(Clone, Copy)]
struct Layout {
    rows: usize,
    columns: usize,
    component: usize,
    column_stride: usize,
}

impl Layout {
    fn new(ty: Type, component: ComponentType) -> Self {
        let size = component.size();
        let (rows, columns) = match ty {
            Type::Mat2 => (2, 2),
            Type::Mat3 => (3, 3),
            Type::Mat4 => (4, 4),
            other => (other.multiplicity(), 1),
        };
        let column_stride = if columns > 1 {
            (rows * size).next_multiple_of(4)
        } else {
            rows * size
        };
        Self {
            rows,
            columns,
            component: size,
            column_stride,
        }
    }

    /// Bytes from an element's first byte to past its last.
    fn size(self) -> usize {
        self.column_stride * (self.columns - 1) + self.rows * self.component
    }

    /// Appends the components of the element starting at `bytes[0]`.
    fn read<T>(self, bytes: &[u8], decode: &impl Fn(&[u8]) -> T, out: &mut Vec<T>) {
        for c in 0..self.columns {
            for r in 0..self.rows {
                out.push(decode(
                    &bytes[c * self.column_stride + r * self.component..],
                ));
            }
        }
    }
}

/// The bytes of buffer view `view` (checked against its buffer).
pub(super) fn view<'a>(data: Data<'a>, view: usize) -> Result<&'a [u8], String> {
    view_bytes(data, view).map(|(bytes, _)| bytes)
}

/// The bytes of buffer view `view` (checked against its buffer), with its
/// stride if it has one.
fn view_bytes<'a>(data: Data<'a>, view: usize) -> Result<(&'a [u8], Option<usize>), String> {
    let v = data
        .root
        .buffer_views
        .get(view)
        .ok_or_else(|| format!("buffer view {view} does not exist"))?;
    let buffer = data
        .buffers
        .get(v.buffer.value())
        .ok_or_else(|| format!("buffer view {view} names a missing buffer"))?;
    let start = v.byte_offset.map_or(0, |o| o.0);
    let end = start.checked_add(v.byte_length.0);
    match end {
        Some(end) if end <= buffer.len() as u64 => Ok((
            &buffer[start as usize..end as usize],
            v.byte_stride.map(|s| s.0),
        )),
        _ => Err(format!(
            "buffer view {view} (bytes {start} + {}) reaches past the end of buffer {} ({} bytes)",
            v.byte_length.0,
            v.buffer.value(),
            buffer.len()
        )),
    }
}

/// The `count` elements of `layout` from `offset` in buffer view `view`,
/// `stride` bytes apart (the view's stride, or packed).
fn elements_in_view<'a>(
    data: Data<'a>,
    view: usize,
    offset: u64,
    count: usize,
    layout: Layout,
    packed: bool,
    what: &str,
) -> Result<(&'a [u8], usize), String> {
    let (bytes, view_stride) = view_bytes(data, view)?;
    let stride = match view_stride {
        Some(s) if !packed => s,
        _ => layout.size(),
    };
    if stride < layout.size() {
        return Err(format!(
            "{what}: buffer view {view}'s stride of {stride} bytes is shorter than an element ({} bytes)",
            layout.size()
        ));
    }
    if count == 0 {
        return Ok((&[], stride));
    }
    let end = (count as u64 - 1)
        .checked_mul(stride as u64)
        .and_then(|n| n.checked_add(layout.size() as u64))
        .and_then(|n| n.checked_add(offset));
    match end {
        Some(end) if end <= bytes.len() as u64 => {
            Ok((&bytes[offset as usize..end as usize], stride))
        }
        _ => Err(format!(
            "{what}: {count} elements of {} bytes, {stride} apart from byte {offset}, do not fit in buffer view {view} ({} bytes)",
            layout.size(),
            bytes.len()
        )),
    }
}

/// The accessor's values: its buffer view's elements (zeros without
/// one), then the sparse substitutions.
fn walk<T: Copy + Default>(
    data: Data,
    index: usize,
    accessor: &json::Accessor,
    component: ComponentType,
    ty: Type,
    max_count: usize,
    decode: impl Fn(&[u8]) -> T + Copy,
) -> Result<Vec<T>, String> {
    let what = format!("accessor {index}");
    let count = usize::try_from(accessor.count.0)
        .ok()
        .filter(|&c| c <= max_count)
        .ok_or_else(|| {
            format!(
                "{what} has {} elements, more than the {max_count} accepted here",
                accessor.count.0
            )
        })?;
    let layout = Layout::new(ty, component);
    let components = ty.multiplicity();
    let mut out = Vec::with_capacity(count * components);
    match accessor.buffer_view {
        Some(view) => {
            let offset = accessor.byte_offset.map_or(0, |o| o.0);
            let (bytes, stride) =
                elements_in_view(data, view.value(), offset, count, layout, false, &what)?;
            for k in 0..count {
                layout.read(&bytes[k * stride..], &decode, &mut out);
            }
        }
        None => out.resize(count * components, T::default()),
    }
    if let Some(sparse) = &accessor.sparse {
        let n = usize::try_from(sparse.count.0)
            .ok()
            .filter(|&n| n <= count)
            .ok_or_else(|| {
                format!(
                    "{what} has {} sparse values for {count} elements",
                    sparse.count.0
                )
            })?;
        let json::validation::Checked::Valid(index_type) = &sparse.indices.component_type else {
            return Err(format!("{what}'s sparse indices have an unknown type"));
        };
        let index_type = index_type.0;
        if !matches!(
            index_type,
            ComponentType::U8 | ComponentType::U16 | ComponentType::U32
        ) {
            return Err(format!("{what}'s sparse indices are not unsigned integers"));
        }
        let index_layout = Layout::new(Type::Scalar, index_type);
        let (index_bytes, index_stride) = elements_in_view(
            data,
            sparse.indices.buffer_view.value(),
            sparse.indices.byte_offset.0,
            n,
            index_layout,
            true,
            &format!("{what}'s sparse indices"),
        )?;
        let (value_bytes, value_stride) = elements_in_view(
            data,
            sparse.values.buffer_view.value(),
            sparse.values.byte_offset.0,
            n,
            layout,
            true,
            &format!("{what}'s sparse values"),
        )?;
        let read_index = unsigned(index_type);
        let mut element = Vec::with_capacity(components);
        for k in 0..n {
            let target = read_index(&index_bytes[k * index_stride..]) as usize;
            if target >= count {
                return Err(format!(
                    "{what}'s sparse index {target} is out of range ({count} elements)"
                ));
            }
            element.clear();
            layout.read(&value_bytes[k * value_stride..], &decode, &mut element);
            out[target * components..][..components].copy_from_slice(&element);
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A document of the given accessors and views over one buffer.
    fn root(accessors: serde_json::Value, views: serde_json::Value, bytes: usize) -> json::Root {
        let doc = serde_json::json!({
            "asset": {"version": "2.0"},
            "buffers": [{"byteLength": bytes}],
            "bufferViews": views,
            "accessors": accessors,
        });
        json::Root::from_slice(&serde_json::to_vec(&doc).unwrap()).unwrap()
    }

    #[test]
    fn normalized_integers_follow_the_quantization_rules() {
        // Two SHORT VEC2 normalized elements, 8 bytes apart (stride), then
        // the same bytes as UNSIGNED_BYTE normalized.
        let mut bytes = Vec::new();
        for element in [[32767i16, -32768], [16384, 0]] {
            for v in element {
                bytes.extend(v.to_le_bytes());
            }
            bytes.extend([0xAA; 4]);
        }
        let r = root(
            serde_json::json!([
                {"bufferView": 0, "componentType": 5122, "normalized": true, "count": 2, "type": "VEC2"},
                {"bufferView": 1, "componentType": 5121, "normalized": true, "count": 2, "type": "SCALAR"},
                {"bufferView": 1, "componentType": 5121, "count": 1, "type": "SCALAR", "byteOffset": 1},
            ]),
            serde_json::json!([
                {"buffer": 0, "byteLength": 16, "byteStride": 8},
                {"buffer": 0, "byteLength": 2},
            ]),
            bytes.len(),
        );
        let buffers = [bytes];
        let data = Data {
            root: &r,
            buffers: &buffers,
        };
        let f = read_floats(data, 0, &[Type::Vec2], 10).unwrap();
        // 32767/32767, max(-32768/32767, -1), 16384/32767, 0.
        assert_eq!(f.values, [1.0, -1.0, 16384.0 / 32767.0, 0.0]);
        let f = read_floats(data, 1, &[Type::Scalar], 10).unwrap();
        // The bytes 0xFF 0x7F (32767 little-endian).
        assert_eq!(f.values, [1.0, 127.0 / 255.0]);
        let f = read_floats(data, 2, &[Type::Scalar], 10).unwrap();
        assert_eq!(f.values, [127.0]);
        assert!(
            read_floats(data, 0, &[Type::Vec3], 10)
                .unwrap_err()
                .contains("VEC2, expected VEC3")
        );
        assert!(
            read_floats(data, 0, &[Type::Vec2], 1)
                .unwrap_err()
                .contains("more than the 1")
        );
    }

    #[test]
    fn sparse_values_replace_zeros_or_the_view() {
        // Base: three u16 indices 1, 2, 3; sparse: index 2 -> 9.
        let mut bytes = Vec::new();
        for v in [1u16, 2, 3, 2, 9, 0] {
            bytes.extend(v.to_le_bytes());
        }
        let sparse = |base: Option<usize>| {
            let mut a = serde_json::json!({"componentType": 5123, "count": 3, "type": "SCALAR",
                "sparse": {"count": 1, "indices": {"bufferView": 1, "componentType": 5123},
                           "values": {"bufferView": 2}}});
            if let Some(v) = base {
                a["bufferView"] = v.into();
            }
            a
        };
        let r = root(
            serde_json::json!([sparse(Some(0)), sparse(None)]),
            serde_json::json!([
                {"buffer": 0, "byteLength": 6},
                {"buffer": 0, "byteOffset": 6, "byteLength": 2},
                {"buffer": 0, "byteOffset": 8, "byteLength": 2},
            ]),
            bytes.len(),
        );
        let buffers = [bytes];
        let data = Data {
            root: &r,
            buffers: &buffers,
        };
        assert_eq!(read_indices(data, 0, 10).unwrap(), [1, 2, 9]);
        assert_eq!(read_indices(data, 1, 10).unwrap(), [0, 0, 9]);
    }

    #[test]
    fn out_of_bounds_views_and_elements_are_errors() {
        let bytes = vec![0u8; 12];
        let r = root(
            serde_json::json!([
                {"bufferView": 0, "componentType": 5126, "count": 2, "type": "VEC3"},
                {"bufferView": 1, "componentType": 5126, "count": 1, "type": "VEC3"},
                {"bufferView": 0, "componentType": 5126, "count": 1, "type": "VEC3", "byteOffset": 4},
            ]),
            serde_json::json!([
                {"buffer": 0, "byteLength": 12},
                {"buffer": 0, "byteOffset": 8, "byteLength": 12},
            ]),
            bytes.len(),
        );
        let buffers = [bytes];
        let data = Data {
            root: &r,
            buffers: &buffers,
        };
        let e = read_floats(data, 0, &[Type::Vec3], 10).unwrap_err();
        assert!(e.contains("do not fit in buffer view 0 (12 bytes)"), "{e}");
        let e = read_floats(data, 1, &[Type::Vec3], 10).unwrap_err();
        assert!(e.contains("reaches past the end of buffer 0"), "{e}");
        assert!(read_floats(data, 2, &[Type::Vec3], 10).is_err());
    }

    #[test]
    fn matrix_columns_of_bytes_are_padded_to_four() {
        // A MAT2 of bytes: column 0 at bytes 0..2, column 1 at 4..6.
        let bytes = vec![1u8, 2, 0xEE, 0xEE, 3, 4, 0xEE, 0xEE];
        let r = root(
            serde_json::json!([{"bufferView": 0, "componentType": 5121, "count": 1, "type": "MAT2"}]),
            serde_json::json!([{"buffer": 0, "byteLength": 8}]),
            bytes.len(),
        );
        let buffers = [bytes];
        let data = Data {
            root: &r,
            buffers: &buffers,
        };
        assert_eq!(
            read_floats(data, 0, &[Type::Mat2], 1).unwrap().values,
            [1.0, 2.0, 3.0, 4.0]
        );
    }
}
