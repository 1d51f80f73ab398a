//! A bounding-volume hierarchy over a mesh's triangles, for the visibility
//! and bounce rays of PRT baking.
//!
//! - **Hierarchy**: the `obvhs` crate's compressed wide BVH (CWBVH, eight
//!   children per node, 80-byte nodes; Ylitie et al. 2017), built by PLOC
//!   with its "medium" parameters, traversed with its SIMD node test.
//!   Chosen over a binned-SAH binary BVH written for shlight by
//!   `benches/rays.rs` (which keeps that candidate): with their own triangle
//!   tests obvhs cast 1.3x to 1.5x more PRT rays per second on the bundled
//!   bunny and a 70k-triangle torus; with shlight's watertight test in both,
//!   1.1x to 1.2x more on the torus and about the same on the bunny
//!   (README, "PRT", measured on a busy 2-core machine).
//! - **Triangles**: shlight's own watertight test (Woop, Benthin and Wald,
//!   JCGT 2013): the ray is sheared to +z, edge functions are evaluated in
//!   the sheared plane and redone in `f64` when one is exactly zero, so a ray
//!   through an edge or a vertex shared by triangles hits at least one of
//!   them, never slipping between. Both sides of a triangle are hit.
//!   Triangles are copied into the hierarchy's leaf order.

use glam::Vec3;
use glam_obvhs::{UVec2, Vec3A};
use obvhs::aabb::Aabb;
use obvhs::cwbvh::CwBvh;
use obvhs::cwbvh::builder::build_cwbvh;
use obvhs::ray::Ray as TraversalRay;
use obvhs::{Boundable, BvhBuildParams};

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
/// +z. Shared by [`Ray`] and the hand-written BVH of the ray benchmark.
#[derive(Clone, Copy, Debug)]
pub struct WatertightRay {
    origin: Vec3,
    k: [usize; 3],
    shear: Vec3,
}

/// A ray with what every test against it needs, computed once.
#[derive(Clone, Copy, Debug)]
pub struct Ray {
    /// The same ray for the hierarchy's node tests.
    traversal: TraversalRay,
    /// The same ray for the triangle tests.
    triangle: WatertightRay,
}

