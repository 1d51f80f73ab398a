//! Reading one layer of an OpenEXR file into an [`Image`].
//!
//! Works at the block level of the `exr` crate: only the chosen part's
//! blocks of the largest level are read, each block's DWA sizes are checked
//! ([`inspect::check_dwa_block`]), and blocks are decompressed on scoped
//! threads (ZIP and ZIPS by `zip_block.rs`, the others by `exr`; scan-line
//! blocks as they are read, each straight into its band of rows), each
//! behind `catch_unwind`, so that a decoder panic on a damaged
//! file becomes an error instead of aborting the process (a panic inside
//! `exr`'s own rayon pool would abort).

use std::collections::HashSet;
use std::io::Cursor;
use std::panic::{self, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Mutex, mpsc};

use exr::block::UncompressedBlock;
use exr::block::chunk::Chunk;
use exr::block::reader::ChunksReader;
use exr::math::Vec2;
use exr::meta::attribute::SampleType;
use exr::meta::{BlockDescription, MetaData};
use exr::prelude::f16;

use super::inspect;
use super::layers::{self, Colour};
use super::zip_block::{self, ZipScratch};
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
    let count = reader.len();
    let compressed = reader.map(|chunk| {
        let chunk = chunk.map_err(map_error)?;
        inspect::check_dwa_block(&chunk, &header)?;
        Ok(chunk)
    });
    let data = decompress(compressed, count, &meta, part, chosen.colour)?;

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
pub(super) struct RgbBlock {
    pub(super) x: usize,
    pub(super) y: usize,
    pub(super) width: usize,
    pub(super) height: usize,
    pub(super) pixels: Vec<[f32; 3]>,
}

/// The threads that decompress, and `chunks` dealt out to them in turn.
fn buckets(chunks: Vec<Chunk>) -> Vec<Vec<Chunk>> {
    let threads = std::thread::available_parallelism()
        .map_or(1, usize::from)
        .min(chunks.len())
        .max(1);
    let mut buckets: Vec<Vec<Chunk>> = (0..threads).map(|_| Vec::new()).collect();
    for (i, chunk) in chunks.into_iter().enumerate() {
        buckets[i % threads].push(chunk);
    }
    buckets
}

