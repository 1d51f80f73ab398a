//! A scene's lightmap baked (`bake_scene_lightmap`) against closed forms:
//! a floor under a point light (`E = I cos / d^2` at every texel, in each
//! engine's units), two nodes of one mesh given regions of their own,
//! texels under a block standing on the floor found inside geometry, and
//! bad UVs refused by name.

use std::sync::Arc;

use glam::{DVec3, Mat4, Vec2, Vec3};
use shlight_core::sh::closed_form;
use shlight_lightmap::{
    DEFAULT_DENOISE, Engine, L1Reconstruction, LightmapError, LightmapSettings, LightmapSize,
    MAX_DENOISE, SceneLightmap, TexelBasis, TexelFormat, bake_scene_lightmap,
};
use shlight_mesh::{
    Instance, InstanceSource, LightKind, LightUnits, Material, Primitive, PunctualLight, Scene,
    generate,
};

/// A floor quad of side `size` (y = 0, facing up), its lightmap UV
/// `(x / size + 1/2, z / size + 1/2)` in set 1.
fn floor(size: f32) -> Primitive {
    let mesh = generate::plane(size, 1);
    let uv: Vec<Vec2> = mesh
        .positions
        .iter()
        .map(|p| Vec2::new(p.x / size + 0.5, p.z / size + 0.5))
        .collect();
    let mut p = Primitive::new(mesh, Some(0), "mesh 0 (Floor) primitive 0");
    p.uvs = vec![uv.clone(), uv];
    p
}

fn scene(
    primitives: Vec<Primitive>,
    placements: &[(usize, Mat4)],
    lights: Vec<PunctualLight>,
) -> Scene {
    Scene {
        source: "lightmap.glb".into(),
        primitives,
        instances: placements
            .iter()
            .map(|&(primitive, transform)| Instance {
                primitive,
                transform,
            })
            .collect(),
        instance_sources: placements
            .iter()
            .enumerate()
            .map(|(node, &(primitive, _))| InstanceSource {
                node,
                mesh: primitive,
                gpu_instance: None,
            })
            .collect(),
        materials: vec![Material {
            base_color: glam::Vec4::new(0.5, 0.5, 0.5, 1.0),
            ..Material::default()
        }],
        lights,
        ..Scene::default()
    }
}

fn settings(size: LightmapSize) -> LightmapSettings {
    let mut s = LightmapSettings {
        size,
        ..LightmapSettings::default()
    };
    s.gather.samples = 16;
    s.gather.surface_samples = 16;
    s.gather.bounces = 1;
    s.gather.light_units = LightUnits::AsWritten;
    s
}

fn bake(
    scene: &Scene,
    settings: &LightmapSettings,
    sky: DVec3,
) -> Result<SceneLightmap, LightmapError> {
    let surfaces = Arc::new(scene.flatten(Vec3::splat(0.5)).unwrap());
    let env = closed_form::constant(2, sky);
    bake_scene_lightmap(
        scene,
        &surfaces,
        &env,
        &scene.lights,
        settings,
        &|_, _, _| {},
    )
}

fn lamp(position: Vec3, intensity: f32) -> PunctualLight {
    PunctualLight {
        name: None,
        kind: LightKind::Point,
        color: Vec3::new(1.0, 0.8, 0.6),
        intensity,
        range: None,
        position,
        direction: Vec3::NEG_Z,
    }
}