impl Ray {
    /// The ray `origin + t dir`, `0 < t < t_max`. `dir` need not be unit.
    #[must_use]
    pub fn new(origin: Vec3, dir: Vec3, t_max: f32) -> Self {
        let a3 = |v: Vec3| Vec3A::new(v.x, v.y, v.z);
        // The node test takes the sign of a direction component from
        // `d < 0` but inverts it as `signum(d) / EPSILON` when |d| <= EPSILON:
        // -0.0 (and tiny components) would be inverted with the wrong sign
        // or scale. Such components become +0.0 for the node tests only
        // (triangle boxes are padded to cover the difference).
        let snapped = Vec3::select(dir.abs().cmple(Vec3::splat(f32::EPSILON)), Vec3::ZERO, dir);
        Self {
            traversal: TraversalRay::new(a3(origin), a3(snapped), 0.0, t_max),
            triangle: WatertightRay::new(origin, dir),
        }
    }
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
        let mut u = cx * by - cy * bx;
        let mut v = ax * cy - ay * cx;
        let mut w = bx * ay - by * ax;
        if u == 0.0 || v == 0.0 || w == 0.0 {
            let f = |a: f32, b: f32, c: f32, d: f32| {
                (f64::from(a) * f64::from(b) - f64::from(c) * f64::from(d)) as f32
            };
            u = f(cx, by, cy, bx);
            v = f(ax, cy, ay, cx);
            w = f(bx, ay, by, ax);
        }
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

/// A triangle's bounding box grown by [`BOX_PADDING`] of its largest
/// coordinate, so that the hierarchy's node test, which does not round
/// outwards, still reaches every box the exact ray touches: at a face, and
/// with direction components below `f32::EPSILON` snapped to zero for the
/// node tests ([`Ray::new`]; a `-0.0` component made rays through the seam
/// of a sphere miss whole nodes before that).
struct PaddedBox(Aabb);

/// Relative growth of triangle boxes, about 16 units in the last place.
pub const BOX_PADDING: f32 = 16.0 * f32::EPSILON;

impl PaddedBox {
    fn around([a, b, c]: &[Vec3; 3]) -> Self {
        let (lo, hi) = (a.min(*b).min(*c), a.max(*b).max(*c));
        let pad =
            Vec3::splat(lo.abs().max(hi.abs()).max_element() * BOX_PADDING + f32::MIN_POSITIVE);
        let a3 = |v: Vec3| Vec3A::new(v.x, v.y, v.z);
        Self(Aabb::new(a3(lo - pad), a3(hi + pad)))
    }
}

impl Boundable for PaddedBox {
    fn aabb(&self) -> Aabb {
        self.0
    }
}

/// The hierarchy, the triangles in its leaf order, and each one's index in
/// the mesh.
#[derive(Clone)]
pub struct Bvh {
    bvh: CwBvh,
    triangles: Vec<[Vec3; 3]>,
    ids: Vec<u32>,
}

impl std::fmt::Debug for Bvh {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Bvh")
            .field("nodes", &self.bvh.nodes.len())
            .field("triangles", &self.triangles.len())
            .finish()
    }
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
        let boxes: Vec<PaddedBox> = corners.iter().map(PaddedBox::around).collect();
        let bvh = build_cwbvh(
            &boxes,
            BvhBuildParams::medium_build(),
            &mut std::time::Duration::default(),
        );
        // Leaf order.
        let ids = bvh.primitive_indices.clone();
        Self {
            triangles: ids.iter().map(|&i| corners[i as usize]).collect(),
            ids,
            bvh,
        }
    }

    /// Number of nodes (each with up to eight children).
    #[must_use]
    pub fn node_count(&self) -> usize {
        self.bvh.nodes.len()
    }

    /// The nearest hit of `ray`, if any.
    #[must_use]
    pub fn closest_hit(&self, ray: &Ray) -> Option<Hit> {
        let mut traversal = ray.traversal;
        let mut state = self.bvh.new_traversal(traversal.direction);
        let mut node;
        let mut best: Option<(f32, usize, [f32; 3])> = None;
        obvhs::traverse!(
            self.bvh,
            node,
            state,
            node.intersect_ray(&traversal, state.oct_inv4),
            {
                let k = state.primitive_id as usize;
                if let Some((t, w)) = ray
                    .triangle
                    .hits_triangle(&self.triangles[k], traversal.tmax)
                {
                    traversal.tmax = t;
                    best = Some((t, k, w));
                }
            }
        );
        best.map(|(t, k, w)| Hit {
            t,
            triangle: self.ids[k],
            barycentrics: w,
        })
    }

    /// Whether anything blocks `ray` (the first hit found ends the search).
    #[must_use]
    pub fn occluded(&self, ray: &Ray) -> bool {
        let traversal = ray.traversal;
        let mut state = self.bvh.new_traversal(traversal.direction);
        let mut node;
        let mut hit = false;
        obvhs::traverse!(
            self.bvh,
            node,
            state,
            node.intersect_ray(&traversal, state.oct_inv4),
            {
                let k = state.primitive_id as usize;
                if ray
                    .triangle
                    .hits_triangle(&self.triangles[k], traversal.tmax)
                    .is_some()
                {
                    // Empty the traversal state: the macro's loop then ends.
                    hit = true;
                    state.stack.clear();
                    state.current_group = UVec2::ZERO;
                    state.primitive_group = UVec2::ZERO;
                    break;
                }
            }
        );
        hit
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng, rngs::StdRng};
    use shlight_mesh::{Mesh, generate};

    /// Möller-Trumbore in f64 against every triangle: an independent
    /// reference for the hierarchy and the watertight test.
    fn reference_closest(mesh: &Mesh, o: Vec3, d: Vec3) -> Option<(f64, u32)> {
        let (o, d) = (o.as_dvec3(), d.as_dvec3());
        let mut best: Option<(f64, u32)> = None;
        for (k, t) in mesh.triangles.iter().enumerate() {
            let [a, b, c] = t.map(|i| mesh.positions[i as usize].as_dvec3());
            let (e1, e2) = (b - a, c - a);
            let p = d.cross(e2);
            let det = e1.dot(p);
            if det.abs() < 1e-300 {
                continue;
            }
            let s = o - a;
            let u = s.dot(p) / det;
            let q = s.cross(e1);
            let v = d.dot(q) / det;
            let t = e2.dot(q) / det;
            if u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t > 0.0 && best.is_none_or(|(bt, _)| t < bt)
            {
                best = Some((t, k as u32));
            }
        }
        best
    }

    fn random_unit(rng: &mut StdRng) -> Vec3 {
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

    #[test]
    fn closest_hits_and_occlusion_match_a_brute_force_reference() {
        let mesh = generate::plane_under_sphere(1.0, 24, 12, 4.0, 6);
        let bvh = Bvh::new(&mesh.positions, &mesh.triangles);
        let mut rng = StdRng::seed_from_u64(5);
        let (mut hits, mut mismatched) = (0, 0);
        for _ in 0..4000 {
            let o = Vec3::new(
                rng.random_range(-2.5..2.5),
                rng.random_range(-0.5..2.5),
                rng.random_range(-2.5..2.5),
            );
            let d = random_unit(&mut rng);
            let ray = Ray::new(o, d, f32::INFINITY);
            let got = bvh.closest_hit(&ray);
            let want = reference_closest(&mesh, o, d);
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
        assert!(bvh.node_count() < mesh.triangle_count());
    }
}
