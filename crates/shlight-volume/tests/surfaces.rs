//! Volumes baked through a glTF scene's surfaces: a probe over a
//! two-coloured floor sees each half in its texels' colour (its SH against
//! a brute-force projection of the radiance around it), and under it the
//! underside in its colours when the floor is double-sided (no back face
//! then: a probe under a double-sided plane is neither inside it nor
//! invalid), a masked ceiling
//! passes the sky through its transparent texels and a blended one its
//! share, the same bits at any thread count, and a scene of one colour per
//! triangle bakes as it does without surfaces.

use core::f64::consts::PI;
use std::sync::Arc;

use glam::{Affine2, DVec3, Mat4, Vec2, Vec3, Vec4};
use rand::{Rng, SeedableRng, rngs::StdRng};
use shlight_baked::ProbeGrid;
use shlight_core::sh::{ShBasis, closed_form, sh_count};
use shlight_mesh::{
    AlphaMode, Filter, Instance, Material, Primitive, Scene, Surfaces, Texture, TextureRef, Wrap,
    generate,
};
use shlight_volume::{VolumeBake, VolumeOptions, bake, bake_surfaces};

/// A scene of unit quads (the xz plane facing +y, UV `(x + 0.5, z +
/// 0.5)`) placed by `parts` (transform, material).
fn scene(
    parts: &[(Mat4, usize)],
    materials: Vec<Material>,
    textures: Vec<Texture>,
) -> Arc<Surfaces> {
    let plane = generate::plane(1.0, 1);
    let uv: Vec<Vec2> = plane
        .positions
        .iter()
        .map(|p| Vec2::new(p.x + 0.5, p.z + 0.5))
        .collect();
    let primitives = (0..materials.len())
        .map(|m| Primitive {
            mesh: plane.clone(),
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
        source: "surfaces.glb".into(),
        primitives,
        instances,
        materials,
        textures,
        ..Scene::default()
    };
    Arc::new(scene.flatten(Vec3::splat(0.5)).unwrap())
}

fn options(samples: usize) -> VolumeOptions {
    VolumeOptions {
        lmax: 2,
        samples,
        bounces: 1,
        surface_samples: 256,
        relocate: false,
        visibility_size: 0,
        ..VolumeOptions::default()
    }
}

/// The probes' radiance coefficients under a white sky: `[probe][i][c]`.
fn lit(volume: &VolumeBake) -> Vec<[[f32; 3]; 9]> {
    let radiance = volume.relight(&closed_form::constant(2, DVec3::ONE));
    radiance
        .chunks_exact(27)
        .map(|p| std::array::from_fn(|i| [p[i * 3], p[i * 3 + 1], p[i * 3 + 2]]))
        .collect()
}

/// `int Y_i(s) L(s) ds` for `i < 9` by the midpoint rule on a 768 x 1536
/// grid in (theta, phi).
fn project(radiance: impl Fn(DVec3) -> DVec3) -> [DVec3; 9] {
    let basis = ShBasis::<f64>::new(2);
    let (nt, np) = (768, 1536);
    let mut y = [0.0f64; 9];
    let mut out = [DVec3::ZERO; 9];
    for a in 0..nt {
        let theta = (a as f64 + 0.5) * PI / nt as f64;
        let w = theta.sin() * (PI / nt as f64) * (2.0 * PI / np as f64);
        for b in 0..np {
            let phi = (b as f64 + 0.5) * 2.0 * PI / np as f64;
            let s = DVec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            );
            basis.eval(s, &mut y);
            let l = radiance(s) * w;
            for (o, yi) in out.iter_mut().zip(&y) {
                *o += l * *yi;
            }
        }
    }
    out
}

