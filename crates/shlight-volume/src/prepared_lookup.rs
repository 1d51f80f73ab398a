//! [`PreparedLookup`]: a [`Lookup`] of one volume made ready for many
//! points, the one way shlight reads a volume's light at a point: the
//! engines' lookups build their texture (Bevy) or dilated grid (three.js)
//! once, shlight's own the probes' irradiance coefficients.

use glam::{DVec3, Vec3};
use shlight_baked::VolumeView;
use shlight_core::sh::ShCoeffs;

use crate::bevy_lookup::BevyLookup;
use crate::lookup::Lookup;
use crate::probe_lookup::ProbeLookup;
use crate::threejs_lookup::ThreeJsLookup;

/// A [`Lookup`] of one volume's probes (a [`VolumeView`]: a `.shvol`
/// file's, or a bake's lit by [`crate::VolumeBake::relight`]) kept to an
/// lmax ([`Lookup::lmax_for`] says which), made ready for many points:
/// what `shlight sample`, the Python package's `Volume.irradiance` and the
/// tests that hold the GPU's volume pass to the CPU read.
#[derive(Clone, Debug)]
pub struct PreparedLookup<'a> {
    precomputed: Precomputed<'a>,
}

/// What each lookup makes ready.
#[derive(Clone, Debug)]
enum Precomputed<'a> {
    /// The `shlight` and `trilinear` lookups: the probes' irradiance
    /// coefficients and how the probes are weighed.
    Probes(ProbeLookup<'a>),
    /// Bevy's: the KTX2 export's texture.
    Bevy(BevyLookup),
    /// three.js's: the dilated grid in three.js's basis.
    ThreeJs(ThreeJsLookup),
}

impl<'a> PreparedLookup<'a> {
    /// `lookup` of `view`'s probes kept to `lmax` (at most the volume's;
    /// see [`Lookup::lmax_for`]).
    #[must_use]
    pub fn new(view: &VolumeView<'a>, lookup: Lookup, lmax: usize) -> Self {
        let precomputed = match lookup {
            Lookup::Bevy => Precomputed::Bevy(BevyLookup::new(view, lmax)),
            Lookup::ThreeJs => Precomputed::ThreeJs(ThreeJsLookup::new(view, lmax)),
            Lookup::Shlight | Lookup::Trilinear => {
                let visibility = lookup.effective(view) == Lookup::Shlight;
                Precomputed::Probes(ProbeLookup::new(view, visibility, lmax))
            }
        };
        Self { precomputed }
    }

    /// The irradiance `E(p, n)` at `p` facing the normal `n` (any length
    /// but 0): what the volume pass shades with (a Lambertian fragment of
    /// albedo `rho` leaves `rho / pi E`). shlight's lookups: `E(p, n) =
    /// sum_lm A_l L_lm(p) Y_lm(n)` of the radiance
    /// [`PreparedLookup::radiance_at`] gives (Ramamoorthi & Hanrahan
    /// 2001's `A_l`), 0 where no valid probe is around `p`, as on the GPU;
    /// the engines' as their shaders compute it from shlight's export, 0
    /// where their volume does not reach.
    #[must_use]
    pub fn irradiance_at(&self, p: Vec3, n: Vec3) -> DVec3 {
        match &self.precomputed {
            Precomputed::Probes(probes) => probes.irradiance_at(p, n),
            Precomputed::Bevy(bevy) => bevy.irradiance_at(p, n),
            Precomputed::ThreeJs(three) => three.irradiance_at(p, n),
        }
    }

    /// [`PreparedLookup::irradiance_at`] of every point facing its normal
    /// (as many of each), on every core: what `shlight sample` and the
    /// Python package's `Volume.irradiance` report.
    ///
    /// # Panics
    /// If the two slices differ in length.
    #[must_use]
    pub fn irradiance_all(&self, points: &[[f32; 3]], normals: &[[f32; 3]]) -> Vec<[f64; 3]> {
        use rayon::prelude::*;
        assert_eq!(points.len(), normals.len(), "a normal per point");
        points
            .par_iter()
            .zip(normals)
            .map(|(p, n)| {
                self.irradiance_at(Vec3::from_array(*p), Vec3::from_array(*n))
                    .to_array()
            })
            .collect()
    }

