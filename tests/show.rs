//! `shlight show` reads every file shlight writes: each kind written by the
//! command that writes it, then shown, its table's facts checked against
//! what was asked for, a closed form, or the file's own header as written;
//! files it does not write are errors naming the file.

use std::f64::consts::PI;
use std::path::Path;

use serde_json::Value;
use shlight_mesh::generate;

use crate::util::{
    s, shlight_err, shlight_ok, synth_sun_map, temp_dir, write_coefficient_rows, write_obj,
    write_radiance_rows, write_two_rooms,
};

/// `shlight show PATH`'s table.
fn show(path: &Path) -> String {
    String::from_utf8(shlight_ok(&["show", s(path)]).stdout).expect("UTF-8 table")
}

/// Every value of the fields called `name` (lines `name`, two or more
/// spaces, the value).
fn fields<'a>(table: &'a str, name: &str) -> Vec<&'a str> {
    table
        .lines()
        .filter_map(|l| {
            l.strip_prefix(name)
                .filter(|rest| rest.starts_with("  "))
                .map(str::trim_start)
        })
        .collect()
}

/// The value of the first field `name`; panics showing the table when
/// there is none.
fn field<'a>(table: &'a str, name: &str) -> &'a str {
    fields(table, name)
        .first()
        .copied()
        .unwrap_or_else(|| panic!("no field {name:?} in\n{table}"))
}

/// The coefficient rows of a table (`l m red green blue`).
fn rows(table: &str) -> Vec<[f64; 3]> {
    let mut out = Vec::new();
    for line in table.lines().filter(|l| !l.starts_with('#')) {
        let v: Vec<&str> = line.split_whitespace().collect();
        if v.len() == 5
            && let (Ok(_), Ok(_)) = (v[0].parse::<i64>(), v[1].parse::<i64>())
        {
            out.push([2, 3, 4].map(|i| v[i].parse::<f64>().expect("a number")));
        }
    }
    out
}

/// `got` agrees with `want` to the table's six digits.
fn assert_printed(got: &[[f64; 3]], want: &[[f64; 3]], what: &str) {
    assert_eq!(got.len(), want.len(), "{what}: rows");
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        for c in 0..3 {
            assert!(
                (g[c] - w[c]).abs() <= 1e-6 * w[c].abs() + 1e-12,
                "{what}: row {i} channel {c}: {} printed, {} expected",
                g[c],
                w[c]
            );
        }
    }
}

/// The header line of a `.shprt` or `.shvol` file, as written.
fn header_line(path: &Path) -> Value {
    let bytes = std::fs::read(path).unwrap();
    let end = bytes.iter().position(|&b| b == b'\n').unwrap();
    serde_json::from_slice(&bytes[..end]).unwrap()
}

/// Radiance rows of lmax 3, each coefficient different.
fn light_rows() -> Vec<[f64; 3]> {
    (0..16)
        .map(|i| {
            let i = i as f64;
            [0.5 + 0.1 * i, -0.2 + 0.05 * i, 0.3 - 0.07 * i]
        })
        .collect()
}

/// The irradiance `E_lm = A_l L_lm` of the first nine rows (lmax 2).
fn irradiance_l2(rows: &[[f64; 3]]) -> Vec<[f64; 3]> {
    let a = [PI, 2.0 * PI / 3.0, PI / 4.0];
    rows[..9]
        .iter()
        .enumerate()
        .map(|(i, r)| {
            let l = if i == 0 {
                0
            } else if i < 4 {
                1
            } else {
                2
            };
            r.map(|x| a[l] * x)
        })
        .collect()
}

