//! Windowing, rotation and irradiance of a coefficient file: the light
//! changed, its standard errors carried along, and the change recorded in
//! the provenance. `shlight project` (through shlight-pipeline) and the
//! Python package's `Sh` both use these, so a file changed either way is
//! the same file.

use glam::DMat3;
use shlight_core::sh::{
    ShRotation, Window, WindowFamily, WindowTarget, apply_channel_windows, auto_windows,
    clamped_cosine_eigenvalue, irradiance, rotate_once, rotate_std_error,
};

use crate::{CoeffFile, FormatError, Quantity, Result, RotationRecord};

impl CoeffFile {
    /// The windows `spec` names for this file's three channels: one window
    /// for all (`none`, `hanning:W`, `lanczos:W`, `laplacian:LAMBDA`), or for
    /// `auto` per channel the weakest Hanning window that makes `target`
    /// (the function itself, or its irradiance) non-negative
    /// ([`shlight_core::sh::auto_windows`]).
    ///
    /// # Errors
    /// A spec that names no window, or no Hanning window that makes a
    /// channel non-negative; the message starts with `window SPEC` (a
    /// front end names the setting its own way before it).
    pub fn windows_for(&self, spec: &str, target: WindowTarget) -> Result<[Window; 3]> {
        let spec = spec.trim();
        if spec == "auto" {
            return auto_windows(&self.coeffs, WindowFamily::Hanning, target)
                .map_err(|e| FormatError::Export(format!("window auto: {e}")));
        }
        let w = spec
            .parse::<Window>()
            .map_err(|e| FormatError::Export(format!("window {spec}: {e}")))?;
        Ok([w; 3])
    }

    /// Each channel multiplied by its window's factors (red, green, blue),
    /// standard errors too (the factors lie in `[0, 1]`). The provenance
    /// records `spec` as the window asked for and each channel's window; a
    /// file already windowed records both, `"FIRST, then SECOND"`.
    #[must_use]
    pub fn windowed(&self, windows: [Window; 3], spec: &str) -> CoeffFile {
        let spec = spec.trim();
        let mut out = self.clone();
        out.coeffs = apply_channel_windows(&windows, &self.coeffs);
        out.std_error = self
            .std_error
            .as_ref()
            .map(|se| apply_channel_windows(&windows, se));
        let p = &mut out.provenance;
        let first = p.window == "none" || p.window.is_empty();
        p.window = if first {
            spec.to_string()
        } else {
            format!("{}, then {spec}", p.window)
        };
        for (old, new) in p.windows.iter_mut().zip(windows) {
            *old = if first || old == "none" {
                new.to_string()
            } else {
                format!("{old}, then {new}")
            };
        }
        out
    }

    /// The light turned by the rotation `matrix` (acting on column vectors:
    /// a light from `a` comes from `matrix * a` afterwards), standard
    /// errors by [`rotate_std_error`]. The provenance records `spec` and the
    /// matrix; a file already rotated records the two composed
    /// (`"FIRST, then SECOND"`, the product of the matrices).
    #[must_use]
    pub fn rotated(&self, matrix: DMat3, spec: &str) -> CoeffFile {
        let spec = spec.trim();
        let mut out = self.clone();
        out.coeffs = rotate_once(&self.coeffs, matrix);
        out.std_error = self
            .std_error
            .as_ref()
            .map(|se| rotate_std_error(&ShRotation::from_mat3(se.lmax(), matrix), se));
        let (spec, total) = match &self.provenance.rotate {
            None => (spec.to_string(), matrix),
            Some(old) => {
                let before = DMat3::from_cols_array_2d(&old.matrix).transpose();
                (format!("{}, then {spec}", old.spec), matrix * before)
            }
        };
        out.provenance.rotate = Some(RotationRecord {
            spec,
            matrix: total.transpose().to_cols_array_2d(),
        });
        out
    }

