//! [`ReadSettings`]: how a job reads its input maps.

use shlight_io::ReadOptions;

use crate::input_layout::InputLayout;
use crate::spelling::Spelling;

/// How input files are read: their layout, the reader's options, and
/// whether bad values are replaced instead of refused.
#[derive(Clone, Debug, Default)]
pub struct ReadSettings {
    /// The layout of the inputs (`auto` by aspect ratio).
    pub layout: InputLayout,
    /// EXR layer and pixel limit.
    pub read: ReadOptions,
    /// Replace NaN, infinities and negatives ([`crate::sanitize_image`]).
    pub sanitize: bool,
    /// How the loader's messages name these settings (`--sanitize`,
    /// `sanitize`).
    pub spelling: Spelling,
}
