//! The two-level occluder of a scene's instances against the flattened
//! scene: every query agrees with brute force over the flattened mesh
//! (triangle, distance, weights in the flattened corner order, the side
//! met), through rotated, scaled, mirrored and tiny instances and through
//! cut-outs; and its memory grows with the unique triangles, not the
//! instances.

use std::sync::Arc;

use glam::{Affine2, Mat4, Quat, Vec2, Vec3, Vec4};
use rand::{Rng, SeedableRng, rngs::StdRng};

mod support;
use shlight_mesh::{
    AlphaMode, Filter, Instance, Material, Mesh, Primitive, Scene, Texture, TextureRef, Wrap,
    generate,
};
use shlight_rays::{
    CutOuts, Direction, InstancedOccluder, LANES, Occluder, Packet, Ray, brute_force_closest_hit,
    brute_force_closest_hit_through,
};
use support::random_unit;

fn primitive(mesh: Mesh, material: Option<usize>, label: &str) -> Primitive {
    let uv = mesh
        .positions
        .iter()
        .map(|p| Vec2::new(p.x + 0.5, p.z + 0.5))
        .collect();
    Primitive {
        mesh,
        uvs: vec![uv],
        color_alpha: None,
        material,
        label: label.into(),
    }
}

fn place(primitive: usize, transform: Mat4) -> Instance {
    Instance {
        primitive,
        transform,
    }
}

/// A sphere, a torus and a plane, placed eight times: turned, scaled
/// unevenly, mirrored (one mirrored and turned), overlapping, and one
/// sphere so small beside the rest that some of its triangles are
/// degenerate in the flattened mesh (left out of it).
fn placed_scene() -> Scene {
    let srt = |s: Vec3, r: Quat, t: Vec3| Mat4::from_scale_rotation_translation(s, r, t);
    Scene {
        source: "instances.glb".into(),
        primitives: vec![
            primitive(generate::uv_sphere(1.0, 16, 8), None, "sphere"),
            primitive(generate::torus(1.0, 0.3, 24, 12), None, "torus"),
            primitive(generate::plane(8.0, 4), None, "plane"),
            // Used by no instance.
            primitive(generate::uv_sphere(1.0, 4, 3), None, "unused"),
        ],
        instances: vec![
            place(2, Mat4::from_translation(Vec3::new(0.0, -1.0, 0.0))),
            place(0, Mat4::IDENTITY),
            place(
                0,
                srt(
                    Vec3::new(0.5, 1.5, 0.8),
                    Quat::from_rotation_z(0.6),
                    Vec3::new(2.5, 0.3, 0.0),
                ),
            ),
            place(
                1,
                srt(
                    Vec3::new(1.0, -1.0, 1.0),
                    Quat::from_rotation_x(0.9),
                    Vec3::new(-2.0, 0.5, 1.0),
                ),
            ),
            place(
                1,
                srt(
                    Vec3::splat(0.7),
                    Quat::from_euler(glam::EulerRot::XYZ, 0.3, 1.1, -0.4),
                    Vec3::new(0.5, 0.2, -2.2),
                ),
            ),
            place(
                0,
                srt(
                    Vec3::new(-0.6, 0.6, 0.6),
                    Quat::IDENTITY,
                    Vec3::new(-1.0, 1.5, -1.0),
                ),
            ),
            // Overlaps the unit sphere.
            place(1, Mat4::from_translation(Vec3::new(0.3, 0.0, 0.2))),
            // 8e-5 across: its smaller triangles fall under the
            // flattening's degenerate area (1e-12 of the squared diagonal).
            place(
                0,
                srt(Vec3::splat(4e-5), Quat::IDENTITY, Vec3::new(3.0, 2.0, 3.0)),
            ),
        ],
        ..Scene::default()
    }
}

/// The flattened triangle's corners.
fn corners(mesh: &Mesh, triangle: u32) -> [Vec3; 3] {
    mesh.triangles[triangle as usize].map(|i| mesh.positions[i as usize])
}

