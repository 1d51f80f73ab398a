//! Loading meshes from files, by extension.
//!
//! Each format keeps the file's vertex order (documented per format: OBJ
//! below, [`ply`], [`off`], [`gltf_file`]); that order is the order of the
//! per-vertex records of a `.shprt` file baked from the mesh.

pub(crate) mod gltf_file;
mod mtl;
mod off;
mod ply;

pub use mtl::{MtlMaterial, parse_mtl_bytes};

use std::panic::{self, AssertUnwindSafe};
use std::path::Path;

use glam::Vec3;

use crate::{LoadOptions, Mesh, MeshError, Scene};

/// The mesh file formats shlight reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeshFormat {
    /// Wavefront OBJ (`.obj`): every object and group, polygons triangulated.
    Obj,
    /// Stanford PLY (`.ply`), ASCII or binary little-endian.
    Ply,
    /// Object File Format (`.off`), with optional colours or normals.
    Off,
    /// glTF 2.0 (`.gltf`, `.glb`): every triangle primitive of the scene.
    Gltf,
}

const EXPECTED: &str = ".obj, .ply, .off, .gltf or .glb";

impl MeshFormat {
    /// The format's usual name: `OBJ`, `PLY`, `OFF` or `glTF`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Obj => "OBJ",
            Self::Ply => "PLY",
            Self::Off => "OFF",
            Self::Gltf => "glTF",
        }
    }

    /// The format a file name's extension names (case-insensitive).
    #[must_use]
    pub fn from_path(path: &Path) -> Option<Self> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "obj" => Some(Self::Obj),
            "ply" => Some(Self::Ply),
            "off" => Some(Self::Off),
            "gltf" | "glb" => Some(Self::Gltf),
            _ => None,
        }
    }
}

/// Loads and validates a mesh file, choosing the format by extension,
/// under the default [`LoadOptions`].
///
/// # Errors
/// An unreadable file, an unknown extension, a parse error, a mesh
/// [`Mesh::new`] rejects, or one beyond the limits
/// ([`MeshError::TooLarge`]); every message starts with the path.
pub fn load(path: &Path) -> Result<Mesh, MeshError> {
    load_with(path, &LoadOptions::default())
}

