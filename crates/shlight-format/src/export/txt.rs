//! `txt`: a table in the style of Ramamoorthi & Hanrahan 2001 (their
//! Figure 2 / Grace Cathedral table): one line per coefficient, named
//! `L00, L1-1, L10, L11, L2-2, ...`, then red, green, blue.
//!
//! # What the numbers are
//!
//! - **Quantity**: the file's own (radiance `L_lm = int L(w) Y_lm(w) dw`, or
//!   irradiance `E_lm = A_l L_lm`), stated in the header; any lmax.
//! - **Basis**: real orthonormal SH **without** the Condon-Shortley phase,
//!   as R&H's tables (R. Ramamoorthi, P. Hanrahan, "An Efficient
//!   Representation for Irradiance Environment Maps", SIGGRAPH 2001, eq. 3:
//!   `Y_11 = 0.488603 x`, `Y_21 = 1.092548 xz`, ...) and three.js. Every
//!   coefficient with odd `|m|` has the opposite sign of shlight's own
//!   (`shlight show`) table.
//! - **Frame**: the file's (y-up or z-up), named in the header; `(x, y, z)`
//!   in the R&H polynomial are those world axes. R&H's own published
//!   numbers are in the z-up frame of their light probes.
//! - For a radiance table of lmax 2 the header repeats R&H's eq. 13, which
//!   turns the nine numbers into irradiance:
//!   `E(n) = c1 L22 (x^2-y^2) + c3 L20 z^2 + c4 L00 - c5 L20
//!          + 2 c1 (L2-2 xy + L21 xz + L2-1 yz) + 2 c2 (L11 x + L1-1 y + L10 z)`.

use shlight_core::sh::lm_from_index;

use super::{ExportInput, Exported, frame_words};
use crate::Quantity;

/// Renders the table.
pub fn render(input: &ExportInput<'_>) -> Exported {
    let c = input.coeffs.toggled_cs_phase();
    let lmax = c.lmax();
    let (what, definition) = match input.quantity {
        Quantity::Radiance => ("radiance", "L_lm = integral of L(w) Y_lm(w) dw"),
        Quantity::Irradiance => (
            "irradiance",
            "E_lm = A_l L_lm, so E(n) = sum E_lm Y_lm(n) with E(n) = integral of L(w) max(n.w, 0) dw",
        ),
    };
    let mut s = format!(
        "# shlight SH {what}, lmax {lmax} ({} coefficients), Ramamoorthi-Hanrahan table layout\n\
         # quantity: {what}, {definition}\n\
         # basis: real orthonormal SH WITHOUT the Condon-Shortley phase (Ramamoorthi & Hanrahan 2001, three.js):\n\
         #   Y00 = 0.282095, Y1-1 = 0.488603 y, Y10 = 0.488603 z, Y11 = 0.488603 x, Y2-2 = 1.092548 xy,\n\
         #   Y2-1 = 1.092548 yz, Y20 = 0.315392 (3z^2 - 1), Y21 = 1.092548 xz, Y22 = 0.546274 (x^2 - y^2)\n\
         #   (shlight's own files carry the phase: odd-|m| coefficients there have the opposite sign)\n\
         # frame: {}; (x, y, z) are those world axes\n\
         # colour: linear Rec.709 RGB\n",
        c.len(),
        frame_words(input.frame),
    );
    if input.quantity == Quantity::Radiance && lmax == 2 {
        s.push_str(
            "# irradiance (R&H eq. 13): E(n) = c1 L22 (x^2-y^2) + c3 L20 z^2 + c4 L00 - c5 L20\n\
             #   + 2 c1 (L2-2 xy + L21 xz + L2-1 yz) + 2 c2 (L11 x + L1-1 y + L10 z),\n\
             #   c1 = 0.429043, c2 = 0.511664, c3 = 0.743125, c4 = 0.886227, c5 = 0.247708\n",
        );
    }
    s.push_str(&format!(
        "# {:<6} {:>16} {:>16} {:>16}\n",
        "coeff", "red", "green", "blue"
    ));
    for (i, v) in c.as_slice().iter().enumerate() {
        let (l, m) = lm_from_index(i);
        s.push_str(&format!(
            "{:<8} {:>16.8e} {:>16.8e} {:>16.8e}\n",
            format!("L{l}{m}"),
            v.x,
            v.y,
            v.z
        ));
    }
    Exported {
        text: s,
        notes: Vec::new(),
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;
    use shlight_core::sh::{Frame, ShCoeffs};

    use super::*;

    /// R&H's Grace Cathedral coefficients (no CS phase, z-up), as published.
    const GRACE: [[f64; 3]; 9] = [
        [0.78908, 0.43710, 0.54161],
        [0.39499, 0.34989, 0.60488],
        [-0.33974, -0.18236, -0.26940],
        [-0.29213, -0.05562, 0.00944],
        [-0.11141, -0.05090, -0.12231],
        [-0.26240, -0.22401, -0.47479],
        [-0.15570, -0.09471, -0.14733],
        [0.56014, 0.21444, 0.13915],
        [0.21205, -0.05432, -0.30374],
    ];

    #[test]
    fn grace_cathedral_comes_out_as_published() {
        // Stored the shlight way (with the CS phase), written the R&H way.
        let published =
            ShCoeffs::from_vec(GRACE.iter().map(|c| DVec3::from(*c)).collect()).unwrap();
        let ours = published.toggled_cs_phase();
        let out = render(&ExportInput {
            coeffs: &ours,
            quantity: Quantity::Radiance,
            frame: Frame::ZUp,
        });
        let rows: Vec<(String, [f64; 3])> = out
            .text
            .lines()
            .filter(|l| !l.starts_with('#'))
            .map(|l| {
                let f: Vec<&str> = l.split_whitespace().collect();
                (
                    f[0].to_string(),
                    [
                        f[1].parse().unwrap(),
                        f[2].parse().unwrap(),
                        f[3].parse().unwrap(),
                    ],
                )
            })
            .collect();
        let names = [
            "L00", "L1-1", "L10", "L11", "L2-2", "L2-1", "L20", "L21", "L22",
        ];
        for (i, (name, v)) in rows.iter().enumerate() {
            assert_eq!(name, names[i]);
            for k in 0..3 {
                assert!((v[k] - GRACE[i][k]).abs() < 1e-9, "{name}");
            }
        }
        assert!(out.text.contains("z-up") && out.text.contains("WITHOUT"));
    }
}
