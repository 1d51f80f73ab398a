//! [`Occluder`]: a mesh made ready to cast rays against, and every query
//! on it.

use std::sync::Arc;

use glam::Vec3;
use shlight_mesh::{Mesh, Surfaces};

use crate::bvh::{Bvh, Hit, Ray};
use crate::cut_outs::{CutOutTable, CutOuts};
use crate::instanced::InstancedOccluder;
use crate::origins;
use crate::packet::{Direction, Packet, PacketBvh, PacketHits};
use crate::vertex_order::{ranked_triangles, vertex_order};

/// A mesh made ready to cast rays against: its triangles in a binned-SAH
/// hierarchy with the watertight triangle test (Woop, Benthin & Wald 2013),
/// laid out for single rays and for packets of eight parallel rays; its
/// vertices in Morton order ([`vertex_order`]: a direction's ray-space
/// copies of them are then read near one another); and its triangles' face
/// normals, `(b - a) x (c - a)`, for which side a ray meets.
///
/// Every query hits both sides of a triangle and names it by its index in
/// the mesh's triangle list, with the barycentric weights of its three
/// corners in the order of its indices. A ray through an edge or a vertex
/// shared by triangles hits at least one of them, never slipping between.
///
/// Single rays: [`occluded`](Self::occluded) and
/// [`closest_hit`](Self::closest_hit). Packets, the fast path for many
/// parallel rays: [`packet_occluded`](Self::packet_occluded),
/// [`packet_closest`](Self::packet_closest) and
/// [`packet_closest_direct`](Self::packet_closest_direct), traced with AVX2
/// where the processor has it and FMA ([`packets_enabled`]), each ray
/// alone otherwise (the answers agree but for rays grazing an edge, where
/// rounding differs).
///
/// Built [`with_cut_outs`](Self::with_cut_outs), every query lets rays
/// through the surfaces that cut out where their opacity says so
/// ([`CutOuts`]: a cut-out texel passes every ray, partial coverage a
/// deterministic fraction of them, and the ray goes on to what lies
/// behind); built with [`new`](Self::new), or when no triangle cuts out,
/// every triangle stops every ray and the queries cost what they did.
///
/// Built [`for_surfaces`](Self::for_surfaces) from a glTF scene whose
/// instances repeat its primitives ([`TWO_LEVEL_REPEATS`]), it casts
/// through the scene's [`InstancedOccluder`] instead: one hierarchy per
/// unique primitive and one over the instances, answering the same
/// queries with the same triangle indices (the flattened scene's), so
/// that its memory grows with the unique triangles, not the copies. Its
/// packets are then traced ray by ray and it has no ray-space copy of the
/// vertices ([`vertex_count`](Self::vertex_count) is 0).
///
/// [`packets_enabled`]: crate::packets_enabled
#[derive(Clone, Debug)]
pub struct Occluder {
    kind: Kind,
}

/// How an [`Occluder`] holds its triangles.
#[derive(Clone, Debug)]
enum Kind {
    /// Every triangle in one hierarchy.
    Flat(Flat),
    /// A glTF scene's unique primitives and their instances.
    Instanced(InstancedOccluder),
}

/// One hierarchy over every triangle.
#[derive(Clone, Debug)]
struct Flat {
    positions: Vec<Vec3>,
    bvh: PacketBvh,
    faces: Vec<Vec3>,
    cut: Option<CutOutTable>,
}

/// [`Occluder::for_surfaces`] casts through the two-level hierarchy when
/// the flattened scene has at least this many times the triangles of its
/// unique primitives (below it, one hierarchy over every triangle costs
/// little more memory and its packets are traced together).
pub const TWO_LEVEL_REPEATS: usize = 2;

impl Occluder {
    /// `mesh` made ready; every triangle stops every ray.
    #[must_use]
    pub fn new(mesh: &Mesh) -> Self {
        Self {
            kind: Kind::Flat(Flat::new(mesh)),
        }
    }

    /// `mesh` made ready, its triangles letting rays through as
    /// `cut_outs` says (triangle indices are `mesh`'s): for a flattened
    /// glTF scene, its [`shlight_mesh::Surfaces`] (whose `mesh` this is).
    /// The crate documentation states how a ray is decided.
    #[must_use]
    pub fn with_cut_outs(mesh: &Mesh, cut_outs: Arc<dyn CutOuts>) -> Self {
        let mut flat = Flat::new(mesh);
        flat.cut = CutOutTable::new(cut_outs, &flat.bvh.bvh().ids);
        Self {
            kind: Kind::Flat(flat),
        }
    }

