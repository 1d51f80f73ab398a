//! Conforming subdivision of a mesh's long edges.
//!
//! Bakes that store light per vertex (PRT transfer, the surface cache an
//! irradiance volume reads) need vertices close enough together to hold a
//! shadow's edge: a floor made of two triangles has four. [`Mesh::subdivided`]
//! splits every edge longer than a given length by longest-edge bisection
//! (Rivara 1984), keeping the mesh conforming: an edge is split at one shared
//! midpoint for both triangles that use it, so no T-junction or crack
//! appears and a closed mesh stays closed.
//!
//! [`Mesh::subdivided_with_map`] also keeps the bisection tree of every
//! original triangle ([`Subdivision`]): a point on an original triangle
//! (its barycentric weights) is found in the subdivided mesh by one side
//! test per split, so rays can be cast against the original triangles,
//! far fewer, and the light read from the subdivided ones.

use std::collections::HashMap;

use glam::Vec3;

use crate::Mesh;

impl Mesh {
    /// The mesh with every edge no longer than `max_edge`.
    ///
    /// A triangle with an edge longer than `max_edge` is cut in two through
    /// the midpoint of its longest edge and the opposite corner; a triangle
    /// whose edge was cut by its neighbour is cut at the same midpoint, so
    /// the result has no T-junctions. New vertices come after the original
    /// ones (which keep their order); their normal is the normalised mean of
    /// the edge's two normals, their colour and emission the mean of the
    /// two. Triangles keep their winding. Returns a copy when no edge is
    /// longer (or `max_edge` is not a positive finite number).
    #[must_use]
    pub fn subdivided(&self, max_edge: f32) -> Mesh {
        self.subdivided_with_map(max_edge).0
    }

    /// [`subdivided`](Self::subdivided), with the map from the original
    /// triangles to the subdivided ones.
    #[must_use]
    pub fn subdivided_with_map(&self, max_edge: f32) -> (Mesh, Subdivision) {
        let mut out = self.clone();
        // Node `t` is original triangle `t`'s root; a triangle in the work
        // lists carries its node, and a split turns the node into an inner
        // one with two new children.
        let mut nodes: Vec<Node> = (0..self.triangles.len()).map(|_| Node::Leaf(0)).collect();
        if !(max_edge.is_finite() && max_edge > 0.0) {
            return (out, Subdivision::unsplit(self.triangles.len()));
        }
        let max2 = max_edge * max_edge;
        // Edges are marked as split by their geometry (the canonical ids of
        // their end positions), so faces that meet at an edge without
        // sharing vertex indices (a box with flat normals) are split
        // alike; each index edge gets its own midpoint vertex (keeping
        // that side's normal and colour).
        let mut canonical: HashMap<[u32; 3], u32> = HashMap::new();
        let mut ids: Vec<u32> = out
            .positions
            .iter()
            .map(|p| {
                let next = canonical.len() as u32;
                *canonical
                    .entry(p.to_array().map(f32::to_bits))
                    .or_insert(next)
            })
            .collect();
        let mut split_edges: std::collections::HashSet<(u32, u32)> = Default::default();
        let mut midpoints: HashMap<(u32, u32), u32> = HashMap::new();
        let mut pending: Vec<([u32; 3], u32)> = std::mem::take(&mut out.triangles)
            .into_iter()
            .zip(0..)
            .collect();
        pending.reverse();
        let mut done = Vec::with_capacity(pending.len());
        // Passes until no triangle has an edge too long or an edge a
        // neighbour split: splitting only creates marks on edges longer than
        // `max_edge`, whose halves are shorter, so this terminates.
        loop {
            while let Some((tri, node)) = pending.pop() {
                let edges = [(0, 1), (1, 2), (2, 0)];
                let len2 = edges.map(|(i, j)| {
                    out.positions[tri[i] as usize].distance_squared(out.positions[tri[j] as usize])
                });
                let marked = edges.map(|(i, j)| {
                    split_edges.contains(&key(ids[tri[i] as usize], ids[tri[j] as usize]))
                });
                let longest = (0..3)
                    .max_by(|&a, &b| len2[a].total_cmp(&len2[b]))
                    .unwrap_or(0);
                let split = if len2[longest] > max2 || marked[longest] {
                    Some(longest)
                } else {
                    (0..3).find(|&e| marked[e])
                };
                let Some(e) = split else {
                    done.push((tri, node));
                    continue;
                };
                let (i, j) = edges[e];
                let (a, b, c) = (tri[i], tri[j], tri[3 - i - j]);
                let m = *midpoints.entry(key(a, b)).or_insert_with(|| {
                    let m = push_midpoint(&mut out, a, b);
                    let p = out.positions[m as usize].to_array().map(f32::to_bits);
                    let next = canonical.len() as u32;
                    ids.push(*canonical.entry(p).or_insert(next));
                    m
                });
                split_edges.insert(key(ids[a as usize], ids[b as usize]));
                // (a, b, c) is the triangle's winding rotated to start at a,
                // so (a, m, c) and (m, b, c) keep it; (a, m, c) is taken next.
                let first = nodes.len() as u32;
                nodes.push(Node::Leaf(0));
                nodes.push(Node::Leaf(0));
                nodes[node as usize] = Node::Split {
                    edge: e as u8,
                    children: first,
                };
                pending.push(([m, b, c], first + 1));
                pending.push(([a, m, c], first));
            }
            let is_stale = |(t, _): &([u32; 3], u32)| {
                [(0, 1), (1, 2), (2, 0)].iter().any(|&(i, j)| {
                    split_edges.contains(&key(ids[t[i] as usize], ids[t[j] as usize]))
                })
            };
            let (mut stale, kept): (Vec<_>, Vec<_>) = done.into_iter().partition(|t| is_stale(t));
            done = kept;
            if stale.is_empty() {
                break;
            }
            stale.reverse();
            pending = stale;
        }
        out.triangles = Vec::with_capacity(done.len());
        for (t, (tri, node)) in done.into_iter().enumerate() {
            nodes[node as usize] = Node::Leaf(t as u32);
            out.triangles.push(tri);
        }
        let map = Subdivision::from_trees(&nodes, self.triangles.len());
        (out, map)
    }
}

