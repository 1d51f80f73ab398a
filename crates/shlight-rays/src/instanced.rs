//! [`InstancedOccluder`]: a scene's unique primitives made ready once each
//! and placed by its instances, cast against through a two-level
//! hierarchy, its triangles named as the flattened scene names them.
//!
//! - **Bottom level**: one hierarchy per primitive an instance uses, in the
//!   primitive's own space, built as [`crate::Occluder`]'s is (binned SAH,
//!   the watertight test), with the primitive's face normals.
//! - **Top level**: a hierarchy of the same build over the instances' world
//!   boxes (the eight corners of the primitive's box carried to the world,
//!   grown by the rounding of that product), each instance holding the
//!   inverse of its transform.
//! - **A query** walks the top level with the world ray; at each instance
//!   it reached, the ray goes into the primitive's space, `o' = M^-1 o`,
//!   `d' = M^-1 d` with `d'` not renormalised, so `o' + t d'` is the image
//!   of `o + t d` and the distance `t` of a hit is the world one (the
//!   watertight test's `t` is invariant under the affine map); the far
//!   limit found so far carries from instance to instance.
//! - **Naming**: a hit names the triangle the flattened scene's mesh
//!   ([`shlight_mesh::Scene::flatten`]) would, by the scene's
//!   [`FlatLayout`] (instance order, then the primitive's triangle order,
//!   triangles degenerate in world space left out and never hit), with the
//!   barycentric weights in that triangle's corner order: an instance with
//!   a negative determinant mirrors, the flattening reverses its winding
//!   (`[a, c, b]`), so its weights `(w0, w1, w2)` are given as
//!   `(w0, w2, w1)`. [`InstancedOccluder::is_front`] reads the primitive's
//!   face normal against the direction taken into its space, which has the
//!   sign of the flattened face's dot product for either determinant.
//! - **Cut-outs** ([`CutOuts`], asked with the flattened indices): an
//!   instance none of whose triangles cuts out is traced without the test;
//!   the coverage sample is drawn from the world ray, so a ray is decided
//!   as the flattened occluder decides it.
//! - **Packets** are traced lane by lane through the two levels (a true
//!   packet path would take a packet into each instance's space, where its
//!   rays are still parallel; not built).
//!
//! The memory is the unique primitives' hierarchies plus a fixed cost per
//! instance ([`InstancedOccluder::heap_bytes`]; docs/benchmarks.md,
//! "Instanced scenes").

use std::sync::Arc;

use glam::{Affine3A, Mat4, Vec3};
use shlight_mesh::{FlatLayout, MeshError, Scene};

use crate::bvh::{self, Bvh, Hit, Node, Ray};
use crate::cut_outs::{CutOuts, stops};
use crate::packet::{Direction, Packet, PacketHits};

/// The most instances in one top-level leaf.
const MAX_INSTANCES_PER_LEAF: usize = 2;
/// What the top level's heuristic charges a node visit, an instance (a
/// transform and a walk of its primitive's hierarchy) costing 1.
const TOP_NODE_COST: f32 = 0.25;

/// A scene's unique primitives each made ready once, placed by its
/// instances: a two-level hierarchy whose memory grows with the unique
/// triangles, not with the instances, and whose queries answer as an
/// [`Occluder`](crate::Occluder) over the flattened scene does (the same
/// triangle indices, distances and weights, up to rounding).
///
/// Single rays: [`occluded`](Self::occluded) and
/// [`closest_hit`](Self::closest_hit); packets of parallel rays (traced
/// lane by lane): [`packet_occluded`](Self::packet_occluded) and
/// [`packet_closest`](Self::packet_closest).
#[derive(Clone)]
pub struct InstancedOccluder {
    /// Per primitive of the scene, its hierarchy and face normals (`None`
    /// for a primitive no instance uses).
    objects: Vec<Option<Object>>,
    /// Per instance, in the scene's order.
    placed: Vec<Placed>,
    /// The top level: leaves index `order`.
    top: Vec<Node>,
    /// Instances in the top level's leaf order.
    order: Vec<u32>,
    layout: FlatLayout,
    cut: Option<Arc<dyn CutOuts>>,
}

impl std::fmt::Debug for InstancedOccluder {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("InstancedOccluder")
            .field("primitives", &self.objects.iter().flatten().count())
            .field("instances", &self.placed.len())
            .field("triangles", &self.layout.triangle_count())
            .field("cut_outs", &self.cut.is_some())
            .finish_non_exhaustive()
    }
}

/// One primitive made ready, in its own space.
#[derive(Clone, Debug)]
struct Object {
    bvh: Bvh,
    /// `(b - a) x (c - a)` per triangle, in the primitive's order.
    faces: Vec<Vec3>,
}

/// One instance.
#[derive(Clone, Copy, Debug)]
struct Placed {
    /// World to the primitive's space.
    to_object: Affine3A,
    primitive: u32,
    /// A negative determinant: the flattened winding is reversed.
    mirrored: bool,
    /// Some triangle of it cuts out.
    cuts_out: bool,
}

