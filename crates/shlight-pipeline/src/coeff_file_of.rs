//! [`coeff_file_of`]: the coefficient file of a projection (windows,
//! rotation, quantity, and its provenance: the input map's [`MapInfo`]).

use shlight_core::sh::Window;
use shlight_format::{CoeffFile, Provenance, Quantity};

use crate::map_info::MapInfo;
use crate::projector::Projection;
use crate::settings::ProjectSettings;

/// The coefficient file of a projection: each channel windowed by its
/// window ([`CoeffFile::windowed`]), then rotated by the settings' rotation
/// ([`CoeffFile::rotated`]), then made irradiance if asked
/// ([`CoeffFile::to_irradiance`]: `E_l^m = A_l L_l^m`, errors scaled by
/// `|A_l|`), with the provenance of the input, the method and every
/// setting.
#[must_use]
pub fn coeff_file_of(
    projection: &Projection,
    windows: [Window; 3],
    s: &ProjectSettings,
    info: &MapInfo,
) -> CoeffFile {
    let mut file = CoeffFile::new(
        projection.coeffs.clone(),
        s.orientation.frame,
        Quantity::Radiance,
    );
    file.mirror = s.orientation.mirror;
    file.std_error.clone_from(&projection.std_error);
    file.provenance = Provenance {
        input: info.name.clone(),
        width: info.width,
        height: info.height,
        layout: info.layout.clone(),
        method: s.method.name().into(),
        window: "none".into(),
        windows: ["none".into(), "none".into(), "none".into()],
        samples: projection.samples,
        seed: projection.seed,
        sampler: projection.sampler.clone(),
        rotate: None,
    };
    file.input_negative_texels = info.stats.negative;
    file.input_min_value = f64::from(info.stats.min_value);
    file.sanitized = info.sanitized;
    let spec = match s.window {
        Some(w) => w.to_string(),
        None => "auto".into(),
    };
    file = file.windowed(windows, &spec);
    if let Some((record, matrix)) = &s.rotation {
        file = file.rotated(*matrix, &record.spec);
    }
    match s.quantity {
        Quantity::Radiance => file,
        Quantity::Irradiance => file
            .to_irradiance()
            .expect("plain SH radiance turns into irradiance"),
    }
}