#[test]
fn two_level_queries_agree_with_brute_force_over_the_flattened_scene() {
    let scene = placed_scene();
    let flat = scene.flatten(Vec3::ONE).unwrap().mesh;
    let occluder = InstancedOccluder::new(&scene).unwrap();
    assert_eq!(occluder.triangle_count(), flat.triangle_count());
    // The tiny sphere lost triangles in the flattening, so the numbering
    // after it is shifted: the test below would catch a layout that
    // ignores it.
    let placed: usize = scene
        .instances
        .iter()
        .map(|i| scene.primitives[i.primitive].mesh.triangle_count())
        .sum();
    assert!(flat.triangle_count() < placed);
    let mut rng = StdRng::seed_from_u64(11);
    let (mut hits, mut mirrored_hits, mut fronts, mut backs, mut mismatched) = (0, 0, 0, 0, 0);
    let mut rays = Vec::new();
    for _ in 0..3000 {
        let o = Vec3::new(
            rng.random_range(-4.0..4.0),
            rng.random_range(-0.9..3.0),
            rng.random_range(-4.0..4.0),
        );
        rays.push((o, random_unit(&mut rng)));
    }
    // Rays aimed at the tiny sphere, where dropped triangles must not be
    // hit.
    for _ in 0..200 {
        let o = Vec3::new(3.0, 2.0, 3.0) + random_unit(&mut rng) * 0.5;
        let target = Vec3::new(3.0, 2.0, 3.0) + random_unit(&mut rng) * 3e-5;
        rays.push((o, (target - o).normalize()));
    }
    let (mut aimed_mismatched, mut aimed_hits) = (0, 0);
    for (r, &(o, d)) in rays.iter().enumerate() {
        let mismatched = if r < 3000 {
            &mut mismatched
        } else {
            &mut aimed_mismatched
        };
        let ray = Ray::new(o, d, f32::INFINITY);
        let got = occluder.closest_hit(&ray);
        assert_eq!(occluder.occluded(&ray), got.is_some());
        let want = brute_force_closest_hit(&flat, o.as_dvec3(), d.as_dvec3(), 0.0);
        let (Some(g), Some((t, k, ..))) = (got, want) else {
            // Only a ray grazing an edge may disagree.
            *mismatched += usize::from(got.is_some() != want.is_some());
            continue;
        };
        hits += 1;
        aimed_hits += usize::from(r >= 3000);
        assert!(
            (f64::from(g.t) - t).abs() < 1e-4 * t.max(1.0),
            "t {} vs {t}",
            g.t
        );
        *mismatched += usize::from(g.triangle as usize != k);
        // The weights are those of the flattened triangle's corners, in
        // its order (reversed for a mirrored instance).
        let [a, b, c] = corners(&flat, g.triangle);
        let w = g.barycentrics;
        let at = a * w[0] + b * w[1] + c * w[2];
        assert!(
            at.distance(o + d * g.t) < 1e-4 * (1.0 + g.t),
            "{at} vs {}",
            o + d * g.t
        );
        let front = (b - a).cross(c - a).dot(d) < 0.0;
        assert_eq!(occluder.is_front(g.triangle, d), front);
        fronts += usize::from(front);
        backs += usize::from(!front);
        let (first_mirrored, end_mirrored) = mirrored_range(&scene, &flat);
        mirrored_hits += usize::from((first_mirrored..end_mirrored).contains(&g.triangle));
    }
    assert!(
        hits > 1000 && mirrored_hits > 50 && fronts > 300 && backs > 100,
        "{hits} hits, {mirrored_hits} on the mirrored torus, {fronts} fronts, {backs} backs"
    );
    assert!(mismatched <= 3, "{mismatched} disagreements");
    // The tiny sphere's triangles are a few hundred units in the last
    // place across, in the world and in its space alike: rounding decides
    // more of its edges.
    assert!(
        aimed_hits > 150 && aimed_mismatched <= 10,
        "{aimed_mismatched} of {aimed_hits} hits of the tiny sphere disagree"
    );
    // A far limit short of everything.
    let ray = Ray::new(Vec3::new(0.0, 3.0, 0.0), Vec3::NEG_Y, 1.5);
    assert!(!occluder.occluded(&ray) && occluder.closest_hit(&ray).is_none());
}

