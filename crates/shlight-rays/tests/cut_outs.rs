//! Rays through cut-out and partly covering surfaces: the fraction of rays
//! a `MASK` quad stops is the fraction of its opaque texels, a `BLEND`
//! quad stops its alpha's share, and every query agrees with a brute-force
//! reference that tests each triangle's alpha.

use std::sync::Arc;

use glam::{Affine2, Mat4, Vec2, Vec3, Vec4};
use rand::{Rng, SeedableRng, rngs::StdRng};

mod support;
use shlight_mesh::{
    AlphaMode, Filter, Instance, Material, Mesh, Primitive, Scene, Surfaces, Texture, TextureRef,
    Wrap, generate,
};
use shlight_rays::{
    CutOuts, Direction, LANES, Occluder, Packet, Ray, brute_force_closest_hit,
    brute_force_closest_hit_through, coverage_sample,
};
use support::random_unit;

/// A 16x16 texture, nearest-filtered, whose texels are opaque (alpha 255)
/// with probability `p`, transparent (alpha 0) otherwise; and the exact
/// fraction of opaque texels.
fn checker(p: f64, seed: u64) -> (Texture, f64) {
    let mut rng = StdRng::seed_from_u64(seed);
    let texels: Vec<[u8; 4]> = (0..256)
        .map(|_| {
            let a = if rng.random_bool(p) { 255 } else { 0 };
            [200, 200, 200, a]
        })
        .collect();
    let opaque = texels.iter().filter(|t| t[3] == 255).count() as f64 / 256.0;
    let texture = Texture {
        width: 16,
        height: 16,
        texels,
        wrap_u: Wrap::Repeat,
        wrap_v: Wrap::Repeat,
        filter: Filter::Nearest,
    };
    (texture, opaque)
}

/// A unit quad in the xz plane facing +y, its UV `(x + 0.5, z + 0.5)`.
fn quad() -> (Mesh, Vec<Vec2>) {
    let plane = generate::plane(1.0, 1);
    let uv = plane
        .positions
        .iter()
        .map(|p| Vec2::new(p.x + 0.5, p.z + 0.5))
        .collect();
    (plane, uv)
}

/// Quads placed by `transforms`, each with material `materials[k]`.
fn scene(
    parts: &[(Mat4, usize)],
    materials: Vec<Material>,
    textures: Vec<Texture>,
) -> Arc<Surfaces> {
    let (mesh, uv) = quad();
    let primitives = (0..materials.len())
        .map(|m| Primitive {
            mesh: mesh.clone(),
            uvs: vec![uv.clone()],
            color_alpha: None,
            material: Some(m),
            label: format!("quad {m}"),
        })
        .collect();
    let instances = parts
        .iter()
        .map(|&(transform, primitive)| Instance {
            primitive,
            transform,
        })
        .collect();
    let scene = Scene {
        source: "cut-outs.glb".into(),
        primitives,
        instances,
        materials,
        textures,
        ..Scene::default()
    };
    Arc::new(scene.flatten(Vec3::splat(0.5)).unwrap())
}

fn masked() -> Material {
    Material {
        base_color_texture: Some(TextureRef {
            texture: 0,
            tex_coord: 0,
            transform: Affine2::IDENTITY,
        }),
        alpha_mode: AlphaMode::Mask { cutoff: 0.5 },
        ..Material::default()
    }
}

fn blended(alpha: f32) -> Material {
    Material {
        base_color: Vec4::new(1.0, 1.0, 1.0, alpha),
        alpha_mode: AlphaMode::Blend,
        ..Material::default()
    }
}

/// Origins spread evenly at random over the quad's square, 1 above it.
fn origins_above(n: usize, seed: u64) -> Vec<Vec3> {
    let mut rng = StdRng::seed_from_u64(seed);
    (0..n)
        .map(|_| {
            Vec3::new(
                rng.random_range(-0.5..0.5),
                1.0,
                rng.random_range(-0.5..0.5),
            )
        })
        .collect()
}

