//! The last steps of a projection: windows, rotation, quantity, and the
//! coefficient file with its provenance.

use glam::DVec3;
use shlight_core::map::Layout;
use shlight_core::sh::{
    ShCoeffs, ShRotation, Window, WindowFamily, WindowTarget, apply_channel_windows, auto_windows,
    clamped_cosine_eigenvalue, irradiance, rotate_once, rotate_std_error,
};
use shlight_format::{CoeffFile, Provenance, Quantity, SanitizeCounts};
use shlight_io::PixelStats;

use crate::projection::Projection;
use crate::settings::ProjectSettings;
use crate::{PipelineError, Result};

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
        Self {
            name: name.to_string(),
            width,
            height,
            layout: layout.name().to_string(),
            stats: PixelStats::of_pixels(pixels, width),
            sanitized: None,
        }
    }
}

/// The window of each colour channel: the settings' window for all three,
/// or (`window: None`, `auto`) per channel the weakest Hanning window that
/// makes that channel's result non-negative: the function itself for
/// radiance, its irradiance for irradiance
/// ([`shlight_core::sh::auto_windows`]).
///
/// # Errors
/// No Hanning window makes a channel non-negative; the message names `name`.
pub fn choose_windows(
    radiance: &ShCoeffs<DVec3>,
    s: &ProjectSettings,
    name: &str,
) -> Result<[Window; 3]> {
    let target = match s.quantity {
        Quantity::Radiance => WindowTarget::Function,
        Quantity::Irradiance => WindowTarget::Irradiance,
    };
    match s.window {
        Some(w) => Ok([w; 3]),
        None => auto_windows(radiance, WindowFamily::Hanning, target).map_err(|e| {
            PipelineError::new(crate::error_chain(&e)).context(format!("{name}: --window auto"))
        }),
    }
}

/// The coefficient file of a projection: each channel windowed by its
/// window, then rotated by the settings' rotation (errors by
/// [`rotate_std_error`]), then made irradiance if asked
/// (`E_l^m = A_l L_l^m`, errors scaled by `|A_l|`), with the provenance of
/// the input, the method and every setting.
#[must_use]
pub fn coefficient_file(
    projection: &Projection,
    windows: [Window; 3],
    s: &ProjectSettings,
    info: &MapInfo,
) -> CoeffFile {
    let mut radiance = apply_channel_windows(&windows, &projection.coeffs);
    // Window factors lie in [0, 1], so errors scale by them as they are.
    let mut std_error = projection
        .std_error
        .as_ref()
        .map(|se| apply_channel_windows(&windows, se));
    if let Some((_, matrix)) = &s.rotation {
        radiance = rotate_once(&radiance, *matrix);
        std_error =
            std_error.map(|se| rotate_std_error(&ShRotation::from_mat3(se.lmax(), *matrix), &se));
    }
    let coeffs = match s.quantity {
        Quantity::Radiance => radiance,
        Quantity::Irradiance => {
            std_error =
                std_error.map(|se| se.scaled_per_band(|l| clamped_cosine_eigenvalue(l).abs()));
            irradiance(&radiance)
        }
    };
    let mut file = CoeffFile::new(coeffs, s.orientation.frame, s.quantity);
    file.mirror = s.orientation.mirror;
    file.provenance = Provenance {
        input: info.name.clone(),
        width: info.width,
        height: info.height,
        layout: info.layout.clone(),
        method: s.method.name().into(),
        window: match s.window {
            Some(w) => w.to_string(),
            None => "auto".into(),
        },
        windows: windows.map(|w| w.to_string()),
        samples: projection.samples,
        seed: projection.seed,
        sampler: projection.sampler.clone(),
        rotate: s.rotation.as_ref().map(|(r, _)| r.clone()),
    };
    file.input_negative_texels = info.stats.negative;
    file.input_min_value = f64::from(info.stats.min_value);
    file.sanitized = info.sanitized;
    file.std_error = std_error;
    file
}
