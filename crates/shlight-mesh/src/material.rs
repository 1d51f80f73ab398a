//! A glTF metallic-roughness material as far as diffuse light needs it:
//! the diffuse albedo, the alpha that cuts a surface out, and the emitted
//! radiance, each from its factor, its texture and the vertex colour.
//!
//! At a surface point with texture coordinates `uv[k]` (set `k` as each
//! texture's `texCoord` says, after its `KHR_texture_transform`) and
//! vertex colour `COLOR_0` (linear RGBA, white where absent):
//!
//! ```text
//! base   = baseColorFactor x baseColorTexture(uv) (sRGB decoded) x COLOR_0
//! albedo = base.rgb x (1 - metallic),  metallic = metallicFactor x metallicRoughnessTexture(uv).b
//! alpha  = base.a
//! Le     = emissiveFactor x KHR_materials_emissive_strength x emissiveTexture(uv) (sRGB decoded)
//! ```
//!
//! The surface stops a ray with probability [`Material::opacity`]: 1 when
//! `OPAQUE`; 1 or 0 as alpha reaches `alphaCutoff` when `MASK` (a cut-out
//! texel lets every ray through, shadow rays too); alpha itself when
//! `BLEND` (coverage: the fraction of the texel's area the surface covers,
//! so a half-transparent curtain passes half of the light that reaches
//! it, colourless).

use glam::{Affine2, Vec2, Vec3, Vec4};

use crate::texture::Texture;

/// A texture as a material uses it: which image and sampler, which UV set,
/// and the set's transform.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureRef {
    /// Index into [`crate::Scene::textures`].
    pub texture: usize,
    /// Which `TEXCOORD_n` set (after `KHR_texture_transform`'s own
    /// `texCoord`, which overrides the reference's).
    pub tex_coord: usize,
    /// `KHR_texture_transform`: `uv' = T(offset) R(rotation) S(scale) uv`
    /// (identity without the extension).
    pub transform: Affine2,
}

impl TextureRef {
    /// The texture's value at a point whose UV sets are `uvs` (a missing set
    /// reads as (0, 0)).
    fn sample(&self, textures: &[Texture], uvs: &[Vec2], srgb: bool) -> Vec4 {
        let uv = uvs.get(self.tex_coord).copied().unwrap_or(Vec2::ZERO);
        textures[self.texture].sample(self.transform.transform_point2(uv), srgb)
    }
}

/// glTF's `alphaMode`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum AlphaMode {
    /// Alpha is ignored: the surface stops every ray.
    #[default]
    Opaque,
    /// A cut-out: the surface is there where alpha `>= cutoff`, absent
    /// elsewhere.
    Mask {
        /// `alphaCutoff` (0.5 by default).
        cutoff: f32,
    },
    /// Alpha is coverage: the surface stops that fraction of the rays.
    Blend,
}

/// A material's inputs to diffuse light.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// The material's name in the file, if any.
    pub name: Option<String>,
    /// `baseColorFactor`, linear RGBA.
    pub base_color: Vec4,
    /// `baseColorTexture`.
    pub base_color_texture: Option<TextureRef>,
    /// `metallicFactor`.
    pub metallic: f32,
    /// `metallicRoughnessTexture` (metalness in its blue channel).
    pub metallic_roughness_texture: Option<TextureRef>,
    /// `emissiveFactor` times `KHR_materials_emissive_strength`, linear
    /// RGB radiance (W sr^-1 m^-2 per channel).
    pub emissive: Vec3,
    /// `emissiveTexture`.
    pub emissive_texture: Option<TextureRef>,
    /// `alphaMode` and `alphaCutoff`.
    pub alpha_mode: AlphaMode,
    /// `doubleSided`: both faces reflect (and, for emitters, emit).
    pub double_sided: bool,
}

impl Default for Material {
    /// glTF's defaults, but dielectric: a white, opaque, single-sided
    /// surface that emits nothing.
    fn default() -> Self {
        Self {
            name: None,
            base_color: Vec4::ONE,
            base_color_texture: None,
            metallic: 0.0,
            metallic_roughness_texture: None,
            emissive: Vec3::ZERO,
            emissive_texture: None,
            alpha_mode: AlphaMode::Opaque,
            double_sided: false,
        }
    }
}

/// What a material gives at one surface point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceSample {
    /// Diffuse albedo, linear RGB.
    pub albedo: Vec3,
    /// Base alpha (before the alpha mode).
    pub alpha: f32,
}

impl Material {
    /// Whether [`Material::surface`] reads a texture (base colour or
    /// metallic), so needs the point's UV sets.
    pub fn is_textured(&self) -> bool {
        self.base_color_texture.is_some() || self.metallic_roughness_texture.is_some()
    }