#[test]
fn engine_lights_show_what_they_hold_and_their_coefficients_read_back() {
    let dir = temp_dir("show-lights");
    let light = dir.join("light.json");
    let written = light_rows();
    write_radiance_rows(&light, &written);
    let convert = |format: &str, out: &str| {
        let path = dir.join(out);
        let mut args = vec!["convert", s(&light), "--format", format, "-o", s(&path)];
        if format == "gltf" {
            args.push("--irradiance-only");
        }
        shlight_ok(&args);
        show(&path)
    };
    // three.js keeps radiance; the others irradiance; all lmax 2 (the
    // light's band 3 left out), read back to shlight's basis and frame.
    let three = convert("threejs", "probe.json");
    assert!(three.starts_with("# three.js LightProbe JSON"), "{three}");
    assert!(
        three.contains("radiance, lmax 2 (9 coefficients)"),
        "{three}"
    );
    assert_printed(&rows(&three), &written[..9], "three.js");
    let irradiance = irradiance_l2(&written);
    for (format, out, kind) in [
        ("unity", "unity.json", "# Unity SphericalHarmonicsL2"),
        ("filament", "sh.txt", "# Filament sh.txt"),
        (
            "gltf",
            "light.gltf",
            "# glTF 2.0 asset (.gltf, JSON): an EXT_lights_image_based",
        ),
    ] {
        let table = convert(format, out);
        assert!(table.starts_with(kind), "{format}: {table}");
        assert!(
            table.contains("irradiance, lmax 2 (9 coefficients)"),
            "{table}"
        );
        assert!(table.contains("frame y-up"), "{table}");
        assert_printed(&rows(&table), &irradiance, format);
    }
    let gltf = show(&dir.join("light.gltf"));
    assert_eq!(
        field(&gltf, "specular"),
        "none (the light was written from coefficients alone)"
    );
    // From a map, the glTF light has its prefiltered images: 4 mips of
    // 8x8 down to 1x1, six faces each.
    let map = synth_sun_map(&dir);
    let whole = dir.join("whole.gltf");
    shlight_ok(&[
        "project",
        s(&map),
        "--format",
        "gltf",
        "--specular-size",
        "8",
        "--specular-samples",
        "16",
        "-o",
        s(&whole),
    ]);
    let table = show(&whole);
    assert!(
        field(&table, "specular").starts_with("4 mips from 8x8, 24 face images"),
        "{table}"
    );
    assert!(field(&table, "contents").ends_with("24 images"), "{table}");
}

#[test]
fn the_table_format_and_code_snippets_say_what_they_are() {
    let dir = temp_dir("show-code");
    let light = dir.join("light.json");
    write_radiance_rows(&light, &light_rows());
    let txt = dir.join("light.txt");
    shlight_ok(&["convert", s(&light), "--format", "txt", "-o", s(&txt)]);
    let table = show(&txt);
    assert!(table.starts_with("# Ramamoorthi-Hanrahan table"), "{table}");
    assert_eq!(field(&table, "holds"), "radiance, lmax 3 (16 coefficients)");
    assert_eq!(field(&table, "rows"), "16");
    assert!(field(&table, "frame").starts_with("y-up"), "{table}");
    let e = dir.join("e.json");
    write_coefficient_rows(&e, &light_rows()[..4], "irradiance");
    shlight_ok(&["convert", s(&e), "--format", "txt", "-o", s(&txt)]);
    assert_eq!(
        field(&show(&txt), "holds"),
        "irradiance, lmax 1 (4 coefficients)"
    );
    for (format, file, language) in [
        ("wgsl", "sh.wgsl", "WGSL"),
        ("glsl", "sh.glsl", "GLSL"),
        ("hlsl", "sh.hlsl", "HLSL"),
        ("c", "sh.h", "C"),
    ] {
        let path = dir.join(file);
        shlight_ok(&["convert", s(&light), "--format", format, "-o", s(&path)]);
        let table = show(&path);
        assert!(
            table.starts_with(&format!(
                "# {language} code: a light's coefficients and its evaluator"
            )),
            "{table}"
        );
        assert_eq!(field(&table, "lmax"), "3", "{format}");
        assert!(
            field(&table, "what").contains("SH radiance, lmax 3 (16 RGB coefficients)"),
            "{table}"
        );
        // The snippet's own header comment follows, as written.
        let text = std::fs::read_to_string(&path).unwrap();
        let first = text.lines().next().unwrap();
        assert!(table.contains(&format!("\n{first}\n")), "{table}");
    }
    // An encoding's snippet names its encoding.
    let sun = synth_sun_map(&dir);
    let encoded = dir.join("sun.json");
    shlight_ok(&[
        "project",
        s(&sun),
        "--encoding",
        "dominant+sh",
        "-o",
        s(&encoded),
    ]);
    let glsl = dir.join("sun.glsl");
    shlight_ok(&["convert", s(&encoded), "-o", s(&glsl)]);
    let table = show(&glsl);
    assert!(table.starts_with("# GLSL code"), "{table}");
    assert!(field(&table, "what").contains("dominant+sh"), "{table}");
}

