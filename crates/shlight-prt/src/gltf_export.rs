//! The mesh with its transfer as a glTF 2.0 file (`.gltf` with an embedded
//! buffer, or binary `.glb`), for engines that load meshes and read custom
//! vertex attributes.
//!
//! One node, one mesh, one triangle primitive with `POSITION`, `NORMAL`,
//! `COLOR_0` (when the mesh has colours), `indices` (`UNSIGNED_INT`), and the
//! transfer in custom attributes `_SH_TRANSFER_0`, `_SH_TRANSFER_1`, ...:
//! each a `VEC4` of `FLOAT`. A vertex's `channels * (lmax+1)^2` transfer
//! values, in the `.shprt` order (channel-major: channel 0's coefficients in
//! SH index order, then channel 1's, ...), are cut into fours: attribute `k`
//! holds values `4k .. 4k+3`, the last one padded with zeros. lmax 4 grey
//! (25 values) gives 7 attributes; lmax 4 RGB (75) gives 19. The `.shprt`
//! header goes in the mesh's `extras.shlight_prt`, so a loader finds lmax,
//! channels and the mode there.

use std::path::Path;

use base64::Engine as _;
use serde_json::{Value, json};
use shlight_mesh::Mesh;

use shlight_format::ShprtFile;

use crate::PrtError;

const FLOAT: u32 = 5126;
const UNSIGNED_INT: u32 = 5125;
const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;

/// Number of `_SH_TRANSFER_k` attributes for `values` floats per vertex.
#[must_use]
pub fn attribute_count(values: usize) -> usize {
    values.div_ceil(4)
}

/// Writes `mesh` and `prt` to `path`: binary glTF for `.glb`, JSON with a
/// base64 buffer otherwise. Atomic.
///
/// Glossy transfer is refused: a matrix per vertex, `(lmax+1)^4` floats
/// per channel (625 at lmax 4, 157 `VEC4` attributes), is beyond what
/// glTF loaders take as vertex attributes (WebGL guarantees 16), and an
/// engine would need shlight's view-dependent shading besides.
///
/// # Errors
/// [`PrtError::Mismatch`] when the transfer has another vertex count than
/// the mesh, or is glossy; [`PrtError::Write`] when writing fails.
pub fn write_gltf(path: &Path, mesh: &Mesh, prt: &ShprtFile) -> Result<(), PrtError> {
    if let Some(g) = &prt.glossy {
        return Err(PrtError::Mismatch(format!(
            "{}: glTF cannot carry glossy transfer ({}): a {}x{} matrix per vertex{} is \
             beyond what glTF vertex attributes hold; write a .shprt file, or bake the \
             diffuse transfer (without --mode glossy) for glTF",
            path.display(),
            g.brdf,
            prt.coeffs_per_channel().isqrt(),
            prt.coeffs_per_channel().isqrt(),
            if prt.channels == 3 {
                " and channel"
            } else {
                ""
            }
        )));
    }
    if prt.vertex_count != mesh.vertex_count() {
        return Err(PrtError::Mismatch(format!(
            "{}: the transfer has {} vertices, the mesh {}",
            path.display(),
            prt.vertex_count,
            mesh.vertex_count()
        )));
    }
    let binary = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("glb"));
    let (mut doc, bin) = document(mesh, prt);
    let bytes = if binary {
        glb(&doc, &bin)
    } else {
        doc["buffers"][0]["uri"] = json!(format!(
            "data:application/octet-stream;base64,{}",
            base64::engine::general_purpose::STANDARD.encode(&bin)
        ));
        serde_json::to_vec(&doc).expect("JSON values serialise")
    };
    shlight_io::write_atomically(path, |w| w.write_all(&bytes))?;
    Ok(())
}

