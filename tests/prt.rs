//! `shlight prt`: the files it writes hold the library's bake, agree with a
//! closed form, read back, and bad input is an error naming the file.

use std::path::Path;

use glam::DVec3;
use shlight_core::sh::closed_form;
use shlight_format::ShprtFile;
use shlight_mesh::generate;
use shlight_prt::{Albedo, BakeOptions, Mode, bake};

use crate::util::{s, shlight_err, shlight_ok, temp_dir, write_coefficient_rows, write_obj};

/// A radiance coefficient file of constant radiance `value` (lmax 4).
fn write_constant_light(path: &Path, value: f64, quantity: &str) {
    let mut rows = vec![[0.0; 3]; 25];
    rows[0] = [value * 2.0 * std::f64::consts::PI.sqrt(); 3];
    write_coefficient_rows(path, &rows, quantity);
}

#[test]
fn shprt_holds_the_library_bake_and_the_bowls_closed_form() {
    let dir = temp_dir("prt_shprt");
    let obj = dir.join("bowl.obj");
    write_obj(&obj, &generate::bowl(1.0, 24, 6));
    let out = dir.join("bowl.shprt");
    let args = [
        "prt",
        s(&obj),
        "--mode",
        "interreflected",
        "--bounces",
        "6",
        "--samples",
        "512",
        "--albedo",
        "0.5",
        "--seed",
        "4",
        "-o",
        s(&out),
    ];
    shlight_ok(&args);
    let file = ShprtFile::read(&out).unwrap();
    let mesh = shlight_mesh::load(&obj).unwrap();
    assert_eq!(
        (file.lmax, file.channels, file.vertex_count),
        (4, 1, mesh.vertex_count())
    );
    assert_eq!(
        (file.mode.as_str(), file.bounces, file.seed),
        ("interreflected", 6, 4)
    );
    assert_eq!(file.albedo, Some([0.5; 3]));
    assert_eq!(file.mesh_hash, mesh.content_hash());
    let options = BakeOptions {
        lmax: 4,
        samples: 512,
        mode: Mode::Interreflected { bounces: 6 },
        albedo: Albedo::Constant([0.5; 3]),
        seed: 4,
        emission: None,
        surfaces: None,
        direct_irradiance: None,
    };
    let library = bake(&mesh, &options, &|_, _, _| {});
    assert_eq!(file.transfer, library.coeffs);
    assert_eq!(file.rays_per_vertex, library.samples as u64);
    // Half bowl, half sky from every point: L_o = rho L / (2 - rho) = 1/3
    // (6 bounces leave (rho/2)^7 ~ 6e-5 out; 512 directions err ~0.01).
    let light = closed_form::constant(4, DVec3::ONE);
    for e in file.view().unwrap().exit_radiance(light.as_slice()) {
        assert!((e.x - 1.0 / 3.0).abs() < 0.02, "{e}");
    }
    // The same command gives the same bytes.
    let again = dir.join("again.shprt");
    let mut args2 = args;
    *args2.last_mut().expect("the output is last") = s(&again);
    shlight_ok(&args2);
    assert_eq!(std::fs::read(&out).unwrap(), std::fs::read(&again).unwrap());
}

#[test]
fn glb_output_loads_back_as_the_mesh_with_the_transfer_in_its_extras() {
    let dir = temp_dir("prt_glb");
    let obj = dir.join("torus.obj");
    write_obj(&obj, &generate::torus(1.0, 0.4, 12, 8));
    let glb = dir.join("torus.glb");
    let shprt = dir.join("torus.shprt");
    for out in [&glb, &shprt] {
        let args = ["prt", s(&obj), "--samples", "64", "--albedo", "1,0.5,0.25"];
        shlight_ok(&[&args[..], &["-o", s(out)]].concat());
    }
    let original = shlight_mesh::load(&obj).unwrap();
    let back = shlight_mesh::load(&glb).unwrap();
    assert_eq!(back.positions, original.positions);
    assert_eq!(back.triangles, original.triangles);
    let file = ShprtFile::read(&shprt).unwrap();
    assert_eq!(file.channels, 3);
    let bytes = std::fs::read(&glb).unwrap();
    let text = String::from_utf8_lossy(&bytes);
    for k in 0..19 {
        assert!(
            text.contains(&format!("\"_SH_TRANSFER_{k}\"")),
            "attribute {k}"
        );
    }
    assert!(!text.contains("_SH_TRANSFER_19"));
    assert!(text.contains("\"shlight_prt\""));
}

