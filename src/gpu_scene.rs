//! What `render-mesh` and `view` hand the GPU renderer: the mesh, its PRT
//! transfer (`--prt`), the light and the map (`--env`), and the lmax to
//! shade at.

use anyhow::{Result, bail};
use shlight_core::{Encoded, Encoding};
use shlight_format::{CoeffFile, ExportFormat, FileEncoding, Quantity};
use shlight_gpu::{GpuContext, MAX_LMAX, Renderer, Transfer, wgpu};
use shlight_mesh::Mesh;
use shlight_prt::ShprtFile;

use crate::environment::Environment;

/// Refuses an `--lmax` above what the GPU shades.
pub fn check_lmax(lmax: Option<usize>) -> Result<()> {
    if let Some(lmax) = lmax.filter(|&l| l > MAX_LMAX) {
        bail!("--lmax {lmax}: the GPU shades to lmax {MAX_LMAX}");
    }
    Ok(())
}

/// The lmax to shade at: `--lmax`, else the transfer's (to [`MAX_LMAX`])
/// when shading by PRT, else 2.
pub fn shading_lmax(requested: Option<usize>, prt: Option<&ShprtFile>) -> usize {
    requested.unwrap_or_else(|| prt.map_or(2, |t| t.lmax.min(MAX_LMAX)))
}

/// `env`'s light kept as `encoding` ([`Environment::encode`], the SH part
/// to `lmax`) and its WGSL snippet (as `shlight project MAP --encoding E
/// --format wgsl` writes it), for [`Renderer::set_encoding`]. `env`'s plain
/// SH to `lmax` is kept beside it as a coefficient file keeps it
/// (`sloan+sh` finds its light again from them).
///
/// # Errors
/// As [`Environment::encode`], and values a 32-bit float cannot hold.
pub fn encoded_light(
    env: &Environment,
    encoding: Encoding,
    lmax: usize,
) -> Result<(Encoded, String)> {
    let encoded = env.encode(encoding, lmax)?;
    let sh = env.radiance.resized(lmax);
    let (record, coeffs) = FileEncoding::from_encoded(encoding, &encoded, &sh);
    let mut file = CoeffFile::new(coeffs, env.orientation.frame, Quantity::Radiance);
    file.mirror = env.orientation.mirror;
    file.encoding = record;
    let exported = shlight_format::export(&file, ExportFormat::Wgsl)
        .map_err(|e| anyhow::anyhow!("{}: {e}", env.path.display()))?;
    Ok((encoded, exported.text))
}

/// A renderer for colour targets of `format` with no mesh: the light of
/// `env` and its map, for the background behind a volume pass.
pub fn background_renderer(
    ctx: &GpuContext,
    format: wgpu::TextureFormat,
    env: &Environment,
) -> Renderer {
    let mut renderer = Renderer::new(ctx, format);
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
    renderer
}

/// A renderer for colour targets of `format` holding `mesh`, its
/// `transfer` (if any), the light of `env` and its map (if any).
///
/// # Errors
/// A transfer the GPU cannot hold.
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
        let t = Transfer::new(t.lmax, t.channels, t.vertex_count, &t.transfer)?;
        renderer.set_transfer(ctx, &t)?;
    }
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
    Ok(renderer)
}
