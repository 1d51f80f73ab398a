//! [`Lookup`] and [`irradiance_at`]: what a volume shades a point with, as
//! the GPU's volume pass shades it, for `shlight sample`.

use glam::{DVec3, Vec3};
use shlight_baked::visibility::visibility_weights;
use shlight_baked::{SHADED_MAX_LMAX, VolumeView};
use shlight_core::sh::irradiance;

use crate::probe_volume::{valid_trilinear, weighted_radiance};

/// How the light at a point is read off a volume's probes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lookup {
    /// The best lookup shlight has: the probes' trilinear weights times
    /// DDGI's visibility term ([`shlight_baked::visibility`]), where the
    /// volume holds distance maps; [`Lookup::Trilinear`] where it does not
    /// (a version 1 file, a bake with `--no-visibility`). The volume pass
    /// of `render-mesh --volume` and `view --volume` shades the same way
    /// (shlight-gpu's `VolumeRenderer`, the same f32 arithmetic).
    Shlight,
    /// Trilinear interpolation of the valid probes among the eight around
    /// the point, weights renormalised ([`crate::sample`]; docs/shvol.md,
    /// "Lookups").
    Trilinear,
    /// Bevy's own lookup of the `--format bevy` export: ambient cubes of
    /// half floats, filtered and blended as bevy_pbr's
    /// `irradiance_volume.wgsl` does ([`crate::BevyLookup`]).
    Bevy,
    /// three.js `LightProbeGrid`'s lookup: the point offset half a probe
    /// spacing along the normal, trilinear L2 SH of the dilated probes,
    /// three.js's irradiance constants ([`crate::ThreeJsLookup`]).
    ThreeJs,
}

impl Lookup {
    /// Every lookup, in `--lookup` order.
    pub const ALL: [Lookup; 4] = [
        Lookup::Shlight,
        Lookup::Trilinear,
        Lookup::Bevy,
        Lookup::ThreeJs,
    ];

    /// The lookup that runs for `view`: [`Lookup::Trilinear`] for
    /// [`Lookup::Shlight`] where the volume holds no distance maps (as on
    /// the GPU), else `self`.
    #[must_use]
    pub fn effective(self, view: &VolumeView<'_>) -> Lookup {
        match self {
            Lookup::Shlight if view.visibility.is_none() => Lookup::Trilinear,
            l => l,
        }
    }

    /// The name on the command line and in files.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Lookup::Shlight => "shlight",
            Lookup::Trilinear => "trilinear",
            Lookup::Bevy => "bevy",
            Lookup::ThreeJs => "threejs",
        }
    }
}

impl std::fmt::Display for Lookup {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for Lookup {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Lookup::ALL
            .into_iter()
            .find(|l| l.name() == s.trim())
            .ok_or_else(|| {
                format!(
                    "unknown lookup {s:?} (expected {})",
                    Lookup::ALL.map(Lookup::name).join(", ")
                )
            })
    }
}

/// The lmax the GPU's volume pass shades `view` at when asked for
/// `requested` (`None`: the volume's own): at most the volume's and at
/// most [`SHADED_MAX_LMAX`].
#[must_use]
pub fn shaded_lmax(view: &VolumeView<'_>, requested: Option<usize>) -> usize {
    requested
        .unwrap_or(view.lmax)
        .min(view.lmax)
        .min(SHADED_MAX_LMAX)
}

/// The irradiance `E(p, n) = sum_lm A_l L_lm(p) Y_lm(n)` at `p` facing the
/// unit normal `n`, with `L(p)` read off the probes of `view` by `lookup`
/// and kept to `lmax` (Ramamoorthi & Hanrahan 2001's `A_l`): what the
/// volume pass shades with (a Lambertian fragment of albedo `rho` leaves
/// `rho / pi E`). Zero where no valid probe is around `p`, as on the GPU.
#[must_use]
pub fn irradiance_at(
    view: &VolumeView<'_>,
    lookup: Lookup,
    lmax: usize,
    p: Vec3,
    n: Vec3,
) -> DVec3 {
    let light = match lookup {
        Lookup::Bevy => return crate::bevy_lookup::irradiance_at(view, lmax, p, n),
        Lookup::ThreeJs => return crate::threejs_lookup::irradiance_at(view, lmax, p, n),
        Lookup::Shlight | Lookup::Trilinear => {
            weighted_radiance(view.radiance, view.lmax, &probe_weights(view, lookup, p, n))
        }
    };
    light.map_or(DVec3::ZERO, |l| {
        irradiance(&l.resized(lmax.min(view.lmax))).eval(n.as_dvec3().normalize())
    })
}

/// The weights of the probes around `p` (unit normal `n`, any length but
/// 0) for the `shlight` and `trilinear` lookups, summing to 1 (empty where
/// no valid probe is around): shlight-baked's visibility weights where the
/// lookup is `shlight` and the volume has distance maps, else the valid
/// probes' trilinear weights renormalised.
pub(crate) fn probe_weights(
    view: &VolumeView<'_>,
    lookup: Lookup,
    p: Vec3,
    n: Vec3,
) -> Vec<(usize, f64)> {
    match lookup.effective(view) {
        Lookup::Shlight => visibility_weights(view, p, n.normalize())
            .unwrap_or_default()
            .into_iter()
            .map(|(k, w)| (k, f64::from(w)))
            .collect(),
        _ => valid_trilinear(&view.grid, view.valid, p),
    }
}

/// The eight corners of a texel-space cell with fractions `f` (each in
/// `[0, 1]`) and their trilinear weights, corner `d` (per axis 0 for the
/// lower, 1 for the upper texel) weighing `prod f_a` or `1 - f_a`; corners
/// of weight 0 left out. The engines' lookups (Bevy's sampler, three.js's)
/// filter their textures with it.
pub(crate) fn texel_corners(f: DVec3) -> impl Iterator<Item = ([usize; 3], f64)> {
    (0..8usize).filter_map(move |corner| {
        let d = [corner & 1, corner >> 1 & 1, corner >> 2 & 1];
        let w = [f.x, f.y, f.z]
            .iter()
            .zip(d)
            .map(|(f, d)| if d == 1 { *f } else { 1.0 - f })
            .product::<f64>();
        (w != 0.0).then_some((d, w))
    })
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
        // Without distance maps the shlight lookup is trilinear; with
        // them it is itself.
        assert_eq!(Lookup::Shlight.effective(&view), Lookup::Trilinear);
        assert_eq!(Lookup::Bevy.effective(&view), Lookup::Bevy);
        let maps = vec![1.0f32; 2 * 2];
        let seen = VolumeView {
            visibility: Some(shlight_baked::Visibility {
                size: 1,
                max_distance: 1.0,
                moments: &maps,
            }),
            ..view
        };
        assert_eq!(Lookup::Shlight.effective(&seen), Lookup::Shlight);
        assert_eq!(shaded_lmax(&view, None), 1);
        assert_eq!(shaded_lmax(&view, Some(0)), 0);
        assert_eq!("trilinear".parse::<Lookup>(), Ok(Lookup::Trilinear));
        assert!(
            "unity"
                .parse::<Lookup>()
                .unwrap_err()
                .contains("shlight, trilinear, bevy, threejs")
        );
    }
}
