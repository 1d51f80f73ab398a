//! Looks at the raw structure of an OpenEXR file around the `exr` crate's
//! decoder: whether the file ends before its data (to report truncation as
//! such), whether a DWA block's sizes are possible before that block is
//! decompressed, how large a decompressed block can be, and which
//! compression a file uses that `exr` cannot name.

use std::io::Cursor;

use exr::block::chunk::{Chunk, CompressedBlock};
use exr::compression::Compression;
use exr::meta::header::Header;

use crate::IoErrorKind;

/// The most bytes one decompressed block may take, per pixel of
/// `max_pixels`: `exr` allocates a block's full size (every channel of the
/// part, not only the ones read) before decompressing some compressions
/// (PIZ, B44), whatever the compressed data holds.
const MAX_BLOCK_BYTES_PER_PIXEL: usize = 16;

/// Refuses a part whose largest decompressed block (its tile, or its scan
/// lines per block, clipped to the data window, times the bytes of all
/// its channels) exceeds [`MAX_BLOCK_BYTES_PER_PIXEL`] bytes a pixel of
/// `max_pixels`, judged from the header before any block is read.
pub(super) fn check_block_size(header: &Header, max_pixels: usize) -> Result<(), IoErrorKind> {
    let (width, height) = (header.layer_size.x(), header.layer_size.y());
    let (block_width, block_height) = match header.blocks {
        exr::meta::BlockDescription::Tiles(tiles) => (tiles.tile_size.x(), tiles.tile_size.y()),
        exr::meta::BlockDescription::ScanLines => {
            (width, header.compression.scan_lines_per_block())
        }
    };
    let pixels = block_width
        .min(width)
        .saturating_mul(block_height.min(height));
    let bytes = pixels.saturating_mul(header.channels.bytes_per_pixel);
    let limit = max_pixels.saturating_mul(MAX_BLOCK_BYTES_PER_PIXEL);
    if bytes <= limit {
        return Ok(());
    }
    Err(IoErrorKind::Unsupported(format!(
        "OpenEXR blocks of {bytes} bytes decompressed ({} channels), more than the {limit} \
         bytes the pixel limit allows ({MAX_BLOCK_BYTES_PER_PIXEL} bytes a pixel of {max_pixels})",
        header.channels.list.len()
    )))
}

/// Whether the file ends before the data it describes: inside its headers
/// or offset tables, or before the end of a chunk that the offset tables
/// point to (each chunk's size is in the chunk's own header).
pub(super) fn ends_early(bytes: &[u8]) -> bool {
    let mut cursor = Cursor::new(bytes);
    let meta = match exr::meta::MetaData::read_from_buffered(&mut cursor, false) {
        Ok(meta) => meta,
        Err(e) => return is_end_of_input(&e),
    };
    let read = |at: u64, n: usize| -> Option<&[u8]> {
        let at = usize::try_from(at).ok()?;
        bytes.get(at..at.checked_add(n)?)
    };
    let len = bytes.len() as u64;
    // The offset tables follow the headers: one little-endian u64 per chunk.
    let mut entry_at = cursor.position();
    for header in &meta.headers {
        // Before a chunk's data size: the part number (multi-part files),
        // then the tile coordinates and levels (16 bytes) or the first scan
        // line (4 bytes).
        let part = if meta.requirements.has_multiple_layers {
            4
        } else {
            0
        };
        let coordinates = match header.blocks {
            exr::meta::BlockDescription::Tiles(_) => 16,
            exr::meta::BlockDescription::ScanLines => 4,
        };
        for _ in 0..header.chunk_count {
            let Some(entry) = read(entry_at, 8) else {
                return true;
            };
            entry_at += 8;
            let chunk = u64::from_le_bytes(entry.try_into().expect("8 bytes"));
            let size_at = chunk.saturating_add(part + coordinates);
            let Some(size) = read(size_at, 4) else {
                return true;
            };
            let size = u64::from(u32::from_le_bytes(size.try_into().expect("4 bytes")));
            if size_at.saturating_add(4).saturating_add(size) > len {
                return true;
            }
        }
    }
    false
}

/// Whether `exr` met the end of its input (it reports that as an invalid
/// "reference to missing bytes").
pub(super) fn is_end_of_input(error: &exr::error::Error) -> bool {
    use exr::error::Error;
    match error {
        Error::Invalid(what) => what == "reference to missing bytes",
        Error::Io(e) => e.kind() == std::io::ErrorKind::UnexpectedEof,
        _ => false,
    }
}

