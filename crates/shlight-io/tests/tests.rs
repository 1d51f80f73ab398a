//! Integration tests of shlight-io, one module per topic, built as one
//! binary. Files are made in temporary directories under the target
//! directory; the bundled maps are read from `envmaps/` at the workspace
//! root.

mod util;

// Image type: construction, accessors, crop, flips, rotations.
mod image_ops;
// Pixel statistics and sanitising.
mod stats;
// sRGB transfer function and tone-mapping curves.
mod srgb_tone;
// OpenEXR: round trips, compressions, tiles, data windows, layers.
mod openexr;
// Radiance HDR: round trips, signatures.
mod radiance;
// PNG and JPEG: sRGB decoding, bit depths, grey, writing.
mod png_jpeg;
// Reading by rows: the streaming readers against the whole-image reader.
mod row_readers;
// Broken inputs: truncated, corrupted, empty, not images, missing, too large.
mod bad_files;
// Inputs that once stopped a fuzz target (fuzz/).
mod fuzz_regressions;
// KTX2 lightmaps: layout and descriptor read by the ktx2 crate, encodings.
mod ktx2_files;
// Atomic writes: failures leave the destination and no temporary file.
mod atomic;
// The environment maps bundled in envmaps/.
mod envmaps;
