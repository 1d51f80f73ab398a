//! `filament`: the `sh.txt` that Filament's `cmgen --sh-shader` (and
//! `cmgen --deploy`) writes, the input of
//! `IndirectLight::Builder::irradiance(3, sh)`.
//!
//! # Format
//!
//! Nine lines, exactly as cmgen's `outputSh` (`tools/cmgen/src/cmgen.cpp`)
//! prints them (`std::fixed`, `setprecision(15)`, `setw(18)`):
//!
//! ```text
//! ( 0.123456789012345,  0.123456789012345,  0.123456789012345); // L00, irradiance, pre-scaled base
//! (-0.012345678901234, ...); // L1-1, irradiance, pre-scaled base
//! ```
//!
//! No header line: loaders parse the nine lines as they come.
//!
//! # What the numbers are
//!
//! `sh_i = E_i k_i / pi`, `i = l(l+1)+m`, where `E_i = A_l L_i` are the
//! irradiance coefficients in the basis with the Condon-Shortley phase and
//! `k_i` the constant of the basis polynomial,
//! `Y_i(n) = k_i p_i(n)`, `p = (1, y, z, x, yx, yz, 3z^2-1, zx, x^2-y^2)`,
//! `k = (1/(2 sqrt pi), -sqrt3/(2 sqrt pi), sqrt3/(2 sqrt pi), -sqrt3/(2 sqrt pi),
//! sqrt15/(2 sqrt pi), -sqrt15/(2 sqrt pi), sqrt5/(4 sqrt pi), -sqrt15/(2 sqrt pi),
//! sqrt15/(4 sqrt pi))`.
//!
//! Source: `libs/ibl/src/CubemapSH.cpp`: `computeSH(..., irradiance = true)`
//! multiplies each band by `computeTruncatedCosSh(l)` (`pi, 2pi/3, pi/4`,
//! i.e. `A_l`); `preprocessSHForShader` multiplies coefficient `i` by its
//! `A[i]` (the `k_i` above, with the CS signs) and by `F_1_PI`, "the
//! lambertian diffuse BRDF 1/pi". The shader (`shaders/src/light_indirect.fs`,
//! `Irradiance_SphericalHarmonics`) computes
//! `max(sum_i sh[i] p_i(n), 0)` at the world normal, with the `p_i` above
//! spelled out (`sh[4] * (n.y * n.x)`, `sh[6] * (3.0 * n.z * n.z - 1.0)`,
//! ...), which is therefore `E(n) / pi`: the radiance a white Lambertian
//! surface reflects (Filament multiplies by the diffuse colour only).
//!
//! - **Frame**: Filament's world, right-handed, +Y up, with the map where
//!   cmgen puts it: its `equirectangularToCubemap` puts the image centre at
//!   +Z (`u = 0.5 + atan2(x, z) / 2pi`) and then mirrors x by default
//!   (`mirrorCubemap`), so the texel shlight's y-up frame reads at
//!   `(x, y, z)` is at `(-z, y, x)` for cmgen, a quarter turn about +Y,
//!   which the export applies ([`super::engine_frame`]): the light lines up
//!   with a cmgen skybox of the same image. A z-up file is turned to y-up
//!   first; reading back turns the other way.
//! - **lmax 2** exactly (the shader form exists for 3 bands only).
//!
//! # Reading back
//!
//! [`read`] takes pre-scaled files (`L00, irradiance, pre-scaled base`) to
//! irradiance, and plain radiance files (`cmgen --sh=N --sh-output=f.txt`,
//! lines named `L00`) to radiance. Files marked `irradiance` without
//! `pre-scaled base` are refused: cmgen versions disagree on a `1/pi` there.

use crate::{FormatError, Result};
use glam::DVec3;
use shlight_core::sh::{Frame, ShCoeffs, lm_from_index, lmax_from_count};

use super::{
    ExportFormat, ExportInput, Exported, basis_constant, engine_coeffs, engine_frame, transform,
};
use crate::{Imported, Quantity};

/// Renders sh.txt.
pub fn render(input: &ExportInput<'_>) -> Result<Exported> {
    let (e, notes) = engine_coeffs(input, Quantity::Irradiance, ExportFormat::Filament)?;
    let mut text = String::new();
    for (i, v) in e.as_slice().iter().enumerate() {
        let (l, m) = lm_from_index(i);
        let s = *v * (basis_constant(i) / std::f64::consts::PI);
        text.push_str(&format!(
            "({:18.15}, {:18.15}, {:18.15}); // L{l}{m}, irradiance, pre-scaled base\n",
            s.x, s.y, s.z
        ));
    }
    Ok(Exported { text, notes })
}

/// Coefficients in Filament's world back in shlight's y-up frame: the
/// inverse of [`engine_frame`]'s quarter turn.
fn from_filament(c: &ShCoeffs<DVec3>) -> ShCoeffs<DVec3> {
    let m = engine_frame(ExportFormat::Filament).expect("an engine");
    transform(c, m.transpose())
}

