//! A bounding-volume hierarchy over a mesh's triangles, for the visibility
//! and bounce rays of the bakes.
//!
//! - **Build**: binary, top-down, binned surface-area heuristic (16 bins on
//!   the centroid bounds of each axis, the cheapest split of the three, the
//!   longest axis first among equals; cost [`NODE_COST`] per node visit, 1
//!   per triangle test: on the longest axis alone, a dense scanned scene's
//!   packets visited 5% more nodes and tested 7% more triangles), leaves
//!   of at most [`MAX_LEAF`] triangles, nodes in
//!   depth-first order with the two children next to each other, each inner
//!   node remembering its split axis. Triangles are copied into leaf order,
//!   so a leaf reads contiguous memory.
//! - **Boxes** are grown by [`BOX_PADDING`] and the far distance of a box
//!   test is widened by `1 + 2 gamma(3)` (Ize 2013), so rounding never loses
//!   a box that a ray touches.
//! - **Single rays** ([`Bvh::occluded`], [`Bvh::closest_hit`]): a fixed
//!   stack, the nearer child first. Baking casts bundles of parallel rays
//!   through the same nodes instead ([`crate::packet`]); single rays serve
//!   processors without AVX2 and the tests.
//! - **Triangles**: the watertight test of Woop, Benthin and Wald (JCGT
//!   2013): the ray is sheared to +z, edge functions are evaluated in the
//!   sheared plane and redone in `f64` when one is exactly zero, so a ray
//!   through an edge or a vertex shared by triangles hits at least one of
//!   them, never slipping between. Both sides of a triangle are hit.
//!
//! Chosen by `benches/rays.rs`, which also measures obvhs's compressed wide
//! BVH (docs/benchmarks.md, "PRT").

use glam::Vec3;

use crate::cut_outs::CutOutTable;

/// Where a ray hit a triangle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Distance along the (unit or not) direction: the point is `o + t d`.
    pub t: f32,
    /// Index of the triangle in the mesh's triangle list.
    pub triangle: u32,
    /// Barycentric weights of the triangle's three corners, in the order of
    /// its indices; they sum to 1 and the point is `sum w_i p_i`.
    pub barycentrics: [f32; 3],
}

/// The part of a ray the watertight triangle test (Woop, Benthin & Wald
/// 2013) needs, computed once per ray: axes permuted so that `kz` is the
/// direction's largest component, and the shear that maps the direction to
/// +z.
#[derive(Clone, Copy, Debug)]
pub(crate) struct WatertightRay {
    origin: Vec3,
    k: [usize; 3],
    shear: Vec3,
}

/// A ray with what every test against it needs, computed once.
#[derive(Clone, Copy, Debug)]
pub struct Ray {
    origin: Vec3,
    dir: Vec3,
    inv_dir: Vec3,
    triangle: WatertightRay,
    t_max: f32,
}

/// The most triangles in one leaf.
const MAX_LEAF: usize = 8;
/// What the surface-area heuristic charges a node visit, a triangle test
/// costing 1. A packet's visit tests two boxes against eight lanes, while
/// most triangle tests end when the lanes' edge functions differ in sign,
/// before the division; so leaves may hold more triangles, and the walks
/// are shorter (docs/benchmarks.md, "Irradiance volume bake", has the
/// timings).
const NODE_COST: f32 = 4.0;
const BINS: usize = 16;
/// Depth of the traversal stacks; the build never nests deeper (a split
/// always leaves both sides non-empty, and [`MAX_DEPTH`] caps it).
pub(crate) const STACK: usize = 64;
/// The deepest node the build makes (leaves below it hold more triangles).
const MAX_DEPTH: usize = STACK - 2;
/// `1 + 2 gamma(3)`, `gamma(n) = n u / (1 - n u)`, `u = 2^-24`: the far
/// distance of a box test is multiplied by it.
pub(crate) const FAR_SCALE: f32 =
    1.0 + 2.0 * (3.0 * f32::EPSILON * 0.5) / (1.0 - 3.0 * f32::EPSILON * 0.5);