    /// A flattened glTF scene made ready, through its cut-outs, its
    /// triangles named as `surfaces.mesh` names them: through the scene's
    /// unique primitives and their instances ([`InstancedOccluder`]) when
    /// the flattened scene has at least [`TWO_LEVEL_REPEATS`] times their
    /// triangles ([`Surfaces::placement`]), else
    /// [`with_cut_outs`](Self::with_cut_outs) of `surfaces.mesh`.
    #[must_use]
    pub fn for_surfaces(surfaces: &Arc<Surfaces>) -> Self {
        let cut_outs = || -> Arc<dyn CutOuts> { surfaces.clone() };
        if let Some(scene) = surfaces
            .placement
            .as_ref()
            .filter(|_| Self::casts_two_level(surfaces))
        {
            // The flattening that made `surfaces` accepted the scene, so
            // the two-level build does too.
            if let Ok(two) = InstancedOccluder::with_cut_outs(scene, cut_outs()) {
                return Self {
                    kind: Kind::Instanced(two),
                };
            }
        }
        Self::with_cut_outs(&surfaces.mesh, cut_outs())
    }

    /// Whether [`for_surfaces`](Self::for_surfaces) casts `surfaces`
    /// through two levels: it has a placement, and at least
    /// [`TWO_LEVEL_REPEATS`] times the triangles of the unique primitives
    /// its instances use.
    #[must_use]
    pub fn casts_two_level(surfaces: &Surfaces) -> bool {
        let Some(scene) = &surfaces.placement else {
            return false;
        };
        let (_, unique) = scene.unique_geometry();
        surfaces.mesh.triangle_count() >= TWO_LEVEL_REPEATS * unique
    }

    /// Whether rays are cast through a scene's unique primitives and their
    /// instances (built [`for_surfaces`](Self::for_surfaces) from a scene
    /// that repeats them), rather than one hierarchy of every triangle.
    #[must_use]
    pub fn is_two_level(&self) -> bool {
        matches!(self.kind, Kind::Instanced(_))
    }

    /// Whether some triangle may let rays through (built
    /// [`with_cut_outs`](Self::with_cut_outs) and one cuts out).
    #[must_use]
    pub fn has_cut_outs(&self) -> bool {
        match &self.kind {
            Kind::Flat(f) => f.cut.is_some(),
            Kind::Instanced(i) => i.has_cut_outs(),
        }
    }

    /// Bytes the occluder holds on the heap: the hierarchy (its nodes,
    /// its triangles' corners and indices, the packet layouts), the
    /// vertices, the face normals and the cut-out flags. The acceleration
    /// structure's memory, as docs/benchmarks.md compares it with an
    /// [`InstancedOccluder`]'s (a two-level occluder's is that).
    #[must_use]
    pub fn heap_bytes(&self) -> usize {
        match &self.kind {
            Kind::Flat(f) => {
                f.bvh.heap_bytes()
                    + f.positions.capacity() * size_of::<Vec3>()
                    + f.faces.capacity() * size_of::<Vec3>()
                    + f.cut.as_ref().map_or(0, CutOutTable::heap_bytes)
            }
            Kind::Instanced(i) => i.heap_bytes(),
        }
    }

    /// Whether anything blocks `ray` (the first hit found ends the search).
    #[must_use]
    pub fn occluded(&self, ray: &Ray) -> bool {
        match &self.kind {
            Kind::Flat(f) => f.bvh.bvh().occluded_through(ray, f.cut.as_ref()),
            Kind::Instanced(i) => i.occluded(ray),
        }
    }

    /// The nearest hit of `ray`, if any.
    #[must_use]
    pub fn closest_hit(&self, ray: &Ray) -> Option<Hit> {
        match &self.kind {
            Kind::Flat(f) => f.bvh.bvh().closest_hit_through(ray, f.cut.as_ref()),
            Kind::Instanced(i) => i.closest_hit(ray),
        }
    }

    /// Whether a ray along `dir` meets triangle `triangle` (the mesh's
    /// index) on its front.
    #[inline]
    #[must_use]
    pub fn is_front(&self, triangle: u32, dir: Vec3) -> bool {
        match &self.kind {
            Kind::Flat(f) => f.faces[triangle as usize].dot(dir) < 0.0,
            Kind::Instanced(i) => i.is_front(triangle, dir),
        }
    }

    /// The vertices the packet queries read in ray space: the length of
    /// [`ray_space`](Self::ray_space) (0 for a two-level occluder, whose
    /// packets are traced ray by ray and read none).
    #[must_use]
    pub fn vertex_count(&self) -> usize {
        self.positions().len()
    }

    /// The occluder's own copy of the vertices (none when two-level).
    fn positions(&self) -> &[Vec3] {
        match &self.kind {
            Kind::Flat(f) => &f.positions,
            Kind::Instanced(_) => &[],
        }
    }

