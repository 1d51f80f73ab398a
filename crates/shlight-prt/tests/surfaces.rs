//! Bakes through a glTF scene's surfaces: a bounce takes the albedo of the
//! texel it hits (a two-coloured floor tints the ceiling above each half as
//! the closed-form view factors say; a metal floor sends none), cut-outs
//! let the rays through (a masked ceiling passes the fraction of its
//! transparent texels, a blended one its share, the same bits at any thread
//! count), and a scene of one colour per triangle bakes as it does without
//! surfaces.

use core::f64::consts::PI;
use std::sync::Arc;

use glam::{Affine2, DVec3, Mat4, Vec2, Vec3, Vec4};
use rand::{Rng, SeedableRng, rngs::StdRng};
use shlight_core::sh::closed_form;
use shlight_mesh::{
    AlphaMode, Filter, Instance, Material, Mesh, Primitive, Scene, Surfaces, Texture, TextureRef,
    Wrap, generate,
};
use shlight_prt::{Albedo, BakeOptions, Mode, Transfer, bake, bake_with_occluder};

/// A unit quad in the xz plane facing +y, `divisions` squares a side, its
/// UV `(x + 0.5, z + 0.5)`.
fn quad(divisions: u32) -> (Mesh, Vec<Vec2>) {
    let plane = generate::plane(1.0, divisions);
    let uv = plane
        .positions
        .iter()
        .map(|p| Vec2::new(p.x + 0.5, p.z + 0.5))
        .collect();
    (plane, uv)
}

/// A scene of quads: `parts` are (mesh divisions, transform, material).
fn scene(
    parts: &[(u32, Mat4, usize)],
    materials: Vec<Material>,
    textures: Vec<Texture>,
) -> Arc<Surfaces> {
    let mut primitives = Vec::new();
    let mut instances = Vec::new();
    for (k, &(divisions, transform, material)) in parts.iter().enumerate() {
        let (mesh, uv) = quad(divisions);
        primitives.push(Primitive {
            mesh,
            uvs: vec![uv],
            color_alpha: None,
            material: Some(material),
            label: format!("quad {k}"),
        });
        instances.push(Instance {
            primitive: k,
            transform,
        });
    }
    let scene = Scene {
        source: "surfaces.glb".into(),
        primitives,
        instances,
        materials,
        textures,
        ..Scene::default()
    };
    Arc::new(scene.flatten(Vec3::splat(0.5)).unwrap())
}

/// A texture of `texels` in one row, nearest-filtered.
fn row_texture(texels: Vec<[u8; 4]>) -> Texture {
    Texture {
        width: texels.len(),
        height: 1,
        texels,
        wrap_u: Wrap::ClampToEdge,
        wrap_v: Wrap::ClampToEdge,
        filter: Filter::Nearest,
    }
}

fn textured(texture: usize, tiles: f32) -> TextureRef {
    TextureRef {
        texture,
        tex_coord: 0,
        transform: Affine2::from_scale(Vec2::splat(tiles)),
    }
}

/// Quads facing down (the ceiling's front towards the floor).
fn facing_down(at: Vec3, scale: f32) -> Mat4 {
    Mat4::from_translation(at)
        * Mat4::from_rotation_x(std::f32::consts::PI)
        * Mat4::from_scale(Vec3::splat(scale))
}

fn lying(at: Vec3, scale: f32) -> Mat4 {
    Mat4::from_translation(at) * Mat4::from_scale(Vec3::splat(scale))
}

fn options(mode: Mode, samples: usize, surfaces: &Arc<Surfaces>, albedo: f32) -> BakeOptions {
    BakeOptions {
        lmax: 2,
        samples,
        mode,
        albedo: Albedo::Constant([albedo; 3]),
        seed: 7,
        emission: None,
        surfaces: Some(surfaces.clone()),
        direct_irradiance: None,
    }
}

/// Exit radiance per vertex under a constant sky of radiance 1.
fn under_white_sky(t: &Transfer) -> Vec<Vec3> {
    t.exit_radiance(&closed_form::constant(t.lmax, DVec3::ONE))
}