/// [`load`] under the given limits.
///
/// # Errors
/// As [`load`].
pub fn load_with(path: &Path, options: &LoadOptions) -> Result<Mesh, MeshError> {
    let format = MeshFormat::from_path(path).ok_or_else(|| MeshError::UnknownFormat {
        path: path.to_path_buf(),
        expected: EXPECTED,
    })?;
    let bytes = std::fs::read(path).map_err(|source| MeshError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    load_bytes_with(path, format, &bytes, options)
}

/// Parses and validates a mesh held in memory, under the default
/// [`LoadOptions`]; `path` names it in errors (and, for glTF, locates
/// external buffer files).
///
/// # Errors
/// As [`load`], less the file reading.
pub fn load_bytes(path: &Path, format: MeshFormat, bytes: &[u8]) -> Result<Mesh, MeshError> {
    load_bytes_with(path, format, bytes, &LoadOptions::default())
}

/// [`load_bytes`] under the given limits.
///
/// A parser that panics on a malformed file is caught and reported as
/// [`MeshError::Parse`].
///
/// # Errors
/// As [`load_bytes`].
pub fn load_bytes_with(
    path: &Path,
    format: MeshFormat,
    bytes: &[u8],
    options: &LoadOptions,
) -> Result<Mesh, MeshError> {
    let read = || match format {
        MeshFormat::Obj => obj(path, bytes, options),
        MeshFormat::Ply => ply::read(path, bytes, options),
        MeshFormat::Off => off::read(path, bytes, options),
        MeshFormat::Gltf => gltf_file::read(path, bytes, options),
    };
    caught(path, format.name(), read)
}

/// Loads a glTF 2.0 file (`.gltf` or `.glb`) as a [`Scene`]: its unique
/// primitives, their instances, materials with decoded textures, and
/// punctual lights, under `options` (see the `gltf_file` module
/// documentation for what is read and refused).
/// [`Scene::flatten`] gives what [`load_with`] returns for the file, less
/// the rule that a file giving no albedo has no colours.
///
/// # Errors
/// An unreadable file or one without a `.gltf` / `.glb` extension, and
/// everything [`load_scene_bytes`] refuses.
pub fn load_scene(path: &Path, options: &LoadOptions) -> Result<Scene, MeshError> {
    if MeshFormat::from_path(path) != Some(MeshFormat::Gltf) {
        return Err(MeshError::UnknownFormat {
            path: path.to_path_buf(),
            expected: ".gltf or .glb (scenes are read from glTF files)",
        });
    }
    let bytes = std::fs::read(path).map_err(|source| MeshError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    load_scene_bytes(path, &bytes, options)
}

/// [`load_scene`] on glTF JSON or GLB bytes held in memory (told apart by
/// the GLB magic); `path` names the file in errors and locates external
/// buffers and images (relative to its directory).
///
/// # Errors
/// A file that is not valid glTF 2.0, one that requires an extension
/// shlight does not read (named), broken accessors or buffers, a
/// non-finite or singular node transform (named), an invalid light
/// (named), a texture that cannot be read or decoded (naming it and its
/// file), and counts beyond the limits ([`MeshError::TooLarge`],
/// [`MeshError::TextureTooLarge`]); every message starts with the path.
pub fn load_scene_bytes(
    path: &Path,
    bytes: &[u8],
    options: &LoadOptions,
) -> Result<Scene, MeshError> {
    caught(path, "glTF", || gltf_file::read_scene(path, bytes, options))
}

/// `read`, with a parser's panic on a malformed file (tobj and gltf panic
/// on some, where overflow checks are on) given as an error naming the
/// file and the reader (`format`: `OBJ`, `MTL`, ...), not a crash.
fn caught<T>(
    path: &Path,
    format: &str,
    read: impl FnOnce() -> Result<T, MeshError>,
) -> Result<T, MeshError> {
    panic::catch_unwind(AssertUnwindSafe(read)).unwrap_or_else(|payload| {
        let message = payload
            .downcast_ref::<&str>()
            .map(|s| (*s).to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "unknown panic".into());
        Err(MeshError::Parse {
            path: path.to_path_buf(),
            message: format!("the {format} reader failed: {message}"),
        })
    })
}

/// OBJ through `tobj`: positions and normals are unified to one index per
/// vertex (`single_index`), so vertices appear in the order tobj first meets
/// each distinct (position, normal) pair; objects are concatenated in file
/// order. Normals are used only when every object has them. tobj reads
/// the whole file first (its memory grows with the file's size); the
/// limits are checked on what it found.
///
/// Materials: the `mtllib` files named by the OBJ are read from its
/// directory (parsed as [`parse_mtl_bytes`] does); an object's material gives its vertices albedo `Kd` and
/// emitted radiance `Ke`. Without any material (or with a missing `mtllib`,
/// which tobj reports and shlight then ignores) the mesh has no colours, as
/// before; objects without a material get white albedo when others have one.
fn obj(path: &Path, bytes: &[u8], limits: &LoadOptions) -> Result<Mesh, MeshError> {
    let options = tobj::LoadOptions {
        single_index: true,
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
    };
    let dir = path.parent().unwrap_or(Path::new(".")).to_path_buf();
    // What mtl::check found wrong in a library, for the error below.
    let bad_mtl = std::cell::RefCell::new(None);
    let (models, materials) = tobj::load_obj_buf(
        &mut std::io::Cursor::new(bytes),
        &options,
        |name| match std::fs::read(dir.join(name)) {
            Ok(b) => match mtl::check(&b) {
                Ok(()) => mtl::parse(&b),
                Err(e) => {
                    *bad_mtl.borrow_mut() = Some(format!("{}: {e}", name.display()));
                    Err(tobj::LoadError::MaterialParseError)
                }
            },
            Err(_) => Ok(Default::default()),
        },
    )
    .map_err(|e| MeshError::Parse {
        path: path.to_path_buf(),
        message: format!("not a valid OBJ file: {e}"),
    })?;
    let materials = materials.map_err(|e| MeshError::Parse {
        path: path.to_path_buf(),
        message: format!(
            "not a valid MTL file: {}",
            bad_mtl.take().unwrap_or_else(|| e.to_string())
        ),
    })?;
    limits.check_vertices(
        path,
        models.iter().map(|m| m.mesh.positions.len() / 3).sum(),
    )?;
    limits.check_triangles(path, models.iter().map(|m| m.mesh.indices.len() / 3).sum())?;
    let all_normals = models
        .iter()
        .all(|m| m.mesh.normals.len() == m.mesh.positions.len());
    let any_material = models.iter().any(|m| m.mesh.material_id.is_some()) && !materials.is_empty();
    let (mut positions, mut normals, mut triangles) = (Vec::new(), Vec::new(), Vec::new());
    let (mut colors, mut emission) = (Vec::new(), Vec::new());
    for model in &models {
        let base = positions.len() as u32;
        let m = &model.mesh;
        positions.extend(
            m.positions
                .chunks_exact(3)
                .map(|p| Vec3::new(p[0], p[1], p[2])),
        );
        if all_normals {
            normals.extend(
                m.normals
                    .chunks_exact(3)
                    .map(|n| Vec3::new(n[0], n[1], n[2])),
            );
        }
        triangles.extend(
            m.indices
                .chunks_exact(3)
                .map(|t| [t[0] + base, t[1] + base, t[2] + base]),
        );
        if any_material {
            let material = m.material_id.and_then(|i| materials.get(i));
            let kd = material
                .and_then(|mat| mat.diffuse)
                .map_or(Vec3::ONE, Vec3::from_array);
            let ke = material
                .and_then(|mat| mat.emissive)
                .map_or(Vec3::ZERO, Vec3::from_array);
            let n = m.positions.len() / 3;
            colors.extend(std::iter::repeat_n(kd, n));
            emission.extend(std::iter::repeat_n(ke, n));
        }
    }
    let mesh = Mesh::new(
        path,
        positions,
        triangles,
        all_normals.then_some(normals),
        any_material.then_some(colors),
    )?;
    if any_material {
        mesh.with_emission(path, emission)
    } else {
        Ok(mesh)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn obj_quad_with_and_without_normals() {
        let src = b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
        let m = load_bytes(Path::new("q.obj"), MeshFormat::Obj, src).unwrap();
        assert_eq!((m.vertex_count(), m.triangle_count()), (4, 2));
        assert!((m.surface_area() - 1.0).abs() < 1e-12);
        assert!(m.normals.iter().all(|n| *n == Vec3::Z));
        let src = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 1 0 0\nf 1//1 2//1 3//1\n";
        let m = load_bytes(Path::new("t.obj"), MeshFormat::Obj, src).unwrap();
        assert!(m.normals.iter().all(|n| *n == Vec3::X));
    }

    #[test]
    fn obj_materials_give_albedo_and_emission() {
        let dir = std::env::temp_dir().join(format!("shlight-mtl-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(
            dir.join("m.mtl"),
            "newmtl red\nKd 0.8 0.1 0.1\nnewmtl lamp\nKd 0 0 0\nKe 5 4 3\n",
        )
        .unwrap();
        let obj = b"mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\no a\nusemtl red\nf 1 2 3\no b\nusemtl lamp\nf 1 2 4\n";
        let m = load_bytes(&dir.join("s.obj"), MeshFormat::Obj, obj).unwrap();
        let colors = m.colors.as_ref().unwrap();
        let emission = m.emission.as_ref().unwrap();
        for tri in &m.triangles {
            let kd = colors[tri[0] as usize];
            let ke = emission[tri[0] as usize];
            assert!(
                (kd, ke) == (Vec3::new(0.8, 0.1, 0.1), Vec3::ZERO)
                    || (kd, ke) == (Vec3::ZERO, Vec3::new(5.0, 4.0, 3.0)),
                "{kd} {ke}"
            );
            assert!(
                tri.iter()
                    .all(|&i| colors[i as usize] == kd && emission[i as usize] == ke)
            );
        }
        assert_eq!(m.triangle_count(), 2);
        // No mtllib: no colours, no emission.
        let m = load_bytes(
            &dir.join("t.obj"),
            MeshFormat::Obj,
            b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
        )
        .unwrap();
        assert!(m.colors.is_none() && m.emission.is_none());
        // A library tobj would panic on (a colour of two values) is an error
        // naming the OBJ, the library and its line.
        std::fs::write(dir.join("bad.mtl"), "newmtl red\nKd 0.8 0.1\n").unwrap();
        let obj = b"mtllib bad.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n";
        let e = load_bytes(&dir.join("u.obj"), MeshFormat::Obj, obj).unwrap_err();
        assert_eq!(
            e.to_string(),
            format!(
                "{}: not a valid MTL file: bad.mtl: line 2: Kd needs 3 values, has 2",
                dir.join("u.obj").display()
            )
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn bad_files_name_the_path() {
        let e =
            load_bytes(Path::new("bad.obj"), MeshFormat::Obj, b"v 0 0 0\nf 1 2 3\n").unwrap_err();
        assert!(e.to_string().starts_with("bad.obj: "), "{e}");
        let e = load(Path::new("mesh.xyz")).unwrap_err();
        assert!(
            e.to_string().contains("mesh.xyz: unknown mesh format"),
            "{e}"
        );
        let e = load(Path::new("/nonexistent/mesh.obj")).unwrap_err();
        assert!(
            e.to_string().contains("/nonexistent/mesh.obj: cannot read"),
            "{e}"
        );
    }
}