    /// The diffuse albedo and alpha at a point with UV sets `uvs` and
    /// vertex colour `color` (linear RGBA).
    pub fn surface(&self, textures: &[Texture], uvs: &[Vec2], color: Vec4) -> SurfaceSample {
        let mut base = self.base_color * color;
        if let Some(t) = &self.base_color_texture {
            base *= t.sample(textures, uvs, true);
        }
        let mut metallic = self.metallic;
        if let Some(t) = &self.metallic_roughness_texture {
            metallic *= t.sample(textures, uvs, false).z;
        }
        SurfaceSample {
            albedo: base.truncate() * (1.0 - metallic.clamp(0.0, 1.0)),
            alpha: base.w,
        }
    }

    /// The emitted radiance at a point with UV sets `uvs`.
    pub fn emission(&self, textures: &[Texture], uvs: &[Vec2]) -> Vec3 {
        match &self.emissive_texture {
            Some(t) if self.emissive != Vec3::ZERO => {
                self.emissive * t.sample(textures, uvs, true).truncate()
            }
            _ => self.emissive,
        }
    }

    /// The fraction of rays the surface stops where its base alpha is
    /// `alpha` (see the module documentation).
    pub fn opacity(&self, alpha: f32) -> f32 {
        match self.alpha_mode {
            AlphaMode::Opaque => 1.0,
            AlphaMode::Mask { cutoff } => {
                if alpha >= cutoff {
                    1.0
                } else {
                    0.0
                }
            }
            AlphaMode::Blend => alpha.clamp(0.0, 1.0),
        }
    }

    /// Whether any point of the surface may let a ray through (`MASK` or
    /// `BLEND`): such surfaces need their alpha looked up where rays hit.
    pub fn cuts_out(&self) -> bool {
        !matches!(self.alpha_mode, AlphaMode::Opaque)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::{Filter, Wrap};

    fn checker() -> Texture {
        // Two texels: white opaque, then sRGB mid grey with alpha 0.
        Texture {
            width: 2,
            height: 1,
            texels: vec![[255, 255, 255, 255], [188, 188, 188, 0]],
            wrap_u: Wrap::Repeat,
            wrap_v: Wrap::Repeat,
            filter: Filter::Nearest,
        }
    }

    fn textured() -> Material {
        Material {
            base_color: Vec4::new(0.5, 1.0, 1.0, 1.0),
            base_color_texture: Some(TextureRef {
                texture: 0,
                tex_coord: 1,
                transform: Affine2::IDENTITY,
            }),
            alpha_mode: AlphaMode::Mask { cutoff: 0.5 },
            ..Material::default()
        }
    }

    #[test]
    fn albedo_is_factor_times_texture_times_colour_on_the_named_uv_set() {
        let m = textured();
        let t = [checker()];
        // Set 0 points at the grey texel, set 1 (the one named) at white.
        let uvs = [Vec2::new(0.75, 0.5), Vec2::new(0.25, 0.5)];
        let s = m.surface(&t, &uvs, Vec4::new(1.0, 0.5, 1.0, 1.0));
        assert_eq!(s.albedo, Vec3::new(0.5, 0.5, 1.0));
        assert_eq!(m.opacity(s.alpha), 1.0);
        let s = m.surface(&t, &[Vec2::ZERO, Vec2::new(0.75, 0.5)], Vec4::ONE);
        assert!((s.albedo.y - 0.5029).abs() < 1e-3, "{s:?}");
        assert_eq!(m.opacity(s.alpha), 0.0, "a cut-out texel passes rays");
    }

    #[test]
    fn the_texture_transform_moves_the_lookup() {
        let mut m = textured();
        m.base_color_texture.as_mut().unwrap().transform =
            Affine2::from_translation(Vec2::new(0.5, 0.0));
        let s = m.surface(&[checker()], &[Vec2::ZERO, Vec2::new(0.25, 0.5)], Vec4::ONE);
        assert_eq!(s.alpha, 0.0);
    }

    #[test]
    fn a_metal_reflects_no_diffuse_light() {
        let m = Material {
            metallic: 1.0,
            ..Material::default()
        };
        assert_eq!(m.surface(&[], &[], Vec4::ONE).albedo, Vec3::ZERO);
    }

    #[test]
    fn blend_alpha_is_coverage() {
        let m = Material {
            alpha_mode: AlphaMode::Blend,
            ..Material::default()
        };
        assert_eq!(m.opacity(0.25), 0.25);
        assert!(m.cuts_out());
        assert!(!Material::default().cuts_out());
    }
}
