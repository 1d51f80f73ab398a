//! `shlight prefilter` and `shlight dfg` end to end: the files as cmgen's
//! `--ibl-ld` names them, compared with cmgen itself on a bundled map.

use std::path::{Path, PathBuf};
use std::process::Command;

use shlight_io::{Image, ReadOptions, WriteOptions, read_image, write_image};

use crate::util::{s, shlight_err, shlight_ok, skip, temp_dir};

const FACES: [&str; 6] = ["px", "nx", "py", "ny", "pz", "nz"];

/// A bundled map written as Radiance `.hdr`, which cmgen reads (its EXR
/// decoder does not know the bundled files' DWAB compression).
fn bundled_hdr(name: &str, dir: &Path) -> PathBuf {
    let src = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("envmaps")
        .join(format!("{name}.exr"));
    let image = read_image(&src, &ReadOptions::default()).unwrap();
    let path = dir.join(format!("{name}.hdr"));
    write_image(&path, &image, &WriteOptions::default()).unwrap();
    path
}

fn read(path: &Path) -> Image {
    read_image(path, &ReadOptions::default()).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Mean absolute difference of two faces over the mean of `b`, all channels.
fn relative_difference(a: &Image, b: &Image) -> f64 {
    assert_eq!((a.width(), a.height()), (b.width(), b.height()));
    let (mut diff, mut sum) = (0.0, 0.0);
    for (p, q) in a.pixels().iter().zip(b.pixels()) {
        for c in 0..3 {
            diff += f64::from((p[c] - q[c]).abs());
            sum += f64::from(q[c].abs());
        }
    }
    diff / sum
}

/// Mean over the six faces of [`relative_difference`] between mip `level`
/// of two `--ibl-ld` directories.
fn level_difference(a: &Path, b: &Path, level: usize, swap: bool) -> f64 {
    FACES
        .iter()
        .enumerate()
        .map(|(k, face)| {
            let other = if swap { FACES[k ^ 1] } else { face };
            relative_difference(
                &read(&a.join(format!("m{level}_{face}.exr"))),
                &read(&b.join(format!("m{level}_{other}.exr"))),
            )
        })
        .sum::<f64>()
        / 6.0
}

/// `shlight prefilter --for filament` against `cmgen --ibl-ld` on the
/// bundled city map, file by file: same names, same faces, same roughness
/// per level, within what the two resamplings leave.
#[test]
fn prefilter_agrees_with_cmgen_file_by_file() {
    const TEST: &str = "specular::prefilter_agrees_with_cmgen_file_by_file";
    /// Mean absolute difference over the mean, per level (mean of the six
    /// faces; measured 4.9%, 3.6%, 7.5% with cmgen 1.9.25). Level 0 is the
    /// map resampled: cmgen scales longitude by `W - 1` and reads texels
    /// without filtering. At level 2 (roughness 1) cmgen is about 5% below
    /// the exact GGX-weighted integral where shlight is within 0.1% (the
    /// crate's brute-force tests; measured at texel (0, 0) of m2_px).
    const TOLERANCE: [f64; 3] = [0.07, 0.06, 0.10];
    let dir = temp_dir("specular_cmgen");
    let map = bundled_hdr("city", &dir);
    let theirs_root = dir.join("theirs");
    let out = match Command::new("cmgen")
        .args(["-q", "--format=exr", "--compression=ZIP", "--size=64"])
        .arg(format!("--ibl-ld={}", s(&theirs_root)))
        .arg(&map)
        .output()
    {
        Ok(out) => out,
        Err(e) => {
            skip(
                TEST,
                &format!("cmgen not found ({e}); apt install libfilament-tools"),
            );
            return;
        }
    };
    assert!(
        out.status.success(),
        "cmgen: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    // cmgen writes into a directory named after the input.
    let theirs = theirs_root.join("city");
    let ours = dir.join("ours");
    shlight_ok(&[
        "prefilter",
        s(&map),
        "-o",
        &format!("{}/", s(&ours)),
        "--for",
        "filament",
        "--size",
        "64",
        "-q",
    ]);
    let mut names: Vec<String> = std::fs::read_dir(&ours)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    let mut theirs_names: Vec<String> = std::fs::read_dir(&theirs)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    theirs_names.sort();
    assert_eq!(
        names, theirs_names,
        "the same files, m0_px.exr ... m2_nz.exr"
    );
    assert_eq!(names.len(), 18);
    for (level, tolerance) in TOLERANCE.into_iter().enumerate() {
        let d = level_difference(&ours, &theirs, level, false);
        eprintln!("level {level}: {:.2}% from cmgen", 100.0 * d);
        assert!(d < tolerance, "level {level}: {:.2}% from cmgen", 100.0 * d);
        // Faces swapped with their opposites would be far off.
        let swapped = level_difference(&ours, &theirs, level, true);
        assert!(
            swapped > 5.0 * tolerance,
            "level {level} swapped: {swapped}"
        );
    }
    // The tolerance tells roughness mappings apart: Babylon's roughness at
    // level 1 (perceptual 0.354 against Filament's 0.293), in the same
    // axes, is further from cmgen than level 1's tolerance.
    let babylon = dir.join("babylon");
    shlight_ok(&[
        "prefilter",
        s(&map),
        "-o",
        &format!("{}/", s(&babylon)),
        "--for",
        "babylon",
        "--size",
        "64",
        "--mips",
        "3",
        "-q",
    ]);
    let off = level_difference(&babylon, &theirs, 1, false);
    assert!(
        off > TOLERANCE[1],
        "another roughness, level 1: {:.2}%",
        100.0 * off
    );
}

/// `shlight dfg` writes the library's table: EXR exactly, PNG to 8 bits,
/// not sRGB-encoded; the form follows `--for`.
#[test]
fn dfg_writes_the_table() {
    let dir = temp_dir("specular_dfg");
    let exr = dir.join("dfg.exr");
    let png = dir.join("dfg.png");
    shlight_ok(&[
        "dfg",
        "-o",
        s(&exr),
        "--size",
        "16",
        "--samples",
        "256",
        "-q",
    ]);
    shlight_ok(&[
        "dfg",
        "-o",
        s(&png),
        "--size",
        "16",
        "--samples",
        "256",
        "--for",
        "unreal",
        "-q",
    ]);
    let filament =
        shlight_specular::DfgTable::for_engine(shlight_specular::TargetEngine::Filament, 16, 256);
    let unreal =
        shlight_specular::DfgTable::for_engine(shlight_specular::TargetEngine::Unreal, 16, 256);
    let (e, p) = (read(&exr), read(&png));
    for (k, (a, b)) in e.pixels().iter().zip(&filament.values).enumerate() {
        assert_eq!([a[0], a[1]], [b[0] as f32, b[1] as f32], "texel {k}");
    }
    // PNG: the values themselves in 8 bits (the reader sRGB-decodes, so
    // encode back before comparing).
    for (k, (a, b)) in p.pixels().iter().zip(&unreal.values).enumerate() {
        for c in 0..2 {
            let stored = shlight_io::linear_to_srgb(a[c]);
            assert!(
                (f64::from(stored) - b[c]).abs() <= 0.5 / 255.0 + 1e-4,
                "texel {k}: {stored} vs {}",
                b[c]
            );
        }
    }
    // Facing and smooth (bottom right): Filament's (B, A + B) is (0, 1).
    let corner = e.get(15, 15);
    assert!(corner[0] < 0.01 && corner[1] > 0.95, "{corner:?}");
    let err = shlight_err(&["dfg", "-o", s(&dir.join("dfg.hdr")), "-q"]);
    assert!(
        err.contains("dfg.hdr") && err.contains(".exr or .png"),
        "{err}"
    );
}

#[test]
fn prefilter_refuses_what_it_cannot_write() {
    let dir = temp_dir("specular_refusals");
    let map = bundled_hdr("sky", &dir);
    let err = shlight_err(&["prefilter", s(&map), "-o", s(&dir.join("out.exr")), "-q"]);
    assert!(err.contains("names a directory"), "{err}");
    let err = shlight_err(&[
        "prefilter",
        s(&map),
        "-o",
        &format!("{}/", s(&dir)),
        "--size",
        "100",
        "-q",
    ]);
    assert!(err.contains("power of two"), "{err}");
    let err = shlight_err(&[
        "prefilter",
        s(&dir.join("missing.exr")),
        "-o",
        &format!("{}/", s(&dir)),
        "-q",
    ]);
    assert!(err.contains("missing.exr"), "{err}");
}

/// The glTF light's specular images hold what Babylon.js reads: decoded
/// from RGBD (Babylon's `fromRGBD`), mip 0 is the map itself in the
/// light's frame, Babylon's world (shlight's `(x, y, z)` at `(z, y, x)`),
/// faces in the order `+X -X +Y -Y +Z -Z`, each PNG's rows bottom first
/// (row `j` of the PNG is row `S - 1 - j` of the OpenGL cube-map
/// convention: Babylon's loader puts a PNG's first row at the bottom of
/// the face, which tests/web.rs measures); every mip halves down to one
/// pixel.
#[test]
fn gltf_specular_images_are_the_map_in_rgbd() {
    use base64::Engine as _;
    use glam::DVec3;
    use shlight_core::map::{CubeFace, MapOrientation, equirect_direction};
    /// RGBD's 8 bits (0.5% above 1) and the bilinear resampling of a smooth
    /// map at 4 map texels per cube texel.
    const TOLERANCE: f64 = 0.03;
    let dir = temp_dir("specular_gltf");
    let f = |d: DVec3| {
        let v = 1.5 + 0.8 * d.x + 0.4 * d.y * d.y - 0.6 * d.z;
        DVec3::new(v, 0.7 * v + 0.3, 2.5 - 0.5 * d.y)
    };
    let (w, h) = (256, 128);
    let map = dir.join("smooth.exr");
    crate::util::write_map(&map, w, h, |x, y| {
        f(equirect_direction(x, y, w, h, MapOrientation::default()))
            .as_vec3()
            .to_array()
    });
    let out = dir.join("l.gltf");
    shlight_ok(&[
        "project",
        s(&map),
        "--format",
        "gltf",
        "-o",
        s(&out),
        "--specular-size",
        "16",
        "--specular-samples",
        "64",
        "-q",
    ]);
    let v: serde_json::Value = serde_json::from_slice(&std::fs::read(&out).unwrap()).unwrap();
    let light = &v["extensions"]["EXT_lights_image_based"]["lights"][0];
    let png = |index: &serde_json::Value| {
        let uri = v["images"][index.as_u64().unwrap() as usize]["uri"]
            .as_str()
            .unwrap();
        let b64 = uri.strip_prefix("data:image/png;base64,").unwrap();
        let bytes = base64::engine::general_purpose::STANDARD
            .decode(b64)
            .unwrap();
        image::load_from_memory(&bytes).unwrap().to_rgba8()
    };
    let mips = light["specularImages"].as_array().unwrap();
    for (k, mip) in mips.iter().enumerate() {
        for face in mip.as_array().unwrap() {
            assert_eq!(png(face).width(), 16 >> k);
        }
    }
    let (mut worst, mut worst_unturned, mut worst_upright) = (0.0f64, 0.0f64, 0.0f64);
    for (face_index, face) in CubeFace::ALL.into_iter().enumerate() {
        let img = png(&mips[0][face_index]);
        for j in 0..16 {
            for i in 0..16 {
                let rgbd = img.get_pixel(i as u32, 15 - j as u32).0;
                let got = DVec3::from(shlight_specular::rgbd_decode(rgbd).map(f64::from));
                let c = |k: usize| (2.0 * k as f64 + 1.0) / 16.0 - 1.0;
                let g = face.point(c(i), c(j)).normalize();
                // Babylon's (z, y, x) is shlight's (x, y, z).
                let want = f(DVec3::new(g.z, g.y, g.x));
                let rel = |w: DVec3| ((got - w).abs() / w).max_element();
                worst = worst.max(rel(want));
                worst_unturned = worst_unturned.max(rel(f(g)));
                // The same texel read upright (row j at the top).
                let up = face.point(c(i), c(15 - j)).normalize();
                worst_upright = worst_upright.max(rel(f(DVec3::new(up.z, up.y, up.x))));
            }
        }
    }
    assert!(worst < TOLERANCE, "{worst}");
    assert!(worst_unturned > 5.0 * TOLERANCE, "{worst_unturned}");
    assert!(worst_upright > 5.0 * TOLERANCE, "{worst_upright}");
}

/// IEEE half to f32, written out (normal and subnormal numbers).
fn half_to_f32(h: u16) -> f32 {
    let sign = if h >> 15 == 1 { -1.0 } else { 1.0 };
    let exp = i32::from((h >> 10) & 0x1f);
    let frac = f32::from(h & 0x3ff);
    match exp {
        0 => sign * frac * 2f32.powi(-24),
        31 => f32::NAN,
        e => sign * (1.0 + frac / 1024.0) * 2f32.powi(e - 15),
    }
}

/// `-o FILE.ktx2` holds, per the KTX2 layout read by hand here, the same
/// mips as the faces `-o DIR/` writes, in half floats: six faces per level
/// in the order `+X -X +Y -Y +Z -Z`, every level at its level index.
#[test]
fn prefilter_writes_a_ktx2_cube_with_its_mips() {
    let dir = temp_dir("specular_ktx2");
    let map = bundled_hdr("sky", &dir);
    let ktx2 = dir.join("sky.ktx2");
    let faces = dir.join("faces");
    let common = ["--for", "bevy", "--size", "8", "--samples", "64", "-q"];
    let mut args = vec!["prefilter", s(&map), "-o", s(&ktx2)];
    args.extend(common);
    shlight_ok(&args);
    let faces_dir = format!("{}/", s(&faces));
    let mut args = vec!["prefilter", s(&map), "-o", &faces_dir];
    args.extend(common);
    shlight_ok(&args);
    let bytes = std::fs::read(&ktx2).unwrap();
    let u32_at = |o: usize| u32::from_le_bytes(bytes[o..o + 4].try_into().unwrap()) as usize;
    let u64_at = |o: usize| u64::from_le_bytes(bytes[o..o + 8].try_into().unwrap()) as usize;
    assert_eq!(&bytes[..12], b"\xABKTX 20\xBB\r\n\x1A\n");
    assert_eq!(u32_at(12), 97, "VK_FORMAT_R16G16B16A16_SFLOAT");
    assert_eq!((u32_at(20), u32_at(24)), (8, 8));
    let (faces_n, levels) = (u32_at(36), u32_at(40));
    assert_eq!((faces_n, levels), (6, 4));
    for k in 0..levels {
        let index = 12 + 9 * 4 + 4 * 4 + 2 * 8 + 24 * k;
        let (offset, len) = (u64_at(index), u64_at(index + 8));
        let s_k = 8 >> k;
        assert_eq!(len, 6 * s_k * s_k * 8);
        for (f, name) in FACES.iter().enumerate() {
            let exr = read(&faces.join(format!("m{k}_{name}.exr")));
            for (i, want) in exr.pixels().iter().enumerate() {
                let t = offset + (f * s_k * s_k + i) * 8;
                for c in 0..4 {
                    let got =
                        half_to_f32(u16::from_le_bytes([bytes[t + 2 * c], bytes[t + 2 * c + 1]]));
                    let want = if c == 3 { 1.0 } else { want[c] };
                    assert!(
                        (got - want).abs() <= 1e-3 * want.abs() + 1e-6,
                        "mip {k} {name} {i}: {got} vs {want}"
                    );
                }
            }
        }
    }
}

/// One mip of a cube: six faces of texels.
type Mip = Vec<Vec<[f32; 3]>>;

/// The levels of a KTX 1.1 cube map as Filament's `KtxBundle` lays them
/// out, read by hand: (header's 13 words after the identifier, per level
/// the six faces' texels unpacked from `R11F_G11F_B10F`).
fn read_ktx1(bytes: &[u8]) -> (Vec<u32>, Vec<Mip>) {
    assert_eq!(&bytes[..12], b"\xABKTX 11\xBB\r\n\x1A\n");
    let word = |o: usize| u32::from_le_bytes(bytes[o..o + 4].try_into().unwrap());
    let header: Vec<u32> = (0..13).map(|k| word(12 + 4 * k)).collect();
    let (levels, kv) = (header[11] as usize, header[12] as usize);
    let mut at = 64 + kv;
    let mut out = Vec::new();
    for _ in 0..levels {
        let face_bytes = word(at) as usize;
        at += 4;
        let mut faces = Vec::new();
        for _ in 0..6 {
            faces.push(
                (0..face_bytes / 4)
                    .map(|i| shlight_format::unpack_r11g11b10(word(at + 4 * i)))
                    .collect(),
            );
            at += face_bytes;
        }
        out.push(faces);
    }
    assert_eq!(at, bytes.len());
    (header, out)
}

/// `-o FILE.ktx` is the file `cmgen --format=ktx --ibl-ld` writes, field
/// for field (the header equal), and its faces agree with cmgen's as the
/// EXR faces do (in cmgen's packed precision).
#[test]
fn prefilter_ktx_matches_cmgens_ktx() {
    const TEST: &str = "specular::prefilter_ktx_matches_cmgens_ktx";
    /// As `prefilter_agrees_with_cmgen_file_by_file` (the same map and
    /// size), plus the packing's half step (under 0.8%).
    const TOLERANCE: [f64; 3] = [0.08, 0.07, 0.11];
    let dir = temp_dir("specular_ktx1");
    let map = bundled_hdr("city", &dir);
    let out = match Command::new("cmgen")
        .args(["-q", "--format=ktx", "--size=64"])
        .arg(format!("--ibl-ld={}", s(&dir.join("theirs"))))
        .arg(&map)
        .output()
    {
        Ok(out) => out,
        Err(e) => {
            skip(
                TEST,
                &format!("cmgen not found ({e}); apt install libfilament-tools"),
            );
            return;
        }
    };
    assert!(
        out.status.success(),
        "cmgen: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    // cmgen names the file after the output directory.
    let theirs = std::fs::read(dir.join("theirs").join("theirs_ibl.ktx")).unwrap();
    let ours_path = dir.join("ours.ktx");
    shlight_ok(&[
        "prefilter",
        s(&map),
        "-o",
        s(&ours_path),
        "--for",
        "filament",
        "--size",
        "64",
        "-q",
    ]);
    let ours = std::fs::read(&ours_path).unwrap();
    let ((h1, l1), (h2, l2)) = (read_ktx1(&ours), read_ktx1(&theirs));
    assert_eq!(h1, h2, "the header, word for word");
    assert_eq!(l1.len(), 3);
    for (k, (a, b)) in l1.iter().zip(&l2).enumerate() {
        let (mut diff, mut sum, mut swapped) = (0.0, 0.0, 0.0);
        for f in 0..6 {
            for (p, q) in a[f].iter().zip(&b[f]) {
                for c in 0..3 {
                    diff += f64::from((p[c] - q[c]).abs());
                    sum += f64::from(q[c]);
                }
            }
            for (p, q) in a[f].iter().zip(&b[f ^ 1]) {
                for c in 0..3 {
                    swapped += f64::from((p[c] - q[c]).abs());
                }
            }
        }
        eprintln!(
            "ktx level {k}: {:.2}% from cmgen (faces swapped: {:.0}%)",
            100.0 * diff / sum,
            100.0 * swapped / sum
        );
        assert!(
            diff / sum < TOLERANCE[k],
            "level {k}: {:.2}%",
            100.0 * diff / sum
        );
        assert!(
            swapped / sum > 2.0 * TOLERANCE[k],
            "level {k} swapped: {swapped}"
        );
    }
}