#[test]
fn prt_files_and_their_gltf_show_the_bake() {
    let dir = temp_dir("show-prt");
    let mesh = generate::torus(1.0, 0.3, 8, 6);
    let obj = dir.join("torus.obj");
    write_obj(&obj, &mesh);
    let bake = |extra: &[&str], out: &str| {
        let path = dir.join(out);
        let mut args = vec!["prt", s(&obj), "--samples", "64", "--seed", "5"];
        args.extend_from_slice(extra);
        args.extend(["-o", s(&path)]);
        shlight_ok(&args);
        path
    };
    let diffuse = [
        "--lmax",
        "3",
        "--mode",
        "interreflected",
        "--bounces",
        "1",
        "--albedo",
        "0.5,0.25,1",
    ];
    let shprt = bake(&diffuse, "t.shprt");
    let written = header_line(&shprt);
    let table = show(&shprt);
    assert!(
        table.starts_with("# shlight PRT transfer (.shprt, format_version 1): diffuse"),
        "{table}"
    );
    let vertices = mesh.vertex_count().to_string();
    for (name, want) in [
        ("lmax", "3"),
        ("vertices", vertices.as_str()),
        ("channels", "3 (linear RGB)"),
        ("mode", "interreflected"),
        ("albedo", "[0.5,0.25,1.0]"),
        ("bounces", "1"),
        ("seed", "5"),
    ] {
        assert_eq!(field(&table, name), want, "{name}: {table}");
    }
    assert!(
        field(&table, "holds").contains("of 16 coefficients"),
        "{table}"
    );
    assert_eq!(
        field(&table, "samples"),
        format!("{} directions", written["samples"])
    );
    assert_eq!(
        field(&table, "mesh"),
        format!(
            "{} ({})",
            written["mesh"].as_str().unwrap(),
            written["mesh_hash"].as_str().unwrap()
        )
    );
    // Glossy matrices, then compressed.
    let glossy = ["--lmax", "2", "--mode", "glossy", "--brdf", "phong:8"];
    let table = show(&bake(&glossy, "g.shprt"));
    assert!(
        table.contains("(.shprt, format_version 2): glossy"),
        "{table}"
    );
    assert!(
        field(&table, "holds").starts_with("a 9x9 transfer matrix"),
        "{table}"
    );
    assert_eq!(field(&table, "brdf"), "phong:8");
    assert_eq!(field(&table, "mode"), "glossy, shadowed transport");
    let table = show(&bake(
        &[&glossy[..], &["--compress", "cpca:3,2"]].concat(),
        "z.shprt",
    ));
    assert!(
        field(&table, "holds")
            .ends_with("compressed by clustered PCA: 3 clusters of 2 basis vectors"),
        "{table}"
    );
    // glTF and GLB: the header in the mesh's extras, and 3 x 16 values a
    // vertex in 12 VEC4 attributes.
    for (file, container) in [("t.gltf", ".gltf, JSON"), ("t.glb", ".glb, binary")] {
        let path = bake(&diffuse, file);
        let table = show(&path);
        assert!(
            table.starts_with(&format!(
                "# glTF 2.0 asset ({container}): a mesh with shlight's PRT transfer\n"
            )),
            "{table}"
        );
        assert!(
            field(&table, "transfer").starts_with(
                "_SH_TRANSFER_0 .. _SH_TRANSFER_11: 12 VEC4 float attributes per vertex"
            ),
            "{table}"
        );
        assert_eq!(field(&table, "lmax"), "3");
        assert_eq!(field(&table, "vertices"), vertices);
        assert_eq!(field(&table, "seed"), "5");
    }
    // A light added to the GLB: both, and the light's coefficients.
    let light = dir.join("light.json");
    write_radiance_rows(&light, &light_rows());
    let glb = dir.join("t.glb");
    shlight_ok(&["convert", s(&light), "--into", s(&glb), "--irradiance-only"]);
    let table = show(&glb);
    assert!(
        table.starts_with(
            "# glTF 2.0 asset (.glb, binary): a mesh with shlight's PRT transfer, and an \
             EXT_lights_image_based light"
        ),
        "{table}"
    );
    assert_eq!(field(&table, "lmax"), "3");
    assert!(field(&table, "light").starts_with("\"shlight\""), "{table}");
    assert_printed(
        &rows(&table),
        &irradiance_l2(&light_rows()),
        "the GLB's light",
    );
}

