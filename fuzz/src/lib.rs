//! What the fuzz targets share: the limits they read with, so that
//! `fuzz/run.sh`'s `-rss_limit_mb` and `-timeout` hold what
//! docs/limits.md promises for them.

/// The pixel limit the image targets read with (`ReadOptions::max_pixels`):
/// 2^22 (2048 x 2048). docs/limits.md bounds a read's memory by
/// 64 bytes a pixel of this limit plus a few times the file's size, so
/// 256 MiB here, well inside the targets' 2048 MiB RSS limit.
pub const MAX_PIXELS: usize = 1 << 22;