#[test]
fn preview_shows_the_sphere_and_its_contact_shadow() {
    let dir = temp_dir("prt_preview");
    let obj = dir.join("pus.obj");
    write_obj(&obj, &generate::plane_under_sphere(1.0, 24, 12, 6.0, 12));
    let light = dir.join("white.json");
    write_constant_light(&light, 1.0, "radiance");
    let png = dir.join("p.png");
    let out = shlight_ok(&[
        "prt",
        s(&obj),
        "--samples",
        "256",
        "--albedo",
        "1",
        "--light",
        s(&light),
        "--preview",
        s(&png),
        "--preview-size",
        "96x64",
        "--preview-exposure",
        "0",
    ]);
    assert!(String::from_utf8_lossy(&out.stderr).contains("rays"));
    let img = shlight_io::read_image(&png, &shlight_io::ReadOptions::default()).unwrap();
    assert_eq!((img.width(), img.height()), (96, 64));
    let values: Vec<f32> = img.pixels().iter().map(|p| p[1]).collect();
    // Background black; the open plane under white light (exit radiance
    // near 1, which ACES maps to 0.80) bright; around the contact, where the
    // sphere hides most of the sky (exit radiance 0.29 at half a radius),
    // and under the sphere, dark.
    assert_eq!(values[0], 0.0);
    let lit = values.iter().filter(|&&v| v > 0.7).count();
    let dark = values.iter().filter(|&&v| v > 0.0 && v < 0.4).count();
    assert!(lit > 500 && dark > 5, "lit {lit}, dark {dark}");
}

