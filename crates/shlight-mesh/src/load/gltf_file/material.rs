//! glTF materials to [`Material`]s: `baseColorFactor` and
//! `baseColorTexture`, `metallicFactor` and `metallicRoughnessTexture`,
//! `emissiveFactor` times `KHR_materials_emissive_strength` and
//! `emissiveTexture`, `alphaMode` and `alphaCutoff` (0.5 by default),
//! `doubleSided`; each texture with its `texCoord` and
//! `KHR_texture_transform` (whose own `texCoord` overrides the
//! reference's).
//!
//! Textures are decoded only where they matter: for materials that a
//! placed primitive uses, the metallic-roughness texture only when
//! `metallicFactor` is not 0, the emissive texture only when
//! `emissiveFactor` is not black. A material no primitive uses keeps its
//! factors and drops its textures.

use std::path::Path;

use glam::{Affine2, Vec2, Vec3, Vec4};
use gltf::json;
use json::validation::Checked;

use super::texture::Textures;
use crate::MeshError;
use crate::material::{AlphaMode, Material, TextureRef};

/// Material `index`; its textures are decoded through `textures` when
/// `used`.
pub(super) fn read(
    path: &Path,
    root: &json::Root,
    index: usize,
    used: bool,
    textures: &mut Textures,
) -> Result<Material, MeshError> {
    let m = &root.materials[index];
    let name = match &m.name {
        Some(n) => format!("material {index} ({n})"),
        None => format!("material {index}"),
    };
    let pbr = &m.pbr_metallic_roughness;
    let base_color = Vec4::from_array(pbr.base_color_factor.0);
    let metallic = pbr.metallic_factor.0;
    let strength = m
        .extensions
        .as_ref()
        .and_then(|e| e.emissive_strength.as_ref())
        .map_or(1.0, |s| s.emissive_strength.0);
    let emissive = Vec3::from_array(m.emissive_factor.0) * strength;
    let fail = |message: String| MeshError::Parse {
        path: path.to_path_buf(),
        message: format!("{name}: {message}"),
    };
    if !base_color.is_finite() || !metallic.is_finite() {
        return Err(fail(
            "a non-finite baseColorFactor or metallicFactor".into(),
        ));
    }
    if !emissive.is_finite() || emissive.min_element() < 0.0 {
        return Err(fail(format!(
            "the emitted radiance {emissive} (emissiveFactor times emissiveStrength) is not finite and non-negative"
        )));
    }
    let alpha_mode = match m.alpha_mode {
        Checked::Valid(json::material::AlphaMode::Mask) => AlphaMode::Mask {
            cutoff: m.alpha_cutoff.map_or(0.5, |c| c.0),
        },
        Checked::Valid(json::material::AlphaMode::Blend) => AlphaMode::Blend,
        _ => AlphaMode::Opaque,
    };
    let mut reference = |info: Option<&json::texture::Info>, wanted: bool| match info {
        Some(info) if used && wanted => texture_ref(info, textures).map(Some),
        _ => Ok(None),
    };
    let base_color_texture = reference(pbr.base_color_texture.as_ref(), true)?;
    let metallic_roughness_texture =
        reference(pbr.metallic_roughness_texture.as_ref(), metallic != 0.0)?;
    let emissive_texture = reference(m.emissive_texture.as_ref(), emissive != Vec3::ZERO)?;
    Ok(Material {
        name: m.name.clone(),
        base_color,
        base_color_texture,
        metallic,
        metallic_roughness_texture,
        emissive,
        emissive_texture,
        alpha_mode,
        double_sided: m.double_sided,
    })
}

/// A texture reference: the decoded texture, its UV set and its
/// `KHR_texture_transform`, `uv' = T(offset) R(rotation) S(scale) uv` with
/// the extension's `R` (`u' = cos r u + sin r v`, `v' = -sin r u + cos r v`:
/// a counter-clockwise turn of the UVs with v pointing down the image).
fn texture_ref(
    info: &json::texture::Info,
    textures: &mut Textures,
) -> Result<TextureRef, MeshError> {
    let texture = textures.get(info.index.value())?;
    let mut tex_coord = info.tex_coord as usize;
    let mut transform = Affine2::IDENTITY;
    if let Some(t) = info
        .extensions
        .as_ref()
        .and_then(|e| e.texture_transform.as_ref())
    {
        if let Some(k) = t.tex_coord {
            tex_coord = k as usize;
        }
        transform = Affine2::from_scale_angle_translation(
            Vec2::from_array(t.scale.0),
            -t.rotation.0,
            Vec2::from_array(t.offset.0),
        );
    }
    Ok(TextureRef {
        texture,
        tex_coord,
        transform,
    })
}
