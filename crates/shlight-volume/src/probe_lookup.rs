//! [`ProbeLookup`]: shlight's own lookups, `shlight` and `trilinear`, made
//! ready for many points: the weights of the probes around a point, the
//! radiance they give there, and its irradiance from the probes' irradiance
//! coefficients made once.

use glam::{DVec3, Vec3};
use shlight_baked::visibility::visibility_weights;
use shlight_baked::{MAX_LMAX, ProbeGrid, VolumeView};
use shlight_core::sh::{ShBasis, ShCoeffs, ZonalKernel, sh_count};

/// The `shlight` or `trilinear` lookup of a volume's probes, kept to an
/// lmax: per probe its irradiance coefficients `A_l L_lm`, `[r, g, b]`
/// rows, so that a point's irradiance is the weighted sum of the probes'
/// irradiance at its normal.
#[derive(Clone, Debug)]
pub(crate) struct ProbeLookup<'a> {
    view: VolumeView<'a>,
    /// Weigh the probes by their distance maps (the `shlight` lookup of a
    /// volume that holds them), else trilinearly.
    visibility: bool,
    /// The degrees read: at most the volume's.
    lmax: usize,
    irradiance: Vec<DVec3>,
    basis: ShBasis<f64>,
}

impl<'a> ProbeLookup<'a> {
    /// The probes of `view` kept to `lmax` (at most the volume's), weighed
    /// by their distance maps when `visibility` (the volume must hold
    /// them), else trilinearly.
    pub(crate) fn new(view: &VolumeView<'a>, visibility: bool, lmax: usize) -> Self {
        let shaded = view.lmax.min(lmax);
        let per = sh_count(view.lmax);
        let kernel = ZonalKernel::clamped_cosine(shaded);
        let irradiance = view
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
        Self {
            view: *view,
            visibility,
            lmax: shaded,
            irradiance,
            basis: ShBasis::new(shaded),
        }
    }

    /// The weights of the probes around `p` (unit normal `n`, any length
    /// but 0), summing to 1 (empty where no valid probe is around):
    /// shlight-baked's visibility weights where the lookup weighs by
    /// distance maps, else the valid probes' trilinear weights
    /// renormalised.
    pub(crate) fn weights(&self, p: Vec3, n: Vec3) -> Vec<(usize, f64)> {
        if self.visibility {
            visibility_weights(&self.view, p, n.normalize())
                .unwrap_or_default()
                .into_iter()
                .map(|(k, w)| (k, f64::from(w)))
                .collect()
        } else {
            valid_trilinear(&self.view.grid, self.view.valid, p)
        }
    }

    /// The radiance coefficients at `p` facing `n`: `sum_k w_k L_k` of the
    /// probes' radiance with [`ProbeLookup::weights`], kept to the lmax;
    /// `None` where no valid probe is around `p`.
    pub(crate) fn radiance_at(&self, p: Vec3, n: Vec3) -> Option<ShCoeffs<DVec3>> {
        let weights = self.weights(p, n);
        if weights.is_empty() {
            return None;
        }
        let (per, nc) = (sh_count(self.view.lmax), sh_count(self.lmax));
        let mut out = ShCoeffs::<DVec3>::zeros(self.lmax);
        for (i, w) in weights {
            for (o, rgb) in out
                .as_mut_slice()
                .iter_mut()
                .zip(self.view.radiance[i * 3 * per..][..3 * nc].chunks_exact(3))
            {
                *o += w * Vec3::from_slice(rgb).as_dvec3();
            }
        }
        Some(out)
    }

    /// The irradiance `E(p, n) = sum_k w_k sum_lm A_l L_k,lm Y_lm(n)` with
    /// [`ProbeLookup::weights`]: the irradiance of
    /// [`ProbeLookup::radiance_at`], its weighted sum taken after the
    /// convolution (the same value, in another order of sums); 0 where no
    /// valid probe is around `p`.
    pub(crate) fn irradiance_at(&self, p: Vec3, n: Vec3) -> DVec3 {
        let weights = self.weights(p, n);
        if weights.is_empty() {
            return DVec3::ZERO;
        }
        let nc = sh_count(self.lmax);
        let mut y = [0.0f64; sh_count(MAX_LMAX)];
        self.basis.eval(n.as_dvec3().normalize(), &mut y[..nc]);
        let mut out = DVec3::ZERO;
        for (k, w) in weights {
            let probe = &self.irradiance[k * nc..][..nc];
            let mut sum = DVec3::ZERO;
            for (c, yl) in probe.iter().zip(&y[..nc]) {
                sum += *c * *yl;
            }
            out += w * sum;
        }
        out
    }
}

/// The trilinear weights of the valid probes among the eight around `p`,
/// renormalised to sum to 1 (empty when none is valid).
fn valid_trilinear(grid: &ProbeGrid, valid: &[bool], p: Vec3) -> Vec<(usize, f64)> {
    let corners: Vec<(usize, f32)> = grid
        .trilinear(p)
        .into_iter()
        .filter(|&(i, _)| valid[i])
        .collect();
    let total: f64 = corners.iter().map(|&(_, w)| f64::from(w)).sum();
    if total <= 0.0 {
        return Vec::new();
    }
    corners
        .into_iter()
        .map(|(i, w)| (i, f64::from(w) / total))
        .collect()
}