#[test]
fn a_floor_under_a_point_light_holds_i_cos_over_d_squared_in_each_engines_units() {
    let light = lamp(Vec3::new(0.2, 2.0, -0.1), 8.0);
    let s = scene(
        vec![floor(2.0)],
        &[(0, Mat4::IDENTITY)],
        vec![light.clone()],
    );
    let map = bake(&s, &settings(LightmapSize::Side(64)), DVec3::ZERO).unwrap();
    assert_eq!(map.side, 64);
    let r = &map.regions[0];
    assert!(r.rect.side >= 50, "{:?}", r.rect);
    assert_eq!(r.covered, (r.rect.side * r.rect.side) as usize);
    // Every texel of the region, read at its centre's point on the floor:
    // the sample point is within half a texel (3 cm of 2 m), where E
    // changes by under 1.5%.
    let three = map.layers(
        TexelFormat::new(
            TexelBasis::Irradiance,
            Engine::ThreeJs,
            L1Reconstruction::Linear,
        )
        .unwrap(),
    );
    let bevy = map.layers(
        TexelFormat::new(
            TexelBasis::Irradiance,
            Engine::Bevy,
            L1Reconstruction::Linear,
        )
        .unwrap(),
    );
    for y in 0..r.rect.side {
        for x in 0..r.rect.side {
            let uv = (Vec2::new(x as f32, y as f32) + 0.5) / r.rect.side as f32;
            let p = Vec3::new((uv.x - 0.5) * 2.0, 0.0, (uv.y - 0.5) * 2.0);
            let to = light.position - p;
            let want = light.color.as_dvec3() * 8.0 * f64::from(to.normalize().y)
                / f64::from(to.length_squared());
            let k = ((r.rect.y + y) * map.side + r.rect.x + x) as usize;
            let t = map.texels[k].unwrap();
            let rel = (t.irradiance / want - 1.0).abs().max_element();
            assert!(
                rel < 0.015,
                "texel ({x}, {y}): {:?} against {want:?}",
                t.irradiance
            );
            let e = DVec3::new(
                three[0][k][0].into(),
                three[0][k][1].into(),
                three[0][k][2].into(),
            );
            assert!((e - t.irradiance).abs().max_element() < 1e-5 * want.max_element());
            let b = f64::from(bevy[0][k][0]);
            assert!((b - t.irradiance.x / std::f64::consts::PI).abs() < 1e-5 * want.max_element());
        }
    }
    // The padding around the region is dilated.
    let corner = ((r.rect.y - 1) * map.side + r.rect.x - 1) as usize;
    assert!(map.texels[corner].is_some());
}

#[test]
fn two_nodes_of_one_mesh_get_regions_of_their_own_lit_as_their_place_is() {
    let light = lamp(Vec3::new(-2.0, 1.0, 0.0), 4.0);
    let s = scene(
        vec![floor(1.0)],
        &[
            (0, Mat4::from_translation(Vec3::new(-2.0, 0.0, 0.0))),
            (0, Mat4::from_translation(Vec3::new(2.0, 0.0, 0.0))),
        ],
        vec![light],
    );
    let map = bake(&s, &settings(LightmapSize::Density(16.0)), DVec3::ZERO).unwrap();
    assert_eq!(map.regions.len(), 2);
    let (a, b) = (&map.regions[0], &map.regions[1]);
    assert!(!a.rect.overlaps(&b.rect));
    // 16 texels per metre on a 1 m tile.
    assert_eq!((a.rect.side, b.rect.side), (16, 16));
    assert_eq!((a.node, b.node), (Some(0), Some(1)));
    // Two cells of 20 (16 and the padding) side by side need 40 texels:
    // a 64 x 64 atlas, whose last rows are beyond the dilation.
    assert_eq!(map.side, 64);
    assert!(map.texels[(map.side * map.side - 1) as usize].is_none());
    let mean = |r: &shlight_lightmap::LightmapRegion| {
        let mut sum = 0.0;
        for y in 0..r.rect.side {
            for x in 0..r.rect.side {
                sum += map.texels[((r.rect.y + y) * map.side + r.rect.x + x) as usize]
                    .unwrap()
                    .irradiance
                    .x;
            }
        }
        sum / f64::from(r.rect.side * r.rect.side)
    };
    // Under the lamp (1 m above) against 4 m away: E = I / d^2 cos.
    let (near, far) = (mean(a), mean(b));
    assert!(near > 2.0 && near < 4.0, "{near}");
    assert!(far < 0.05 * near, "{far} against {near}");
    // The placement maps the node's UVs onto its texels.
    let uv = Vec2::new(0.25, 0.75);
    let at = a.placement.apply(uv.as_dvec2()) * f64::from(map.side);
    let want = Vec2::new(a.rect.x as f32, a.rect.y as f32) + uv * a.rect.side as f32;
    assert!((at.as_vec2() - want).length() < 1e-3);
}

