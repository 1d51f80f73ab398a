//! Decompressing one ZIP or ZIPS block of an OpenEXR file with libdeflate,
//! into buffers reused from block to block.
//!
//! OpenEXR's ZIP compression (OpenEXR's `ImfZip.cpp`) stores each block's
//! little-endian bytes as zlib data after two reversible steps: the bytes
//! are split into the even-indexed half followed by the odd-indexed half,
//! and each byte is replaced by its difference from the one before plus 128
//! (mod 256). Decompressing undoes them in the opposite order: inflate,
//! running sum (`b[i] = b[i-1] + d[i] - 128`), then interleave the halves.
//! A block whose stored size equals its raw size was stored uncompressed.
//!
//! The `exr` crate inflates with `zune-inflate`; libdeflate, which OpenEXR
//! itself uses, inflates these blocks with about half the instructions
//! (docs/benchmarks.md), and it writes into a buffer of the exact size, so
//! nothing is allocated per block.

use exr::block::chunk::{Chunk, CompressedBlock};
use exr::block::{BlockIndex, UncompressedBlock};
use exr::compression::Compression;
use exr::meta::MetaData;

use crate::IoErrorKind;

/// Whether a block of this compression is decompressed here rather than by
/// the `exr` crate.
pub(super) fn handles(compression: Compression) -> bool {
    matches!(compression, Compression::ZIP1 | Compression::ZIP16)
}

/// Per-thread buffers and inflater, reused from block to block.
pub(super) struct ZipScratch {
    inflater: libdeflater::Decompressor,
    /// The inflated bytes (halves, differences undone in place).
    inflated: Vec<u8>,
    /// The interleaved bytes, handed out as the block's data.
    data: Vec<u8>,
}

impl ZipScratch {
    pub(super) fn new() -> Self {
        Self {
            inflater: libdeflater::Decompressor::new(),
            inflated: Vec::new(),
            data: Vec::new(),
        }
    }

    /// Takes back a block's data buffer for the next block.
    pub(super) fn recycle(&mut self, block: UncompressedBlock) {
        self.data = block.data;
    }

    /// Decompresses one ZIP or ZIPS chunk of `meta` into a block of
    /// native-endian samples, as `UncompressedBlock::decompress_chunk` of
    /// the `exr` crate does (same checks of the block's position and size).
    pub(super) fn decompress(
        &mut self,
        chunk: Chunk,
        meta: &MetaData,
    ) -> Result<UncompressedBlock, IoErrorKind> {
        let corrupt = |what: String| IoErrorKind::Corrupt(what);
        let header = meta
            .headers
            .get(chunk.layer_index)
            .ok_or_else(|| corrupt("a chunk of a part that does not exist".into()))?;
        let indices = header
            .get_block_data_indices(&chunk.compressed_block)
            .map_err(|e| corrupt(e.to_string()))?;
        let bounds = header
            .get_absolute_block_pixel_coordinates(indices)
            .map_err(|e| corrupt(e.to_string()))?;
        bounds
            .validate(Some(header.layer_size))
            .and_then(|()| bounds.validate(Some(header.max_block_pixel_size())))
            .map_err(|e| corrupt(e.to_string()))?;
        let compressed = match &chunk.compressed_block {
            CompressedBlock::ScanLine(b) => &b.compressed_pixels_le,
            CompressedBlock::Tile(b) => &b.compressed_pixels_le,
            _ => {
                return Err(IoErrorKind::Unsupported(
                    "OpenEXR deep data (only flat images are read)".into(),
                ));
            }
        };
        let expected = bounds.size.area() * header.channels.bytes_per_pixel;

        // Every byte of both buffers is written below before it is read, so
        // a buffer of the right length from the block before is used as it
        // is, not cleared.
        self.data.resize(expected, 0);
        if compressed.len() == expected {
            // Larger compressed than raw: stored as it is.
            self.data.copy_from_slice(compressed);
        } else {
            self.inflated.resize(expected, 0);
            let n = self
                .inflater
                .zlib_decompress(compressed, &mut self.inflated)
                .map_err(|e| corrupt(format!("a ZIP block that does not inflate ({e})")))?;
            if n != expected {
                return Err(corrupt(format!(
                    "a ZIP block inflates to {n} bytes instead of {expected}"
                )));
            }
            undo_differences(&mut self.inflated);
            interleave(&self.inflated, &mut self.data);
        }
        #[cfg(target_endian = "big")]
        swap_to_native(&mut self.data, header, bounds);

        Ok(UncompressedBlock {
            index: BlockIndex {
                layer: chunk.layer_index,
                pixel_position: bounds
                    .position
                    .to_usize("block position")
                    .map_err(|e| corrupt(e.to_string()))?,
                level: indices.level_index,
                pixel_size: bounds.size,
            },
            data: std::mem::take(&mut self.data),
        })
    }
}

/// `b[i] = b[i-1] + b[i] - 128` (mod 256) for `i >= 1`: the running sum
/// that undoes OpenEXR's byte differences.
fn undo_differences(bytes: &mut [u8]) {
    #[cfg(target_arch = "x86_64")]
    {
        // SSE2 is part of x86-64.
        // SAFETY: the function only needs SSE2.
        unsafe { undo_differences_sse2(bytes) };
    }
    #[cfg(not(target_arch = "x86_64"))]
    undo_differences_from(bytes, 1);
}

