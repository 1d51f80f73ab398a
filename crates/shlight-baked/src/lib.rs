//! Baked lighting data as one set of types, below the crates that bake it
//! (shlight-volume, shlight-prt), store it (shlight-format) and shade with
//! it (shlight-gpu), so that each fact about a bake exists once.
//!
//! - [`ProbeGrid`]: an irradiance volume's box and resolution, a probe at
//!   each cell's centre (`min + (i + 1/2) (max - min) / n`, the one formula
//!   of a probe's place), probes numbered x fastest, then y, then z;
//!   trilinear weights of a point, clamped to the grid.
//! - [`VolumeView`]: a volume's lit probes borrowed (grid, lmax, validity,
//!   radiance), as a `.shvol` file or a bake relit holds them, checked for
//!   shape; [`MAX_LMAX`], the most a volume holds,
//!   and [`SHADED_MAX_LMAX`], the most the GPU's volume pass shades;
//!   [`LIGHT_MAX_LMAX`], the most of a distant light the renderers shade;
//!   the probes' offsets (where the bake moved them out of geometry) and
//!   [`Visibility`], their distance maps.
//! - [`visibility`]: DDGI's probe visibility (Majercik et al. 2019), the one
//!   definition of the distance moments a bake stores
//!   ([`visibility::MomentFilter`]) and of the weights a shaded point gives
//!   the probes around it ([`visibility::visibility_weights`]), on
//!   [`octahedral`] maps of the sphere.
//! - [`TransferView`]: PRT transfer vectors borrowed (Sloan, Kautz &
//!   Snyder 2002), `L_out(v) = sum_i T_vi L_i` per vertex; [`GlossyView`]:
//!   glossy transfer matrices, plain or clustered PCA, and the transferred
//!   radiance `T_p = M_p L` they give under a light
//!   ([`TransferredRadiance`], per cluster once, then summed per vertex).
//! - [`dilate`]: a volume's invalid probes filled from their valid face
//!   neighbours, pass by pass, for engines whose lookups know no validity.
//! - [`morton_code`] and [`morton_order`]: the Z-order that bakes
//!   neighbouring probes and vertices together.
//!
//! ```
//! use glam::Vec3;
//! use shlight_baked::ProbeGrid;
//!
//! let grid = ProbeGrid::new([2, 1, 2], Vec3::ZERO, Vec3::new(2.0, 1.0, 2.0)).unwrap();
//! assert_eq!(grid.centre([1, 0, 1]), Vec3::new(1.5, 0.5, 1.5));
//! // Halfway between probes 0 and 1: half of each.
//! assert_eq!(grid.trilinear(Vec3::new(1.0, 0.5, 0.5)), vec![(0, 0.5), (1, 0.5)]);
//! ```
//!
//! **Architecture invariant:** a leaf (glam only): no I/O, no GPU, no
//! mathematics of SH (that is shlight-core's).

mod dilate;
mod glossy_view;
mod light_lmax;
mod morton;
pub mod octahedral;
mod probe_grid;
mod shape_error;
mod transfer_view;
pub mod visibility;
mod visibility_weights;
mod volume_view;

pub use dilate::dilate;
pub use glossy_view::{GlossyMatrices, GlossyView, TransferredRadiance};
pub use light_lmax::LIGHT_MAX_LMAX;
pub use morton::{morton_code, morton_order};
pub use probe_grid::{MAX_PROBES, PADDING, ProbeGrid};
pub use shape_error::ShapeError;
pub use transfer_view::TransferView;
pub use visibility::{ProbeVisibility, Visibility};
pub use volume_view::{MAX_LMAX, SHADED_MAX_LMAX, VolumeView, largest_move, moved_probes};
