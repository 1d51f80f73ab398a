//! Reading one layer of an OpenEXR file as bands of whole rows, handed to
//! a callback as they are decoded ([`ExrRows`]), with no image buffer:
//! the file is read through a buffer, not mapped, and at most a few
//! compressed blocks per thread wait to be decoded.
//!
//! Scan-line blocks become bands as they are decompressed; tiles are
//! gathered into the band of rows of their tile row, handed on when the
//! band's last tile comes (tiles stored in row order, as writers store
//! them, keep one or two bands open). Files whose data window is not their
//! display window, and deep files, are left to the whole-image reader.

use std::collections::{HashMap, HashSet};
use std::fs::File;
use std::io::BufReader;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, PoisonError};

use exr::block::chunk::Chunk;
use exr::block::reader::ChunksReader;
use exr::math::Vec2;
use exr::meta::{BlockDescription, MetaData};

use super::decode::{check_covered, check_size, decode_block, decode_on_threads, map_error};
use super::inspect;
use super::layers::{self, Colour};
use super::zip_block::{self, ZipScratch};
use crate::{IoErrorKind, ReadOptions};

/// An OpenEXR file's chosen layer, ready to be read as rows.
pub(crate) struct ExrRows {
    path: PathBuf,
    part: usize,
    colour: Colour,
    width: usize,
    height: usize,
}

/// A file reader with a buffer of this many bytes.
const BUFFER: usize = 1 << 20;

fn open_file(path: &Path) -> Result<BufReader<File>, IoErrorKind> {
    let file = File::open(path).map_err(IoErrorKind::from_read_error)?;
    Ok(BufReader::with_capacity(BUFFER, file))
}

impl ExrRows {
    /// The header of the file at `path`, checked as the whole-image reader
    /// checks it; `None` when the file is one that reader must read
    /// (a data window other than the display window, deep data).
    pub(crate) fn open(path: &Path, options: &ReadOptions) -> Result<Option<Self>, IoErrorKind> {
        let reader = exr::block::read(open_file(path)?, false).map_err(map_error)?;
        let chosen = layers::choose(reader.headers(), options.layer.as_deref())?;
        let header = &reader.headers()[chosen.part];
        if header.deep {
            return Ok(None);
        }
        let display = header.shared_attributes.display_window;
        check_size(display.size.x(), display.size.y(), options.max_pixels)?;
        let (width, height) = (header.layer_size.x(), header.layer_size.y());
        check_size(width, height, options.max_pixels)?;
        inspect::check_block_size(header, options.max_pixels)?;
        if header.own_attributes.layer_position != display.position
            || (width, height) != (display.size.x(), display.size.y())
        {
            return Ok(None);
        }
        Ok(Some(Self {
            path: path.to_path_buf(),
            part: chosen.part,
            colour: chosen.colour,
            width,
            height,
        }))
    }

    pub(crate) fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }

    /// Decodes every block of the layer on all cores and hands each band
    /// of whole rows to `sink(first_row, rows)` as it is complete.
    pub(crate) fn read(
        &self,
        sink: &(dyn Fn(usize, &[[f32; 3]]) + Sync),
    ) -> Result<(), IoErrorKind> {
        let reader = exr::block::read(open_file(&self.path)?, false).map_err(map_error)?;
        let part = self.part;
        let reader = reader
            .filter_chunks(false, |_, tile, block| {
                block.layer == part && tile.level_index == Vec2(0, 0)
            })
            .map_err(map_error)?;
        let meta = reader.meta_data().clone();
        let header = meta.headers[part].clone();
        let count = reader.len();
        let chunks = reader.map(|chunk| {
            let chunk = chunk.map_err(map_error)?;
            inspect::check_dwa_block(&chunk, &header)?;
            Ok(chunk)
        });
        let bands = Bands::new(&header, self.width, self.height);
        let zip = zip_block::handles(header.compression);
        let covered = decode_on_threads(chunks, count, zip, |chunk, zip| {
            bands.decode(chunk, &meta, part, self.colour, zip, sink)
        })?;
        check_covered(covered, self.width * self.height)
    }
}

/// Where decoded blocks go: whole scan-line bands straight to the sink,
/// tiles into the band of their tile row.
struct Bands {
    width: usize,
    height: usize,
    /// Rows per band: the scan lines per block, or the tile height.
    lines: usize,
    tiled: bool,
    /// Blocks already seen, by position.
    seen: Mutex<HashSet<(usize, usize)>>,
    /// Tile bands still open: their rows and the pixels they have.
    open: Mutex<HashMap<usize, OpenBand>>,
}

/// A band of rows being filled by tiles: its texels and how many it has.
type OpenBand = (Vec<[f32; 3]>, usize);

impl Bands {
    fn new(header: &exr::meta::header::Header, width: usize, height: usize) -> Self {
        let (lines, tiled) = match header.blocks {
            BlockDescription::ScanLines => (header.compression.scan_lines_per_block(), false),
            BlockDescription::Tiles(t) => (t.tile_size.y(), true),
        };
        Self {
            width,
            height,
            lines: lines.max(1),
            tiled,
            seen: Mutex::new(HashSet::new()),
            open: Mutex::new(HashMap::new()),
        }
    }

    /// Decodes one chunk and hands on the rows it completes; returns the
    /// pixels it covered. A panic in the decoder is returned as an error.
    fn decode(
        &self,
        chunk: Chunk,
        meta: &MetaData,
        part: usize,
        colour: Colour,
        zip: Option<&mut ZipScratch>,
        sink: &(dyn Fn(usize, &[[f32; 3]]) + Sync),
    ) -> Result<usize, IoErrorKind> {
        // `decode_block` turns a decoder panic into an error.
        let block = decode_block(chunk, meta, part, colour, zip)?;
        let (x, y, w, h) = (block.x, block.y, block.width, block.height);
        let band_height = self.lines.min(self.height.saturating_sub(y));
        let aligned = y.is_multiple_of(self.lines)
            && y < self.height
            && if self.tiled {
                h == band_height
            } else {
                x == 0 && w == self.width && h == band_height
            };
        if !aligned {
            return Err(IoErrorKind::Corrupt(format!(
                "a block at ({x}, {y}) of {w}x{h} pixels that is not a band of {} lines of \
                 the layer",
                self.lines
            )));
        }
        if !self
            .seen
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .insert((x, y))
        {
            return Err(IoErrorKind::Corrupt(format!(
                "block at ({x}, {y}) appears twice"
            )));
        }
        if !self.tiled {
            sink(y, &block.pixels);
            return Ok(w * h);
        }
        let full = self.width * band_height;
        let done = {
            let mut open = self.open.lock().unwrap_or_else(PoisonError::into_inner);
            let (rows, have) = open.entry(y).or_insert_with(|| (vec![[0.0; 3]; full], 0));
            for r in 0..h {
                rows[r * self.width + x..r * self.width + x + w]
                    .copy_from_slice(&block.pixels[r * w..(r + 1) * w]);
            }
            *have += w * h;
            if *have >= full {
                open.remove(&y).map(|(rows, _)| rows)
            } else {
                None
            }
        };
        if let Some(rows) = done {
            sink(y, &rows);
        }
        Ok(w * h)
    }
}
