//! glTF materials on the GPU: per material a uniform block (`Material` in
//! `shaders/material.wgsl`), its base colour texture as an sRGB texture
//! (the GPU decodes it before filtering) and its metallic-roughness
//! texture as a linear one, each with a full mip chain made on the CPU
//! ([`mip_chain`](crate::mip_chain)) and a sampler with the texture's
//! glTF wrap modes and filter; bind group 1 of the surface passes.
//!
//! Samplers: the magnification filter is the texture's (`Linear` or
//! `Nearest`), minification the same, between mip levels always linear
//! (trilinear). No anisotropic filtering: lavapipe's blurs a magnified
//! texture (a texel's centre then mixes in a tenth of its neighbours), so
//! frames would differ by adapter. A material without a texture reads a
//! white 1x1 texel in its place, which multiplies nothing.

use std::collections::HashMap;

use shlight_mesh::{AlphaMode, Filter, Material, Texture, TextureRef, Wrap};
use wgpu::util::DeviceExt;

use crate::mip_chain::mip_chain;
use crate::pipeline::{UNIFORM, buffer_entry};
use crate::{GpuContext, GpuError};

/// `Material` of `shaders/material.wgsl`, byte for byte.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct MaterialUniform {
    /// `baseColorFactor`, linear RGBA.
    base_color: [f32; 4],
    /// `metallicFactor`.
    metallic: f32,
    /// `alphaCutoff` (`MASK`).
    cutoff: f32,
    /// `ALPHA_OPAQUE`, `ALPHA_MASK` or `ALPHA_BLEND`.
    alpha_mode: u32,
    pad: u32,
}

impl MaterialUniform {
    pub(crate) fn new(m: &Material) -> Self {
        let (alpha_mode, cutoff) = match m.alpha_mode {
            AlphaMode::Opaque => (0, 0.0),
            AlphaMode::Mask { cutoff } => (1, cutoff),
            AlphaMode::Blend => (2, 0.0),
        };
        Self {
            base_color: m.base_color.to_array(),
            metallic: m.metallic,
            cutoff,
            alpha_mode,
            pad: 0,
        }
    }
}

/// The layout of bind group 1 of the surface passes: `0` the material's
/// uniform, `1` and `2` the base colour texture and its sampler, `3` and
/// `4` the metallic-roughness texture and its sampler.
pub(crate) fn material_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    let fragment = wgpu::ShaderStages::FRAGMENT;
    let texture = |binding| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: fragment,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: true },
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    };
    let sampler = |binding| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: fragment,
        ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
        count: None,
    };
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("material"),
        entries: &[
            buffer_entry(0, fragment, UNIFORM),
            texture(1),
            sampler(2),
            texture(3),
            sampler(4),
        ],
    })
}

/// A material ready to draw with: its bind group.
#[derive(Debug)]
pub(crate) struct GpuMaterial {
    pub bind: wgpu::BindGroup,
}

/// A texture uploaded once per way it is read (sRGB or linear), with its
/// sampler.
struct Uploaded {
    view: wgpu::TextureView,
    sampler: wgpu::Sampler,
}

/// The materials `materials` (their textures among `textures`) as bind
/// groups of `layout` ([`material_layout`]), each texture uploaded once
/// per way it is read.
///
/// # Errors
/// [`GpuError::Invalid`] for a texture index beyond `textures` or a
/// texture whose texels are not `width x height`; GPU errors while
/// uploading.
pub(crate) fn gpu_materials(
    ctx: &GpuContext,
    layout: &wgpu::BindGroupLayout,
    materials: &[Material],
    textures: &[Texture],
) -> Result<Vec<GpuMaterial>, GpuError> {
    let white = Texture {
        width: 1,
        height: 1,
        texels: vec![[255; 4]],
        wrap_u: Wrap::Repeat,
        wrap_v: Wrap::Repeat,
        filter: Filter::Nearest,
    };
    let mut uploaded: HashMap<(Option<usize>, bool), Uploaded> = HashMap::new();
    let mut texture_of =
        |t: Option<&TextureRef>, srgb: bool| -> Result<(Option<usize>, bool), GpuError> {
            let index = t.map(|t| t.texture);
            let key = (index, srgb);
            if let std::collections::hash_map::Entry::Vacant(slot) = uploaded.entry(key) {
                let texture = match index {
                    None => &white,
                    Some(i) => textures.get(i).ok_or_else(|| {
                        GpuError::Invalid(format!(
                            "a material reads texture {i}; the scene has {}",
                            textures.len()
                        ))
                    })?,
                };
                slot.insert(upload(ctx, texture, srgb)?);
            }
            Ok(key)
        };
    let mut keys = Vec::with_capacity(materials.len());
    for m in materials {
        keys.push((
            texture_of(m.base_color_texture.as_ref(), true)?,
            texture_of(m.metallic_roughness_texture.as_ref(), false)?,
        ));
    }
    let device = &ctx.device;
    Ok(materials
        .iter()
        .zip(keys)
        .map(|(m, (base, metal))| {
            let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("material"),
                contents: bytemuck::bytes_of(&MaterialUniform::new(m)),
                usage: wgpu::BufferUsages::UNIFORM,
            });
            let (base, metal) = (&uploaded[&base], &uploaded[&metal]);
            let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("material"),
                layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: uniform.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: wgpu::BindingResource::TextureView(&base.view),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: wgpu::BindingResource::Sampler(&base.sampler),
                    },
                    wgpu::BindGroupEntry {
                        binding: 3,
                        resource: wgpu::BindingResource::TextureView(&metal.view),
                    },
                    wgpu::BindGroupEntry {
                        binding: 4,
                        resource: wgpu::BindingResource::Sampler(&metal.sampler),
                    },
                ],
            });
            GpuMaterial { bind }
        })
        .collect())
}

