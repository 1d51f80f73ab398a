//! [`VolumeFormat`]: what an irradiance volume is written as, chosen by
//! name (`shlight volume --format`) or by the output's extension, and
//! [`ShvolFile::write_as`], which writes it (the command line and the
//! Python package both call it, so the two write the same bytes).

use std::path::Path;

use crate::threejs_volume::{Precision, threejs_grid};
use crate::{Result, ShvolFile, bevy_volume};

/// What a volume is written as.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum VolumeFormat {
    /// shlight's own binary file (header JSON + f32 data; docs/shvol.md).
    Shvol,
    /// The same as one JSON document, for other tools.
    Json,
    /// A KTX2 3D texture of ambient cubes for Bevy's `IrradianceVolume`
    /// (docs/shvol.md, "Bevy").
    Bevy,
    /// A JSON document of three.js's `LightProbeGridWebGL` atlas (lmax 2,
    /// invalid probes dilated), for web/shlight-three.js's
    /// `loadLightProbeGrid` (docs/shvol.md, "three.js").
    Threejs,
}

impl std::str::FromStr for VolumeFormat {
    type Err = String;

    /// One of the [names](VolumeFormat::name).
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        VolumeFormat::ALL
            .into_iter()
            .find(|f| f.name() == s.trim())
            .ok_or_else(|| "unknown volume format (expected shvol, json, bevy or threejs)".into())
    }
}

impl VolumeFormat {
    /// Every format, in the order the help lists them.
    pub const ALL: [VolumeFormat; 4] = [
        VolumeFormat::Shvol,
        VolumeFormat::Json,
        VolumeFormat::Bevy,
        VolumeFormat::Threejs,
    ];

    /// The name `--format` takes.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            VolumeFormat::Shvol => "shvol",
            VolumeFormat::Json => "json",
            VolumeFormat::Bevy => "bevy",
            VolumeFormat::Threejs => "threejs",
        }
    }

    /// One line on what it is, for the help.
    #[must_use]
    pub fn description(self) -> &'static str {
        match self {
            VolumeFormat::Shvol => {
                "shlight's own binary file (header JSON + f32 data; docs/shvol.md)"
            }
            VolumeFormat::Json => "the same as one JSON document, for other tools",
            VolumeFormat::Bevy => {
                "a KTX2 3D texture of ambient cubes for Bevy's IrradianceVolume (docs/shvol.md, \"Bevy\")"
            }
            VolumeFormat::Threejs => {
                "three.js's LightProbeGridWebGL atlas as JSON, for web/shlight-three.js (docs/shvol.md, \"three.js\")"
            }
        }
    }

    /// The format a name ends in: `json` for `.json`, `bevy` for `.ktx2`,
    /// else `shvol` (`threejs`, also JSON, is only ever asked for by name).
    #[must_use]
    pub fn from_path(path: &Path) -> Self {
        let extension = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase());
        match extension.as_deref() {
            Some("json") => VolumeFormat::Json,
            Some("ktx2") => VolumeFormat::Bevy,
            _ => VolumeFormat::Shvol,
        }
    }
}

impl ShvolFile {
    /// Writes the volume to `path` as `format` (the three.js atlas's
    /// numbers in `precision`), atomically, and returns what the user needs
    /// to know of it, each note naming the file: for Bevy the
    /// `LightProbe`'s transform that puts the texture on the volume's box,
    /// for three.js what the export clipped, dilated or moved.
    ///
    /// # Errors
    /// [`crate::FormatError::Write`] naming the file; for three.js, a value
    /// beyond half floats' range in `Precision::Half`.
    pub fn write_as(
        &self,
        path: &Path,
        format: VolumeFormat,
        precision: Precision,
    ) -> Result<Vec<String>> {
        match format {
            VolumeFormat::Threejs => {
                let grid = threejs_grid(self, precision).map_err(|e| {
                    crate::FormatError::Export(format!("{}: three.js export: {e}", path.display()))
                })?;
                shlight_io::write_atomically(path, |w| w.write_all(grid.text.as_bytes()))?;
                return Ok(grid
                    .notes
                    .into_iter()
                    .map(|n| format!("{}: {n}", path.display()))
                    .collect());
            }
            VolumeFormat::Shvol => self.write(path)?,
            VolumeFormat::Json => self.write_json(path)?,
            VolumeFormat::Bevy => {
                let bytes = bevy_volume::bevy_ktx2(self, &self.generator);
                shlight_io::write_atomically(path, |w| w.write_all(&bytes))?;
                let ([tx, ty, tz], [sx, sy, sz]) = bevy_volume::light_probe_transform(self.bounds);
                return Ok(vec![format!(
                    "Bevy: put the IrradianceVolume on a LightProbe with Transform::from_translation(Vec3::new({tx}, {ty}, {tz})).with_scale(Vec3::new({sx}, {sy}, {sz}))"
                )]);
            }
        }
        Ok(Vec::new())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_extension_chooses_the_format_and_names_parse_back() {
        for (name, format) in [
            ("v.json", VolumeFormat::Json),
            ("v.JSON", VolumeFormat::Json),
            ("v.ktx2", VolumeFormat::Bevy),
            ("v.shvol", VolumeFormat::Shvol),
            ("v", VolumeFormat::Shvol),
        ] {
            assert_eq!(VolumeFormat::from_path(Path::new(name)), format, "{name}");
        }
        let names: Vec<&str> = VolumeFormat::ALL.iter().map(|f| f.name()).collect();
        assert_eq!(names, ["shvol", "json", "bevy", "threejs"]);
    }
}
