//! The `.shprt` file: per-vertex transfer vectors and how they were made
//! (docs/shprt.md).
//!
//! ```text
//! {"format":"shlight-prt","format_version":1,"lmax":4,...}\n     one line of JSON
//! f32 f32 f32 ...                                               little-endian transfer
//! ```
//!
//! The header is one line of JSON (no newline inside) ending in `\n`. The
//! data that follows is exactly `vertex_count * channels * (lmax+1)^2`
//! little-endian `f32`, vertex-major: all of vertex 0 (channel 0's
//! coefficients in SH index order `l(l+1)+m`, then channel 1's, ...), then
//! vertex 1, and so on, the vertices in the mesh's order after loading.

use std::path::Path;

use serde_json::{Value, json};
use shlight_core::sh::sh_count;

use crate::{FormatError, Result, header_line};

/// The `format` key's value.
pub const FORMAT: &str = "shlight-prt";
/// The layout version this build writes (and the newest it reads).
pub const FORMAT_VERSION: u64 = 1;
/// Longest header a reader accepts, in bytes.
pub const MAX_HEADER: usize = 1 << 20;

/// A `.shprt` file's content.
#[derive(Clone, Debug, PartialEq)]
pub struct ShprtFile {
    /// Highest SH degree.
    pub lmax: usize,
    /// 1 (grey albedo) or 3 (linear RGB).
    pub channels: usize,
    /// Vertices, in the mesh's order after loading.
    pub vertex_count: usize,
    /// `vertex_count * channels * (lmax+1)^2` coefficients, vertex-major,
    /// then channel, then SH index.
    pub transfer: Vec<f32>,
    /// `unshadowed`, `shadowed` or `interreflected`.
    pub mode: String,
    /// Directions in the shared set.
    pub samples: u64,
    /// Interreflection bounces (0 for the other modes).
    pub bounces: u32,
    /// Seed of the direction set.
    pub seed: u64,
    /// Constant linear RGB albedo, or `None` for per-vertex albedo (the
    /// mesh's colours).
    pub albedo: Option<[f32; 3]>,
    /// The baked mesh's content hash (shlight-mesh's `Mesh::content_hash`).
    pub mesh_hash: u64,
    /// The mesh as named on the command line (informational).
    pub mesh: String,
}

