//! [`TargetEngine`]: whose shader reads the prefiltered cube, which fixes the
//! roughness of every mip, the mip count, the cube's axes and the DFG
//! table's form.
//!
//! Each engine samples its prefiltered cube at a level of detail computed
//! from the material's roughness; the prefilter must give mip `k` the
//! roughness that the engine's formula maps to `lod = k`. `perceptual` is
//! the material's roughness parameter, `alpha = perceptual^2` the GGX
//! roughness; `N` the number of mips, `S` the size of mip 0.
//!
//! | engine | the engine's lookup (source) | roughness of mip `k` |
//! |---|---|---|
//! | `filament` | `perceptualRoughnessToLod(r) = (N-1) r (2 - r)` (Filament's `light_indirect.fs`, `iblRoughnessOneLevel = N-1`); cmgen's `lodToPerceptualRoughness` inverts it | `perceptual = 1 - sqrt(1 - k/(N-1))` |
//! | `babylon` | `lod = log2(S alphaG) * lodGenerationScale` (`getLodFromAlphaG`, `pbrIBLFunctions.fx`), the glTF loader's `lodGenerationScale = (N-1)/log2(S)` (`EXT_lights_image_based.ts`) | `alpha = S^(k/(N-1) - 1)`; mip 0 mirror (`alpha = 0`), as Babylon's own `HDRFiltering` does |
//! | `bevy` | `radiance_level = perceptual_roughness * (N-1)` (`environment_map.wgsl`) | `perceptual = k/(N-1)` |
//! | `unreal` | `ComputeReflectionCaptureMipFromRoughness`: `LevelFrom1x1 = 1 - 1.2 log2(r)`, `mip = N - 1 - LevelFrom1x1` (`ReflectionEnvironmentShared.ush`, UE4) | `perceptual = min(1, 2^((1 - (N-1-k)) / 1.2))` |
//!
//! cmgen stops at 16-pixel faces (`IBL_DEFAULT_MIN_LOD_SIZE`), so a
//! 256-pixel cube has 5 levels; Babylon's loader and Bevy read any count,
//! and a full chain (to 1 pixel) is what Babylon's own tools write.

use core::fmt;
use std::str::FromStr;

use glam::{DMat3, DVec3};

use crate::ggx::MaskingShadowing;

/// The engine a prefiltered cube and DFG table are made for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TargetEngine {
    /// Filament (and cmgen's `--ibl-ld`).
    Filament,
    /// Babylon.js (its `EXT_lights_image_based` loader).
    Babylon,
    /// Bevy's `EnvironmentMapLight`.
    Bevy,
    /// Unreal Engine 4's reflection captures.
    Unreal,
}

impl TargetEngine {
    /// Every engine, in the order `--for` lists them.
    pub const ALL: [TargetEngine; 4] = [
        TargetEngine::Filament,
        TargetEngine::Babylon,
        TargetEngine::Bevy,
        TargetEngine::Unreal,
    ];

    /// The name `--for` takes.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            TargetEngine::Filament => "filament",
            TargetEngine::Babylon => "babylon",
            TargetEngine::Bevy => "bevy",
            TargetEngine::Unreal => "unreal",
        }
    }

    /// The number of mips of a cube of `size` (a power of two) when none is
    /// asked for: cmgen's for Filament (down to 16 pixels, or all when the
    /// cube is 16 or smaller), the full chain to 1 pixel for the others.
    #[must_use]
    pub fn default_mips(self, size: usize) -> usize {
        let full = size.max(1).ilog2() as usize + 1;
        match self {
            TargetEngine::Filament if size > 16 => full - 4,
            _ => full,
        }
    }

    /// The GGX roughness `alpha` of mip `level` of `mips` in a cube whose
    /// mip 0 is `size` pixels wide (table in the module docs). One mip
    /// alone is the unfiltered map (`alpha = 0`).
    #[must_use]
    pub fn mip_alpha(self, level: usize, mips: usize, size: usize) -> f64 {
        if mips <= 1 || level == 0 {
            return match self {
                TargetEngine::Unreal if mips > 1 => unreal_perceptual(0, mips).powi(2),
                _ => 0.0,
            };
        }
        let t = level as f64 / (mips - 1) as f64;
        match self {
            TargetEngine::Filament => {
                let p = 1.0 - (1.0 - t.min(1.0)).sqrt();
                p * p
            }
            TargetEngine::Babylon => (size as f64).powf(t - 1.0).min(1.0),
            TargetEngine::Bevy => t * t,
            TargetEngine::Unreal => unreal_perceptual(level, mips).powi(2),
        }
    }

    /// How the engine's cube sees shlight's world: the cube texel in
    /// direction `c` holds the radiance shlight's map has at
    /// `world_from_cube * c` (docs/conventions.md for shlight's frame).
    ///
    /// - Filament: cmgen's picture of an equirect map (its
    ///   `equirectangularToCubemap` and default `mirrorCubemap`), the frame
    ///   of shlight's Filament export: the world direction `d` is at
    ///   `c = (-d.z, d.y, d.x)`.
    /// - Babylon: the frame of shlight's `--format gltf` light, Babylon's
    ///   left-handed world as its glTF loader and shaders look the cube up:
    ///   `c = (d.z, d.y, d.x)`, a mirror (docs/exporters.md).
    /// - Bevy: shlight's world as Bevy's world, seen through Bevy's lookup
    ///   `textureSampleLevel(specular, R * (1, 1, -1))`: `c = (d.x, d.y, -d.z)`.
    /// - Unreal: shlight's own y-up frame, unchanged.
    #[must_use]
    pub fn world_from_cube(self) -> DMat3 {
        match self {
            // c = (-z, y, x)  =>  d = (c.z, c.y, -c.x)
            TargetEngine::Filament => DMat3::from_cols(DVec3::NEG_Z, DVec3::Y, DVec3::X),
            // c = (z, y, x)  =>  d = (c.z, c.y, c.x)
            TargetEngine::Babylon => DMat3::from_cols(DVec3::Z, DVec3::Y, DVec3::X),
            TargetEngine::Bevy => DMat3::from_diagonal(DVec3::new(1.0, 1.0, -1.0)),
            TargetEngine::Unreal => DMat3::IDENTITY,
        }
    }

    /// The masking-shadowing term of the engine's DFG table.
    #[must_use]
    pub fn masking_shadowing(self) -> MaskingShadowing {
        match self {
            TargetEngine::Unreal => MaskingShadowing::SchlickSmith,
            _ => MaskingShadowing::HeightCorrelated,
        }
    }

    /// Whether the engine's DFG table has the multiscatter form
    /// (`(bias, scale + bias)`, Filament's `DFV_Multiscatter`) rather than
    /// Karis' `(scale, bias)`.
    #[must_use]
    pub fn multiscatter_dfg(self) -> bool {
        matches!(self, TargetEngine::Filament)
    }
}

