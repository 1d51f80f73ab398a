//! Conforming subdivision of a mesh's long edges.
//!
//! Bakes that store light per vertex (PRT transfer, the surface cache an
//! irradiance volume reads) need vertices close enough together to hold a
//! shadow's edge: a floor made of two triangles has four. [`Mesh::subdivided`]
//! splits every edge longer than a given length by longest-edge bisection
//! (Rivara 1984), keeping the mesh conforming: an edge is split at one shared
//! midpoint for both triangles that use it, so no T-junction or crack
//! appears and a closed mesh stays closed.

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
        let mut out = self.clone();
        if !(max_edge.is_finite() && max_edge > 0.0) {
            return out;
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
        let mut pending: Vec<[u32; 3]> = std::mem::take(&mut out.triangles);
        pending.reverse();
        let mut done = Vec::with_capacity(pending.len());
        // Passes until no triangle has an edge too long or an edge a
        // neighbour split: splitting only creates marks on edges longer than
        // `max_edge`, whose halves are shorter, so this terminates.
        loop {
            while let Some(tri) = pending.pop() {
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
                    done.push(tri);
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
                pending.push([m, b, c]);
                pending.push([a, m, c]);
            }
            let is_stale = |t: &[u32; 3]| {
                [(0, 1), (1, 2), (2, 0)].iter().any(|&(i, j)| {
                    split_edges.contains(&key(ids[t[i] as usize], ids[t[j] as usize]))
                })
            };
            let (mut stale, kept): (Vec<[u32; 3]>, Vec<[u32; 3]>) =
                done.into_iter().partition(|t| is_stale(t));
            done = kept;
            if stale.is_empty() {
                break;
            }
            stale.reverse();
            pending = stale;
        }
        out.triangles = done;
        out
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
}
