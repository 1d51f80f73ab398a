//! Image files in and out: HDR environment maps read from and written to
//! disk as linear `f32` RGB.
//!
//! This crate has one job: turn an OpenEXR, Radiance HDR, PNG or JPEG file
//! into an [`Image`] of linear, scene-referred Rec.709 RGB values, and write
//! an [`Image`] back as OpenEXR, Radiance HDR or PNG. What the pixels mean
//! (equirectangular or cube-map layout, directions, spherical harmonics) is
//! for the crates above it.
//!
//! # Main items
//! - [`Image`]: width, height and row-major pixels (row 0 at the top), with
//!   exact geometric operations ([`Image::crop`], flips, quarter turns),
//!   box-filtered resizing ([`Image::resample`], [`Image::halve`]) and
//!   value checks ([`Image::stats`], [`Image::sanitize`]).
//! - [`read_image`] with [`ReadOptions`] (OpenEXR layer, pixel-count limit):
//!   the format is recognised by the file's first bytes;
//!   [`read_image_bytes`] reads the same from bytes in memory.
//! - [`open_rows`]: the same image handed out as bands of whole rows while
//!   it is decoded ([`RowSource`]: OpenEXR scan lines and tiles, Radiance,
//!   PNG stream; other files are read whole first), with [`read_image`]'s
//!   values and errors, for callers that fold rows into sums without
//!   holding the image; [`sanitize_pixels`] sanitizes such a band.
//! - [`image_info`]: a file's [`ImageInfo`] (format, size, channels as
//!   stored) from its header alone, without decoding a pixel.
//! - [`write_image`] with [`WriteOptions`] (exposure, [`ToneMap`] for PNG):
//!   the format is named by the extension; [`auto_exposure`] picks the
//!   exposure that brings a mean luminance to a grey.
//! - [`write_ktx2`] and [`encode_ktx2`]: linear float lightmaps as KTX 2.0
//!   files ([`Ktx2TexelFormat`]: half-float RGBA or packed unsigned
//!   B10G11R11 floats), read back by [`read_ktx2`].
//! - [`write_atomically`]: every file is written to a temporary file and
//!   renamed into place, so a failed write never leaves a half-written
//!   file or damages an existing one.
//! - [`IoError`]: the path and an [`IoErrorKind`]; its message names the
//!   file and the problem in plain words.
//!
//! # Design
//! Files are read whole into memory (except by [`open_rows`]) and decoded
//! from there: the signature,
//! the header's size (checked against [`ReadOptions::max_pixels`] before
//! pixels are allocated) and the completeness checks that tell a truncated
//! file from a corrupt one all look at the same bytes. 8- and 16-bit values
//! are decoded with the exact sRGB EOTF ([`srgb_to_linear`]) so that every
//! image is linear by the time anyone sees it. OpenEXR goes through the `exr`
//! crate's block API (all its compressions, DWAA/DWAB included): only the
//! chosen layer is decompressed, on scoped threads whose panics are caught,
//! after each DWA block's stated sizes are checked (a damaged one could
//! otherwise make `exr` request terabytes and abort). The other formats go
//! through the `image` crate with only the Radiance, PNG and JPEG codecs
//! built. A malformed file gives an error, never a panic, and no file makes
//! a read hang or allocate beyond what [`ReadOptions::max_pixels`] allows
//! (docs/limits.md states the bounds; the fuzz targets in `fuzz/` check
//! them).
//!
//! OpenEXR layers: a layer is a group of channels with a common name prefix
//! (`diffuse.R`, `diffuse.G`, `diffuse.B` form layer `diffuse`), within one
//! part of the file; in a multi-part file the part's name comes first
//! (`beauty.diffuse`). Plain `R`, `G`, `B` channels form the unnamed layer
//! `""`. The image returned covers the file's display window; pixels outside
//! the data window are 0.
//!
//! # Example
//! ```
//! use shlight_io::{Image, ReadOptions, WriteOptions, read_image, write_image};
//!
//! let dir = std::env::temp_dir().join(format!("shlight-io-doc-{}", std::process::id()));
//! std::fs::create_dir_all(&dir).unwrap();
//! let path = dir.join("gradient.exr");
//!
//! let image = Image::from_fn(8, 4, |x, y| [x as f32, y as f32, 10.0]);
//! write_image(&path, &image, &WriteOptions::default())?;
//! let back = read_image(&path, &ReadOptions::default())?;
//! assert_eq!(back, image); // 32-bit float OpenEXR is exact
//! assert_eq!(back.get(7, 3), [7.0, 3.0, 10.0]);
//! # std::fs::remove_dir_all(&dir).unwrap();
//! # Ok::<(), shlight_io::IoError>(())
//! ```
//!
//! **Architecture invariant:** this crate depends on no other shlight crate
//! (in particular not on `shlight-core`) and on no GPU API; it knows files
//! and pixels, nothing about spherical harmonics or rendering.

#![deny(missing_docs)]

mod atomic;
mod error;
mod exposure;
mod exr_compression;
mod format;
mod image;
mod image_codecs;
mod image_info;
mod ktx2;
mod openexr;
mod panic_message;
mod read;
mod read_options;
mod resample;
mod row_readers;
mod srgb;
mod stats;
mod tone_map;
mod transform;
mod write;

pub use crate::atomic::write_atomically;
pub use crate::error::{IoError, IoErrorKind};
pub use crate::exposure::auto_exposure;
pub use crate::exr_compression::ExrCompression;
pub use crate::format::Format;
pub use crate::image::{Image, PixelCountError};
pub use crate::image_codecs::encode_png_rgba8;
pub use crate::image_info::{ImageInfo, image_info};
pub use crate::ktx2::{
    Ktx2Image, Ktx2TexelFormat, decode_ktx2, encode_ktx2, f16_bits_to_f32, f32_to_f16_bits,
    pack_b10g11r11, read_ktx2, unpack_b10g11r11, write_ktx2,
};
pub use crate::read::{read_image, read_image_bytes};
pub use crate::read_options::ReadOptions;
pub use crate::row_readers::{RowSink, RowSource, open_rows, read_image_by_rows};
pub use crate::srgb::{linear_to_srgb, srgb_to_linear};
pub use crate::stats::{PixelStats, SanitizeReport, sanitize_pixels};
pub use crate::tone_map::{ParseToneMapError, ToneMap};
pub use crate::write::{WriteOptions, write_image};
