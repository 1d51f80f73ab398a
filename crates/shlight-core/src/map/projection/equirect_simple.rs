//! [`project_equirect_simple`]: the plain route to the equirect quadrature,
//! the reference the ring transform is tested and benchmarked against.

use glam::DVec3;

use super::pole::to_frame;
use super::rows::{RowState, run_rows};
use crate::map::equirect::{EquirectView, equirect_angles, equirect_row_solid_angle};
use crate::map::orientation::MapOrientation;
use crate::sh::index::sh_index;
use crate::sh::legendre::{Legendre, legendre_count, legendre_index};
use crate::sh::sh_coeffs::ShCoeffs;

/// The same quadrature as [`super::project_equirect`] by the plain route: per row,
/// direct azimuthal sums against a trig table, then one Legendre evaluation
/// per row. `O(W H lmax + H lmax^2)`, no pairing, no FFT, no vector code: the
/// reference the fast path is tested and benchmarked against.
///
/// Panics if `pixels.len() != width * height`.
///
/// A test and benchmark reference, hidden from the documentation.
#[doc(hidden)]
#[must_use]
pub fn project_equirect_simple(
    map: EquirectView<'_>,
    lmax: usize,
    o: MapOrientation,
) -> ShCoeffs<DVec3> {
    let (w, h) = (map.width, map.height);
    assert_eq!(
        map.pixels.len(),
        w * h,
        "pixel count must be width * height"
    );
    let sign = o.pole_azimuth_sign();
    let trig: Vec<[f64; 2]> = (0..=lmax)
        .flat_map(|m| {
            (0..w).map(move |i| {
                let (_, p) = equirect_angles(i, 0, w, h);
                let a = m as f64 * sign * p;
                [a.cos(), a.sin()]
            })
        })
        .collect();
    let legendre = Legendre::<f64>::new(lmax);

    let row = |j: usize, acc: &mut Accumulator| {
        let texels = &map.pixels[j * w..(j + 1) * w];
        for m in 0..=lmax {
            let t = &trig[m * w..(m + 1) * w];
            let (mut c, mut s) = (DVec3::ZERO, DVec3::ZERO);
            for (px, cs) in texels.iter().zip(t) {
                let f = DVec3::new(px[0] as f64, px[1] as f64, px[2] as f64);
                c += f * cs[0];
                s += f * cs[1];
            }
            acc.ring_c[m] = c;
            acc.ring_s[m] = s;
        }
        let (theta, _) = equirect_angles(0, j, w, h);
        legendre.eval(theta.cos(), &mut acc.p);
        let omega = equirect_row_solid_angle(j, w, h);
        let sqrt2 = 2f64.sqrt();
        for l in 0..=lmax {
            acc.sh[sh_index(l, 0)] += acc.ring_c[0] * (omega * acc.p[legendre_index(l, 0)]);
            for m in 1..=l {
                let k = omega * sqrt2 * acc.p[legendre_index(l, m)];
                acc.sh[sh_index(l, m as isize)] += acc.ring_c[m] * k;
                acc.sh[sh_index(l, -(m as isize))] += acc.ring_s[m] * k;
            }
        }
    };

    to_frame(run_rows::<Accumulator>(h, lmax, row), o.frame)
}

/// Per-thread scratch and partial sums.
struct Accumulator {
    sh: ShCoeffs<DVec3>,
    ring_c: Vec<DVec3>,
    ring_s: Vec<DVec3>,
    p: Vec<f64>,
}

impl Accumulator {
    fn new(lmax: usize) -> Self {
        Self {
            sh: ShCoeffs::zeros(lmax),
            ring_c: vec![DVec3::ZERO; lmax + 1],
            ring_s: vec![DVec3::ZERO; lmax + 1],
            p: vec![0.0; legendre_count(lmax)],
        }
    }
}

impl RowState for Accumulator {
    fn new(lmax: usize) -> Self {
        Accumulator::new(lmax)
    }
    fn into_coeffs(self) -> ShCoeffs<DVec3> {
        self.sh
    }
}