impl Placed {
    /// `ray` taken into the primitive's space, searched up to `t_max`.
    #[inline(always)]
    fn local(&self, ray: &Ray, t_max: f32) -> Ray {
        Ray::new(
            self.to_object.transform_point3(ray.origin()),
            self.to_object.transform_vector3(ray.dir()),
            t_max,
        )
    }

    /// The weights `w` of the primitive's triangle in the flattened
    /// triangle's corner order.
    #[inline(always)]
    fn flat_weights(&self, w: [f32; 3]) -> [f32; 3] {
        if self.mirrored { [w[0], w[2], w[1]] } else { w }
    }
}

impl InstancedOccluder {
    /// `scene` made ready; every triangle stops every ray.
    ///
    /// # Errors
    /// What [`Scene::flatten`] refuses: a non-finite or singular
    /// transform, no instances, no triangle left.
    pub fn new(scene: &Scene) -> Result<Self, MeshError> {
        let layout = scene.flat_layout()?;
        let mut objects: Vec<Option<Object>> = vec![None; scene.primitives.len()];
        for instance in &scene.instances {
            let slot = &mut objects[instance.primitive];
            if slot.is_none() {
                let m = &scene.primitives[instance.primitive].mesh;
                *slot = Some(Object {
                    bvh: Bvh::new(&m.positions, &m.triangles).without_corners(),
                    faces: m
                        .triangles
                        .iter()
                        .map(|t| {
                            let [a, b, c] = t.map(|i| m.positions[i as usize]);
                            (b - a).cross(c - a)
                        })
                        .collect(),
                });
            }
        }
        let mut boxes = Vec::with_capacity(scene.instances.len());
        let placed = scene
            .instances
            .iter()
            .map(|instance| {
                let object = objects[instance.primitive].as_ref().expect("built above");
                boxes.push(world_box(object.bvh.bounds(), &instance.transform));
                Placed {
                    to_object: Affine3A::from_mat4(instance.transform.inverse()),
                    primitive: instance.primitive as u32,
                    mirrored: instance.transform.determinant() < 0.0,
                    cuts_out: false,
                }
            })
            .collect();
        let (top, order) = bvh::build_nodes(boxes, MAX_INSTANCES_PER_LEAF, TOP_NODE_COST);
        Ok(Self {
            objects,
            placed,
            top,
            order,
            layout,
            cut: None,
        })
    }

    /// `scene` made ready, its triangles letting rays through as
    /// `cut_outs` says, asked with the flattened scene's triangle indices
    /// (the scene's flattened [`shlight_mesh::Surfaces`], for one). The
    /// crate documentation states how a ray is decided.
    ///
    /// # Errors
    /// As [`new`](Self::new).
    pub fn with_cut_outs(scene: &Scene, cut_outs: Arc<dyn CutOuts>) -> Result<Self, MeshError> {
        let mut occluder = Self::new(scene)?;
        let mut any = false;
        for (i, p) in occluder.placed.iter_mut().enumerate() {
            let count = scene.primitives[p.primitive as usize].mesh.triangle_count() as u32;
            p.cuts_out = (0..count)
                .filter_map(|t| occluder.layout.triangle(i, t))
                .any(|g| cut_outs.cuts_out(g));
            any |= p.cuts_out;
        }
        occluder.cut = any.then_some(cut_outs);
        Ok(occluder)
    }

    /// Whether some triangle may let rays through (built
    /// [`with_cut_outs`](Self::with_cut_outs) and one cuts out).
    #[must_use]
    pub fn has_cut_outs(&self) -> bool {
        self.cut.is_some()
    }

    /// Triangles of the flattened scene.
    #[must_use]
    pub fn triangle_count(&self) -> usize {
        self.layout.triangle_count() as usize
    }

    /// Bytes held on the heap: each used primitive's hierarchy (nodes,
    /// triangle corners and indices) and face normals, and per instance
    /// its transform, its top-level node share and its place in the
    /// flattened numbering. Grows with the unique triangles and, by a
    /// fixed amount, with the instances.
    #[must_use]
    pub fn heap_bytes(&self) -> usize {
        let objects: usize = self
            .objects
            .iter()
            .flatten()
            .map(|o| o.bvh.heap_bytes() + o.faces.capacity() * size_of::<Vec3>())
            .sum();
        objects
            + self.objects.capacity() * size_of::<Option<Object>>()
            + self.placed.capacity() * size_of::<Placed>()
            + self.top.capacity() * size_of::<Node>()
            + self.order.capacity() * size_of::<u32>()
            + self.layout.heap_bytes()
    }

    /// Whether a hit on triangle `local` of instance `i` at weights `w`
    /// (the primitive's order) stops `world`.
    #[inline(always)]
    fn accepts(&self, i: usize, p: &Placed, local: u32, w: [f32; 3], world: &Ray) -> bool {
        let Some(g) = self.layout.triangle(i, local) else {
            return false;
        };
        match &self.cut {
            Some(cut) if p.cuts_out => {
                !cut.cuts_out(g) || stops(&**cut, g, p.flat_weights(w), world.origin(), world.dir())
            }
            _ => true,
        }
    }

