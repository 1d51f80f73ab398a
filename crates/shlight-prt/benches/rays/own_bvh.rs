#![allow(dead_code)]
//! A binary BVH written for shlight: the benchmark's second candidate.
//!
//! - **Build**: binary, top-down, binned surface-area heuristic (16 bins on
//!   the centroid bounds of the longest axis; cost 1 per node visit, 1 per
//!   triangle test), leaves of at most [`MAX_LEAF`] triangles, nodes in
//!   depth-first order with the two children next to each other. Triangles
//!   are copied into leaf order, so a leaf reads contiguous memory.
//! - **Traversal**: a fixed stack, the nearer child first (by the ray's
//!   direction sign on the split axis); box tests by slabs, with the far
//!   distance widened by `1 + 2 gamma(3)` so rounding never loses a box that
//!   the ray touches (Ize 2013).
//! - **Triangles**: the watertight test of Woop, Benthin and Wald (JCGT
//!   2013): the ray is sheared to +z, edge functions are evaluated in the
//!   sheared plane and redone in `f64` when one is exactly zero, so a ray
//!   through an edge or a vertex shared by triangles hits at least one of
//!   them, never slipping between. Both sides of a triangle are hit.
//!
//! The candidate that lost to `obvhs` in `benches/rays.rs` (shlight-prt's
//! `bvh.rs` uses obvhs's CWBVH with this file's watertight triangle test),
//! kept here so the comparison can be repeated.

use glam::Vec3;
use shlight_prt::bvh::{Hit, WatertightRay};

/// The most triangles in one leaf.
pub const MAX_LEAF: usize = 4;
const BINS: usize = 16;
const STACK: usize = 64;
/// `1 + 2 gamma(3)`, `gamma(n) = n u / (1 - n u)`, `u = 2^-24`.
const FAR_SCALE: f32 = 1.0 + 2.0 * (3.0 * f32::EPSILON * 0.5) / (1.0 - 3.0 * f32::EPSILON * 0.5);

/// One node: a box and either two children (`count == 0`, the left child at
/// `first`, the right at `first + 1`) or `count` triangles from `first`.
#[derive(Clone, Copy, Debug)]
#[repr(C)]
struct Node {
    min: Vec3,
    first: u32,
    max: Vec3,
    count: u32,
}

/// A ray with what every test against it needs, computed once.
#[derive(Clone, Copy, Debug)]
pub struct Ray {
    origin: Vec3,
    inv_dir: Vec3,
    /// The same ray for the (shared) watertight triangle test.
    triangle: WatertightRay,
    /// Largest `t` of interest.
    t_max: f32,
}

impl Ray {
    /// The ray `origin + t dir`, `0 < t < t_max`. `dir` need not be unit.
    #[must_use]
    pub fn new(origin: Vec3, dir: Vec3, t_max: f32) -> Self {
        Self {
            origin,
            inv_dir: dir.recip(),
            triangle: WatertightRay::new(origin, dir),
            t_max,
        }
    }

    /// Entry distance into the box, or `None` when missed within `(0, t_max)`.
    #[inline(always)]
    fn hits_box(&self, min: Vec3, max: Vec3, t_max: f32) -> Option<f32> {
        let t1 = (min - self.origin) * self.inv_dir;
        let t2 = (max - self.origin) * self.inv_dir;
        let near = t1.min(t2).max_element().max(0.0);
        let far = t1.max(t2).min_element().min(t_max) * FAR_SCALE;
        (near <= far).then_some(near)
    }
}

/// The hierarchy: nodes, triangles in leaf order, and each one's index in
/// the mesh.
#[derive(Clone, Debug)]
pub struct Bvh {
    nodes: Vec<Node>,
    triangles: Vec<[Vec3; 3]>,
    ids: Vec<u32>,
}

