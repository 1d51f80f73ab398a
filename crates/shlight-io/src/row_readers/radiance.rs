//! Radiance RGBE files read scan line by scan line ([`RadianceRows`]): the
//! header by the `image` crate's decoder (which reads it byte by byte), the
//! scan lines (new per-component RLE, old RLE and flat) here, converted as
//! that decoder converts them, so the values are the whole-image reader's.

use std::fs::File;
use std::io::{BufReader, Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};

use image::ImageDecoder;
use image::codecs::hdr::HdrDecoder;

use crate::IoErrorKind;
use crate::row_readers::row_sink::{BLOCK_TEXELS, RowSink};

/// A Radiance file whose header has been read.
pub(crate) struct RadianceRows {
    path: PathBuf,
    /// Bytes before the first scan line.
    data_start: u64,
    width: usize,
    height: usize,
}

/// Counts the bytes read through it.
struct Counting<R> {
    inner: R,
    count: u64,
}

impl<R: Read> Read for Counting<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        self.count += n as u64;
        Ok(n)
    }
}

fn corrupt(what: impl std::fmt::Display) -> IoErrorKind {
    IoErrorKind::Corrupt(what.to_string())
}

impl RadianceRows {
    pub(crate) fn open(path: &Path) -> Result<Self, IoErrorKind> {
        let file = File::open(path).map_err(IoErrorKind::from_read_error)?;
        let mut counting = Counting {
            inner: BufReader::new(file),
            count: 0,
        };
        // Not strict, as the whole-image reader.
        let decoder = HdrDecoder::with_strictness(&mut counting, false).map_err(corrupt)?;
        let (w, h) = decoder.dimensions();
        drop(decoder);
        Ok(Self {
            path: path.to_path_buf(),
            data_start: counting.count,
            width: w as usize,
            height: h as usize,
        })
    }

    pub(crate) fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }

    /// Decodes the scan lines in order, handing them to `sink` in bands
    /// of about [`BLOCK_TEXELS`] texels.
    pub(crate) fn read(&self, sink: &RowSink<'_>) -> Result<(), IoErrorKind> {
        let mut file = File::open(&self.path).map_err(IoErrorKind::from_read_error)?;
        file.seek(SeekFrom::Start(self.data_start))
            .map_err(IoErrorKind::from_read_error)?;
        let mut r = BufReader::with_capacity(1 << 20, file);
        let w = self.width;
        let rows_per_band = (BLOCK_TEXELS / w).max(1);
        let mut rgbe = vec![[0_u8; 4]; w];
        let mut band: Vec<[f32; 3]> = Vec::with_capacity(rows_per_band * w);
        let mut first = 0;
        for y in 0..self.height {
            read_scanline(&mut r, &mut rgbe)?;
            band.extend(rgbe.iter().map(|&p| to_linear(p)));
            if band.len() == rows_per_band * w || y + 1 == self.height {
                sink(first, &band);
                band.clear();
                first = y + 1;
            }
        }
        Ok(())
    }
}

/// An RGBE pixel as linear RGB, computed as the `image` crate does.
fn to_linear([r, g, b, e]: [u8; 4]) -> [f32; 3] {
    if e == 0 {
        return [0.0; 3];
    }
    let exp = f32::exp2(f32::from(e) - (128.0 + 8.0));
    [exp * f32::from(r), exp * f32::from(g), exp * f32::from(b)]
}

fn read_bytes<const N: usize>(r: &mut impl Read) -> Result<[u8; N], IoErrorKind> {
    let mut buf = [0; N];
    r.read_exact(&mut buf).map_err(|e| {
        if e.kind() == std::io::ErrorKind::UnexpectedEof {
            IoErrorKind::Truncated
        } else {
            IoErrorKind::from_read_error(e)
        }
    })?;
    Ok(buf)
}

/// One scan line: per-component RLE when it starts `2 2 hi lo` with
/// `hi < 128`, else old RLE (runs marked by `1 1 1 n`) or flat pixels.
fn read_scanline(r: &mut impl Read, out: &mut [[u8; 4]]) -> Result<(), IoErrorKind> {
    let width = out.len();
    let first = read_bytes::<4>(r)?;
    if first[0] == 2 && first[1] == 2 && first[2] < 128 {
        for c in 0..4 {
            let mut pos = 0;
            while pos < width {
                let [n] = read_bytes::<1>(r)?;
                if n <= 128 {
                    let n = usize::from(n);
                    if pos + n > width {
                        return Err(corrupt("a scan line runs past the image's width"));
                    }
                    for o in &mut out[pos..pos + n] {
                        o[c] = read_bytes::<1>(r)?[0];
                    }
                    pos += n;
                } else {
                    let n = usize::from(n - 128);
                    if pos + n > width {
                        return Err(corrupt("a scan line runs past the image's width"));
                    }
                    let [v] = read_bytes::<1>(r)?;
                    for o in &mut out[pos..pos + n] {
                        o[c] = v;
                    }
                    pos += n;
                }
            }
        }
        return Ok(());
    }
    let marker = |p: [u8; 4]| (p[..3] == [1, 1, 1]).then_some(usize::from(p[3]));
    if marker(first).is_some() {
        return Err(corrupt("a scan line starts with a run marker"));
    }
    out[0] = first;
    let (mut x, mut multiplier, mut previous) = (1, 1, first);
    while x < width {
        let p = read_bytes::<4>(r)?;
        if let Some(n) = marker(p) {
            let n = n * multiplier;
            multiplier *= 256;
            if x + n > width {
                return Err(corrupt("a scan line runs past the image's width"));
            }
            out[x..x + n].fill(previous);
            x += n;
        } else {
            multiplier = 1;
            previous = p;
            out[x] = p;
            x += 1;
        }
    }
    Ok(())
}
