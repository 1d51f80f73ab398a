//! [`choose_windows`]: the ringing window of each colour channel, the step
//! between the projection and the coefficient file.

use glam::DVec3;
use shlight_core::sh::{ShCoeffs, Window, WindowFamily, WindowTarget, auto_windows};
use shlight_format::Quantity;

use crate::settings::ProjectSettings;
use crate::spelling::Spelling;
use crate::{PipelineError, Result};

/// The window of each colour channel: the settings' window for all three,
/// or (`window: None`, `auto`) per channel the weakest Hanning window that
/// makes that channel's result non-negative: the function itself for
/// radiance, its irradiance for irradiance
/// ([`shlight_core::sh::auto_windows`]).
///
/// # Errors
/// No Hanning window makes a channel non-negative; the message names `name`
/// and the setting as `spelling` does.
pub fn choose_windows(
    radiance: &ShCoeffs<DVec3>,
    s: &ProjectSettings,
    name: &str,
    spelling: Spelling,
) -> Result<[Window; 3]> {
    let target = match s.quantity {
        Quantity::Radiance => WindowTarget::Function,
        Quantity::Irradiance => WindowTarget::Irradiance,
    };
    match s.window {
        Some(w) => Ok([w; 3]),
        None => auto_windows(radiance, WindowFamily::Hanning, target).map_err(|e| {
            PipelineError::new(crate::error_chain(&e)).context(format!(
                "{name}: {}",
                spelling.option_value("window", "auto")
            ))
        }),
    }
}
