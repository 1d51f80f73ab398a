//! What a file shlight writes holds, as a readable table (`shlight show`):
//! [`describe`] tells the file's kind from its content (a signature, a
//! header line, the keys of its JSON; the name only tells apart textures
//! of one shape) and returns a [`Description`]: a coefficient file's own
//! table ([`CoeffFile::to_table`]), or any other file's [`Header`].
//!
//! Each kind's facts are read in the module of its family: `baked`
//! (`.shprt`, `.shvol` and its JSON form, three.js's grid), `light` (the
//! engine exports of one light, and the Ramamoorthi-Hanrahan table),
//! `gltf` (glTF and GLB: a light, PRT transfer, or both), `code` (shader
//! and C snippets), `texture` (KTX2 and KTX 1.1), `samples` (`shlight
//! sample`'s files and `shlight compare`'s rows) and `picture` (images and
//! SVG plots).

mod baked;
mod code;
mod gltf;
mod header;
mod light;
mod picture;
mod samples;
mod texture;

use std::path::Path;

use serde_json::Value;

pub use self::header::Header;
use crate::{CoeffFile, FormatError, Result};

/// What `shlight show` prints of a file.
#[derive(Clone, Debug)]
pub enum Description {
    /// A shlight coefficient file: its coefficients, as
    /// [`CoeffFile::to_table`] prints them.
    Coefficients(Box<CoeffFile>),
    /// Any other file shlight writes: what it is and its header's facts.
    Header(Header),
}

impl Description {
    /// The readable table: [`CoeffFile::to_table`] or [`Header::to_table`].
    #[must_use]
    pub fn to_table(&self) -> String {
        match self {
            Description::Coefficients(file) => file.to_table(),
            Description::Header(header) => header.to_table(),
        }
    }
}

/// What `shlight show` says of files it does not recognise.
const NOT_SHLIGHTS: &str = "not a file shlight writes (a coefficient file, an engine export \
     of a light, a code snippet, a .shprt or .shvol file or their exports, glTF, KTX2, KTX, \
     shlight sample's or compare's output, or an image)";

