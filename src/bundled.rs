//! The files `shlight view` uses when given none, built into the binary so
//! that they work from any working directory (and after `cargo install`).

use std::path::Path;

use anyhow::{Context, Result};
use shlight_core::sh::Frame;
use shlight_io::{Image, ReadOptions, read_image_bytes};
use shlight_mesh::{Mesh, MeshFormat};
use shlight_pipeline::{Environment, LoadedMap, ReadSettings};

/// The name the bundled mesh goes by (its path in the repository).
pub const MESH_NAME: &str = "meshes/bunny.obj";
/// The Stanford bunny (meshes/README.md).
const MESH: &[u8] = include_bytes!("../meshes/bunny.obj");

/// The name the bundled map goes by (its path in the repository).
pub const ENV_NAME: &str = "envmaps/default.exr";
/// The default equirect map (envmaps/README.md).
const ENV: &[u8] = include_bytes!("../envmaps/default.exr");

/// The bundled mesh, loaded and validated.
pub fn mesh() -> Result<Mesh> {
    Ok(shlight_mesh::load_bytes(
        Path::new(MESH_NAME),
        MeshFormat::Obj,
        MESH,
    )?)
}

/// The bundled map, decoded from the bytes built into the binary.
pub fn env_image() -> Result<Image> {
    read_image_bytes(ENV, Path::new(ENV_NAME), &ReadOptions::default())
        .with_context(|| format!("reading the bundled {ENV_NAME}"))
}

/// The bundled map as the light of the GPU commands: through the loader
/// of every map ([`LoadedMap::from_image`]) and projected to the GPU's lmax
/// ([`Environment::from_loaded`]). Its known negative texels are not
/// reported: the user did not name the file.
pub fn environment(up: Frame) -> Result<Environment> {
    let loaded = LoadedMap::from_image(ENV_NAME, env_image()?, &ReadSettings::default())?;
    let mut env = Environment::from_loaded(
        Path::new(ENV_NAME),
        loaded,
        up,
        shlight_baked::LIGHT_MAX_LMAX,
    )?;
    env.warnings.clear();
    Ok(env)
}

#[cfg(test)]
mod tests {
    use super::*;
    use shlight_io::read_image;

    #[test]
    fn the_bundled_files_are_the_repository_files() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let from_disk = shlight_mesh::load(&root.join(MESH_NAME)).unwrap();
        let bundled = mesh().unwrap();
        assert_eq!(bundled.positions, from_disk.positions);
        assert_eq!(bundled.triangles, from_disk.triangles);
        let disk = read_image(&root.join(ENV_NAME), &ReadOptions::default()).unwrap();
        let image = env_image().unwrap();
        assert_eq!(
            (image.width(), image.height()),
            (disk.width(), disk.height())
        );
        assert_eq!(image.pixels(), disk.pixels());
    }

    /// The bundled light is the repository file's as `--env` loads it,
    /// without the file's warnings.
    #[test]
    fn the_bundled_light_is_the_files() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let lmax = shlight_baked::LIGHT_MAX_LMAX;
        for up in [Frame::YUp, Frame::ZUp] {
            let bundled = environment(up).unwrap();
            let file = Environment::load(&root.join(ENV_NAME), up, lmax).unwrap();
            assert_eq!(bundled.radiance, file.radiance);
            assert_eq!(bundled.orientation, file.orientation);
            assert!(bundled.warnings.is_empty());
            assert!(!file.warnings.is_empty(), "the file has negative texels");
        }
    }
}