/// Relative growth of triangle boxes, about 16 units in the last place of
/// the mesh's largest coordinate.
const BOX_PADDING: f32 = 16.0 * f32::EPSILON;
/// Direction components smaller than this are replaced by it (with their
/// sign) before inverting, so slab distances stay finite.
pub(crate) const TINY_DIRECTION: f32 = 1e-30;

impl Ray {
    /// The ray `origin + t dir`, `0 < t < t_max`. `dir` need not be unit.
    #[must_use]
    pub fn new(origin: Vec3, dir: Vec3, t_max: f32) -> Self {
        Self {
            origin,
            dir,
            inv_dir: safe_inverse(dir),
            triangle: WatertightRay::new(origin, dir),
            t_max,
        }
    }

    /// The origin.
    pub(crate) fn origin(&self) -> Vec3 {
        self.origin
    }

    /// The direction, as given.
    pub(crate) fn dir(&self) -> Vec3 {
        self.dir
    }

    /// The far limit.
    pub(crate) fn t_max(&self) -> f32 {
        self.t_max
    }

    /// Entry distance into the box, or `None` when missed within `(0, t_max)`.
    #[inline(always)]
    fn hits_box(&self, node: &Node, t_max: f32) -> Option<f32> {
        let t1 = (node.min - self.origin) * self.inv_dir;
        let t2 = (node.max - self.origin) * self.inv_dir;
        let near = t1.min(t2).max_element().max(0.0);
        let far = t1.max(t2).min_element().min(t_max) * FAR_SCALE;
        (near <= far).then_some(near)
    }
}

/// `1 / d` per component, with components below [`TINY_DIRECTION`] in
/// magnitude (zeros included, keeping their sign) raised to it first.
pub(crate) fn safe_inverse(d: Vec3) -> Vec3 {
    let tiny = Vec3::splat(TINY_DIRECTION).copysign(d);
    Vec3::select(d.abs().cmplt(Vec3::splat(TINY_DIRECTION)), tiny, d).recip()
}

impl WatertightRay {
    /// The ray `origin + t dir`; `dir` need not be unit.
    #[must_use]
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        let a = dir.abs();
        let kz = if a.x > a.y {
            if a.x > a.z { 0 } else { 2 }
        } else if a.y > a.z {
            1
        } else {
            2
        };
        let (mut kx, mut ky) = ((kz + 1) % 3, (kz + 2) % 3);
        if dir[kz] < 0.0 {
            core::mem::swap(&mut kx, &mut ky);
        }
        Self {
            origin,
            k: [kx, ky, kz],
            shear: Vec3::new(dir[kx] / dir[kz], dir[ky] / dir[kz], 1.0 / dir[kz]),
        }
    }

    /// The watertight ray-triangle test: `(t, [w0, w1, w2])`, the distance
    /// (`0 < t < t_max`) and the barycentric weights of the three corners,
    /// or `None`.
    #[inline(always)]
    pub fn hits_triangle(&self, tri: &[Vec3; 3], t_max: f32) -> Option<(f32, [f32; 3])> {
        let [kx, ky, kz] = self.k;
        let s = self.shear;
        let rel = tri.map(|v| v - self.origin);
        let sheared = rel.map(|p| (p[kx] - s.x * p[kz], p[ky] - s.y * p[kz]));
        let [(ax, ay), (bx, by), (cx, cy)] = sheared;
        let (u, v, w) = edge_functions([ax, ay, bx, by, cx, cy]);
        if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
            return None;
        }
        let det = u + v + w;
        if det == 0.0 {
            return None;
        }
        let t_scaled = s.z * (u * rel[0][kz] + v * rel[1][kz] + w * rel[2][kz]);
        let inv = det.recip();
        let t = t_scaled * inv;
        (t > 0.0 && t < t_max).then_some((t, [u * inv, v * inv, w * inv]))
    }
}