/// Reads an sh.txt back (see the module documentation for which).
pub fn read(text: &str, name: &str) -> Result<Imported> {
    let mut values = Vec::new();
    let mut kinds = Vec::new();
    for (k, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() {
            continue;
        }
        let bad = || {
            FormatError::invalid(
                name,
                format!("line {}: expected \"(r, g, b); // Llm...\"", k + 1),
            )
        };
        let rest = line.strip_prefix('(').ok_or_else(bad)?;
        let (numbers, comment) = rest.split_once(')').ok_or_else(bad)?;
        let v: Vec<f64> = numbers
            .split(',')
            .map(|s| s.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|_| bad())?;
        let [r, g, b] = v[..] else { return Err(bad()) };
        values.push(DVec3::new(r, g, b));
        let comment = comment
            .trim_start_matches(';')
            .trim()
            .trim_start_matches("//")
            .trim();
        let i = values.len() - 1;
        let (l, m) = lm_from_index(i);
        let label = format!("L{l}{m}");
        let mut parts = comment.split(',').map(str::trim);
        if parts.next() != Some(label.as_str()) {
            return Err(FormatError::invalid(
                name,
                format!(
                    "line {}: expected coefficient {label}, found {comment:?}",
                    k + 1
                ),
            ));
        }
        let flags: Vec<&str> = parts.collect();
        kinds.push((
            flags.contains(&"irradiance"),
            flags.contains(&"pre-scaled base"),
        ));
    }
    let Some(lmax) = lmax_from_count(values.len()).filter(|_| !values.is_empty()) else {
        return Err(FormatError::invalid(
            name,
            format!(
                "{} coefficients is not a whole number of bands (1, 4, 9, ...)",
                values.len()
            ),
        ));
    };
    let kind = kinds[0];
    if kinds.iter().any(|k| *k != kind) {
        return Err(FormatError::invalid(
            name,
            "lines disagree on irradiance / pre-scaled".to_string(),
        ));
    }
    let coeffs = ShCoeffs::from_vec(values).expect("square count");
    match kind {
        (true, true) => {
            if lmax != 2 {
                return Err(FormatError::invalid(
                    name,
                    format!("pre-scaled sh.txt has 9 lines, found {}", coeffs.len()),
                ));
            }
            let pi = std::f64::consts::PI;
            let mut e = coeffs;
            for (i, v) in e.as_mut_slice().iter_mut().enumerate() {
                *v *= pi / basis_constant(i);
            }
            Ok(Imported {
                coeffs: from_filament(&e),
                quantity: Quantity::Irradiance,
                frame: Frame::YUp,
                source: "Filament sh.txt (pre-scaled irradiance)",
            })
        }
        (false, false) => Ok(Imported {
            coeffs: from_filament(&coeffs),
            quantity: Quantity::Radiance,
            frame: Frame::YUp,
            source: "Filament sh.txt (radiance)",
        }),
        (true, false) => Err(FormatError::invalid(
            name,
            "irradiance coefficients that are not pre-scaled: cmgen versions differ by a \
             factor 1/pi there; write them with --sh-shader (pre-scaled) or as radiance"
                .to_string(),
        )),
        (false, true) => Err(FormatError::invalid(
            name,
            "pre-scaled but not irradiance: not something cmgen writes".to_string(),
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::export::basis_polynomial;

    /// Filament's `Irradiance_SphericalHarmonics`, without the clamp at 0.
    fn irradiance_sh(sh: &[DVec3], n: [f64; 3]) -> DVec3 {
        let p = basis_polynomial(n);
        (0..9).map(|i| sh[i] * p[i]).sum()
    }

    #[test]
    fn the_shader_gives_irradiance_over_pi_and_reads_back() {
        let radiance = &shlight_core::sh::closed_form::directional(
            2,
            DVec3::new(0.6, 0.0, -0.8),
            DVec3::new(2.0, 1.0, 0.5),
        ) + &shlight_core::sh::closed_form::constant(2, DVec3::splat(0.25));
        let out = render(&ExportInput {
            coeffs: &radiance,
            quantity: Quantity::Radiance,
            frame: Frame::YUp,
        })
        .unwrap();
        assert_eq!(out.text.lines().count(), 9);
        let sh: Vec<DVec3> = out
            .text
            .lines()
            .map(|l| {
                let inner = &l[1..l.find(')').unwrap()];
                let v: Vec<f64> = inner
                    .split(',')
                    .map(|s| s.trim().parse().unwrap())
                    .collect();
                DVec3::new(v[0], v[1], v[2])
            })
            .collect();
        let e = shlight_core::sh::irradiance(&radiance);
        for n in [[0.6, 0.0, -0.8], [0.0, 1.0, 0.0], [-0.48, 0.6, 0.64]] {
            // cmgen shows the texel shlight reads at (x, y, z) at (-z, y, x).
            let [x, y, z] = n;
            let got = irradiance_sh(&sh, [-z, y, x]);
            let want = e.eval(DVec3::from(n)) / std::f64::consts::PI;
            assert!((got - want).abs().max_element() < 1e-13, "{got} vs {want}");
        }
        let back = read(&out.text, "sh.txt").unwrap();
        assert_eq!(back.quantity, Quantity::Irradiance);
        for (a, b) in back.coeffs.as_slice().iter().zip(e.as_slice()) {
            assert!((*a - *b).abs().max_element() < 1e-13);
        }
    }

    #[test]
    fn ambiguous_and_broken_files_are_refused() {
        let err = read("( 1.0, 2.0, 3.0); // L00, irradiance\n", "a.txt").unwrap_err();
        assert!(
            err.to_string().contains("a.txt") && err.to_string().contains("1/pi"),
            "{err}"
        );
        let err = read("( 1.0, 2.0); // L00\n", "b.txt").unwrap_err();
        assert!(err.to_string().contains("b.txt: line 1"), "{err}");
        let err = read("( 1.0, 2.0, 3.0); // L1-1\n", "c.txt").unwrap_err();
        assert!(
            err.to_string().contains("expected coefficient L00"),
            "{err}"
        );
        let r = read("( 1.0, 2.0, 3.0); // L00\n", "d.txt").unwrap();
        assert_eq!(r.quantity, Quantity::Radiance);
        assert_eq!(r.coeffs.lmax(), 0);
    }
}