/// The share of a downward-facing point's cosine-weighted view of the
/// plane `h` below it that lies beyond a line `d` away along the plane
/// (`d > 0`: on the point's side): `(1 + d / sqrt(d^2 + h^2)) / 2`.
fn half_plane_view(d: f64, h: f64) -> f64 {
    0.5 * (1.0 + d / (d * d + h * h).sqrt())
}

/// A floor of 20 x 20 at y = 0 facing up, red for x < 0 and blue for
/// x > 0 (a 2 x 1 texture), and two small ceilings 0.1 above it facing
/// down, over x = -0.1 and x = +0.1.
fn two_colour_room(floor: Material) -> (Arc<Surfaces>, [Vec3; 2]) {
    two_colour_room_from(floor, false)
}

/// [`two_colour_room`], or with `below` the small quads 0.1 under the
/// floor facing up, towards its underside.
fn two_colour_room_from(floor: Material, below: bool) -> (Arc<Surfaces>, [Vec3; 2]) {
    let texture = row_texture(vec![[188, 40, 40, 255], [40, 40, 188, 255]]);
    // The texels' linear colours, as the texture decodes them.
    let red = texture.sample(Vec2::new(0.25, 0.5), true).truncate();
    let blue = texture.sample(Vec2::new(0.75, 0.5), true).truncate();
    let facing_floor = |x: f32| {
        if below {
            lying(Vec3::new(x, -0.1, 0.0), 0.02)
        } else {
            facing_down(Vec3::new(x, 0.1, 0.0), 0.02)
        }
    };
    let surfaces = scene(
        &[
            (1, lying(Vec3::ZERO, 20.0), 0),
            (1, facing_floor(-0.1), 1),
            (1, facing_floor(0.1), 1),
        ],
        vec![floor, Material::default()],
        vec![texture],
    );
    (surfaces, [red, blue])
}

/// The bounce light (interreflected, one bounce, less shadowed) at each
/// vertex under a white sky.
fn bounce_light(surfaces: &Arc<Surfaces>, albedo: f32) -> Vec<Vec3> {
    let mesh = &surfaces.mesh;
    let run = |mode| bake(mesh, &options(mode, 8192, surfaces, albedo), &|_, _, _| {});
    let once = under_white_sky(&run(Mode::Interreflected { bounces: 1 }));
    let direct = under_white_sky(&run(Mode::Shadowed));
    once.iter().zip(&direct).map(|(a, b)| *a - *b).collect()
}

#[test]
fn a_two_coloured_floor_tints_the_ceiling_above_each_half() {
    let floor = Material {
        base_color_texture: Some(textured(0, 1.0)),
        ..Material::default()
    };
    let (surfaces, [red, blue]) = two_colour_room(floor);
    assert!(red.x > 10.0 * red.z && blue.z > 10.0 * blue.x);
    // The ceilings' albedo 1: their bounce light is the light arriving.
    let bounced = bounce_light(&surfaces, 1.0);
    let mesh = &surfaces.mesh;
    let mut checked = 0;
    for (v, p) in mesh.positions.iter().enumerate() {
        if p.y < 0.05 {
            continue;
        }
        // The floor under a ceiling vertex leaves its texel's albedo times
        // the sky's irradiance over pi, 1 (the ceilings hide a few
        // thousandths of the floor's sky; the floor's edges, 10 away, a
        // ten-thousandth of the ceiling's view): the bounce light is each
        // half's albedo times its share of the view.
        let own = half_plane_view(f64::from(p.x.abs()), 0.1) as f32;
        let (near, far) = if p.x < 0.0 { (red, blue) } else { (blue, red) };
        let want = near * own + far * (1.0 - own);
        let got = bounced[v];
        assert!(
            (got - want).abs().max_element() < 0.012,
            "vertex at {p}: {got} vs {want}"
        );
        // Tinted by the half below it.
        if p.x < 0.0 {
            assert!(got.x > 3.0 * got.z, "{got}");
        } else {
            assert!(got.z > 3.0 * got.x, "{got}");
        }
        checked += 1;
    }
    assert_eq!(checked, 8);
}

