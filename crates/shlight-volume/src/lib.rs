//! Irradiance volumes for shlight (Greger, Shirley, Hubbard & Greenberg
//! 1998): SH probes on a grid through a scene, so that objects moving
//! through it are lit by the light at their position, interpolated from the
//! probes around them.
//!
//! # What a reader meets
//! Four things, in the order a volume goes through them:
//!
//! 1. **The bake.** [`bake()`] bakes the probes of a
//!    [`shlight_baked::ProbeGrid`] (the probes' box and resolution, probes
//!    at cell centres, x fastest) through a scene with [`VolumeOptions`]
//!    into a [`VolumeBake`] ([`bake_surfaces`] through a glTF scene's
//!    surfaces: cut-outs, and the albedo of the texel a ray hits): each
//!    probe's incident radiance as a transfer
//!    matrix per channel and the emitters' light, `L_probe = M L_env +
//!    L_emitted`, through the scene's shadows and interreflections
//!    ([`bake()`] states the estimator); [`bake_with_lights`] adds a
//!    scene's punctual lights (glTF's `KHR_lights_punctual`) to the
//!    static part, by shadow rays at the probes and at the surfaces. [`bake_file()`] is a bake as a
//!    front end asks for it (`shlight volume`, the Python package's
//!    `bake_volume`): [`VolumeBakeSettings`] (the grid and the options)
//!    over a scene and an environment to a [`BakedFile`], the bake and its
//!    `.shvol` file ([`VolumeBake::to_shvol`]).
//! 2. **Its lit probes.** [`VolumeBake::relight`] lights the probes for
//!    any environment (rotated, or another map) without a new bake;
//!    [`relight_file`] does the same for a `.shvol` file. Lit probes are
//!    read as a [`shlight_baked::VolumeView`], borrowed from a file
//!    ([`shlight_format::ShvolFile::view`]) or a bake
//!    ([`VolumeBake::view`]).
//! 3. **A lookup kind.** [`Lookup`] says how the light at a point facing a
//!    normal is read off the probes: shlight's own (`shlight`,
//!    visibility-weighted where the volume holds distance maps, and
//!    `trilinear`), or an engine's as the engine computes it from
//!    shlight's export (`bevy`: Bevy's irradiance volume, the KTX2
//!    export's half-float ambient cubes filtered and blended as its shader
//!    does; `threejs`: three.js r187's `LightProbeGrid`, the point offset
//!    half a probe spacing along the normal, trilinear L2 SH, three.js's
//!    constants); [`Lookup::lmax_for`] says which degrees each reads. The
//!    engines know no probe validity: their lookups read the probes
//!    dilated ([`shlight_baked::dilate`]).
//! 4. **A prepared lookup.** [`PreparedLookup`] is a lookup of one
//!    volume made ready for many points (`shlight sample`), the one way
//!    the light at a point is read: [`PreparedLookup::irradiance_at`],
//!    and for shlight's lookups the radiance it comes from
//!    ([`PreparedLookup::radiance_at`]).
//!
//! Besides: [`probe_sheet()`], a picture of the lit probes, each a white
//! ball lit by its light, and [`probe_sheet_exposure`] to show it at;
//! files through [`shlight_format::ShvolFile`] (docs/shvol.md).
//!
//! ```
//! use glam::{DVec3, Vec3};
//! use shlight_core::sh::closed_form;
//! use shlight_baked::ProbeGrid;
//! use shlight_volume::{Lookup, PreparedLookup, VolumeOptions, bake};
//!
//! // No scene: every probe sees the environment itself.
//! let grid = ProbeGrid::new([2, 1, 2], Vec3::ZERO, Vec3::ONE).unwrap();
//! let volume = bake(None, &grid, &VolumeOptions::default(), &|_, _, _| {}).unwrap();
//! let sky = closed_form::constant(2, DVec3::new(1.0, 2.0, 3.0));
//! let probes = volume.relight(&sky);
//! // Probe 0's first row, [r, g, b] of L_00, is the sky's.
//! assert_eq!(&probes[..3], &sky.as_slice()[0].as_vec3().to_array());
//! assert_eq!(volume.invalid_count(), 0);
//! // A constant sky of radiance L gives the irradiance pi L everywhere.
//! let lookup = PreparedLookup::new(&volume.view(&probes), Lookup::Trilinear, 2);
//! let e = lookup.irradiance_at(Vec3::splat(0.4), Vec3::Y);
//! assert!((e - std::f64::consts::PI * DVec3::new(1.0, 2.0, 3.0)).abs().max_element() < 1e-5);
//! ```
//!
//! # Modules
//! Imports go one way: [`PreparedLookup`] (`prepared_lookup.rs`) takes
//! the kind ([`Lookup`], `lookup.rs`) to one of the lookups — shlight's
//! (`probe_lookup.rs`), Bevy's (`bevy_lookup.rs`), three.js's
//! (`threejs_lookup.rs`) — and the engines' lookups filter their textures
//! with `texel_corners.rs`, below them all. The bake (`bake.rs`, with
//! `bake/` below it) makes a [`VolumeBake`] (`volume_bake.rs`);
//! `bake_file.rs` is above both.
//!
//! **Architecture invariant:** no GPU and no command line; files through
//! shlight-format.

mod bake;
mod bake_file;
mod bevy_lookup;
mod error;
mod lookup;
mod prepared_lookup;
mod probe_lookup;
mod probe_sheet;
mod texel_corners;
mod threejs_lookup;
mod volume_bake;

pub use bake::{
    MAX_SUBDIVIDED_TRIANGLES, SURFACE_DIVISIONS, Stage, SurfaceLight, SurfacePoint,
    SurfacePointsBake, VolumeOptions, bake, bake_surfaces, bake_with_lights,
    gather_at_surface_points, relocate,
};
pub use bake_file::{BakedFile, VolumeBakeSettings, bake_file, check_environment};
pub use error::VolumeError;
pub use lookup::{Lookup, LookupLmax};
pub use prepared_lookup::PreparedLookup;
pub use probe_sheet::{probe_sheet, probe_sheet_exposure};
pub use volume_bake::{FileMeta, VolumeBake, relight_file};
