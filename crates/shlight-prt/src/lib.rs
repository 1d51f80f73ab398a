//! Precomputed radiance transfer (Sloan, Kautz & Snyder 2002) for shlight:
//! per-vertex diffuse transfer vectors for any mesh, so a renderer shades
//! soft shadows and bounce light under any distant SH lighting with one dot
//! product per vertex.
//!
//! # Main items
//! - [`bvh::Bvh`]: binned-SAH hierarchy with a watertight ray/triangle test;
//!   occlusion and closest-hit queries with barycentrics for single rays.
//! - [`packet::PacketBvh`]: the same hierarchy traced by packets of eight
//!   parallel rays with AVX2, what baking uses.
//! - [`transfer::bake`]: unshadowed, shadowed and interreflected transfer
//!   to any lmax, constant or per-vertex albedo, in parallel and
//!   deterministic for a seed ([`transfer`] states the estimator).
//! - [`glossy::bake_glossy`]: glossy transfer matrices `M_p` (shadowed or
//!   with diffuse interreflections), and [`glossy::exit_radiance`], the
//!   view-dependent exit radiance of a [`brdf::Brdf`] lobe ([`glossy`]
//!   states the definition).
//! - [`cpca::compress`]: clustered PCA of glossy matrices (Sloan, Hall,
//!   Hart & Snyder 2003), [`cpca::Cpca::reconstruct`], and
//!   [`cpca::compress_file`], a glossy `.shprt` file compressed.
//! - [`transfer::Transfer::to_shprt`]: the bake as a `.shprt` file
//!   ([`shlight_format::ShprtFile`], docs/shprt.md).
//! - [`bake_file::bake_file`]: a bake as a front end asks for it
//!   ([`bake_file::BakeRequest`], `shlight prt`'s options: the albedo
//!   chosen, the bake, its `.shprt` file), for the command line and the
//!   Python package alike.
//! - [`gltf_export::write_gltf`]: the mesh with `_SH_TRANSFER_k` attributes.
//! - [`preview::render`]: a CPU z-buffer rasteriser of vertex colours;
//!   [`preview::vertex_exposure`] the exposure to show them at.
//!
//! # Shading convention
//! Exit radiance = transfer . (light radiance coefficients): albedo/pi is
//! folded into the transfer, the light is the radiance `L_lm` of
//! docs/conventions.md (not irradiance). A grey transfer (1 channel) is
//! applied to each colour channel of the light.
//!
//! ```
//! use shlight_core::sh::closed_form;
//! use shlight_mesh::generate;
//! use shlight_prt::transfer::{bake, BakeOptions, Mode};
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
//! written through shlight-io's atomic writer.

pub mod bake_file;
pub mod brdf;
pub mod brute_force;
pub mod bvh;
pub mod cpca;
mod error;
pub mod ggx_lobe;
pub mod glossy;
pub mod gltf_export;
pub mod packet;
pub mod preview;
pub mod records;
pub mod transfer;

pub use error::PrtError;

/// For shlight's own tests (this crate's, its test binaries' and
/// shlight-volume's): reports a test, or the part of it that needs AVX2 and
/// FMA, as skipped. Prints `SKIPPED test: why` with `write!` on the
/// process's stderr handle, which the test harness does not capture (it
/// captures only the `print!`/`eprint!` macros), so the line shows in a
/// passing run; panics under `SHLIGHT_REQUIRE_ALL=1`, where no test may
/// skip.
#[doc(hidden)]
pub fn skip_test(test: &str, why: &str) {
    if std::env::var("SHLIGHT_REQUIRE_ALL").as_deref() == Ok("1") {
        panic!("{test}: SHLIGHT_REQUIRE_ALL=1 but it would be skipped: {why}");
    }
    use std::io::Write as _;
    let _ = writeln!(std::io::stderr(), "SKIPPED {test}: {why}");
}