/// Where the triangles of a subdivided mesh lie in the original ones
/// ([`Mesh::subdivided_with_map`]): per original triangle, its subdivided
/// triangles in its own barycentric plane `(w1, w2)`, bucketed in a grid of
/// about one cell per triangle, so that finding a point's triangle tests a
/// few candidates.
#[derive(Clone, Debug, PartialEq)]
pub struct Subdivision {
    /// Per original triangle: cells per axis (0: not split, `first` is then
    /// its triangle) and its first cell in `cells`.
    grids: Vec<(u32, u32)>,
    /// Per cell, its first entry in `entries` (one more at each grid's end).
    cells: Vec<u32>,
    /// The pieces meeting each cell: indices into `pieces`.
    entries: Vec<u32>,
    /// Each original triangle's pieces in the order of its bisection tree
    /// (depth first: neighbours in space are near in memory).
    pieces: Vec<Piece>,
}

/// A subdivided triangle and its corners in its original triangle's
/// `(w1, w2)` plane.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Piece {
    triangle: u32,
    corners: [[f32; 2]; 3],
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Node {
    /// A triangle of the subdivided mesh (its index).
    Leaf(u32),
    /// Cut through the midpoint `m` of the edge from corner `edge` to the
    /// next one, `(a, b)`, and the opposite corner `c`, into `(a, m, c)`
    /// (node `children`) and `(m, b, c)` (the next node), in the corner
    /// order the subdivided triangles keep.
    Split { edge: u8, children: u32 },
}

/// Asks for the cache line holding `x`.
#[inline]
fn prefetch<T>(x: &T) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        // SAFETY: SSE is part of every x86-64 processor, and a prefetch
        // only hints the cache (it reads nothing and cannot fault).
        unsafe { _mm_prefetch::<_MM_HINT_T0>(std::ptr::from_ref(x).cast::<i8>()) };
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = x;
}

