//! Reading one layer of an OpenEXR file into an [`Image`].
//!
//! Works at the block level of the `exr` crate: only the chosen part's
//! blocks of the largest level are read, each block's DWA sizes are checked
//! ([`inspect::check_dwa_block`]), and blocks are decompressed on scoped
//! threads, each behind `catch_unwind`, so that a decoder panic on a damaged
//! file becomes an error instead of aborting the process (a panic inside
//! `exr`'s own rayon pool would abort).

use std::collections::HashSet;
use std::io::Cursor;
use std::panic::{self, AssertUnwindSafe};
use std::sync::mpsc;

use exr::block::UncompressedBlock;
use exr::block::chunk::Chunk;
use exr::block::reader::ChunksReader;
use exr::math::Vec2;
use exr::meta::MetaData;
use exr::meta::attribute::SampleType;
use exr::prelude::f16;

use super::inspect;
use super::layers::{self, Colour};
use crate::panic_message::panic_message;
use crate::{Image, IoErrorKind, ReadOptions};

/// Decodes an OpenEXR file held in `bytes`.
pub(crate) fn decode(bytes: &[u8], options: &ReadOptions) -> Result<Image, IoErrorKind> {
    decode_layer(bytes, options).map_err(|kind| match kind {
        // `exr` reports data cut short as invalid data; the chunk table
        // tells whether the file really ends early.
        IoErrorKind::Corrupt(_) if inspect::ends_early(bytes) => IoErrorKind::Truncated,
        // `exr` says "unknown compression method"; name it.
        IoErrorKind::Unsupported(_) if inspect::unknown_compression(bytes).is_some() => {
            let name = inspect::unknown_compression(bytes).expect("checked");
            IoErrorKind::Unsupported(format!(
                "OpenEXR compression {name}, which this build cannot decode (it reads NONE, \
                 RLE, ZIPS, ZIP, PIZ, PXR24, B44, B44A, DWAA and DWAB)"
            ))
        }
        other => other,
    })
}

fn decode_layer(bytes: &[u8], options: &ReadOptions) -> Result<Image, IoErrorKind> {
    let reader = exr::block::read(Cursor::new(bytes), false).map_err(map_error)?;
    let chosen = layers::choose(reader.headers(), options.layer.as_deref())?;
    let header = reader.headers()[chosen.part].clone();
    if header.deep {
        return Err(IoErrorKind::Unsupported(
            "OpenEXR deep data (only flat images are read)".into(),
        ));
    }

    // Sizes from the header, before any pixel memory is allocated.
    let display = header.shared_attributes.display_window;
    check_size(display.size.x(), display.size.y(), options.max_pixels)?;
    let (data_width, data_height) = (header.layer_size.x(), header.layer_size.y());
    check_size(data_width, data_height, options.max_pixels)?;
    inspect::check_block_size(&header, options.max_pixels)?;

    let part = chosen.part;
    let reader = reader
        .filter_chunks(false, |_, tile, block| {
            block.layer == part && tile.level_index == Vec2(0, 0)
        })
        .map_err(map_error)?;
    let meta = reader.meta_data().clone();
    let mut compressed = Vec::with_capacity(reader.len());
    for chunk in reader {
        let chunk = chunk.map_err(map_error)?;
        inspect::check_dwa_block(&chunk, &header)?;
        compressed.push(chunk);
    }
    let data = decompress(compressed, &meta, part, chosen.colour)?;

    // Place the data window in the display window.
    let origin = header.own_attributes.layer_position;
    let (width, height) = (display.size.x(), display.size.y());
    let dx = i64::from(origin.x()) - i64::from(display.position.x());
    let dy = i64::from(origin.y()) - i64::from(display.position.y());
    if dx == 0 && dy == 0 && (data_width, data_height) == (width, height) {
        return Ok(Image::new(width, height, data).expect("size checked"));
    }
    Ok(Image::from_fn(width, height, |x, y| {
        let sx = x as i64 - dx;
        let sy = y as i64 - dy;
        if (0..data_width as i64).contains(&sx) && (0..data_height as i64).contains(&sy) {
            data[sy as usize * data_width + sx as usize]
        } else {
            [0.0; 3]
        }
    }))
}

/// A decompressed block, converted to RGB: its rectangle in the data
/// window and its pixels, row-major.
struct RgbBlock {
    x: usize,
    y: usize,
    width: usize,
    height: usize,
    pixels: Vec<[f32; 3]>,
}

