//! The map wing: environment maps. The geometry of every image layout, the
//! sources projections read texels from, projection to SH, Monte Carlo
//! projection, lights drawn into maps, the exact irradiance of a map,
//! coefficients rendered back into a map, and a function drawn as its
//! lobe. It builds on the SH wing and
//! knows nothing of files: a map is a borrowed slice of linear RGB texels.
//!
//! # Layouts and orientation
//!
//! [`Layout`] names how a map's texels are arranged (equirect, the cube
//! crosses and strip, the angular map, the mirror ball) and holds their
//! geometry: each texel that holds a direction has a unit direction at its
//! centre in the map's own y-up frame, taken to the world by a
//! [`MapOrientation`] (which world axis is up, a [`Frame`](crate::sh::Frame),
//! and whether azimuth runs mirrored), and the exact solid angle it covers,
//! so that every layout's solid angles sum to `4π`. An equirect texel of a
//! `W x H` map sits at `θ = π (y + 1/2)/H`, `φ = 2π ((x + 1/2)/W - 1/2)`
//! ([`equirect_angles`], [`equirect_direction`]) and every texel of row `j`
//! covers `Ω_j = (2π/W)(cos(jπ/H) - cos((j+1)π/H))`
//! ([`equirect_row_solid_angle`]); cube texels have a closed form
//! ([`cube_texel_solid_angle`], faces [`CubeFace`], cells [`FaceCell`]);
//! disc texels integrate `dω = w(r) dA` over their part of the disc.
//! [`EnvMap`] is a borrowed image in one layout with its lookups;
//! [`TexelGrid`] the same geometry without pixels, for drawing maps;
//! [`LayoutSizeError`] ([`LayoutSizeErrorKind`]) says why a size does not
//! fit a layout, [`ParseLayoutError`] why a name is none.
//!
//! # Texel sources
//!
//! [`TexelSource`]: the texels of a map however they are stored, which is
//! what projection reads: [`EnvMap`] and [`EquirectView`] (contiguous),
//! [`StridedImage`] (rows a pitch apart), [`CubeFaces`] (six separate
//! faces, seen as a strip), or a type of the caller's. Readers that need
//! rows or the whole image contiguous take them through [`read_row`] and
//! [`contiguous_pixels`]: in place where the source stores them so, copied
//! otherwise.
//!
//! # Projection
//!
//! [`project`] estimates `L_l^m ≈ Σ f(texel) Y_l^m(d(texel)) Ω(texel)`
//! over the texels of any source, in `f64`, exact for constants and with an
//! `O(h²)` error in the texel size for smooth functions. Equirect maps take
//! the ring transform: rows are rings about the map's pole, so per row
//! azimuthal sums `C_m`, `S_m` (direct, or a real FFT from lmax 48), then per
//! order `m` Legendre sums over symmetric pairs of rows, in `O(W H min(lmax,
//! log W) + H lmax²)`, vectorised with AVX and FMA where the CPU has them;
//! a y-up map's z-up coefficients are then turned by a quarter turn
//! ([`to_frame`]). The other layouts sum texel by texel with the basis
//! evaluated in batches. [`project_map`] and [`project_equirect`] are
//! [`project`] for the crate's own maps; [`project_equirect_simple`] is the
//! plain equirect sum the ring transform is tested against. Rows are summed
//! in fixed bands, so a result repeats bit for bit for any thread count.
//! [`RingAccumulator`] is the same ring transform fed rows as a file is
//! decoded (any order, any thread), without an image buffer, and equal to
//! [`project`]'s result bit for bit.
//!
//! # Monte Carlo
//!
//! [`montecarlo`]: the unbiased estimator `(1/N) Σ L(ω_i) Y(ω_i) / p(ω_i)`
//! with uniform, stratified, scrambled Sobol and luminance-importance
//! sampling, and standard errors, over any [`RadianceMap`] (a lookup of
//! radiance by direction; [`luminance`] weighs RGB by Rec. 709).
//!
//! # Drawing lights into maps
//!
//! [`texel_means()`] fills each texel with a function's mean over
//! equal-area points of it (equirect; the centre elsewhere), so that a
//! light with edges keeps its power; [`AnalyticLight`] is a constant, cap
//! or gradient light with its radiance and closed-form coefficients;
//! [`directional_texels()`] draws a delta as one texel, or as a cap of its
//! exact power ([`DirectionalTexels`], [`DirectionalDrawing`]). These are
//! the maps whose projections are known in closed form (`shlight synth`).
//!
//! # Exact irradiance
//!
//! [`irradiance_brute_force`]: `E(n) = Σ_k L_k max(n · d_k, 0) Ω_k` over
//! every texel ([`TexelSet`]), with no truncation in degree: the ground
//! truth SH irradiance is compared with.
//!
//! # Rendering
//!
//! [`render_map`] draws a function of direction into any layout;
//! [`render_coefficients`] evaluates an expansion at every texel centre of a
//! [`TexelGrid`], in batches and in parallel: the way back from
//! coefficients to a map. [`render_lobe`] draws a scalar function as its
//! lobe, the surface `|p| = |f(p / |p|)|` ([`LobeSurface`]) coloured by
//! sign, seen by an orthographic [`LobeCamera`] (from
//! [`default_lobe_view`] unless told, the picture [`LOBE_MARGIN`] times
//! the lobe's radius; [`LobeError`] says why one cannot be drawn): rays
//! marched with steps bounded by Bernstein's inequality and bisected.
//!
//! # References
//!
//! 1. A. Van Oosterom, J. Strackee, *The Solid Angle of a Plane Triangle*,
//!    IEEE Trans. Biomed. Eng. 30 (1983) — cube texels' solid angles.
//! 2. M. Reinecke, D. S. Seljebotn, *Libsharp — spherical harmonic
//!    transforms revisited*, A&A 554 (2013) — the ring transform's
//!    recurrence and its cut-off past the turning point.
//! 3. B. Burley, *Practical Hash-based Owen Scrambling*, JCGT 9 (2020) —
//!    the Sobol points' scrambling.