/// The three edge functions of a triangle whose corners, relative to the
/// ray and in the plane across it, are `(ax, ay), (bx, by), (cx, cy)`:
/// `u = c x b`, `v = a x c`, `w = b x a` (2D cross products), the
/// unnormalised barycentric weights of `a`, `b` and `c`. When one is exactly
/// zero all three are redone in `f64`, so that a ray through a shared edge
/// gets the same decision from both triangles.
#[inline(always)]
pub(crate) fn edge_functions([ax, ay, bx, by, cx, cy]: [f32; 6]) -> (f32, f32, f32) {
    let u = cx * by - cy * bx;
    let v = ax * cy - ay * cx;
    let w = bx * ay - by * ax;
    if u == 0.0 || v == 0.0 || w == 0.0 {
        let f = |a: f32, b: f32, c: f32, d: f32| {
            (f64::from(a) * f64::from(b) - f64::from(c) * f64::from(d)) as f32
        };
        return (f(cx, by, cy, bx), f(ax, cy, ay, cx), f(bx, ay, by, ax));
    }
    (u, v, w)
}

/// One node: a box and either two children (the left at `first`, the right
/// at `first + 1`, split along axis `kind - INNER`) or `kind` triangles from
/// `first` (`kind < INNER`).
#[derive(Clone, Copy, Debug)]
#[repr(C)]
pub(crate) struct Node {
    pub(crate) min: Vec3,
    pub(crate) first: u32,
    pub(crate) max: Vec3,
    pub(crate) kind: u32,
}

/// [`Node::kind`] of inner nodes: `INNER + axis`.
pub(crate) const INNER: u32 = 1 << 31;

/// The hierarchy: nodes, triangles in leaf order (corners, and vertex
/// indices into the mesh), and each one's index in the mesh.
#[derive(Clone, Debug)]
pub(crate) struct Bvh {
    pub(crate) nodes: Vec<Node>,
    pub(crate) triangles: Vec<[Vec3; 3]>,
    pub(crate) corners: Vec<[u32; 3]>,
    /// The largest vertex index of any triangle.
    pub(crate) max_corner: Option<u32>,
    pub(crate) ids: Vec<u32>,
}

struct Builder<'a> {
    max_leaf: usize,
    node_cost: f32,
    bounds: Vec<(Vec3, Vec3)>,
    centroids: Vec<Vec3>,
    order: &'a mut [u32],
    nodes: Vec<Node>,
}

impl Bvh {
    /// Builds the hierarchy over `triangles` (indices into `positions`).
    ///
    /// # Panics
    /// If an index is out of range (a [`shlight_mesh::Mesh`] never has one).
    #[must_use]
    pub fn new(positions: &[Vec3], triangles: &[[u32; 3]]) -> Self {
        let corners: Vec<[Vec3; 3]> = triangles
            .iter()
            .map(|t| t.map(|i| positions[i as usize]))
            .collect();
        let scale = positions
            .iter()
            .fold(0.0f32, |m, p| m.max(p.abs().max_element()));
        let bounds: Vec<(Vec3, Vec3)> = corners.iter().map(|c| padded_box(c, scale)).collect();
        let (nodes, order) = build_nodes(bounds, MAX_LEAF, NODE_COST);
        Self {
            nodes,
            triangles: order.iter().map(|&i| corners[i as usize]).collect(),
            corners: order.iter().map(|&i| triangles[i as usize]).collect(),
            max_corner: triangles.iter().flatten().copied().max(),
            ids: order,
        }
    }

    /// Number of nodes (inner and leaves).
    #[cfg(test)]
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// The nearest hit of `ray`, if any.
    #[must_use]
    pub fn closest_hit(&self, ray: &Ray) -> Option<Hit> {
        self.closest_accepting(ray, |_, _| true)
    }

    /// Whether anything blocks `ray` (the first hit found ends the search).
    #[must_use]
    pub fn occluded(&self, ray: &Ray) -> bool {
        self.occluded_accepting(ray, |_, _| true)
    }

    /// [`closest_hit`](Self::closest_hit) through the cut-outs `cut`
    /// (none: every triangle stops the ray).
    #[must_use]
    pub(crate) fn closest_hit_through(&self, ray: &Ray, cut: Option<&CutOutTable>) -> Option<Hit> {
        match cut {
            None => self.closest_hit(ray),
            Some(c) => self.closest_accepting(ray, |k, w| {
                !c.flagged(k) || c.stops(self.ids[k], w, ray.origin, ray.dir)
            }),
        }
    }

