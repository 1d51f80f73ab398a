//! `--volume FILE.shvol` of `render-mesh` and `view`: the arguments, and
//! `load_volume`, which reads them into shlight-viewer's `VolumeScene` (the
//! scene lit by its baked irradiance volume and a dynamic object moved
//! through it, docs/shvol.md, "Shading"). A `--static` volume keeps its
//! stored SH, and turning the environment is refused (`render-mesh
//! --rotate`) or moves only the background (`view`).

use std::path::PathBuf;

use anyhow::{Result, bail};
use clap::Args;
use glam::Vec3;
use shlight_baked::SHADED_MAX_LMAX;

/// The volume options shared by `render-mesh` and `view`.
#[derive(Args, Debug, Clone, Default)]
pub struct VolumeShadingArgs {
    /// An irradiance volume baked through MESH by `shlight volume`
    /// (.shvol): MESH and --object are lit per fragment by its probes
    /// (lmax clipped to 4).
    #[arg(long, value_name = "FILE.shvol")]
    pub volume: Option<PathBuf>,
    /// With --volume: the dynamic object moved through the volume (OBJ,
    /// PLY, OFF, glTF/GLB) [default: the Stanford bunny, meshes/bunny.obj,
    /// built into shlight].
    #[arg(long, value_name = "MESH")]
    pub object: Option<PathBuf>,
    /// With --volume: where the object's bounding-box centre goes, X,Y,Z
    /// [default: the volume's centre].
    #[arg(long, value_parser = crate::values::parse_vec3_f32, allow_hyphen_values = true)]
    pub at: Option<Vec3>,
    /// With --volume: the object's bounding-box diagonal, in scene units
    /// [default: a third of the volume box's shortest side].
    #[arg(long)]
    pub object_size: Option<f32>,
}

impl VolumeShadingArgs {
    /// Refuses the object options without `--volume`, a volume that is not
    /// a `.shvol` file, an `--lmax` beyond [`SHADED_MAX_LMAX`] and a
    /// size that is not positive.
    ///
    /// # Errors
    /// As above, naming the option or the file.
    pub fn check(&self, lmax: Option<usize>) -> Result<()> {
        let Some(path) = &self.volume else {
            for (given, name) in [
                (self.object.is_some(), "--object"),
                (self.at.is_some(), "--at"),
                (self.object_size.is_some(), "--object-size"),
            ] {
                if given {
                    bail!(
                        "{name} places an object in an irradiance volume: it needs --volume FILE.shvol"
                    );
                }
            }
            return Ok(());
        };
        if !path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("shvol"))
        {
            bail!(
                "{}: --volume takes a .shvol file (bake one with shlight volume SCENE --env LIGHT -o FILE.shvol)",
                path.display()
            );
        }
        if let Some(l) = lmax.filter(|&l| l > SHADED_MAX_LMAX) {
            bail!("--lmax {l}: volumes are shaded to lmax {SHADED_MAX_LMAX} at most");
        }
        if let Some(s) = self.object_size
            && !(s.is_finite() && s > 0.0)
        {
            bail!("--object-size {s}: expected a positive length");
        }
        Ok(())
    }
}

/// Reads `--volume` and `--object` into the scene the GPU shades, warning
/// when `scene` is not the mesh the volume was baked in and noting a volume
/// above the shading lmax.
///
/// # Errors
/// An unreadable or invalid file, an `--at` that is not finite.
#[cfg(feature = "gpu")]
pub fn load_volume(
    args: &VolumeShadingArgs,
    scene: &shlight_mesh::Mesh,
    scene_name: &std::path::Path,
    ui: &crate::progress::Ui,
) -> Result<shlight_viewer::VolumeScene> {
    let path = args
        .volume
        .clone()
        .expect("load_volume is called with --volume");
    if !path.exists() {
        bail!("{}: no such volume file", path.display());
    }
    let file = shlight_format::ShvolFile::read(&path)?;
    let name = path.display();
    if file.scene_hash != scene.content_hash() {
        ui.warn(format!(
            "{name} was baked in {} (fnv1a64:{:016x}), not in {} (fnv1a64:{:016x}): its light does not match this scene",
            file.scene,
            file.scene_hash,
            scene_name.display(),
            scene.content_hash()
        ));
    }
    if file.lmax > SHADED_MAX_LMAX {
        ui.note(format!(
            "{name} holds lmax {}; the GPU shades volumes to lmax {SHADED_MAX_LMAX}",
            file.lmax
        ));
    }
    let object = match &args.object {
        Some(p) => (shlight_mesh::load(p)?, p.display().to_string()),
        None => (
            crate::bundled::mesh()?,
            crate::bundled::MESH_NAME.to_string(),
        ),
    };
    let volume =
        shlight_viewer::VolumeScene::new(file, path.clone(), object, args.at, args.object_size)?;
    let file = &volume.file;
    let valid = file.valid.iter().filter(|v| **v).count();
    ui.note(format!(
        "{name}: {}x{}x{} probes ({valid} valid of {}), lmax {}, {}",
        file.resolution[0],
        file.resolution[1],
        file.resolution[2],
        file.valid.len(),
        file.lmax,
        if file.transfer.is_some() {
            "relightable"
        } else {
            "static"
        }
    ));
    Ok(volume)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[cfg(feature = "gpu")]
    #[test]
    fn object_options_need_a_volume_and_a_volume_needs_its_extension() {
        let object = VolumeShadingArgs {
            object: Some("bunny.obj".into()),
            ..Default::default()
        };
        let e = object.check(None).unwrap_err().to_string();
        assert!(e.contains("--object") && e.contains("--volume"), "{e}");
        let wrong = VolumeShadingArgs {
            volume: Some("room.json".into()),
            ..Default::default()
        };
        let e = wrong.check(None).unwrap_err().to_string();
        assert!(e.contains("room.json") && e.contains(".shvol"), "{e}");
        let right = VolumeShadingArgs {
            volume: Some("room.shvol".into()),
            ..Default::default()
        };
        assert!(right.check(Some(4)).is_ok());
        let e = right.check(Some(5)).unwrap_err().to_string();
        assert!(e.contains("--lmax 5") && e.contains("lmax 4"), "{e}");
    }
}
