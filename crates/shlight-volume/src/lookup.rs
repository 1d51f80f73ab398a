//! [`Lookup`]: the ways a volume's light at a point is read off its
//! probes, and the degrees each reads ([`Lookup::lmax_for`]).

use shlight_baked::{SHADED_MAX_LMAX, VolumeView};
use shlight_format::threejs_volume::THREEJS_LMAX;

use crate::error::VolumeError;

/// How the light at a point is read off a volume's probes: shlight's own
/// lookups or an engine's. [`crate::PreparedLookup`] reads it.
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
    /// the point, weights renormalised (docs/shvol.md, "Lookups"): the
    /// radiance is [`crate::PreparedLookup::radiance_at`].
    Trilinear,
    /// Bevy's own lookup of the `--format bevy` export: ambient cubes of
    /// half floats, filtered and blended as bevy_pbr's
    /// `irradiance_volume.wgsl` does (`bevy_lookup.rs`).
    Bevy,
    /// three.js `LightProbeGrid`'s lookup: the point offset half a probe
    /// spacing along the normal, trilinear L2 SH of the dilated probes,
    /// three.js's irradiance constants (`threejs_lookup.rs`).
    ThreeJs,
}

/// The lmax a lookup reads a volume to ([`Lookup::lmax_for`]), and what
/// the user should know about it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LookupLmax {
    /// The degrees read: `0..=lmax`.
    pub lmax: usize,
    /// Set when the volume holds degrees the lookup cannot read.
    pub note: Option<String>,
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

    /// The lmax this lookup reads `view` to when asked for `requested`
    /// (`None`: the lookup's own choice), never above the volume's:
    ///
    /// - `shlight`, `trilinear`: what the GPU's volume pass shades (the
    ///   volume's, at most [`SHADED_MAX_LMAX`]);
    /// - `bevy`: the volume's, as the `--format bevy` export builds its
    ///   ambient cubes from every degree;
    /// - `threejs`: at most 2, the nine coefficients of three.js's grid; a
    ///   volume of higher lmax is clipped, with a note.
    ///
    /// # Errors
    /// A `requested` lmax the lookup cannot shade: above [`SHADED_MAX_LMAX`]
    /// for shlight's lookups, above 2 for three.js's. The message says why;
    /// the caller names the option as its users spell it (`--lmax 5`,
    /// `lmax=5`).
    pub fn lmax_for(
        self,
        view: &VolumeView<'_>,
        requested: Option<usize>,
    ) -> Result<LookupLmax, VolumeError> {
        let refuse = |most: usize, why: &str| -> Result<(), VolumeError> {
            match requested.filter(|&l| l > most) {
                Some(_) => Err(VolumeError::Options(format!("{why} lmax {most} at most"))),
                None => Ok(()),
            }
        };
        match self {
            Lookup::Bevy => Ok(LookupLmax {
                lmax: requested.unwrap_or(view.lmax).min(view.lmax),
                note: None,
            }),
            Lookup::ThreeJs => {
                refuse(
                    THREEJS_LMAX,
                    "three.js's LightProbeGrid holds nine coefficients per probe,",
                )?;
                let lmax = requested.unwrap_or(THREEJS_LMAX).min(view.lmax);
                let note = (requested.is_none() && view.lmax > THREEJS_LMAX).then(|| {
                    let left_out = if view.lmax == THREEJS_LMAX + 1 {
                        format!("degree {} is", view.lmax)
                    } else {
                        format!("degrees {} to {} are", THREEJS_LMAX + 1, view.lmax)
                    };
                    format!(
                        "three.js's LightProbeGrid holds lmax {THREEJS_LMAX}: the volume's {left_out} left out"
                    )
                });
                Ok(LookupLmax { lmax, note })
            }
            _ => {
                refuse(SHADED_MAX_LMAX, "volumes are shaded to")?;
                Ok(LookupLmax {
                    lmax: shaded_lmax(view, requested),
                    note: None,
                })
            }
        }
    }
}

/// The lmax the GPU's volume pass shades `view` at when asked for
/// `requested` (`None`: the volume's own): at most the volume's and at
/// most [`SHADED_MAX_LMAX`].
fn shaded_lmax(view: &VolumeView<'_>, requested: Option<usize>) -> usize {
    requested
        .unwrap_or(view.lmax)
        .min(view.lmax)
        .min(SHADED_MAX_LMAX)
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

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;
    use shlight_baked::ProbeGrid;

    /// Without distance maps the shlight lookup is trilinear, with them
    /// it is itself; the lmax shaded is the volume's unless asked for
    /// less; the names parse.
    #[test]
    fn the_lookup_that_runs_and_its_names() {
        let grid = ProbeGrid::new([2, 1, 1], Vec3::ZERO, Vec3::new(2.0, 1.0, 1.0)).unwrap();
        let radiance = vec![0.0f32; 2 * 4 * 3];
        let valid = [true, true];
        let view = VolumeView {
            grid,
            lmax: 1,
            valid: &valid,
            radiance: &radiance,
            offsets: None,
            visibility: None,
        };
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