#[test]
fn texels_under_a_block_standing_on_the_floor_are_found_inside_geometry() {
    let mut block = generate::cuboid(Vec3::new(0.3, 0.5, 0.3));
    for p in &mut block.positions {
        p.y += 0.4;
    }
    let mut solid = Primitive::new(block, Some(0), "mesh 1 (Block) primitive 0");
    // The block's lightmap UVs: each face in its own cell of a 3 x 2 grid.
    let uv: Vec<Vec2> = (0..24)
        .map(|v| {
            let face = v / 4;
            let corner = [
                Vec2::new(0.1, 0.1),
                Vec2::new(0.9, 0.1),
                Vec2::new(0.9, 0.9),
                Vec2::new(0.1, 0.9),
            ][v % 4];
            (Vec2::new((face % 3) as f32, (face / 3) as f32) + corner) / Vec2::new(3.0, 2.0)
        })
        .collect();
    solid.uvs = vec![uv.clone(), uv];
    let s = scene(
        vec![floor(2.0), solid],
        &[(0, Mat4::IDENTITY), (1, Mat4::IDENTITY)],
        vec![],
    );
    let map = bake(&s, &settings(LightmapSize::Side(128)), DVec3::ONE).unwrap();
    // The block stands 0.1 m into the floor over 0.6 x 0.6 m of its 2 x 2.
    let r = &map.regions[0];
    let texel_area = (2.0 / f64::from(r.rect.side)).powi(2);
    let under = 0.36 / texel_area;
    assert!(
        (map.invalid as f64) > 0.7 * under && (map.invalid as f64) < 1.3 * under,
        "{} invalid texels, about {under:.0} under the block",
        map.invalid
    );
    // Every texel has light (the invalid ones filled); the open floor far
    // from the block sees most of the sky: E near pi.
    let k = ((r.rect.y + 2) * map.side + r.rect.x + 2) as usize;
    let e = map.texels[k].unwrap().irradiance.x;
    assert!(
        e > 0.85 * std::f64::consts::PI && e <= std::f64::consts::PI * 1.001,
        "{e}"
    );
}

#[test]
fn a_primitive_without_the_uv_set_or_with_overlapping_uvs_is_refused_by_name() {
    let mut bare = floor(1.0);
    bare.uvs.truncate(1);
    let s = scene(vec![bare], &[(0, Mat4::IDENTITY)], vec![]);
    let e = bake(&s, &settings(LightmapSize::Side(32)), DVec3::ONE)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("mesh 0 (Floor) primitive 0 has no UV set 1 (TEXCOORD_1)"),
        "{e}"
    );

    // Both triangles of the quad on the same half of the square.
    let mut folded = floor(1.0);
    folded.uvs[1] = vec![
        Vec2::new(0.0, 0.0),
        Vec2::new(1.0, 0.0),
        Vec2::new(0.0, 1.0),
        Vec2::new(0.0, 0.0),
    ];
    let s = scene(vec![folded], &[(0, Mat4::IDENTITY)], vec![]);
    let e = bake(&s, &settings(LightmapSize::Side(32)), DVec3::ONE)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("mesh 0 (Floor)") && e.contains("overlap in its lightmap UVs"),
        "{e}"
    );

    let mut outside = floor(1.0);
    outside.uvs[1][2] = Vec2::new(1.5, 0.2);
    let s = scene(vec![outside], &[(0, Mat4::IDENTITY)], vec![]);
    let e = bake(&s, &settings(LightmapSize::Side(32)), DVec3::ONE)
        .unwrap_err()
        .to_string();
    assert!(e.contains("outside the unit square"), "{e}");

    let e = bake(
        &scene(vec![floor(1.0)], &[(0, Mat4::IDENTITY)], vec![]),
        &settings(LightmapSize::Side(2)),
        DVec3::ONE,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("from 4 to"), "{e}");
}

