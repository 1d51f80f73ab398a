//! Every mesh format against hand-written files with known content, and bad
//! files of each format (errors naming the file, never panics).

use std::path::{Path, PathBuf};

use base64::Engine as _;
use glam::Vec3;
use shlight_mesh::{Mesh, MeshFormat, load, load_bytes};

fn parse(name: &str, bytes: &[u8]) -> Result<Mesh, String> {
    let path = Path::new(name);
    let format = MeshFormat::from_path(path).expect("a known extension");
    load_bytes(path, format, bytes).map_err(|e| e.to_string())
}

fn err(name: &str, bytes: &[u8]) -> String {
    let e = parse(name, bytes).expect_err("a bad file must be an error");
    assert!(e.starts_with(&format!("{name}: ")), "{e}");
    e
}

/// A unit square in z = 0 as a quad (fanned into two triangles) and a
/// coloured, normal-carrying vertex list in the formats' own spellings.
const PLY_ASCII: &str = "ply\nformat ascii 1.0\ncomment a quad\nelement vertex 4\n\
property float x\nproperty float y\nproperty float z\n\
property float nx\nproperty float ny\nproperty float nz\n\
property uchar red\nproperty uchar green\nproperty uchar blue\n\
element face 1\nproperty list uchar int vertex_indices\nend_header\n\
0 0 0 0 0 1 255 0 0\n1 0 0 0 0 1 0 255 0\n1 1 0 0 0 1 0 0 255\n0 1 0 0 0 1 188 188 188\n\
4 0 1 2 3\n";

fn ply_binary(truncate: usize) -> Vec<u8> {
    let mut b = b"ply\nformat binary_little_endian 1.0\nelement vertex 4\n\
property double x\nproperty double y\nproperty double z\nproperty short extra\n\
element face 1\nproperty list uchar uint vertex_indices\nelement note 1\nproperty int n\nend_header\n"
        .to_vec();
    for p in [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0f64],
    ] {
        for c in p {
            b.extend(c.to_le_bytes());
        }
        b.extend(7i16.to_le_bytes());
    }
    b.push(4);
    for i in [0u32, 1, 2, 3] {
        b.extend(i.to_le_bytes());
    }
    b.extend(5i32.to_le_bytes());
    b.truncate(b.len() - truncate);
    b
}

fn assert_unit_square(m: &Mesh) {
    assert_eq!((m.vertex_count(), m.triangle_count()), (4, 2));
    assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 3]]);
    assert!((m.surface_area() - 1.0).abs() < 1e-12);
    assert!(m.normals.iter().all(|n| (*n - Vec3::Z).length() < 1e-6));
}

#[test]
fn ply_ascii_reads_normals_and_srgb_colours() {
    let m = parse("q.ply", PLY_ASCII.as_bytes()).unwrap();
    assert_unit_square(&m);
    assert_eq!(m.report.computed_normals, 0);
    let c = m.colors.as_ref().unwrap();
    assert_eq!(c[0], Vec3::X);
    // sRGB 188/255 is linear 0.5029 (IEC 61966-2-1).
    assert!((c[3].x - 0.502_886).abs() < 1e-5, "{:?}", c[3]);
}

#[test]
fn ply_binary_skips_unknown_properties_and_elements() {
    let m = parse("q.ply", &ply_binary(0)).unwrap();
    assert_unit_square(&m);
    assert_eq!(m.report.computed_normals, 4);
    assert!(m.colors.is_none());
}

#[test]
fn bad_ply_files_are_errors() {
    assert!(err("t.ply", &ply_binary(6)).contains("truncated"));
    assert!(err("t.ply", b"solid x\n").contains("not a PLY file"));
    assert!(
        err(
            "t.ply",
            b"ply\nformat binary_big_endian 1.0\nelement vertex 0\nend_header\n"
        )
        .contains("binary_big_endian\" is not supported")
    );
    let bad_index = PLY_ASCII.replace("4 0 1 2 3", "4 0 1 2 9");
    assert!(err("t.ply", bad_index.as_bytes()).contains("index 9 out of range"));
    let nan = PLY_ASCII.replace("1 1 0 0 0 1", "nan 1 0 0 0 1");
    assert!(err("t.ply", nan.as_bytes()).contains("non-finite"));
    let word = PLY_ASCII.replace("1 1 0 0 0 1", "1 x 0 0 0 1");
    assert!(err("t.ply", word.as_bytes()).contains("\"x\" is not a number"));
    let empty = "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
    assert!(err("t.ply", empty.as_bytes()).contains("no vertices"));
    let short = PLY_ASCII.replace("4 0 1 2 3\n", "4 0 1\n");
    assert!(err("t.ply", short.as_bytes()).contains("ends early"));
}