/// Fractions of rays from `origins` along `dir` stopped: single-ray
/// occlusion, single-ray closest hits, packet occlusion, packet closest
/// hits.
fn stopped_fractions(occluder: &Occluder, origins: &[Vec3], dir: Vec3) -> [f64; 4] {
    let (mut single, mut closest, mut packets, mut packet_closest) = (0, 0, 0, 0);
    for o in origins {
        let ray = Ray::new(*o, dir, f32::INFINITY);
        single += usize::from(occluder.occluded(&ray));
        closest += usize::from(occluder.closest_hit(&ray).is_some());
    }
    let d = Direction::new(dir);
    let local: Vec<[f32; 4]> = occluder.ray_space(&d).collect();
    for eight in origins.chunks(LANES) {
        let packet = Packet::new(&d, eight);
        packets += occluder.packet_occluded(&d, &local, &packet).count_ones() as usize;
        let found = occluder.packet_closest(&d, &local, &packet);
        assert_eq!(occluder.packet_closest_direct(&d, &packet), found);
        packet_closest += found.mask.count_ones() as usize;
    }
    let n = origins.len() as f64;
    [single, closest, packets, packet_closest].map(|c| c as f64 / n)
}

#[test]
fn a_masked_quad_stops_the_fraction_of_its_opaque_texels() {
    let (texture, opaque) = checker(0.37, 1);
    assert!((0.25..0.5).contains(&opaque), "{opaque}");
    let surfaces = scene(&[(Mat4::IDENTITY, 0)], vec![masked()], vec![texture]);
    let occluder = Occluder::with_cut_outs(&surfaces.mesh, surfaces.clone());
    assert!(occluder.has_cut_outs());
    let n = 40_000;
    let origins = origins_above(n, 2);
    // Straight down, each ray reads the texel under its origin: the
    // origins are uniform over the quad, so a ray is stopped with the
    // probability of an opaque texel. Slanted rays, from origins shifted
    // back along them, meet the quad at uniform points too.
    for dir in [Vec3::NEG_Y, Vec3::new(0.3, -1.0, -0.2)] {
        let shifted: Vec<Vec3> = origins
            .iter()
            .map(|o| *o - Vec3::new(dir.x, 0.0, dir.z) / dir.y.abs())
            .collect();
        let sigma = (opaque * (1.0 - opaque) / n as f64).sqrt();
        for f in stopped_fractions(&occluder, &shifted, dir) {
            assert!(
                (f - opaque).abs() < 4.0 * sigma,
                "{f} stopped, {opaque} of the texels opaque"
            );
        }
    }
    // Without its cut-outs the quad stops every one of them.
    let solid = Occluder::new(&surfaces.mesh);
    assert_eq!(stopped_fractions(&solid, &origins, Vec3::NEG_Y), [1.0; 4]);
}

#[test]
fn a_blended_quad_stops_its_alpha_of_the_rays_the_same_rays_every_time() {
    let surfaces = scene(&[(Mat4::IDENTITY, 0)], vec![blended(0.3)], Vec::new());
    let occluder = Occluder::with_cut_outs(&surfaces.mesh, surfaces.clone());
    let n = 40_000;
    let origins = origins_above(n, 3);
    let fractions = stopped_fractions(&occluder, &origins, Vec3::NEG_Y);
    let sigma = (0.3 * 0.7 / n as f64).sqrt();
    assert!(
        (fractions[0] - 0.3).abs() < 4.0 * sigma,
        "{fractions:?} of the rays stopped"
    );
    // Every query decides each ray alike (the same hash), so the four
    // fractions are one.
    assert!(
        fractions.iter().all(|&f| f == fractions[0]),
        "{fractions:?}"
    );
    // And a ray is stopped exactly when its coverage sample, computed here
    // from its bits, is below the alpha.
    let solid = Occluder::new(&surfaces.mesh);
    for o in &origins[..2000] {
        let ray = Ray::new(*o, Vec3::NEG_Y, f32::INFINITY);
        let hit = solid
            .closest_hit(&ray)
            .expect("every origin is over the quad");
        let want = coverage_sample(*o, Vec3::NEG_Y, hit.triangle) < 0.3;
        assert_eq!(occluder.occluded(&ray), want);
    }
}

