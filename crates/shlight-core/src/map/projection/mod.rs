//! Projection of environment maps to SH by exact texel-solid-angle
//! quadrature: [`project`], the entry point for every texel source, and its
//! wrappers for the crate's own maps.

use glam::DVec3;

use crate::map::equirect::EquirectView;
use crate::map::layout::env_map::EnvMap;
use crate::map::layout::kind::{Layout, LayoutSizeError};
use crate::map::orientation::MapOrientation;
use crate::map::projection::pole::to_frame;
use crate::map::texel_source::TexelSource;
use crate::sh::sh_coeffs::ShCoeffs;

pub(crate) mod equirect_simple;
pub(crate) mod layout_quadrature;
pub(crate) mod pole;
pub(crate) mod ring_transform;
pub(crate) mod rows;

/// Radiance coefficients up to `lmax` of any environment map by exact
/// texel-solid-angle quadrature, accumulated in `f64`: the one entry point
/// for every [`TexelSource`] (a contiguous [`EnvMap`] or [`EquirectView`], a
/// [`crate::map::StridedImage`], six [`crate::map::CubeFaces`], a user's own type),
/// the texels read in `orientation`:
///
/// ```text
/// L_l^m ≈ sum over texels with a direction of f(texel) Y_l^m(d(texel)) Ω(texel)
/// ```
///
/// Equirect sources go through the ring transform (azimuthal sums per row —
/// direct sums over each row folded onto its first quarter, or a real FFT
/// per row from lmax 48 on — then Legendre sums per column `m` over
/// symmetric row pairs, vectorised and parallel with the `rayon` feature;
/// any lmax, the Legendre values carrying an extended exponent; cost
/// `O(W H min(lmax, log W) + H lmax^2)`; a y-up map's coefficients are then
/// turned from the map's z-up pole by a quarter turn about X,
/// [`crate::sh::quarter_turn_x`]), reading each row through
/// [`TexelSource::row`] without a copy when the source stores it
/// contiguously. The other layouts evaluate the basis in batches
/// ([`crate::sh::ShBasis::eval_batch`]) per row, rows in parallel. The
/// quadrature is exact for constants (the weights sum to `4π`); for a smooth
/// band-limited function its error falls as `h²` with the texel size (module
/// docs).
///
/// The sums depend only on the texel values, so every source with the same
/// texels gives the same coefficients bit for bit (six faces and the strip
/// they make, a strided image and its contiguous copy).
///
/// # Errors
/// [`LayoutSizeError`] when the source's size does not fit its layout
/// ([`Layout::check_size`]).
///
/// # Quadrature
///
/// The estimate of each radiance coefficient is the sum over texels
///
/// ```text
/// L_l^m ≈ sum_texels f(texel) Y_l^m(d(texel centre)) Ω(texel)
/// ```
///
/// with `Ω` the exact solid angle the texel covers ([`Layout`] gives both
/// for every layout). For an equirect map of `W x H` texels every texel of
/// row `j` covers `Ω_j = (2π/W)(cos(jπ/H) - cos((j+1)π/H))`
/// ([`crate::map::equirect_row_solid_angle`]), and the rows sum to exactly
/// `4π`.
///
/// # Ring structure
///
/// Rows are rings about the map's own pole. In the z-up
/// frame that pole is the basis's polar axis, so the sum separates:
/// per row, azimuthal sums `C_m = sum_i f_i cos(m ψ_i)`, `S_m = sum_i f_i sin(m ψ_i)`,
/// then `L_l^m += Ω_j sqrt2 Pbar_l^m(cos θ_j) {C_m, S_m}` — `O(W lmax + lmax^2)`
/// per row instead of `O(W lmax^2)`. A y-up map is projected the same way and
/// its coefficients rotated by `Rx(-90°)` (docs/conventions.md).
///
/// # Accuracy of projection
///
/// With exact weights only the texel-centre (midpoint) error is left, which
/// falls as `h²`. Projecting a rendered lmax-4 expansion (constant 3, other
/// coefficients up to 0.3) back to lmax 4, the worst coefficient is off by
/// `6.5e-5` (equirect `512 x 256`), `3.6e-4` / `2.2e-5` (cube faces of
/// `64²` / `256²`), `1.5e-4` / `9.6e-6` (angular `N = 256` / `1024`),
/// `1.1e-3` / `7.2e-5` (mirror ball `N = 256` / `1024`).
///
/// # Entry points
///
/// [`project`] takes any [`TexelSource`]; [`project_map`] and
/// [`project_equirect`] are its wrappers for the crate's own contiguous
/// maps (panicking on a bad size, as they always have). Every route sums
/// rows in fixed bands, so a result repeats bit for bit for any thread
/// count.
pub fn project<S: TexelSource + ?Sized>(
    source: &S,
    lmax: usize,
    orientation: MapOrientation,
) -> Result<ShCoeffs<DVec3>, LayoutSizeError> {
    let (w, h) = source.size();
    let layout = source.layout();
    layout.check_size(w, h)?;
    Ok(match layout {
        Layout::Equirect => rings(source, lmax, orientation),
        _ => layout_quadrature::project_texels(source, lmax, orientation),
    })
}

/// The ring transform of an equirect source, turned into its frame.
fn rings<S: TexelSource + ?Sized>(source: &S, lmax: usize, o: MapOrientation) -> ShCoeffs<DVec3> {
    let zup =
        crate::map::projection::ring_transform::project_rings(source, lmax, o.pole_azimuth_sign());
    to_frame(zup, o.frame)
}

/// [`project`] of a contiguous equirect image (the ring transform).
///
/// Panics if `pixels.len() != width * height`.
#[must_use]
pub fn project_equirect(map: EquirectView<'_>, lmax: usize, o: MapOrientation) -> ShCoeffs<DVec3> {
    assert_eq!(
        map.pixels.len(),
        map.width * map.height,
        "pixel count must be width * height"
    );
    rings(&map, lmax, o)
}

/// [`project`] of an [`EnvMap`] in its own orientation.
///
/// # Panics
/// If the size does not fit the layout ([`Layout::check_size`]) or
/// `pixels.len() != width * height` ([`EnvMap::new`] checks both).
#[must_use]
pub fn project_map(map: &EnvMap<'_>, lmax: usize) -> ShCoeffs<DVec3> {
    assert_eq!(
        map.pixels.len(),
        map.width.saturating_mul(map.height),
        "project_map: pixel count must be width * height"
    );
    project(map, lmax, map.orientation).unwrap_or_else(|e| panic!("project_map: {e}"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::equirect::{equirect_direction, equirect_row_solid_angle};
    use crate::map::projection::equirect_simple::project_equirect_simple;
    use crate::sh::closed_form;
    use crate::sh::frame::Frame;

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
                let basis = crate::sh::basis::ShBasis::<f64>::new(6);
                let mut y = vec![0.0; basis.count()];
                let mut slow = ShCoeffs::<DVec3>::zeros(6);
                for j in 0..h {
                    let omega = equirect_row_solid_angle(j, w, h);
                    for i in 0..w {
                        basis.eval(equirect_direction(i, j, w, h, o), &mut y);
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
        let want: ShCoeffs<f64> = closed_form::linear_gradient(4, axis, 1.0, 0.5);
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