/// Decompresses `chunks` (all blocks of level 0 of `part`) on all cores and
/// assembles the data window, row-major.
fn decompress(
    chunks: Vec<Chunk>,
    meta: &MetaData,
    part: usize,
    colour: Colour,
) -> Result<Vec<[f32; 3]>, IoErrorKind> {
    let header = &meta.headers[part];
    let (width, height) = (header.layer_size.x(), header.layer_size.y());
    let mut data = vec![[0.0_f32; 3]; width * height];

    let threads = std::thread::available_parallelism()
        .map_or(1, usize::from)
        .min(chunks.len())
        .max(1);
    let mut buckets: Vec<Vec<Chunk>> = (0..threads).map(|_| Vec::new()).collect();
    for (i, chunk) in chunks.into_iter().enumerate() {
        buckets[i % threads].push(chunk);
    }

    let mut seen = HashSet::new();
    let mut covered = 0;
    let (send, receive) = mpsc::channel();
    std::thread::scope(|scope| {
        for bucket in buckets {
            let send = send.clone();
            scope.spawn(move || {
                for chunk in bucket {
                    let block = decode_block(chunk, meta, part, colour);
                    let failed = block.is_err();
                    if send.send(block).is_err() || failed {
                        break;
                    }
                }
            });
        }
        drop(send);
        // Dropping the receiver on an error stops the other threads.
        for block in receive {
            let block = block?;
            if !seen.insert((block.x, block.y)) {
                return Err(IoErrorKind::Corrupt(format!(
                    "block at ({}, {}) appears twice",
                    block.x, block.y
                )));
            }
            for row in 0..block.height {
                let start = (block.y + row) * width + block.x;
                data[start..start + block.width]
                    .copy_from_slice(&block.pixels[row * block.width..(row + 1) * block.width]);
            }
            covered += block.width * block.height;
        }
        Ok(())
    })?;
    if covered != width * height {
        return Err(IoErrorKind::Corrupt(format!(
            "blocks cover {covered} of the {} pixels",
            width * height
        )));
    }
    Ok(data)
}

/// Decompresses one chunk and converts its pixels to RGB; a panic in the
/// decoder is returned as an error.
fn decode_block(
    chunk: Chunk,
    meta: &MetaData,
    part: usize,
    colour: Colour,
) -> Result<RgbBlock, IoErrorKind> {
    panic::catch_unwind(AssertUnwindSafe(|| {
        let block = UncompressedBlock::decompress_chunk(chunk, meta, false).map_err(map_error)?;
        let header = &meta.headers[part];
        let index = block.index;
        let (x, y) = (index.pixel_position.x(), index.pixel_position.y());
        let (width, height) = (index.pixel_size.x(), index.pixel_size.y());
        let inside = x + width <= header.layer_size.x() && y + height <= header.layer_size.y();
        if index.layer != part || index.level != Vec2(0, 0) || !inside {
            return Err(IoErrorKind::Corrupt(format!(
                "a block at ({x}, {y}) outside the layer"
            )));
        }
        let mut pixels = vec![[0.0_f32; 3]; width * height];
        for line in block.lines(&header.channels) {
            let at = line.location;
            let components: &[usize] = match colour {
                Colour::Rgb { r, .. } if at.channel == r => &[0],
                Colour::Rgb { g, .. } if at.channel == g => &[1],
                Colour::Rgb { b, .. } if at.channel == b => &[2],
                Colour::Grey { y } if at.channel == y => &[0, 1, 2],
                _ => continue,
            };
            let row = at.position.y() - y;
            let first = row * width + (at.position.x() - x);
            let sample_type = header.channels.list[at.channel].sample_type;
            for_each_sample(line.value, sample_type, |i, v| {
                for &c in components {
                    pixels[first + i][c] = v;
                }
            });
        }
        Ok(RgbBlock {
            x,
            y,
            width,
            height,
            pixels,
        })
    }))
    .unwrap_or_else(|payload| {
        Err(IoErrorKind::Corrupt(format!(
            "the OpenEXR decoder failed: {}",
            panic_message(payload.as_ref())
        )))
    })
}

/// Calls `f(i, value)` for each sample of a line of native-endian samples.
fn for_each_sample(bytes: &[u8], sample_type: SampleType, mut f: impl FnMut(usize, f32)) {
    match sample_type {
        SampleType::F16 => {
            for (i, b) in bytes.chunks_exact(2).enumerate() {
                f(i, f16::from_bits(u16::from_ne_bytes([b[0], b[1]])).to_f32());
            }
        }
        SampleType::F32 => {
            for (i, b) in bytes.chunks_exact(4).enumerate() {
                f(i, f32::from_ne_bytes([b[0], b[1], b[2], b[3]]));
            }
        }
        SampleType::U32 => {
            for (i, b) in bytes.chunks_exact(4).enumerate() {
                f(i, u32::from_ne_bytes([b[0], b[1], b[2], b[3]]) as f32);
            }
        }
    }
}

fn check_size(width: usize, height: usize, max_pixels: usize) -> Result<(), IoErrorKind> {
    match width.checked_mul(height) {
        Some(n) if n <= max_pixels => Ok(()),
        _ => Err(IoErrorKind::TooLarge {
            width,
            height,
            max_pixels,
        }),
    }
}

fn map_error(error: exr::error::Error) -> IoErrorKind {
    use exr::error::Error;
    match error {
        Error::NotSupported(what) => IoErrorKind::Unsupported(format!("OpenEXR {what}")),
        Error::Invalid(what) => IoErrorKind::Corrupt(format!("invalid {what}")),
        Error::Io(e) => IoErrorKind::Corrupt(e.to_string()),
        Error::Aborted => IoErrorKind::Corrupt("decoding aborted".into()),
    }
}
