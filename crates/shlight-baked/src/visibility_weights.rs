//! [`visibility_weights`]: what a shaded point gives the probes around it,
//! DDGI's visibility term on the trilinear weights (the formula is
//! [`crate::visibility`]'s module documentation).

use glam::Vec3;

use crate::visibility::{CHEBYSHEV_FLOOR, CRUSH, NORMAL_BIAS};
use crate::volume_view::VolumeView;

/// The weights of the probes of `view` around the point `p` with unit
/// normal `n` (`(probe, weight)`, summing to 1; empty when no valid probe
/// is around): the module's formula, the probes where
/// [`VolumeView::position`] puts them. `None` when `view` holds no
/// distance maps.
#[must_use]
pub fn visibility_weights(view: &VolumeView<'_>, p: Vec3, n: Vec3) -> Option<Vec<(usize, f32)>> {
    let visibility = view.visibility.as_ref()?;
    let (grid, valid) = (&view.grid, view.valid);
    let bias = NORMAL_BIAS * grid.cell().min_element();
    let biased = p + n * bias;
    let mut out: Vec<(usize, f32)> = Vec::with_capacity(8);
    for (k, t) in grid.trilinear(p) {
        if !valid[k] {
            continue;
        }
        let v = biased - view.position(k);
        let d = v.length();
        let cheb = if d > 0.0 {
            let (mean, mean_sq) = visibility.moments_at(k, v / d);
            if d > mean {
                let variance = (mean_sq - mean * mean).abs();
                let x = d - mean;
                let c = variance / (variance + x * x);
                c * c * c
            } else {
                1.0
            }
        } else {
            1.0
        };
        let mut w = cheb.max(CHEBYSHEV_FLOOR);
        if w < CRUSH {
            w *= w * w / (CRUSH * CRUSH);
        }
        out.push((k, w * t));
    }
    let total: f32 = out.iter().map(|x| x.1).sum();
    if total > 0.0 {
        for x in &mut out {
            x.1 /= total;
        }
    } else {
        out.clear();
    }
    Some(out)
}