/// The glTF JSON (without the buffer's URI) and the buffer.
fn document(mesh: &Mesh, prt: &ShprtFile) -> (Value, Vec<u8>) {
    let n = mesh.vertex_count();
    let mut bin = Vec::new();
    let mut views = Vec::new();
    let mut accessors = Vec::new();
    let mut attributes = serde_json::Map::new();
    let mut push = |bin: &mut Vec<u8>, data: &[u8], target: u32, accessor: Value| {
        let offset = bin.len();
        bin.extend_from_slice(data);
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
        views.push(
            json!({"buffer": 0, "byteOffset": offset, "byteLength": data.len(), "target": target}),
        );
        let mut a = accessor;
        a["bufferView"] = json!(views.len() - 1);
        accessors.push(a);
        accessors.len() - 1
    };
    let floats =
        |v: &mut dyn Iterator<Item = f32>| v.flat_map(f32::to_le_bytes).collect::<Vec<u8>>();

    let (lo, hi) = mesh.bounds();
    let pos = floats(&mut mesh.positions.iter().flat_map(|p| p.to_array()));
    let i = push(
        &mut bin,
        &pos,
        ARRAY_BUFFER,
        json!({"componentType": FLOAT, "count": n, "type": "VEC3",
        "min": lo.to_array(), "max": hi.to_array()}),
    );
    attributes.insert("POSITION".into(), json!(i));
    let nor = floats(&mut mesh.normals.iter().flat_map(|p| p.to_array()));
    let i = push(
        &mut bin,
        &nor,
        ARRAY_BUFFER,
        json!({"componentType": FLOAT, "count": n, "type": "VEC3"}),
    );
    attributes.insert("NORMAL".into(), json!(i));
    if let Some(colors) = &mesh.colors {
        let col = floats(&mut colors.iter().flat_map(|p| p.to_array()));
        let i = push(
            &mut bin,
            &col,
            ARRAY_BUFFER,
            json!({"componentType": FLOAT, "count": n, "type": "VEC3"}),
        );
        attributes.insert("COLOR_0".into(), json!(i));
    }
    let per_vertex = prt.channels * prt.coeffs_per_channel();
    for k in 0..attribute_count(per_vertex) {
        let data = floats(&mut (0..n).flat_map(|v| {
            let row = &prt.transfer[v * per_vertex..][..per_vertex];
            (4 * k..4 * k + 4).map(move |f| row.get(f).copied().unwrap_or(0.0))
        }));
        let i = push(
            &mut bin,
            &data,
            ARRAY_BUFFER,
            json!({"componentType": FLOAT, "count": n, "type": "VEC4"}),
        );
        attributes.insert(format!("_SH_TRANSFER_{k}"), json!(i));
    }
    let idx: Vec<u8> = mesh
        .triangles
        .iter()
        .flatten()
        .flat_map(|i| i.to_le_bytes())
        .collect();
    let indices = push(
        &mut bin,
        &idx,
        ELEMENT_ARRAY_BUFFER,
        json!({"componentType": UNSIGNED_INT,
        "count": 3 * mesh.triangle_count(), "type": "SCALAR"}),
    );
    let doc = json!({
        "asset": {"version": "2.0", "generator": concat!("shlight ", env!("CARGO_PKG_VERSION"))},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "name": prt.mesh}],
        "meshes": [{
            "primitives": [{"attributes": attributes, "indices": indices, "mode": 4}],
            "extras": {"shlight_prt": prt.header()},
        }],
        "buffers": [{"byteLength": bin.len()}],
        "bufferViews": views,
        "accessors": accessors,
    });
    (doc, bin)
}

