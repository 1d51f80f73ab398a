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
//!
//! Glossy transfer (`"mode":"glossy"`) is format version 2: the data is the
//! vertices' positions (`3 * vertex_count` `f32`), their normals (as many),
//! then `vertex_count * channels * (lmax+1)^4` matrix entries, vertex-major,
//! then channel, then row, then column; compressed by clustered PCA
//! (`"compression":"cpca:C,K"`), the cluster means, bases, each vertex's
//! cluster index and weights instead of the matrices. Diffuse files stay
//! version 1.
//!
//! Diffuse transfer of a scene with light of its own (punctual lights,
//! emissive materials) is format version 3: the header adds `static`
//! ([`StaticLight`]), and after the transfer come `3 * vertex_count`
//! little-endian `f32`, each vertex's static exit radiance (linear R, G, B),
//! so that the vertex leaves `T . L + S` under distant light `L`.

use std::path::Path;

use serde_json::{Value, json};
use shlight_core::sh::sh_count;

use crate::{FormatError, Result, VolumeLights, header_line};

/// The `format` key's value.
pub const FORMAT: &str = "shlight-prt";
/// The layout version this build writes for diffuse transfer vectors.
pub const FORMAT_VERSION: u64 = 1;
/// The layout version of glossy transfer matrices (and the newest this
/// build reads).
pub const GLOSSY_FORMAT_VERSION: u64 = 2;
/// The layout version of diffuse transfer with a static term per vertex
/// ([`StaticLight`]; the newest this build reads).
pub const STATIC_FORMAT_VERSION: u64 = 3;
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
    /// Rays per vertex: the directions of the shared set (the file's
    /// `samples`).
    pub rays_per_vertex: u64,
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
    /// For glossy transfer (`mode` `glossy`, format version 2): `transfer`
    /// holds a matrix per vertex and channel, `(lmax+1)^2` rows (the
    /// transferred radiance's coefficients) of `(lmax+1)^2` columns (the
    /// light's), and this what shading it needs besides.
    pub glossy: Option<GlossyData>,
    /// Diffuse transfer of a scene with light of its own (format version
    /// 3): each vertex's static exit radiance, added to `T . L`.
    pub static_light: Option<StaticLight>,
}

/// The light a scene's vertices leave whatever the distant light: the
/// direct light of its punctual lights, reflected by the vertex's albedo,
/// its emissive materials' emission, and both bounced as the transfer
/// bounces the distant light. A renderer shades vertex `v` as
/// `T_v . L + radiance[v]` per channel.
#[derive(Clone, Debug, PartialEq)]
pub struct StaticLight {
    /// Per vertex, linear RGB exit radiance (W sr^-1 m^-2 per channel).
    pub radiance: Vec<[f32; 3]>,
    /// The punctual lights it holds and their units (`None`: none).
    pub lights: Option<VolumeLights>,
    /// Whether it holds emissive materials' light.
    pub emission: bool,
}

/// What a glossy `.shprt` file holds besides its matrices.
#[derive(Clone, Debug, PartialEq)]
pub struct GlossyData {
    /// The BRDF, as `--brdf` names it (`phong:32`).
    pub brdf: String,
    /// The transport the matrices hold: `unshadowed`, `shadowed` or
    /// `interreflected` (with the file's `bounces`).
    pub transport: String,
    /// Each vertex's position, in the mesh's frame.
    pub positions: Vec<[f32; 3]>,
    /// Each vertex's unit normal.
    pub normals: Vec<[f32; 3]>,
    /// The matrices compressed by clustered PCA (`"compression":
    /// "cpca:C,K"`); the file's `transfer` is then empty.
    pub cpca: Option<CpcaData>,
}

