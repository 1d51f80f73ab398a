//! Projection of environment maps to SH by exact texel-solid-angle quadrature.
//!
//! The estimate of each radiance coefficient is the sum over texels
//!
//! ```text
//! L_l^m ≈ sum_texels f(texel) Y_l^m(d(texel centre)) Ω(texel)
//! ```
//!
//! with `Ω` the exact solid angle the texel covers. For an equirect map of
//! `W x H` texels every texel of row `j` covers
//! `Ω_j = (2π/W)(cos(jπ/H) - cos((j+1)π/H))` ([`equirect_row_solid_angle`]),
//! and the rows sum to exactly `4π`.
//!
//! **Ring structure.** Rows are rings about the map's own pole. In the z-up
//! frame that pole is the basis's polar axis, so the sum separates:
//! per row, azimuthal sums `C_m = sum_i f_i cos(m ψ_i)`, `S_m = sum_i f_i sin(m ψ_i)`,
//! then `L_l^m += Ω_j sqrt2 Pbar_l^m(cos θ_j) {C_m, S_m}` — `O(W lmax + lmax^2)`
//! per row instead of `O(W lmax^2)`. A y-up map is projected the same way and
//! its coefficients rotated by `Rx(-90°)` (docs/conventions.md).

use core::f64::consts::PI;

use glam::DVec3;

use crate::legendre::{Legendre, legendre_count, legendre_index};
use crate::rotation::Frame;
use crate::{ShCoeffs, sh_index};

/// A borrowed equirectangular map: `width x height` texels, row-major from
/// the top-left corner, linear RGB.
#[derive(Clone, Copy, Debug)]
pub struct EquirectView<'a> {
    /// Texels per row.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// `width * height` linear RGB texels.
    pub pixels: &'a [[f32; 3]],
}

/// How an equirect map's texels meet world directions.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MapOrientation {
    /// Which world axis row 0 faces (docs/conventions.md).
    pub frame: Frame,
    /// Read maps made for the mirrored pbrt / google mapping: `φ` runs the
    /// other way around the pole.
    pub mirror: bool,
}

impl MapOrientation {
    /// Every orientation: both frames, unmirrored and mirrored.
    pub const ALL: [Self; 4] = [
        Self {
            frame: Frame::YUp,
            mirror: false,
        },
        Self {
            frame: Frame::YUp,
            mirror: true,
        },
        Self {
            frame: Frame::ZUp,
            mirror: false,
        },
        Self {
            frame: Frame::ZUp,
            mirror: true,
        },
    ];

    /// World direction of a direction `d` given in the map's own y-up frame:
    /// `mirror` negates its `z` (for equirect maps that is `φ -> -φ`), then
    /// `Frame::YUp.rotation_to(frame)` turns it into the frame.
    #[inline]
    #[must_use]
    pub fn world_from_map(self, d: DVec3) -> DVec3 {
        let d = if self.mirror {
            d * DVec3::new(1.0, 1.0, -1.0)
        } else {
            d
        };
        Frame::YUp.rotation_to(self.frame) * d
    }

    /// `s` in `ψ = s φ`: the azimuth `ψ` about the map's pole (its z-up
    /// frame, `d_zup = (sin θ cos φ, -sin θ sin φ, cos θ)`) of texel azimuth
    /// `φ`; -1, or +1 when mirrored. What the ring transforms (CPU and GPU)
    /// turn each row by.
    #[inline]
    #[must_use]
    pub fn pole_azimuth_sign(self) -> f64 {
        if self.mirror { 1.0 } else { -1.0 }
    }

    /// The inverse of [`MapOrientation::world_from_map`].
    #[inline]
    #[must_use]
    pub fn map_from_world(self, d: DVec3) -> DVec3 {
        let d = self.frame.rotation_to(Frame::YUp) * d;
        if self.mirror {
            d * DVec3::new(1.0, 1.0, -1.0)
        } else {
            d
        }
    }
}