#[test]
fn the_bilinear_read_interpolates_texel_centres_and_skips_empty_texels() {
    // A floor lit by a lamp: at a texel's centre the read is the texel,
    // halfway between two it is their mean.
    let light = lamp(Vec3::new(0.2, 1.0, -0.1), 3.0);
    let s = scene(vec![floor(2.0)], &[(0, Mat4::IDENTITY)], vec![light]);
    let map = bake(&s, &settings(LightmapSize::Side(32)), DVec3::ZERO).unwrap();
    let r = &map.regions[0];
    let side = f64::from(r.rect.side);
    let texel = |x: u32, y: u32| {
        map.texels[((r.rect.y + y) * map.side + r.rect.x + x) as usize]
            .unwrap()
            .irradiance
    };
    let centre = |x: f64, y: f64| Vec2::new(((x + 0.5) / side) as f32, ((y + 0.5) / side) as f32);
    let at = map.bilinear(0, centre(5.0, 7.0)).unwrap().irradiance;
    assert!((at - texel(5, 7)).abs().max_element() < 1e-4 * texel(5, 7).max_element());
    let mid = map.bilinear(0, centre(5.5, 7.0)).unwrap().irradiance;
    let want = (texel(5, 7) + texel(6, 7)) / 2.0;
    assert!((mid - want).abs().max_element() < 1e-4 * want.max_element());
    assert!(map.bilinear(1, centre(1.0, 1.0)).is_none());
}

#[test]
fn a_seam_between_two_charts_reads_the_same_light_on_both_sides() {
    // A 2 x 1 m floor as two 1 m quads sharing the edge x = 0, laid out in
    // two charts of TEXCOORD_1 apart from each other; a lamp low over the
    // seam makes the light change fast across it.
    let mut positions = Vec::new();
    let mut uv = Vec::new();
    for (x0, u0) in [(-1.0f32, 0.05f32), (0.0, 0.55)] {
        for (x, z) in [(0.0, -0.5), (1.0, -0.5), (1.0, 0.5), (0.0, 0.5)] {
            positions.push(Vec3::new(x0 + x, 0.0, z));
            uv.push(Vec2::new(u0 + 0.4 * x, 0.3 + 0.4 * (z + 0.5)));
        }
    }
    let triangles = vec![[0, 2, 1], [0, 3, 2], [4, 6, 5], [4, 7, 6]];
    let mesh = shlight_mesh::Mesh::new(
        "two quads",
        positions,
        triangles,
        Some(vec![Vec3::Y; 8]),
        None,
    )
    .unwrap();
    let mut p = Primitive::new(mesh, Some(0), "mesh 0 (Split) primitive 0");
    p.uvs = vec![uv.clone(), uv];
    let light = lamp(Vec3::new(0.05, 0.3, 0.1), 2.0);
    let s = scene(vec![p], &[(0, Mat4::IDENTITY)], vec![light.clone()]);
    let map = bake(&s, &settings(LightmapSize::Density(32.0)), DVec3::ZERO).unwrap();
    assert_eq!(map.seams, 1);
    let [before, after] = map.seam_gap;
    println!("seam gap: {before:.3e} before stitching, {after:.3e} after");
    for k in 0..40 {
        let z = -0.5 + (k as f32 + 0.5) / 40.0;
        let v = 0.3 + 0.4 * (z + 0.5);
        let a = map.bilinear(0, Vec2::new(0.45, v)).unwrap().irradiance;
        let b = map.bilinear(0, Vec2::new(0.55, v)).unwrap().irradiance;
        let to = light.position - Vec3::new(0.0, 0.0, z);
        let exact = 2.0 * f64::from(to.normalize().y) / f64::from(to.length_squared());
        assert!(
            (a - b).abs().max_element() < 1e-3 * exact,
            "z {z}: {a:?} against {b:?}"
        );
        // The stitched light is still the lamp's (within what bilinear
        // reading of a steep falloff allows).
        assert!(
            (a.x / (exact * f64::from(light.color.x)) - 1.0).abs() < 0.05,
            "z {z}: {a:?}, exact {exact}"
        );
    }
    assert!(before > 20.0 * after, "gap {before} before, {after} after");
}