pub mod montecarlo;

pub(crate) mod analytic_light;
pub(crate) mod cube_faces;
pub(crate) mod directional_texels;
pub(crate) mod equirect;
pub(crate) mod irradiance_map;
pub(crate) mod layout;
pub(crate) mod lobe;
pub(crate) mod orientation;
pub(crate) mod projection;
pub(crate) mod radiance_map;
pub(crate) mod render;
pub(crate) mod strided_image;
pub(crate) mod texel_means;
pub(crate) mod texel_source;

pub use analytic_light::AnalyticLight;
pub use cube_faces::CubeFaces;
pub use directional_texels::{DirectionalDrawing, DirectionalTexels, directional_texels};
pub use equirect::{EquirectView, equirect_angles, equirect_direction, equirect_row_solid_angle};
pub use irradiance_map::{TexelSet, irradiance_brute_force};
pub use layout::cube::{CubeFace, FaceCell, cube_texel_solid_angle};
pub use layout::env_map::EnvMap;
pub use layout::kind::{Layout, LayoutSizeError, LayoutSizeErrorKind, ParseLayoutError};
pub use layout::texel_grid::TexelGrid;
pub use lobe::camera::{LOBE_MARGIN, LobeCamera, default_lobe_view};
pub use lobe::error::LobeError;
pub use lobe::render_lobe;
pub use lobe::surface::LobeSurface;
pub use orientation::MapOrientation;
pub use projection::equirect_simple::project_equirect_simple;
pub use projection::pole::to_frame;
pub use projection::ring_transform::stream::{MissingRows, RingAccumulator};
pub use projection::{project, project_equirect, project_map};
pub use radiance_map::{RadianceMap, luminance};
pub use render::{render_coefficients, render_map};
pub use strided_image::StridedImage;
pub use texel_means::texel_means;
pub use texel_source::{TexelSource, contiguous_pixels, read_row};