/// The cell of `x` (in 0..=1) in a grid of `r` cells per axis.
fn cell_of(x: f32, r: usize) -> usize {
    // Truncation is the floor for x >= 0 (and NaN goes to cell 0).
    ((f64::from(x) * r as f64).max(0.0) as usize).min(r - 1)
}

/// `(a - o) x (b - o)`.
fn cross(o: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
}

impl Subdivision {
    /// The map of a mesh of `n` triangles left as it was.
    fn unsplit(n: usize) -> Self {
        Self {
            grids: (0..n as u32).map(|t| (0, t)).collect(),
            cells: Vec::new(),
            entries: Vec::new(),
            pieces: Vec::new(),
        }
    }

    /// The grids of the bisection trees `nodes`, nodes `0..roots` the
    /// original triangles' roots.
    fn from_trees(nodes: &[Node], roots: usize) -> Self {
        let mut out = Self {
            grids: Vec::with_capacity(roots),
            cells: Vec::new(),
            entries: Vec::new(),
            pieces: Vec::new(),
        };
        let mut stack = Vec::new();
        let mut bucketed: Vec<(u32, u32)> = Vec::new();
        for root in 0..roots {
            if let Node::Leaf(t) = nodes[root] {
                out.grids.push((0, t));
                continue;
            }
            let base = out.pieces.len();
            stack.push((root, [[0.0f64, 0.0], [1.0, 0.0], [0.0, 1.0]]));
            while let Some((n, p)) = stack.pop() {
                match nodes[n] {
                    Node::Leaf(triangle) => out.pieces.push(Piece {
                        triangle,
                        corners: p.map(|c| c.map(|x| x as f32)),
                    }),
                    Node::Split { edge, children } => {
                        let i = usize::from(edge);
                        let (a, b, c) = (p[i], p[(i + 1) % 3], p[(i + 2) % 3]);
                        let m = [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
                        stack.push((children as usize + 1, [m, b, c]));
                        stack.push((children as usize, [a, m, c]));
                    }
                }
            }
            // About one cell per piece over the half of the square the
            // triangle covers.
            let count = out.pieces.len() - base;
            let r = (1.42 * (count as f64).sqrt()).ceil() as usize;
            let cell = |x: f32| cell_of(x, r);
            bucketed.clear();
            for (k, piece) in out.pieces[base..].iter().enumerate() {
                let lo = [0, 1].map(|a| piece.corners.iter().map(|c| c[a]).fold(1.0, f32::min));
                let hi = [0, 1].map(|a| piece.corners.iter().map(|c| c[a]).fold(0.0, f32::max));
                for y in cell(lo[1])..=cell(hi[1]) {
                    for x in cell(lo[0])..=cell(hi[0]) {
                        bucketed.push(((y * r + x) as u32, (base + k) as u32));
                    }
                }
            }
            bucketed.sort_unstable();
            out.grids.push((r as u32, out.cells.len() as u32));
            let mut next = 0;
            for c in 0..=r * r {
                out.cells.push(out.entries.len() as u32);
                while next < bucketed.len() && bucketed[next].0 as usize == c {
                    out.entries.push(bucketed[next].1);
                    next += 1;
                }
            }
        }
        out
    }

    /// Triangles of the original mesh.
    #[must_use]
    pub fn original_triangles(&self) -> usize {
        self.grids.len()
    }

    /// [`locate`](Self::locate) for each of `points` (`(triangle, w)`),
    /// into `out` (cleared first). The points' memory reads are started
    /// together, so that their cache misses overlap.
    pub fn locate_each(&self, points: &[(u32, [f32; 3])], out: &mut Vec<Option<(u32, [f32; 3])>>) {
        out.clear();
        let cell = |&(t, w): &(u32, [f32; 3])| match self.grids.get(t as usize) {
            Some(&(r, first)) if r > 0 => {
                let r = r as usize;
                Some(first as usize + cell_of(w[2], r) * r + cell_of(w[1], r))
            }
            _ => None,
        };
        for c in points.iter().filter_map(cell) {
            prefetch(&self.cells[c]);
        }
        for c in points.iter().filter_map(cell) {
            if let Some(&k) = self.entries.get(self.cells[c] as usize) {
                prefetch(&self.pieces[k as usize]);
            }
        }
        out.extend(points.iter().map(|&(t, w)| self.locate(t, w)));
    }

    /// The subdivided triangle holding the point of original triangle
    /// `triangle` with barycentric weights `w` (of its corners in order),
    /// and the point's weights in that triangle; `None` when `triangle` is
    /// not an original triangle. A point on a cut goes to either side
    /// (the two agree there).
    #[must_use]
    pub fn locate(&self, triangle: u32, w: [f32; 3]) -> Option<(u32, [f32; 3])> {
        let &(r, first) = self.grids.get(triangle as usize)?;
        if r == 0 {
            // Not split: the weights as they are.
            return Some((first, w));
        }
        let r = r as usize;
        let c = first as usize + cell_of(w[2], r) * r + cell_of(w[1], r);
        let q = [f64::from(w[1]), f64::from(w[2])];
        // The candidate the point is most inside of (all weights >= 0 but
        // for rounding on a cut).
        let mut best = None;
        let mut best_min = f64::NEG_INFINITY;
        for &k in &self.entries[self.cells[c] as usize..self.cells[c + 1] as usize] {
            let piece = &self.pieces[k as usize];
            let p = piece.corners.map(|c| c.map(f64::from));
            // Every piece keeps the original winding: d > 0, and the point
            // is inside when the three unnormalised weights are >= 0.
            let d = cross(p[0], p[1], p[2]);
            let w1 = cross(p[0], q, p[2]);
            let w2 = cross(p[0], p[1], q);
            let w0 = d - w1 - w2;
            let min = w0.min(w1).min(w2) / d;
            if min > best_min {
                best_min = min;
                best = Some((piece.triangle, [w0, w1, w2].map(|x| (x / d) as f32)));
                if min >= 0.0 {
                    break;
                }
            }
        }
        best
    }
}

fn key(a: u32, b: u32) -> (u32, u32) {
    (a.min(b), a.max(b))
}

fn push_midpoint(mesh: &mut Mesh, a: u32, b: u32) -> u32 {
    let (a, b) = (a as usize, b as usize);
    let index = mesh.positions.len() as u32;
    mesh.positions
        .push(0.5 * (mesh.positions[a] + mesh.positions[b]));
    let n = mesh.normals[a] + mesh.normals[b];
    mesh.normals
        .push(n.try_normalize().unwrap_or(mesh.normals[a]));
    for values in [&mut mesh.colors, &mut mesh.emission].into_iter().flatten() {
        let mean: Vec3 = 0.5 * (values[a] + values[b]);
        values.push(mean);
    }
    index
}

#[cfg(test)]
mod tests {
    use std::collections::HashMap;

