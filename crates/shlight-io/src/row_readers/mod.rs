//! [`RowSource`]: an image handed out as bands of whole rows, decoded from
//! its file as they are read where the format allows it ([`open_rows`]),
//! so that a caller that folds rows into sums (an SH projection) never
//! holds the image.
//!
//! OpenEXR (scan lines and tiles, every compression the whole-image reader
//! decodes), Radiance (every RLE form) and non-interlaced PNG stream;
//! JPEG, interlaced PNG, OpenEXR files whose data window is not their
//! display window and deep OpenEXR files are read whole and then handed
//! out by rows ([`RowSource::streams`] says which). The values are the
//! whole-image reader's ([`crate::read_image`]) bit for bit, and so are
//! the errors: a file a streaming reader refuses is read again by the
//! whole-image reader for its message.

use std::path::{Path, PathBuf};
use std::sync::{Mutex, PoisonError};

use crate::openexr::ExrRows;
use crate::{Format, Image, IoError, IoErrorKind, ReadOptions, read_image};

mod png;
mod radiance;
mod row_sink;

use self::png::PngRows;
use self::radiance::RadianceRows;
use self::row_sink::BLOCK_TEXELS;
pub use self::row_sink::RowSink;

/// An image that hands out its rows ([`open_rows`]).
pub trait RowSource: Send + Sync {
    /// `(width, height)`, from the file's header.
    fn size(&self) -> (usize, usize);

    /// Decodes the image and hands every row to `sink` exactly once, in
    /// bands of whole rows, in any order and possibly from several threads
    /// at once. Each call decodes the file again.
    ///
    /// # Errors
    /// As [`crate::read_image`]; `sink` may have had some rows by then.
    fn read_rows(&self, sink: &RowSink<'_>) -> Result<(), IoError>;

    /// Whether rows are decoded as they are read (memory bounded by a few
    /// blocks), rather than the image read whole first.
    fn streams(&self) -> bool;

    /// Whether [`RowSource::read_rows`] calls the sink from threads of its
    /// own, several at once (OpenEXR, decoded on every core), rather than
    /// from the calling thread alone. A sink called from such threads must
    /// not wait on work it hands to a thread pool whose workers may be
    /// waiting on the read (a read started from a pool task).
    fn calls_from_many_threads(&self) -> bool {
        false
    }

    /// The whole image, where the source already holds it (a file read
    /// whole: [`RowSource::streams`] is false), so that a caller that
    /// wants it after all need not read the file again.
    fn into_image(self: Box<Self>) -> Option<Image> {
        None
    }
}

/// An image in memory, handed out in bands of rows.
impl RowSource for Image {
    fn size(&self) -> (usize, usize) {
        (self.width(), self.height())
    }

    fn read_rows(&self, sink: &RowSink<'_>) -> Result<(), IoError> {
        let w = self.width().max(1);
        for (band, rows) in self
            .pixels()
            .chunks((BLOCK_TEXELS / w).max(1) * w)
            .enumerate()
        {
            sink(band * (BLOCK_TEXELS / w).max(1), rows);
        }
        Ok(())
    }

    fn streams(&self) -> bool {
        false
    }

    fn into_image(self: Box<Self>) -> Option<Image> {
        Some(*self)
    }
}

/// A streaming reader of one format.
enum Streaming {
    Exr(ExrRows),
    Radiance(RadianceRows),
    Png(PngRows),
}

/// A file read by a streaming reader.
struct FileRows {
    path: PathBuf,
    options: ReadOptions,
    reader: Streaming,
}

impl RowSource for FileRows {
    fn size(&self) -> (usize, usize) {
        match &self.reader {
            Streaming::Exr(r) => r.size(),
            Streaming::Radiance(r) => r.size(),
            Streaming::Png(r) => r.size(),
        }
    }

    fn read_rows(&self, sink: &RowSink<'_>) -> Result<(), IoError> {
        let result = match &self.reader {
            Streaming::Exr(r) => r.read(sink),
            Streaming::Radiance(r) => r.read(sink),
            Streaming::Png(r) => r.read(sink),
        };
        result.map_err(|kind| self.whole_image_error(kind))
    }