#[test]
fn volumes_their_exports_and_their_samples_show_the_grid() {
    let dir = temp_dir("show-volume");
    let rooms = dir.join("rooms.obj");
    write_two_rooms(&rooms, 2.1);
    let sky = dir.join("sky.json");
    let mut rows = vec![[0.0; 3]; 9];
    rows[0] = [2.0, 1.5, 1.0];
    write_radiance_rows(&sky, &rows);
    let bake = |extra: &[&str], out: &str| {
        let path = dir.join(out);
        let mut args = vec![
            "volume",
            s(&rooms),
            "--env",
            s(&sky),
            "--resolution",
            "3x2x2",
            "--lmax",
            "1",
            "--samples",
            "128",
            "--surface-samples",
            "16",
            "--seed",
            "3",
        ];
        args.extend_from_slice(extra);
        args.extend(["-o", s(&path)]);
        shlight_ok(&args);
        path
    };
    let shvol = bake(&[], "v.shvol");
    let written = header_line(&shvol);
    let invalid = written["invalid"].as_array().unwrap().len();
    let relocated = written["relocated"].as_array().unwrap().len();
    let size = written["visibility"]["size"].as_u64().unwrap();
    let table = show(&shvol);
    assert!(
        table.starts_with("# shlight irradiance volume (.shvol, format_version 2)\n"),
        "{table}"
    );
    let same_bake = |table: &str| {
        for (name, want) in [
            (
                "lmax",
                "1 (4 coefficients per probe and channel)".to_string(),
            ),
            (
                "grid",
                "3 x 2 x 2 = 12 probes at the cells' centres, x fastest".into(),
            ),
            ("invalid", format!("{invalid} probes (inside geometry)")),
            (
                "relocated",
                format!("{relocated} probes moved out of geometry"),
            ),
            ("frame", "y-up".into()),
            ("samples", format!("{} rays per probe", written["samples"])),
            ("bounces", written["bounces"].to_string()),
            ("seed", "3".into()),
            (
                "scene",
                format!(
                    "{} ({})",
                    written["scene"].as_str().unwrap(),
                    written["scene_hash"].as_str().unwrap()
                ),
            ),
            (
                "environment",
                written["environment"].as_str().unwrap().into(),
            ),
        ] {
            assert_eq!(field(table, name), want, "{name}: {table}");
        }
        assert!(
            field(table, "visibility").starts_with(&format!("a {size}x{size} octahedral map")),
            "{table}"
        );
    };
    same_bake(&table);
    assert!(field(&table, "holds").contains("relightable"), "{table}");
    // The JSON form says the same; a static bake holds no transfer; one
    // without relocation and visibility is version 1.
    let json = show(&bake(&[], "v.json"));
    assert!(
        json.starts_with("# shlight irradiance volume, JSON form"),
        "{json}"
    );
    same_bake(&json);
    let table = show(&bake(&["--static"], "static.shvol"));
    assert!(
        field(&table, "holds").starts_with("radiance, offsets, visibility: static"),
        "{table}"
    );
    let table = show(&bake(&["--no-visibility", "--no-relocate"], "v1.shvol"));
    assert!(table.contains("(.shvol, format_version 1)"), "{table}");
    assert!(fields(&table, "visibility").is_empty() && fields(&table, "relocated").is_empty());
    // Bevy's texture: nx x 2 ny x 3 nz half floats.
    let table = show(&bake(&[], "v.ktx2"));
    assert!(
        table.starts_with("# KTX2: Bevy IrradianceVolume texture"),
        "{table}"
    );
    assert!(
        field(&table, "holds").starts_with("a 3 x 2 x 2 grid of probes"),
        "{table}"
    );
    assert_eq!(field(&table, "size"), "3 x 4 x 6 (3D)");
    // three.js's grid: seven sub-volumes of nz + 2 slices.
    let grid = dir.join("grid.json");
    shlight_ok(&["convert", s(&shvol), "--format", "threejs", "-o", s(&grid)]);
    let table = show(&grid);
    assert!(table.starts_with("# three.js LightProbeGrid"), "{table}");
    assert_eq!(
        field(&table, "grid"),
        "3 x 2 x 2 = 12 probes at the cells' centres"
    );
    assert!(field(&table, "atlas").starts_with("3 x 2 x 28 RGBAFormat texels of HalfFloatType"));
    assert!(
        field(&table, "holds").contains("from a volume of lmax 1"),
        "{table}"
    );
    assert_eq!(field(&table, "seed"), "3");
    // The shader snippet and its three textures.
    let snippet = dir.join("vol.wgsl");
    shlight_ok(&["convert", s(&shvol), "-o", s(&snippet)]);
    let table = show(&snippet);
    assert!(
        table.starts_with("# WGSL code: an irradiance volume's lookup"),
        "{table}"
    );
    assert_eq!(field(&table, "lmax"), "1");
    assert_eq!(fields(&table, "texture").len(), 3, "{table}");
    let sh = show(&dir.join("vol.sh.ktx2"));
    assert!(
        sh.starts_with("# KTX2: a volume snippet's sh texture"),
        "{sh}"
    );
    assert_eq!(field(&sh, "size"), "3 x 2 x 8 (3D)");
    assert!(
        field(&sh, "holds").ends_with("8 slices = (lmax+1)^2 x nz"),
        "{sh}"
    );
    let probes = show(&dir.join("vol.probes.ktx2"));
    assert!(
        field(&probes, "holds").starts_with("a 3 x 2 x 2 grid"),
        "{probes}"
    );
    let moments = show(&dir.join("vol.moments.ktx2"));
    assert!(field(&moments, "format").starts_with("VK_FORMAT_R32G32_SFLOAT"));
    assert_eq!(
        field(&moments, "size"),
        format!("{0} x {1} x 2 (3D)", 3 * (size + 2), 2 * (size + 2))
    );
    // `sample`'s answer and the points it read.
    let points = dir.join("points.csv");
    std::fs::write(
        &points,
        "x,y,z,nx,ny,nz\n1,0.1,1,0,1,0\n3,0.1,1,0,1,0\n2,1,0.5,1,0,0\n",
    )
    .unwrap();
    let table = show(&points);
    assert!(table.starts_with("# points to sample (shlight sample --points, CSV)"));
    assert_eq!(field(&table, "holds"), "3 points, each with a unit normal");
    for (out, kind) in [
        (
            "s.json",
            "# shlight sample's answer (shlight-samples, format_version 1)",
        ),
        ("s.csv", "# shlight sample's answer as CSV"),
    ] {
        let path = dir.join(out);
        shlight_ok(&["sample", s(&shvol), "--points", s(&points), "-o", s(&path)]);
        let table = show(&path);
        assert!(table.starts_with(kind), "{table}");
        assert!(
            field(&table, "holds").starts_with("3 [r, g, b] values"),
            "{table}"
        );
    }
    let table = show(&dir.join("s.json"));
    assert_eq!(field(&table, "holds"), "3 [r, g, b] values of irradiance");
    assert_eq!(field(&table, "provenance seed"), "3");
    assert_eq!(field(&table, "lmax"), "1");
}