const OFF: &str = "OFF\n# a quad\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n";

#[test]
fn off_and_coff_read_polygons_and_colours() {
    assert_unit_square(&parse("q.off", OFF.as_bytes()).unwrap());
    let coff = "COFF 4 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n1 1 0 0 0 255 255\n0 1 0 188 188 188 255\n4 0 1 2 3 1 1 1\n";
    let m = parse("q.off", coff.as_bytes()).unwrap();
    assert_unit_square(&m);
    let c = m.colors.unwrap();
    assert_eq!(c[1], Vec3::Y);
    assert!((c[3].y - 0.502_886).abs() < 1e-5);
}

#[test]
fn bad_off_files_are_errors() {
    assert!(err("t.off", b"PLY\n").contains("not an OFF file"));
    assert!(err("t.off", b"OFF\n4 1 0\n0 0 0\n1 0 0\n").contains("ends at vertex 2 of 4"));
    assert!(
        err("t.off", OFF.replace("4 0 1 2 3", "4 0 1 2 7").as_bytes())
            .contains("index 7 out of range")
    );
    assert!(err("t.off", OFF.replace("1 1 0", "1 NaN 0").as_bytes()).contains("non-finite"));
    assert!(
        err("t.off", OFF.replace("1 1 0", "1 one 0").as_bytes())
            .contains("\"one\" is not a number")
    );
    assert!(err("t.off", b"OFF\n0 0 0\n").contains("no vertices"));
    assert!(
        err("t.off", OFF.replace("4 0 1 2 3", "4 0 1").as_bytes())
            .contains("face 0 has 4 corners and lists 2")
    );
}