    /// [`occluded`](Self::occluded) through the cut-outs `cut` (none:
    /// every triangle stops the ray).
    #[must_use]
    pub(crate) fn occluded_through(&self, ray: &Ray, cut: Option<&CutOutTable>) -> bool {
        match cut {
            None => self.occluded(ray),
            Some(c) => self.occluded_accepting(ray, |k, w| {
                !c.flagged(k) || c.stops(self.ids[k], w, ray.origin, ray.dir)
            }),
        }
    }

    /// The nearest hit of `ray` that `accept(k, weights)` takes (`k` the
    /// triangle in leaf order); the others are passed over.
    #[inline(always)]
    pub(crate) fn closest_accepting(
        &self,
        ray: &Ray,
        accept: impl Fn(usize, [f32; 3]) -> bool,
    ) -> Option<Hit> {
        let mut best: Option<(f32, u32, [f32; 3])> = None;
        let mut t_max = ray.t_max;
        self.traverse(
            ray,
            |t_max_now, first, count| {
                for k in first..first + count {
                    if let Some((t, w)) = ray.triangle.hits_triangle(&self.triangles[k], *t_max_now)
                        && accept(k, w)
                    {
                        *t_max_now = t;
                        best = Some((t, k as u32, w));
                    }
                }
                false
            },
            &mut t_max,
        );
        best.map(|(t, k, w)| Hit {
            t,
            triangle: self.ids[k as usize],
            barycentrics: w,
        })
    }

    /// Whether a hit of `ray` that `accept` takes exists (as in
    /// [`closest_accepting`](Self::closest_accepting)).
    #[inline(always)]
    pub(crate) fn occluded_accepting(
        &self,
        ray: &Ray,
        accept: impl Fn(usize, [f32; 3]) -> bool,
    ) -> bool {
        let mut t_max = ray.t_max;
        let mut hit = false;
        self.traverse(
            ray,
            |t_max_now, first, count| {
                hit = (first..first + count).any(|k| {
                    ray.triangle
                        .hits_triangle(&self.triangles[k], *t_max_now)
                        .is_some_and(|(_, w)| accept(k, w))
                });
                hit
            },
            &mut t_max,
        );
        hit
    }

    /// Visits the leaves `ray` may reach ([`traverse`]).
    #[inline(always)]
    fn traverse(
        &self,
        ray: &Ray,
        leaf: impl FnMut(&mut f32, usize, usize) -> bool,
        t_max: &mut f32,
    ) {
        traverse(&self.nodes, ray, leaf, t_max);
    }

    /// The root's box (the triangles' padded boxes together).
    pub(crate) fn bounds(&self) -> (Vec3, Vec3) {
        (self.nodes[0].min, self.nodes[0].max)
    }

    /// Bytes held on the heap.
    pub(crate) fn heap_bytes(&self) -> usize {
        self.nodes.capacity() * size_of::<Node>()
            + self.triangles.capacity() * size_of::<[Vec3; 3]>()
            + self.corners.capacity() * size_of::<[u32; 3]>()
            + self.ids.capacity() * size_of::<u32>()
    }

    /// Leaves out the triangles' vertex indices, which only the packet
    /// traversal and the ray origins read.
    pub(crate) fn without_corners(mut self) -> Self {
        self.corners = Vec::new();
        self.max_corner = None;
        self
    }
}

/// The nodes of a hierarchy over items whose boxes are `bounds`, built as
/// the crate's triangle hierarchy is (binned SAH, a node visit costing
/// `node_cost` items, leaves of at most `max_leaf` items where the
/// heuristic allows), and the items in leaf order: a leaf's `first..first +
/// kind` index that order.
pub(crate) fn build_nodes(
    bounds: Vec<(Vec3, Vec3)>,
    max_leaf: usize,
    node_cost: f32,
) -> (Vec<Node>, Vec<u32>) {
    let n = bounds.len();
    let centroids = bounds.iter().map(|(lo, hi)| (*lo + *hi) * 0.5).collect();
    let mut order: Vec<u32> = (0..n as u32).collect();
    let mut builder = Builder {
        max_leaf,
        node_cost,
        bounds,
        centroids,
        order: &mut order,
        nodes: Vec::with_capacity(2 * n.div_ceil(max_leaf).max(1)),
    };
    builder.nodes.push(Node {
        min: Vec3::ZERO,
        first: 0,
        max: Vec3::ZERO,
        kind: 0,
    });
    builder.build(0, 0, n, 0);
    (builder.nodes, order)
}