/// Checks the sizes in a DWAA/DWAB block's header against the block.
///
/// A DWA block starts with eleven little-endian u64 counters (OpenEXR's
/// `DataSizesSingle`). `exr` 1.74 allocates buffers of the sizes they state
/// before decoding, so a damaged counter can request hundreds of gigabytes
/// and abort the process; this refuses such a block first. The bounds are
/// loose (no valid block comes near them): byte sizes at most the block's
/// uncompressed size (twice that for the RLE stream), compressed sizes at
/// most the chunk's size, coefficient counts at most the samples of the
/// block padded to 8x8 DCT blocks.
pub(super) fn check_dwa_block(chunk: &Chunk, header: &Header) -> Result<(), IoErrorKind> {
    if !matches!(
        header.compression,
        Compression::DWAA(_) | Compression::DWAB(_)
    ) {
        return Ok(());
    }
    let (tile, data) = match &chunk.compressed_block {
        CompressedBlock::ScanLine(block) => (
            header.get_scan_line_block_tile_coordinates(block.y_coordinate),
            &block.compressed_pixels_le,
        ),
        CompressedBlock::Tile(block) => (Ok(block.coordinates), &block.compressed_pixels_le),
        // Deep data is refused before any chunk is read.
        _ => return Ok(()),
    };
    // Blocks at impossible positions are reported by the decoder.
    let Ok(bounds) = tile.and_then(|t| header.get_absolute_block_pixel_coordinates(t)) else {
        return Ok(());
    };
    let raw_size = bounds.size.area() * header.channels.bytes_per_pixel;
    const HEADER_SIZE: usize = 11 * 8;
    if data.len() == raw_size || data.len() < HEADER_SIZE {
        // Stored uncompressed, or too short (the decoder says so).
        return Ok(());
    }
    let counter =
        |i: usize| u64::from_le_bytes(data[8 * i..8 * i + 8].try_into().expect("8 bytes"));
    let (w, h) = (bounds.size.width() as u64, bounds.size.height() as u64);
    let channels = header.channels.list.len() as u64;
    let padded_samples = w.div_ceil(8) * h.div_ceil(8) * 64 * channels;
    let raw = raw_size as u64;
    let chunk_len = data.len() as u64;
    let limits: [(usize, &str, u64); 9] = [
        (1, "unknown-channel size", raw),
        (2, "unknown-channel compressed size", chunk_len),
        (3, "AC compressed size", chunk_len),
        (4, "DC compressed size", chunk_len),
        (5, "RLE compressed size", chunk_len),
        (6, "RLE stream size", 2 * raw + 64),
        (7, "RLE raw size", raw),
        (8, "AC coefficient count", padded_samples),
        (9, "DC coefficient count", padded_samples),
    ];
    for (index, what, limit) in limits {
        let value = counter(index);
        if value > limit {
            return Err(IoErrorKind::Corrupt(format!(
                "DWA block at ({}, {}): {what} {value} is more than the possible {limit}",
                bounds.position.x(),
                bounds.position.y()
            )));
        }
    }
    Ok(())
}

/// The names of OpenEXR's compression codes, as numbered by OpenEXR 3.5
/// (`Imf::Compression`); `exr` 1.74 decodes codes 0 to 9.
const COMPRESSION_NAMES: [&str; 14] = [
    "NONE", "RLE", "ZIPS", "ZIP", "PIZ", "PXR24", "B44", "B44A", "DWAA", "DWAB", "HTJ2K256",
    "HTJ2K32", "LJ2K", "ZSTD",
];

/// The first compression code in the file's headers that `exr` cannot
/// decode (above 9), with its OpenEXR name when known, e.g.
/// `"HTJ2K256 (code 10)"`.
pub(super) fn unknown_compression(bytes: &[u8]) -> Option<String> {
    // Magic number and version, then attributes: name, type (both
    // null-terminated), a little-endian i32 size and the value. A header
    // ends with an empty name; multi-part files have several.
    // Bit 12 of the version field marks a multi-part file.
    let multi_part = bytes.get(5).is_some_and(|flags| flags & 0x10 != 0);
    let mut at = 8;
    let string = |at: &mut usize| -> Option<&[u8]> {
        let end = *at + bytes.get(*at..)?.iter().position(|&b| b == 0)?;
        let s = &bytes[*at..end];
        *at = end + 1;
        Some(s)
    };
    loop {
        let name = string(&mut at)?;
        if name.is_empty() {
            // End of a header; in a multi-part file, an empty header ends
            // the list.
            if !multi_part || bytes.get(at) == Some(&0) {
                return None;
            }
            continue;
        }
        let _type = string(&mut at)?;
        let size =
            usize::try_from(i32::from_le_bytes(bytes.get(at..at + 4)?.try_into().ok()?)).ok()?;
        at += 4;
        let value = bytes.get(at..at.checked_add(size)?)?;
        at += size;
        if name == b"compression" && value.len() == 1 && value[0] > 9 {
            let code = value[0];
            return Some(match COMPRESSION_NAMES.get(usize::from(code)) {
                Some(name) => format!("{name} (code {code})"),
                None => format!("code {code}"),
            });
        }
    }
}