#[test]
fn cubes_dfg_tables_plots_and_images_show_their_headers() {
    let dir = temp_dir("show-images");
    let map = synth_sun_map(&dir);
    let prefilter = |extra: &[&str], out: &str| {
        let path = dir.join(out);
        let mut args = vec!["prefilter", s(&map), "--samples", "16", "-o", s(&path)];
        args.extend_from_slice(extra);
        shlight_ok(&args);
        path
    };
    let table = show(&prefilter(&["--for", "bevy", "--size", "16"], "bevy.ktx2"));
    assert!(table.starts_with("# KTX2: a cube map with mips"), "{table}");
    assert!(
        field(&table, "holds")
            .starts_with("6 faces (+X -X +Y -Y +Z -Z), 5 mips, 16x16 down to 1x1")
    );
    assert_eq!(field(&table, "faces"), "6");
    assert!(field(&table, "writer").starts_with("shlight "), "{table}");
    let table = show(&prefilter(
        &["--for", "bevy", "--size", "16", "--mips", "3"],
        "three.ktx2",
    ));
    assert_eq!(field(&table, "levels"), "3");
    assert!(
        field(&table, "holds").contains("3 mips, 16x16 down to 4x4"),
        "{table}"
    );
    // Filament stops at 16 pixels: 32 and 16.
    let table = show(&prefilter(&["--size", "32"], "filament.ktx"));
    assert!(
        table.starts_with("# KTX 1.1: Filament's prefiltered cube map"),
        "{table}"
    );
    assert_eq!(field(&table, "levels"), "2 mips, 32x32 down to 16x16");
    assert!(field(&table, "format").starts_with("GL_R11F_G11F_B10F"));
    prefilter(&["--size", "16"], "ld/");
    let table = show(&dir.join("ld/m1_nz.exr"));
    assert!(table.starts_with("# OpenEXR image\n"), "{table}");
    assert_eq!(field(&table, "size"), "8 x 8");
    assert!(field(&table, "note").starts_with("an image"), "{table}");
    for (file, kind, channels) in [
        ("dfg.png", "# PNG image", "R, G, B (8-bit)"),
        ("dfg.exr", "# OpenEXR image", "B, G, R (32-bit float)"),
    ] {
        let path = dir.join(file);
        shlight_ok(&["dfg", "-o", s(&path), "--size", "8", "--samples", "16"]);
        let table = show(&path);
        assert!(table.starts_with(kind), "{table}");
        assert_eq!(field(&table, "size"), "8 x 8");
        assert_eq!(field(&table, "channels"), channels);
    }
    let light = dir.join("light.json");
    write_radiance_rows(&light, &light_rows());
    let hdr = dir.join("r.hdr");
    shlight_ok(&["render", s(&light), "-o", s(&hdr), "--size", "24x12"]);
    let table = show(&hdr);
    assert!(table.starts_with("# Radiance HDR image"), "{table}");
    assert_eq!(field(&table, "size"), "24 x 12");
    // compare's rows and plot.
    let out = dir.join("compare");
    shlight_ok(&["compare", s(&map), "--normals", "16x8", "-o", s(&out)]);
    let rows_written = crate::util::read_json(&out.join("compare.json"));
    let table = show(&out.join("compare.json"));
    assert!(table.starts_with("# shlight compare's rows"), "{table}");
    assert!(
        field(&table, "holds")
            .starts_with(&format!("{} rows", rows_written.as_array().unwrap().len())),
        "{table}"
    );
    assert_eq!(field(&table, "maps"), "sun");
    let table = show(&out.join("compare-sun.svg"));
    assert!(table.starts_with("# SVG picture"), "{table}");
}