    /// The irradiance of a radiance file (Ramamoorthi & Hanrahan 2001:
    /// `E_l^m = A_l L_l^m`, [`irradiance`]), standard errors scaled by
    /// `|A_l|`; a file that holds irradiance comes back as it is.
    ///
    /// # Errors
    /// A file whose light is an encoding other than plain SH (its
    /// coefficients alone are not the light).
    pub fn to_irradiance(&self) -> Result<CoeffFile> {
        if self.quantity == Quantity::Irradiance {
            return Ok(self.clone());
        }
        if self.encoding.encoding() != shlight_core::encoding::Encoding::Sh {
            return Err(FormatError::Export(format!(
                "the light is kept as {}; only plain SH radiance turns into irradiance coefficients",
                self.encoding.encoding()
            )));
        }
        let mut out = self.clone();
        out.coeffs = irradiance(&self.coeffs);
        out.std_error = self
            .std_error
            .as_ref()
            .map(|se| se.scaled_per_band(|l| clamped_cosine_eigenvalue(l).abs()));
        out.quantity = Quantity::Irradiance;
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;
    use shlight_core::sh::{Frame, ShCoeffs, closed_form};

    fn sun_file() -> CoeffFile {
        let dir = DVec3::new(0.3, 0.8, -0.52).normalize();
        let c: ShCoeffs<f64> = closed_form::directional(4, dir, 2.0);
        let coeffs = c.map(|v| DVec3::new(v, 0.5 * v, 0.25 * v));
        let mut f = CoeffFile::new(coeffs, Frame::YUp, Quantity::Radiance);
        f.std_error = Some(f.coeffs.scaled_per_band(|l| 0.01 * (l + 1) as f64));
        f
    }

    /// Irradiance of a band-limited sun is the clamped cosine's closed
    /// form per band: `E_l^m = A_l L_l^m` with `A_0 = pi`, `A_1 = 2 pi / 3`,
    /// `A_2 = pi / 4`, `A_3 = 0`, `A_4 = -pi / 24`; errors scale by `|A_l|`.
    #[test]
    fn irradiance_scales_each_band_by_the_clamped_cosine() {
        use std::f64::consts::PI;
        let f = sun_file();
        let e = f.to_irradiance().unwrap();
        assert_eq!(e.quantity, Quantity::Irradiance);
        let a = [PI, 2.0 * PI / 3.0, PI / 4.0, 0.0, -PI / 24.0];
        for l in 0..=4usize {
            for m in -(l as i64)..=(l as i64) {
                let k = (l * (l + 1)) as i64 + m;
                let (got, want) = (e.coeffs[k as usize], f.coeffs[k as usize] * a[l]);
                assert!(
                    (got - want).abs().max_element() < 1e-13,
                    "l {l}: {got} {want}"
                );
                let (se, se0) = (
                    e.std_error.as_ref().unwrap()[k as usize],
                    f.std_error.as_ref().unwrap()[k as usize],
                );
                assert!((se - se0 * a[l].abs()).abs().max_element() < 1e-15);
            }
        }
        // An irradiance file comes back as it is.
        assert_eq!(
            e.to_irradiance().unwrap().to_json_string(),
            e.to_json_string()
        );
    }

    /// A rotation turns the sun's direction: the rotated expansion equals
    /// the closed form of the turned sun; two rotations compose in the
    /// record and equal one by their product.
    #[test]
    fn rotations_turn_the_light_and_compose_in_the_record() {
        let f = sun_file();
        let r1 = DMat3::from_rotation_y(0.7);
        let r2 = DMat3::from_rotation_x(-0.4);
        let once = f.rotated(r1, "yaw:40").rotated(r2, " pitch:-23 ");
        let both = f.rotated(r2 * r1, "both");
        for (a, b) in once.coeffs.as_slice().iter().zip(both.coeffs.as_slice()) {
            assert!((*a - *b).abs().max_element() < 1e-12);
        }
        let dir = DVec3::new(0.3, 0.8, -0.52).normalize();
        let turned: ShCoeffs<f64> = closed_form::directional(4, r2 * r1 * dir, 2.0);
        for (a, b) in once.coeffs.as_slice().iter().zip(turned.as_slice()) {
            assert!((a.x - b).abs() < 1e-12, "{a} {b}");
        }
        let rec = once.provenance.rotate.as_ref().unwrap();
        assert_eq!(rec.spec, "yaw:40, then pitch:-23");
        let m = DMat3::from_cols_array_2d(&rec.matrix).transpose();
        assert!((m - r2 * r1).abs_diff_eq(DMat3::ZERO, 1e-15));
    }

    /// Windows scale band `l` by the window's factor, per channel, and the
    /// record keeps every window applied.
    #[test]
    fn windows_scale_bands_and_are_recorded() {
        let f = sun_file();
        let w: [Window; 3] = [
            "hanning:5".parse().unwrap(),
            Window::None,
            "lanczos:6".parse().unwrap(),
        ];
        let out = f.windowed(w, "mixed");
        for l in 0..=4usize {
            let k = l * (l + 1);
            for (c, win) in w.iter().enumerate() {
                let want = f.coeffs[k][c] * win.factor(l);
                assert!((out.coeffs[k][c] - want).abs() < 1e-15);
            }
        }
        assert_eq!(out.provenance.window, "mixed");
        let again = out.windowed([Window::None; 3], "none");
        assert_eq!(again.provenance.window, "mixed, then none");
        assert_eq!(again.provenance.windows[0], "hanning:5, then none");
        assert_eq!(again.provenance.windows[1], "none");
        assert!(f.windows_for("hanning:x", WindowTarget::Function).is_err());
        let auto = f.windows_for("auto", WindowTarget::Function).unwrap();
        assert!(auto.iter().all(|w| *w != Window::None));
    }
}
