//! OpenEXR reading and writing, through the `exr` crate, except that ZIP
//! and ZIPS blocks are inflated by libdeflate (`zip_block.rs`).
//!
//! Reading takes one layer's R, G, B channels (A and every other channel are
//! ignored), or a lone Y channel as grey. Samples may be half, float or uint,
//! in scan lines or tiles (the largest mip level), with any compression the
//! `exr` crate decodes: none, RLE, ZIPS, ZIP, PIZ, PXR24, B44, B44A, DWAA and
//! DWAB. Only the chosen layer's blocks are read and decompressed, on all
//! cores; scan-line blocks as they are read, straight into their rows.
//!
//! A *layer* is a group of channels sharing a name prefix (`diffuse.R`,
//! `diffuse.G`, ...) within one part of the file; see [`layers`].
//!
//! The returned image covers the file's display window. The data window may
//! be offset from it, smaller or larger: pixels of the display window outside
//! the data window are 0, data outside the display window is dropped.

mod decode;
mod encode;
mod inspect;
mod layers;
mod stream;
mod zip_block;

pub(crate) use decode::decode;
pub(crate) use encode::encode;
pub(crate) use stream::ExrRows;