/// Visits the leaves of `nodes` that `ray` may reach, nearer child first;
/// `leaf` gets the current far limit (which it may shrink), the first item
/// and the count, and returns `true` to stop.
#[inline(always)]
pub(crate) fn traverse(
    nodes: &[Node],
    ray: &Ray,
    mut leaf: impl FnMut(&mut f32, usize, usize) -> bool,
    t_max: &mut f32,
) {
    let root = &nodes[0];
    if ray.hits_box(root, *t_max).is_none() {
        return;
    }
    let mut stack = [0u32; STACK];
    let mut top = 0;
    let mut node = root;
    loop {
        if node.kind < INNER {
            if leaf(t_max, node.first as usize, node.kind as usize) {
                return;
            }
        } else {
            let (l, r) = (&nodes[node.first as usize], &nodes[node.first as usize + 1]);
            match (ray.hits_box(l, *t_max), ray.hits_box(r, *t_max)) {
                (Some(a), Some(b)) => {
                    let (near, far) = if a <= b {
                        (node.first, node.first + 1)
                    } else {
                        (node.first + 1, node.first)
                    };
                    stack[top] = far;
                    top += 1;
                    node = &nodes[near as usize];
                    continue;
                }
                (Some(_), None) => {
                    node = l;
                    continue;
                }
                (None, Some(_)) => {
                    node = r;
                    continue;
                }
                (None, None) => {}
            }
        }
        if top == 0 {
            return;
        }
        top -= 1;
        node = &nodes[stack[top] as usize];
    }
}

/// A triangle's bounding box grown by [`BOX_PADDING`] of `scale`, the
/// mesh's largest coordinate, so that box tests, which do not round
/// outwards, still reach every box that a ray from anywhere in the mesh's
/// box touches, also when the triangle test works in a rotated frame
/// ([`crate::packet`]).
fn padded_box([a, b, c]: &[Vec3; 3], scale: f32) -> (Vec3, Vec3) {
    padded((a.min(*b).min(*c), a.max(*b).max(*c)), scale)
}

/// The box `(lo, hi)` grown by [`BOX_PADDING`] of `scale`.
pub(crate) fn padded((lo, hi): (Vec3, Vec3), scale: f32) -> (Vec3, Vec3) {
    let pad = Vec3::splat(scale * BOX_PADDING + f32::MIN_POSITIVE);
    (lo - pad, hi + pad)
}

