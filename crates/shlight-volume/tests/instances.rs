//! A glTF scene whose instances repeat its primitives bakes through the
//! two-level hierarchy (the unique primitives and their instances) to the
//! light of the same scene with every instance a copy of its own, cast
//! through one hierarchy of every triangle: the same probes valid, the same
//! back faces, the same light, with relocation, visibility, a punctual
//! light, textures' albedo in the bounces and a mirrored instance.

use std::sync::Arc;

use glam::{DVec3, Mat4, Quat, Vec3, Vec4};
use shlight_baked::ProbeGrid;
use shlight_core::sh::closed_form;
use shlight_mesh::{
    Instance, LightKind, Material, Primitive, PunctualLight, Scene, Surfaces, generate,
};
use shlight_rays::Occluder;
use shlight_volume::{VolumeBake, VolumeOptions, bake_surfaces};

/// A floor with six boxes (one mirrored) and three tori on it: as
/// instances of one box and one torus (`copies` false), or with every
/// instance placing a primitive of its own.
fn scene(copies: bool) -> Arc<Surfaces> {
    let floor = generate::plane(4.0, 8);
    let cube = generate::cuboid(Vec3::new(0.3, 0.4, 0.2));
    let torus = generate::torus(0.3, 0.1, 16, 8);
    let mut placed: Vec<(Mesh3, Mat4)> = vec![(Mesh3::Floor, Mat4::IDENTITY)];
    for k in 0..6 {
        let a = k as f32;
        let mut t = Mat4::from_rotation_translation(
            Quat::from_rotation_y(0.7 * a),
            Vec3::new(-1.5 + 0.6 * a, 0.4, -1.0 + 0.3 * (a % 2.0)),
        );
        if k == 3 {
            t *= Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0));
        }
        placed.push((Mesh3::Cube, t));
    }
    for k in 0..3 {
        let a = k as f32;
        placed.push((
            Mesh3::Torus,
            Mat4::from_rotation_translation(
                Quat::from_rotation_x(0.4 * a),
                Vec3::new(-1.0 + a, 0.35, 1.0),
            ),
        ));
    }
    let mesh = |m: Mesh3| match m {
        Mesh3::Floor => (floor.clone(), 0),
        Mesh3::Cube => (cube.clone(), 1),
        Mesh3::Torus => (torus.clone(), 2),
    };
    let (primitives, instances): (Vec<Primitive>, Vec<Instance>) = if copies {
        placed
            .iter()
            .enumerate()
            .map(|(i, &(m, transform))| {
                let (mesh, material) = mesh(m);
                (
                    Primitive::new(mesh, Some(material), format!("copy {i}")),
                    Instance {
                        primitive: i,
                        transform,
                    },
                )
            })
            .unzip()
    } else {
        let primitives = [Mesh3::Floor, Mesh3::Cube, Mesh3::Torus]
            .into_iter()
            .map(|m| {
                let (mesh, material) = mesh(m);
                Primitive::new(mesh, Some(material), format!("{m:?}"))
            })
            .collect();
        let instances = placed
            .iter()
            .map(|&(m, transform)| Instance {
                primitive: m as usize,
                transform,
            })
            .collect();
        (primitives, instances)
    };
    let colour = |r, g, b| Material {
        base_color: Vec4::new(r, g, b, 1.0),
        ..Material::default()
    };
    let scene = Scene {
        source: "instances.glb".into(),
        primitives,
        instances,
        materials: vec![
            colour(0.8, 0.7, 0.6),
            colour(0.2, 0.6, 0.9),
            Material {
                emissive: Vec3::new(0.5, 0.2, 0.1),
                ..colour(0.9, 0.3, 0.3)
            },
        ],
        ..Scene::default()
    };
    Arc::new(scene.flatten(Vec3::ONE).unwrap())
}

/// Which of the scene's three meshes.
#[derive(Clone, Copy, Debug)]
enum Mesh3 {
    Floor = 0,
    Cube = 1,
    Torus = 2,
}

fn bake(surfaces: &Arc<Surfaces>) -> VolumeBake {
    let lamp = PunctualLight {
        name: None,
        kind: LightKind::Point,
        color: Vec3::ONE,
        intensity: 683.0 * 20.0,
        range: None,
        position: Vec3::new(0.3, 2.0, 0.2),
        direction: Vec3::NEG_Y,
    };
    let (lo, hi) = surfaces.mesh.bounds();
    let grid = ProbeGrid::new([6, 3, 6], lo, hi + Vec3::Y).unwrap();
    let options = VolumeOptions {
        lmax: 2,
        samples: 256,
        surface_samples: 64,
        bounces: 2,
        relocate: true,
        visibility_size: 4,
        ..VolumeOptions::default()
    };
    bake_surfaces(surfaces, &[lamp], &grid, &options, &|_, _, _| {}).unwrap()
}

#[test]
fn instances_bake_through_two_levels_to_the_light_of_copies() {
    let (instanced, copied) = (scene(false), scene(true));
    // The same flattened scene either way; only the hierarchy differs.
    assert_eq!(instanced.mesh.positions, copied.mesh.positions);
    assert_eq!(instanced.mesh.triangles, copied.mesh.triangles);
    assert!(Occluder::for_surfaces(&instanced).is_two_level());
    assert!(!Occluder::for_surfaces(&copied).is_two_level());

    let (a, b) = (bake(&instanced), bake(&copied));
    assert_eq!(a.valid, b.valid);
    let moved = a.offsets.as_ref().expect("relocated");
    assert!(
        moved.iter().any(|o| *o != 0.0),
        "some probe moved out of a box"
    );
    assert_eq!(a.offsets.is_some(), b.offsets.is_some());
    for (x, y) in a.offsets.iter().flatten().zip(b.offsets.iter().flatten()) {
        assert!((x - y).abs() <= 1e-4, "offsets {x} vs {y}");
    }
    for (x, y) in a.backfaces.iter().zip(&b.backfaces) {
        assert!((x - y).abs() <= 2.0 / 256.0, "back faces {x} vs {y}");
    }
    // The light under a sky and the static light (the lamp and the
    // torus's emission): a ray grazing an edge may go either way in the
    // two hierarchies' rounding, one sample of 256, far under this bound.
    let sky = closed_form::constant(2, DVec3::ONE);
    for (x, y) in [
        (a.relight(&sky), b.relight(&sky)),
        (a.emitted.clone(), b.emitted.clone()),
    ] {
        let max = x.iter().fold(0.0f32, |m, v| m.max(v.abs()));
        assert!(max > 0.0);
        let worst = x
            .iter()
            .zip(&y)
            .map(|(p, q)| (p - q).abs())
            .fold(0.0f32, f32::max);
        assert!(worst <= 2e-4 * max, "worst {worst} of {max}");
    }
    if let (Some(p), Some(q)) = (&a.visibility, &b.visibility) {
        assert_eq!(p.size, q.size);
    } else {
        panic!("visibility maps baked");
    }
}