/// Texel centre angles `(θ, φ)` of equirect texel `(x, y)` in a `w x h` map:
/// `u = (x+.5)/w`, `v = (y+.5)/h`, `θ = π v`, `φ = 2π (u - .5)`.
#[inline]
#[must_use]
pub fn equirect_angles(x: usize, y: usize, w: usize, h: usize) -> (f64, f64) {
    let u = (x as f64 + 0.5) / w as f64;
    let v = (y as f64 + 0.5) / h as f64;
    (PI * v, 2.0 * PI * (u - 0.5))
}

/// World direction of the centre of equirect texel `(x, y)`.
#[must_use]
pub fn equirect_direction(x: usize, y: usize, w: usize, h: usize, o: MapOrientation) -> DVec3 {
    let (t, p) = equirect_angles(x, y, w, h);
    o.frame.direction(t, if o.mirror { -p } else { p })
}

/// Exact solid angle of one texel in row `j` of a `w x h` equirect map:
/// `(2π/w)(cos(jπ/h) - cos((j+1)π/h))`.
#[must_use]
pub fn equirect_row_solid_angle(j: usize, w: usize, h: usize) -> f64 {
    let t0 = PI * j as f64 / h as f64;
    let t1 = PI * (j + 1) as f64 / h as f64;
    // cos a - cos b = 2 sin((a+b)/2) sin((b-a)/2), without cancellation.
    2.0 * PI / w as f64 * 2.0 * ((t0 + t1) / 2.0).sin() * ((t1 - t0) / 2.0).sin()
}

/// Radiance coefficients up to `lmax` of an equirect map by exact
/// texel-solid-angle quadrature (see the module docs), accumulated in `f64`.
///
/// Runs the ring transform: azimuthal sums per row (direct sums over each
/// row folded onto its first quarter, or a real FFT per row from lmax 48 on), then Legendre sums per column `m` over symmetric row pairs,
/// vectorised and parallel with the `rayon` feature. Any lmax works (the
/// Legendre values carry an extended exponent); cost is
/// `O(W H min(lmax, log W) + H lmax^2)`. A y-up map's coefficients are then
/// rotated from the map's z-up pole by a quarter turn about X
/// ([`crate::quarter_turn`], `O(lmax^3)` with a small constant).
///
/// Panics if `pixels.len() != width * height`.
#[must_use]
pub fn project_equirect(map: EquirectView<'_>, lmax: usize, o: MapOrientation) -> ShCoeffs<DVec3> {
    assert_eq!(
        map.pixels.len(),
        map.width * map.height,
        "pixel count must be width * height"
    );
    let sign = o.pole_azimuth_sign();
    let zup = crate::ring_transform::project_rings(map, lmax, sign);
    to_frame(zup, o.frame)
}

/// Coefficients computed about the map's pole (z-up) turned into `frame`:
/// unchanged for z-up, a quarter turn about X (`Rx(-90°)`,
/// [`crate::quarter_turn`]) for y-up. The last step of [`project_equirect`],
/// public for other routes to the same ring sums (the GPU's).
#[must_use]
pub fn to_frame(zup: ShCoeffs<DVec3>, frame: Frame) -> ShCoeffs<DVec3> {
    match frame {
        Frame::ZUp => zup,
        // z-up -> y-up is Rx(-90°) (`Frame::rotation_to`).
        Frame::YUp => crate::quarter_turn::quarter_turn_x(&zup, -1),
    }
}

/// The same quadrature as [`project_equirect`] by the plain route: per row,
/// direct azimuthal sums against a trig table, then one Legendre evaluation
/// per row. `O(W H lmax + H lmax^2)`, no pairing, no FFT, no vector code: the
/// reference the fast path is tested and benchmarked against.
///
/// Panics if `pixels.len() != width * height`.
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

/// Per-thread state of a parallel loop over rows that ends in coefficients.
pub(crate) trait RowState: Send {
    /// Fresh state for degree `lmax`.
    fn new(lmax: usize) -> Self;
    /// The partial sums this state holds.
    fn into_coeffs(self) -> ShCoeffs<DVec3>;
}

