//! The one BIN chunk of the GLB being written, and the GLB's framing
//! (glTF 2.0 specification, "GLB File Format Specification").

use serde_json::{Map, Value, json};

use super::json_lists::push;

/// Where every piece goes: each 8-byte aligned (at least the 4 bytes
/// glTF asks of accessors, and 8 for a KTX2 file's half floats).
const ALIGN: usize = 8;

/// The BIN chunk's bytes, which are buffer 0, and the other buffers.
#[derive(Default)]
pub(super) struct BinChunk {
    data: Vec<u8>,
    /// Buffers after buffer 0 (`EXT_meshopt_compression` fallbacks).
    others: Vec<Value>,
}

impl BinChunk {
    /// Appends `bytes`, giving their offset.
    pub fn push(&mut self, bytes: &[u8]) -> usize {
        let offset = self.data.len().next_multiple_of(ALIGN);
        self.data.resize(offset, 0);
        self.data.extend_from_slice(bytes);
        offset
    }

    /// The buffers besides the merged one: `buffers[0]` stands for it.
    pub fn set_buffers(&mut self, buffers: Vec<Value>) {
        self.others = buffers.into_iter().skip(1).collect();
    }

    /// Appends `bytes` and a buffer view of them to `root`, giving the
    /// view's index.
    pub fn push_view(&mut self, root: &mut Map<String, Value>, bytes: &[u8]) -> usize {
        let offset = self.push(bytes);
        push(
            root,
            "bufferViews",
            json!({"buffer": 0, "byteOffset": offset, "byteLength": bytes.len()}),
        )
    }

    /// Appends `values` as a float `VEC2` vertex accessor (its own buffer
    /// view, with its bounds), giving the accessor's index.
    pub fn push_vec2_accessor(
        &mut self,
        root: &mut Map<String, Value>,
        values: &[[f32; 2]],
    ) -> usize {
        let bytes: Vec<u8> = values
            .iter()
            .flatten()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        let view = self.push_view(root, &bytes);
        root["bufferViews"][view]["target"] = 34962.into(); // ARRAY_BUFFER
        let bound = |pick: fn(f32, f32) -> f32, start: f32| {
            values
                .iter()
                .fold([start; 2], |b, v| [pick(b[0], v[0]), pick(b[1], v[1])])
        };
        let (min, max) = (
            bound(f32::min, f32::INFINITY),
            bound(f32::max, f32::NEG_INFINITY),
        );
        let mut accessor = json!({
            "bufferView": view,
            "componentType": 5126, // FLOAT
            "count": values.len(),
            "type": "VEC2",
        });
        if min.iter().chain(&max).all(|v| v.is_finite()) {
            accessor["min"] = json!(min);
            accessor["max"] = json!(max);
        }
        push(root, "accessors", accessor)
    }

    /// The GLB: the header, `root` as the JSON chunk (padded with spaces)
    /// with the buffers in place, the BIN chunk (padded with zeros); an
    /// error past GLB's 4 GiB.
    pub fn into_glb(mut self, root: &mut Map<String, Value>) -> Result<Vec<u8>, String> {
        if self.data.is_empty() {
            self.data.resize(ALIGN, 0); // a buffer holds at least one byte
        }
        self.data.resize(self.data.len().next_multiple_of(4), 0);
        let mut buffers = vec![json!({"byteLength": self.data.len()})];
        buffers.append(&mut self.others);
        root.insert("buffers".into(), Value::Array(buffers));
        let mut json = serde_json::to_vec(root).expect("JSON values serialize");
        json.resize(json.len().next_multiple_of(4), b' ');

        let total = 12 + 8 + json.len() + 8 + self.data.len();
        if u32::try_from(total).is_err() {
            return Err(format!(
                "the GLB would take {total} bytes, more than the format's 4 GiB"
            ));
        }
        let mut glb = Vec::with_capacity(total);
        glb.extend(b"glTF");
        glb.extend(2u32.to_le_bytes());
        glb.extend((total as u32).to_le_bytes());
        glb.extend((json.len() as u32).to_le_bytes());
        glb.extend(b"JSON");
        glb.extend(&json);
        glb.extend((self.data.len() as u32).to_le_bytes());
        glb.extend(b"BIN\0");
        glb.extend(&self.data);
        Ok(glb)
    }
}
