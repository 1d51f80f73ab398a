//! Environment-map layouts (equirect, cube cross, strip, angular map, mirror
//! ball): their geometry. Texel directions, exact texel solid angles,
//! inverse lookups and drawing; projection to SH is [`crate::map`].
//!
//! An [`EnvMap`] is a borrowed image of linear RGB texels, row-major from
//! the top-left, in one [`Layout`]. Every texel that holds a direction has
//! a unit world direction ([`EnvMap::texel_direction`], at the texel's
//! centre) and the exact solid angle it covers
//! ([`EnvMap::texel_solid_angle`]); [`crate::map::project`] sums
//! `f(texel) Y(centre) Ω(texel)` in `f64` and [`render_map`] draws a function
//! into any layout. A [`TexelGrid`] is the same geometry without pixels:
//! texel directions, points inside texels, solid angles and the texel a
//! direction falls in, for drawing maps.
//!
//! # Map frame
//!
//! Each layout first gives a direction `d` in the map's own **y-up** frame;
//! the map's [`MapOrientation`](crate::map::MapOrientation) then takes it to the world exactly as for
//! equirect maps ([`crate::map::equirect_direction`]):
//! `mirror` negates the map-frame `z` (for the equirect layout that is
//! `φ -> -φ`), then `frame` applies `Frame::YUp.rotation_to(frame)`
//! (`Frame::ZUp`: the y-up sphere turned `+90°` about X,
//! `(x, y, z) -> (x, -z, y)`).
//!
//! | layout | size | map-frame direction |
//! |---|---|---|
//! | `equirect` | any `W x H` (2:1 usual) | `(sin θ cos φ, cos θ, sin θ sin φ)`, `θ = π v`, `φ = 2π (u - 1/2)` (docs/conventions.md) |
//! | `cross-h` | `4f x 3f` | cells: row 0 col 1 `+Y`; row 1 `-X +Z +X -Z`; row 2 col 1 `-Y` |
//! | `cross-v` | `3f x 4f` | row 0 col 1 `+Y`; row 1 `-X +Z +X`; row 2 col 1 `-Y`; row 3 col 1 `-Z` turned 180° |
//! | `strip` | `6f x f` | `+X -X +Y -Y +Z -Z` left to right ([`CubeFace::ALL`]) |
//! | `angular` | `N x N` | `(sin(πr) u/r, sin(πr) v/r, -cos(πr))`: centre `-Z`, right `+X`, up `+Y`, rim `+Z` |
//! | `mirror-ball` | `N x N` | `n = (u, v, sqrt(1-r²))`, `d = (2 n_z u, 2 n_z v, 2 n_z² - 1)`: centre `+Z`, rim `-Z` |
//!
//! Cube faces follow the OpenGL / Vulkan / D3D sampling convention (table on
//! [`CubeFace`]); with these cells every seam inside a cross joins texels of
//! neighbouring directions. Disc layouts use `u = 2(x + 1/2)/N - 1` to the
//! right and `v = 1 - 2(y + 1/2)/N` up, `r = |(u, v)|`: the disc inscribed
//! in the square image. Image coordinates are in pixels from the top-left
//! corner with texel centres at `+0.5`.
//!
//! # Which texels hold a direction
//!
//! Unused cells of a cross hold none. A disc texel holds one when its
//! square meets the open disc. Texels whose centre lies inside the disc
//! carry the direction of the centre. **Rim texels** (centre outside, square
//! partly inside) carry the direction of the rim, a single point of the
//! sphere ([`Layout::Angular`] `+Z`, [`Layout::MirrorBall`] `-Z`, before the
//! orientation), and the solid angle of their part inside the disc, so the
//! quadrature's weights sum to exactly `4π` and constants project exactly.
//! Images that left these texels black (sampled at the centre only) lose
//! that solid angle: `2e-5 sr` for an angular map of `N = 512` but
//! `1.2e-2 sr` for a mirror ball, whose rim squeezes a whole cap around
//! `-Z` into a thin ring (measured in `tests/layout.rs`).
//!
//! # Solid angles
//!
//! Equirect rows: [`crate::map::equirect_row_solid_angle`]. Cube
//! texels: [`cube_texel_solid_angle`] (closed form). Disc texels integrate
//! `dω = w(r) dA` over the texel's part of the unit disc, `w = π sin(πr)/r`
//! for the angular map (`θ = πr` from `-Z`) and `w = 4` for the mirror ball
//! (`θ = 2 asin r` from `+Z`): interior texels by a tensor Gauss-Legendre
//! rule whose error bound is below `1e-17 π² h²`, texels the rim cuts in
//! polar coordinates with the radial integral in closed form and the
//! angle range cut wherever the integrand has a kink. Every layout's solid
//! angles sum to `4π` within `1e-12` (tests).
//!
//! # Example
//! ```
//! use glam::DVec3;
//! use shlight_core::map::{EnvMap, Layout, MapOrientation, project_map, render_map};
//!
//! let o = MapOrientation::default();
//! let layout: Layout = "cross-h".parse().unwrap();
//! let (w, h) = layout.dimensions(32); // faces of 32 x 32 texels
//! let pixels = render_map(layout, o, w, h, |d| DVec3::splat(1.0 + d.y)).unwrap();
//! let map = EnvMap::new(layout, o, w, h, &pixels).unwrap();
//! let sh = project_map(&map, 2);
//! // The weights sum to 4 pi and y cancels between opposite texels, so the
//! // constant term is exact up to the f32 pixels: int 1 Y_0^0 = 2 sqrt(pi).
//! assert!((sh[0].x - 2.0 * std::f64::consts::PI.sqrt()).abs() < 1e-6);
//! // int y Y_1^-1 = -sqrt(4 pi / 3), to the quadrature's O(h^2).
//! assert!((sh[1].x + (4.0 * std::f64::consts::PI / 3.0).sqrt()).abs() < 1e-3);
//! ```

pub(crate) mod cube;
pub(crate) mod disc;
pub(crate) mod env_map;
pub(crate) mod geometry;
pub(crate) mod kind;
pub(crate) mod texel_grid;
