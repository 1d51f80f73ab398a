//! [`PreparedLookup`]: a [`Lookup`] made ready once for many points (the
//! engines' lookups build their texture or dilated grid first), and
//! [`lookup_lmax`], the lmax each lookup reads a volume to.

use glam::{DVec3, Vec3};
use shlight_baked::{MAX_LMAX, SHADED_MAX_LMAX, VolumeView};
use shlight_core::sh::{ShBasis, ShCoeffs, ZonalKernel, sh_count};

use crate::bevy_lookup::BevyLookup;
use crate::lookup::probe_weights;
use crate::threejs_lookup::{THREEJS_LMAX, ThreeJsLookup};
use crate::{Lookup, VolumeError, shaded_lmax};

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
/// for shlight's lookups, above 2 for three.js's. The message says why;
/// the caller names the option as its users spell it (`--lmax 5`,
/// `lmax=5`).
pub fn lookup_lmax(
    view: &VolumeView<'_>,
    lookup: Lookup,
    requested: Option<usize>,
) -> Result<LookupLmax, VolumeError> {
    let refuse = |most: usize, why: &str| -> Result<(), VolumeError> {
        match requested.filter(|&l| l > most) {
            Some(_) => Err(VolumeError::Options(format!("{why} lmax {most} at most"))),
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
/// here; the others read the probes as [`irradiance_at`](crate::irradiance_at) does.
#[derive(Clone, Debug)]
pub struct PreparedLookup<'a> {
    view: VolumeView<'a>,
    lookup: Lookup,
    lmax: usize,
    precomputed: Precomputed,
}

/// What a [`PreparedLookup`] computes once for all its points.
#[derive(Clone, Debug)]
enum Precomputed {
    /// The `shlight` and `trilinear` lookups: per probe its irradiance
    /// coefficients `A_l L_lm` to the lookup's lmax, `[r, g, b]` rows.
    Probes(Vec<DVec3>, ShBasis<f64>),
    /// The `bevy` lookup: the volume as Bevy's texture.
    Bevy(BevyLookup),
    /// The `threejs` lookup: the dilated grid in three.js's basis.
    ThreeJs(ThreeJsLookup),
}

impl PreparedLookup<'_> {
    /// [`crate::irradiance_at`] of the `shlight` and `trilinear` lookups
    /// from the probes' irradiance coefficients `e`: the same weights, the
    /// weighted sum taken after the convolution (the same value, in
    /// another order of sums).
    fn probes_at(&self, e: &[DVec3], basis: &ShBasis<f64>, p: Vec3, n: Vec3) -> DVec3 {
        let view = &self.view;
        let weights = probe_weights(view, self.lookup, p, n);
        if weights.is_empty() {
            return DVec3::ZERO;
        }
        let lmax = view.lmax.min(self.lmax);
        let nc = sh_count(lmax);
        let mut y = [0.0f64; sh_count(MAX_LMAX)];
        basis.eval(n.as_dvec3().normalize(), &mut y[..nc]);
        let mut out = DVec3::ZERO;
        for (k, w) in weights {
            let probe = &e[k * nc..][..nc];
            let mut sum = DVec3::ZERO;
            for (c, yl) in probe.iter().zip(&y[..nc]) {
                sum += *c * *yl;
            }
            out += w * sum;
        }
        out
    }
}

impl<'a> PreparedLookup<'a> {
    /// `lookup` of `view`'s probes kept to `lmax` (see [`lookup_lmax`]).
    #[must_use]
    pub fn new(view: &VolumeView<'a>, lookup: Lookup, lmax: usize) -> Self {
        let precomputed = match lookup {
            Lookup::Bevy => Precomputed::Bevy(BevyLookup::new(view, lmax)),
            Lookup::ThreeJs => Precomputed::ThreeJs(ThreeJsLookup::new(view, lmax)),
            _ => {
                let shaded = view.lmax.min(lmax);
                let per = sh_count(view.lmax);
                let kernel = ZonalKernel::clamped_cosine(shaded);
                let e = view
                    .radiance
                    .chunks_exact(3 * per)
                    .flat_map(|probe| {
                        let l = ShCoeffs::from_vec(
                            probe[..3 * sh_count(shaded)]
                                .chunks_exact(3)
                                .map(|c| Vec3::from_slice(c).as_dvec3())
                                .collect(),
                        )
                        .expect("whole degrees");
                        kernel.apply(&l).as_slice().to_vec()
                    })
                    .collect();
                Precomputed::Probes(e, ShBasis::new(shaded))
            }
        };
        Self {
            view: *view,
            lookup,
            lmax,
            precomputed,
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

    /// The irradiance at `p` facing `n`: [`irradiance_at`](crate::irradiance_at) with this
    /// lookup and lmax.
    #[must_use]
    pub fn irradiance_at(&self, p: Vec3, n: Vec3) -> DVec3 {
        match &self.precomputed {
            Precomputed::Bevy(b) => b.irradiance_at(p, n),
            Precomputed::ThreeJs(t) => t.irradiance_at(p, n),
            Precomputed::Probes(e, basis) => self.probes_at(e, basis, p, n),
        }
    }
}
