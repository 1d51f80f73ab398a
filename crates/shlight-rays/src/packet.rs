//! Bundles of up to eight parallel rays traced together through a [`Bvh`].
//!
//! PRT baking shares one set of directions among all vertices, so the rays
//! along one direction `d` from nearby vertices are parallel and start
//! close together: they cross the same nodes. A [`Packet`] holds eight such
//! rays, and one traversal tests all eight against a box or a triangle with
//! AVX2 (one 8-lane instruction per step), visiting a node when any live ray
//! needs it.
//!
//! Baking takes the vertices facing a direction in Morton order, so the
//! eight origins of a packet are neighbours on the surface.
//!
//! - **Boxes** are tested in world space. The rays share `1/d`, so the near
//!   and far planes of every axis are chosen once per direction, and a
//!   plane's distance is one fused multiply-subtract, `plane/d - o/d`; the
//!   far distance is widened as in [`Bvh`]'s single rays, and the boxes'
//!   padding covers the rounding of `o/d`.
//! - **Triangles** are tested in *ray space*, the orthonormal frame
//!   `(e1, e2, d)` in which every ray of the bundle runs along +z: a point
//!   `p` has coordinates `(e1.p, e2.p, d.p)`. The caller computes them once
//!   per direction for every mesh vertex ([`Direction::to_ray_space`]), or
//!   [`PacketBvh::closest_direct`] computes a triangle's as it tests it (for
//!   callers that take many directions in turn per packet, or a mesh too
//!   large to copy per direction); either way a
//!   vertex has the same coordinates in every triangle that shares it; the
//!   edge functions of a shared edge are then exact negatives of each other
//!   and redone in `f64` when zero, as in the watertight test of
//!   [`crate::bvh`], so no ray slips between two triangles. The distance to
//!   a hit is the difference of the `z` coordinates (`d` is unit).
//!
//! On processors without AVX2 and FMA (or when [`set_packets_enabled`] turns
//! them off, for tests) each live ray of a packet is traced alone through
//! [`Bvh::occluded`] and [`Bvh::closest_hit`]; the answers agree but for rays
//! grazing an edge, where rounding differs.

use std::sync::atomic::{AtomicBool, Ordering};

use glam::Vec3;

use crate::bvh::{Bvh, INNER, Ray};
use crate::cpu::has_avx2_and_fma;
use crate::cut_outs::CutOutTable;

/// Rays in a packet: one AVX register. Sixteen (two registers, rays from a
/// wider patch of vertices) visited 1.5x the nodes per packet (105 against
/// 71 on the torus of `benches/transfer.rs`) at twice the work per node,
/// and baking was slower; four-wide nodes folded from the binary hierarchy
/// cost more instructions per ray too (callgrind), so neither is kept.
pub const LANES: usize = 8;

static DISABLED: AtomicBool = AtomicBool::new(false);

/// Turns the AVX2 packet traversal off (`false`) or back on, for every
/// [`Occluder`](crate::Occluder) made afterwards: each ray of a packet is
/// then traced alone. For tests and benchmarks.
pub fn set_packets_enabled(enabled: bool) {
    DISABLED.store(!enabled, Ordering::Relaxed);
}

/// Whether packets are traced with AVX2 (the processor has AVX2 and FMA, and
/// [`set_packets_enabled`] has not turned them off).
#[must_use]
pub fn packets_enabled() -> bool {
    !DISABLED.load(Ordering::Relaxed) && has_avx2_and_fma()
}

/// The direction a packet's rays share, and its ray-space frame.
#[derive(Clone, Copy, Debug)]
pub struct Direction {
    dir: Vec3,
    inv: Vec3,
    e1: Vec3,
    e2: Vec3,
}

impl Direction {
    /// The unit direction `dir` (normalised here).
    #[must_use]
    pub fn new(dir: Vec3) -> Self {
        let dir = dir.normalize();
        let (e1, e2) = dir.any_orthonormal_pair();
        Self {
            dir,
            inv: crate::bvh::safe_inverse(dir),
            e1,
            e2,
        }
    }

    /// The unit direction.
    #[must_use]
    pub fn dir(&self) -> Vec3 {
        self.dir
    }

    /// `p` in ray space: `(e1.p, e2.p, d.p)` (the fourth entry is 0).
    #[inline]
    #[must_use]
    pub fn to_ray_space(&self, p: Vec3) -> [f32; 4] {
        [self.e1.dot(p), self.e2.dot(p), self.dir.dot(p), 0.0]
    }
}

/// Up to [`LANES`] rays along one [`Direction`]: origins in world and in
/// ray space, lane by lane.
#[derive(Clone, Copy, Debug)]
pub struct Packet {
    world: [[f32; LANES]; 3],
    local: [[f32; LANES]; 3],
    origins: [Vec3; LANES],
    /// Bit `k` set: lane `k` holds a ray.
    live: u32,
}

