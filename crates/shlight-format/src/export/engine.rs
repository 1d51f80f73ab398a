//! What the lmax-2 engine formats (three.js, glTF, Filament, Unity) share:
//! the coefficients they start from and the constants of the basis
//! polynomials their shaders evaluate.

use glam::DVec3;
use shlight_core::ShCoeffs;
use shlight_core::rotation::{Frame, ShRotation};

use super::ExportInput;
use crate::{Quantity, Result};

/// `k_i`, the constant of the basis polynomial in shlight's basis (CS
/// phase), `Y_i(n) = k_i p_i(n)` with
/// `p = (1, y, z, x, xy, yz, 3z^2 - 1, xz, x^2 - y^2)`, `i = 0..9`.
///
/// These are Filament's `preprocessSHForShader` factors `A[i]` and HDRP's
/// `SphericalHarmonicMath.ks` (both with the signs of the CS phase).
pub(crate) fn basis_constant(i: usize) -> f64 {
    let pi = std::f64::consts::PI;
    let k0 = 0.5 / pi.sqrt();
    let k1 = 3f64.sqrt() / (2.0 * pi.sqrt());
    let k2 = 15f64.sqrt() / (2.0 * pi.sqrt());
    let k20 = 5f64.sqrt() / (4.0 * pi.sqrt());
    let k22 = 15f64.sqrt() / (4.0 * pi.sqrt());
    [k0, -k1, k1, -k1, k2, -k2, k20, -k2, k22][i]
}

/// The polynomials `p_i(n)` of [`basis_constant`].
#[cfg(test)]
pub(crate) fn basis_polynomial(n: [f64; 3]) -> [f64; 9] {
    let [x, y, z] = n;
    [
        1.0,
        y,
        z,
        x,
        x * y,
        y * z,
        3.0 * z * z - 1.0,
        x * z,
        x * x - y * y,
    ]
}

/// The coefficients an lmax-2, y-up engine format starts from: truncated or
/// zero-padded to lmax 2 (with a note), turned to the y-up frame, converted
/// to `want`.
pub(crate) fn engine_coeffs(
    input: &ExportInput<'_>,
    want: Quantity,
    format: &str,
) -> Result<(ShCoeffs<DVec3>, Vec<String>)> {
    let mut notes = Vec::new();
    let lmax = input.coeffs.lmax();
    if lmax > 2 {
        notes.push(format!(
            "{format} holds lmax 2 (9 coefficients): degrees 3..={lmax} of the input are dropped"
        ));
    } else if lmax < 2 {
        notes.push(format!(
            "{format} holds lmax 2: the input has lmax {lmax}, the missing degrees are written as \
             zeros (the same function)"
        ));
    }
    let c = input.coeffs.resized(2);
    let c = to_frame(&c, input.frame, Frame::YUp);
    let c = crate::convert_quantity(&c, input.quantity, want)?;
    Ok((c, notes))
}

/// The same function in another frame's world axes.
pub(crate) fn to_frame(coeffs: &ShCoeffs<DVec3>, from: Frame, to: Frame) -> ShCoeffs<DVec3> {
    if from == to {
        coeffs.clone()
    } else {
        ShRotation::between_frames(coeffs.lmax(), from, to).apply(coeffs)
    }
}

/// `"y-up"` / `"z-up"` with the axis the map's top row faces.
pub(crate) fn frame_words(frame: Frame) -> &'static str {
    match frame {
        Frame::YUp => "y-up (world +Y up; three.js / glTF equirect mapping)",
        Frame::ZUp => "z-up (world +Z up; Blender equirect mapping)",
    }
}

/// A float array literal for JSON and messages.
pub(crate) fn rgb_array(v: DVec3) -> [f64; 3] {
    [v.x, v.y, v.z]
}