impl RowState for Accumulator {
    fn new(lmax: usize) -> Self {
        Accumulator::new(lmax)
    }
    fn into_coeffs(self) -> ShCoeffs<DVec3> {
        self.sh
    }
}

/// Runs `row(j, state)` for every row `j < h` (in parallel with rayon, one
/// state per worker) and sums the states' coefficients.
#[cfg(feature = "rayon")]
pub(crate) fn run_rows<S: RowState>(
    h: usize,
    lmax: usize,
    row: impl Fn(usize, &mut S) + Sync,
) -> ShCoeffs<DVec3> {
    use rayon::prelude::*;
    (0..h)
        .into_par_iter()
        .fold(
            || S::new(lmax),
            |mut acc, j| {
                row(j, &mut acc);
                acc
            },
        )
        .map(S::into_coeffs)
        .reduce(
            || ShCoeffs::zeros(lmax),
            |mut a, b| {
                a += &b;
                a
            },
        )
}

/// Runs `row(j, state)` for every row `j < h` and returns the coefficients.
#[cfg(not(feature = "rayon"))]
pub(crate) fn run_rows<S: RowState>(
    h: usize,
    lmax: usize,
    row: impl Fn(usize, &mut S),
) -> ShCoeffs<DVec3> {
    let mut acc = S::new(lmax);
    for j in 0..h {
        row(j, &mut acc);
    }
    acc.into_coeffs()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analytic;

    fn map_from_fn(
        w: usize,
        h: usize,
        o: MapOrientation,
        f: impl Fn(DVec3) -> f64,
    ) -> Vec<[f32; 3]> {
        let mut px = Vec::with_capacity(w * h);
        for y in 0..h {
            for x in 0..w {
                let v = f(equirect_direction(x, y, w, h, o)) as f32;
                px.push([v, 0.5 * v, 0.25 * v]);
            }
        }
        px
    }

    #[test]
    fn row_solid_angles_sum_to_four_pi() {
        for (w, h) in [(8, 4), (64, 32), (2048, 1024)] {
            let total: f64 = (0..h)
                .map(|j| w as f64 * equirect_row_solid_angle(j, w, h))
                .sum();
            assert!((total - 4.0 * PI).abs() < 1e-12, "{w}x{h}");
        }
    }

    #[test]
    fn quadrature_matches_brute_force_texel_sum_in_every_orientation() {
        let (w, h) = (48, 24);
        let px: Vec<[f32; 3]> = (0..w * h)
            .map(|i| [((i * 7919) % 101) as f32 / 50.0, 1.0, (i % 13) as f32])
            .collect();
        let map = EquirectView {
            width: w,
            height: h,
            pixels: &px,
        };
        for frame in [Frame::YUp, Frame::ZUp] {
            for mirror in [false, true] {
                let o = MapOrientation { frame, mirror };
                let fast = project_equirect(map, 6, o);
                let basis = crate::ShBasis::<f64>::new(6);
                let mut y = vec![0.0; basis.count()];
                let mut slow = ShCoeffs::<DVec3>::zeros(6);
                for j in 0..h {
                    let omega = equirect_row_solid_angle(j, w, h);
                    for i in 0..w {
                        basis.eval(equirect_direction(i, j, w, h, o).to_array(), &mut y);
                        let f = DVec3::from(px[j * w + i].map(f64::from));
                        for k in 0..y.len() {
                            slow[k] += f * (y[k] * omega);
                        }
                    }
                }
                for k in 0..slow.len() {
                    assert!(
                        (fast[k] - slow[k]).abs().max_element() < 1e-11,
                        "{frame} mirror {mirror} k {k}"
                    );
                }
            }
        }
    }

    /// Largest difference between two expansions relative to the largest coefficient.
    fn rel_diff(a: &ShCoeffs<DVec3>, b: &ShCoeffs<DVec3>) -> f64 {
        let scale = b
            .as_slice()
            .iter()
            .map(|v| v.abs().max_element())
            .fold(0.0, f64::max);
        let diff = (0..a.len())
            .map(|k| (a[k] - b[k]).abs().max_element())
            .fold(0.0, f64::max);
        diff / scale
    }

    fn noise_map(w: usize, h: usize) -> Vec<[f32; 3]> {
        (0..w * h)
            .map(|i| {
                let a = ((i * 7919) % 1009) as f32 / 500.0;
                [a, 1.0 + (i % 17) as f32 * 0.1, ((i * 31) % 97) as f32]
            })
            .collect()
    }

    /// [`rel_diff`] of the fast path against the simple route on the noise map.
    fn fast_vs_simple(w: usize, h: usize, lmax: usize, o: MapOrientation) -> f64 {
        let px = noise_map(w, h);
        let map = EquirectView {
            width: w,
            height: h,
            pixels: &px,
        };
        rel_diff(
            &project_equirect(map, lmax, o),
            &project_equirect_simple(map, lmax, o),
        )
    }

    #[test]
    fn fast_path_matches_the_simple_route_direct_and_fft() {
        // (w, h, lmax): even/odd sizes, the direct sums (lmax < 48) folded
        // (w a multiple of 4, with and without a vector tail) and not, the
        // FFT path, lmax beyond w/2 where the FFT bins wrap around, and
        // several blocks of row pairs near the poles (extended exponent).
        for (w, h, lmax) in [
            (48, 24, 6),
            (47, 23, 5),
            (64, 32, 30),
            (64, 32, 60),
            (50, 25, 60),
            (256, 128, 100),
            (50, 26, 7),
            (40, 20, 5),
            (40, 80, 300),
            (1040, 8, 10),
        ] {
            for o in MapOrientation::ALL {
                let d = fast_vs_simple(w, h, lmax, o);
                assert!(d < 1e-12, "{w}x{h} lmax {lmax} {o:?}: {d:e}");
            }
        }
    }

    #[test]
    fn portable_kernels_match_the_simple_route() {
        // The AVX + FMA kernels run wherever the CPU has them; this checks
        // the portable ones too (both the direct sums and the FFT path).
        use std::sync::atomic::Ordering;
        crate::cpu_features::FORCE_PORTABLE.store(true, Ordering::Relaxed);
        for (w, h, lmax) in [(48, 24, 6), (40, 20, 5), (50, 26, 7), (50, 25, 60)] {
            let o = MapOrientation {
                frame: Frame::ZUp,
                mirror: true,
            };
            let d = fast_vs_simple(w, h, lmax, o);
            assert!(d < 1e-12, "{w}x{h} lmax {lmax}: {d:e}");
        }
        crate::cpu_features::FORCE_PORTABLE.store(false, Ordering::Relaxed);
    }

    #[test]
    fn fast_path_keeps_the_extended_exponent_at_high_lmax() {
        // Sectoral values s^m underflow f64 once m log10(1/s) > 308, yet the
        // column grows back to significance near l = m/s: at s = 0.5 that is
        // m > 1023, l > 2046. The coefficients of so small a map are aliased,
        // but both routes compute the same sums; the simple route uses
        // Legendre::eval, whose extended exponent is tested on its own.
        let o = MapOrientation {
            frame: Frame::ZUp,
            mirror: false,
        };
        let d = fast_vs_simple(64, 32, 2100, o);
        assert!(d < 1e-11, "{d:e}");
    }

    #[test]
    fn projects_a_smooth_light_close_to_its_closed_form() {
        let axis = DVec3::new(0.48, 0.6, -0.64);
        let o = MapOrientation::default();
        let (w, h) = (512, 256);
        let px = map_from_fn(w, h, o, |d| 1.0 + 0.5 * d.dot(axis));
        let got = project_equirect(
            EquirectView {
                width: w,
                height: h,
                pixels: &px,
            },
            4,
            o,
        );
        let want: ShCoeffs<f64> = analytic::linear_gradient(4, axis.to_array(), 1.0, 0.5);
        for k in 0..25 {
            assert!(
                (got[k].x - want[k]).abs() < 1e-4,
                "k {k}: {} vs {}",
                got[k].x,
                want[k]
            );
            assert!((got[k].y - 0.5 * want[k]).abs() < 1e-4);
        }
    }
}