#[test]
fn bad_meshes_and_arguments_are_errors_and_leave_outputs_alone() {
    let dir = temp_dir("prt_bad");
    let out = dir.join("out.shprt");
    std::fs::write(&out, b"keep").unwrap();
    let cases: [(&str, &[u8], &str); 5] = [
        ("nan.obj", b"v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n", "non-finite"),
        ("range.ply", b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 5\n", "out of range"),
        ("empty.off", b"OFF\n0 0 0\n", "no vertices"),
        ("flat.off", b"OFF\n3 1 0\n0 0 0\n1 0 0\n2 0 0\n3 0 1 2\n", "no usable triangles (1 degenerate)"),
        ("junk.glb", b"glTF\x02\x00\x00\x00junk", "not a valid glTF"),
    ];
    for (name, bytes, what) in cases {
        let mesh = dir.join(name);
        std::fs::write(&mesh, bytes).unwrap();
        let err = shlight_err(&["prt", s(&mesh), "-o", s(&out)]);
        assert!(
            err.contains(&format!("{}: ", mesh.display())) && err.contains(what),
            "{name}: {err}"
        );
    }
    assert_eq!(std::fs::read(&out).unwrap(), b"keep");

    let obj = dir.join("ok.obj");
    write_obj(&obj, &generate::cuboid(glam::Vec3::ONE));
    let irr = dir.join("irr.json");
    write_constant_light(&irr, 1.0, "irradiance");
    for (args, what) in [
        (vec!["-o", "x.png"], "unknown output format"),
        (
            vec!["--bounces", "2", "-o", s(&out)],
            "--bounces needs --mode interreflected",
        ),
        (vec![], "nothing to write"),
        (
            vec!["--light", s(&irr), "--preview", "p.png"],
            "holds irradiance",
        ),
        (vec!["--albedo", "2", "-o", s(&out)], "must lie in [0, 1]"),
    ] {
        let mut all = vec!["prt", s(&obj)];
        all.extend(args);
        let err = shlight_err(&all);
        assert!(err.contains(what), "{all:?}: {err}");
    }
    assert_eq!(std::fs::read(&out).unwrap(), b"keep");
}

#[test]
fn glossy_files_are_sampled_toward_a_view_and_bad_glossy_input_is_refused() {
    let dir = temp_dir("prt_glossy");
    let obj = dir.join("ball.obj");
    write_obj(&obj, &generate::uv_sphere(1.0, 24, 12));
    let out = dir.join("ball.shprt");
    shlight_ok(&[
        "prt",
        s(&obj),
        "--mode",
        "glossy",
        "--brdf",
        "phong:50",
        "--lmax",
        "3",
        "--samples",
        "256",
        "-o",
        s(&out),
    ]);
    let file = ShprtFile::read(&out).unwrap();
    let mesh = shlight_mesh::load(&obj).unwrap();
    let glossy = file.glossy.as_ref().expect("a glossy file");
    assert_eq!((file.mode.as_str(), file.lmax), ("glossy", 3));
    assert_eq!(
        (glossy.brdf.as_str(), glossy.transport.as_str()),
        ("phong:50", "shadowed")
    );
    assert_eq!(file.transfer.len(), mesh.vertex_count() * 16 * 16);
    assert_eq!(glossy.normals[5], mesh.normals[5].to_array());
    // A sun: the vertex that shines brightest toward the view is the one
    // whose mirror of the view direction (from the vertex to the eye) is
    // the sun's direction.
    let sun = DVec3::new(0.3, 0.9, 0.2).normalize();
    let light = dir.join("sun.json");
    let rows: Vec<[f64; 3]> = closed_form::directional(3, sun, 1.0)
        .as_slice()
        .iter()
        .map(|c| [*c; 3])
        .collect();
    crate::util::write_radiance_rows(&light, &rows);
    let view = DVec3::new(-0.5, 0.2, 0.8).normalize();
    let sample = |extra: &[&str], name: &str| {
        let json = dir.join(name);
        let mut args = vec!["sample", s(&out), "--light", s(&light), "-o", s(&json)];
        args.extend(extra);
        shlight_ok(&args);
        let v = crate::util::read_json(&json);
        v["radiance"]
            .as_array()
            .unwrap()
            .iter()
            .map(|r| r[0].as_f64().unwrap())
            .collect::<Vec<f64>>()
    };
    let by_view = sample(&["--view", "-0.5,0.2,0.8"], "view.json");
    let brightest = (0..by_view.len())
        .max_by(|&a, &b| by_view[a].total_cmp(&by_view[b]))
        .unwrap();
    let n = mesh.normals[brightest].as_dvec3();
    let r = 2.0 * n.dot(view) * n - view;
    assert!(
        r.dot(sun) > 0.97,
        "brightest vertex mirrors the view to {r}, the sun is at {sun}"
    );
    // An eye far along the view sees (nearly) the same.
    let far = view * 1e5;
    let by_eye = sample(
        &["--eye", &format!("{},{},{}", far.x, far.y, far.z)],
        "eye.json",
    );
    for (a, b) in by_view.iter().zip(&by_eye) {
        assert!((a - b).abs() < 1e-3 * (1.0 + a.abs()), "{a} vs {b}");
    }
    // A diffuse file looks the same from everywhere: --view is ignored.
    let diffuse = dir.join("diffuse.shprt");
    shlight_ok(&["prt", s(&obj), "--samples", "64", "-o", s(&diffuse)]);
    let plain = dir.join("plain.json");
    let viewed = dir.join("viewed.json");
    shlight_ok(&["sample", s(&diffuse), "--light", s(&light), "-o", s(&plain)]);
    shlight_ok(&[
        "sample",
        s(&diffuse),
        "--light",
        s(&light),
        "--view",
        "1,2,3",
        "-o",
        s(&viewed),
    ]);
    assert_eq!(
        crate::util::read_json(&plain)["radiance"],
        crate::util::read_json(&viewed)["radiance"]
    );
    // Bad input.
    let json = dir.join("bad.json");
    for (args, what) in [
        (vec!["--view", "0,0,0"], "zero length"),
        (vec![], "give --view"),
    ] {
        let mut all = vec!["sample", s(&out), "--light", s(&light), "-o", s(&json)];
        all.extend(args);
        let err = shlight_err(&all);
        assert!(err.contains(what), "{all:?}: {err}");
    }
    let bunny = Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes/bunny.obj");
    let keep = dir.join("keep.shprt");
    for (mesh, args, what) in [
        (&obj, vec!["--brdf", "phong:shiny"], "not a number"),
        (&obj, vec!["--brdf", "blinn:3"], "unknown BRDF \"blinn\""),
        (
            &obj,
            vec!["--brdf", "ggx:0"],
            "alpha must be from 0.001 to 1",
        ),
        (
            &obj,
            vec!["--brdf", "ggx:0.3,1.5"],
            "F0 must be from 0 to 1",
        ),
        (&obj, vec!["--brdf", "ggx:rough"], "not a number"),
        (&obj, vec![], "needs --brdf"),
        (
            &bunny,
            vec!["--brdf", "phong:8", "--lmax", "30"],
            "would take 6479 MiB",
        ),
    ] {
        let mut all = vec!["prt", s(mesh), "--mode", "glossy", "-o", s(&keep)];
        all.extend(args);
        let err = shlight_err(&all);
        assert!(err.contains(what), "{all:?}: {err}");
    }
    let err = shlight_err(&[
        "prt",
        s(&obj),
        "--mode",
        "glossy",
        "--brdf",
        "phong:8",
        "-o",
        "x.glb",
    ]);
    assert!(err.contains("glTF cannot carry glossy transfer"), "{err}");
    assert!(!keep.exists());
    // Compressed by CPCA: with a cluster per vertex the same radiance; with
    // few clusters and vectors a smaller file, near it.
    let n = mesh.vertex_count();
    let compressed = |spec: &str, name: &str| {
        let path = dir.join(name);
        shlight_ok(&[
            "prt",
            s(&obj),
            "--mode",
            "glossy",
            "--brdf",
            "phong:50",
            "--lmax",
            "3",
            "--samples",
            "256",
            "--compress",
            spec,
            "-o",
            s(&path),
        ]);
        path
    };
    let exact = compressed(&format!("cpca:{n},0"), "exact.shprt");
    let small = compressed("cpca:4,6", "small.shprt");
    let sample_of = |path: &Path, name: &str| {
        let json = dir.join(name);
        shlight_ok(&[
            "sample",
            s(path),
            "--light",
            s(&light),
            "--view",
            "-0.5,0.2,0.8",
            "-o",
            s(&json),
        ]);
        crate::util::read_json(&json)["radiance"]
            .as_array()
            .unwrap()
            .iter()
            .map(|r| r[0].as_f64().unwrap())
            .collect::<Vec<f64>>()
    };
    let peak = by_view.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    for (a, b) in sample_of(&exact, "exact.json").iter().zip(&by_view) {
        assert!((a - b).abs() < 1e-9 * peak, "{a} vs {b}");
    }
    let near = sample_of(&small, "small.json");
    let worst = near
        .iter()
        .zip(&by_view)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0f64, f64::max);
    assert!(worst > 0.0 && worst < 0.25 * peak, "{worst} of {peak}");
    let size = |p: &Path| std::fs::metadata(p).unwrap().len();
    assert!(
        size(&small) < size(&out) / 4,
        "{} vs {}",
        size(&small),
        size(&out)
    );
    for (args, what) in [
        (
            vec!["--brdf", "phong:8", "--compress", "cpca:0,2"],
            "is not cpca:C,K",
        ),
        (
            vec!["--brdf", "phong:8", "--compress", "pca:2,2"],
            "is not cpca:C,K",
        ),
        (
            vec!["--brdf", "phong:8", "--compress", "cpca:4"],
            "is not cpca:C,K",
        ),
        (
            vec![
                "--brdf",
                "phong:8",
                "--lmax",
                "1",
                "--compress",
                "cpca:2,17",
            ],
            "at most 16",
        ),
    ] {
        let mut all = vec![
            "prt",
            s(&obj),
            "--mode",
            "glossy",
            "--samples",
            "64",
            "-o",
            s(&keep),
        ];
        all.extend(args);
        let err = shlight_err(&all);
        assert!(err.contains(what), "{all:?}: {err}");
    }
    let err = shlight_err(&["prt", s(&obj), "--compress", "cpca:2,2", "-o", s(&keep)]);
    assert!(
        err.contains("--compress compresses the matrices of --mode glossy"),
        "{err}"
    );
    assert!(!keep.exists());
}

