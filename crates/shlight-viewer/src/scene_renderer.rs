//! What `render-mesh` and `view` hand the GPU renderer: the mesh, its PRT
//! transfer (`--prt`), the light and the map (`--env`, a
//! `shlight_pipeline::Environment` projected to the GPU's lmax), and the
//! lmax to shade at.

use anyhow::{Result, bail};
use shlight_baked::LIGHT_MAX_LMAX;
use shlight_format::ShprtFile;
use shlight_gpu::{GlossyLobe, GpuContext, Renderer, wgpu};
use shlight_mesh::Mesh;
use shlight_pipeline::Environment;

/// Refuses an `--lmax` above what the GPU shades.
pub fn check_lmax(lmax: Option<usize>) -> Result<()> {
    if let Some(lmax) = lmax.filter(|&l| l > LIGHT_MAX_LMAX) {
        bail!("--lmax {lmax}: the GPU shades to lmax {LIGHT_MAX_LMAX}");
    }
    Ok(())
}

/// The lmax to shade at: `--lmax`, else the transfer's (to [`LIGHT_MAX_LMAX`])
/// when shading by PRT, else 2.
pub fn shading_lmax(requested: Option<usize>, prt: Option<&ShprtFile>) -> usize {
    requested.unwrap_or_else(|| prt.map_or(2, |t| t.lmax.min(LIGHT_MAX_LMAX)))
}

/// Gives `renderer` the light of `env` and its map, if it has one.
fn set_light(renderer: &mut Renderer, ctx: &GpuContext, env: &Environment) {
    renderer.set_light(ctx, &env.radiance);
    if let Some(map) = &env.map {
        renderer.set_environment(
            ctx,
            map.width(),
            map.height(),
            map.pixels(),
            env.orientation,
        );
    }
}

/// A renderer for colour targets of `format` with no mesh: the light of
/// `env` and its map, for the background behind a volume pass.
pub fn background_renderer(
    ctx: &GpuContext,
    format: wgpu::TextureFormat,
    env: &Environment,
) -> Renderer {
    let mut renderer = Renderer::new(ctx, format);
    set_light(&mut renderer, ctx, env);
    renderer
}

/// A renderer for colour targets of `format` holding `mesh`, its
/// `transfer` (if any: diffuse transfer vectors, or glossy matrices with
/// their lobe), the light of `env` and its map (if any).
///
/// # Errors
/// A transfer the GPU cannot hold, or a glossy file's unknown BRDF.
pub fn renderer(
    ctx: &GpuContext,
    format: wgpu::TextureFormat,
    mesh: &Mesh,
    transfer: Option<&ShprtFile>,
    env: &Environment,
) -> Result<Renderer> {
    let mut renderer = Renderer::new(ctx, format);
    renderer.set_mesh(ctx, mesh);
    if let Some(t) = transfer {
        match (t.glossy_view()?, &t.glossy) {
            (Some(matrices), Some(g)) => {
                let brdf = shlight_prt::Brdf::parse(&g.brdf).map_err(anyhow::Error::msg)?;
                match brdf.lobe(t.lmax) {
                    shlight_prt::BrdfLobe::Zonal(lambda) => {
                        renderer.set_glossy(ctx, &matrices, GlossyLobe::Zonal(&lambda))?;
                    }
                    shlight_prt::BrdfLobe::Ggx(lobe) => renderer.set_glossy(
                        ctx,
                        &matrices,
                        GlossyLobe::Directions(&lobe.direction_table()),
                    )?,
                }
            }
            _ => renderer.set_transfer(ctx, &t.view()?)?,
        }
    }
    set_light(&mut renderer, ctx, env);
    Ok(renderer)
}
