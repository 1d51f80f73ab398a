//! [`BuiltIn`]: the mesh and the map a scene uses where its request names
//! none (the viewer's defaults, the volume's object), as bytes the front
//! end holds.

use std::path::Path;

use shlight_core::sh::Frame;
use shlight_io::{Image, ReadOptions, read_image_bytes};
use shlight_mesh::{Mesh, MeshFormat};
use shlight_pipeline::{Environment, LoadedMap, ReadSettings};

use super::SceneError;

/// A mesh and an equirect map built into a front end.
#[derive(Clone, Copy, Debug)]
pub struct BuiltIn<'a> {
    /// What the mesh is called in messages (its path in shlight's
    /// repository, `meshes/bunny.obj`).
    pub mesh_name: &'a str,
    /// The mesh: an OBJ file's bytes.
    pub mesh_obj: &'a [u8],
    /// What the map is called in messages (`envmaps/default.exr`).
    pub map_name: &'a str,
    /// The map: an image file's bytes, in a format named by `map_name`'s
    /// extension.
    pub map: &'a [u8],
}

impl BuiltIn<'_> {
    /// The mesh, loaded and validated as a file of it would be.
    ///
    /// # Errors
    /// Bytes that are not a valid OBJ mesh.
    pub fn mesh(&self) -> Result<Mesh, SceneError> {
        Ok(shlight_mesh::load_bytes(
            Path::new(self.mesh_name),
            MeshFormat::Obj,
            self.mesh_obj,
        )?)
    }

    /// The map, decoded.
    ///
    /// # Errors
    /// Bytes that do not decode as the name's format.
    pub fn map_image(&self) -> Result<Image, SceneError> {
        read_image_bytes(self.map, Path::new(self.map_name), &ReadOptions::default()).map_err(
            |source| SceneError::BuiltIn {
                name: self.map_name.to_string(),
                source,
            },
        )
    }

    /// The map as a scene's light: through the loader of every map
    /// ([`LoadedMap::from_image`]), projected to `lmax` with its top row
    /// facing `up` ([`Environment::from_loaded`]). Its warnings (the
    /// bundled map's known negative texels) are dropped: the user did not
    /// name the file.
    ///
    /// # Errors
    /// As [`BuiltIn::map_image`], and a map that is not equirect.
    pub fn environment(&self, up: Frame, lmax: usize) -> Result<Environment, SceneError> {
        let read = ReadSettings::default();
        let loaded = LoadedMap::from_image(self.map_name, self.map_image()?, &read)?;
        let mut env = Environment::from_loaded(Path::new(self.map_name), loaded, up, lmax)?;
        env.warnings.clear();
        Ok(env)
    }
}