    fn streams(&self) -> bool {
        true
    }

    fn calls_from_many_threads(&self) -> bool {
        matches!(self.reader, Streaming::Exr(_))
    }
}

impl FileRows {
    /// The whole-image reader's error for this file, or `kind` if that
    /// reader reads it.
    fn whole_image_error(&self, kind: IoErrorKind) -> IoError {
        match read_image(&self.path, &self.options) {
            Err(e) => e,
            Ok(_) => IoError::new(&self.path, kind),
        }
    }
}

/// Opens the image file at `path` for reading by rows: its header is read
/// and checked (size, [`ReadOptions::max_pixels`], the OpenEXR layer) and
/// a streaming reader chosen where the format has one; other files (see
/// the module documentation) are read whole here.
///
/// # Errors
/// As [`crate::read_image`], with the same messages.
pub fn open_rows(path: &Path, options: &ReadOptions) -> Result<Box<dyn RowSource>, IoError> {
    let whole =
        || -> Result<Box<dyn RowSource>, IoError> { Ok(Box::new(read_image(path, options)?)) };
    let Some(format) = sniff(path) else {
        return whole();
    };
    let opened = match format {
        Format::Exr => ExrRows::open(path, options).map(|r| r.map(Streaming::Exr)),
        Format::Radiance => RadianceRows::open(path).map(|r| Some(Streaming::Radiance(r))),
        Format::Png => PngRows::open(path).map(|r| r.map(Streaming::Png)),
        _ => Ok(None),
    };
    let Ok(Some(reader)) = opened else {
        // Not streamed, or refused: the whole-image reader reads it or
        // says why not.
        return whole();
    };
    let rows = FileRows {
        path: path.to_path_buf(),
        options: options.clone(),
        reader,
    };
    let (w, h) = rows.size();
    match w.checked_mul(h) {
        Some(n) if n > 0 && n <= options.max_pixels => Ok(Box::new(rows)),
        // Empty or too large: as the whole-image reader says it.
        _ => whole(),
    }
}

/// The image file at `path` read whole, exactly as [`crate::read_image`]
/// reads it (the same pixels, bit for bit, and the same errors), but
/// decoded by rows where the format streams ([`open_rows`]): what it holds
/// is the image and a few compressed blocks, never the file's bytes beside
/// the image (read or mapped), so a large compressed map takes its
/// texels' memory and little more.
///
/// # Errors
/// As [`crate::read_image`].
pub fn read_image_by_rows(path: &Path, options: &ReadOptions) -> Result<Image, IoError> {
    let source = open_rows(path, options)?;
    if !source.streams() {
        if let Some(image) = source.into_image() {
            return Ok(image);
        }
        return read_image(path, options);
    }
    let (w, h) = source.size();
    let pixels = Mutex::new(vec![[0.0_f32; 3]; w * h]);
    source.read_rows(&|first, band: &[[f32; 3]]| {
        let mut pixels = pixels.lock().unwrap_or_else(PoisonError::into_inner);
        let start = first * w;
        if let Some(rows) = pixels.get_mut(start..start + band.len()) {
            rows.copy_from_slice(band);
        }
    })?;
    let pixels = pixels.into_inner().unwrap_or_else(PoisonError::into_inner);
    Image::new(w, h, pixels).map_err(|e| IoError::new(path, IoErrorKind::Corrupt(e.to_string())))
}

/// The format by the file's first bytes, then its extension
/// ([`read_image`]'s rule); `None` when unreadable or unknown.
fn sniff(path: &Path) -> Option<Format> {
    let mut head = [0_u8; 16];
    let mut file = std::fs::File::open(path).ok()?;
    let n = std::io::Read::read(&mut file, &mut head).ok()?;
    match (Format::from_magic(&head[..n]), Format::from_extension(path)) {
        (Some(f), _) => Some(f),
        (None, Some(Format::Radiance)) if n > 0 => Some(Format::Radiance),
        _ => None,
    }
}
