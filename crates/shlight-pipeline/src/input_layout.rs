//! [`InputLayout`]: how an input names its layout (by aspect ratio, six
//! `{face}` files, or one image in a named layout).

use std::path::{Path, PathBuf};
use std::str::FromStr;

use shlight_core::map::Layout;

/// The layout of an input map, as `--layout` (and the Python `layout=`)
/// names it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum InputLayout {
    /// [`Layout::detect`] by aspect ratio (or six faces for `{face}` inputs).
    #[default]
    Auto,
    /// Six face files, [`FACE_PLACEHOLDER`] in the input name.
    Faces,
    /// One image in this layout.
    Image(Layout),
}

impl FromStr for InputLayout {
    type Err = String;

    /// `auto`, `faces`, or a [`Layout`] name (`equirect`, `cross-h`, ...).
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        match s.trim() {
            "auto" => Ok(InputLayout::Auto),
            "faces" => Ok(InputLayout::Faces),
            name => name
                .parse::<Layout>()
                .map(InputLayout::Image)
                .map_err(|e| format!("{e} (or auto, faces)")),
        }
    }
}

/// The placeholder of six-face inputs (`sky_{face}.exr`).
pub const FACE_PLACEHOLDER: &str = "{face}";
/// Face names replacing [`FACE_PLACEHOLDER`], in strip order (+X -X +Y -Y +Z -Z).
pub const FACE_NAMES: [&str; 6] = ["px", "nx", "py", "ny", "pz", "nz"];

/// Whether an input names six face files (holds [`FACE_PLACEHOLDER`]).
#[must_use]
pub fn is_faces(path: &Path) -> bool {
    path.to_string_lossy().contains(FACE_PLACEHOLDER)
}

/// The six face files of a `{face}` input, in strip order.
#[must_use]
pub fn face_paths(path: &Path) -> Vec<PathBuf> {
    let pattern = path.to_string_lossy();
    FACE_NAMES
        .iter()
        .map(|f| PathBuf::from(pattern.replace(FACE_PLACEHOLDER, f)))
        .collect()
}