/// The relative noise of the texels of region 0 within `half` metres of
/// the floor's centre: the RMS difference of two bakes with other seeds,
/// over sqrt(2), over their mean.
fn relative_noise(a: &SceneLightmap, b: &SceneLightmap, floor_side: f32, half: f32) -> f64 {
    let r = &a.regions[0];
    let (mut diff2, mut sum, mut n) = (0.0, 0.0, 0usize);
    for y in 0..r.rect.side {
        for x in 0..r.rect.side {
            let uv = (Vec2::new(x as f32, y as f32) + 0.5) / r.rect.side as f32;
            let p = (uv - 0.5) * floor_side;
            if p.abs().max_element() > half {
                continue;
            }
            let k = ((r.rect.y + y) * a.side + r.rect.x + x) as usize;
            let (ea, eb) = (
                a.texels[k].unwrap().irradiance,
                b.texels[k].unwrap().irradiance,
            );
            diff2 += (ea - eb).length_squared() / 3.0;
            sum += ea.element_sum() / 3.0;
            n += 1;
        }
    }
    (diff2 / n as f64 / 2.0).sqrt() / (sum / n as f64)
}

#[test]
fn an_evenly_lit_floors_noise_is_under_2_percent_at_the_default_settings() {
    // A 3 x 3 m floor under a constant sky and a 1 x 1 m slab 0.6 m up
    // (no lightmap UVs: it casts shadow and bounces light): the light
    // under it is gathered by rays, changing slowly across the floor.
    let mut slab = generate::cuboid(Vec3::new(0.5, 0.05, 0.5));
    for p in &mut slab.positions {
        p.y += 0.6;
    }
    let s = scene(
        vec![
            floor(3.0),
            Primitive::new(slab, Some(0), "mesh 1 (Slab) primitive 0"),
        ],
        &[(0, Mat4::IDENTITY), (1, Mat4::IDENTITY)],
        vec![],
    );
    let with = |seed: u64, denoise: u32| {
        let mut settings = LightmapSettings {
            size: LightmapSize::Density(16.0),
            denoise,
            ..LightmapSettings::default()
        };
        settings.gather.seed = seed;
        bake(&s, &settings, DVec3::ONE).unwrap()
    };
    assert_eq!(LightmapSettings::default().denoise, DEFAULT_DENOISE);
    let too_wide = LightmapSettings {
        denoise: MAX_DENOISE + 1,
        ..LightmapSettings::default()
    };
    let e = bake(&s, &too_wide, DVec3::ONE).unwrap_err().to_string();
    assert!(
        e.contains("denoising radius of 17 texels") && e.contains("at most 16"),
        "{e}"
    );
    let filtered = relative_noise(
        &with(1, DEFAULT_DENOISE),
        &with(2, DEFAULT_DENOISE),
        3.0,
        1.0,
    );
    let raw = relative_noise(&with(1, 0), &with(2, 0), 3.0, 1.0);
    println!("relative noise at 256 rays: {raw:.4} unfiltered, {filtered:.4} filtered");
    assert!(filtered < 0.02, "{filtered}");
    // The filter of radius 2 divides independent texels' noise by about
    // 3.3; the bounce light, shared by neighbouring texels, is not
    // divided.
    assert!(filtered < 0.5 * raw, "{filtered} against {raw}");
}