/// Decompresses `chunks` (all `count` blocks of level 0 of `part`, as they
/// are read) on all cores and assembles the data window, row-major:
/// scan-line blocks straight into their rows ([`decompress_scan_lines`]),
/// tiles through [`RgbBlock`]s once all are read.
fn decompress(
    chunks: impl Iterator<Item = Result<Chunk, IoErrorKind>>,
    count: usize,
    meta: &MetaData,
    part: usize,
    colour: Colour,
) -> Result<Vec<[f32; 3]>, IoErrorKind> {
    let header = &meta.headers[part];
    if header.blocks == BlockDescription::ScanLines {
        return decompress_scan_lines(chunks, count, meta, part, colour);
    }
    let chunks = chunks.collect::<Result<Vec<_>, _>>()?;
    let (width, height) = (header.layer_size.x(), header.layer_size.y());
    let mut data = vec![[0.0_f32; 3]; width * height];

    let mut seen = HashSet::new();
    let mut covered = 0;
    let (send, receive) = mpsc::channel();
    let zip = zip_block::handles(header.compression);
    std::thread::scope(|scope| {
        for bucket in buckets(chunks) {
            let send = send.clone();
            scope.spawn(move || {
                let mut scratch = zip.then(ZipScratch::new);
                for chunk in bucket {
                    let block = decode_block(chunk, meta, part, colour, scratch.as_mut());
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
    check_covered(covered, width * height)?;
    Ok(data)
}

pub(super) fn check_covered(covered: usize, pixels: usize) -> Result<(), IoErrorKind> {
    if covered != pixels {
        return Err(IoErrorKind::Corrupt(format!(
            "blocks cover {covered} of the {pixels} pixels"
        )));
    }
    Ok(())
}

/// [`decompress`] of a scan-line part: the data window is cut into bands of
/// the compression's lines per block, and each thread converts its blocks
/// straight into their band (taken once: a second block for a band is an
/// error), so no block is copied. Blocks are dealt out to the threads in
/// turn as they are read, so decompression starts with the first block.
fn decompress_scan_lines(
    chunks: impl Iterator<Item = Result<Chunk, IoErrorKind>>,
    count: usize,
    meta: &MetaData,
    part: usize,
    colour: Colour,
) -> Result<Vec<[f32; 3]>, IoErrorKind> {
    let header = &meta.headers[part];
    let (width, height) = (header.layer_size.x(), header.layer_size.y());
    let lines = header.compression.scan_lines_per_block();
    let mut data = vec![[0.0_f32; 3]; width * height];
    let zip = zip_block::handles(header.compression);
    let covered = {
        let bands: Vec<Mutex<Option<&mut [[f32; 3]]>>> = data
            .chunks_mut((width * lines).max(1))
            .map(|band| Mutex::new(Some(band)))
            .collect();
        let geometry = BandGeometry {
            width,
            height,
            lines,
            bands: &bands,
        };
        decode_on_threads(chunks, count, zip, |chunk, scratch| {
            decode_scan_block(chunk, meta, part, colour, scratch, &geometry)
        })?
    };
    check_covered(covered, width * height)?;
    Ok(data)
}

/// Compressed blocks that may wait for each decoding thread.
const QUEUE_PER_THREAD: usize = 2;

/// Deals `chunks` out to one thread per core in turn, through bounded
/// queues, and runs `decode` on each; returns the sum of what `decode`
/// returned. The first error (reading before decoding) stops every thread.
pub(super) fn decode_on_threads(
    chunks: impl Iterator<Item = Result<Chunk, IoErrorKind>>,
    count: usize,
    zip: bool,
    decode: impl Fn(Chunk, Option<&mut ZipScratch>) -> Result<usize, IoErrorKind> + Sync,
) -> Result<usize, IoErrorKind> {
    let threads = std::thread::available_parallelism()
        .map_or(1, usize::from)
        .min(count)
        .max(1);
    let failed = AtomicBool::new(false);
    let decode = &decode;
    let (read, decoded) = std::thread::scope(|scope| {
        let mut senders = Vec::with_capacity(threads);
        let mut handles = Vec::with_capacity(threads);
        for _ in 0..threads {
            let (send, receive) = mpsc::sync_channel::<Chunk>(QUEUE_PER_THREAD);
            senders.push(send);
            let failed = &failed;
            handles.push(scope.spawn(move || {
                let mut scratch = zip.then(ZipScratch::new);
                let mut covered = 0;
                for chunk in receive {
                    match decode(chunk, scratch.as_mut()) {
                        Ok(n) => covered += n,
                        Err(e) => {
                            failed.store(true, Ordering::Relaxed);
                            return Err(e);
                        }
                    }
                    if failed.load(Ordering::Relaxed) {
                        break;
                    }
                }
                Ok(covered)
            }));
        }
        let mut read = Ok(());
        for (i, chunk) in chunks.enumerate() {
            if failed.load(Ordering::Relaxed) {
                break;
            }
            match chunk {
                Ok(chunk) => {
                    let _ = senders[i % threads].send(chunk);
                }
                Err(e) => {
                    failed.store(true, Ordering::Relaxed);
                    read = Err(e);
                    break;
                }
            }
        }
        drop(senders);
        let decoded: Vec<Result<usize, IoErrorKind>> = handles
            .into_iter()
            .map(|h| {
                h.join().unwrap_or_else(|payload| {
                    Err(IoErrorKind::Corrupt(format!(
                        "the OpenEXR decoder failed: {}",
                        panic_message(payload.as_ref())
                    )))
                })
            })
            .collect();
        (read, decoded)
    });
    // An error reading the file comes first: it explains the others.
    read?;
    let mut covered = 0;
    for r in decoded {
        covered += r?;
    }
    Ok(covered)
}

/// Where the blocks of a scan-line part go: the data window's size, the
/// lines per block, and each band of rows, until a block takes it.
struct BandGeometry<'a, 'd> {
    width: usize,
    height: usize,
    lines: usize,
    bands: &'a [Mutex<Option<&'d mut [[f32; 3]]>>],
}

/// A chunk's pixels: ZIP and ZIPS blocks through libdeflate into `zip`'s
/// buffers, every other compression through the exr crate.
pub(super) fn decompress_chunk(
    chunk: Chunk,
    meta: &MetaData,
    zip: Option<&mut ZipScratch>,
) -> Result<UncompressedBlock, IoErrorKind> {
    match zip {
        Some(scratch) => scratch.decompress(chunk, meta),
        None => UncompressedBlock::decompress_chunk(chunk, meta, false).map_err(map_error),
    }
}

/// Decompresses one scan-line chunk (see [`decode_block`]) and converts it
/// into its band of rows; returns the pixels it covered.
fn decode_scan_block(
    chunk: Chunk,
    meta: &MetaData,
    part: usize,
    colour: Colour,
    mut zip: Option<&mut ZipScratch>,
    geometry: &BandGeometry<'_, '_>,
) -> Result<usize, IoErrorKind> {
    panic::catch_unwind(AssertUnwindSafe(|| {
        let block = decompress_chunk(chunk, meta, zip.as_deref_mut())?;
        let header = &meta.headers[part];
        let index = block.index;
        let (x, y) = (index.pixel_position.x(), index.pixel_position.y());
        let (width, height) = (index.pixel_size.x(), index.pixel_size.y());
        let BandGeometry {
            width: full_width,
            height: full_height,
            lines,
            bands,
        } = *geometry;
        let whole_band = x == 0
            && width == full_width
            && y.is_multiple_of(lines)
            && y < full_height
            && height == lines.min(full_height - y);
        if index.layer != part || index.level != Vec2(0, 0) || !whole_band {
            return Err(IoErrorKind::Corrupt(format!(
                "a block at ({x}, {y}) of {width}x{height} pixels that is not a band of \
                 {lines} scan lines of the layer"
            )));
        }
        let mut band = bands[y / lines]
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        let Some(pixels) = band.take() else {
            return Err(IoErrorKind::Corrupt(format!(
                "block at ({x}, {y}) appears twice"
            )));
        };
        drop(band);
        convert_block(&block, header, colour, pixels);
        if let Some(scratch) = zip {
            scratch.recycle(block);
        }
        Ok(width * height)
    }))
    .unwrap_or_else(|payload| {
        Err(IoErrorKind::Corrupt(format!(
            "the OpenEXR decoder failed: {}",
            panic_message(payload.as_ref())
        )))
    })
}

/// Decompresses one chunk (ZIP and ZIPS blocks through `zip`, the others
/// by the `exr` crate) and converts its pixels to RGB; a panic in the
/// decoder is returned as an error.
pub(super) fn decode_block(
    chunk: Chunk,
    meta: &MetaData,
    part: usize,
    colour: Colour,
    mut zip: Option<&mut ZipScratch>,
) -> Result<RgbBlock, IoErrorKind> {
    panic::catch_unwind(AssertUnwindSafe(|| {
        let block = decompress_chunk(chunk, meta, zip.as_deref_mut())?;
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
        convert_block(&block, header, colour, &mut pixels);
        if let Some(scratch) = zip {
            scratch.recycle(block);
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

/// Converts the colour channels of a decompressed block into `pixels`, the
/// block's rectangle row-major (channels it does not hold stay as they
/// are).
pub(super) fn convert_block(
    block: &UncompressedBlock,
    header: &exr::meta::header::Header,
    colour: Colour,
    pixels: &mut [[f32; 3]],
) {
    let (x, y) = (
        block.index.pixel_position.x(),
        block.index.pixel_position.y(),
    );
    let width = block.index.pixel_size.x();
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
        let bytes_per_sample = match sample_type {
            SampleType::F16 => 2,
            SampleType::F32 | SampleType::U32 => 4,
        };
        let out = &mut pixels[first..first + line.value.len() / bytes_per_sample];
        for &c in components {
            write_component(line.value, sample_type, out, c);
        }
    }
}

/// `out[i][c]` = sample `i` of a line of native-endian samples.
fn write_component(bytes: &[u8], sample_type: SampleType, out: &mut [[f32; 3]], c: usize) {
    match sample_type {
        SampleType::F16 => {
            for (o, b) in out.iter_mut().zip(bytes.chunks_exact(2)) {
                o[c] = f16::from_bits(u16::from_ne_bytes([b[0], b[1]])).to_f32();
            }
        }
        SampleType::F32 => {
            for (o, b) in out.iter_mut().zip(bytes.chunks_exact(4)) {
                o[c] = f32::from_ne_bytes([b[0], b[1], b[2], b[3]]);
            }
        }
        SampleType::U32 => {
            for (o, b) in out.iter_mut().zip(bytes.chunks_exact(4)) {
                o[c] = u32::from_ne_bytes([b[0], b[1], b[2], b[3]]) as f32;
            }
        }
    }
}

pub(super) fn check_size(
    width: usize,
    height: usize,
    max_pixels: usize,
) -> Result<(), IoErrorKind> {
    match width.checked_mul(height) {
        Some(n) if n <= max_pixels => Ok(()),
        _ => Err(IoErrorKind::TooLarge {
            width,
            height,
            max_pixels,
        }),
    }
}

pub(super) fn map_error(error: exr::error::Error) -> IoErrorKind {
    use exr::error::Error;
    match error {
        Error::NotSupported(what) => IoErrorKind::Unsupported(format!("OpenEXR {what}")),
        Error::Invalid(what) => IoErrorKind::Corrupt(format!("invalid {what}")),
        Error::Io(e) => IoErrorKind::Corrupt(e.to_string()),
        Error::Aborted => IoErrorKind::Corrupt("decoding aborted".into()),
    }
}