/// The flattened triangles of the first mirrored instance (the torus
/// scaled by -1 in y, the fourth instance).
fn mirrored_range(scene: &Scene, flat: &Mesh) -> (u32, u32) {
    let layout = scene.flat_layout().unwrap();
    let first = layout.triangle(3, 0).unwrap();
    let count = scene.primitives[1].mesh.triangle_count() as u32;
    let end = layout.triangle(4, 0).unwrap();
    assert_eq!(end - first, count);
    assert!(end as usize <= flat.triangle_count());
    (first, end)
}

#[test]
fn packets_of_instances_agree_with_single_rays_and_the_flat_packets() {
    let scene = placed_scene();
    let flat = scene.flatten(Vec3::ONE).unwrap().mesh;
    let occluder = InstancedOccluder::new(&scene).unwrap();
    let flat_occluder = Occluder::new(&flat);
    let mut rng = StdRng::seed_from_u64(3);
    let (mut blocked, mut differ) = (0, 0);
    for _ in 0..100 {
        let dir = Direction::new(random_unit(&mut rng));
        let centre = Vec3::new(
            rng.random_range(-3.0..3.0),
            rng.random_range(-0.5..2.5),
            rng.random_range(-3.0..3.0),
        );
        let origins: Vec<Vec3> = (0..LANES - 1)
            .map(|_| centre + random_unit(&mut rng) * 0.3)
            .collect();
        let packet = Packet::new(&dir, &origins);
        let mask = occluder.packet_occluded(&dir, &packet);
        let found = occluder.packet_closest(&dir, &packet);
        assert_eq!(found.mask, mask);
        assert_eq!(mask >> (LANES - 1), 0, "no ray in the last lane");
        let flat_found = flat_occluder.packet_closest_direct(&dir, &packet);
        for (k, o) in origins.iter().enumerate() {
            let single = occluder.closest_hit(&Ray::new(*o, dir.dir(), f32::INFINITY));
            let lane = (mask >> k & 1 == 1).then(|| (found.t[k], found.triangle[k]));
            assert_eq!(single.map(|h| (h.t, h.triangle)), lane);
            let flat_lane = (flat_found.mask >> k & 1 == 1).then_some(flat_found.triangle[k]);
            differ += usize::from(lane.map(|l| l.1) != flat_lane);
            blocked += usize::from(lane.is_some());
        }
    }
    assert!(blocked > 200, "{blocked}");
    assert!(
        differ <= 2,
        "{differ} lanes differ from the flat occluder's"
    );
}

/// A 16x16 nearest-filtered texture, each texel opaque or transparent
/// at random.
fn checker(seed: u64) -> Texture {
    let mut rng = StdRng::seed_from_u64(seed);
    Texture {
        width: 16,
        height: 16,
        texels: (0..256)
            .map(|_| [200, 200, 200, if rng.random_bool(0.5) { 255 } else { 0 }])
            .collect(),
        wrap_u: Wrap::Repeat,
        wrap_v: Wrap::Repeat,
        filter: Filter::Nearest,
    }
}