    use super::*;
    use crate::generate;

    /// Every edge of a closed surface (its ends compared by position, as
    /// faces may not share vertex indices) is used by exactly two
    /// triangles, once in each direction: no crack, no T-junction.
    fn assert_closed(mesh: &Mesh) {
        let at = |i: u32| mesh.positions[i as usize].to_array().map(f32::to_bits);
        let mut uses: HashMap<([u32; 3], [u32; 3]), i32> = HashMap::new();
        for t in &mesh.triangles {
            for (i, j) in [(0, 1), (1, 2), (2, 0)] {
                *uses.entry((at(t[i]), at(t[j]))).or_default() += 1;
            }
        }
        for (&(a, b), &n) in &uses {
            assert_eq!(n, 1, "edge {a:?}-{b:?} used {n} times one way");
            assert_eq!(uses.get(&(b, a)), Some(&1), "edge {a:?}-{b:?} has no twin");
        }
    }

    #[test]
    fn splits_long_edges_and_keeps_a_closed_mesh_closed() {
        let cube = generate::cuboid(Vec3::ONE);
        assert_closed(&cube);
        let area = cube.surface_area();
        let fine = cube.subdivided(0.3);
        assert_closed(&fine);
        assert!(fine.triangle_count() > 8 * cube.triangle_count());
        assert!((fine.surface_area() - area).abs() < 1e-4 * area);
        for t in &fine.triangles {
            for (i, j) in [(0, 1), (1, 2), (2, 0)] {
                let d = fine.positions[t[i] as usize].distance(fine.positions[t[j] as usize]);
                assert!(d <= 0.3 + 1e-6, "edge of {d}");
            }
            // Winding kept: the face normal agrees with the vertex normals.
            let [a, b, c] = t.map(|i| fine.positions[i as usize]);
            let face = (b - a).cross(c - a);
            assert!(face.dot(fine.normals[t[0] as usize]) > 0.0);
        }
        // The original vertices come first, unchanged.
        assert_eq!(&fine.positions[..cube.vertex_count()], &cube.positions[..]);
    }