    /// The nearest hit of `ray`, if any.
    #[must_use]
    pub fn closest_hit(&self, ray: &Ray) -> Option<Hit> {
        let mut best: Option<(Hit, usize)> = None;
        let mut t_max = ray.t_max();
        bvh::traverse(
            &self.top,
            ray,
            |t_now, first, count| {
                for &i in &self.order[first..first + count] {
                    let i = i as usize;
                    let p = &self.placed[i];
                    let object = self.objects[p.primitive as usize].as_ref().expect("built");
                    let local = p.local(ray, *t_now);
                    if let Some(h) = object.bvh.closest_accepting(&local, |k, w| {
                        self.accepts(i, p, object.bvh.ids[k], w, ray)
                    }) {
                        *t_now = h.t;
                        best = Some((h, i));
                    }
                }
                false
            },
            &mut t_max,
        );
        best.map(|(h, i)| {
            let p = &self.placed[i];
            Hit {
                t: h.t,
                triangle: self.layout.triangle(i, h.triangle).expect("accepted"),
                barycentrics: p.flat_weights(h.barycentrics),
            }
        })
    }

    /// Whether anything blocks `ray` (the first hit found ends the search).
    #[must_use]
    pub fn occluded(&self, ray: &Ray) -> bool {
        self.occluded_through(ray, true)
    }

    /// Whether any triangle, cut out or not, blocks `ray`.
    pub(crate) fn occluded_opaque(&self, ray: &Ray) -> bool {
        self.occluded_through(ray, false)
    }

    /// Whether anything blocks `ray`, through the cut-outs when `cut`.
    fn occluded_through(&self, ray: &Ray, cut: bool) -> bool {
        let mut t_max = ray.t_max();
        let mut hit = false;
        bvh::traverse(
            &self.top,
            ray,
            |t_now, first, count| {
                hit = self.order[first..first + count].iter().any(|&i| {
                    let i = i as usize;
                    let p = &self.placed[i];
                    let object = self.objects[p.primitive as usize].as_ref().expect("built");
                    object
                        .bvh
                        .occluded_accepting(&p.local(ray, *t_now), |k, w| {
                            if cut {
                                self.accepts(i, p, object.bvh.ids[k], w, ray)
                            } else {
                                self.layout.triangle(i, object.bvh.ids[k]).is_some()
                            }
                        })
                });
                hit
            },
            &mut t_max,
        );
        hit
    }

    /// Whether a ray along `dir` meets triangle `triangle` (the flattened
    /// scene's index) on its front.
    ///
    /// # Panics
    /// If `triangle` is not below [`triangle_count`](Self::triangle_count).
    #[must_use]
    pub fn is_front(&self, triangle: u32, dir: Vec3) -> bool {
        let (i, local) = self.layout.locate(triangle);
        let p = &self.placed[i];
        let object = self.objects[p.primitive as usize].as_ref().expect("built");
        object.faces[local as usize].dot(p.to_object.transform_vector3(dir)) < 0.0
    }

    /// Which rays of `packet` (along `dir`, from `0 < t`) are blocked: bit
    /// `k` set for lane `k`. Each ray is traced alone.
    #[must_use]
    pub fn packet_occluded(&self, dir: &Direction, packet: &Packet) -> u32 {
        packet
            .rays()
            .filter(|&(_, o)| self.occluded(&Ray::new(o, dir.dir(), f32::INFINITY)))
            .fold(0, |mask, (k, _)| mask | 1 << k)
    }

    /// The nearest hit of each ray of `packet` (along `dir`). Each ray is
    /// traced alone.
    #[must_use]
    pub fn packet_closest(&self, dir: &Direction, packet: &Packet) -> PacketHits {
        let mut out = PacketHits::NONE;
        for (k, o) in packet.rays() {
            if let Some(h) = self.closest_hit(&Ray::new(o, dir.dir(), f32::INFINITY)) {
                out.mask |= 1 << k;
                out.t[k] = h.t;
                out.triangle[k] = h.triangle;
                out.barycentrics[k] = h.barycentrics;
            }
        }
        out
    }
}

/// The world box of a primitive whose box is `(lo, hi)` placed by
/// `transform`: its eight corners carried over, grown by the rounding of
/// that product (relative to the largest sum of magnitudes it adds).
fn world_box((lo, hi): (Vec3, Vec3), transform: &Mat4) -> (Vec3, Vec3) {
    let (mut a, mut b) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
    let mut scale = 0.0f32;
    let column = |j: usize| transform.col(j).truncate().abs();
    for k in 0..8 {
        let corner = Vec3::new(
            if k & 1 == 0 { lo.x } else { hi.x },
            if k & 2 == 0 { lo.y } else { hi.y },
            if k & 4 == 0 { lo.z } else { hi.z },
        );
        let w = transform.transform_point3(corner);
        (a, b) = (a.min(w), b.max(w));
        let c = corner.abs();
        let size = column(0) * c.x + column(1) * c.y + column(2) * c.z + column(3);
        scale = scale.max(size.max_element());
    }
    bvh::padded((a, b), scale)
}