/// A glTF with one triangle primitive (a unit square in z = 0, indexed,
/// with COLOR_0) placed twice: by a node translated +2 in x whose child is
/// mirrored in x (scale -1), so the second copy must keep facing +z. The
/// material is a dielectric (`metallicFactor` 0; glTF's default, 1, is a
/// metal, which has no diffuse albedo).
fn gltf_json(buffer_uri: Option<&str>, bytes: usize) -> String {
    let uri = buffer_uri.map_or(String::new(), |u| format!("\"uri\": \"{u}\", "));
    format!(
        r#"{{"asset": {{"version": "2.0"}}, "scene": 0,
 "scenes": [{{"nodes": [0]}}],
 "nodes": [{{"mesh": 0, "translation": [2, 0, 0], "children": [1]}}, {{"mesh": 0, "scale": [-1, 1, 1]}}],
 "materials": [{{"pbrMetallicRoughness": {{"baseColorFactor": [0.5, 1, 1, 1], "metallicFactor": 0}}}}],
 "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "COLOR_0": 1}}, "indices": 2, "material": 0}}]}}],
 "buffers": [{{{uri}"byteLength": {bytes}}}],
 "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 48}}, {{"buffer": 0, "byteOffset": 48, "byteLength": 48}}, {{"buffer": 0, "byteOffset": 96, "byteLength": 12}}],
 "accessors": [
  {{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}},
  {{"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"}},
  {{"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}}]}}"#
    )
}

fn gltf_buffer() -> Vec<u8> {
    let mut b = Vec::new();
    for p in [
        [0.0f32, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ] {
        p.iter().for_each(|c| b.extend(c.to_le_bytes()));
    }
    for c in [
        [1.0f32, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.2, 0.2, 0.2],
    ] {
        c.iter().for_each(|v| b.extend(v.to_le_bytes()));
    }
    for i in [0u16, 1, 2, 0, 2, 3] {
        b.extend(i.to_le_bytes());
    }
    b
}

fn glb(json: &str, bin: &[u8]) -> Vec<u8> {
    let mut j = json.as_bytes().to_vec();
    j.resize(j.len().next_multiple_of(4), b' ');
    let mut bin = bin.to_vec();
    bin.resize(bin.len().next_multiple_of(4), 0);
    let mut out = b"glTF".to_vec();
    out.extend(2u32.to_le_bytes());
    out.extend(((12 + 8 + j.len() + 8 + bin.len()) as u32).to_le_bytes());
    out.extend((j.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(j);
    out.extend((bin.len() as u32).to_le_bytes());
    out.extend(b"BIN\0");
    out.extend(bin);
    out
}

fn assert_two_squares(m: &Mesh) {
    assert_eq!((m.vertex_count(), m.triangle_count()), (8, 4));
    // First instance: translated by +2 in x.
    assert_eq!(m.positions[1], Vec3::new(3.0, 0.0, 0.0));
    // Second: its child, mirrored in x then translated: x = 2 - x.
    assert_eq!(m.positions[5], Vec3::new(1.0, 0.0, 0.0));
    assert!((m.surface_area() - 2.0).abs() < 1e-12);
    // Both face +z: the mirrored copy's winding was reversed.
    assert!(
        m.normals.iter().all(|n| (*n - Vec3::Z).length() < 1e-6),
        "{:?}",
        m.normals
    );
    let c = m.colors.as_ref().unwrap();
    assert_eq!(c[0], Vec3::new(0.5, 0.0, 0.0)); // COLOR_0 times baseColorFactor
    assert_eq!(c[5], Vec3::new(0.0, 1.0, 0.0));
}

#[test]
fn gltf_with_a_data_uri_and_glb_apply_node_transforms_and_colours() {
    let buffer = gltf_buffer();
    let uri = format!(
        "data:application/octet-stream;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(&buffer)
    );
    let json = gltf_json(Some(&uri), buffer.len());
    assert_two_squares(&parse("s.gltf", json.as_bytes()).unwrap());
    assert_two_squares(&parse("s.glb", &glb(&gltf_json(None, buffer.len()), &buffer)).unwrap());
}

#[test]
fn gltf_with_an_external_buffer_file() {
    let dir = std::env::temp_dir().join(format!("shlight-mesh-gltf-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let buffer = gltf_buffer();
    std::fs::write(dir.join("my data.bin"), &buffer).unwrap();
    let path = dir.join("s.gltf");
    std::fs::write(&path, gltf_json(Some("my%20data.bin"), buffer.len())).unwrap();
    let m = load(&path);
    std::fs::remove_dir_all(&dir).unwrap();
    assert_two_squares(&m.unwrap());
}

#[test]
fn bad_gltf_files_are_errors() {
    let buffer = gltf_buffer();
    assert!(err("t.gltf", b"{\"asset\": 1}").contains("not a valid glTF file"));
    assert!(err("t.glb", &glb(&gltf_json(None, buffer.len()), &buffer[..50])).contains("holds"));
    let mut bad = buffer.clone();
    bad[96..98].copy_from_slice(&9u16.to_le_bytes());
    assert!(err("t.glb", &glb(&gltf_json(None, bad.len()), &bad)).contains("index 9 out of range"));
    let mut nan = buffer.clone();
    nan[4..8].copy_from_slice(&f32::NAN.to_le_bytes());
    assert!(err("t.glb", &glb(&gltf_json(None, nan.len()), &nan)).contains("non-finite"));
    assert!(err("t.gltf", gltf_json(Some("missing.bin"), 108).as_bytes()).contains("cannot read"));
}

fn bundled(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../meshes")
        .join(name)
}

#[test]
fn bundled_meshes_load_with_their_counts() {
    let bunny = load(&bundled("bunny.obj")).unwrap();
    assert_eq!((bunny.vertex_count(), bunny.triangle_count()), (1839, 3674));
    assert_eq!(bunny.report.degenerate_triangles, 0);
    let teapot = load(&bundled("teapot.obj")).unwrap();
    assert_eq!(teapot.vertex_count(), 792);
    assert_eq!(
        teapot.triangle_count() + teapot.report.degenerate_triangles,
        992
    );
}
