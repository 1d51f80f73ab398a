//! Punctual lights (glTF's `KHR_lights_punctual`, [`PunctualLight`]) at a
//! bake's vertices, as a path tracer such as Cycles treats them: deltas,
//! whose direct light is found with a shadow ray. At a vertex at `p` with
//! unit normal `n`: `E_direct = sum E_perp max(n . toward, 0)` over the
//! lights whose shadow ray reaches them from the vertex's ray origin (where
//! its transfer's rays start, [`Occluder::ray_origins`]); a light behind
//! the surface gives nothing (surfaces are one-sided). A bake takes it as
//! [`BakeOptions::direct_irradiance`](crate::BakeOptions::direct_irradiance)
//! ([`punctual_irradiance`]); shlight-volume's probes use [`light_reaches`]
//! too.
//!
//! A shadow ray meets both sides of a triangle (a surface seen from behind
//! still casts its shadow), passes cut-outs where the occluder was built
//! with them ([`Occluder::with_cut_outs`]), and is cast up to the light
//! itself (to infinity for a directional light). Every sum runs over the
//! lights in their order, in `f64`, per vertex: the same bits at any
//! thread count.

use glam::{DVec3, Vec3};
use rayon::prelude::*;
use shlight_format::VolumeLights;
use shlight_mesh::{Arrival, LightKind, LightUnits, Mesh, PunctualLight};
use shlight_rays::{Occluder, Ray};

/// Whether the light of `arrival` (found at a point `at`) reaches `from`,
/// the point the shadow ray starts at (`at` itself, or a vertex's ray
/// origin just off its surface): nothing in `occluder` (`None`: an empty
/// scene) between `from` and the light.
pub fn light_reaches(occluder: Option<&Occluder>, at: Vec3, from: Vec3, arrival: &Arrival) -> bool {
    let Some(occluder) = occluder else {
        return true;
    };
    let ray = if arrival.distance.is_finite() {
        // Up to the light's own position: `t` in (0, 1).
        let light = at + arrival.toward * arrival.distance;
        Ray::new(from, light - from, 1.0)
    } else {
        Ray::new(from, arrival.toward, f32::INFINITY)
    };
    !occluder.occluded(&ray)
}

/// Per vertex of `mesh` (the scene, or a mesh subdivided from the one
/// `occluder` was made of), the irradiance `lights` (in `units`) give it
/// directly: `sum E_perp max(n . toward, 0)` over the lights whose shadow
/// ray from the vertex's ray origin ([`Occluder::ray_origins`]) reaches
/// them, `E_perp` and `toward` taken at the vertex.
#[must_use]
pub fn punctual_irradiance(
    occluder: &Occluder,
    mesh: &Mesh,
    lights: &[PunctualLight],
    units: LightUnits,
) -> Vec<Vec3> {
    let origins = occluder.ray_origins(mesh);
    mesh.positions
        .par_iter()
        .zip(&mesh.normals)
        .zip(&origins)
        .map(|((&p, &n), &o)| {
            let mut e = DVec3::ZERO;
            for light in lights {
                let Some(a) = light.arriving(p, units) else {
                    continue;
                };
                let cos = n.dot(a.toward);
                if cos <= 0.0 || !light_reaches(Some(occluder), p, o, &a) {
                    continue;
                }
                e += a.irradiance.as_dvec3() * f64::from(cos);
            }
            e.as_vec3()
        })
        .collect()
}

/// What a file records of a bake's punctual lights: their units and how
/// many of each kind (`None` without lights).
#[must_use]
pub fn light_counts(lights: &[PunctualLight], units: LightUnits) -> Option<VolumeLights> {
    if lights.is_empty() {
        return None;
    }
    let count = |f: fn(&LightKind) -> bool| lights.iter().filter(|l| f(&l.kind)).count() as u64;
    Some(VolumeLights {
        units: units.name().to_string(),
        point: count(|k| matches!(k, LightKind::Point)),
        spot: count(|k| matches!(k, LightKind::Spot { .. })),
        directional: count(|k| matches!(k, LightKind::Directional)),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use shlight_mesh::generate;

    fn point(position: Vec3, intensity: f32) -> PunctualLight {
        PunctualLight {
            name: None,
            kind: LightKind::Point,
            color: Vec3::new(1.0, 0.5, 0.25),
            intensity,
            range: None,
            position,
            direction: Vec3::NEG_Y,
        }
    }

    #[test]
    fn a_plane_under_a_point_light_gets_i_cos_over_d_squared_and_none_from_below() {
        // A plane y = 0 (normal +Y) of 4 m, 8 x 8 cells; a light of 10 cd,
        // as written, 1.5 m above (0.3, _, -0.2): each vertex gets
        // I h / d^3 per channel of the light's colour. A second light under
        // the plane gives nothing: it is behind every vertex.
        let plane = generate::plane(4.0, 8);
        let occluder = Occluder::new(&plane);
        let above = Vec3::new(0.3, 1.5, -0.2);
        let lights = [point(above, 10.0), point(Vec3::new(0.0, -1.0, 0.0), 50.0)];
        let e = punctual_irradiance(&occluder, &plane, &lights, LightUnits::AsWritten);
        for (p, e) in plane.positions.iter().zip(&e) {
            let d = f64::from(p.distance(above));
            let want = 10.0 * 1.5 / (d * d * d);
            let got = e.as_dvec3();
            let colour = DVec3::new(1.0, 0.5, 0.25);
            assert!(
                (got - want * colour).abs().max_element() <= 1e-5 * want,
                "{p}: {got} vs {want}"
            );
        }
    }

    #[test]
    fn a_sphere_shadows_the_plane_under_it() {
        // The unit sphere at height 2 over a plane, a light straight above
        // it at height 4: vertices within the shadow's disc get nothing,
        // those well outside it the closed form.
        let scene = generate::plane_under_sphere(1.0, 32, 16, 8.0, 32);
        let occluder = Occluder::new(&scene);
        let (lo, hi) = scene.bounds();
        let floor = lo.y;
        let centre_y = hi.y - 1.0;
        let light = point(Vec3::new(0.0, centre_y + 2.0, 0.0), 100.0);
        let e = punctual_irradiance(
            &occluder,
            &scene,
            std::slice::from_ref(&light),
            LightUnits::AsWritten,
        );
        // The shadow's edge on the floor: the cone from the light tangent
        // to the sphere (half-angle asin(1/2)) at depth h below the light.
        let h = centre_y + 2.0 - floor;
        let edge = h * (1.0f32 / 3.0f32.sqrt());
        let (mut dark, mut lit) = (0, 0);
        for ((p, n), e) in scene.positions.iter().zip(&scene.normals).zip(&e) {
            if (p.y - floor).abs() > 1e-4 || n.y < 0.99 {
                continue;
            }
            let r = Vec3::new(p.x, 0.0, p.z).length();
            if r < 0.9 * edge {
                assert_eq!(*e, Vec3::ZERO, "{p} is in the sphere's shadow");
                dark += 1;
            } else if r > 1.1 * edge {
                let d = f64::from(p.distance(light.position));
                let want = 100.0 * f64::from(h) / (d * d * d);
                assert!((f64::from(e.x) - want).abs() <= 1e-5 * want, "{p}");
                lit += 1;
            }
        }
        assert!(dark >= 4 && lit >= 100, "{dark} dark, {lit} lit");
    }
}