/// A floor of 20 x 20 at y = 0 facing up, red for x < 0 and blue for
/// x > 0, `double_sided` or not, and two probes 0.1 above it (or, with
/// `below`, 0.1 under it) at x = -0.15 and x = 0.15, baked under a white
/// sky. Each probe's SH is held to a brute-force projection of the
/// radiance around it: the sky, and the floor's texel where a ray meets
/// the floor's front (the side facing the probe when double-sided), lit
/// by the whole sky on that side, its albedo times radiance 1.
fn probes_by_a_two_coloured_floor(below: bool, double_sided: bool) -> VolumeBake {
    let texture = Texture {
        width: 2,
        height: 1,
        texels: vec![[188, 40, 40, 255], [40, 40, 188, 255]],
        wrap_u: Wrap::ClampToEdge,
        wrap_v: Wrap::ClampToEdge,
        filter: Filter::Nearest,
    };
    let red = texture
        .sample(Vec2::new(0.25, 0.5), true)
        .truncate()
        .as_dvec3();
    let blue = texture
        .sample(Vec2::new(0.75, 0.5), true)
        .truncate()
        .as_dvec3();
    let floor = Material {
        base_color_texture: Some(TextureRef {
            texture: 0,
            tex_coord: 0,
            transform: Affine2::IDENTITY,
        }),
        double_sided,
        ..Material::default()
    };
    let surfaces = scene(
        &[(Mat4::from_scale(Vec3::splat(20.0)), 0)],
        vec![floor],
        vec![texture],
    );
    let y = if below { -0.1 } else { 0.1 };
    let grid = ProbeGrid::new(
        [2, 1, 1],
        Vec3::new(-0.3, y - 0.05, -0.1),
        Vec3::new(0.3, y + 0.05, 0.1),
    )
    .unwrap();
    let volume = bake_surfaces(&surfaces, &[], &grid, &options(8192), &|_, _, _| {}).unwrap();
    if below && !double_sided {
        return volume;
    }
    let probes = lit(&volume);
    for (p, centre) in grid.centres().iter().enumerate() {
        let x = centre.as_dvec3();
        // The sky on the probe's side of the floor, and on the other the
        // floor's texel under the ray, lit by the whole sky on the probe's
        // side (radiance 1 times its albedo); beyond the floor's edge the
        // sky again.
        let want = project(|s| {
            if s.y * x.y >= 0.0 {
                return DVec3::ONE;
            }
            let q = x + s * (-x.y / s.y);
            match (q.x.abs() < 10.0 && q.z.abs() < 10.0, q.x < 0.0) {
                (false, _) => DVec3::ONE,
                (true, true) => red,
                (true, false) => blue,
            }
        });
        for (i, w) in want.iter().enumerate() {
            let got = DVec3::from_array(probes[p][i].map(f64::from));
            assert!(
                (got - *w).abs().max_element() < 0.02,
                "probe {p} coefficient {i}: {got} vs {w}"
            );
        }
        // The x-gradient (Y_1,1) has opposite signs in red and blue: the
        // colours sit on their own sides, which vertex colours interpolated
        // across the floor would blur.
        assert!(want[3].x * want[3].z < -0.01, "{:?}", want[3]);
    }
    volume
}

#[test]
fn a_probe_over_a_two_coloured_floor_sees_each_half_in_its_colour() {
    for double_sided in [false, true] {
        let volume = probes_by_a_two_coloured_floor(false, double_sided);
        assert!(volume.backfaces.iter().all(|&b| b == 0.0));
    }
}

#[test]
fn a_probe_under_a_double_sided_floor_sees_its_underside_in_its_colours() {
    // Under the floor's back: lit by the sky below and reflecting it down
    // in its texels' colours, no ray meets a back face.
    let volume = probes_by_a_two_coloured_floor(true, true);
    assert!(volume.backfaces.iter().all(|&b| b == 0.0));
    assert!(volume.valid.iter().all(|&v| v));
    // One-sided, the rays up meet its back: no light from there, and the
    // rays within the floor's solid angle (about half: its edges are 10
    // away; the probes' 0.15 off its centre change it by 1e-4) on back
    // faces.
    let one = probes_by_a_two_coloured_floor(true, false);
    let up = square_solid_angle(10.0, 0.1) / (4.0 * PI);
    for (p, (l, b)) in lit(&one).iter().zip(&one.backfaces).enumerate() {
        assert!((f64::from(*b) - up).abs() < 0.01, "probe {p}: {b} vs {up}");
        // L_00: the sky's, sqrt(4 pi), but for the floor's solid angle.
        let want = (4.0 * PI).sqrt() * (1.0 - up);
        for c in l[0] {
            assert!(
                (f64::from(c) - want).abs() < 0.02,
                "probe {p}: {c} vs {want}"
            );
        }
    }
}

