//! The specular half of image-based lighting: an environment prefiltered
//! with the GGX lobe into a cube map with mips, and the DFG table of the
//! split-sum approximation (Karis 2013, "Real Shading in Unreal Engine 4").
//!
//! Engines light a surface from an environment in two halves: the diffuse
//! half (SH irradiance, shlight-core) and the specular half, the
//! environment convolved with the GGX lobe at several roughnesses, one mip
//! each, times a table of the BRDF's directional albedo (DFG). This crate
//! makes the second half:
//!
//! - [`prefilter()`]: a map ([`shlight_core::map::EnvMap`], any layout) into
//!   a [`Prefiltered`] cube, mip `k` at the roughness the target
//!   [`TargetEngine`]'s shader reads it at, in that engine's cube axes; GGX
//!   importance sampling with source-mip filtering by each sample's
//!   density (Colbert & Krivanek 2007), as Filament's cmgen does;
//! - [`DfgTable`], [`dfg()`]: the table, as scale and bias of `F0` or
//!   Filament's multiscatter form; [`dfg_karis_approx`] Karis' fit;
//! - [`d_ggx`], [`sample_ggx_half`], [`hammersley`], [`MaskingShadowing`]: the
//!   lobe, its sampling, the Hammersley points, masking and shadowing;
//! - [`rgbd_encode`], [`rgbd_decode`]: Babylon's RGBD encoding of HDR texels in 8-bit RGBA, what
//!   glTF's `EXT_lights_image_based` specular images hold.
//!
//! Everything is deterministic (fixed Hammersley points, independent
//! texels, `f64` sums) and parallel over rows (rayon).
//!
//! ```
//! use shlight_core::map::{EnvMap, Layout, MapOrientation};
//! use shlight_specular::{PrefilterSettings, TargetEngine, prefilter};
//!
//! // A constant sky stays constant at every roughness.
//! let pixels = vec![[0.5f32; 3]; 32 * 16];
//! let map = EnvMap::new(Layout::Equirect, MapOrientation::default(), 32, 16, &pixels).unwrap();
//! let settings = PrefilterSettings { size: 8, samples: 64, ..PrefilterSettings::new(TargetEngine::Bevy) };
//! let cube = prefilter(&map, &settings, &|_| {}).unwrap();
//! assert_eq!(cube.levels.len(), 4);
//! for level in &cube.levels {
//!     assert!(level.cube.strip().iter().all(|p| (p[0] - 0.5).abs() < 1e-5));
//! }
//! ```
//!
//! **Invariant:** no I/O, no GPU; files are written by shlight-pipeline.

mod bordered_cube;
mod cube_image;
mod dfg;
mod ggx;
mod prefilter;
mod rgbd;
mod source_mips;
mod target_engine;

pub use bordered_cube::{BorderedCube, FacePoint};
pub use cube_image::CubeImage;
pub use dfg::{DfgForm, DfgTable, dfg, dfg_karis_approx};
pub use ggx::{MaskingShadowing, d_ggx, hammersley, sample_ggx_half};
pub use prefilter::{
    PrefilterError, PrefilterSettings, Prefiltered, PrefilteredLevel, prefilter, prefilter_source,
};
pub use rgbd::{rgbd_decode, rgbd_encode};
pub use source_mips::{MAX_SOURCE_SIZE, SourceMips};
pub use target_engine::{ParseTargetEngineError, TargetEngine};
