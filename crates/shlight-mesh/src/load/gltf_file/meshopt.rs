//! `EXT_meshopt_compression`: buffer views whose bytes are
//! meshoptimizer-compressed, decoded (with their filter) before the
//! document is validated, each into a buffer of its own that the view is
//! pointed at, so that everything after reads plain data.
//!
//! The decoders are meshoptimizer's own (the `meshopt` crate), which read
//! malformed input safely; the parameters they assert on (stride, count,
//! filter) are checked here first. All the decoded views of a file
//! together may hold at most 64 bytes a vertex of the vertex limit plus
//! 12 a triangle of the triangle limit, checked before each is decoded.

use std::path::Path;

use gltf::json;
use serde_json::Value;

use crate::{LoadOptions, MeshError};

/// The extension's name.
pub(super) const NAME: &str = "EXT_meshopt_compression";

/// Decodes every compressed buffer view of `root` from `buffers`, adding a
/// buffer per view to both.
pub(super) fn decode(
    path: &Path,
    root: &mut json::Root,
    buffers: &mut Vec<Vec<u8>>,
    options: &LoadOptions,
) -> Result<(), MeshError> {
    let mut budget = (options.max_vertices as u64)
        .saturating_mul(64)
        .saturating_add((options.max_triangles as u64).saturating_mul(12));
    for v in 0..root.buffer_views.len() {
        let Some(ext) = root.buffer_views[v]
            .extensions
            .as_mut()
            .and_then(|e| e.others.remove(NAME))
        else {
            continue;
        };
        let fail = |message: String| MeshError::Parse {
            path: path.to_path_buf(),
            message: format!("buffer view {v}: {NAME}: {message}"),
        };
        let field = |key: &str| ext.get(key).and_then(Value::as_u64);
        let (Some(buffer), Some(length), Some(stride), Some(count)) = (
            field("buffer"),
            field("byteLength"),
            field("byteStride"),
            field("count"),
        ) else {
            return Err(fail(
                "buffer, byteLength, byteStride and count are required".into(),
            ));
        };
        let offset = field("byteOffset").unwrap_or(0);
        let mode = ext.get("mode").and_then(Value::as_str).unwrap_or("");
        let filter = ext.get("filter").and_then(Value::as_str).unwrap_or("NONE");
        let source = buffers
            .get(buffer as usize)
            .ok_or_else(|| fail(format!("buffer {buffer} does not exist")))?;
        let encoded = offset
            .checked_add(length)
            .filter(|&end| end <= source.len() as u64)
            .map(|end| &source[offset as usize..end as usize])
            .ok_or_else(|| {
                fail(format!(
                    "bytes {offset} + {length} reach past the end of buffer {buffer} ({} bytes)",
                    source.len()
                ))
            })?;
        let size = count
            .checked_mul(stride)
            .filter(|&n| n <= budget)
            .ok_or_else(|| {
                fail(format!(
                    "{count} elements of {stride} bytes decode to more than the mesh limits allow ({budget} bytes left)"
                ))
            })?;
        budget -= size;
        let (count, stride) = (count as usize, stride as usize);
        let words = match mode {
            "ATTRIBUTES" => {
                if stride == 0 || stride % 4 != 0 || stride > 256 {
                    return Err(fail(format!(
                        "an ATTRIBUTES stride of {stride} bytes (a multiple of 4 up to 256)"
                    )));
                }
                let mut out = vec![0u32; count * stride / 4];
                // SAFETY: `out` holds `count * stride` bytes, the decoder
                // writes at most that and reads `encoded` within its length.
                let rc = unsafe {
                    meshopt::ffi::meshopt_decodeVertexBuffer(
                        out.as_mut_ptr().cast(),
                        count,
                        stride,
                        encoded.as_ptr(),
                        encoded.len(),
                    )
                };
                if rc != 0 {
                    return Err(fail(format!("the vertex data does not decode (code {rc})")));
                }
                filtered(&mut out, count, stride, filter).map_err(fail)?;
                out
            }
            "TRIANGLES" | "INDICES" => {
                if stride != 2 && stride != 4 {
                    return Err(fail(format!("an index stride of {stride} bytes (2 or 4)")));
                }
                if mode == "TRIANGLES" && count % 3 != 0 {
                    return Err(fail(format!("{count} TRIANGLES indices (a multiple of 3)")));
                }
                if filter != "NONE" {
                    return Err(fail(format!("the filter {filter} on indices")));
                }
                let mut out = vec![0u32; (count * stride).div_ceil(4)];
                let decoder = if mode == "TRIANGLES" {
                    meshopt::ffi::meshopt_decodeIndexBuffer
                } else {
                    meshopt::ffi::meshopt_decodeIndexSequence
                };
                // SAFETY: as above, `out` holds at least `count * stride`
                // bytes, 4-byte aligned.
                let rc = unsafe {
                    decoder(
                        out.as_mut_ptr().cast(),
                        count,
                        stride,
                        encoded.as_ptr(),
                        encoded.len(),
                    )
                };
                if rc != 0 {
                    return Err(fail(format!("the index data does not decode (code {rc})")));
                }
                out
            }
            other => return Err(fail(format!("an unknown mode \"{other}\""))),
        };
        let mut bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
        bytes.truncate(count * stride);
        let decoded_length = bytes.len() as u64;
        let new_buffer: json::Buffer =
            serde_json::from_value(serde_json::json!({"byteLength": bytes.len()}))
                .map_err(|e| fail(e.to_string()))?;
        root.buffers.push(new_buffer);
        buffers.push(bytes);
        let view = &mut root.buffer_views[v];
        view.buffer = json::Index::new((root.buffers.len() - 1) as u32);
        view.byte_offset = None;
        view.byte_length = decoded_length.into();
    }
    Ok(())
}

/// Applies the view's filter to its decoded elements in place.
fn filtered(out: &mut [u32], count: usize, stride: usize, filter: &str) -> Result<(), String> {
    let run = |f: unsafe extern "C" fn(*mut std::os::raw::c_void, usize, usize),
               out: &mut [u32]| {
        // SAFETY: `out` holds `count * stride` bytes, 4-byte aligned; the
        // filter rewrites them in place.
        unsafe { f(out.as_mut_ptr().cast(), count, stride) }
    };
    match (filter, stride) {
        ("NONE", _) => {}
        ("OCTAHEDRAL", 4 | 8) => run(meshopt::ffi::meshopt_decodeFilterOct, out),
        ("QUATERNION", 8) => run(meshopt::ffi::meshopt_decodeFilterQuat, out),
        ("EXPONENTIAL", _) => run(meshopt::ffi::meshopt_decodeFilterExp, out),
        ("COLOR", 4 | 8) => run(meshopt::ffi::meshopt_decodeFilterColor, out),
        (f, s) => return Err(format!("the filter {f} with a stride of {s} bytes")),
    }
    Ok(())
}