#[test]
fn a_probe_under_a_double_sided_plane_is_not_inside_it() {
    // One probe cell of 1 m, its centre 0.3 under a white 20 x 20 plane
    // facing up (clear of it by more than relocate::CLEARANCE of the
    // cell): half its rays meet the plane's underside. A one-sided plane's
    // underside is a back face: the probe is inside geometry (beyond
    // relocate::INSIDE_BACKFACES and the bake's invalid_backfaces), so it
    // is moved above the plane (the candidates under it are inside too),
    // or, not relocated, marked invalid. Double-sided, it is in free
    // space: it stays, and is valid.
    let grid = ProbeGrid::new(
        [1, 1, 1],
        Vec3::new(-0.5, -0.8, -0.5),
        Vec3::new(0.5, 0.2, 0.5),
    )
    .unwrap();
    assert_eq!(grid.centres()[0], Vec3::new(0.0, -0.3, 0.0));
    let run = |double_sided: bool, relocate: bool| {
        let plane = Material {
            double_sided,
            ..Material::default()
        };
        let surfaces = scene(
            &[(Mat4::from_scale(Vec3::splat(20.0)), 0)],
            vec![plane],
            vec![],
        );
        let options = VolumeOptions {
            relocate,
            invalid_backfaces: 0.25,
            surface_samples: 64,
            ..options(1024)
        };
        bake_surfaces(&surfaces, &[], &grid, &options, &|_, _, _| {}).unwrap()
    };
    let two = run(true, true);
    assert_eq!(two.offsets.as_deref(), Some(&[0.0f32; 3][..]));
    assert_eq!(two.backfaces, [0.0]);
    assert_eq!(two.valid, [true]);
    let one = run(false, true);
    let moved = one.offsets.as_deref().unwrap();
    assert!(moved[1] > 0.3, "{moved:?}");
    let stuck = run(false, false);
    assert!(stuck.backfaces[0] > 0.45, "{:?}", stuck.backfaces);
    assert_eq!(stuck.valid, [false]);
}

/// A black ceiling of 200 x 200, 1 above four probes, facing them, cut
/// out as `ceiling` says, the sky all around; baked on `threads` threads.
fn under_ceiling(ceiling: Material, textures: Vec<Texture>, threads: usize) -> VolumeBake {
    let turn = Mat4::from_translation(Vec3::new(0.0, 1.0, 0.0))
        * Mat4::from_rotation_x(std::f32::consts::PI)
        * Mat4::from_scale(Vec3::splat(200.0));
    let surfaces = scene(&[(turn, 0)], vec![ceiling], textures);
    // Probes 1.3 apart: their rays meet unrelated texels.
    let grid = ProbeGrid::new(
        [2, 1, 2],
        Vec3::new(-1.3, -0.1, -1.3),
        Vec3::new(1.3, 0.1, 1.3),
    )
    .unwrap();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| bake_surfaces(&surfaces, &[], &grid, &options(16384), &|_, _, _| {}).unwrap())
}

/// The solid angle of the square of half-side `a`, `h` above a point
/// under its centre.
fn square_solid_angle(a: f64, h: f64) -> f64 {
    4.0 * (a * a / ((a * a + h * h) * (a * a + h * h)).sqrt()).asin()
}

/// The mean over the probes of `L_00` under a white sky, over `L_00` of
/// the sky itself: the share of the sphere's light that reaches them.
fn reaching(volume: &VolumeBake) -> f64 {
    let probes = lit(volume);
    let sky = (4.0 * PI).sqrt();
    probes.iter().map(|p| f64::from(p[0][0]) / sky).sum::<f64>() / probes.len() as f64
}