/// `tests/scenes/point.glb` (a closed room, one point lamp; its truth file
/// gives the lamp's place and glTF intensity): baked shadowed, the file is
/// format version 3 with a static term, and each vertex facing the lamp
/// leaves `rho / pi I cos / d^2`, `I` the glTF intensity over 683 (the
/// room is convex: every vertex sees the lamp), `rho` its material's
/// albedo; `sample` under a black sky gives that term. A scene refuses
/// `--albedo`, a mesh `--light-units`, and glTF output of a static term is
/// refused.
#[test]
fn a_gltf_scene_bakes_its_lamp_into_a_static_term() {
    let dir = temp_dir("prt_scene");
    let out = dir.join("point.shprt");
    shlight_ok(&[
        "prt",
        "tests/scenes/point.glb",
        "--samples",
        "64",
        "--lmax",
        "2",
        "-o",
        s(&out),
    ]);
    let file = ShprtFile::read(&out).unwrap();
    let lit = file.static_light.as_ref().expect("a static term");
    let lights = lit.lights.as_ref().unwrap();
    assert_eq!((lights.units.as_str(), lights.point), ("blender", 1));
    let truth: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string("tests/scenes/point.truth.json").unwrap())
            .unwrap();
    let lamp = &truth["lights"][0];
    let at = DVec3::from_array([0, 1, 2].map(|i| lamp["position"][i].as_f64().unwrap()));
    let intensity = lamp["gltf_intensity"].as_f64().unwrap() / 683.0;
    let scene =
        shlight_mesh::load_scene(Path::new("tests/scenes/point.glb"), &Default::default()).unwrap();
    let mesh = scene.flatten(glam::Vec3::splat(0.8)).unwrap().mesh;
    assert_eq!(mesh.vertex_count(), file.vertex_count);
    let colours = mesh.colors.as_ref().expect("the materials' albedo");
    let mut checked = 0;
    for (v, (p, n)) in mesh.positions.iter().zip(&mesh.normals).enumerate() {
        let to = at - p.as_dvec3();
        let cos = n.as_dvec3().dot(to.normalize());
        let rho = colours[v].as_dvec3();
        let want = rho / std::f64::consts::PI * intensity * cos.max(0.0) / to.length_squared();
        let got = DVec3::from_array(lit.radiance[v].map(f64::from));
        assert!(
            (got - want).abs().max_element() <= 1e-4 * want.max_element().max(1e-3),
            "vertex {v} at {p}: {got} vs {want}"
        );
        checked += usize::from(cos > 0.1);
    }
    assert!(checked > 10, "{checked} vertices face the lamp");
    let black = dir.join("black.json");
    write_constant_light(&black, 0.0, "radiance");
    let sampled = dir.join("black-out.json");
    shlight_ok(&["sample", s(&out), "--light", s(&black), "-o", s(&sampled)]);
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&sampled).unwrap()).unwrap();
    for (i, row) in v["radiance"].as_array().unwrap().iter().enumerate() {
        for c in 0..3 {
            let got = row[c].as_f64().unwrap();
            let want = f64::from(lit.radiance[i][c]);
            assert!(
                (got - want).abs() <= 1e-6 * want.abs().max(1.0),
                "{i}: {got} vs {want}"
            );
        }
    }

    let err = shlight_err(&[
        "prt",
        "tests/scenes/point.glb",
        "--albedo",
        "0.5",
        "-o",
        s(&out),
    ]);
    assert!(
        err.contains("tests/scenes/point.glb: a glTF scene's albedo is its materials'"),
        "{err}"
    );
    let obj = dir.join("box.obj");
    write_obj(&obj, &generate::cuboid(glam::Vec3::ONE));
    let err = shlight_err(&["prt", s(&obj), "--light-units", "as-written", "-o", s(&out)]);
    assert!(
        err.contains("--light-units reads a glTF scene's punctual lights"),
        "{err}"
    );
    let glb = dir.join("point-out.glb");
    let err = shlight_err(&[
        "prt",
        "tests/scenes/point.glb",
        "--samples",
        "16",
        "-o",
        s(&glb),
    ]);
    assert!(err.contains("cannot carry the static light"), "{err}");
}