impl Builder<'_> {
    /// Fills node `index` (at `depth`) with triangles `order[start..end]`,
    /// splitting it when the surface-area heuristic says so.
    fn build(&mut self, index: usize, start: usize, end: usize, depth: usize) {
        let (mut lo, mut hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
        let (mut clo, mut chi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
        for &i in &self.order[start..end] {
            let (a, b) = self.bounds[i as usize];
            lo = lo.min(a);
            hi = hi.max(b);
            let c = self.centroids[i as usize];
            clo = clo.min(c);
            chi = chi.max(c);
        }
        let n = end - start;
        let leaf = Node {
            min: lo,
            first: start as u32,
            max: hi,
            kind: n as u32,
        };
        let extent = chi - clo;
        let mut axis = extent.max_position();
        if n <= 1 || depth >= MAX_DEPTH {
            self.nodes[index] = leaf;
            return;
        }
        if extent[axis] <= 0.0 {
            // Every centroid in one point: no split can separate them.
            self.nodes[index] = leaf;
            if n > self.max_leaf {
                self.split_at(index, start, end, start + n / 2, lo, hi, axis, depth);
            }
            return;
        }
        let area = |(a, b): (Vec3, Vec3)| {
            let d = (b - a).max(Vec3::ZERO);
            d.x * d.y + d.y * d.z + d.z * d.x
        };
        // Binned SAH on every axis the centroids spread along, the
        // triangles binned on the three in one pass.
        let axes = [axis, (axis + 1) % 3, (axis + 2) % 3];
        let spread = axes.map(|ax| extent[ax] > 0.0);
        let scales = axes.map(|ax| BINS as f32 / extent[ax]);
        let mut counts = [[0usize; BINS]; 3];
        let mut boxes = [[(Vec3::INFINITY, Vec3::NEG_INFINITY); BINS]; 3];
        for &i in &self.order[start..end] {
            let c = self.centroids[i as usize];
            let (a, d) = self.bounds[i as usize];
            for s in 0..3 {
                if spread[s] {
                    let ax = axes[s];
                    let b = (((c[ax] - clo[ax]) * scales[s]) as usize).min(BINS - 1);
                    counts[s][b] += 1;
                    boxes[s][b] = (boxes[s][b].0.min(a), boxes[s][b].1.max(d));
                }
            }
        }
        let (mut best, mut best_cost) = (0, f32::INFINITY);
        for s in 0..3 {
            if !spread[s] {
                continue;
            }
            let (counts, boxes) = (&counts[s], &boxes[s]);
            let mut right_cost = [0.0f32; BINS];
            let (mut acc, mut cnt) = ((Vec3::INFINITY, Vec3::NEG_INFINITY), 0);
            for b in (1..BINS).rev() {
                acc = (acc.0.min(boxes[b].0), acc.1.max(boxes[b].1));
                cnt += counts[b];
                right_cost[b] = area(acc) * cnt as f32;
            }
            let (mut acc, mut cnt) = ((Vec3::INFINITY, Vec3::NEG_INFINITY), 0);
            for b in 0..BINS - 1 {
                acc = (acc.0.min(boxes[b].0), acc.1.max(boxes[b].1));
                cnt += counts[b];
                if cnt == 0 || cnt == n {
                    continue;
                }
                let cost = area(acc) * cnt as f32 + right_cost[b + 1];
                if cost < best_cost {
                    best_cost = cost;
                    best = b;
                    axis = axes[s];
                }
            }
        }
        let scale = BINS as f32 / extent[axis];
        let bin_of = |c: Vec3| (((c[axis] - clo[axis]) * scale) as usize).min(BINS - 1);
        let parent_area = area((lo, hi));
        let split_cost = self.node_cost + best_cost / parent_area.max(f32::MIN_POSITIVE);
        if n <= self.max_leaf && split_cost >= n as f32 || best_cost == f32::INFINITY {
            self.nodes[index] = leaf;
            if n > self.max_leaf {
                self.split_at(index, start, end, start + n / 2, lo, hi, axis, depth);
            }
            return;
        }
        let mut mid = start;
        for k in start..end {
            if bin_of(self.centroids[self.order[k] as usize]) <= best {
                self.order.swap(k, mid);
                mid += 1;
            }
        }
        self.split_at(index, start, end, mid, lo, hi, axis, depth);
    }

    /// Makes node `index` an inner node over `start..mid` and `mid..end`,
    /// split along `axis`.
    #[allow(clippy::too_many_arguments)]
    fn split_at(
        &mut self,
        index: usize,
        start: usize,
        end: usize,
        mid: usize,
        lo: Vec3,
        hi: Vec3,
        axis: usize,
        depth: usize,
    ) {
        let first = self.nodes.len();
        let empty = Node {
            min: Vec3::ZERO,
            first: 0,
            max: Vec3::ZERO,
            kind: 0,
        };
        self.nodes.push(empty);
        self.nodes.push(empty);
        self.nodes[index] = Node {
            min: lo,
            first: first as u32,
            max: hi,
            kind: INNER + axis as u32,
        };
        self.build(first, start, mid, depth + 1);
        self.build(first + 1, mid, end, depth + 1);
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::brute_force::brute_force_closest_hit;
    use rand::{Rng, SeedableRng, rngs::StdRng};
    use shlight_mesh::generate;

    /// A random unit vector, uniform over the sphere.
    pub(crate) fn random_unit(rng: &mut StdRng) -> Vec3 {
        loop {
            let v = Vec3::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
            );
            if v.length_squared() > 0.01 && v.length_squared() <= 1.0 {
                return v.normalize();
            }
        }
    }

    /// A random point in and around the box of
    /// `generate::plane_under_sphere(1.0, 24, 12, 4.0, 6)`.
    pub(crate) fn random_origin(rng: &mut StdRng) -> Vec3 {
        Vec3::new(
            rng.random_range(-2.5..2.5),
            rng.random_range(-0.5..2.5),
            rng.random_range(-2.5..2.5),
        )
    }

    #[test]
    fn closest_hits_and_occlusion_match_a_brute_force_reference() {
        let mesh = generate::plane_under_sphere(1.0, 24, 12, 4.0, 6);
        let bvh = Bvh::new(&mesh.positions, &mesh.triangles);
        let mut rng = StdRng::seed_from_u64(5);
        let (mut hits, mut mismatched) = (0, 0);
        for _ in 0..4000 {
            let o = random_origin(&mut rng);
            let d = random_unit(&mut rng);
            let ray = Ray::new(o, d, f32::INFINITY);
            let got = bvh.closest_hit(&ray);
            let want = brute_force_closest_hit(&mesh, o.as_dvec3(), d.as_dvec3(), 0.0)
                .map(|(t, k, ..)| (t, k as u32));
            assert_eq!(bvh.occluded(&ray), got.is_some());
            match (got, want) {
                (Some(g), Some((t, k))) => {
                    hits += 1;
                    assert!(
                        (f64::from(g.t) - t).abs() < 1e-4 * t.max(1.0),
                        "t {} vs {t}",
                        g.t
                    );
                    // A ray through a shared edge may report either triangle.
                    if g.triangle != k {
                        mismatched += 1;
                    }
                    let tri =
                        mesh.triangles[g.triangle as usize].map(|i| mesh.positions[i as usize]);
                    let w = g.barycentrics;
                    assert!(
                        (w.iter().sum::<f32>() - 1.0).abs() < 1e-5 && w.iter().all(|&x| x >= 0.0)
                    );
                    let p = tri[0] * w[0] + tri[1] * w[1] + tri[2] * w[2];
                    assert!(p.distance(o + d * g.t) < 1e-4, "{p} vs {}", o + d * g.t);
                }
                (None, None) => {}
                // Only a ray grazing an edge may disagree, within rounding.
                _ => mismatched += 1,
            }
        }
        assert!(hits > 1000, "{hits}");
        assert!(mismatched <= 2, "{mismatched} disagreements");
        // t_max limits the search.
        let ray = Ray::new(Vec3::new(0.0, 3.0, 0.0), Vec3::NEG_Y, 0.5);
        assert!(!bvh.occluded(&ray) && bvh.closest_hit(&ray).is_none());
    }

    #[test]
    fn rays_through_shared_edges_and_vertices_never_slip_through() {
        // From inside a closed sphere every ray must hit, including those
        // aimed exactly at vertices and edge midpoints, where a test that is
        // not watertight lets some rays pass between the triangles.
        let mesh = generate::uv_sphere(1.0, 37, 23);
        let bvh = Bvh::new(&mesh.positions, &mesh.triangles);
        let origins = [
            Vec3::ZERO,
            Vec3::new(0.1, -0.2, 0.3),
            Vec3::new(-0.31, 0.17, 0.05),
        ];
        let mut targets: Vec<Vec3> = mesh.positions.clone();
        for t in &mesh.triangles {
            let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
            targets.extend([(a + b) * 0.5, (b + c) * 0.5, (c + a) * 0.5]);
        }
        let mut misses = 0;
        for o in origins {
            for &p in &targets {
                if !bvh.occluded(&Ray::new(o, p - o, f32::INFINITY)) {
                    misses += 1;
                }
            }
        }
        assert_eq!(misses, 0, "of {} rays", 3 * targets.len());
        // A binary tree with at least one triangle per leaf.
        assert!(bvh.node_count() < 2 * mesh.triangle_count());
    }
}