#[test]
fn cut_outs_through_instances_agree_with_brute_force() {
    // A masked checker quad, a blended quad (alpha 0.45) and an opaque
    // one, each placed twice, turned, scaled, one of each mirrored: rays
    // pass through cut-outs to what lies behind, and a mirrored instance's
    // weights (reversed corners) must still find the right texel.
    let masked = Material {
        base_color_texture: Some(TextureRef {
            texture: 0,
            tex_coord: 0,
            transform: Affine2::IDENTITY,
        }),
        alpha_mode: AlphaMode::Mask { cutoff: 0.5 },
        ..Material::default()
    };
    let blended = Material {
        base_color: Vec4::new(1.0, 1.0, 1.0, 0.45),
        alpha_mode: AlphaMode::Blend,
        ..Material::default()
    };
    let quad = || generate::plane(1.0, 2);
    let turn = |y: f32, angle: f32, scale: Vec3| {
        Mat4::from_translation(Vec3::new(0.0, y, 0.0))
            * Mat4::from_rotation_x(angle)
            * Mat4::from_scale(scale)
    };
    let scene = Scene {
        source: "cut-outs.glb".into(),
        primitives: vec![
            primitive(quad(), Some(0), "masked"),
            primitive(quad(), Some(1), "blended"),
            primitive(quad(), Some(2), "opaque"),
        ],
        instances: vec![
            place(0, turn(0.0, 0.0, Vec3::splat(2.0))),
            place(1, turn(0.3, 0.4, Vec3::new(1.5, 1.0, -1.5))),
            place(0, turn(0.6, -0.3, Vec3::new(-1.8, 1.0, 1.8))),
            place(1, turn(0.9, 0.2, Vec3::splat(1.2))),
            place(2, turn(-0.4, 0.1, Vec3::ONE)),
            place(2, turn(1.2, 3.0, Vec3::new(1.0, -1.0, 1.0))),
        ],
        materials: vec![masked, blended, Material::default()],
        textures: vec![checker(4)],
        ..Scene::default()
    };
    let surfaces = Arc::new(scene.flatten(Vec3::splat(0.5)).unwrap());
    let mesh = &surfaces.mesh;
    let occluder = InstancedOccluder::with_cut_outs(&scene, surfaces.clone()).unwrap();
    assert!(occluder.has_cut_outs());
    let cut: &dyn CutOuts = &*surfaces;
    let mut rng = StdRng::seed_from_u64(5);
    let (mut hits, mut passed, mut mismatched, mut rays) = (0, 0, 0, 0);
    for _ in 0..2000 {
        let d = random_unit(&mut rng);
        let o = Vec3::new(
            rng.random_range(-0.8..0.8),
            rng.random_range(-0.6..1.5),
            rng.random_range(-0.8..0.8),
        );
        rays += 1;
        let want = brute_force_closest_hit_through(mesh, cut, o, d, 0.0);
        let solid = brute_force_closest_hit(mesh, o.as_dvec3(), d.as_dvec3(), 0.0);
        passed += usize::from(solid.map(|h| h.1) != want.map(|h| h.1));
        let ray = Ray::new(o, d, f32::INFINITY);
        let got = occluder.closest_hit(&ray);
        mismatched += usize::from(match (got, want) {
            (Some(g), Some((tw, w, ..))) => {
                g.triangle as usize != w || (f64::from(g.t) - tw).abs() > 1e-4 * tw.max(1.0)
            }
            (None, None) => false,
            // Only a ray grazing an edge, or meeting a texel's border,
            // where the weights' rounding picks the texel, may disagree.
            _ => true,
        });
        mismatched += usize::from(occluder.occluded(&ray) != want.is_some());
        hits += usize::from(want.is_some());
    }
    assert!(
        hits > 600 && passed > 200,
        "{hits} hits, {passed} passed a cut-out, of {rays}"
    );
    assert!(mismatched <= 4, "{mismatched} disagreements in {rays} rays");
}

#[test]
fn memory_grows_with_the_unique_triangles_not_the_instances() {
    // A 10,000-triangle torus placed once, 10 times and 1,000 times on a
    // grid: the two-level occluder adds a fixed amount per instance, far
    // below a copy of the mesh; the flat occluder grows with every copy.
    let torus = generate::torus(1.0, 0.3, 100, 50);
    assert_eq!(torus.triangle_count(), 10_000);
    let scene = |n: usize| Scene {
        source: "grid.glb".into(),
        primitives: vec![primitive(torus.clone(), None, "torus")],
        instances: (0..n)
            .map(|i| {
                let at = Vec3::new((i % 32) as f32, 0.0, (i / 32) as f32) * 3.0;
                place(
                    0,
                    Mat4::from_rotation_translation(Quat::from_rotation_y(i as f32), at),
                )
            })
            .collect(),
        ..Scene::default()
    };
    let two_level = |n| InstancedOccluder::new(&scene(n)).unwrap().heap_bytes();
    let flat = |n| Occluder::new(&scene(n).flatten(Vec3::ONE).unwrap().mesh).heap_bytes();
    let (one, thousand) = (two_level(1), two_level(1000));
    let per_instance = (thousand - one) as f64 / 999.0;
    let (flat_one, flat_ten) = (flat(1), flat(10));
    let per_copy = (flat_ten - flat_one) as f64 / 9.0;
    eprintln!(
        "two-level: {one} bytes for 1 instance, {thousand} for 1,000 ({per_instance:.0} per \
         instance); flat: {flat_one} for 1, {flat_ten} for 10 ({per_copy:.0} per copy)"
    );
    // Per instance: a transform (64 bytes) and a few words of numbering
    // and top-level nodes.
    assert!(per_instance < 200.0, "{per_instance} bytes per instance");
    // The unique mesh's hierarchy: at most the flat occluder's of one copy.
    assert!(one <= flat_one, "{one} vs {flat_one}");
    // A copy of the mesh costs the flat occluder about what one whole
    // copy's hierarchy does (not a fixed amount per instance).
    assert!(per_copy > 0.9 * flat_one as f64, "{per_copy} vs {flat_one}");
    // 1,000 instances in less than two unique meshes' worth.
    assert!(thousand < 2 * one, "{thousand} vs {one}");
}