impl Packet {
    /// Rays from `origins` (at most [`LANES`]) along `dir`.
    ///
    /// # Panics
    /// If there are more than [`LANES`] origins.
    #[must_use]
    pub fn new(dir: &Direction, origins: &[Vec3]) -> Self {
        assert!(origins.len() <= LANES, "at most {LANES} rays in a packet");
        let mut p = Self {
            world: [[0.0; LANES]; 3],
            local: [[0.0; LANES]; 3],
            origins: [Vec3::ZERO; LANES],
            live: ((1u64 << origins.len()) - 1) as u32,
        };
        for (k, o) in origins.iter().enumerate() {
            let r = dir.to_ray_space(*o);
            for a in 0..3 {
                p.world[a][k] = o[a];
                p.local[a][k] = r[a];
            }
            p.origins[k] = *o;
        }
        p
    }
}

impl Packet {
    /// Each ray of the packet: its lane and origin.
    pub(crate) fn rays(&self) -> impl Iterator<Item = (usize, Vec3)> + '_ {
        lanes(self.live).map(|k| (k, self.origins[k]))
    }
}

impl PacketHits {
    /// No lane hit.
    pub(crate) const NONE: Self = Self {
        mask: 0,
        t: [f32::INFINITY; LANES],
        triangle: [0; LANES],
        barycentrics: [[0.0; 3]; LANES],
    };
}

/// The nearest hits of a packet's rays.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PacketHits {
    /// Bit `k` set: lane `k` hit something.
    pub mask: u32,
    /// Distance per lane (meaningful where `mask` is set).
    pub t: [f32; LANES],
    /// Mesh triangle per lane.
    pub triangle: [u32; LANES],
    /// Barycentric weights of the triangle's corners per lane.
    pub barycentrics: [[f32; 3]; LANES],
}

/// A [`Bvh`] laid out for packet traversal, once per octant of directions:
/// each node holds its two children's boxes, as near and far planes along
/// the octant's directions, the nearer child first, in one 64-byte line.
/// A visit then reads one cache line at fixed offsets. Eight copies of the
/// inner nodes, about a third of the triangles' memory together.
#[derive(Clone, Debug)]
pub(crate) struct PacketBvh {
    bvh: Bvh,
    octants: Vec<Vec<Node2>>,
    /// The root: [`Node2::child`]'s code and count.
    root: (u32, u32),
    /// Packets are traced with AVX2 ([`packets_enabled`] when built; the
    /// octant layouts are empty otherwise).
    avx2: bool,
}

/// One node of a [`PacketBvh`]: per child slot (nearer first), the box's
/// near and far planes on each axis, and the child: below [`LEAF`] an
/// inner node's index, `LEAF | first` a leaf of `count` triangles from
/// `first` (leaf order).
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
pub(crate) struct Node2 {
    near: [[f32; 2]; 3],
    far: [[f32; 2]; 3],
    child: [u32; 2],
    count: [u32; 2],
}

/// [`Node2::child`] of a leaf: `LEAF | first`.
const LEAF: u32 = 1 << 31;

/// The octant of directions `dir` is in: bit `a` set when `1/d_a < 0`.
fn octant(dir: &Direction) -> usize {
    usize::from(dir.inv.x < 0.0)
        | usize::from(dir.inv.y < 0.0) << 1
        | usize::from(dir.inv.z < 0.0) << 2
}

impl PacketBvh {
    /// The packet layout of `bvh`.
    #[must_use]
    pub fn new(bvh: Bvh) -> Self {
        let root = &bvh.nodes[0];
        let root_code = if root.kind < INNER {
            (LEAF | root.first, root.kind)
        } else {
            (0, 0)
        };
        let avx2 = packets_enabled();
        let octants = (0..8)
            .map(|o| {
                let mut nodes = Vec::new();
                if avx2 && root.kind >= INNER {
                    Self::lay_out(&bvh, o, 0, &mut nodes);
                }
                nodes
            })
            .collect();
        Self {
            bvh,
            octants,
            root: root_code,
            avx2,
        }
    }

    /// The binary hierarchy.
    #[must_use]
    pub fn bvh(&self) -> &Bvh {
        &self.bvh
    }

    /// Bytes held on the heap: the hierarchy and its octant layouts.
    pub(crate) fn heap_bytes(&self) -> usize {
        self.bvh.heap_bytes()
            + self.octants.capacity() * size_of::<Vec<Node2>>()
            + self
                .octants
                .iter()
                .map(|o| o.capacity() * size_of::<Node2>())
                .sum::<usize>()
    }

