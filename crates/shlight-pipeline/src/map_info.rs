//! [`MapInfo`]: what a coefficient file records of the map it was
//! projected from.

use shlight_core::map::Layout;
use shlight_format::SanitizeCounts;
use shlight_io::PixelStats;

/// What the coefficient file records about the input map.
#[derive(Clone, Debug)]
pub struct MapInfo {
    /// The input as named to the user (a path as given).
    pub name: String,
    /// Width in texels.
    pub width: usize,
    /// Height in texels.
    pub height: usize,
    /// Layout name (`equirect`, ..., or `faces` for six face files).
    pub layout: String,
    /// Statistics of the values as read.
    pub stats: PixelStats,
    /// What sanitizing replaced, if it was asked for.
    pub sanitized: Option<SanitizeCounts>,
}

impl MapInfo {
    /// The record of the map `name`, `size` texels of the layout named
    /// `layout`, with the statistics `stats` of its values as read and what
    /// sanitizing replaced.
    #[must_use]
    pub fn new(
        name: &str,
        layout: &str,
        (width, height): (usize, usize),
        stats: PixelStats,
        sanitized: Option<SanitizeCounts>,
    ) -> Self {
        Self {
            name: name.to_string(),
            width,
            height,
            layout: layout.to_string(),
            stats,
            sanitized,
        }
    }

    /// The record of a contiguous map of `pixels` (statistics computed
    /// here, not sanitized).
    #[must_use]
    pub fn of_pixels(
        name: &str,
        layout: Layout,
        width: usize,
        height: usize,
        pixels: &[[f32; 3]],
    ) -> Self {
        let stats = PixelStats::of_pixels(pixels, width);
        Self::new(name, layout.name(), (width, height), stats, None)
    }
}
