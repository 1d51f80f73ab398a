//! Ray casting for shlight's bakes: a triangle mesh made ready to cast
//! against, and the occlusion and closest-hit queries the bakes make of it,
//! one ray at a time or eight parallel rays at once.
//!
//! # Main items
//! - [`Occluder`]: a mesh made ready: a binned-SAH bounding-volume
//!   hierarchy over its triangles with the watertight ray/triangle test of
//!   Woop, Benthin and Wald (JCGT 2013), its vertices in Morton order, its
//!   face normals. Queries: [`Occluder::occluded`] and
//!   [`Occluder::closest_hit`] for a [`Ray`] ([`Hit`]: distance, triangle,
//!   barycentric weights); [`Occluder::packet_occluded`],
//!   [`Occluder::packet_closest`] and [`Occluder::packet_closest_direct`]
//!   for a [`Packet`] of up to [`LANES`] rays along one [`Direction`]
//!   ([`PacketHits`]), traced together with AVX2 where the processor has it
//!   (the fast path the bakes take; [`packets_enabled`]); which side of a
//!   triangle a ray meets ([`Occluder::is_front`]); and where a vertex's
//!   rays start, off its surface and never across the mesh
//!   ([`Occluder::ray_origins`], [`OFFSET`]).
//! - [`InstancedOccluder`]: a glTF scene's unique primitives made ready
//!   once each and placed by its instances (nodes sharing a mesh,
//!   `EXT_mesh_gpu_instancing`): a two-level hierarchy whose memory grows
//!   with the unique triangles plus a fixed cost per instance
//!   ([`InstancedOccluder::heap_bytes`], [`Occluder::heap_bytes`]), whose
//!   hits name the triangles, weights and sides the flattened scene's
//!   [`Occluder`] would (below).
//! - [`vertex_order`] and [`ranked_triangles`]: a mesh's vertices along a
//!   Morton curve, so that rays from consecutive vertices make coherent
//!   packets.
//! - [`CutOuts`]: surfaces that let rays through, for an occluder built
//!   [`Occluder::with_cut_outs`] (a flattened glTF scene's
//!   [`shlight_mesh::Surfaces`]: `MASK` and `BLEND` materials).
//! - [`brute_force_closest_hit`]: Möller-Trumbore in `f64` against every
//!   triangle, the independent reference the hierarchy, the packets and
//!   the bakes are tested against; [`brute_force_closest_hit_through`]
//!   the same through cut-outs.
//!
//! Every query hits both sides of a triangle, and a ray through an edge or
//! a vertex shared by triangles hits at least one of them.
//!
//! # Cut-outs and coverage
//! An occluder built with [`CutOuts`] asks, for a candidate hit on a
//! triangle that cuts out, its opacity at the hit's barycentric weights,
//! and passes over the hit (the traversal goes on behind it, any-hit) unless
//! the ray is stopped: always at opacity 1, never at 0 (a cut-out texel of
//! a `MASK` material lets every ray through, shadow rays too), and in
//! between (a `BLEND` material's alpha, coverage) when
//! [`coverage_sample`]`(origin, direction, triangle)`, a hash of the ray's
//! origin and direction bits and the triangle's index mapped to `[0, 1)`,
//! is below the opacity. So the decision is deterministic (the same at any
//! thread count, the same for [`Occluder::occluded`] and
//! [`Occluder::closest_hit`], single rays and packets), and over many rays
//! the fraction stopped is the coverage. Surfaces that do not cut out cost
//! nothing more: an occluder without cut-outs takes the traversal without
//! the test.
//!
//! # Instances: the two-level hierarchy
//! [`InstancedOccluder::new`] builds one hierarchy per primitive an
//! instance uses, in the primitive's own space (the same binned-SAH build
//! and watertight test), and one over the instances' world boxes, each
//! instance holding the inverse of its transform. A query walks the top
//! level with the world ray and, at each instance it reaches, takes the
//! ray into the primitive's space without renormalising its direction, so
//! that the distance of a hit is the world one (the watertight test's `t`
//! does not change under an affine map) and the nearest hit so far limits
//! the next instance's walk. Hits are named by the flattened scene's
//! numbering ([`shlight_mesh::Scene::flat_layout`]: instance order, the
//! primitive's triangle order, triangles that are degenerate in world
//! space never hit), with weights in the flattened triangle's corner order
//! (a mirroring instance's winding is reversed by the flattening, so its
//! second and third weights swap), and [`InstancedOccluder::is_front`]
//! reads the primitive's face normal against the direction taken into its
//! space, which has the flattened face's sign whatever the determinant. So
//! per-triangle data of the flattened [`shlight_mesh::Surfaces`]
//! (materials, textures, [`CutOuts`]) serves both occluders, and a cut-out
//! is decided by the world ray's [`coverage_sample`], as the flat occluder
//! decides it. Packets are traced lane by lane through the two levels (a
//! packet's rays stay parallel in an instance's space, but no packet path
//! takes them there yet). On probe rays through 100 instances of a
//! 10,000-triangle mesh the two levels cast 1.5x to 1.8x the flat
//! hierarchy's single rays per second, in 0.3% of its memory, on a par
//! with obvhs's CWBVH8 in two levels (within the run-to-run spread;
//! docs/benchmarks.md, "Instanced scenes").
//!
//! ```
//! use glam::Vec3;
//! use shlight_mesh::generate;
//! use shlight_rays::{Direction, Occluder, Packet, Ray};
//!
//! let sphere = generate::uv_sphere(1.0, 16, 8);
//! let occluder = Occluder::new(&sphere);
//! // From the centre, a ray meets the inside of the sphere (the back of a
//! // triangle, whose front faces out) at a distance just under 1 (the
//! // triangles' chords).
//! let hit = occluder.closest_hit(&Ray::new(Vec3::ZERO, Vec3::X, f32::INFINITY)).unwrap();
//! assert!(hit.t > 0.9 && hit.t < 1.0);
//! assert!(!occluder.is_front(hit.triangle, Vec3::X));
//! // Eight parallel rays from outside: those aimed at the sphere are
//! // blocked, the others not.
//! let dir = Direction::new(Vec3::NEG_Z);
//! let local: Vec<[f32; 4]> = occluder.ray_space(&dir).collect();
//! let origins: Vec<Vec3> = (0..8).map(|k| Vec3::new(k as f32 * 0.4, 0.1, 3.0)).collect();
//! let blocked = occluder.packet_occluded(&dir, &local, &Packet::new(&dir, &origins));
//! assert_eq!(blocked, 0b0000_0111);
//! ```
//!
//! **Architecture invariant:** rays and nothing else: no SH, no I/O, no
//! GPU. The crate reads shlight-mesh's meshes and shlight-baked's Morton
//! codes; the bakes (shlight-prt, shlight-volume) are above it.