    /// Appends the node for inner binary node `n` and its subtree, for
    /// octant `o`; returns its index.
    fn lay_out(bvh: &Bvh, o: usize, n: usize, out: &mut Vec<Node2>) -> u32 {
        let index = out.len();
        let neg = [o & 1 != 0, o & 2 != 0, o & 4 != 0];
        let node = bvh.nodes[n];
        let (l, r) = (node.first as usize, node.first as usize + 1);
        let slots = if neg[(node.kind - INNER) as usize] {
            [r, l]
        } else {
            [l, r]
        };
        out.push(Node2 {
            near: [[0.0; 2]; 3],
            far: [[0.0; 2]; 3],
            child: [0; 2],
            count: [0; 2],
        });
        for (s, &c) in slots.iter().enumerate() {
            let child = bvh.nodes[c];
            for a in 0..3 {
                let (lo, hi) = (child.min[a], child.max[a]);
                let (near, far) = if neg[a] { (hi, lo) } else { (lo, hi) };
                out[index].near[a][s] = near;
                out[index].far[a][s] = far;
            }
            if child.kind < INNER {
                out[index].child[s] = LEAF | child.first;
                out[index].count[s] = child.kind;
            } else {
                out[index].child[s] = Self::lay_out(bvh, o, c, out);
            }
        }
        index as u32
    }

    /// Which rays of `packet` (along `dir`, from `0 < t`) are blocked: bit
    /// `k` set for lane `k`. `local` holds the mesh's vertices in `dir`'s
    /// ray space ([`Direction::to_ray_space`], indexed like the positions the
    /// hierarchy was built from). `cut`: the cut-outs rays pass through
    /// (none: every triangle stops them).
    #[must_use]
    pub fn occluded(
        &self,
        dir: &Direction,
        local: &[[f32; 4]],
        packet: &Packet,
        cut: Option<&CutOutTable>,
    ) -> u32 {
        #[cfg(target_arch = "x86_64")]
        if self.avx2 {
            assert!(self.bvh.corners_within(local.len()));
            // SAFETY: AVX2 and FMA are present (checked when `self` was
            // built), and every corner index is below `local.len()`.
            return unsafe {
                match cut {
                    None => avx2::occluded::<false>(self, dir, local, packet, None),
                    Some(_) => avx2::occluded::<true>(self, dir, local, packet, cut),
                }
            };
        }
        let _ = (local, self.avx2);
        let mut out = 0;
        for k in lanes(packet.live) {
            let ray = Ray::new(packet.origins[k], dir.dir, f32::INFINITY);
            if self.bvh.occluded_through(&ray, cut) {
                out |= 1 << k;
            }
        }
        out
    }

    /// The nearest hit of each ray of `packet` (see
    /// [`occluded`](Self::occluded) for `local` and `cut`).
    #[must_use]
    pub fn closest(
        &self,
        dir: &Direction,
        local: &[[f32; 4]],
        packet: &Packet,
        cut: Option<&CutOutTable>,
    ) -> PacketHits {
        #[cfg(target_arch = "x86_64")]
        if self.avx2 {
            assert!(self.bvh.corners_within(local.len()));
            // SAFETY: as in `occluded`.
            return unsafe {
                match cut {
                    None => avx2::closest::<false>(self, dir, local, packet, None),
                    Some(_) => avx2::closest::<true>(self, dir, local, packet, cut),
                }
            };
        }
        let _ = local;
        self.closest_single(dir, packet, cut)
    }

    /// [`closest`](Self::closest) without the ray-space copy of the
    /// vertices: each triangle's corners are put in ray space as it is
    /// tested ([`Direction::to_ray_space`], so the hits are the same). For
    /// callers that take the directions in an order of their own, or whose
    /// mesh is too large to copy for every direction.
    #[must_use]
    pub fn closest_direct(
        &self,
        dir: &Direction,
        packet: &Packet,
        cut: Option<&CutOutTable>,
    ) -> PacketHits {
        #[cfg(target_arch = "x86_64")]
        if self.avx2 {
            // SAFETY: AVX2 and FMA are present (checked when `self` was
            // built).
            return unsafe {
                match cut {
                    None => avx2::closest_direct::<false>(self, dir, packet, None),
                    Some(_) => avx2::closest_direct::<true>(self, dir, packet, cut),
                }
            };
        }
        self.closest_single(dir, packet, cut)
    }

    /// Each live ray of `packet` traced alone.
    fn closest_single(
        &self,
        dir: &Direction,
        packet: &Packet,
        cut: Option<&CutOutTable>,
    ) -> PacketHits {
        let mut out = PacketHits::NONE;
        for k in lanes(packet.live) {
            let ray = Ray::new(packet.origins[k], dir.dir, f32::INFINITY);
            if let Some(h) = self.bvh.closest_hit_through(&ray, cut) {
                out.mask |= 1 << k;
                out.t[k] = h.t;
                out.triangle[k] = h.triangle;
                out.barycentrics[k] = h.barycentrics;
            }
        }
        out
    }
}

impl Bvh {
    /// Whether every corner index is below `n`.
    fn corners_within(&self, n: usize) -> bool {
        self.max_corner.is_none_or(|m| (m as usize) < n)
    }
}

/// The set bits of `mask`, lowest first.
fn lanes(mut mask: u32) -> impl Iterator<Item = usize> {
    std::iter::from_fn(move || {
        (mask != 0).then(|| {
            let k = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            k
        })
    })
}

#[cfg(target_arch = "x86_64")]
mod avx2 {
    //! The AVX2 traversal: one lane per ray; lane masks are bit sets, bit
    //! `k` for lane `k`.

