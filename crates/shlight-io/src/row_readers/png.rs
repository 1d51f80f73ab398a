//! PNG files read row by row ([`PngRows`]) through the `png` crate, with
//! the `image` crate's transformations (palettes and low bit depths
//! expanded) and conversions (grey to equal R, G, B; alpha dropped; sRGB
//! decoded by the same tables), so the values are the whole-image reader's.
//! Interlaced files are left to the whole-image reader.

use std::fs::File;
use std::io::BufReader;
use std::path::{Path, PathBuf};

use png::{BitDepth, ColorType, Transformations};

use crate::IoErrorKind;
use crate::row_readers::row_sink::{BLOCK_TEXELS, RowSink};
use crate::srgb::{srgb8_table, srgb16_table};

/// A PNG file whose header has been read.
pub(crate) struct PngRows {
    path: PathBuf,
    width: usize,
    height: usize,
}

fn corrupt(what: impl std::fmt::Display) -> IoErrorKind {
    IoErrorKind::Corrupt(what.to_string())
}

fn reader(path: &Path) -> Result<png::Reader<BufReader<File>>, IoErrorKind> {
    let file = File::open(path).map_err(IoErrorKind::from_read_error)?;
    let mut decoder = png::Decoder::new(BufReader::with_capacity(1 << 20, file));
    decoder.set_transformations(Transformations::EXPAND);
    decoder.read_info().map_err(corrupt)
}

impl PngRows {
    /// `None` for an interlaced file.
    pub(crate) fn open(path: &Path) -> Result<Option<Self>, IoErrorKind> {
        let r = reader(path)?;
        let info = r.info();
        if info.interlaced {
            return Ok(None);
        }
        Ok(Some(Self {
            path: path.to_path_buf(),
            width: info.width as usize,
            height: info.height as usize,
        }))
    }

    pub(crate) fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }

    /// Decodes the rows in order, handing them to `sink` in bands of about
    /// [`BLOCK_TEXELS`] texels.
    pub(crate) fn read(&self, sink: &RowSink<'_>) -> Result<(), IoErrorKind> {
        let mut r = reader(&self.path)?;
        let (colour, depth) = r.output_color_type();
        let channels = match colour {
            ColorType::Grayscale => 1,
            ColorType::GrayscaleAlpha => 2,
            ColorType::Rgb => 3,
            ColorType::Rgba => 4,
            ColorType::Indexed => return Err(corrupt("a palette left unexpanded")),
        };
        let w = self.width;
        let rows_per_band = (BLOCK_TEXELS / w).max(1);
        let table8 = srgb8_table();
        let table16 = srgb16_table();
        let mut band: Vec<[f32; 3]> = Vec::with_capacity(rows_per_band * w);
        let mut first = 0;
        for y in 0..self.height {
            let row = r
                .next_row()
                .map_err(corrupt)?
                .ok_or(IoErrorKind::Truncated)?;
            let data = row.data();
            let code = |x: usize, c: usize| -> f32 {
                // Grey (and grey with alpha) gives equal R, G, B.
                let c = if channels < 3 { 0 } else { c };
                let i = x * channels + c;
                match depth {
                    BitDepth::Sixteen => {
                        table16[usize::from(u16::from_be_bytes([data[2 * i], data[2 * i + 1]]))]
                    }
                    _ => table8[usize::from(data[i])],
                }
            };
            band.extend((0..w).map(|x| [code(x, 0), code(x, 1), code(x, 2)]));
            if band.len() == rows_per_band * w || y + 1 == self.height {
                sink(first, &band);
                band.clear();
                first = y + 1;
            }
        }
        // The file must go on to its end (`IEND`), as for the whole-image
        // reader.
        r.finish().map_err(corrupt)
    }
}
