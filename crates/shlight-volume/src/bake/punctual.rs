//! Punctual lights (glTF's `KHR_lights_punctual`, [`PunctualLight`]) in a
//! volume's bake, as a path tracer such as Cycles treats them: deltas, whose
//! direct light is found with a shadow ray wherever light is gathered.
//!
//! - **At a probe** at `x`: each light arriving there
//!   ([`PunctualLight::arriving`]: `toward`, its distance and `E_perp`)
//!   whose shadow ray from `x` (the probes' own rays start there, `0 < t`)
//!   meets nothing before the light adds the SH projection of the radiance
//!   `E_perp delta(s - toward)`, exactly `E_perp Y_lm(toward)`, to the
//!   probe's static light ([`add_to_probes`]).
//! - **At a surface vertex** at `p` with unit normal `n`:
//!   `E_direct = sum E_perp max(n . toward, 0)` over the lights whose
//!   shadow ray reaches them from the vertex's ray origin (where its
//!   transfer's rays start, [`Occluder::ray_origins`]); a light behind the
//!   surface gives nothing (surfaces are one-sided). The bake hands it to
//!   the surfaces' transfer as [`shlight_prt::BakeOptions::direct_irradiance`],
//!   where `albedo / pi E_direct` is a source of exit radiance beside the
//!   emitters' and bounces as theirs does ([`shlight_prt::punctual_irradiance`],
//!   shared with `shlight prt`'s scenes).
//!
//! A shadow ray meets both sides of a triangle (a surface seen from behind
//! still casts its shadow), and is cast up to the light itself (to
//! infinity for a directional light). Every sum runs over the lights in
//! their order, in `f64`, per probe or vertex: the same bits at any thread
//! count.

use glam::{DVec3, Vec3};
use rayon::prelude::*;
use shlight_core::sh::{ShBasis, sh_count};
use shlight_mesh::{LightUnits, PunctualLight};
use shlight_prt::light_reaches;
use shlight_rays::Occluder;

/// Adds the direct light of `lights` (intensities read in `units`) to the
/// probes at `probes`: per probe `(lmax+1)^2` rows of `[r, g, b]` in
/// `emitted`, each light that reaches the probe unblocked adding
/// `E_perp Y_lm(toward)` (summed in `f64` over the lights, added to the
/// row once).
pub(crate) fn add_to_probes(
    occluder: Option<&Occluder>,
    lights: &[PunctualLight],
    units: LightUnits,
    probes: &[Vec3],
    lmax: usize,
    emitted: &mut [f32],
) {
    let nc = sh_count(lmax);
    let basis = ShBasis::<f64>::new(lmax);
    emitted
        .par_chunks_exact_mut(3 * nc)
        .zip(probes.par_iter())
        .for_each_init(
            || (vec![0.0f64; nc], vec![DVec3::ZERO; nc]),
            |(y, sum), (rows, &x)| {
                sum.fill(DVec3::ZERO);
                for light in lights {
                    let Some(a) = light.arriving(x, units) else {
                        continue;
                    };
                    if !light_reaches(occluder, x, x, &a) {
                        continue;
                    }
                    basis.eval(a.toward.as_dvec3(), y);
                    let e = a.irradiance.as_dvec3();
                    for (s, yi) in sum.iter_mut().zip(y.iter()) {
                        *s += e * *yi;
                    }
                }
                for (row, s) in rows.chunks_exact_mut(3).zip(sum.iter()) {
                    for (r, v) in row.iter_mut().zip(s.to_array()) {
                        *r = (f64::from(*r) + v) as f32;
                    }
                }
            },
        );
}
