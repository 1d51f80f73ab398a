//! [`PreparedLookup`]: a [`Lookup`] made ready once for many points (the
//! engines' lookups build their texture or dilated grid first), and
//! [`lookup_lmax`], the lmax each lookup reads a volume to.

use glam::{DVec3, Vec3};
use shlight_baked::{SHADED_MAX_LMAX, VolumeView};

use crate::bevy_lookup::BevyLookup;
use crate::threejs_lookup::{THREEJS_LMAX, ThreeJsLookup};
use crate::{Lookup, VolumeError, irradiance_at, shaded_lmax};

/// The lmax a lookup reads a volume to, and what the user should know
/// about it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LookupLmax {
    /// The degrees read: `0..=lmax`.
    pub lmax: usize,
    /// Set when the volume holds degrees the lookup cannot read.
    pub note: Option<String>,
}

/// The lmax `lookup` reads `view` to when asked for `requested` (`None`:
/// the lookup's own choice), never above the volume's:
///
/// - `shlight`, `trilinear`: what the GPU's volume pass shades
///   ([`shaded_lmax`]: the volume's, at most [`SHADED_MAX_LMAX`]);
/// - `bevy`: the volume's, as the `--format bevy` export builds its ambient
///   cubes from every degree;
/// - `threejs`: at most 2, the nine coefficients of three.js's grid; a
///   volume of higher lmax is clipped, with a note.
///
/// # Errors
/// A `requested` lmax the lookup cannot shade: above [`SHADED_MAX_LMAX`]
/// for shlight's lookups, above 2 for three.js's.
pub fn lookup_lmax(
    view: &VolumeView<'_>,
    lookup: Lookup,
    requested: Option<usize>,
) -> Result<LookupLmax, VolumeError> {
    let refuse = |most: usize, why: &str| -> Result<(), VolumeError> {
        match requested.filter(|&l| l > most) {
            Some(l) => Err(VolumeError::Options(format!(
                "--lmax {l}: {why} lmax {most} at most"
            ))),
            None => Ok(()),
        }
    };
    match lookup {
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

/// A lookup of one volume made ready for many points: the engines'
/// lookups build their texture (Bevy) or dilated grid (three.js) once
/// here; the others read the probes as [`irradiance_at`] does.
#[derive(Clone, Debug)]
pub struct PreparedLookup<'a> {
    view: VolumeView<'a>,
    lookup: Lookup,
    lmax: usize,
    engine: Engine,
}

#[derive(Clone, Debug)]
enum Engine {
    Probes,
    Bevy(BevyLookup),
    ThreeJs(ThreeJsLookup),
}

impl<'a> PreparedLookup<'a> {
    /// `lookup` of `view`'s probes kept to `lmax` (see [`lookup_lmax`]).
    #[must_use]
    pub fn new(view: &VolumeView<'a>, lookup: Lookup, lmax: usize) -> Self {
        let engine = match lookup {
            Lookup::Bevy => Engine::Bevy(BevyLookup::new(view, lmax)),
            Lookup::ThreeJs => Engine::ThreeJs(ThreeJsLookup::new(view, lmax)),
            _ => Engine::Probes,
        };
        Self {
            view: *view,
            lookup,
            lmax,
            engine,
        }
    }

    /// The irradiance at `p` facing `n`: [`irradiance_at`] with this
    /// lookup and lmax.
    #[must_use]
    pub fn irradiance_at(&self, p: Vec3, n: Vec3) -> DVec3 {
        match &self.engine {
            Engine::Bevy(b) => b.irradiance_at(p, n),
            Engine::ThreeJs(t) => t.irradiance_at(p, n),
            Engine::Probes => irradiance_at(&self.view, self.lookup, self.lmax, p, n),
        }
    }
}