    use std::arch::x86_64::*;

    use super::{Direction, LANES, LEAF, Node2, Packet, PacketBvh, PacketHits, lanes, octant};
    use crate::bvh::{Bvh, FAR_SCALE, STACK, edge_functions};
    use crate::cut_outs::CutOutTable;

    /// What every test of one traversal shares.
    struct Rays {
        /// `o * (1/d)` per axis: a plane's distance is `plane / d - o / d`.
        o_inv: [__m256; 3],
        inv: [__m256; 3],
        /// Ray-space origins.
        r: [__m256; 3],
    }

    #[inline(always)]
    unsafe fn load(a: &[f32; LANES]) -> __m256 {
        unsafe { _mm256_loadu_ps(a.as_ptr()) }
    }

    #[inline(always)]
    unsafe fn store(x: __m256) -> [f32; LANES] {
        let mut o = [0.0f32; LANES];
        unsafe { _mm256_storeu_ps(o.as_mut_ptr(), x) };
        o
    }

    /// The bit set of lanes where `x` is set.
    #[inline(always)]
    unsafe fn bits(x: __m256) -> u32 {
        unsafe { _mm256_movemask_ps(x) as u32 }
    }

    /// A select mask from the bit set `bits`.
    #[inline(always)]
    unsafe fn lane_mask(bits: u32) -> __m256 {
        unsafe {
            let lane_bits = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
            let b = _mm256_set1_epi32(bits as i32);
            _mm256_castsi256_ps(_mm256_cmpeq_epi32(
                _mm256_and_si256(b, lane_bits),
                lane_bits,
            ))
        }
    }

    /// The edge functions `uvw` of the lanes in `zeros` redone from the
    /// relative corners `e` (`ax, ay, bx, by, cx, cy`) in `f64`.
    #[cold]
    #[inline(never)]
    fn redo_in_f64(e: &[[f32; LANES]; 6], uvw: &mut [[f32; LANES]; 3], zeros: u32) {
        for l in lanes(zeros) {
            (uvw[0][l], uvw[1][l], uvw[2][l]) = edge_functions(e.map(|x| x[l]));
        }
    }