/// Describes the file at `path` ([`describe_bytes`] of its content).
///
/// # Errors
/// [`FormatError::Read`] when it cannot be read; as [`describe_bytes`].
pub fn describe(path: &Path) -> Result<Description> {
    let bytes = std::fs::read(path).map_err(|source| FormatError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    describe_bytes(&bytes, &path.display().to_string())
}

/// Describes a file held in memory; `name` names it in errors and tells
/// apart the textures a volume's shader snippet reads (`NAME.sh.ktx2`,
/// `NAME.probes.ktx2`, `NAME.moments.ktx2`), which share their shapes.
///
/// The kind is read from the content: the GLB, KTX2, KTX 1.1 and image
/// signatures; a header line of JSON naming `shlight-prt` or
/// `shlight-volume` (the binary files); else the text: JSON by its keys
/// (`format`, three.js's `metadata`, glTF's `asset`, ...), Filament's
/// `(r, g, b);` rows, the Ramamoorthi-Hanrahan table's and the snippets'
/// first lines, CSV by its header, SVG by its root element.
///
/// # Errors
/// [`FormatError::Invalid`] naming the file: what it is not (an empty or
/// unknown file), or what is wrong with a file of a kind it recognises (a
/// truncated `.shvol`, a glTF whose JSON is broken, ...).
pub fn describe_bytes(bytes: &[u8], name: &str) -> Result<Description> {
    if bytes.is_empty() {
        return Err(FormatError::invalid(
            name,
            format!("an empty file, {NOT_SHLIGHTS}"),
        ));
    }
    if let Some(header) = texture::describe(bytes, name)? {
        return Ok(Description::Header(header));
    }
    if crate::export::gltf::is_glb(bytes) {
        let json = crate::export::gltf::glb_json(bytes, name)?;
        return gltf::describe(&json, name, true).map(Description::Header);
    }
    if let Some(header) = picture::describe_image(bytes, name)? {
        return Ok(Description::Header(header));
    }
    if let Some(header) = baked::describe_binary(bytes, name)? {
        return Ok(Description::Header(header));
    }
    let Ok(text) = std::str::from_utf8(bytes) else {
        return Err(FormatError::invalid(
            name,
            format!("binary, but {NOT_SHLIGHTS}"),
        ));
    };
    describe_text(text, name)
}

/// A file of text: JSON by its keys, else by its first line.
fn describe_text(text: &str, name: &str) -> Result<Description> {
    let start = text.trim_start();
    if start.starts_with('{') || start.starts_with('[') {
        let v: Value = serde_json::from_str(text)
            .map_err(|e| FormatError::invalid(name, format!("not valid JSON ({e})")))?;
        return describe_json(&v, text, name);
    }
    if start.starts_with('(') {
        return light::describe_filament(text, name).map(Description::Header);
    }
    if let Some(header) = light::describe_table(text) {
        return Ok(Description::Header(header));
    }
    if let Some(header) = code::describe(text) {
        return Ok(Description::Header(header));
    }
    if let Some(header) = samples::describe_csv(text, name)? {
        return Ok(Description::Header(header));
    }
    if let Some(header) = picture::describe_svg(text) {
        return Ok(Description::Header(header));
    }
    Err(FormatError::invalid(
        name,
        format!("text, but {NOT_SHLIGHTS}"),
    ))
}

/// A JSON document, by its keys.
fn describe_json(v: &Value, text: &str, name: &str) -> Result<Description> {
    let format = v.get("format").and_then(Value::as_str);
    if format == Some(crate::coeff_file::FORMAT) {
        let file = CoeffFile::from_json_str(text, name)?;
        return Ok(Description::Coefficients(Box::new(file)));
    }
    let header = if format == Some(crate::shvol::FORMAT) {
        baked::describe_volume_json(v, name)?
    } else if format == Some(crate::SAMPLES_FORMAT) {
        samples::describe_samples(v, name)?
    } else if format == Some(crate::export::unity::FORMAT_TAG)
        || v.get("SphericalHarmonicsL2").is_some()
    {
        light::describe_unity(v, name)?
    } else if v.get("asset").is_some() {
        gltf::describe(v, name, false)?
    } else if v.pointer("/metadata/type").and_then(Value::as_str)
        == Some(crate::threejs_volume::DOCUMENT_TYPE)
    {
        baked::describe_threejs_grid(v, name)?
    } else if crate::export::threejs::is_light_probe_json(v) {
        light::describe_threejs(v, name)?
    } else if v.get("points").is_some() && v.get("normals").is_some() {
        samples::describe_points_json(text, name)?
    } else if let Some(header) = samples::describe_compare(v) {
        header
    } else {
        return Err(FormatError::invalid(
            name,
            format!("JSON, but {NOT_SHLIGHTS}"),
        ));
    };
    Ok(Description::Header(header))
}

/// The number at `key` of `v` as a whole number, or an error naming the
/// file, what it was read as and the key.
fn uint(v: &Value, key: &str, what: &str, name: &str) -> Result<u64> {
    v.get(key).and_then(Value::as_u64).ok_or_else(|| {
        FormatError::invalid(
            name,
            format!("{what}, but \"{key}\" is missing or not a whole number"),
        )
    })
}

/// `v` as text: strings as they are, anything else as compact JSON.
fn plain(v: &Value) -> String {
    match v {
        Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;
    use shlight_baked::ProbeVisibility;
    use shlight_core::sh::{Frame, ShCoeffs};

    use super::*;
    use crate::threejs_volume::{Precision, threejs_grid};
    use crate::{
        ExportFormat, GlossyData, Quantity, SampledValues, ShprtFile, ShvolFile, bevy_volume,
        cube_map_ktx2, export, filament_ktx1,
    };

    fn header(d: Description) -> Header {
        match d {
            Description::Header(h) => h,
            Description::Coefficients(_) => panic!("a coefficient file"),
        }
    }

    /// A relightable 3 x 1 x 2 volume of lmax 1, probe 4 invalid, probe 1
    /// moved, with 2x2 distance maps.
    fn volume() -> ShvolFile {
        let (probes, nc) = (6, 4);
        let mut offsets = vec![0.0f32; 3 * probes];
        offsets[3] = 0.125;
        ShvolFile {
            lmax: 1,
            resolution: [3, 1, 2],
            bounds: ([-1.0, 0.0, -2.0], [2.0, 0.5, 2.0]),
            frame: "y-up".into(),
            valid: (0..probes).map(|i| i != 4).collect(),
            radiance: (0..probes * 3 * nc).map(|i| i as f32 * 0.125).collect(),
            emitted: Some(vec![0.0; probes * 3 * nc]),
            transfer: Some(vec![0.5; probes * 3 * nc * nc]),
            offsets: Some(offsets),
            visibility: Some(ProbeVisibility {
                size: 2,
                max_distance: 1.5,
                moments: vec![0.25; probes * 8],
            }),
            rays_per_probe: 300,
            bounces: 3,
            seed: 11,
            scene: "room.obj".into(),
            scene_hash: 0x0123_4567_89ab_cdef,
            environment: "sky.exr".into(),
            generator: "shlight test".into(),
            lights: Some(crate::VolumeLights {
                units: "blender".into(),
                point: 2,
                spot: 1,
                directional: 0,
            }),
        }
    }

    #[test]
    fn a_volume_its_json_form_and_its_exports_give_its_grid() {
        let v = volume();
        let binary = header(describe_bytes(&v.to_bytes(), "v.shvol").unwrap());
        assert_eq!(
            binary.kind,
            "shlight irradiance volume (.shvol, format_version 2)"
        );
        let mut text = serde_json::to_string(&v.to_json()).unwrap();
        text.push('\n');
        let json = header(describe_bytes(text.as_bytes(), "v.json").unwrap());
        assert!(json.kind.contains("JSON form"), "{}", json.kind);
        for h in [&binary, &json] {
            assert_eq!(
                h.get("lmax"),
                Some("1 (4 coefficients per probe and channel)")
            );
            assert_eq!(
                h.get("grid"),
                Some("3 x 1 x 2 = 6 probes at the cells' centres, x fastest")
            );
            assert_eq!(h.get("invalid"), Some("1 probes (inside geometry)"));
            assert_eq!(h.get("relocated"), Some("1 probes moved out of geometry"));
            assert_eq!(h.get("samples"), Some("300 rays per probe"));
            assert_eq!(h.get("bounces"), Some("3"));
            assert_eq!(h.get("seed"), Some("11"));
            assert_eq!(h.get("scene"), Some("room.obj (fnv1a64:0123456789abcdef)"));
            assert_eq!(h.get("environment"), Some("sky.exr"));
            assert_eq!(
                h.get("lights"),
                Some(
                    "2 point, 1 spot, 0 directional (punctual, in the static light); intensities divided by 683 (blender)"
                )
            );
            assert!(h.get("holds").unwrap().contains("relightable"));
            assert!(
                h.get("visibility")
                    .unwrap()
                    .starts_with("a 2x2 octahedral map of distances per probe, max distance 1.5")
            );
            assert_eq!(
                h.get("bounds"),
                Some("min [-1.0,0.0,-2.0], max [2.0,0.5,2.0]")
            );
        }
        let grid = threejs_grid(&v, Precision::F32).unwrap();
        let three = header(describe_bytes(grid.text.as_bytes(), "grid.json").unwrap());
        assert_eq!(
            three.get("grid"),
            Some("3 x 1 x 2 = 6 probes at the cells' centres")
        );
        assert!(
            three
                .get("atlas")
                .unwrap()
                .starts_with("3 x 1 x 28 RGBAFormat texels of FloatType"),
            "{three:?}"
        );
        assert_eq!(three.get("seed"), Some("11"));
        let bevy =
            header(describe_bytes(&bevy_volume::bevy_ktx2(&v, "shlight test"), "v.ktx2").unwrap());
        assert!(bevy.kind.contains("Bevy IrradianceVolume"), "{}", bevy.kind);
        assert_eq!(bevy.get("size"), Some("3 x 2 x 6 (3D)"));
        assert_eq!(bevy.get("writer"), Some("shlight test"));
        assert!(bevy.get("holds").unwrap().starts_with("a 3 x 1 x 2 grid"));
        // Cut short: the reader's error, naming the file.
        let bytes = v.to_bytes();
        let e = describe_bytes(&bytes[..bytes.len() - 4], "cut.shvol").unwrap_err();
        assert!(e.to_string().starts_with("cut.shvol: truncated"), "{e}");
    }

    #[test]
    fn transfer_files_give_lmax_vertices_and_their_bake() {
        let diffuse = ShprtFile {
            lmax: 2,
            channels: 3,
            vertex_count: 5,
            transfer: vec![0.25; 5 * 3 * 9],
            mode: "interreflected".into(),
            rays_per_vertex: 99,
            bounces: 2,
            seed: 4,
            albedo: None,
            mesh_hash: 0xfeed,
            mesh: "m.obj".into(),
            glossy: None,
            static_light: None,
        };
        let h = header(describe_bytes(&diffuse.to_bytes(), "m.shprt").unwrap());
        assert_eq!(
            h.kind,
            "shlight PRT transfer (.shprt, format_version 1): diffuse"
        );
        for (name, want) in [
            ("lmax", "2"),
            ("vertices", "5"),
            ("channels", "3 (linear RGB)"),
            ("mode", "interreflected"),
            ("albedo", "per vertex (the mesh's colours)"),
            ("samples", "99 directions"),
            ("bounces", "2"),
            ("seed", "4"),
            ("mesh", "m.obj (fnv1a64:000000000000feed)"),
        ] {
            assert_eq!(h.get(name), Some(want), "{name}");
        }
        assert_eq!(h.get("static"), None);
        let lit = ShprtFile {
            static_light: Some(crate::StaticLight {
                radiance: vec![[0.5; 3]; 5],
                lights: Some(crate::VolumeLights {
                    units: "blender".into(),
                    point: 2,
                    spot: 1,
                    directional: 0,
                }),
                emission: true,
            }),
            ..diffuse.clone()
        };
        let h = header(describe_bytes(&lit.to_bytes(), "lit.shprt").unwrap());
        assert_eq!(
            h.kind,
            "shlight PRT transfer (.shprt, format_version 3): diffuse"
        );
        assert_eq!(
            h.get("static"),
            Some(
                "exit radiance per vertex added to T . L: 2 point, 1 spot, 0 directional \
                 lights (blender units) and emissive materials"
            )
        );
        let glossy = ShprtFile {
            channels: 1,
            transfer: vec![0.5; 5 * 81],
            mode: "glossy".into(),
            albedo: Some([0.5, 0.25, 1.0]),
            static_light: None,
            glossy: Some(GlossyData {
                brdf: "ggx:0.25,0.04".into(),
                transport: "shadowed".into(),
                positions: vec![[0.0; 3]; 5],
                normals: vec![[0.0, 1.0, 0.0]; 5],
                cpca: None,
            }),
            ..diffuse
        };
        let h = header(describe_bytes(&glossy.to_bytes(), "g.shprt").unwrap());
        assert!(h.kind.ends_with("format_version 2): glossy"), "{}", h.kind);
        assert!(h.get("holds").unwrap().starts_with("a 9x9 transfer matrix"));
        assert_eq!(h.get("brdf"), Some("ggx:0.25,0.04"));
        assert_eq!(h.get("mode"), Some("glossy, shadowed transport"));
        assert_eq!(h.get("albedo"), Some("[0.5,0.25,1.0]"));
    }

    #[test]
    fn coefficient_files_keep_their_table_and_exports_read_back() {
        let rows: Vec<DVec3> = (0..9)
            .map(|i| DVec3::new(1.0 + f64::from(i), 0.5, -0.25))
            .collect();
        let file = CoeffFile::new(
            ShCoeffs::from_vec(rows).unwrap(),
            Frame::YUp,
            Quantity::Radiance,
        );
        let text = file.to_json_string();
        let d = describe_bytes(text.as_bytes(), "c.json").unwrap();
        assert!(matches!(d, Description::Coefficients(_)));
        assert_eq!(d.to_table(), file.to_table());
        // three.js holds radiance; its rows read back as written.
        let three = export(&file, ExportFormat::Threejs).unwrap();
        let h = header(describe_bytes(three.text.as_bytes(), "p.json").unwrap());
        assert!(
            h.rows.contains("radiance, lmax 2 (9 coefficients)"),
            "{}",
            h.rows
        );
        let row = format!(
            "{:4} {:3} {:13.6e} {:13.6e} {:13.6e}\n",
            2, 2, 9.0, 0.5, -0.25
        );
        assert!(h.rows.ends_with(&row), "{}", h.rows);
        // Filament holds irradiance: band 2 times pi / 4.
        let filament = export(&file, ExportFormat::Filament).unwrap();
        let h = header(describe_bytes(filament.text.as_bytes(), "sh.txt").unwrap());
        let want = format!("{:13.6e}", 9.0 * std::f64::consts::FRAC_PI_4);
        assert!(h.rows.contains(&format!("   2   2 {want}")), "{}", h.rows);
        for (format, kind) in [
            (ExportFormat::Wgsl, "WGSL code"),
            (ExportFormat::Glsl, "GLSL code"),
            (ExportFormat::Hlsl, "HLSL code"),
            (ExportFormat::C, "C code"),
            (ExportFormat::Txt, "Ramamoorthi-Hanrahan table"),
            (ExportFormat::Unity, "Unity SphericalHarmonicsL2"),
        ] {
            let out = export(&file, format).unwrap();
            let h = header(describe_bytes(out.text.as_bytes(), "x").unwrap());
            assert!(h.kind.starts_with(kind), "{format:?}: {}", h.kind);
        }
    }

    #[test]
    fn cubes_give_their_faces_and_mips() {
        let levels: Vec<[Vec<[f32; 3]>; 6]> = (0..3)
            .map(|k| std::array::from_fn(|_| vec![[1.0, 0.5, 0.25]; (8 >> k) * (8 >> k)]))
            .collect();
        let h = header(describe_bytes(&cube_map_ktx2(8, &levels, "me"), "c.ktx2").unwrap());
        assert!(
            h.kind.starts_with("KTX2: a cube map with mips"),
            "{}",
            h.kind
        );
        assert_eq!(h.get("faces"), Some("6"));
        assert_eq!(h.get("levels"), Some("3"));
        assert_eq!(h.get("writer"), Some("me"));
        assert!(h.get("holds").unwrap().contains("3 mips, 8x8 down to 2x2"));
        let h = header(describe_bytes(&filament_ktx1(8, &levels), "c.ktx").unwrap());
        assert!(h.kind.starts_with("KTX 1.1: Filament's"), "{}", h.kind);
        assert_eq!(h.get("levels"), Some("3 mips, 8x8 down to 2x2"));
        let bytes = filament_ktx1(8, &levels);
        let e = describe_bytes(&bytes[..bytes.len() - 1], "cut.ktx").unwrap_err();
        assert!(
            e.to_string()
                .starts_with("cut.ktx: a truncated KTX 1.1 file"),
            "{e}"
        );
    }

    #[test]
    fn samples_give_their_count_and_what_they_say() {
        let s = SampledValues {
            quantity: "irradiance",
            values: vec![[1.0, 2.0, 3.0]; 4],
            about: serde_json::json!({"lookup": "trilinear", "provenance": {"seed": 8}}),
        };
        let h = header(describe_bytes(s.to_json_text().as_bytes(), "s.json").unwrap());
        assert_eq!(h.get("holds"), Some("4 [r, g, b] values of irradiance"));
        assert_eq!(h.get("lookup"), Some("trilinear"));
        assert_eq!(h.get("provenance seed"), Some("8"));
        let h = header(describe_bytes(s.to_csv().as_bytes(), "s.csv").unwrap());
        assert!(h.get("holds").unwrap().starts_with("4 [r, g, b] values"));
        let e = describe_bytes(b"r,g,b\n1,2\n", "s.csv").unwrap_err();
        assert!(e.to_string().contains("line 2 is not three numbers"), "{e}");
    }

    /// Every prefix of a file of each binary kind gives a table or an
    /// error, never a panic (a header's counts are not trusted).
    #[test]
    fn every_prefix_gives_a_table_or_an_error() {
        let v = volume();
        let levels: Vec<[Vec<[f32; 3]>; 6]> = (0..2)
            .map(|k| std::array::from_fn(|_| vec![[1.0; 3]; (2 >> k) * (2 >> k)]))
            .collect();
        let png = shlight_io::encode_png_rgba8("p.png", 2, 2, &[9; 16]).unwrap();
        let png_header = header(describe_bytes(&png, "p.png").unwrap());
        assert_eq!(png_header.get("size"), Some("2 x 2"));
        assert_eq!(png_header.get("channels"), Some("R, G, B, A (8-bit)"));
        for (name, bytes) in [
            ("v.shvol", v.to_bytes()),
            ("v.ktx2", bevy_volume::bevy_ktx2(&v, "w")),
            ("c.ktx2", cube_map_ktx2(2, &levels, "w")),
            ("c.ktx", filament_ktx1(2, &levels)),
            ("p.png", png),
        ] {
            for n in 0..bytes.len() {
                let _ = describe_bytes(&bytes[..n], name);
            }
        }
    }

    #[test]
    fn other_files_are_errors_saying_what_they_are_not() {
        for (bytes, want) in [
            (&b""[..], "x: an empty file, not a file shlight writes"),
            (b"plain words\n", "x: text, but not a file shlight writes"),
            (b"\xff\xfe\x00", "x: binary, but not a file shlight writes"),
            (b"[1, 2]", "x: JSON, but not a file shlight writes"),
        ] {
            let e = describe_bytes(bytes, "x").unwrap_err().to_string();
            assert!(e.starts_with(want), "{e}");
        }
    }
}
