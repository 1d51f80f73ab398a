//! Surfaces that let rays through: cut-outs (glTF `MASK`) and partial
//! coverage (`BLEND`), as an [`Occluder`](crate::Occluder) built with them
//! sees them ([`CutOuts`]).
//!
//! A candidate hit at barycentric weights `w` of a triangle that
//! [cuts out](CutOuts::cuts_out) stops the ray when
//!
//! ```text
//! coverage_sample(origin, direction, triangle) < opacity(triangle, w)
//! ```
//!
//! and is passed over otherwise, the traversal going on to the triangles
//! behind it (any-hit), for occlusion and closest hits alike. Opacity 1
//! always stops the ray and 0 never does: a cut-out texel lets every ray
//! through, shadow rays too. Between them ([`coverage_sample`]) a hash of
//! the bits of the ray's origin and direction and of the triangle's index,
//! mapped to `[0, 1)`, decides: the same ray always meets the same
//! surface, whichever query asks and at any thread count, and over many
//! rays the fraction stopped is the opacity (the coverage).
//!
//! Triangles that do not cut out are tested as before, and an occluder
//! without any costs nothing more: its queries take the traversal without
//! the test.

use std::sync::Arc;

use glam::Vec3;
use shlight_mesh::Surfaces;

/// Which triangles of a mesh may let rays through, and how much of the
/// light each point stops.
pub trait CutOuts: Send + Sync {
    /// Whether triangle `triangle` (the mesh's index) may let a ray
    /// through; the others stop every ray and are never asked their
    /// opacity.
    fn cuts_out(&self, triangle: u32) -> bool;

    /// The fraction of rays that triangle `triangle` stops at barycentric
    /// weights `barycentrics` (of its three corners, in the order of its
    /// indices): 1 opaque, 0 cut out, coverage between.
    fn opacity(&self, triangle: u32, barycentrics: [f32; 3]) -> f32;
}

/// A flattened scene's materials: `MASK` and `BLEND` cut out, their
/// opacity [`shlight_mesh::Material::opacity`] of the base alpha
/// ([`Surfaces::sample`]) at the point.
impl CutOuts for Surfaces {
    fn cuts_out(&self, triangle: u32) -> bool {
        self.material(triangle).cuts_out()
    }

    fn opacity(&self, triangle: u32, barycentrics: [f32; 3]) -> f32 {
        let alpha = self.sample(triangle, barycentrics).alpha;
        self.material(triangle).opacity(alpha)
    }
}

/// The number in `[0, 1)` that decides whether a ray from `origin` along
/// `dir` (as given to [`Ray::new`](crate::Ray::new), or a packet's
/// [`Direction::dir`](crate::Direction::dir)) is stopped by triangle
/// `triangle` where it covers part of its texels: a 64-bit mix (SplitMix64's
/// finaliser) of the bits of the six coordinates and the index, its top 24
/// bits over `2^24`. The ray is stopped when this is below the opacity.
#[must_use]
pub fn coverage_sample(origin: Vec3, dir: Vec3, triangle: u32) -> f32 {
    let mut h = 0x9e37_79b9_7f4a_7c15u64 ^ u64::from(triangle);
    for x in [origin.x, origin.y, origin.z, dir.x, dir.y, dir.z] {
        h = mix(h ^ u64::from(x.to_bits()));
    }
    (mix(h) >> 40) as f32 * (1.0 / (1u64 << 24) as f32)
}

/// SplitMix64's finaliser: every bit of the input flips about half the
/// output bits.
fn mix(mut h: u64) -> u64 {
    h = h.wrapping_add(0x9e37_79b9_7f4a_7c15);
    h = (h ^ (h >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    h = (h ^ (h >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    h ^ (h >> 31)
}

/// Whether a candidate hit at `barycentrics` of triangle `triangle`, which
/// cuts out, stops the ray from `origin` along `dir`.
#[must_use]
pub(crate) fn stops(
    cut_outs: &dyn CutOuts,
    triangle: u32,
    barycentrics: [f32; 3],
    origin: Vec3,
    dir: Vec3,
) -> bool {
    let opacity = cut_outs.opacity(triangle, barycentrics);
    if opacity >= 1.0 {
        return true;
    }
    if opacity <= 0.0 || opacity.is_nan() {
        return false;
    }
    coverage_sample(origin, dir, triangle) < opacity
}

/// An occluder's cut-outs: the triangles that cut out, one bit each in
/// the hierarchy's leaf order, and what answers their opacity.
#[derive(Clone)]
pub(crate) struct CutOutTable {
    flagged: Vec<u64>,
    source: Arc<dyn CutOuts>,
}

impl std::fmt::Debug for CutOutTable {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let count: u32 = self.flagged.iter().map(|w| w.count_ones()).sum();
        f.debug_struct("CutOutTable")
            .field("triangles_cutting_out", &count)
            .finish_non_exhaustive()
    }
}

impl CutOutTable {
    /// The table of `source` for a hierarchy whose leaf-order triangle `k`
    /// is the mesh's triangle `ids[k]`; `None` when no triangle cuts out.
    pub(crate) fn new(source: Arc<dyn CutOuts>, ids: &[u32]) -> Option<Self> {
        let mut flagged = vec![0u64; ids.len().div_ceil(64)];
        let mut any = false;
        for (k, &id) in ids.iter().enumerate() {
            if source.cuts_out(id) {
                flagged[k / 64] |= 1 << (k % 64);
                any = true;
            }
        }
        any.then_some(Self { flagged, source })
    }

    /// Bytes held on the heap (the flags; the source is shared).
    pub(crate) fn heap_bytes(&self) -> usize {
        self.flagged.capacity() * 8
    }

    /// Whether leaf-order triangle `k` cuts out.
    #[inline(always)]
    pub(crate) fn flagged(&self, k: usize) -> bool {
        self.flagged[k / 64] >> (k % 64) & 1 == 1
    }

    /// [`stops`] with this table's source; `triangle` is the mesh's index.
    pub(crate) fn stops(
        &self,
        triangle: u32,
        barycentrics: [f32; 3],
        origin: Vec3,
        dir: Vec3,
    ) -> bool {
        stops(&*self.source, triangle, barycentrics, origin, dir)
    }
}