struct Builder<'a> {
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
        let bounds: Vec<(Vec3, Vec3)> = corners
            .iter()
            .map(|[a, b, c]| (a.min(*b).min(*c), a.max(*b).max(*c)))
            .collect();
        let centroids = bounds.iter().map(|(lo, hi)| (*lo + *hi) * 0.5).collect();
        let mut order: Vec<u32> = (0..triangles.len() as u32).collect();
        let mut builder = Builder {
            bounds,
            centroids,
            order: &mut order,
            nodes: Vec::with_capacity(2 * triangles.len().div_ceil(MAX_LEAF).max(1)),
        };
        builder.nodes.push(Node {
            min: Vec3::ZERO,
            first: 0,
            max: Vec3::ZERO,
            count: 0,
        });
        builder.build(0, 0, triangles.len());
        let nodes = builder.nodes;
        Self {
            nodes,
            triangles: order.iter().map(|&i| corners[i as usize]).collect(),
            ids: order,
        }
    }

    /// Number of nodes (inner and leaves).
    #[must_use]
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// The nearest hit of `ray`, if any.
    #[must_use]
    pub fn closest_hit(&self, ray: &Ray) -> Option<Hit> {
        let mut best: Option<(f32, u32, [f32; 3])> = None;
        let mut t_max = ray.t_max;
        self.traverse(
            ray,
            |t_max_now, first, count| {
                for k in first..first + count {
                    if let Some((t, w)) = ray.triangle.hits_triangle(&self.triangles[k], *t_max_now)
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

    /// Whether anything blocks `ray` (the first hit found ends the search).
    #[must_use]
    pub fn occluded(&self, ray: &Ray) -> bool {
        let mut t_max = ray.t_max;
        let mut hit = false;
        self.traverse(
            ray,
            |t_max_now, first, count| {
                hit = (first..first + count).any(|k| {
                    ray.triangle
                        .hits_triangle(&self.triangles[k], *t_max_now)
                        .is_some()
                });
                hit
            },
            &mut t_max,
        );
        hit
    }

    /// Visits the leaves `ray` may reach, nearer child first; `leaf` gets the
    /// current far limit (which it may shrink), the first triangle and the
    /// count, and returns `true` to stop.
    #[inline(always)]
    fn traverse(
        &self,
        ray: &Ray,
        mut leaf: impl FnMut(&mut f32, usize, usize) -> bool,
        t_max: &mut f32,
    ) {
        let root = &self.nodes[0];
        if ray.hits_box(root.min, root.max, *t_max).is_none() {
            return;
        }
        let mut stack = [0u32; STACK];
        let mut top = 0;
        let mut node = root;
        loop {
            if node.count > 0 {
                if leaf(t_max, node.first as usize, node.count as usize) {
                    return;
                }
            } else {
                let (l, r) = (
                    &self.nodes[node.first as usize],
                    &self.nodes[node.first as usize + 1],
                );
                let (hl, hr) = (
                    ray.hits_box(l.min, l.max, *t_max),
                    ray.hits_box(r.min, r.max, *t_max),
                );
                match (hl, hr) {
                    (Some(a), Some(b)) => {
                        let (near, far) = if a <= b {
                            (node.first, node.first + 1)
                        } else {
                            (node.first + 1, node.first)
                        };
                        stack[top] = far;
                        top += 1;
                        node = &self.nodes[near as usize];
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
            node = &self.nodes[stack[top] as usize];
        }
    }
}

impl Builder<'_> {
    /// Fills node `index` with triangles `order[start..end]`, splitting it
    /// when the surface-area heuristic says so.
    fn build(&mut self, index: usize, start: usize, end: usize) {
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
            count: n as u32,
        };
        let extent = chi - clo;
        let axis = extent.max_position();
        if n <= 1 || extent[axis] <= 0.0 {
            // Every centroid in one point: no split can separate them.
            self.nodes[index] = leaf;
            if n > MAX_LEAF {
                self.split_at(index, start, end, start + n / 2, lo, hi);
            }
            return;
        }
        // Binned SAH on the longest centroid axis.
        let scale = BINS as f32 / extent[axis];
        let bin_of = |c: Vec3| (((c[axis] - clo[axis]) * scale) as usize).min(BINS - 1);
        let mut counts = [0usize; BINS];
        let mut boxes = [(Vec3::INFINITY, Vec3::NEG_INFINITY); BINS];
        for &i in &self.order[start..end] {
            let b = bin_of(self.centroids[i as usize]);
            counts[b] += 1;
            let (a, c) = self.bounds[i as usize];
            boxes[b] = (boxes[b].0.min(a), boxes[b].1.max(c));
        }
        let area = |(a, b): (Vec3, Vec3)| {
            let d = (b - a).max(Vec3::ZERO);
            d.x * d.y + d.y * d.z + d.z * d.x
        };
        let mut right_cost = [0.0f32; BINS];
        let (mut acc, mut cnt) = ((Vec3::INFINITY, Vec3::NEG_INFINITY), 0);
        for b in (1..BINS).rev() {
            acc = (acc.0.min(boxes[b].0), acc.1.max(boxes[b].1));
            cnt += counts[b];
            right_cost[b] = area(acc) * cnt as f32;
        }
        let (mut best, mut best_cost) = (0, f32::INFINITY);
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
            }
        }
        let parent_area = area((lo, hi));
        let split_cost = 1.0 + best_cost / parent_area.max(f32::MIN_POSITIVE);
        if n <= MAX_LEAF && split_cost >= n as f32 || best_cost == f32::INFINITY {
            self.nodes[index] = leaf;
            if n > MAX_LEAF {
                self.split_at(index, start, end, start + n / 2, lo, hi);
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
        self.split_at(index, start, end, mid, lo, hi);
    }

    /// Makes node `index` an inner node over `start..mid` and `mid..end`.
    fn split_at(&mut self, index: usize, start: usize, end: usize, mid: usize, lo: Vec3, hi: Vec3) {
        let first = self.nodes.len();
        let empty = Node {
            min: Vec3::ZERO,
            first: 0,
            max: Vec3::ZERO,
            count: 0,
        };
        self.nodes.push(empty);
        self.nodes.push(empty);
        self.nodes[index] = Node {
            min: lo,
            first: first as u32,
            max: hi,
            count: 0,
        };
        self.build(first, start, mid);
        self.build(first + 1, mid, end);
    }
}
