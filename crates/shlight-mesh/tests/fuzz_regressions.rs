//! Every input that once made a mesh loader crash, hang or run out of
//! memory, or panic inside a parser (found by the fuzz targets in fuzz/ or
//! while writing the limits they test), read through the loader a user
//! calls with the default limits (MTL files through `parse_mtl_bytes`,
//! what the OBJ loader parses each `mtllib` with): each must give the
//! clean error listed here, naming the file.
//!
//! The inputs live in `tests/fuzz_regressions/<target>/`, one folder per
//! fuzz target (`fuzz/run.sh` also feeds them to the fuzzer as seeds). A
//! new input needs a line in [`EXPECTED`]: the test fails on a file it
//! does not know.

use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::Duration;

use shlight_mesh::{MeshFormat, load_bytes, parse_mtl_bytes};

/// (fuzz target folder, file, what the error must say), with what the
/// file once did.
const EXPECTED: &[(&str, &str, &str)] = &[
    // Allocated room for the header's 10^17 vertices: an abort.
    (
        "off",
        "huge-vertex-count.off",
        "the mesh has 99999999999999999 vertices, more than the limit of 67108864",
    ),
    // A face of 2^64-1 corners: `1 + n` wrapped and the slice panicked.
    (
        "off",
        "face-corner-count-overflows.off",
        "line 6: face 0 has 18446744073709551615 corners and lists 3",
    ),
    // An element of 2^64-1 rows without properties: looped for ever.
    // Skipped now, so the rest of the file reads.
    ("ply", "empty-element-huge-count.ply", ""),
    // A node that is its own grandparent: unbounded recursion, a stack
    // overflow.
    (
        "gltf",
        "node-cycle.gltf",
        "node 0 appears twice in the scene's hierarchy",
    ),
    // 64 levels of nodes whose two children are the same node: 2^64 mesh
    // instances, a hang.
    (
        "gltf",
        "node-shared-children.gltf",
        "node 64 appears twice in the scene's hierarchy",
    ),
    // A sparse POSITION accessor (no buffer needed) of 4e9 vertices: a
    // 48 GB allocation, an abort.
    (
        "gltf",
        "sparse-huge-count.gltf",
        "the mesh has 4000000000 vertices, more than the limit of 67108864",
    ),
    // With overflow checks (the fuzz build), tobj's `vt * 2 + 1` on a
    // relative texture index before the first one overflowed and panicked
    // (a release build wraps and refuses it); either way an error now.
    ("obj", "negative-texcoord-index.obj", "not a valid OBJ file"),
    // A GLB header whose length is below the header's own 12 bytes: the
    // gltf crate's `length - 12` overflowed (with overflow checks).
    (
        "gltf",
        "glb-length-below-header.glb",
        "not a valid glTF file",
    ),
    // POSITION names an accessor that does not exist: the gltf crate's
    // validation indexed past its accessor list and panicked (in any build).
    // Checked before the crate's validation now.
    (
        "gltf",
        "position-accessor-missing.gltf",
        "mesh 0 primitive 0: POSITION names accessor 9, which does not exist",
    ),
    // Float indices: the gltf crate's index reader hit `unreachable!()`.
    // shlight's accessor reader refuses them.
    (
        "gltf",
        "float-indices.gltf",
        "indices: accessor 3 holds indices as FLOAT, not unsigned integers",
    ),
    // COLOR_0 of signed bytes: the gltf crate's colour reader hit
    // `unreachable!()`. shlight's reader refuses the component type.
    (
        "gltf",
        "signed-byte-colours.gltf",
        "COLOR_0 holds BYTE; glTF allows FLOAT, or normalized UNSIGNED_BYTE or UNSIGNED_SHORT",
    ),
    // A colour of two values: tobj's `try_into::<[f32; 3]>().unwrap()`
    // panicked (in any build; the guard made it "the MTL reader failed").
    (
        "mtl",
        "colour-of-two-values.mtl",
        "not a valid MTL file: line 2: Kd needs 3 values, has 2",
    ),
];

/// Longer than any of these files takes (each is refused from its
/// header, in microseconds), short enough that a hang fails quickly.
const TIME_LIMIT: Duration = Duration::from_secs(20);

fn dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz_regressions")
}

fn format(target: &str) -> MeshFormat {
    match target {
        "obj" => MeshFormat::Obj,
        "ply" => MeshFormat::Ply,
        "off" => MeshFormat::Off,
        "gltf" => MeshFormat::Gltf,
        other => panic!("no mesh fuzz target {other}"),
    }
}

#[test]
fn every_regression_input_is_listed() {
    let mut found = Vec::new();
    for target in std::fs::read_dir(dir()).unwrap() {
        let target = target.unwrap();
        for file in std::fs::read_dir(target.path()).unwrap() {
            found.push((
                target.file_name().into_string().unwrap(),
                file.unwrap().file_name().into_string().unwrap(),
            ));
        }
    }
    found.sort();
    let mut listed: Vec<(String, String)> = EXPECTED
        .iter()
        .map(|(t, f, _)| ((*t).to_string(), (*f).to_string()))
        .collect();
    listed.sort();
    assert_eq!(found, listed);
}

#[test]
fn every_regression_input_reads_cleanly() {
    for &(target, file, expected) in EXPECTED {
        let path = dir().join(target).join(file);
        let bytes = std::fs::read(&path).unwrap();
        let name = PathBuf::from(file);
        let (send, receive) = mpsc::channel();
        std::thread::spawn(move || {
            let result = if target == "mtl" {
                parse_mtl_bytes(&name, &bytes).map(|m| m.len())
            } else {
                load_bytes(&name, format(target), &bytes).map(|m| m.triangle_count())
            };
            let result = result.map_err(|e| e.to_string());
            let _ = send.send(result);
        });
        let result = receive
            .recv_timeout(TIME_LIMIT)
            .unwrap_or_else(|_| panic!("{file}: no answer within {TIME_LIMIT:?}"));
        match (result, expected) {
            (Ok(count), "") => assert!(count > 0, "{file}"),
            (Ok(_), _) => panic!("{file}: read, expected the error \"{expected}\""),
            (Err(e), _) => {
                assert!(e.starts_with(&format!("{file}: ")), "{file}: {e}");
                assert!(!expected.is_empty() && e.contains(expected), "{file}: {e}");
            }
        }
    }
}