#[test]
fn a_lit_floor_passes_its_texels_colour_to_the_ceiling_as_emitters_do_not() {
    // The room above, its floor lit directly (BakeOptions::
    // direct_irradiance: pi on every floor vertex, so the light arriving
    // over pi is 1) and, the second time, emitting Le = 0.2 as well; the
    // vertex albedo is 1 everywhere, the floor's texels red and blue. The
    // lights' light is read times the albedo of the texel hit: the
    // ceilings' bounce light is each half's texel albedo times its share of
    // the view, as under a white sky; the emission reaches them as it is.
    let floor = Material {
        base_color_texture: Some(textured(0, 1.0)),
        ..Material::default()
    };
    let (surfaces, [red, blue]) = two_colour_room(floor);
    let mesh = &surfaces.mesh;
    let on_floor = |p: &Vec3| p.y < 0.05;
    let lit: Vec<Vec3> = mesh
        .positions
        .iter()
        .map(|p| {
            if on_floor(p) {
                Vec3::splat(PI as f32)
            } else {
                Vec3::ZERO
            }
        })
        .collect();
    let le = Vec3::splat(0.2);
    for emission in [None, Some(le)] {
        let options = BakeOptions {
            direct_irradiance: Some(lit.clone()),
            emission: emission.map(|le| {
                mesh.positions
                    .iter()
                    .map(|p| if on_floor(p) { le } else { Vec3::ZERO })
                    .collect()
            }),
            ..options(Mode::Interreflected { bounces: 1 }, 8192, &surfaces, 1.0)
        };
        let emitted = bake(mesh, &options, &|_, _, _| {}).emitted.unwrap();
        let mut checked = 0;
        for (v, p) in mesh.positions.iter().enumerate() {
            if on_floor(p) {
                // Its own light: Le plus its albedo (1) times what arrives.
                let want = emission.unwrap_or(Vec3::ZERO) + Vec3::ONE;
                assert!(
                    (emitted[v] - want).abs().max_element() < 1e-5,
                    "{}",
                    emitted[v]
                );
                continue;
            }
            let own = half_plane_view(f64::from(p.x.abs()), 0.1) as f32;
            let (near, far) = if p.x < 0.0 { (red, blue) } else { (blue, red) };
            let want = near * own + far * (1.0 - own) + emission.unwrap_or(Vec3::ZERO);
            let got = emitted[v];
            assert!(
                (got - want).abs().max_element() < 0.012,
                "{emission:?}: vertex at {p}: {got} vs {want}"
            );
            checked += 1;
        }
        assert_eq!(checked, 8);
    }
}

#[test]
fn a_double_sided_floor_tints_what_lies_under_it_as_its_top_does_above() {
    // The two-coloured room upside down: the small quads under the floor,
    // facing its underside. Double-sided, the underside is lit by the sky
    // below and reflects it in its texels' colours: each quad's bounce
    // light is each half's albedo times its share of the view, as above
    // the floor; emitting, the underside emits as the top does. One-sided,
    // the underside is a back face: no bounce light, no emission.
    let le = Vec3::splat(0.2);
    for double_sided in [true, false] {
        let floor = Material {
            base_color_texture: Some(textured(0, 1.0)),
            double_sided,
            ..Material::default()
        };
        let (surfaces, [red, blue]) = two_colour_room_from(floor, true);
        let bounced = bounce_light(&surfaces, 1.0);
        let mesh = &surfaces.mesh;
        let on_floor = |p: &Vec3| p.y.abs() < 0.05;
        let emission: Vec<Vec3> = mesh
            .positions
            .iter()
            .map(|p| if on_floor(p) { le } else { Vec3::ZERO })
            .collect();
        let options = BakeOptions {
            emission: Some(emission),
            ..options(Mode::Interreflected { bounces: 1 }, 1024, &surfaces, 1.0)
        };
        let t = bake(mesh, &options, &|_, _, _| {});
        // The transfer is the mesh's vertices' (their front); the floor's
        // four corners have back copies when it is double-sided.
        assert_eq!(t.vertex_count, mesh.vertex_count());
        assert_eq!(t.coeffs.len(), mesh.vertex_count() * 3 * 9);
        let back = t.back.as_ref().map(|b| b.sides.copies.len());
        assert_eq!(back, double_sided.then_some(4));
        let emitted = t.emitted.as_ref().unwrap();
        let mut checked = 0;
        for (v, p) in mesh.positions.iter().enumerate() {
            if p.y > -0.05 {
                continue;
            }
            let own = half_plane_view(f64::from(p.x.abs()), 0.1) as f32;
            let (near, far) = if p.x < 0.0 { (red, blue) } else { (blue, red) };
            let (want, want_emitted) = if double_sided {
                // The floor's edges, 10 away, hide a ten-thousandth of the
                // view.
                (near * own + far * (1.0 - own), le)
            } else {
                (Vec3::ZERO, Vec3::ZERO)
            };
            let got = bounced[v];
            assert!(
                (got - want).abs().max_element() < 0.012,
                "double-sided {double_sided}: vertex at {p}: {got} vs {want}"
            );
            assert!(
                (emitted[v] - want_emitted).abs().max_element() < 1e-3,
                "double-sided {double_sided}: vertex at {p}: {} vs {want_emitted}",
                emitted[v]
            );
            checked += 1;
        }
        assert_eq!(checked, 8);
    }
}

