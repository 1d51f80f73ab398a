//! [`light_of`]: the distant light a baked file is shaded or relit with,
//! as Python gives it (a path, or an `SH` of radiance).

use std::path::PathBuf;

use glam::DVec3;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use shlight_core::sh::ShCoeffs;
use shlight_format::Quantity;
use shlight_pipeline::Environment;

use crate::errors::{pipeline_error, shlight_error};
use crate::guard::guard;
use crate::options::frame_of;
use crate::sh::Sh;

/// The light a volume is relit with: a path (an equirect map or a radiance
/// coefficient file, read as `shlight sample --env` reads it) or an `SH` of
/// plain radiance; radiance coefficients in the volume's frame, and the
/// warnings of reading them.
pub fn light_of(
    py: Python<'_>,
    env: &Bound<'_, PyAny>,
    up: &str,
) -> PyResult<(ShCoeffs<DVec3>, Vec<String>)> {
    if let Ok(sh) = env.cast::<Sh>() {
        let sh = sh.get();
        sh.plain("relight")?;
        if sh.file().quantity != Quantity::Radiance {
            return Err(shlight_error(
                "relight takes radiance; this SH holds irradiance (project with quantity=\"radiance\")",
            ));
        }
        return Ok((sh.file().coeffs.clone(), Vec::new()));
    }
    let path = env.extract::<PathBuf>().map_err(|_| {
        PyValueError::new_err(
            "env must be a path (an equirect map or a radiance coefficient file) or an SH of radiance",
        )
    })?;
    let up = frame_of(up)?;
    let env = py.detach(|| {
        guard(|| Environment::load(&path, up, shlight_baked::MAX_LMAX).map_err(pipeline_error))
    })?;
    Ok((env.radiance, env.warnings))
}