    /// The vertices in `dir`'s ray space ([`Direction::to_ray_space`]), in
    /// the order the packet queries read them: the `local` of
    /// [`packet_occluded`](Self::packet_occluded) and
    /// [`packet_closest`](Self::packet_closest), computed once per
    /// direction for all the packets along it.
    pub fn ray_space<'a>(
        &'a self,
        dir: &'a Direction,
    ) -> impl ExactSizeIterator<Item = [f32; 4]> + 'a {
        self.positions().iter().map(|p| dir.to_ray_space(*p))
    }

    /// Which rays of `packet` (along `dir`, from `0 < t`) are blocked: bit
    /// `k` set for lane `k`. `local` holds this occluder's vertices in
    /// `dir`'s ray space ([`ray_space`](Self::ray_space)).
    ///
    /// # Panics
    /// If `local` holds fewer vertices than the occluder.
    #[must_use]
    pub fn packet_occluded(&self, dir: &Direction, local: &[[f32; 4]], packet: &Packet) -> u32 {
        match &self.kind {
            Kind::Flat(f) => f.bvh.occluded(dir, local, packet, f.cut.as_ref()),
            Kind::Instanced(i) => i.packet_occluded(dir, packet),
        }
    }

    /// The nearest hit of each ray of `packet` (`local` as in
    /// [`packet_occluded`](Self::packet_occluded)).
    ///
    /// # Panics
    /// If `local` holds fewer vertices than the occluder.
    #[must_use]
    pub fn packet_closest(
        &self,
        dir: &Direction,
        local: &[[f32; 4]],
        packet: &Packet,
    ) -> PacketHits {
        match &self.kind {
            Kind::Flat(f) => f.bvh.closest(dir, local, packet, f.cut.as_ref()),
            Kind::Instanced(i) => i.packet_closest(dir, packet),
        }
    }

    /// [`packet_closest`](Self::packet_closest) without the ray-space copy
    /// of the vertices: each triangle's corners are put in ray space as it
    /// is tested, so the hits are the same. For callers that take the
    /// directions in an order of their own, or whose mesh is too large to
    /// copy for every direction.
    #[must_use]
    pub fn packet_closest_direct(&self, dir: &Direction, packet: &Packet) -> PacketHits {
        match &self.kind {
            Kind::Flat(f) => f.bvh.closest_direct(dir, packet, f.cut.as_ref()),
            Kind::Instanced(i) => i.packet_closest(dir, packet),
        }
    }

    /// Where the rays of each vertex of `mesh` start, off its surface and
    /// never across this occluder's triangles, cut out or not (`mesh` is the occluder's own mesh, or
    /// one subdivided from it): `p + eps (n + c)`, `eps` = [`OFFSET`]
    /// times the bounding-box diagonal, `c` the unit vector in the tangent
    /// plane from `p` towards the mean centroid of the triangles that use
    /// it (zero for a vertex no triangle uses, or one whose mean lies along
    /// its normal, like a sphere's pole), so that a vertex on a concave
    /// edge starts off the other surface's plane — unless the segment from
    /// `p` to that point crosses the occluder, which an origin must never
    /// do (a vertex just inside another part of a self-intersecting mesh
    /// would have its rays start on the far side of the surface it is
    /// inside). Then the first of `p + eps n`, `p + eps n / 4`, ...
    /// ([`SHORTER_OFFSETS`] of them) whose segment crosses nothing is
    /// taken, and the shortest when every one crosses.
    ///
    /// [`OFFSET`]: crate::OFFSET
    /// [`SHORTER_OFFSETS`]: crate::SHORTER_OFFSETS
    #[must_use]
    pub fn ray_origins(&self, mesh: &Mesh) -> Vec<Vec3> {
        match &self.kind {
            Kind::Flat(f) => origins::ray_origins(mesh, |ray| f.bvh.bvh().occluded(ray)),
            Kind::Instanced(i) => origins::ray_origins(mesh, |ray| i.occluded_opaque(ray)),
        }
    }
}

impl Flat {
    /// `mesh` in one hierarchy, its vertices in Morton order; no cut-outs.
    fn new(mesh: &Mesh) -> Self {
        let order = vertex_order(&mesh.positions, mesh.bounds());
        let triangles = ranked_triangles(&mesh.triangles, &order);
        let positions: Vec<Vec3> = order.iter().map(|&v| mesh.positions[v as usize]).collect();
        Self {
            bvh: PacketBvh::new(Bvh::new(&positions, &triangles)),
            positions,
            faces: face_normals(mesh),
            cut: None,
        }
    }
}

