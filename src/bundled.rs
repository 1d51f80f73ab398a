//! The files `shlight view` uses when given none, built into the binary so
//! that they work from any working directory (and after `cargo install`).

use std::io::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use shlight_io::{Image, ReadOptions, read_image};
use shlight_mesh::{Mesh, MeshFormat};

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

/// The bundled map, decoded. The image reader takes files, so the bytes go
/// through a private temporary file, removed afterwards.
pub fn env_image() -> Result<Image> {
    let path = temporary_path("default.exr");
    let mut file = std::fs::File::create_new(&path)
        .with_context(|| format!("{}: cannot write the bundled map", path.display()))?;
    let written = file.write_all(ENV).and_then(|()| file.flush());
    drop(file);
    let image = written
        .with_context(|| format!("{}: cannot write the bundled map", path.display()))
        .and_then(|()| Ok(read_image(&path, &ReadOptions::default())?));
    let _ = std::fs::remove_file(&path);
    image.with_context(|| format!("reading the bundled {ENV_NAME}"))
}

/// A path in the system's temporary directory no other process uses.
fn temporary_path(name: &str) -> PathBuf {
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.subsec_nanos());
    std::env::temp_dir().join(format!("shlight-{}-{nanos}-{name}", std::process::id()))
}

#[cfg(test)]
mod tests {
    use super::*;

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
}