#[test]
fn a_metal_floor_reflects_no_diffuse_light_onto_the_ceiling() {
    let white = Material {
        base_color: Vec4::ONE,
        ..Material::default()
    };
    let metal = Material {
        metallic: 1.0,
        ..white.clone()
    };
    // The vertices' own albedo is 0.8 whatever the floor: only the hits
    // read the floor's material.
    let (dielectric, _) = two_colour_room(white);
    let (metallic, _) = two_colour_room(metal);
    let lit = bounce_light(&dielectric, 0.8);
    let dark = bounce_light(&metallic, 0.8);
    for (v, p) in metallic.mesh.positions.iter().enumerate() {
        if p.y > 0.05 {
            // A white floor sends the ceiling 0.8 x (nearly) 1; a metal
            // one nothing, exactly.
            assert!(
                (lit[v] - Vec3::splat(0.8)).abs().max_element() < 0.01,
                "{}",
                lit[v]
            );
            assert_eq!(dark[v], Vec3::ZERO);
        }
    }
}

/// A 16 x 16 texture whose texels are opaque with probability `p`, the
/// others alpha 0, black; and the fraction of opaque texels.
fn alpha_checker(p: f64, seed: u64) -> (Texture, f64) {
    let mut rng = StdRng::seed_from_u64(seed);
    let texels: Vec<[u8; 4]> = (0..256)
        .map(|_| [0, 0, 0, if rng.random_bool(p) { 255 } else { 0 }])
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

/// The cosine-weighted view from a point of the square of half-side `a`
/// parallel to it, `h` away, centred over it (four corner rectangles).
fn square_view(a: f64, h: f64) -> f64 {
    let (x, y) = (a / h, a / h);
    let corner = |x: f64, y: f64| {
        let (sx, sy) = ((1.0 + x * x).sqrt(), (1.0 + y * y).sqrt());
        (x / sx * (y / sx).atan() + y / sy * (x / sy).atan()) / (2.0 * PI)
    };
    4.0 * corner(x, y)
}

/// A floor of 3.3 x 3.3 (vertices 0.825 apart, 6.6 texels of the ceiling
/// below, so that their rays meet unrelated texels) under a ceiling of
/// 200 x 200, 1 above it, facing down, black, with `ceiling`'s alpha mode,
/// baked on `threads` threads: the light on the floor's vertices under a
/// white sky (albedo 1), and the bake.
fn light_under(ceiling: Material, textures: Vec<Texture>, threads: usize) -> (Vec<Vec3>, Transfer) {
    let surfaces = scene(
        &[
            (4, lying(Vec3::ZERO, 3.3), 0),
            (1, facing_down(Vec3::new(0.0, 1.0, 0.0), 200.0), 1),
        ],
        vec![Material::default(), ceiling],
        textures,
    );
    let options = options(Mode::Interreflected { bounces: 1 }, 16384, &surfaces, 1.0);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let t = pool.install(|| bake(&surfaces.mesh, &options, &|_, _, _| {}));
    let floor: Vec<Vec3> = under_white_sky(&t)
        .into_iter()
        .zip(&surfaces.mesh.positions)
        .filter(|(_, p)| p.y < 0.5)
        .map(|(e, _)| e)
        .collect();
    (floor, t)
}

#[test]
fn a_masked_ceiling_passes_the_fraction_of_its_transparent_texels() {
    let (texture, opaque) = alpha_checker(0.37, 3);
    assert!((0.25..0.5).contains(&opaque));
    let ceiling = Material {
        base_color: Vec4::new(0.0, 0.0, 0.0, 1.0),
        base_color_texture: Some(textured(0, 100.0)),
        alpha_mode: AlphaMode::Mask { cutoff: 0.5 },
        ..Material::default()
    };
    let (floor, _) = light_under(ceiling, vec![texture], 2);
    assert_eq!(floor.len(), 25);
    // The ceiling covers all but a ten-thousandth of the floor's view; a
    // ray reaching it passes where a texel is transparent (texels an
    // eighth of the height across, so its rays meet them evenly), and the
    // black ceiling sends nothing back.
    let view = square_view(100.0, 1.0);
    let want = 1.0 - opaque * view;
    let mean = floor.iter().map(|e| f64::from(e.x)).sum::<f64>() / floor.len() as f64;
    // About 8,000 rays a vertex: the blocked share's standard deviation is
    // sqrt(f (1 - f) sum w^2) = 0.0075 (cosine weights), 0.0015 for the
    // mean of 25: 4 of them.
    assert!(
        (mean - want).abs() < 0.006,
        "{mean} of the sky's light passes, {want} expected ({opaque} of the texels opaque)"
    );
    // Each vertex alone within 5 of its standard deviations (their spread
    // is a little wider than the cosine weights say: neighbouring rays
    // meet neighbouring texels).
    for e in &floor {
        assert!((f64::from(e.x) - want).abs() < 0.05, "{e} vs {want}");
    }
}

#[test]
fn a_blended_ceiling_passes_its_share_the_same_at_any_thread_count() {
    let ceiling = Material {
        base_color: Vec4::new(0.0, 0.0, 0.0, 0.3),
        alpha_mode: AlphaMode::Blend,
        ..Material::default()
    };
    let (floor, once) = light_under(ceiling.clone(), Vec::new(), 2);
    let want = 1.0 - 0.3 * square_view(100.0, 1.0);
    let mean = floor.iter().map(|e| f64::from(e.x)).sum::<f64>() / floor.len() as f64;
    assert!((mean - want).abs() < 0.006, "{mean} vs {want}");
    // The same bits again, and on one thread.
    let (_, again) = light_under(ceiling.clone(), Vec::new(), 2);
    let (_, alone) = light_under(ceiling, Vec::new(), 1);
    assert_eq!(once.coeffs, again.coeffs);
    assert_eq!(once.coeffs, alone.coeffs);
    assert_eq!(once.incident, alone.incident);
}

/// A sphere over a plane as one glTF primitive with one coloured, emitting
/// material.
fn one_colour_scene() -> Arc<Surfaces> {
    let mesh = generate::plane_under_sphere(1.0, 16, 8, 4.0, 4);
    let uv = vec![Vec2::ZERO; mesh.vertex_count()];
    let scene = Scene {
        source: "one-colour.glb".into(),
        primitives: vec![Primitive {
            mesh,
            uvs: vec![uv],
            color_alpha: None,
            material: Some(0),
            label: "mesh 0 primitive 0".into(),
        }],
        instances: vec![Instance {
            primitive: 0,
            transform: Mat4::IDENTITY,
        }],
        materials: vec![Material {
            base_color: Vec4::new(0.7, 0.5, 0.3, 1.0),
            emissive: Vec3::new(0.2, 0.1, 0.4),
            ..Material::default()
        }],
        ..Scene::default()
    };
    Arc::new(scene.flatten(Vec3::ONE).unwrap())
}

#[test]
fn one_colour_per_triangle_bakes_as_it_does_without_surfaces() {
    // With the albedo the same at a triangle's corners, the albedo of a
    // texel hit times the light interpolated there is the interpolation of
    // the corners' exit light: the bake with surfaces (incident records,
    // scaled per hit) and the one without (exit records) agree to
    // rounding, emitters included; cast against the mesh itself and
    // against the one a subdivided mesh came from.
    let surfaces = one_colour_scene();
    let coarse = &surfaces.mesh;
    let (fine, map) = coarse.subdivided_with_map(0.4);
    for (mesh, occluder) in [(coarse, None), (&fine, Some((coarse, &map)))] {
        let without = BakeOptions {
            lmax: 2,
            samples: 512,
            mode: Mode::Interreflected { bounces: 3 },
            albedo: Albedo::PerVertex(mesh.colors.clone().unwrap()),
            seed: 3,
            emission: mesh.emission.clone(),
            surfaces: None,
            direct_irradiance: None,
        };
        let with = BakeOptions {
            surfaces: Some(surfaces.clone()),
            ..without.clone()
        };
        let a = bake_with_occluder(mesh, occluder, &without, &|_, _, _| {});
        let b = bake_with_occluder(mesh, occluder, &with, &|_, _, _| {});
        assert!(a.incident.is_none() && b.incident.is_some());
        let max = a.coeffs.iter().fold(0.0f32, |m, x| m.max(x.abs()));
        for (x, y) in a.coeffs.iter().zip(&b.coeffs) {
            assert!((x - y).abs() <= 2e-5 * max, "{x} vs {y}");
        }
        let bounced = a.emitted.as_ref().unwrap();
        for (x, y) in bounced.iter().zip(b.emitted.as_ref().unwrap()) {
            assert!((*x - *y).abs().max_element() <= 2e-5, "{x} vs {y}");
        }
        // And the light arriving is the exit light over the albedo.
        let arriving = b.incident.as_ref().unwrap();
        let colours = mesh.colors.as_ref().unwrap();
        for (v, rho) in colours.iter().enumerate() {
            for c in 0..3 {
                let row = &arriving.coeffs[v * 27 + c * 9..][..9];
                let out = &b.coeffs[v * 27 + c * 9..][..9];
                for (g, t) in row.iter().zip(out) {
                    assert!((g * rho[c] - t).abs() <= 1e-6 * max);
                }
            }
        }
    }
}

#[test]
fn glossy_matrices_through_one_colour_per_triangle_are_those_without_surfaces() {
    // The glossy matrices gather the diffuse bounce light at their hits:
    // with the albedo the same at a triangle's corners, reading it per hit
    // (surfaces) or through the corners' exit transfer (without) agrees to
    // rounding.
    let surfaces = one_colour_scene();
    let mesh = &surfaces.mesh;
    let without = BakeOptions {
        lmax: 2,
        samples: 256,
        mode: Mode::Interreflected { bounces: 2 },
        albedo: Albedo::PerVertex(mesh.colors.clone().unwrap()),
        seed: 9,
        emission: None,
        surfaces: None,
        direct_irradiance: None,
    };
    let with = BakeOptions {
        surfaces: Some(surfaces.clone()),
        ..without.clone()
    };
    let a = shlight_prt::bake_glossy(mesh, &without, &|_, _, _| {});
    let b = shlight_prt::bake_glossy(mesh, &with, &|_, _, _| {});
    assert_eq!((a.channels, b.channels), (3, 3));
    let max = a.matrices.iter().fold(0.0f32, |m, x| m.max(x.abs()));
    let mut bounced = 0;
    for (x, y) in a.matrices.iter().zip(&b.matrices) {
        assert!((x - y).abs() <= 2e-5 * max, "{x} vs {y}");
        bounced += usize::from(x != y);
    }
    // The bounce light is there (and read by each route its own way).
    assert!(bounced > 0);
}
