//! The [`Renderer`]s of a scene: [`mesh_renderer`] (a mesh, its
//! transfer, the light and its map) and [`light_renderer`] (the light and
//! its map alone, the background behind a volume pass).

use shlight_format::ShprtFile;
use shlight_mesh::Mesh;
use shlight_pipeline::Environment;

use super::SceneError;
use super::transfer_file::set_transfer;
use crate::{GpuContext, Renderer};

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
/// `transfer` (if any: diffuse transfer vectors, or glossy matrices with
/// their lobe), the light of `light` and its map (if any).
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