    /// The radiance coefficients shlight's lookups read at `p` (facing
    /// `n`, which the `shlight` lookup's visibility weights depend on),
    /// kept to the lookup's lmax: `sum_k w_k L_k` over the probes around
    /// `p`, the weights summing to 1 — the valid probes' trilinear weights
    /// renormalised (`trilinear`), or shlight-baked's visibility weights
    /// (`shlight` with distance maps). `None` where no valid probe is
    /// around `p`, and for the engines' lookups, which blend no SH
    /// radiance (Bevy's ambient cubes; three.js's own basis).
    #[must_use]
    pub fn radiance_at(&self, p: Vec3, n: Vec3) -> Option<ShCoeffs<DVec3>> {
        match &self.precomputed {
            Precomputed::Probes(probes) => probes.radiance_at(p, n),
            Precomputed::Bevy(_) | Precomputed::ThreeJs(_) => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use shlight_baked::ProbeGrid;
    use std::f64::consts::PI;

    /// Two probes along x, degree 1, probe 1 pointing its light along +x:
    /// the irradiance is the closed form `E = pi a Y00 + 2 pi / 3 (b . n)
    /// sqrt(3 / 4 pi)` of the interpolated coefficients, worked out here by
    /// hand (`Y_00 = 1 / (2 sqrt(pi))`, `Y_1,1 = -sqrt(3 / 4 pi) x`).
    #[test]
    fn the_closed_form_of_interpolated_degree_one_probes() {
        let grid = ProbeGrid::new([2, 1, 1], Vec3::ZERO, Vec3::new(2.0, 1.0, 1.0)).unwrap();
        // Per probe 4 rows of [r, g, b]: L00, L1-1, L10, L11.
        let mut radiance = vec![0.0f32; 2 * 4 * 3];
        radiance[..3].copy_from_slice(&[1.0, 2.0, 3.0]);
        radiance[12..15].copy_from_slice(&[2.0, 2.0, 2.0]);
        radiance[12 + 9..12 + 12].copy_from_slice(&[-0.5, -0.5, -0.5]);
        let valid = [true, true];
        let view = VolumeView {
            grid,
            lmax: 1,
            valid: &valid,
            radiance: &radiance,
            offsets: None,
            visibility: None,
        };
        let irradiance_at = |view: &VolumeView<'_>, lookup, lmax, p, n| {
            PreparedLookup::new(view, lookup, lmax).irradiance_at(p, n)
        };
        let c1 = (3.0 / (4.0 * PI)).sqrt();
        let y00 = 0.5 / PI.sqrt();
        // A quarter of the way from probe 0 (x = 0.5) to probe 1 (x = 1.5).
        let p = Vec3::new(0.75, 0.5, 0.5);
        for n in [Vec3::X, Vec3::NEG_X, Vec3::Y, Vec3::new(1.0, 1.0, 0.0)] {
            let got = irradiance_at(&view, Lookup::Trilinear, 1, p, n);
            let nn = n.as_dvec3().normalize();
            let l00 = 0.75 * DVec3::new(1.0, 2.0, 3.0) + 0.25 * DVec3::splat(2.0);
            let l11 = 0.25 * DVec3::splat(-0.5);
            let want = PI * l00 * y00 + 2.0 * PI / 3.0 * l11 * (-c1 * nn.x);
            assert!((got - want).abs().max_element() < 1e-6, "{n}: {got} {want}");
        }
        // lmax 0 drops the directional term.
        let got = irradiance_at(&view, Lookup::Shlight, 0, p, Vec3::X);
        let want = PI * y00 * (0.75 * DVec3::new(1.0, 2.0, 3.0) + 0.25 * DVec3::splat(2.0));
        assert!((got - want).abs().max_element() < 1e-6);
        // An invalid probe takes no weight; none valid: no light.
        let one = [false, true];
        let view1 = VolumeView {
            valid: &one,
            ..view
        };
        let got = irradiance_at(&view1, Lookup::Trilinear, 0, p, Vec3::X);
        assert!((got - PI * y00 * DVec3::splat(2.0)).abs().max_element() < 1e-6);
        let none = [false, false];
        let view0 = VolumeView {
            valid: &none,
            ..view
        };
        assert_eq!(
            irradiance_at(&view0, Lookup::Trilinear, 1, p, Vec3::X),
            DVec3::ZERO
        );
    }
}
