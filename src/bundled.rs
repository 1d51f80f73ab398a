//! The files `shlight view` uses when given none (and the object of
//! `--volume`), built into the binary so that they work from any working
//! directory (and after `cargo install`); shlight-gpu's `BuiltIn` decodes
//! them.

use shlight_gpu::BuiltIn;

/// The Stanford bunny (meshes/README.md) and the default equirect map
/// (envmaps/README.md), each under its path in the repository.
pub const BUILT_IN: BuiltIn<'static> = BuiltIn {
    mesh_name: "meshes/bunny.obj",
    mesh_obj: include_bytes!("../meshes/bunny.obj"),
    map_name: "envmaps/default.exr",
    map: include_bytes!("../envmaps/default.exr"),
};

#[cfg(test)]
mod tests {
    use super::*;
    use shlight_core::sh::Frame;
    use shlight_io::{ReadOptions, read_image};
    use shlight_pipeline::Environment;
    use std::path::Path;

    #[test]
    fn the_bundled_files_are_the_repository_files() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let from_disk = shlight_mesh::load(&root.join(BUILT_IN.mesh_name)).unwrap();
        let bundled = BUILT_IN.mesh().unwrap();
        assert_eq!(bundled.positions, from_disk.positions);
        assert_eq!(bundled.triangles, from_disk.triangles);
        let disk = read_image(&root.join(BUILT_IN.map_name), &ReadOptions::default()).unwrap();
        let image = BUILT_IN.map_image().unwrap();
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
            let bundled = BUILT_IN.environment(up, lmax).unwrap();
            let file = Environment::load(&root.join(BUILT_IN.map_name), up, lmax).unwrap();
            assert_eq!(bundled.radiance, file.radiance);
            assert_eq!(bundled.orientation, file.orientation);
            assert!(bundled.warnings.is_empty());
            assert!(!file.warnings.is_empty(), "the file has negative texels");
        }
    }
}
