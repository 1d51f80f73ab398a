//! The geometric groundwork of lightmap baking: which texels of a
//! lightmap a mesh's UV triangles cover and where each is sampled, whether
//! a mesh's UVs overlap, and the padding around its charts.
//!
//! # Main items
//! - [`TexelRaster`]: a mesh's UV triangles rasterised conservatively
//!   onto a `W x H` grid of texels, optionally through a [`Placement`]
//!   (`uv * scale + offset`: an instance's region of a shared atlas). Each
//!   texel any triangle overlaps with positive area, however little, gets
//!   a [`TexelSample`]: its owner (the triangle overlapping it most), a
//!   sample point inside both the owner and the texel (the centroid of the
//!   triangle clipped to the texel, as barycentric weights), and the
//!   fraction of it the mesh covers. [`texel_pieces`] is the step under
//!   it: one triangle cut to the texels it overlaps, areas and centroids
//!   in `f64`.
//! - [`first_uv_overlap`]: the first two triangles of a mesh whose
//!   interiors overlap in a UV set ([`UvOverlap`]), found through a uniform
//!   grid over the triangles' boxes in near-linear time; shared edges and
//!   corners are no overlap.
//! - [`TexelFormat`]: what a texel holds for an engine ([`Engine`]:
//!   three.js, Bevy, Godot, Unity with Bakery) in a basis ([`TexelBasis`]:
//!   irradiance, L1 SH, MonoSH), with its [`L1Reconstruction`]:
//!   [`TexelFormat::pack`] turns a texel's lmax-1 radiance SH into the
//!   engine's layers ([`PackedTexel`]), [`TexelFormat::reconstruct`] ports
//!   the engine's shader back to light. Under them, [`DiffuseL1`] (the
//!   irradiance `a + b . n` per channel, in [`TexelUnits`]) and
//!   [`geomerics_l1`] (the non-linear reconstruction). docs/lightmaps.md
//!   quotes each shader.
//! - [`denoise`]: an edge-aware filter over a lightmap's texels, guided
//!   by each texel's position and normal ([`TexelGuide`]), never across a
//!   geometric edge.
//! - [`dilate`]: empty texels filled from the mean of their valid
//!   neighbours, pass by pass, for any value that can be averaged
//!   ([`Blend`]).
//!
//! # Conventions
//! - **Texel coordinates.** A UV `(u, v)` lands at `(u W, v H)`; texel
//!   `(x, y)` covers `[x, x + 1] x [y, y + 1]`, so its centre is at
//!   `((x + 1/2) / W, (y + 1/2) / H)` in UV. Row `y = 0` holds `v` near 0:
//!   glTF puts the UV origin at an image's top-left corner, so row 0 is
//!   the image's first row, stored first (no flip). Texels are stored row
//!   by row, texel `(x, y)` at index `y W + x`.
//! - **Placement.** `uv' = uv * scale + offset`, applied before the
//!   texel mapping (Unity's `lightmapScaleOffset`; Bevy's
//!   `Lightmap::uv_rect` from `min` to `max` is scale `max - min`, offset
//!   `min`).
//! - **Coverage.** A texel's pieces are the convex polygons of
//!   Sutherland-Hodgman clipping of each triangle to the texel square, in
//!   `f64`; areas are fractions of a texel, so one triangle's pieces sum
//!   to its UV area times `W H`. A texel belongs to the triangle with the
//!   largest piece (the lowest index among equals); its coverage is the
//!   sum of all pieces, at most 1. Parts of triangles outside the unit
//!   square are dropped.
//! - **Barycentric weights** are in the order of the triangle's corners
//!   as listed: the sample point is `w0 a + w1 b + w2 c`. Either winding is
//!   accepted.
//! - **Degenerate triangles** (zero UV area, collinear corners to
//!   rounding: twice the area at most `1e-12` of the longest edge squared)
//!   cover nothing and overlap nothing; the raster counts them.
//! - **Errors.** An index past the UVs or a UV that is not finite is an
//!   error naming the triangle ([`UvError`]); nothing panics on bad input.
//!
//! - [`bake_scene_lightmap`]: a glTF scene's lightmap: a square region of
//!   one atlas per placed node ([`pack_squares`]), its texels rasterised
//!   onto its second UV set and the light gathered at each
//!   (`shlight_volume::gather_at_surface_points`), texels inside geometry
//!   and the padding filled by dilation; [`SceneLightmap::layers`] packs
//!   it for an engine.
//!
//! No I/O, no GPU.

mod atlas;
mod denoise;
mod diffuse_l1;
mod dilate;
mod engine_packing;
mod geomerics;
mod lightmap_error;
mod placement;
mod polygon;
mod scene_lightmap;
mod seams;
mod texel_format;
mod texel_raster;
mod uv_error;
mod uv_overlap;
mod uv_triangles;

pub use atlas::{TexelRect, pack_squares, smallest_atlas};
pub use denoise::{FACING_POWER, TexelGuide, denoise};
pub use diffuse_l1::{DiffuseL1, TexelUnits};
pub use dilate::{Blend, GridShapeError, dilate};
pub use engine_packing::PackedTexel;
pub use geomerics::geomerics_l1;
pub use lightmap_error::LightmapError;
pub use placement::Placement;
pub use scene_lightmap::{
    DEFAULT_DENOISE, LightmapRegion, LightmapSettings, LightmapSize, MAX_DENOISE, SceneLightmap,
    TexelLight, bake_scene_lightmap,
};
pub use seams::{SMOOTH_COS, STITCH_SWEEPS, Seam, SeamCorner, find_seams, stitch_seams};
pub use texel_format::{Engine, L1Reconstruction, TexelBasis, TexelFormat, TexelFormatError};
pub use texel_raster::{MAX_SIDE, TexelPiece, TexelRaster, TexelSample, texel_pieces};
pub use uv_error::UvError;
pub use uv_overlap::{OVERLAP_TOLERANCE, UvOverlap, first_uv_overlap};