#[test]
fn a_masked_ceiling_passes_the_sky_through_its_transparent_texels() {
    let mut rng = StdRng::seed_from_u64(8);
    let texels: Vec<[u8; 4]> = (0..256)
        .map(|_| [0, 0, 0, if rng.random_bool(0.37) { 255 } else { 0 }])
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
    // 100 tiles across: texels 0.125 wide, an eighth of the height.
    let ceiling = Material {
        base_color: Vec4::new(0.0, 0.0, 0.0, 1.0),
        base_color_texture: Some(TextureRef {
            texture: 0,
            tex_coord: 0,
            transform: Affine2::from_scale(Vec2::splat(100.0)),
        }),
        alpha_mode: AlphaMode::Mask { cutoff: 0.5 },
        ..Material::default()
    };
    let volume = under_ceiling(ceiling, vec![texture], 2);
    assert_eq!(volume.invalid_count(), 0);
    // A ray meeting the ceiling is stopped where its texel is opaque; the
    // black ceiling sends nothing back.
    let want = 1.0 - opaque * square_solid_angle(100.0, 1.0) / (4.0 * PI);
    let got = reaching(&volume);
    // About 8,000 rays a probe meet the ceiling: the blocked share's
    // standard deviation is sqrt(f (1 - f) / 8000) / 2 = 0.0027 of the
    // sphere, 0.0013 for the mean of four.
    assert!(
        (got - want).abs() < 0.0055,
        "{got} of the sky reaches the probes, {want} expected ({opaque} of the texels opaque)"
    );
}

#[test]
fn a_blended_ceiling_passes_its_share_the_same_at_any_thread_count() {
    let ceiling = Material {
        base_color: Vec4::new(0.0, 0.0, 0.0, 0.3),
        alpha_mode: AlphaMode::Blend,
        ..Material::default()
    };
    let volume = under_ceiling(ceiling.clone(), Vec::new(), 2);
    let want = 1.0 - 0.3 * square_solid_angle(100.0, 1.0) / (4.0 * PI);
    let got = reaching(&volume);
    assert!((got - want).abs() < 0.0055, "{got} vs {want}");
    assert_eq!(volume, under_ceiling(ceiling.clone(), Vec::new(), 2));
    assert_eq!(volume, under_ceiling(ceiling, Vec::new(), 1));
}

#[test]
fn one_colour_per_triangle_bakes_as_it_does_without_surfaces() {
    // A sphere over a plane, one coloured emitting material: with the
    // albedo the same at a triangle's corners, the texel's albedo times
    // the light interpolated at a hit is the interpolation of the corners'
    // exit light, so the bake through the surfaces and the one through
    // the mesh alone agree to rounding.
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
    let surfaces = Arc::new(scene.flatten(Vec3::ONE).unwrap());
    let grid = ProbeGrid::around([3, 2, 3], surfaces.mesh.bounds()).unwrap();
    let options = VolumeOptions {
        samples: 1024,
        surface_samples: 128,
        bounces: 2,
        ..VolumeOptions::default()
    };
    let with = bake_surfaces(&surfaces, &[], &grid, &options, &|_, _, _| {}).unwrap();
    let without = bake(Some(&surfaces.mesh), &grid, &options, &|_, _, _| {}).unwrap();
    assert_eq!(with.valid, without.valid);
    assert_eq!(with.backfaces, without.backfaces);
    for (a, b) in [
        (&with.transfer, &without.transfer),
        (&with.emitted, &without.emitted),
    ] {
        let max = a.iter().fold(0.0f32, |m, x| m.max(x.abs()));
        assert!(max > 0.0);
        for (x, y) in a.iter().zip(b) {
            assert!((x - y).abs() <= 2e-5 * max, "{x} vs {y} of {max}");
        }
    }
    assert_eq!(sh_count(with.lmax), 9);
}