/// `texture` with its mip chain (`Rgba8UnormSrgb` when `srgb`, else
/// `Rgba8Unorm`) and its sampler.
fn upload(ctx: &GpuContext, texture: &Texture, srgb: bool) -> Result<Uploaded, GpuError> {
    if texture.width == 0
        || texture.height == 0
        || texture.texels.len() != texture.width * texture.height
    {
        return Err(GpuError::Invalid(format!(
            "a texture of {}x{} texels holds {}",
            texture.width,
            texture.height,
            texture.texels.len()
        )));
    }
    let device = &ctx.device;
    let levels = mip_chain(
        texture.width,
        texture.height,
        &texture.texels,
        srgb,
        device.limits().max_texture_dimension_2d,
    );
    let data: Vec<u8> = levels
        .iter()
        .flat_map(|l| l.texels.iter().flatten().copied())
        .collect();
    let format = if srgb {
        wgpu::TextureFormat::Rgba8UnormSrgb
    } else {
        wgpu::TextureFormat::Rgba8Unorm
    };
    let gpu = ctx.checked(|| {
        device.create_texture_with_data(
            &ctx.queue,
            &wgpu::TextureDescriptor {
                label: Some("material texture"),
                size: wgpu::Extent3d {
                    width: levels[0].width,
                    height: levels[0].height,
                    depth_or_array_layers: 1,
                },
                mip_level_count: levels.len() as u32,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
                view_formats: &[],
            },
            wgpu::util::TextureDataOrder::LayerMajor,
            &data,
        )
    })?;
    let address = |w: Wrap| match w {
        Wrap::Repeat => wgpu::AddressMode::Repeat,
        Wrap::MirroredRepeat => wgpu::AddressMode::MirrorRepeat,
        Wrap::ClampToEdge => wgpu::AddressMode::ClampToEdge,
    };
    let filter = match texture.filter {
        Filter::Linear => wgpu::FilterMode::Linear,
        Filter::Nearest => wgpu::FilterMode::Nearest,
    };
    let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("material texture"),
        address_mode_u: address(texture.wrap_u),
        address_mode_v: address(texture.wrap_v),
        address_mode_w: wgpu::AddressMode::Repeat,
        mag_filter: filter,
        min_filter: filter,
        mipmap_filter: wgpu::MipmapFilterMode::Linear,
        ..Default::default()
    });
    Ok(Uploaded {
        view: gpu.create_view(&Default::default()),
        sampler,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_uniform_block_has_the_wgsl_size_and_codes() {
        // Material in material.wgsl: vec4<f32>, f32, f32, u32, padding.
        assert_eq!(std::mem::size_of::<MaterialUniform>(), 32);
        let mask = Material {
            alpha_mode: AlphaMode::Mask { cutoff: 0.25 },
            metallic: 0.5,
            ..Material::default()
        };
        let u = MaterialUniform::new(&mask);
        assert_eq!((u.alpha_mode, u.cutoff, u.metallic), (1, 0.25, 0.5));
        let blend = MaterialUniform::new(&Material {
            alpha_mode: AlphaMode::Blend,
            ..Material::default()
        });
        assert_eq!(blend.alpha_mode, 2);
    }
}