    #[test]
    fn attributes_are_interpolated_and_short_meshes_are_copied() {
        // Colour = position and emission = x on the corners: both are linear
        // in position, so midpoint interpolation must reproduce them at
        // every new vertex.
        let corners = vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y];
        let quad = Mesh::new(
            "quad",
            corners.clone(),
            vec![[0, 1, 2], [0, 2, 3]],
            None,
            Some(corners.clone()),
        )
        .unwrap()
        .with_emission("quad", corners.iter().map(|p| Vec3::splat(p.x)).collect())
        .unwrap();
        let fine = quad.subdivided(0.26);
        assert!(fine.vertex_count() > 20);
        let colors = fine.colors.as_ref().unwrap();
        let emission = fine.emission.as_ref().unwrap();
        for (v, p) in fine.positions.iter().enumerate() {
            assert_eq!(fine.normals[v], Vec3::Z);
            assert!(colors[v].distance(*p) < 1e-6, "{v}: {} at {p}", colors[v]);
            assert!(emission[v].distance(Vec3::splat(p.x)) < 1e-6);
        }
        assert_eq!(quad.subdivided(2.0).triangles, quad.triangles);
        assert_eq!(quad.subdivided(f32::NAN).triangles, quad.triangles);
    }

    #[test]
    fn a_point_of_an_original_triangle_is_found_in_the_subdivided_one_holding_it() {
        // The same point by two routes: the original triangle's weights,
        // and the located subdivided triangle's weights of its corners.
        let meshes = [
            generate::cuboid(Vec3::new(1.0, 0.4, 2.0)),
            generate::uv_sphere(1.0, 6, 3),
        ];
        for mesh in meshes {
            let (fine, map) = mesh.subdivided_with_map(0.17);
            assert_eq!(map.original_triangles(), mesh.triangle_count());
            assert!(fine.triangle_count() > 10 * mesh.triangle_count());
            let mut seen = std::collections::HashSet::new();
            // A lattice of points over each triangle, corners and edges
            // included.
            let n = 40;
            for (t, tri) in mesh.triangles.iter().enumerate() {
                let [a, b, c] = tri.map(|i| mesh.positions[i as usize]);
                for i in 0..=n {
                    for j in 0..=n - i {
                        let (w1, w2) = (i as f32 / n as f32, j as f32 / n as f32);
                        let w = [1.0 - w1 - w2, w1, w2];
                        let want = w[0] * a + w[1] * b + w[2] * c;
                        let (sub, u) = map.locate(t as u32, w).unwrap();
                        assert!(u.iter().all(|x| (-1e-5..=1.0 + 1e-5).contains(x)), "{u:?}");
                        let [p, q, r] =
                            fine.triangles[sub as usize].map(|i| fine.positions[i as usize]);
                        let got = u[0] * p + u[1] * q + u[2] * r;
                        assert!(got.distance(want) < 1e-5, "{t}: {got} vs {want}");
                        seen.insert(sub);
                    }
                }
            }
            // Every subdivided triangle is some original triangle's leaf.
            assert!(seen.len() > fine.triangle_count() / 2);
            assert!(
                map.locate(mesh.triangle_count() as u32, [1.0, 0.0, 0.0])
                    .is_none()
            );
        }
        let quad = generate::plane(1.0, 1);
        let (same, map) = quad.subdivided_with_map(f32::NAN);
        assert_eq!(same.triangles, quad.triangles);
        assert_eq!(map.locate(1, [0.2, 0.3, 0.5]), Some((1, [0.2, 0.3, 0.5])));
    }
}