#[test]
fn an_occluder_for_repeating_surfaces_casts_through_two_levels_as_the_flat_one() {
    // The placed scene repeats its sphere and torus: its flattened
    // surfaces carry the placement, and `Occluder::for_surfaces` casts
    // through two levels, answering every query the bakers ask (packets
    // without a ray-space copy, where rays start, which side is met) as
    // one hierarchy over the flattened triangles does.
    let surfaces = Arc::new(placed_scene().flatten(Vec3::ONE).unwrap());
    assert!(surfaces.placement.is_some());
    let two = Occluder::for_surfaces(&surfaces);
    let flat = Occluder::new(&surfaces.mesh);
    assert!(two.is_two_level() && !flat.is_two_level());
    assert_eq!(two.vertex_count(), 0);
    assert!(two.heap_bytes() * 2 < flat.heap_bytes());
    // Where rays start: the same points, up to the two levels' rounding.
    let (a, b) = (
        two.ray_origins(&surfaces.mesh),
        flat.ray_origins(&surfaces.mesh),
    );
    let off = a
        .iter()
        .zip(&b)
        .filter(|(p, q)| p.distance(**q) > 1e-5)
        .count();
    assert!(off <= 2, "{off} ray origins differ");
    let mut rng = StdRng::seed_from_u64(9);
    let (mut hits, mut differ) = (0, 0);
    for _ in 0..100 {
        let dir = Direction::new(random_unit(&mut rng));
        let origins: Vec<Vec3> = (0..LANES)
            .map(|_| {
                Vec3::new(
                    rng.random_range(-3.0..3.0),
                    rng.random_range(-0.5..2.5),
                    rng.random_range(-3.0..3.0),
                )
            })
            .collect();
        let packet = Packet::new(&dir, &origins);
        let local: Vec<[f32; 4]> = flat.ray_space(&dir).collect();
        let want = flat.packet_closest(&dir, &local, &packet);
        let got = two.packet_closest(&dir, &[], &packet);
        assert_eq!(got.mask, two.packet_closest_direct(&dir, &packet).mask);
        assert_eq!(got.mask, two.packet_occluded(&dir, &[], &packet));
        for k in 0..LANES {
            let lane =
                |h: &shlight_rays::PacketHits| (h.mask >> k & 1 == 1).then_some(h.triangle[k]);
            differ += usize::from(lane(&got) != lane(&want));
            if let Some(t) = lane(&got) {
                hits += 1;
                assert_eq!(two.is_front(t, dir.dir()), flat.is_front(t, dir.dir()));
            }
        }
    }
    assert!(hits > 200, "{hits}");
    assert!(
        differ <= 2,
        "{differ} lanes differ from the flat occluder's"
    );
}

#[test]
fn a_scene_that_places_each_primitive_once_casts_through_one_hierarchy() {
    let mut scene = placed_scene();
    scene.instances.retain({
        let mut seen = [false; 4];
        move |i| !std::mem::replace(&mut seen[i.primitive], true)
    });
    let surfaces = Arc::new(scene.flatten(Vec3::ONE).unwrap());
    assert!(surfaces.placement.is_none());
    assert!(!Occluder::for_surfaces(&surfaces).is_two_level());
}