/// Glossy matrices compressed by clustered PCA (Sloan, Hall, Hart & Snyder
/// 2003): vertex `v`'s matrix (all its channels, `dim` values) is
/// `means[c] + sum_k weights[v][k] bases[c][k]`, `c = cluster[v]`.
#[derive(Clone, Debug, PartialEq)]
pub struct CpcaData {
    /// Clusters `C`.
    pub clusters: usize,
    /// Basis vectors per cluster `K`.
    pub vectors: usize,
    /// `C x dim` means.
    pub means: Vec<f32>,
    /// `C x K x dim` basis vectors.
    pub bases: Vec<f32>,
    /// Each vertex's cluster, below `C`.
    pub cluster: Vec<u32>,
    /// `vertex_count x K` weights.
    pub weights: Vec<f32>,
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
        if let Some(g) = &self.glossy {
            return Err(shlight_baked::ShapeError(format!(
                "glossy transfer ({}) holds a matrix per vertex, not a transfer vector: \
                 it is shaded view by view (sampled toward a view direction or an eye)",
                g.brdf
            )));
        }
        shlight_baked::TransferView::new(
            self.lmax,
            self.channels,
            self.vertex_count,
            &self.transfer,
        )
    }

    /// A glossy file's matrices borrowed, as `shlight sample` and the
    /// renderer shade them (`None` for a diffuse file).
    ///
    /// # Errors
    /// Arrays that do not fit the counts (a file read by
    /// [`ShprtFile::from_bytes`] always fits).
    pub fn glossy_view(
        &self,
    ) -> std::result::Result<Option<shlight_baked::GlossyView<'_>>, shlight_baked::ShapeError> {
        use shlight_baked::{GlossyMatrices, GlossyView};
        use std::borrow::Cow;
        let Some(g) = &self.glossy else {
            return Ok(None);
        };
        let matrices = match &g.cpca {
            None => GlossyMatrices::Full(Cow::Borrowed(&self.transfer)),
            Some(z) => GlossyMatrices::Cpca {
                clusters: z.clusters,
                vectors: z.vectors,
                means: Cow::Borrowed(&z.means),
                bases: Cow::Borrowed(&z.bases),
                cluster: Cow::Borrowed(&z.cluster),
                weights: Cow::Borrowed(&z.weights),
            },
        };
        GlossyView::new(self.lmax, self.channels, self.vertex_count, matrices).map(Some)
    }

    /// Values per vertex and channel: `(lmax+1)^2`, or `(lmax+1)^4` for
    /// glossy matrices.
    #[must_use]
    pub fn coeffs_per_channel(&self) -> usize {
        let nc = sh_count(self.lmax);
        if self.glossy.is_some() { nc * nc } else { nc }
    }

    /// The transfer of vertex `v`, channel `c` (a glossy file's matrix,
    /// row by row; not for a compressed file, whose `transfer` is empty).
    #[must_use]
    pub fn vertex(&self, v: usize, c: usize) -> &[f32] {
        let nc = self.coeffs_per_channel();
        &self.transfer[(v * self.channels + c) * nc..][..nc]
    }

    /// The header line's JSON object.
    #[must_use]
    pub fn header(&self) -> Value {
        let mut header = json!({
            "format": FORMAT,
            "format_version": self.format_version(),
            "lmax": self.lmax,
            "vertex_count": self.vertex_count,
            "channels": self.channels,
            "mode": self.mode,
            "samples": self.rays_per_vertex,
            "bounces": self.bounces,
            "seed": self.seed,
            // Each f32 written as its shortest decimal (0.8, not 0.800000011920929).
            "albedo": self.albedo.map_or(json!("vertex"), |a| {
                json!(a.map(|x| x.to_string().parse::<f64>().unwrap_or(f64::NAN)))
            }),
            "mesh_hash": header_line::hash_text(self.mesh_hash),
            "mesh": self.mesh,
            "data": "f32 little-endian, vertex-major, then channel, then SH index l(l+1)+m",
        });
        if let Some(s) = &self.static_light {
            header["static"] = json!({
                "quantity": "exit radiance, linear RGB per vertex, added to T . L",
                "lights": s.lights.as_ref().map(|l| json!({
                    "units": l.units,
                    "point": l.point,
                    "spot": l.spot,
                    "directional": l.directional,
                })),
                "emission": s.emission,
            });
            header["data"] = json!(
                "f32 little-endian: transfer vertex-major, then channel, then SH index \
                 l(l+1)+m; then each vertex's static exit radiance [r, g, b]"
            );
        }
        if let Some(g) = &self.glossy {
            header["brdf"] = json!(g.brdf);
            header["transport"] = json!(g.transport);
            header["frame"] = json!("the mesh's");
            header["data"] = json!(
                "f32 little-endian: positions (x, y, z per vertex), normals (likewise), then \
                 matrices vertex-major, then channel, then row i (transferred radiance), then \
                 column j (light), T_i = sum_j M_ij L_j, SH index l(l+1)+m"
            );
            if let Some(z) = &g.cpca {
                header["compression"] = json!(format!("cpca:{},{}", z.clusters, z.vectors));
                header["data"] = json!(
                    "f32 little-endian: positions (x, y, z per vertex), normals (likewise), \
                     cluster means (C x dim), basis vectors (C x K x dim), each vertex's \
                     cluster index, each vertex's K weights; dim = channels x rows x columns \
                     of a vertex's matrices, as uncompressed"
                );
            }
        }
        header
    }

    /// The layout version the file is written in: 1 for diffuse transfer,
    /// 2 for glossy, 3 for diffuse transfer with a static term.
    #[must_use]
    pub fn format_version(&self) -> u64 {
        match (&self.glossy, &self.static_light) {
            (Some(_), _) => GLOSSY_FORMAT_VERSION,
            (None, Some(_)) => STATIC_FORMAT_VERSION,
            (None, None) => FORMAT_VERSION,
        }
    }

    /// The whole file as bytes.
    #[must_use]
    pub fn to_bytes(&self) -> Vec<u8> {
        match &self.glossy {
            None => match &self.static_light {
                None => header_line::to_bytes(&self.header(), &self.transfer),
                Some(s) => {
                    let mut data = self.transfer.clone();
                    data.extend(s.radiance.iter().flatten());
                    header_line::to_bytes(&self.header(), &data)
                }
            },
            Some(g) => {
                let mut data = Vec::with_capacity(6 * self.vertex_count + self.transfer.len());
                data.extend(g.positions.iter().flatten());
                data.extend(g.normals.iter().flatten());
                match &g.cpca {
                    None => data.extend(&self.transfer),
                    Some(z) => {
                        data.extend(&z.means);
                        data.extend(&z.bases);
                        data.extend(z.cluster.iter().map(|&c| c as f32));
                        data.extend(&z.weights);
                    }
                }
                header_line::to_bytes(&self.header(), &data)
            }
        }
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
        if version == 0 || version > STATIC_FORMAT_VERSION {
            return Err(bad(format!(
                "format_version {version} is not supported (this build reads 1..={STATIC_FORMAT_VERSION})"
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
        let glossy = (mode == "glossy") != (version == GLOSSY_FORMAT_VERSION);
        if glossy {
            return Err(bad(format!(
                "bad header (mode \"{mode}\" in format_version {version}: glossy transfer is version {GLOSSY_FORMAT_VERSION}, diffuse versions {FORMAT_VERSION} and {STATIC_FORMAT_VERSION})"
            )));
        }
        let glossy = version == GLOSSY_FORMAT_VERSION;
        let lights = static_lights(&header, version, &bad)?;
        let nc = sh_count(lmax);
        let per_channel = if glossy { nc * nc } else { nc };
        // Glossy files' positions and normals before the matrices; a static
        // term's radiance after the transfer.
        let vectors = match (glossy, &lights) {
            (true, _) => 6 * vertex_count,
            (false, Some(_)) => 3 * vertex_count,
            (false, None) => 0,
        };
        // A compressed glossy file: its clusters and vectors per cluster.
        let compression = match header.get("compression") {
            None => None,
            Some(v) if glossy => {
                let text = v.as_str().unwrap_or_default();
                let parsed = text
                    .strip_prefix("cpca:")
                    .and_then(|r| r.split_once(','))
                    .and_then(|(c, k)| Some((c.parse::<usize>().ok()?, k.parse::<usize>().ok()?)));
                match parsed {
                    Some((c, k)) if c >= 1 && k <= channels * per_channel => Some((c, k)),
                    _ => {
                        return Err(bad(format!(
                            "bad header (\"compression\" {v} is not cpca:C,K with C >= 1 and K at most {})",
                            channels * per_channel
                        )));
                    }
                }
            }
            Some(_) => {
                return Err(bad("bad header (\"compression\" in a diffuse file)".into()));
            }
        };
        let dim = channels * per_channel;
        let count = match compression {
            None => vertex_count.checked_mul(dim),
            Some((c, k)) => c
                .checked_mul(k + 1)
                .and_then(|x| x.checked_mul(dim))
                .and_then(|x| x.checked_add(vertex_count.checked_mul(k + 1)?)),
        }
        .and_then(|c| c.checked_add(vectors))
        .filter(|c| c.checked_mul(4).is_some())
        .ok_or_else(|| bad("bad header (the sizes overflow)".into()))?;
        if data.len() < 4 * count {
            return Err(bad(format!(
                "truncated: {vertex_count} vertices x {channels} channels x {per_channel} {} need {} bytes of data, the file has {}",
                match (glossy, compression) {
                    (false, _) if lights.is_some() => "coefficients (with the static radiance)",
                    (false, _) => "coefficients",
                    (true, None) => "matrix entries (with positions and normals)",
                    (true, Some(_)) => "matrix entries, compressed (with positions and normals)",
                },
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
        let mut transfer = header_line::f32s(data);
        let static_light = lights.map(|(lights, emission)| {
            let radiance = transfer
                .split_off(vertex_count * dim)
                .chunks_exact(3)
                .map(|c| [c[0], c[1], c[2]])
                .collect();
            StaticLight {
                radiance,
                lights,
                emission,
            }
        });
        let glossy = if glossy {
            let text = |key: &str| header_line::text(&header, key, &name);
            let (brdf, transport) = (text("brdf")?, text("transport")?);
            let rest = transfer.split_off(vectors);
            let triples = |v: &[f32]| -> Vec<[f32; 3]> {
                v.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect()
            };
            let (positions, normals) = transfer.split_at(3 * vertex_count);
            let mut data = GlossyData {
                brdf,
                transport,
                positions: triples(positions),
                normals: triples(normals),
                cpca: None,
            };
            transfer = rest;
            if let Some((c, k)) = compression {
                let mut rest = std::mem::take(&mut transfer);
                let weights = rest.split_off(c * (k + 1) * dim + vertex_count);
                let indices = rest.split_off(c * (k + 1) * dim);
                let bases = rest.split_off(c * dim);
                let cluster = indices
                    .iter()
                    .map(|&x| {
                        if x >= 0.0 && x < c as f32 && x.fract() == 0.0 {
                            Ok(x as u32)
                        } else {
                            Err(bad(format!(
                                "a vertex's cluster index {x} is not one of the {c} clusters"
                            )))
                        }
                    })
                    .collect::<Result<Vec<u32>>>()?;
                data.cpca = Some(CpcaData {
                    clusters: c,
                    vectors: k,
                    means: rest,
                    bases,
                    cluster,
                    weights,
                });
            }
            Some(data)
        } else {
            None
        };
        Ok(Self {
            glossy,
            static_light,
            lmax,
            channels,
            vertex_count,
            transfer,
            bounces: header.get("bounces").and_then(Value::as_u64).unwrap_or(0) as u32,
            rays_per_vertex: uint("samples")?,
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

/// A version 3 header's `static` key: its punctual lights and whether it
/// holds emission (`None` for versions 1 and 2, which have none).
fn static_lights(
    header: &Value,
    version: u64,
    bad: &dyn Fn(String) -> FormatError,
) -> Result<Option<(Option<VolumeLights>, bool)>> {
    let found = header.get("static");
    if (version == STATIC_FORMAT_VERSION) != found.is_some() {
        return Err(bad(format!(
            "bad header (format_version {version} {} \"static\": diffuse transfer with a static term is version {STATIC_FORMAT_VERSION})",
            if found.is_some() { "with" } else { "without" }
        )));
    }
    let Some(s) = found else {
        return Ok(None);
    };
    let shape = || {
        bad("bad header (\"static\" is not {\"lights\": null or {\"units\": text, \"point\", \"spot\", \"directional\": counts}, \"emission\": true or false})".into())
    };
    let emission = s
        .get("emission")
        .and_then(Value::as_bool)
        .ok_or_else(shape)?;
    let lights = match s.get("lights") {
        None | Some(Value::Null) => None,
        Some(l) => {
            let count = |kind: &str| l.get(kind).and_then(Value::as_u64);
            let units = l.get("units").and_then(Value::as_str);
            match (units, count("point"), count("spot"), count("directional")) {
                (Some(units), Some(point), Some(spot), Some(directional)) => Some(VolumeLights {
                    units: units.to_string(),
                    point,
                    spot,
                    directional,
                }),
                _ => return Err(shape()),
            }
        }
    };
    Ok(Some((lights, emission)))
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
            rays_per_vertex: 1035,
            bounces: 2,
            seed: 9,
            albedo: Some([0.5, 0.25, 1.0]),
            mesh_hash: 0x0123_4567_89ab_cdef,
            mesh: "m.obj".into(),
            glossy: None,
            static_light: None,
        }
    }

    fn glossy_sample() -> ShprtFile {
        ShprtFile {
            lmax: 1,
            channels: 1,
            vertex_count: 2,
            transfer: (0..32).map(|i| i as f32 * 0.25 - 1.0).collect(),
            mode: "glossy".into(),
            bounces: 0,
            albedo: Some([0.8; 3]),
            static_light: None,
            glossy: Some(GlossyData {
                brdf: "phong:32".into(),
                transport: "shadowed".into(),
                positions: vec![[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]],
                normals: vec![[0.0, 1.0, 0.0], [1.0, 0.0, 0.0]],
                cpca: None,
            }),
            ..sample()
        }
    }

    #[test]
    fn glossy_files_are_version_2_and_round_trip() {
        let f = glossy_sample();
        let bytes = f.to_bytes();
        let nl = bytes.iter().position(|&b| b == b'\n').unwrap();
        // Positions, normals, then 2 vertices x 4 x 4 entries.
        assert_eq!(bytes.len(), nl + 1 + (12 + 32) * 4);
        let header = String::from_utf8_lossy(&bytes[..nl]).into_owned();
        assert!(header.contains("\"format_version\":2"), "{header}");
        assert!(header.contains("\"brdf\":\"phong:32\""), "{header}");
        // The first value after the header is vertex 0's x; the last, the
        // last matrix entry.
        assert_eq!(&bytes[nl + 1..nl + 5], &1.0f32.to_le_bytes());
        assert_eq!(
            &bytes[bytes.len() - 4..],
            &(31.0f32 * 0.25 - 1.0).to_le_bytes()
        );
        assert_eq!(f.vertex(1, 0)[15], 31.0 * 0.25 - 1.0);
        let back = ShprtFile::from_bytes(&bytes, Path::new("g.shprt")).unwrap();
        assert_eq!(back, f);
        // Not a transfer vector: the renderer's view refuses it.
        assert!(f.view().unwrap_err().to_string().contains("glossy"));
        // A version 2 header that is not glossy, or a version 1 that is,
        // is refused; so is a glossy file without its BRDF.
        let e = |b: Vec<u8>| {
            ShprtFile::from_bytes(&b, Path::new("g.shprt"))
                .unwrap_err()
                .to_string()
        };
        let swap = |from: &str, to: &str| {
            let mut b = header.replace(from, to).into_bytes();
            b.extend_from_slice(&bytes[nl..]);
            b
        };
        assert!(
            e(swap("\"format_version\":2", "\"format_version\":1"))
                .contains("glossy transfer is version 2")
        );
        assert!(
            e(swap("\"mode\":\"glossy\"", "\"mode\":\"shadowed\"")).contains("mode \"shadowed\"")
        );
        assert!(e(swap("\"brdf\"", "\"bdrf\"")).contains("\"brdf\""));
        assert!(e(bytes[..bytes.len() - 4].to_vec()).contains("truncated"));
        // Compressed: 2 clusters of 1 vector over the 16 entries.
        let mut z = glossy_sample();
        z.transfer.clear();
        z.glossy.as_mut().unwrap().cpca = Some(CpcaData {
            clusters: 2,
            vectors: 1,
            means: (0..32).map(|i| i as f32).collect(),
            bases: (0..32).map(|i| -(i as f32)).collect(),
            cluster: vec![1, 0],
            weights: vec![0.5, -0.25],
        });
        let zb = z.to_bytes();
        let znl = zb.iter().position(|&b| b == b'\n').unwrap();
        assert_eq!(zb.len(), znl + 1 + (12 + 64 + 2 + 2) * 4);
        assert_eq!(ShprtFile::from_bytes(&zb, Path::new("z.shprt")).unwrap(), z);
        let zheader = String::from_utf8_lossy(&zb[..znl]).into_owned();
        assert!(
            zheader.contains("\"compression\":\"cpca:2,1\""),
            "{zheader}"
        );
        // A cluster index out of range, and a compression beyond the
        // matrices' size, are refused.
        let mut bad_index = zb.clone();
        let at = znl + 1 + (12 + 64) * 4;
        bad_index[at..at + 4].copy_from_slice(&2.0f32.to_le_bytes());
        assert!(e(bad_index).contains("cluster index 2"));
        let mut big = zheader.replace("cpca:2,1", "cpca:2,17").into_bytes();
        big.extend_from_slice(&zb[znl..]);
        assert!(e(big).contains("K at most 16"));
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
    fn a_static_term_is_version_3_after_the_transfer_and_round_trips() {
        let mut f = sample();
        f.static_light = Some(StaticLight {
            radiance: vec![[1.0, 2.0, 3.0], [4.0, 5.0, 6.5]],
            lights: Some(VolumeLights {
                units: "blender".into(),
                point: 2,
                spot: 0,
                directional: 1,
            }),
            emission: false,
        });
        let bytes = f.to_bytes();
        let nl = bytes.iter().position(|&b| b == b'\n').unwrap();
        // The transfer's 24 values, then 2 x 3 of static radiance, the last
        // vertex 1's blue.
        assert_eq!(bytes.len(), nl + 1 + (24 + 6) * 4);
        assert_eq!(&bytes[bytes.len() - 4..], &6.5f32.to_le_bytes());
        assert_eq!(
            &bytes[nl + 1 + 23 * 4..nl + 1 + 24 * 4],
            &(23.0f32 * 0.5 - 3.0).to_le_bytes()
        );
        let header: Value = serde_json::from_slice(&bytes[..nl]).unwrap();
        assert_eq!(header["format_version"], 3);
        assert_eq!(
            header["static"]["lights"],
            json!({"units": "blender", "point": 2, "spot": 0, "directional": 1})
        );
        assert_eq!(header["static"]["emission"], false);
        assert_eq!(
            ShprtFile::from_bytes(&bytes, Path::new("x.shprt")).unwrap(),
            f
        );
        // Without the static term the file is version 1, as before.
        assert!(sample().to_bytes().starts_with(b"{"));
        let plain: Value = serde_json::from_slice(
            &sample().to_bytes()[..sample()
                .to_bytes()
                .iter()
                .position(|&b| b == b'\n')
                .unwrap()],
        )
        .unwrap();
        assert_eq!(plain["format_version"], 1);
        // A version 3 header without "static", or a version 1 with it, is refused.
        let text = String::from_utf8_lossy(&bytes[..nl]).into_owned();
        let err = |h: String| {
            let mut b = h.into_bytes();
            b.extend_from_slice(&bytes[nl..]);
            ShprtFile::from_bytes(&b, Path::new("x.shprt"))
                .unwrap_err()
                .to_string()
        };
        let e = err(text.replace("\"format_version\":3", "\"format_version\":1"));
        assert!(e.contains("format_version 1 with \"static\""), "{e}");
        let e = err(text.replace("\"emission\":false", "\"emission\":7"));
        assert!(e.contains("\"static\" is not"), "{e}");
        let e = err(text.replace("\"format_version\":3", "\"format_version\":4"));
        assert!(e.contains("format_version 4 is not supported"), "{e}");
        let mut short = bytes.clone();
        short.truncate(bytes.len() - 4);
        let e = ShprtFile::from_bytes(&short, Path::new("x.shprt"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("truncated") && e.contains("static radiance"),
            "{e}"
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