#[test]
fn cut_out_queries_agree_with_a_brute_force_reference() {
    // Quads at three heights, turned about: a masked checker, a blended
    // one (alpha 0.45) and an opaque one, each twice, so rays pass through
    // cut-outs to what is behind.
    let (texture, _) = checker(0.5, 4);
    let turn = |y: f32, angle: f32, scale: f32| {
        Mat4::from_translation(Vec3::new(0.0, y, 0.0))
            * Mat4::from_rotation_x(angle)
            * Mat4::from_scale(Vec3::splat(scale))
    };
    let parts = [
        (turn(0.0, 0.0, 2.0), 0),
        (turn(0.3, 0.4, 1.5), 1),
        (turn(0.6, -0.3, 1.8), 0),
        (turn(0.9, 0.2, 1.2), 1),
        (turn(-0.4, 0.1, 1.0), 2),
        (turn(1.2, 3.0, 1.0), 2),
    ];
    let surfaces = scene(
        &parts,
        vec![masked(), blended(0.45), Material::default()],
        vec![texture],
    );
    let mesh = &surfaces.mesh;
    let occluder = Occluder::with_cut_outs(mesh, surfaces.clone());
    let cut: &dyn CutOuts = &*surfaces;
    let mut rng = StdRng::seed_from_u64(5);
    let (mut hits, mut passed, mut mismatched, mut rays) = (0, 0, 0, 0);
    for _ in 0..200 {
        // Eight parallel rays from a small patch, as bakes make them.
        let d = random_unit(&mut rng);
        let dir = Direction::new(d);
        let centre = Vec3::new(
            rng.random_range(-0.8..0.8),
            rng.random_range(-0.6..1.5),
            rng.random_range(-0.8..0.8),
        );
        let origins: Vec<Vec3> = (0..LANES)
            .map(|_| centre + Vec3::new(rng.random(), rng.random(), rng.random()) * 0.1)
            .collect();
        let local: Vec<[f32; 4]> = occluder.ray_space(&dir).collect();
        let packet = Packet::new(&dir, &origins);
        let blocked = occluder.packet_occluded(&dir, &local, &packet);
        let found = occluder.packet_closest(&dir, &local, &packet);
        for (k, o) in origins.iter().enumerate() {
            rays += 1;
            let want = brute_force_closest_hit_through(mesh, cut, *o, dir.dir(), 0.0);
            let solid = brute_force_closest_hit(mesh, o.as_dvec3(), dir.dir().as_dvec3(), 0.0);
            passed += usize::from(solid.map(|h| h.1) != want.map(|h| h.1));
            let ray = Ray::new(*o, dir.dir(), f32::INFINITY);
            let single = occluder.closest_hit(&ray);
            let agree = |got: Option<(f32, u32)>| match (got, want) {
                (Some((t, g)), Some((tw, w, ..))) => {
                    g as usize == w && (f64::from(t) - tw).abs() < 1e-4 * tw.max(1.0)
                }
                (None, None) => true,
                _ => false,
            };
            let packet_hit = (found.mask >> k & 1 == 1).then(|| (found.t[k], found.triangle[k]));
            // Only a ray grazing an edge, or meeting a texel's border,
            // where the weights' rounding picks the texel, may disagree.
            mismatched += usize::from(!agree(single.map(|h| (h.t, h.triangle))));
            mismatched += usize::from(!agree(packet_hit));
            mismatched += usize::from(occluder.occluded(&ray) != want.is_some());
            mismatched += usize::from((blocked >> k & 1 == 1) != want.is_some());
            hits += usize::from(want.is_some());
        }
    }
    assert!(
        hits > 400 && passed > 100,
        "{hits} hits, {passed} passed a cut-out, of {rays}"
    );
    assert!(mismatched <= 4, "{mismatched} disagreements in {rays} rays");
}
