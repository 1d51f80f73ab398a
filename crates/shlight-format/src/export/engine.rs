//! What the lmax-2 engine formats (three.js, glTF, Filament, Unity) share:
//! the coefficients they start from and the constants of the basis
//! polynomials their shaders evaluate.

use glam::{DMat3, DVec3};
use shlight_core::sh::{Frame, ShCoeffs, ShRotation};

use super::{ExportFormat, ExportInput};
use crate::{Quantity, Result};

/// How an engine shows the equirect map that shlight reads in its y-up
/// frame: the texel shlight puts at direction `d` (docs/conventions.md)
/// is where the engine puts it at `M d`, in the engine's own world axes.
/// `None` for formats that keep the file's own frame (txt and the shader
/// snippets).
///
/// | format | engine, and the mapping it uses | `M d` for `d = (x, y, z)` |
/// |---|---|---|
/// | `threejs` | three.js `equirectUv` (backgrounds, PMREM, `LightProbeGenerator`) | `(x, y, z)` |
/// | `filament` | Filament `cmgen` (`equirectangularToCubemap`, then its default `mirrorCubemap`) | `(-z, y, x)`: a quarter turn, `yaw:-90` |
/// | `gltf` | Babylon.js, the extension's reference loader, in its default left-handed scene: its own panorama mapping (`PanoramaToCubeMapTools`), and the Khronos glTF Sample Viewer's picture (`panorama_to_cubemap`, `environmentRotation` 90) carried through the loader's root node | `(z, y, x)`: a mirror |
/// | `unity` | Unity `Skybox/Panoramic` (`ToRadialCoords`), left-handed world | `(x, y, -z)`: a mirror |
///
/// Exporting rotates (or, for Unity and glTF, mirrors) the coefficients by `M`, so
/// the light lines up with the engine's own skybox of the same map; reading
/// a file back applies `M^T`. Sources and measurements: docs/exporters.md.
#[must_use]
pub fn engine_frame(format: ExportFormat) -> Option<DMat3> {
    match format {
        ExportFormat::Threejs => Some(DMat3::IDENTITY),
        // (x, y, z) -> (-z, y, x): +X (the image centre) to +Z.
        ExportFormat::Filament => Some(DMat3::from_cols(DVec3::Z, DVec3::Y, DVec3::NEG_X)),
        // (x, y, z) -> (z, y, x): the image centre to +Z of Babylon's
        // left-handed world, which is the glTF world with x mirrored.
        ExportFormat::Gltf => Some(DMat3::from_cols(DVec3::Z, DVec3::Y, DVec3::X)),
        ExportFormat::Unity => Some(DMat3::from_diagonal(DVec3::new(1.0, 1.0, -1.0))),
        _ => None,
    }
}

/// `f` carried by the orthogonal matrix `m` (`g(m d) = f(d)`): a rotation
/// for `det m = +1`; for `det m = -1`, the rotation `-m` followed by the
/// parity `d -> -d`, which multiplies band `l` by `(-1)^l`.
pub(crate) fn transform(f: &ShCoeffs<DVec3>, m: DMat3) -> ShCoeffs<DVec3> {
    if m == DMat3::IDENTITY {
        return f.clone();
    }
    if m.determinant() > 0.0 {
        return ShRotation::from_mat3(f.lmax(), m).apply(f);
    }
    ShRotation::from_mat3(f.lmax(), -m)
        .apply(f)
        .scaled_per_band(|l| if l % 2 == 0 { 1.0 } else { -1.0 })
}

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

/// The coefficients an lmax-2 engine format starts from: truncated or
/// zero-padded to lmax 2 (with a note), turned to the y-up frame, carried
/// into the engine's picture of the map ([`engine_frame`]), converted to
/// `want`.
pub(crate) fn engine_coeffs(
    input: &ExportInput<'_>,
    want: Quantity,
    format: ExportFormat,
) -> Result<(ShCoeffs<DVec3>, Vec<String>)> {
    let m = engine_frame(format).expect("an engine format");
    let format = format.name();
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
    let c = transform(&to_frame(&c, input.frame, Frame::YUp), m);
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