mod brute_force;
mod bvh;
mod cpu;
mod cut_outs;
mod instanced;
mod occluder;
mod origins;
mod packet;
mod vertex_order;

pub use brute_force::{brute_force_closest_hit, brute_force_closest_hit_through};
pub use bvh::{Hit, Ray};
pub use cpu::has_avx2_and_fma;
pub use cut_outs::{CutOuts, coverage_sample};
pub use instanced::InstancedOccluder;
pub use occluder::{Occluder, TWO_LEVEL_REPEATS};
pub use origins::{OFFSET, SHORTER_OFFSETS};
pub use packet::{Direction, LANES, Packet, PacketHits, packets_enabled, set_packets_enabled};
pub use vertex_order::{ranked_triangles, vertex_order};

/// For shlight's own tests (this crate's and the bakes' above it): reports
/// a test, or the part of it that needs AVX2 and FMA, as skipped. Prints
/// `SKIPPED test: why` with `write!` on the process's stderr handle, which
/// the test harness does not capture (it captures only the
/// `print!`/`eprint!` macros), so the line shows in a passing run; panics
/// under `SHLIGHT_REQUIRE_ALL=1`, where no test may skip.
#[doc(hidden)]
pub fn skip_test(test: &str, why: &str) {
    if std::env::var("SHLIGHT_REQUIRE_ALL").as_deref() == Ok("1") {
        panic!("{test}: SHLIGHT_REQUIRE_ALL=1 but it would be skipped: {why}");
    }
    use std::io::Write as _;
    let _ = writeln!(std::io::stderr(), "SKIPPED {test}: {why}");
}