/// [`undo_differences`] from index `start` on (`start >= 1`), a byte at a
/// time.
#[inline(always)]
fn undo_differences_from(bytes: &mut [u8], start: usize) {
    for i in start..bytes.len() {
        bytes[i] = bytes[i - 1].wrapping_add(bytes[i]).wrapping_sub(128);
    }
}

/// [`undo_differences`] sixteen bytes at a time: with `e[i] = d[i] - 128`,
/// `b[i] = b[0] + e[1] + ... + e[i]`, an inclusive prefix sum of each
/// vector by four shift-and-add steps, plus the last byte of the vector
/// before (wrapping arithmetic throughout, as the scalar loop).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "sse2")]
unsafe fn undo_differences_sse2(bytes: &mut [u8]) {
    use core::arch::x86_64::*;
    let n = bytes.len();
    if n < 2 {
        return;
    }
    // Vectors cover bytes 1.. in runs of 16; byte 0 stays as it is.
    let body = (n - 1) / 16 * 16;
    let bias = _mm_set1_epi8(-128);
    let mut carry = _mm_set1_epi8(bytes[0] as i8);
    let p = bytes.as_mut_ptr();
    // SAFETY: every load and store covers bytes 1 + i..1 + i + 16 with
    // i + 16 <= body <= n - 1, inside the slice.
    unsafe {
        let mut i = 0;
        while i < body {
            let at = p.add(1 + i).cast::<__m128i>();
            let mut v = _mm_sub_epi8(_mm_loadu_si128(at), bias);
            v = _mm_add_epi8(v, _mm_slli_si128::<1>(v));
            v = _mm_add_epi8(v, _mm_slli_si128::<2>(v));
            v = _mm_add_epi8(v, _mm_slli_si128::<4>(v));
            v = _mm_add_epi8(v, _mm_slli_si128::<8>(v));
            v = _mm_add_epi8(v, carry);
            _mm_storeu_si128(at, v);
            // The last byte, broadcast, carries into the next vector.
            let last = _mm_unpackhi_epi8(v, v);
            let last = _mm_unpackhi_epi16(last, last);
            carry = _mm_shuffle_epi32::<0xff>(last);
            i += 16;
        }
    }
    undo_differences_from(bytes, 1 + body);
}

/// `out[2i] = bytes[i]`, `out[2i + 1] = bytes[h + i]` with
/// `h = ceil(n / 2)`: the first half holds the even-indexed bytes, the
/// second the odd-indexed ones. `out.len() == bytes.len()`.
fn interleave(bytes: &[u8], out: &mut [u8]) {
    let n = bytes.len();
    debug_assert_eq!(out.len(), n);
    let (even, odd) = bytes.split_at(n.div_ceil(2));
    let mut pairs = out.chunks_exact_mut(2);
    for ((o, &a), &b) in (&mut pairs).zip(even).zip(odd) {
        o[0] = a;
        o[1] = b;
    }
    if let [last] = pairs.into_remainder() {
        *last = even[even.len() - 1];
    }
}

/// Little-endian samples to native order on big-endian machines: each
/// line of each channel is a run of samples of that channel's type.
#[cfg(target_endian = "big")]
fn swap_to_native(
    data: &mut [u8],
    header: &exr::meta::header::Header,
    bounds: exr::meta::attribute::IntegerBounds,
) {
    let mut at = 0;
    for _ in 0..bounds.size.height() {
        for channel in &header.channels.list {
            let size = channel.sample_type.bytes_per_sample();
            let len = bounds.size.width() * size;
            for sample in data[at..at + len].chunks_exact_mut(size) {
                sample.reverse();
            }
            at += len;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// OpenEXR's compression steps, written from the description in the
    /// module docs: split into even/odd halves, then differences + 128.
    fn forward(raw: &[u8]) -> Vec<u8> {
        let mut split: Vec<u8> = raw.iter().step_by(2).copied().collect();
        split.extend(raw.iter().skip(1).step_by(2));
        let mut out = split.clone();
        for i in 1..split.len() {
            out[i] = split[i].wrapping_sub(split[i - 1]).wrapping_add(128);
        }
        out
    }

    fn pseudo_random(n: usize) -> Vec<u8> {
        let mut x = 0x2545_f491_u32;
        (0..n)
            .map(|_| {
                x ^= x << 13;
                x ^= x >> 17;
                x ^= x << 5;
                (x >> 7) as u8
            })
            .collect()
    }

    #[test]
    fn undoing_both_steps_gives_the_raw_bytes_back_for_every_length() {
        // Lengths around the 16-byte vectors and their tail, odd and even.
        for n in (0..70).chain([393_216, 393_217]) {
            let raw = pseudo_random(n);
            let mut coded = forward(&raw);
            undo_differences(&mut coded);
            let mut out = vec![0; n];
            interleave(&coded, &mut out);
            assert_eq!(out, raw, "n = {n}");
        }
    }

    #[test]
    fn the_vector_running_sum_matches_the_byte_loop() {
        for n in [0, 1, 2, 16, 17, 18, 33, 1000, 4097] {
            let coded = pseudo_random(n);
            let mut vector = coded.clone();
            undo_differences(&mut vector);
            let mut scalar = coded.clone();
            if n > 1 {
                undo_differences_from(&mut scalar, 1);
            }
            assert_eq!(vector, scalar, "n = {n}");
        }
    }
}
