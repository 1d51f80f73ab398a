//! Precomputed radiance transfer (Sloan, Kautz & Snyder 2002) for shlight:
//! per-vertex diffuse transfer vectors for any mesh, so a renderer shades
//! soft shadows and bounce light under any distant SH lighting with one dot
//! product per vertex. The rays are cast by shlight-rays.
//!
//! # Main items
//! - [`bake`]: unshadowed, shadowed and interreflected [`Transfer`] to any
//!   lmax ([`BakeOptions`]: [`Mode`], [`Albedo`], samples, seed, emission,
//!   and the surfaces of a glTF scene: cut-outs the rays pass and the
//!   albedo of the texel a bounce hits, [`IncidentTransfer`]),
//!   in parallel and deterministic for a seed ([`Transfer`] states the
//!   definitions, [`bake`] the estimator); [`bake_with_occluder`] and
//!   [`bake_against`] cast a subdivided mesh's rays against the mesh it was
//!   subdivided from ([`shlight_rays::Occluder`]). A glTF material's
//!   `doubleSided` makes its triangles surfaces on both faces
//!   ([`BackSides`]; their back's light in [`Transfer::back`],
//!   [`BackTransfer`]).
//! - [`bake_glossy`]: glossy transfer matrices `M_p` ([`GlossyTransfer`],
//!   shadowed or with diffuse interreflections), and
//!   [`glossy_exit_radiance`], the view-dependent exit radiance of a
//!   [`Brdf`] lobe ([`GlossyTransfer`] states the definition);
//!   [`glossy_shade`] with a diffuse base; [`file_shade`] and
//!   [`file_exit_radiance`] on a `.shprt` file of either kind.
//! - [`compress`]: clustered PCA of glossy matrices (Sloan, Hall, Hart &
//!   Snyder 2003), [`Cpca::reconstruct`], and [`compress_file`], a glossy
//!   `.shprt` file compressed.
//! - [`Transfer::to_shprt`]: the bake as a `.shprt` file
//!   ([`shlight_format::ShprtFile`], docs/shprt.md).
//! - [`bake_file`]: a bake as a front end asks for it ([`BakeRequest`],
//!   `shlight prt`'s options: the albedo chosen, the bake, its `.shprt`
//!   file), for the command line and the Python package alike.
//! - [`bake_scene_file`]: a glTF scene's bake ([`SceneLighting`]: its
//!   surfaces and punctual lights, [`punctual_irradiance`]), the transfer
//!   and a static term per vertex in one `.shprt` file.
//! - [`write_gltf`]: the mesh with `_SH_TRANSFER_k` attributes.
//! - [`render_preview`]: a CPU z-buffer rasteriser of vertex colours;
//!   [`vertex_exposure`] the exposure to show them at.
//! - [`Transfer::records`] ([`VertexRecords`]) and [`Kernels`]: a bake's
//!   vectors as the summing kernels read them, and which kernels run; the
//!   bounces and shlight-volume's probe sums share both.
//!
//! # Shading convention
//! Exit radiance = transfer . (light radiance coefficients): albedo/pi is
//! folded into the transfer, the light is the radiance `L_lm` of
//! docs/conventions.md (not irradiance). A grey transfer (1 channel) is
//! applied to each colour channel of the light; every reader of a bake
//! shades with [`shlight_baked::TransferView::exit_radiance`].
//!
//! ```
//! use shlight_core::sh::closed_form;
//! use shlight_mesh::generate;
//! use shlight_prt::{BakeOptions, Mode, bake};
//!
//! let sphere = generate::uv_sphere(1.0, 16, 8);
//! let options = BakeOptions { mode: Mode::Shadowed, samples: 256, ..BakeOptions::default() };
//! let t = bake(&sphere, &options, &|_, _, _| {});
//! // Under constant radiance 1, a convex surface of albedo 0.8 leaves 0.8.
//! let light = closed_form::constant(4, glam::DVec3::ONE);
//! let top = t.exit_radiance(&light)[0];
//! assert!((top.x - 0.8).abs() < 1e-5);
//! ```
//!
//! **Architecture invariant:** no GPU and no command line; files are
//! written through shlight-io's atomic writer; rays only through
//! shlight-rays's public items.

mod back_sides;
mod bake;
mod bake_file;
mod brdf;
mod cast;
mod cpca;
mod error;
mod gather;
mod ggx_lobe;
mod glossy;
mod gltf_export;
mod options;
mod preview;
mod punctual;
mod records;
mod transfer;

pub use back_sides::BackSides;
pub use bake::{bake, bake_against, bake_with_occluder};
pub use bake_file::{
    BakeRequest, DEFAULT_ALBEDO, DEFAULT_BOUNCES, MAX_BAKE_LMAX, SceneLighting, bake_file,
    bake_glossy_file, bake_scene_file, mesh_name,
};
pub use brdf::{Brdf, BrdfLobe, MAX_PHONG_EXPONENT};
pub use cpca::{CompressionError, Cpca, compress, compress_file, parse_cpca, reconstruct_data};
pub use error::PrtError;
pub use ggx_lobe::{GgxLobe, MIN_GGX_ALPHA};
pub use glossy::{
    GlossyTransfer, MAX_GLOSSY_BYTES, Observer, bake_glossy, file_exit_radiance, file_shade,
    glossy_bytes, glossy_channels, glossy_exit_radiance, glossy_shade,
};
pub use gltf_export::write_gltf;
pub use options::{Albedo, BakeOptions, Mode, Stage};
pub use preview::{render_preview, vertex_exposure};
pub use punctual::{light_counts, light_reaches, punctual_irradiance};
pub use records::{Kernels, VertexRecords};
pub use transfer::{BackTransfer, IncidentTransfer, Transfer};