/// A GLB container: the header, the JSON chunk (space-padded) and the BIN
/// chunk (zero-padded).
fn glb(doc: &Value, bin: &[u8]) -> Vec<u8> {
    let mut json = serde_json::to_vec(doc).expect("JSON values serialise");
    json.resize(json.len().next_multiple_of(4), b' ');
    let mut bin = bin.to_vec();
    bin.resize(bin.len().next_multiple_of(4), 0);
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut out = Vec::with_capacity(total);
    out.extend(b"glTF");
    out.extend(2u32.to_le_bytes());
    out.extend((total as u32).to_le_bytes());
    out.extend((json.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(json);
    out.extend((bin.len() as u32).to_le_bytes());
    out.extend(b"BIN\0");
    out.extend(bin);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use gltf::Semantic;
    use shlight_mesh::generate;

    fn fake(mesh: &Mesh, channels: usize) -> ShprtFile {
        let per = channels * 25;
        ShprtFile {
            lmax: 4,
            channels,
            vertex_count: mesh.vertex_count(),
            transfer: (0..mesh.vertex_count() * per)
                .map(|i| i as f32 * 0.25)
                .collect(),
            mode: "shadowed".into(),
            rays_per_vertex: 1035,
            bounces: 0,
            seed: 1,
            albedo: Some([0.8; 3]),
            mesh_hash: mesh.content_hash(),
            mesh: "torus".into(),
            glossy: None,
            static_light: None,
        }
    }

    /// Writes, reads back with the `gltf` crate, and checks every value.
    fn round_trip(name: &str, channels: usize) {
        let mesh = generate::torus(1.0, 0.3, 8, 6);
        let prt = fake(&mesh, channels);
        let dir =
            std::env::temp_dir().join(format!("shlight-prt-gltf-{}-{name}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join(name);
        write_gltf(&path, &mesh, &prt).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();

        let gltf = gltf::Gltf::from_slice(&bytes).unwrap();
        let buffer = match gltf.blob.clone() {
            Some(blob) => blob,
            None => {
                let uri = gltf.document.buffers().next().unwrap().source();
                let gltf::buffer::Source::Uri(uri) = uri else {
                    panic!("no URI")
                };
                let data = uri.split_once(";base64,").unwrap().1;
                base64::engine::general_purpose::STANDARD
                    .decode(data)
                    .unwrap()
            }
        };
        let get = |_: gltf::Buffer| Some(buffer.as_slice());
        let mesh_doc = gltf.document.meshes().next().unwrap();
        let prim = mesh_doc.primitives().next().unwrap();
        let reader = prim.reader(get);
        let positions: Vec<[f32; 3]> = reader.read_positions().unwrap().collect();
        assert_eq!(positions.len(), mesh.vertex_count());
        assert_eq!(positions[5], mesh.positions[5].to_array());
        let indices: Vec<u32> = reader.read_indices().unwrap().into_u32().collect();
        assert_eq!(indices[..3], mesh.triangles[0]);
        let per = channels * 25;
        let count = attribute_count(per);
        assert_eq!(count, if channels == 1 { 7 } else { 19 });
        let mut rebuilt = vec![vec![0.0f32; 4 * count]; mesh.vertex_count()];
        for k in 0..count {
            let accessor = prim
                .get(&Semantic::Extras(format!("SH_TRANSFER_{k}")))
                .unwrap();
            assert_eq!(accessor.dimensions(), gltf::accessor::Dimensions::Vec4);
            let values: Vec<[f32; 4]> = gltf::accessor::Iter::new(accessor, get).unwrap().collect();
            for (v, x) in values.iter().enumerate() {
                rebuilt[v][4 * k..4 * k + 4].copy_from_slice(x);
            }
        }
        for (v, row) in rebuilt.iter().enumerate() {
            assert_eq!(&row[..per], &prt.transfer[v * per..][..per]);
            assert!(row[per..].iter().all(|&x| x == 0.0));
        }
        let extras = mesh_doc.extras().as_ref().unwrap().get();
        let extras: Value = serde_json::from_str(extras).unwrap();
        assert_eq!(extras["shlight_prt"]["lmax"], 4);
        assert_eq!(extras["shlight_prt"]["channels"], channels);
    }

    #[test]
    fn gltf_and_glb_read_back_with_every_transfer_value() {
        round_trip("t.gltf", 1);
        round_trip("t.glb", 3);
    }

    #[test]
    fn a_transfer_for_another_mesh_is_refused() {
        let mesh = generate::torus(1.0, 0.3, 8, 6);
        let prt = fake(&generate::uv_sphere(1.0, 8, 4), 1);
        let e = write_gltf(Path::new("x.glb"), &mesh, &prt).unwrap_err();
        assert!(e.to_string().contains("x.glb: the transfer has"), "{e}");
    }
}