#[test]
fn the_filter_keeps_a_lit_floor_and_a_dark_wall_apart_at_their_crease() {
    // One node, one chart: a floor (x in [-1, 0], facing up) and a wall
    // rising from its edge x = 0, facing +x, away from a lamp over the
    // floor; the wall black and double-sided, the sky black. The floor's
    // light is the lamp's alone (E = I cos / d^2, no noise) up to the
    // crease, the wall's front none; a filter that ignored normals would
    // average the wall's zeros into the floor's texels along the crease.
    let v = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
    let floor_uv = |p: Vec3| Vec2::new((p.x + 1.0) * 0.45 + 0.05, (p.z + 0.5) * 0.9 + 0.05);
    let wall_uv = |p: Vec3| Vec2::new(0.5 + p.y * 0.45, (p.z + 0.5) * 0.9 + 0.05);
    let quad =
        |corners: [Vec3; 4], normal: Vec3, tris, uv: &dyn Fn(Vec3) -> Vec2, material, label| {
            let mesh =
                shlight_mesh::Mesh::new(label, corners.to_vec(), tris, Some(vec![normal; 4]), None)
                    .unwrap();
            let mut p = Primitive::new(mesh, Some(material), label);
            let uvs: Vec<Vec2> = corners.iter().map(|&c| uv(c)).collect();
            p.uvs = vec![uvs.clone(), uvs];
            p
        };
    let floor = quad(
        [
            v(-1.0, 0.0, -0.5),
            v(0.0, 0.0, -0.5),
            v(0.0, 0.0, 0.5),
            v(-1.0, 0.0, 0.5),
        ],
        Vec3::Y,
        vec![[0, 2, 1], [0, 3, 2]],
        &floor_uv,
        0,
        "mesh 0 (Corner) primitive 0",
    );
    let wall = quad(
        [
            v(0.0, 0.0, -0.5),
            v(0.0, 1.0, -0.5),
            v(0.0, 1.0, 0.5),
            v(0.0, 0.0, 0.5),
        ],
        Vec3::X,
        vec![[0, 1, 2], [0, 2, 3]],
        &wall_uv,
        1,
        "mesh 0 (Corner) primitive 1",
    );
    let light = lamp(Vec3::new(-0.5, 0.8, 0.1), 4.0);
    let mut s = scene(
        vec![floor, wall],
        &[(0, Mat4::IDENTITY), (1, Mat4::IDENTITY)],
        vec![light.clone()],
    );
    for source in &mut s.instance_sources {
        source.node = 0;
        source.mesh = 0;
    }
    s.materials.push(Material {
        base_color: glam::Vec4::new(0.0, 0.0, 0.0, 1.0),
        double_sided: true,
        ..Material::default()
    });
    let mut settings = settings(LightmapSize::Density(40.0));
    settings.denoise = 3;
    let map = bake(&s, &settings, DVec3::ZERO).unwrap();
    assert_eq!(map.regions.len(), 1);
    let r = &map.regions[0];
    let side = r.rect.side as f32;
    let (mut floor_texels, mut wall_texels) = (0, 0);
    for y in 0..r.rect.side {
        for x in 0..r.rect.side {
            let uv = (Vec2::new(x as f32, y as f32) + 0.5) / side;
            // Texels wholly on one side of the crease (u = 0.5), inside
            // the chart.
            if (uv.x - 0.5).abs() < 0.5 / side
                || !(0.05 + 0.5 / side..0.95 - 0.5 / side).contains(&uv.x)
                || !(0.05 + 0.5 / side..0.95 - 0.5 / side).contains(&uv.y)
            {
                continue;
            }
            let z = (uv.y - 0.05) / 0.9 - 0.5;
            let t = map.texels[((r.rect.y + y) * map.side + r.rect.x + x) as usize].unwrap();
            if uv.x < 0.5 {
                let p = Vec3::new((uv.x - 0.05) / 0.45 - 1.0, 0.0, z);
                let to = light.position - p;
                let want = f64::from(light.color.x * 4.0 * to.normalize().y / to.length_squared());
                let rel = (t.irradiance.x / want - 1.0).abs();
                assert!(
                    rel < 0.015,
                    "floor at {p}: {} against {want}",
                    t.irradiance.x
                );
                floor_texels += 1;
            } else {
                assert!(
                    t.irradiance.max_element() < 1e-9,
                    "wall: {:?}",
                    t.irradiance
                );
                wall_texels += 1;
            }
        }
    }
    assert!(
        floor_texels > 1000 && wall_texels > 1000,
        "{floor_texels} {wall_texels}"
    );
}