#[test]
fn files_shlight_does_not_write_and_broken_ones_are_errors_naming_the_file() {
    let dir = temp_dir("show-errors");
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        (
            "empty.json",
            Vec::new(),
            "an empty file, not a file shlight writes",
        ),
        (
            "notes.txt",
            b"hello\n".to_vec(),
            "text, but not a file shlight writes",
        ),
        (
            "noise.bin",
            vec![0x00, 0xff, 0xfe, 0x80, 7],
            "binary, but not a file shlight writes",
        ),
        (
            "other.json",
            b"{\"a\": 1}\n".to_vec(),
            "JSON, but not a file shlight writes",
        ),
        ("broken.json", b"{\"a\": \n".to_vec(), "not valid JSON"),
    ];
    for (file, bytes, want) in cases {
        let path = dir.join(file);
        std::fs::write(&path, bytes).unwrap();
        let e = shlight_err(&["show", s(&path)]);
        assert!(
            e.starts_with(&format!("error: {}: ", path.display())),
            "{e}"
        );
        assert!(e.contains(want), "{file}: {e}");
    }
    // Files of a kind shlight writes, cut short: the kind's reader says so.
    let light = dir.join("light.json");
    write_radiance_rows(&light, &light_rows());
    let mesh = dir.join("torus.obj");
    write_obj(&mesh, &generate::torus(1.0, 0.3, 8, 6));
    let prt = dir.join("t.shprt");
    shlight_ok(&["prt", s(&mesh), "--samples", "16", "-o", s(&prt)]);
    let glb = dir.join("t.glb");
    shlight_ok(&["prt", s(&mesh), "--samples", "16", "-o", s(&glb)]);
    let map = synth_sun_map(&dir);
    let ktx2 = dir.join("p.ktx2");
    shlight_ok(&[
        "prefilter",
        s(&map),
        "--for",
        "bevy",
        "--size",
        "8",
        "--samples",
        "4",
        "-o",
        s(&ktx2),
    ]);
    for (path, want) in [
        (&prt, "truncated"),
        (&glb, "the GLB header says"),
        (&ktx2, "a truncated KTX2 file"),
    ] {
        let bytes = std::fs::read(path).unwrap();
        let cut = dir.join(format!(
            "cut-{}",
            path.file_name().unwrap().to_string_lossy()
        ));
        std::fs::write(&cut, &bytes[..bytes.len() - 8]).unwrap();
        let e = shlight_err(&["show", s(&cut)]);
        assert!(e.starts_with(&format!("error: {}: ", cut.display())), "{e}");
        assert!(e.contains(want), "{}: {e}", cut.display());
    }
}