fn unreal_perceptual(level: usize, mips: usize) -> f64 {
    let from_1x1 = (mips - 1 - level) as f64;
    2f64.powf((1.0 - from_1x1) / 1.2).min(1.0)
}

impl fmt::Display for TargetEngine {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// An engine name that is none of [`TargetEngine::ALL`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ParseTargetEngineError(pub String);

impl fmt::Display for ParseTargetEngineError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "unknown engine '{}' (filament, babylon, bevy, unreal)",
            self.0
        )
    }
}

impl std::error::Error for ParseTargetEngineError {}

impl FromStr for TargetEngine {
    type Err = ParseTargetEngineError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        TargetEngine::ALL
            .into_iter()
            .find(|e| e.name() == s)
            .ok_or_else(|| ParseTargetEngineError(s.to_owned()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each mapping, put back through the engine's own LOD formula (as the
    /// engine's shader computes it), gives the mip it was made for.
    #[test]
    fn each_engine_reads_each_mip_at_its_roughness() {
        let (size, mips) = (256usize, 9usize);
        for k in 1..mips {
            let n1 = (mips - 1) as f64;
            // Filament: lod = (N-1) r (2 - r).
            let r = TargetEngine::Filament.mip_alpha(k, mips, size).sqrt();
            assert!((n1 * r * (2.0 - r) - k as f64).abs() < 1e-9);
            // Babylon: lod = log2(S alpha) (N-1) / log2(S).
            let a = TargetEngine::Babylon.mip_alpha(k, mips, size);
            let lod = (size as f64 * a).log2() * n1 / (size as f64).log2();
            assert!((lod - k as f64).abs() < 1e-9);
            // Bevy: lod = r (N-1).
            let r = TargetEngine::Bevy.mip_alpha(k, mips, size).sqrt();
            assert!((r * n1 - k as f64).abs() < 1e-9);
            // Unreal: mip = N - 1 - (1 - 1.2 log2 r), where r < 1.
            let r = TargetEngine::Unreal.mip_alpha(k, mips, size).sqrt();
            if r < 1.0 {
                let mip = n1 - (1.0 - 1.2 * r.log2());
                assert!((mip - k as f64).abs() < 1e-9, "{k}: {mip}");
            }
        }
        // cmgen's levels for a 256 cube: 256 .. 16.
        assert_eq!(TargetEngine::Filament.default_mips(256), 5);
        assert_eq!(TargetEngine::Bevy.default_mips(256), 9);
    }

    #[test]
    fn the_cube_frames_are_rotations_or_mirrors() {
        for e in TargetEngine::ALL {
            let m = e.world_from_cube();
            assert!(
                (m * m.transpose() - DMat3::IDENTITY)
                    .abs()
                    .to_cols_array()
                    .iter()
                    .all(|v| *v < 1e-12)
            );
        }
        // Filament: the world's +X is at the cube's +Z.
        let d = TargetEngine::Filament.world_from_cube() * DVec3::Z;
        assert!((d - DVec3::X).length() < 1e-12);
        // Babylon: the same, and the world's -Z at the cube's +X (a mirror
        // of Filament's +Z there).
        let m = TargetEngine::Babylon.world_from_cube();
        assert!((m * DVec3::Z - DVec3::X).length() < 1e-12);
        assert!((m * DVec3::X - DVec3::Z).length() < 1e-12);
        assert!((m.determinant() + 1.0).abs() < 1e-12);
    }
}