/// `(b - a) x (c - a)` of each triangle `(a, b, c)`: its front side.
fn face_normals(mesh: &Mesh) -> Vec<Vec3> {
    mesh.triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
            (b - a).cross(c - a)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::brute_force::brute_force_closest_hit;
    use crate::bvh::tests::{random_origin, random_unit};
    use crate::packet::LANES;
    use rand::{SeedableRng, rngs::StdRng};
    use shlight_mesh::generate;

    #[test]
    fn hits_name_the_mesh_triangles_and_their_sides() {
        // The occluder holds its vertices in Morton order; its hits must
        // still name the mesh's triangles, with the weights of their
        // corners in the mesh's order, and which side was met.
        let mesh = generate::plane_under_sphere(1.0, 24, 12, 4.0, 6);
        let occluder = Occluder::new(&mesh);
        let mut rng = StdRng::seed_from_u64(17);
        let (mut hits, mut fronts, mut mismatched) = (0, 0, 0);
        for _ in 0..2000 {
            let o = random_origin(&mut rng);
            let d = random_unit(&mut rng);
            let ray = Ray::new(o, d, f32::INFINITY);
            let got = occluder.closest_hit(&ray);
            assert_eq!(occluder.occluded(&ray), got.is_some());
            let want = brute_force_closest_hit(&mesh, o.as_dvec3(), d.as_dvec3(), 0.0);
            let (Some(g), Some((t, k, ..))) = (got, want) else {
                // Only a ray grazing an edge may disagree.
                mismatched += usize::from(got.is_some() != want.is_some());
                continue;
            };
            hits += 1;
            assert!((f64::from(g.t) - t).abs() < 1e-4 * t.max(1.0));
            mismatched += usize::from(g.triangle as usize != k);
            let [a, b, c] = mesh.triangles[g.triangle as usize].map(|i| mesh.positions[i as usize]);
            let w = g.barycentrics;
            assert!((a * w[0] + b * w[1] + c * w[2]).distance(o + d * g.t) < 1e-4);
            let front = (b - a).cross(c - a).dot(d) < 0.0;
            assert_eq!(occluder.is_front(g.triangle, d), front);
            fronts += usize::from(front);
        }
        assert!(
            hits > 500 && fronts > 100 && hits - fronts > 100,
            "{hits} {fronts}"
        );
        assert!(mismatched <= 2, "{mismatched} disagreements");
    }

    #[test]
    fn packets_of_origins_off_the_surface_agree_with_single_rays() {
        // Each vertex's rays start off the surface, a little: the rays down
        // from the sphere's underside meet the plane under it (its front),
        // as single rays and as packets alike.
        let mesh = generate::plane_under_sphere(1.0, 24, 12, 4.0, 6);
        let occluder = Occluder::new(&mesh);
        let origins = occluder.ray_origins(&mesh);
        let (lo, hi) = mesh.bounds();
        // At most `eps |n + c|`, `n` and `c` unit vectors (orthogonal but
        // where `c` is the rounding left of a mean along the normal).
        let most = crate::OFFSET * (hi - lo).length() * 2.0 * 1.001;
        for (p, o) in mesh.positions.iter().zip(&origins) {
            let offset = (*o - *p).length();
            assert!(offset > 0.0 && offset <= most, "{offset} of at most {most}");
        }
        let dir = Direction::new(Vec3::new(0.1, -1.0, 0.05));
        let local: Vec<[f32; 4]> = occluder.ray_space(&dir).collect();
        assert_eq!(local.len(), occluder.vertex_count());
        let facing: Vec<Vec3> = (0..mesh.vertex_count())
            .filter(|&v| mesh.normals[v].dot(dir.dir()) > 0.0)
            .map(|v| origins[v])
            .collect();
        let (mut blocked, mut fronts, mut disagreements) = (0, 0, 0);
        for eight in facing.chunks(LANES) {
            let packet = Packet::new(&dir, eight);
            let mask = occluder.packet_occluded(&dir, &local, &packet);
            let found = occluder.packet_closest(&dir, &local, &packet);
            assert_eq!(occluder.packet_closest_direct(&dir, &packet), found);
            assert_eq!(found.mask, mask);
            for (k, o) in eight.iter().enumerate() {
                let single = occluder.closest_hit(&Ray::new(*o, dir.dir(), f32::INFINITY));
                // Only a ray grazing an edge may be decided otherwise by
                // the packet traversal (its rounding differs).
                let packet_hit = (mask >> k & 1 == 1).then_some(found.triangle[k]);
                if single.map(|h| h.triangle) != packet_hit {
                    disagreements += 1;
                }
                if let Some(h) = single {
                    blocked += 1;
                    fronts += usize::from(occluder.is_front(h.triangle, dir.dir()));
                }
            }
        }
        assert!(
            blocked > 50 && fronts * 10 > blocked * 9,
            "{fronts} of {blocked}"
        );
        assert!(disagreements <= 2, "{disagreements}");
    }
}