    /// The lanes of `hits` (lanes meeting leaf-order triangle `k` with edge
    /// functions `uvw` and `1/det` `inv`) that the triangle stops: all of
    /// them unless it cuts out.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    unsafe fn stopped(
        cut: &CutOutTable,
        bvh: &Bvh,
        k: usize,
        hits: u32,
        [u, v, w]: [__m256; 3],
        inv: __m256,
        packet: &Packet,
        dir: &Direction,
    ) -> u32 {
        if hits == 0 || !cut.flagged(k) {
            return hits;
        }
        // SAFETY: AVX2 is available (the caller's requirement).
        let (u, v, w, inv) = unsafe { (store(u), store(v), store(w), store(inv)) };
        let id = bvh.ids[k];
        let mut kept = hits;
        for l in lanes(hits) {
            // The weights as `nearest` reports them.
            let b = [u[l] * inv[l], v[l] * inv[l], w[l] * inv[l]];
            if !cut.stops(id, b, packet.origins[l], dir.dir) {
                kept &= !(1 << l);
            }
        }
        kept
    }

    impl Rays {
        #[inline(always)]
        unsafe fn new(dir: &Direction, p: &Packet) -> Self {
            unsafe {
                let inv = dir.inv.to_array();
                let inv = [
                    _mm256_set1_ps(inv[0]),
                    _mm256_set1_ps(inv[1]),
                    _mm256_set1_ps(inv[2]),
                ];
                let (wx, wy, wz) = (load(&p.world[0]), load(&p.world[1]), load(&p.world[2]));
                Self {
                    o_inv: [
                        _mm256_mul_ps(wx, inv[0]),
                        _mm256_mul_ps(wy, inv[1]),
                        _mm256_mul_ps(wz, inv[2]),
                    ],
                    inv,
                    r: [load(&p.local[0]), load(&p.local[1]), load(&p.local[2])],
                }
            }
        }

        /// Lanes whose ray meets the box of slot `s` of `node` within
        /// `(0, t_max)`.
        #[inline(always)]
        unsafe fn hits_box(&self, node: &Node2, s: usize, t_max: __m256) -> u32 {
            unsafe {
                let [n0, n1, n2] = [0, 1, 2].map(|a| _mm256_set1_ps(node.near[a][s]));
                let [f0, f1, f2] = [0, 1, 2].map(|a| _mm256_set1_ps(node.far[a][s]));
                let scale = _mm256_set1_ps(FAR_SCALE);
                let [ix, iy, iz] = self.inv;
                let [ox, oy, oz] = self.o_inv;
                let ok = {
                    let near = _mm256_max_ps(
                        _mm256_max_ps(_mm256_fmsub_ps(n0, ix, ox), _mm256_fmsub_ps(n1, iy, oy)),
                        _mm256_max_ps(_mm256_fmsub_ps(n2, iz, oz), _mm256_setzero_ps()),
                    );
                    let far = _mm256_min_ps(
                        _mm256_min_ps(_mm256_fmsub_ps(f0, ix, ox), _mm256_fmsub_ps(f1, iy, oy)),
                        _mm256_min_ps(_mm256_fmsub_ps(f2, iz, oz), t_max),
                    );
                    _mm256_cmp_ps::<_CMP_LE_OQ>(near, _mm256_mul_ps(far, scale))
                };
                bits(ok)
            }
        }

        /// Triangle `k` (leaf order) against every lane: `(hit lanes, t,
        /// [u, v, w], 1/det)` with `0 < t < t_max` on hit lanes. Its
        /// corners in ray space are read from `local`.
        #[inline(always)]
        unsafe fn hits_triangle(
            &self,
            bvh: &Bvh,
            local: &[[f32; 4]],
            k: usize,
            live: u32,
            t_max: __m256,
        ) -> (u32, __m256, [__m256; 3], __m256) {
            unsafe {
                let [ia, ib, ic] = *bvh.corners.get_unchecked(k);
                let a = local.get_unchecked(ia as usize);
                let b = local.get_unchecked(ib as usize);
                let c = local.get_unchecked(ic as usize);
                self.hits_corners(a, b, c, live, t_max)
            }
        }

        /// [`hits_triangle`](Self::hits_triangle) with the corners in ray
        /// space `a`, `b`, `c`.
        #[inline(always)]
        unsafe fn hits_corners(
            &self,
            a: &[f32; 4],
            b: &[f32; 4],
            c: &[f32; 4],
            live: u32,
            t_max: __m256,
        ) -> (u32, __m256, [__m256; 3], __m256) {
            unsafe {
                let [rx, ry, rz] = self.r;
                let (sax, say, saz) = (
                    _mm256_set1_ps(a[0]),
                    _mm256_set1_ps(a[1]),
                    _mm256_set1_ps(a[2]),
                );
                let (sbx, sby, sbz) = (
                    _mm256_set1_ps(b[0]),
                    _mm256_set1_ps(b[1]),
                    _mm256_set1_ps(b[2]),
                );
                let (scx, scy, scz) = (
                    _mm256_set1_ps(c[0]),
                    _mm256_set1_ps(c[1]),
                    _mm256_set1_ps(c[2]),
                );
                let ax = _mm256_sub_ps(sax, rx);
                let ay = _mm256_sub_ps(say, ry);
                let bx = _mm256_sub_ps(sbx, rx);
                let by = _mm256_sub_ps(sby, ry);
                let cx = _mm256_sub_ps(scx, rx);
                let cy = _mm256_sub_ps(scy, ry);
                let mut u = _mm256_sub_ps(_mm256_mul_ps(cx, by), _mm256_mul_ps(cy, bx));
                let mut v = _mm256_sub_ps(_mm256_mul_ps(ax, cy), _mm256_mul_ps(ay, cx));
                let mut w = _mm256_sub_ps(_mm256_mul_ps(bx, ay), _mm256_mul_ps(by, ax));
                let zero = _mm256_setzero_ps();
                let zeros = bits(_mm256_or_ps(
                    _mm256_or_ps(
                        _mm256_cmp_ps::<_CMP_EQ_OQ>(u, zero),
                        _mm256_cmp_ps::<_CMP_EQ_OQ>(v, zero),
                    ),
                    _mm256_cmp_ps::<_CMP_EQ_OQ>(w, zero),
                )) & live;
                if zeros != 0 {
                    // Rare: an edge through a ray. Redo those lanes in f64.
                    let e = [
                        store(ax),
                        store(ay),
                        store(bx),
                        store(by),
                        store(cx),
                        store(cy),
                    ];
                    let mut uvw = [store(u), store(v), store(w)];
                    redo_in_f64(&e, &mut uvw, zeros);
                    (u, v, w) = (load(&uvw[0]), load(&uvw[1]), load(&uvw[2]));
                }
                // Inside when the edge functions do not differ in sign:
                // most tests end here, before the division.
                let outside = _mm256_and_ps(
                    _mm256_or_ps(
                        _mm256_or_ps(
                            _mm256_cmp_ps::<_CMP_LT_OQ>(u, zero),
                            _mm256_cmp_ps::<_CMP_LT_OQ>(v, zero),
                        ),
                        _mm256_cmp_ps::<_CMP_LT_OQ>(w, zero),
                    ),
                    _mm256_or_ps(
                        _mm256_or_ps(
                            _mm256_cmp_ps::<_CMP_GT_OQ>(u, zero),
                            _mm256_cmp_ps::<_CMP_GT_OQ>(v, zero),
                        ),
                        _mm256_cmp_ps::<_CMP_GT_OQ>(w, zero),
                    ),
                );
                let inside = !bits(outside) & live;
                if inside == 0 {
                    return (0, zero, [u, v, w], zero);
                }
                let one = _mm256_set1_ps(1.0);
                let inv = _mm256_div_ps(one, _mm256_add_ps(_mm256_add_ps(u, v), w));
                let t = _mm256_mul_ps(
                    _mm256_add_ps(
                        _mm256_add_ps(
                            _mm256_mul_ps(u, _mm256_sub_ps(saz, rz)),
                            _mm256_mul_ps(v, _mm256_sub_ps(sbz, rz)),
                        ),
                        _mm256_mul_ps(w, _mm256_sub_ps(scz, rz)),
                    ),
                    inv,
                );
                let abs_mask = _mm256_set1_ps(-0.0);
                let infinity = _mm256_set1_ps(f32::INFINITY);
                let ok = {
                    // 1/det is finite exactly when det != 0.
                    let finite =
                        _mm256_cmp_ps::<_CMP_LT_OQ>(_mm256_andnot_ps(abs_mask, inv), infinity);
                    let ahead = _mm256_and_ps(
                        _mm256_cmp_ps::<_CMP_GT_OQ>(t, zero),
                        _mm256_cmp_ps::<_CMP_LT_OQ>(t, t_max),
                    );
                    _mm256_and_ps(finite, ahead)
                };
                (bits(ok) & inside, t, [u, v, w], inv)
            }
        }
    }

    /// A visit of inner node `node` by the lanes of `mask`: the lanes
    /// reaching each of its two slots (nearer first).
    #[inline(always)]
    unsafe fn visit(rays: &Rays, node: &Node2, mask: u32, t_max: __m256) -> [u32; 2] {
        unsafe {
            [
                rays.hits_box(node, 0, t_max) & mask,
                rays.hits_box(node, 1, t_max) & mask,
            ]
        }
    }

    /// Walks `tree` for `packet`, nearer children first (farther first
    /// when `FAR_FIRST`: an any-hit ray from a surface is blocked, if at
    /// all, by something across the mesh rather than by its own
    /// neighbourhood, and finding it sooner ends the walk sooner), calling
    /// `leaf(first, count, lanes, t_max)` for each leaf some lanes reach;
    /// `leaf` returns the lanes still open after it (any-hit drops the
    /// blocked ones) and may lower `t_max`. Stops when no lane is open.
    #[inline(always)]
    unsafe fn walk<const FAR_FIRST: bool>(
        tree: &PacketBvh,
        nodes: &[Node2],
        rays: &Rays,
        live: u32,
        t_max: &mut __m256,
        mut leaf: impl FnMut(usize, usize, u32, &mut __m256) -> u32,
    ) {
        unsafe {
            let mut open = live;
            // Left uninitialised: every entry is written before it is read.
            let mut stack = [const { std::mem::MaybeUninit::<(u32, u32, u32)>::uninit() }; STACK];
            let mut top = 0;
            let mut current = (tree.root.0, tree.root.1, live);
            loop {
                let (child, count, lanes) = current;
                let mask = lanes & open;
                if mask != 0 {
                    if child & LEAF != 0 {
                        open &= leaf((child & !LEAF) as usize, count as usize, mask, t_max) | !mask;
                        if open == 0 {
                            return;
                        }
                    } else {
                        let node = nodes.get_unchecked(child as usize);
                        let m = visit(rays, node, mask, *t_max);
                        let (a, b) = if FAR_FIRST { (1, 0) } else { (0, 1) };
                        if m[a] != 0 {
                            if m[b] != 0 {
                                stack.get_unchecked_mut(top).write((
                                    node.child[b],
                                    node.count[b],
                                    m[b],
                                ));
                                top += 1;
                            }
                            current = (node.child[a], node.count[a], m[a]);
                            continue;
                        }
                        if m[b] != 0 {
                            current = (node.child[b], node.count[b], m[b]);
                            continue;
                        }
                    }
                }
                if top == 0 {
                    return;
                }
                top -= 1;
                current = stack.get_unchecked(top).assume_init();
            }
        }
    }

    /// Lanes of `packet` blocked along `dir`, through the cut-outs `cut`
    /// when `CUT`.
    ///
    /// # Safety
    /// AVX2 and FMA must be available, and every corner index of `tree`
    /// below `local.len()`; `cut` given when `CUT`.
    #[target_feature(enable = "avx2,fma")]
    pub(super) unsafe fn occluded<const CUT: bool>(
        tree: &PacketBvh,
        dir: &Direction,
        local: &[[f32; 4]],
        packet: &Packet,
        cut: Option<&CutOutTable>,
    ) -> u32 {
        unsafe {
            let rays = Rays::new(dir, packet);
            let mut t_max = _mm256_set1_ps(f32::INFINITY);
            let mut blocked = 0u32;
            walk::<true>(
                tree,
                &tree.octants[octant(dir)],
                &rays,
                packet.live,
                &mut t_max,
                |first, count, mut mask, t_max| {
                    for k in first..first + count {
                        let (mut hits, _, uvw, inv) =
                            rays.hits_triangle(&tree.bvh, local, k, mask, *t_max);
                        if CUT && let Some(c) = cut {
                            hits = stopped(c, &tree.bvh, k, hits, uvw, inv, packet, dir);
                        }
                        blocked |= hits;
                        mask &= !hits;
                        if mask == 0 {
                            break;
                        }
                    }
                    mask
                },
            );
            blocked
        }
    }

    /// Nearest hits of `packet`'s rays along `dir`.
    ///
    /// # Safety
    /// As [`occluded`].
    #[target_feature(enable = "avx2,fma")]
    pub(super) unsafe fn closest<const CUT: bool>(
        tree: &PacketBvh,
        dir: &Direction,
        local: &[[f32; 4]],
        packet: &Packet,
        cut: Option<&CutOutTable>,
    ) -> PacketHits {
        unsafe {
            nearest(tree, dir, packet, |rays, k, mask, t_max| {
                let (mut hits, t, uvw, inv) = rays.hits_triangle(&tree.bvh, local, k, mask, t_max);
                if CUT && let Some(c) = cut {
                    hits = stopped(c, &tree.bvh, k, hits, uvw, inv, packet, dir);
                }
                (hits, t, uvw, inv)
            })
        }
    }

    /// [`closest`] with each triangle's corners put in ray space as it is
    /// tested.
    ///
    /// # Safety
    /// AVX2 and FMA must be available; `cut` given when `CUT`.
    #[target_feature(enable = "avx2,fma")]
    pub(super) unsafe fn closest_direct<const CUT: bool>(
        tree: &PacketBvh,
        dir: &Direction,
        packet: &Packet,
        cut: Option<&CutOutTable>,
    ) -> PacketHits {
        unsafe {
            nearest(tree, dir, packet, |rays, k, mask, t_max| {
                // Not `map` with a closure: core's `map` has no AVX2, so a
                // closure called from it would not be inlined.
                let [pa, pb, pc] = *tree.bvh.triangles.get_unchecked(k);
                let (a, b, c) = (
                    dir.to_ray_space(pa),
                    dir.to_ray_space(pb),
                    dir.to_ray_space(pc),
                );
                let (mut hits, t, uvw, inv) = rays.hits_corners(&a, &b, &c, mask, t_max);
                if CUT && let Some(cut) = cut {
                    hits = stopped(cut, &tree.bvh, k, hits, uvw, inv, packet, dir);
                }
                (hits, t, uvw, inv)
            })
        }
    }

    /// The closest-hit walk, `test(rays, k, lanes, t_max)` testing
    /// triangle `k` (leaf order).
    #[inline(always)]
    unsafe fn nearest(
        tree: &PacketBvh,
        dir: &Direction,
        packet: &Packet,
        test: impl Fn(&Rays, usize, u32, __m256) -> (u32, __m256, [__m256; 3], __m256),
    ) -> PacketHits {
        unsafe {
            let rays = Rays::new(dir, packet);
            let mut t_max = _mm256_set1_ps(f32::INFINITY);
            let mut best = _mm256_setzero_ps();
            let mut bary = [_mm256_setzero_ps(); 3];
            let mut hit_mask = 0u32;
            let bvh = &tree.bvh;
            walk::<false>(
                tree,
                &tree.octants[octant(dir)],
                &rays,
                packet.live,
                &mut t_max,
                |first, count, mask, t_max| {
                    for k in first..first + count {
                        let (hits, t, [u, v, w], inv) = test(&rays, k, mask, *t_max);
                        if hits != 0 {
                            let sel = lane_mask(hits);
                            let id = _mm256_castsi256_ps(_mm256_set1_epi32(k as i32));
                            *t_max = _mm256_blendv_ps(*t_max, t, sel);
                            best = _mm256_blendv_ps(best, id, sel);
                            for (b, x) in bary.iter_mut().zip([u, v, w]) {
                                *b = _mm256_blendv_ps(*b, _mm256_mul_ps(x, inv), sel);
                            }
                            hit_mask |= hits;
                        }
                    }
                    mask
                },
            );
            let (t, k) = (store(t_max), store(best));
            let [u, v, w] = [store(bary[0]), store(bary[1]), store(bary[2])];
            let mut out = PacketHits {
                mask: hit_mask,
                t,
                triangle: [0; LANES],
                barycentrics: [[0.0; 3]; LANES],
            };
            for l in lanes(hit_mask) {
                out.triangle[l] = bvh.ids[k[l].to_bits() as usize];
                out.barycentrics[l] = [u[l], v[l], w[l]];
            }
            out
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bvh::tests::random_unit;
    use rand::{Rng, SeedableRng, rngs::StdRng};
    use shlight_mesh::generate;

    #[test]
    fn packets_agree_with_single_rays() {
        // On a processor with AVX2 this compares the 8-lane traversal with
        // the single-ray one, ray by ray; elsewhere both are single rays.
        if !packets_enabled() {
            crate::skip_test(
                "packets_agree_with_single_rays",
                "no AVX2 and FMA here: the packets are single rays, compared with themselves",
            );
        }
        let mesh = generate::plane_under_sphere(1.0, 24, 12, 4.0, 6);
        let tree = PacketBvh::new(Bvh::new(&mesh.positions, &mesh.triangles));
        let bvh = tree.bvh();
        let mut rng = StdRng::seed_from_u64(11);
        let (mut hits, mut mismatched, mut rays) = (0, 0, 0);
        for _ in 0..60 {
            let dir = Direction::new(random_unit(&mut rng));
            let local: Vec<[f32; 4]> = mesh
                .positions
                .iter()
                .map(|p| dir.to_ray_space(*p))
                .collect();
            for _ in 0..20 {
                // Eight origins close together, as baking makes them.
                let centre = Vec3::new(
                    rng.random_range(-2.0..2.0),
                    rng.random_range(-0.2..2.2),
                    rng.random_range(-2.0..2.0),
                );
                let n = rng.random_range(1..=LANES);
                let origins: Vec<Vec3> = (0..n)
                    .map(|_| centre + random_unit(&mut rng) * rng.random_range(0.0..0.2))
                    .collect();
                let packet = Packet::new(&dir, &origins);
                let blocked = tree.occluded(&dir, &local, &packet, None);
                let found = tree.closest(&dir, &local, &packet, None);
                // Corners put in ray space as they are tested: the same
                // numbers, so the same hits to the bit (without AVX2 both
                // are the single-ray traversal).
                assert_eq!(tree.closest_direct(&dir, &packet, None), found);
                assert_eq!(blocked >> n, 0, "only live lanes");
                assert_eq!(blocked, found.mask, "occlusion and closest hits agree");
                for (k, o) in origins.iter().enumerate() {
                    rays += 1;
                    let single = bvh.closest_hit(&Ray::new(*o, dir.dir(), f32::INFINITY));
                    match (found.mask >> k & 1 == 1, single) {
                        (true, Some(h)) => {
                            hits += 1;
                            assert!((found.t[k] - h.t).abs() < 1e-4 * h.t.max(1.0));
                            if found.triangle[k] != h.triangle {
                                mismatched += 1;
                            }
                            let w = found.barycentrics[k];
                            assert!((w.iter().sum::<f32>() - 1.0).abs() < 1e-5);
                            let tri = mesh.triangles[found.triangle[k] as usize]
                                .map(|i| mesh.positions[i as usize]);
                            let p = tri[0] * w[0] + tri[1] * w[1] + tri[2] * w[2];
                            assert!(p.distance(*o + dir.dir() * found.t[k]) < 1e-4);
                        }
                        (false, None) => {}
                        // Only a ray grazing an edge may disagree.
                        _ => mismatched += 1,
                    }
                }
            }
        }
        assert!(hits > 1500, "{hits} of {rays}");
        assert!(mismatched <= 3, "{mismatched} disagreements in {rays} rays");
    }

    #[test]
    fn parallel_rays_through_shared_edges_and_vertices_never_slip_through() {
        // Bundles of parallel rays from inside a closed sphere aimed exactly
        // at its vertices and edge midpoints must all hit.
        if !packets_enabled() {
            crate::skip_test(
                "parallel_rays_through_shared_edges_and_vertices_never_slip_through",
                "no AVX2 and FMA here: single rays are cast instead of packets, \
                 and closest_direct is compared with closest, the same traversal",
            );
        }
        let mesh = generate::uv_sphere(1.0, 37, 23);
        let tree = PacketBvh::new(Bvh::new(&mesh.positions, &mesh.triangles));
        let mut targets: Vec<Vec3> = mesh.positions.clone();
        for t in &mesh.triangles {
            let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
            targets.extend([(a + b) * 0.5, (b + c) * 0.5, (c + a) * 0.5]);
        }
        let mut rng = StdRng::seed_from_u64(3);
        let (mut cast, mut missed) = (0, 0);
        for d in [
            Vec3::X,
            Vec3::Y,
            Vec3::NEG_Z,
            random_unit(&mut rng),
            random_unit(&mut rng),
        ] {
            let dir = Direction::new(d);
            let local: Vec<[f32; 4]> = mesh
                .positions
                .iter()
                .map(|p| dir.to_ray_space(*p))
                .collect();
            let origins: Vec<Vec3> = targets
                .iter()
                .filter(|q| q.dot(dir.dir()) > 0.3)
                .map(|q| *q - 0.5 * dir.dir())
                .collect();
            for eight in origins.chunks(LANES) {
                let packet = Packet::new(&dir, eight);
                let blocked = tree.occluded(&dir, &local, &packet, None);
                cast += eight.len();
                missed += eight.len() - blocked.count_ones() as usize;
                // Without AVX2 these are the single-ray traversal thrice.
                assert_eq!(tree.closest(&dir, &local, &packet, None).mask, blocked);
                assert_eq!(tree.closest_direct(&dir, &packet, None).mask, blocked);
            }
        }
        assert!(cast > 3000, "{cast}");
        assert_eq!(missed, 0, "of {cast} rays");
    }
}
