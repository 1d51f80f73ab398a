//! What a lightmap texel holds for one engine: the basis (irradiance, L1
//! SH, MonoSH), the units and the packing, and which pairs exist.

use core::fmt;

use crate::diffuse_l1::TexelUnits;

/// The engine that will read the lightmap: it fixes the units and the
/// packing of each basis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Engine {
    /// three.js: `lightMap` holds irradiance `E`.
    ThreeJs,
    /// Bevy: `Lightmap` holds `E / pi`, one RGB texture.
    Bevy,
    /// Godot 4's `LightmapGI`: `E / pi`; directional lightmaps as L0 then
    /// three L1 layers.
    Godot,
    /// Unity with Bakery's shaders: `E / pi`; Bakery's SH and MonoSH modes.
    Unity,
}

impl Engine {
    /// The engine's name as its users write it.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::ThreeJs => "three.js",
            Self::Bevy => "Bevy",
            Self::Godot => "Godot",
            Self::Unity => "Unity",
        }
    }

    /// What the engine's shader takes a texel to be.
    #[must_use]
    pub fn units(self) -> TexelUnits {
        match self {
            Self::ThreeJs => TexelUnits::Irradiance,
            Self::Bevy | Self::Godot | Self::Unity => TexelUnits::IrradianceOverPi,
        }
    }
}

/// What a texel holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TexelBasis {
    /// RGB irradiance at the texel's own normal: one layer.
    Irradiance,
    /// L0 and L1 per channel, so a normal map reshades it: four layers.
    ShL1,
    /// RGB L0 and one L1 direction shared by the channels (Bakery's
    /// MonoSH): two layers.
    MonoSh,
}

impl TexelBasis {
    /// The basis's name in shlight's documentation.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Irradiance => "irradiance",
            Self::ShL1 => "sh-l1",
            Self::MonoSh => "monosh",
        }
    }
}

/// How the reading shader turns L0 and L1 into light.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum L1Reconstruction {
    /// `L0 + L1 . n`: exact for the lmax-1 irradiance, negative in places
    /// for strongly directional light.
    Linear,
    /// Geomerics' non-linear reconstruction ([`crate::geomerics_l1`]):
    /// never negative, closer to a single light's irradiance.
    NonLinear,
}

impl L1Reconstruction {
    /// The reconstruction's name in shlight's files (`SHLIGHT_lightmap`).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Linear => "linear",
            Self::NonLinear => "non-linear",
        }
    }
}

/// A texel format: basis, engine and (for SH bases) reconstruction, one
/// of the pairs an engine can read.
///
/// | basis | three.js | Bevy | Godot | Unity |
/// |---|---|---|---|---|
/// | irradiance | `E` | `E/pi` | `E/pi` | `E/pi` |
/// | sh-l1 | shlight's layout, `E` | — | directional, linear | Bakery SH |
/// | monosh | — | — | — | Bakery MonoSH |
///
/// Bevy's lightmap shader reads one RGB texture, and Godot's directional
/// lightmaps reconstruct linearly only; three.js has no SH lightmaps of
/// its own, so its `sh-l1` is shlight's layout (float layers, no
/// packing), for a patched material.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TexelFormat {
    basis: TexelBasis,
    engine: Engine,
    reconstruction: L1Reconstruction,
}

impl TexelFormat {
    /// The format, or why `engine` cannot read `basis` reconstructed so.
    /// The reconstruction is ignored for [`TexelBasis::Irradiance`]
    /// (stored as [`L1Reconstruction::Linear`]).
    pub fn new(
        basis: TexelBasis,
        engine: Engine,
        reconstruction: L1Reconstruction,
    ) -> Result<Self, TexelFormatError> {
        use {Engine::*, L1Reconstruction::*, TexelBasis::*};
        let reconstruction = if basis == Irradiance {
            Linear
        } else {
            reconstruction
        };
        let ok = matches!(
            (basis, engine, reconstruction),
            (Irradiance, _, _)
                | (ShL1, ThreeJs | Unity, _)
                | (ShL1, Godot, Linear)
                | (MonoSh, Unity, _)
        );
        if ok {
            Ok(Self {
                basis,
                engine,
                reconstruction,
            })
        } else {
            Err(TexelFormatError {
                basis,
                engine,
                reconstruction,
            })
        }
    }

    /// The basis.
    #[must_use]
    pub fn basis(self) -> TexelBasis {
        self.basis
    }

    /// The engine.
    #[must_use]
    pub fn engine(self) -> Engine {
        self.engine
    }

    /// The reconstruction (always linear for irradiance).
    #[must_use]
    pub fn reconstruction(self) -> L1Reconstruction {
        self.reconstruction
    }

    /// The engine's units.
    #[must_use]
    pub fn units(self) -> TexelUnits {
        self.engine.units()
    }

    /// How many RGBA layers a texel takes: 1, 4 (L0, then three L1) or 2
    /// (L0, then the direction).
    #[must_use]
    pub fn layer_count(self) -> usize {
        self.layer_names().len()
    }

    /// The layers' names, in order, as files and shlight's glTF extension
    /// name them: `irradiance`; `l0`, then `l1x`, `l1y`, `l1z` (three.js,
    /// shlight's layout), `l1y`, `l1z`, `l1x` (Godot's order), or `rnm0`,
    /// `rnm1`, `rnm2` (Bakery's SH textures, for x, y, z); MonoSH's `l0`
    /// and `direction`.
    #[must_use]
    pub fn layer_names(self) -> &'static [&'static str] {
        match (self.basis, self.engine) {
            (TexelBasis::Irradiance, _) => &["irradiance"],
            (TexelBasis::MonoSh, _) => &["l0", "direction"],
            (TexelBasis::ShL1, Engine::Godot) => &["l0", "l1y", "l1z", "l1x"],
            (TexelBasis::ShL1, Engine::Unity) => &["l0", "rnm0", "rnm1", "rnm2"],
            (TexelBasis::ShL1, _) => &["l0", "l1x", "l1y", "l1z"],
        }
    }
}

/// An engine that cannot read a basis (or not with that reconstruction).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TexelFormatError {
    /// The basis asked for.
    pub basis: TexelBasis,
    /// The engine asked for.
    pub engine: Engine,
    /// The reconstruction asked for.
    pub reconstruction: L1Reconstruction,
}

impl fmt::Display for TexelFormatError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let why = match (self.basis, self.engine) {
            (TexelBasis::ShL1, Engine::Godot) => {
                "Godot's directional lightmaps reconstruct linearly only"
            }
            (TexelBasis::ShL1, Engine::Bevy) | (TexelBasis::MonoSh, Engine::Bevy) => {
                "Bevy's lightmap shader reads one RGB texture"
            }
            (TexelBasis::MonoSh, _) => "MonoSH is Bakery's format, read by Unity only",
            _ => "no such texel format",
        };
        let how = match self.reconstruction {
            L1Reconstruction::Linear => "",
            L1Reconstruction::NonLinear => " with the non-linear reconstruction",
        };
        write!(
            f,
            "{} cannot read {} lightmaps{how}: {why}",
            self.engine.name(),
            self.basis.name()
        )
    }
}

impl std::error::Error for TexelFormatError {}
