//! The [`Renderer`]s of a scene: [`scene_renderer`] (the scene read,
//! through one of the next two), [`mesh_renderer`] (a mesh, its transfer,
//! the light and its map), [`gltf_renderer`] (a glTF scene with its
//! materials, textures and instances, its transfer, the light and its
//! map) and [`light_renderer`] (the light and its map alone, the
//! background behind a volume pass).

use shlight_baked::TransferView;
use shlight_format::ShprtFile;
use shlight_mesh::Mesh;
use shlight_pipeline::Environment;

use super::transfer_file::{per_unit_albedo, set_transfer, static_radiance};
use super::{GltfScene, Scene, SceneError};
use crate::{GpuContext, LightmapTexels, Renderer};

/// Gives `renderer` the light of `light` and its map, if it has one.
fn set_light(renderer: &mut Renderer, ctx: &GpuContext, light: &Environment) {
    renderer.set_light(ctx, &light.radiance);
    if let Some(map) = &light.map {
        renderer.set_environment(
            ctx,
            map.width(),
            map.height(),
            map.pixels(),
            light.orientation,
        );
    }
}

/// A renderer for colour targets of `format` with no mesh: the light of
/// `light` and its map, for the background behind a volume pass.
#[must_use]
pub fn light_renderer(
    ctx: &GpuContext,
    format: wgpu::TextureFormat,
    light: &Environment,
) -> Renderer {
    let mut renderer = Renderer::new(ctx, format);
    set_light(&mut renderer, ctx, light);
    renderer
}

/// A renderer for colour targets of `format` holding `mesh`, its
/// `transfer` (if any: diffuse transfer vectors with their static term,
/// or glossy matrices with their lobe), the light of `light` and its map
/// (if any).
///
/// # Errors
/// A transfer the GPU cannot hold, or a glossy file's unknown BRDF.
pub fn mesh_renderer(
    ctx: &GpuContext,
    format: wgpu::TextureFormat,
    mesh: &Mesh,
    transfer: Option<&ShprtFile>,
    light: &Environment,
) -> Result<Renderer, SceneError> {
    let mut renderer = Renderer::new(ctx, format);
    renderer.set_mesh(ctx, mesh);
    if let Some(file) = transfer {
        set_transfer(&mut renderer, ctx, file)?;
    }
    set_light(&mut renderer, ctx, light);
    Ok(renderer)
}

/// A renderer for colour targets of `format` holding `gltf`, its
/// `transfer` (if any) and the light of `light` and its map (if any):
///
/// - without a transfer, each unique primitive drawn once per instance
///   with its material ([`Renderer::set_scene`]);
/// - with a diffuse transfer (baked for the flattened scene, per world
///   vertex), the flattened scene with its materials
///   ([`Renderer::set_surfaces`]), the transfer per unit albedo
///   ([`per_unit_albedo`]) and the file's static term
///   ([`static_radiance`]): PRT mode shows the transferred radiance times
///   each fragment's albedo, plus the static exit radiance interpolated;
/// - with a glossy transfer, the flattened mesh as [`mesh_renderer`] draws
///   a mesh (the glossy layer per vertex; no textures).
///
/// # Errors
/// As [`mesh_renderer`], and a scene the GPU refuses (an index beyond its
/// materials or textures, a singular transform).
pub fn gltf_renderer(
    ctx: &GpuContext,
    format: wgpu::TextureFormat,
    gltf: &GltfScene,
    transfer: Option<&ShprtFile>,
    light: &Environment,
) -> Result<Renderer, SceneError> {
    let mut renderer = Renderer::new(ctx, format);
    match transfer {
        None => renderer.set_scene(ctx, &gltf.scene, gltf.default_albedo)?,
        Some(file) if file.glossy.is_none() => {
            renderer.set_surfaces(ctx, &gltf.surfaces)?;
            let albedo = gltf.mesh().colors.as_deref().unwrap_or(&[]);
            let data = per_unit_albedo(file, albedo);
            let view = TransferView::new(file.lmax, file.channels, file.vertex_count, &data)?;
            renderer.set_transfer_with_static(ctx, &view, static_radiance(file))?;
        }
        Some(file) => return mesh_renderer(ctx, format, gltf.mesh(), Some(file), light),
    }
    set_light(&mut renderer, ctx, light);
    Ok(renderer)
}

/// The renderer of `scene` for colour targets of `format`: its glTF scene
/// ([`gltf_renderer`]; drawn by its lightmap with
/// [`Renderer::set_scene_with_lightmap`] when it has one) or its mesh
/// ([`mesh_renderer`]), with its transfer and light.
///
/// # Errors
/// As [`gltf_renderer`] and [`mesh_renderer`].
pub fn scene_renderer(
    ctx: &GpuContext,
    format: wgpu::TextureFormat,
    scene: &Scene,
) -> Result<Renderer, SceneError> {
    match (&scene.gltf, &scene.lightmap) {
        (Some(gltf), Some(lightmap)) => {
            let mut renderer = Renderer::new(ctx, format);
            let layers: Vec<&[[f32; 4]]> = lightmap
                .atlas
                .layers
                .iter()
                .map(|l| l.texels.as_slice())
                .collect();
            renderer.set_scene_with_lightmap(
                ctx,
                &gltf.scene,
                gltf.default_albedo,
                &LightmapTexels {
                    format: lightmap.atlas.format,
                    side: lightmap.atlas.side,
                    layers: &layers,
                    instances: &lightmap.instances,
                },
            )?;
            set_light(&mut renderer, ctx, &scene.light);
            Ok(renderer)
        }
        (Some(gltf), None) => {
            gltf_renderer(ctx, format, gltf, scene.transfer.as_ref(), &scene.light)
        }
        (None, _) => mesh_renderer(
            ctx,
            format,
            &scene.mesh,
            scene.transfer.as_ref(),
            &scene.light,
        ),
    }
}