impl ShprtFile {
    /// The transfer vectors borrowed, as the renderer takes them.
    ///
    /// # Errors
    /// A channel count other than 1 or 3, or a length that does not fit
    /// the counts (a file read by [`ShprtFile::from_bytes`] always fits).
    pub fn view(
        &self,
    ) -> std::result::Result<shlight_baked::TransferView<'_>, shlight_baked::ShapeError> {
        shlight_baked::TransferView::new(
            self.lmax,
            self.channels,
            self.vertex_count,
            &self.transfer,
        )
    }

    /// Coefficients per vertex and channel, `(lmax+1)^2`.
    #[must_use]
    pub fn coeffs_per_channel(&self) -> usize {
        sh_count(self.lmax)
    }

    /// The transfer of vertex `v`, channel `c`.
    #[must_use]
    pub fn vertex(&self, v: usize, c: usize) -> &[f32] {
        let nc = self.coeffs_per_channel();
        &self.transfer[(v * self.channels + c) * nc..][..nc]
    }

    /// The header line's JSON object.
    #[must_use]
    pub fn header(&self) -> Value {
        json!({
            "format": FORMAT,
            "format_version": FORMAT_VERSION,
            "lmax": self.lmax,
            "vertex_count": self.vertex_count,
            "channels": self.channels,
            "mode": self.mode,
            "samples": self.samples,
            "bounces": self.bounces,
            "seed": self.seed,
            // Each f32 written as its shortest decimal (0.8, not 0.800000011920929).
            "albedo": self.albedo.map_or(json!("vertex"), |a| {
                json!(a.map(|x| x.to_string().parse::<f64>().unwrap_or(f64::NAN)))
            }),
            "mesh_hash": header_line::hash_text(self.mesh_hash),
            "mesh": self.mesh,
            "data": "f32 little-endian, vertex-major, then channel, then SH index l(l+1)+m",
        })
    }

    /// The whole file as bytes.
    #[must_use]
    pub fn to_bytes(&self) -> Vec<u8> {
        header_line::to_bytes(&self.header(), &self.transfer)
    }

    /// Writes the file atomically (a temporary file renamed into place).
    ///
    /// # Errors
    /// [`FormatError::Write`] naming the file.
    pub fn write(&self, path: &Path) -> Result<()> {
        let bytes = self.to_bytes();
        shlight_io::write_atomically(path, |w| w.write_all(&bytes))?;
        Ok(())
    }

    /// Reads a `.shprt` file.
    ///
    /// # Errors
    /// [`FormatError::Read`] when it cannot be read; [`FormatError::Invalid`]
    /// naming the file for a bad header or data of the wrong length.
    pub fn read(path: &Path) -> Result<Self> {
        let bytes = header_line::read_file(path)?;
        Self::from_bytes(&bytes, path)
    }

    /// Parses a file held in memory; `path` names it in errors.
    ///
    /// # Errors
    /// As [`ShprtFile::read`].
    pub fn from_bytes(bytes: &[u8], path: &Path) -> Result<Self> {
        let name = path.display().to_string();
        let bad = |message: String| FormatError::invalid(&name, message);
        let (header, data) = header_line::split(bytes, &name, FORMAT, ".shprt", MAX_HEADER)?;
        let uint = |key: &str| header_line::uint(&header, key, &name);
        let version = uint("format_version")?;
        if version == 0 || version > FORMAT_VERSION {
            return Err(bad(format!(
                "format_version {version} is not supported (this build reads 1..={FORMAT_VERSION})"
            )));
        }
        let lmax = uint("lmax")? as usize;
        let vertex_count = uint("vertex_count")? as usize;
        let channels = uint("channels")? as usize;
        if !(channels == 1 || channels == 3) {
            return Err(bad(format!("bad header (channels {channels}, not 1 or 3)")));
        }
        if lmax > 64 {
            return Err(bad(format!("bad header (lmax {lmax} is beyond 64)")));
        }
        let mode = header
            .get("mode")
            .and_then(Value::as_str)
            .ok_or_else(|| bad("bad header (\"mode\" is missing)".into()))?
            .to_string();
        let albedo = match header.get("albedo") {
            Some(Value::String(s)) if s == "vertex" => None,
            Some(Value::Array(a)) if a.len() == 3 && a.iter().all(Value::is_number) => {
                Some([0, 1, 2].map(|i| a[i].as_f64().unwrap_or(0.0) as f32))
            }
            _ => {
                return Err(bad(
                    "bad header (\"albedo\" is not [r, g, b] or \"vertex\")".into(),
                ));
            }
        };
        let mesh_hash = header_line::hash(&header, "mesh_hash", &name)?;
        let count = vertex_count
            .checked_mul(channels * sh_count(lmax))
            .filter(|c| c.checked_mul(4).is_some())
            .ok_or_else(|| bad("bad header (the sizes overflow)".into()))?;
        if data.len() < 4 * count {
            return Err(bad(format!(
                "truncated: {vertex_count} vertices x {channels} channels x {} coefficients need {} bytes of data, the file has {}",
                sh_count(lmax),
                4 * count,
                data.len()
            )));
        }
        if data.len() > 4 * count {
            return Err(bad(format!(
                "wrong length: {} bytes of data where the header says {}",
                data.len(),
                4 * count
            )));
        }
        let transfer = header_line::f32s(data);
        Ok(Self {
            lmax,
            channels,
            vertex_count,
            transfer,
            bounces: header.get("bounces").and_then(Value::as_u64).unwrap_or(0) as u32,
            samples: uint("samples")?,
            seed: uint("seed")?,
            mode,
            albedo,
            mesh_hash,
            mesh: header
                .get("mesh")
                .and_then(Value::as_str)
                .unwrap_or_default()
                .to_string(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> ShprtFile {
        ShprtFile {
            lmax: 1,
            channels: 3,
            vertex_count: 2,
            transfer: (0..24).map(|i| i as f32 * 0.5 - 3.0).collect(),
            mode: "interreflected".into(),
            samples: 1035,
            bounces: 2,
            seed: 9,
            albedo: Some([0.5, 0.25, 1.0]),
            mesh_hash: 0x0123_4567_89ab_cdef,
            mesh: "m.obj".into(),
        }
    }

    #[test]
    fn round_trips_and_the_layout_is_as_documented() {
        let f = sample();
        let bytes = f.to_bytes();
        let nl = bytes.iter().position(|&b| b == b'\n').unwrap();
        assert_eq!(bytes.len(), nl + 1 + 24 * 4);
        assert!(bytes[..nl].starts_with(b"{\""));
        // Vertex 1, channel 2 (blue), coefficient 3 is the last value.
        assert_eq!(
            &bytes[bytes.len() - 4..],
            &(23.0f32 * 0.5 - 3.0).to_le_bytes()
        );
        assert_eq!(f.vertex(1, 2)[3], 23.0 * 0.5 - 3.0);
        let header = String::from_utf8_lossy(&bytes[..nl]).into_owned();
        assert!(header.contains("\"albedo\":[0.5,0.25,1.0]"), "{header}");
        let back = ShprtFile::from_bytes(&bytes, Path::new("x.shprt")).unwrap();
        assert_eq!(back, f);
        let mut grey = sample();
        grey.albedo = None;
        assert_eq!(
            ShprtFile::from_bytes(&grey.to_bytes(), Path::new("x.shprt")).unwrap(),
            grey
        );
    }

    #[test]
    fn bad_files_are_errors_naming_the_file() {
        let bytes = sample().to_bytes();
        let err = |b: &[u8]| {
            ShprtFile::from_bytes(b, Path::new("x.shprt"))
                .unwrap_err()
                .to_string()
        };
        let e = err(&bytes[..bytes.len() - 1]);
        assert!(e.starts_with("x.shprt: truncated"), "{e}");
        let mut long = bytes.clone();
        long.push(0);
        assert!(err(&long).contains("wrong length"));
        assert!(err(b"{\"format\": 1}").contains("no header line"));
        assert!(err(b"nonsense\n").contains("bad header (not JSON"));
        let text =
            String::from_utf8_lossy(&bytes[..bytes.iter().position(|&b| b == b'\n').unwrap()])
                .into_owned();
        for (from, to, what) in [
            (
                "\"format_version\":1",
                "\"format_version\":7",
                "format_version 7",
            ),
            ("\"channels\":3", "\"channels\":2", "channels 2"),
            ("\"lmax\":1", "\"lmax\":\"one\"", "\"lmax\" is missing"),
            (
                "\"format\":\"shlight-prt\"",
                "\"format\":\"x\"",
                "\"format\" is not",
            ),
        ] {
            assert!(text.contains(from), "{text}");
            let e = err(format!("{}\n", text.replace(from, to)).as_bytes());
            assert!(e.contains(what), "{e}");
        }
        let e = ShprtFile::read(Path::new("/nonexistent/x.shprt")).unwrap_err();
        assert!(
            e.to_string()
                .starts_with("/nonexistent/x.shprt: cannot read")
        );
    }
}
