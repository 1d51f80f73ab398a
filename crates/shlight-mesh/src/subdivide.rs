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
//! [`Mesh::subdivided_with_map`] also maps the original triangles to the
//! subdivided ones ([`Subdivision`]): a point on an original triangle (its
//! barycentric weights) is found in the subdivided mesh through a grid over
//! the original triangle's barycentric plane, usually by reading one cell
//! and testing one or two candidates, so rays can be cast against the
//! original triangles, far fewer, and the light read from the subdivided
//! ones.

use glam::Vec3;
use rayon::prelude::*;
use rustc_hash::{FxHashMap, FxHashSet};

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
        let mut canonical: FxHashMap<[u32; 3], u32> = FxHashMap::default();
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
        let mut split_edges: FxHashSet<(u32, u32)> = FxHashSet::default();
        let mut midpoints: FxHashMap<(u32, u32), u32> = FxHashMap::default();
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
/// triangles (its *pieces*) in its own barycentric plane `(w1, w2)`,
/// bucketed in a grid of about two cells per piece.
///
/// A cell lists the pieces that overlap it with a positive area (no side of
/// the piece has the whole cell outside it): the one that holds the cell's
/// centre and one other are held in the cell itself, the rest in a list
/// after it. Finding a point reads its cell and those two pieces (nine
/// points in ten are in one of them), memory reads that
/// [`locate_each`](Self::locate_each) starts for a few dozen points at
/// once so that their cache misses overlap. A piece holds its corner 0 and
/// the inverse of its edge matrix: a candidate's weights are two dot
/// products in `f32`. The grids are built in parallel, one original
/// triangle per task.
#[derive(Clone, Debug, PartialEq)]
pub struct Subdivision {
    /// Per original triangle: cells per axis (0: not split, `first` is then
    /// its triangle) and its first cell in `cells`.
    grids: Vec<(u32, u32)>,
    /// Per original triangle, its first piece in `pieces` (one more at the
    /// end).
    spans: Vec<u32>,
    /// The cells of every grid, row by row (`w2` rows, `w1` columns), and
    /// one more at each grid's end that ends its last cell's `rest`.
    cells: Vec<Cell>,
    /// The cells' candidates after their first two.
    entries: Vec<u32>,
    /// Each original triangle's pieces in the order of its bisection tree
    /// (depth first: neighbours in space are near in memory).
    pieces: Vec<Piece>,
}

/// Cells per piece of a [`Subdivision`]'s grids (over the original
/// triangle, which covers half of its grid's square). Two: a cell is about
/// half a piece and meets two or three of them, and the piece holding its
/// centre holds about two points in three of it (the two candidates a cell
/// holds, about nine in ten).
const CELLS_PER_PIECE: f64 = 2.0;

/// No piece: a cell that no piece overlaps with a positive area.
const NONE: u32 = u32::MAX;

/// One cell of a [`Subdivision`] grid.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Cell {
    /// The piece that holds the cell's centre (the first such piece when
    /// the centre is on a cut), or, when none does (a cell across the
    /// triangle's long side), the first piece that overlaps the cell;
    /// [`NONE`]: no piece overlaps it.
    first: u32,
    /// Another piece that overlaps it ([`NONE`]: no other).
    second: u32,
    /// Its other candidates: `entries[rest..]` up to the next cell's `rest`.
    rest: u32,
}

/// A subdivided triangle in its original triangle's `(w1, w2)` plane: a
/// point `q`'s weights of its corners 1 and 2 are `inverse (q - origin)`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(32))]
struct Piece {
    /// Corner 0.
    origin: [f32; 2],
    /// The inverse of the matrix whose columns are the edges from corner 0
    /// to corners 1 and 2, row-major.
    inverse: [f32; 4],
    /// Its triangle in the subdivided mesh.
    triangle: u32,
}

impl Piece {
    /// The piece with corners `p` (in the subdivided triangle's order).
    fn new(triangle: u32, p: [[f64; 2]; 3]) -> Self {
        let e1 = [p[1][0] - p[0][0], p[1][1] - p[0][1]];
        let e2 = [p[2][0] - p[0][0], p[2][1] - p[0][1]];
        let det = e1[0] * e2[1] - e1[1] * e2[0];
        Self {
            origin: p[0].map(|x| x as f32),
            inverse: [e2[1] / det, -e2[0] / det, -e1[1] / det, e1[0] / det].map(|x| x as f32),
            triangle,
        }
    }

    /// The barycentric weights of `q` (all `>= 0` inside the piece).
    #[inline]
    fn weights(&self, q: [f32; 2]) -> [f32; 3] {
        let d = [q[0] - self.origin[0], q[1] - self.origin[1]];
        let [a, b, c, e] = self.inverse;
        let u1 = a * d[0] + b * d[1];
        let u2 = c * d[0] + e * d[1];
        [1.0 - u1 - u2, u1, u2]
    }
}

/// The smallest of three weights.
#[inline]
fn least(w: [f32; 3]) -> f32 {
    w[0].min(w[1]).min(w[2])
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
fn cell_of(x: f64, r: usize) -> usize {
    // Truncation is the floor for x >= 0 (and NaN goes to cell 0).
    ((x * r as f64).max(0.0) as usize).min(r - 1)
}

/// One split triangle's pieces and grid, indices local to it.
struct Part {
    r: u32,
    pieces: Vec<Piece>,
    /// `r * r` cells and the one that ends the last.
    cells: Vec<Cell>,
    entries: Vec<u32>,
}

impl Part {
    /// The pieces of the bisection tree at `root` (depth first) and their
    /// grid: each cell lists the pieces that overlap it with a positive
    /// area, in the pieces' order except that the first piece holding the
    /// cell's centre comes first (when none holds it, the first piece that
    /// overlaps the cell stays first).
    fn new(nodes: &[Node], root: usize) -> Self {
        let mut pieces = Vec::new();
        let mut corners: Vec<[[f64; 2]; 3]> = Vec::new();
        let mut stack = vec![(root, [[0.0f64, 0.0], [1.0, 0.0], [0.0, 1.0]])];
        while let Some((n, p)) = stack.pop() {
            match nodes[n] {
                Node::Leaf(triangle) => {
                    pieces.push(Piece::new(triangle, p));
                    corners.push(p);
                }
                Node::Split { edge, children } => {
                    let i = usize::from(edge);
                    let (a, b, c) = (p[i], p[(i + 1) % 3], p[(i + 2) % 3]);
                    let m = [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
                    stack.push((children as usize + 1, [m, b, c]));
                    stack.push((children as usize, [a, m, c]));
                }
            }
        }
        // The triangle covers half of the grid's square.
        let r = (2.0 * CELLS_PER_PIECE * corners.len() as f64).sqrt().ceil() as usize;
        let size = 1.0 / r as f64;
        // (cell, whether the piece holds the cell's centre, piece), per
        // piece in order.
        let mut overlaps: Vec<(u32, bool, u32)> = Vec::with_capacity(4 * corners.len());
        for (k, p) in corners.iter().enumerate() {
            let lo = [0, 1].map(|a| p.iter().map(|c| c[a]).fold(1.0, f64::min));
            let hi = [0, 1].map(|a| p.iter().map(|c| c[a]).fold(0.0, f64::max));
            for y in cell_of(lo[1], r)..=cell_of(hi[1], r) {
                for x in cell_of(lo[0], r)..=cell_of(hi[0], r) {
                    let (x0, y0) = (x as f64 * size, y as f64 * size);
                    let (x1, y1) = (x0 + size, y0 + size);
                    if hi[0] <= x0 || lo[0] >= x1 || hi[1] <= y0 || lo[1] >= y1 {
                        continue;
                    }
                    if let Some(centre) = overlaps_box(p, [x0, y0], [x1, y1]) {
                        overlaps.push(((y * r + x) as u32, centre, k as u32));
                    }
                }
            }
        }
        // Grouped by cell (a counting sort, pieces in order within a
        // cell), the piece holding the centre first.
        let mut start = vec![0u32; r * r + 1];
        for o in &overlaps {
            start[o.0 as usize + 1] += 1;
        }
        for c in 0..r * r {
            start[c + 1] += start[c];
        }
        let mut grouped = vec![(0u32, false); overlaps.len()];
        let mut at = start.clone();
        for &(c, centre, k) in &overlaps {
            grouped[at[c as usize] as usize] = (k, centre);
            at[c as usize] += 1;
        }
        let mut cells = Vec::with_capacity(r * r + 1);
        let mut entries = Vec::with_capacity(overlaps.len());
        for c in 0..r * r {
            let list = &grouped[start[c] as usize..start[c + 1] as usize];
            let first = list.iter().position(|o| o.1).unwrap_or(0);
            let mut others = list
                .iter()
                .enumerate()
                .filter(|&(i, _)| i != first)
                .map(|(_, o)| o.0);
            cells.push(Cell {
                first: list.get(first).map_or(NONE, |o| o.0),
                second: others.next().unwrap_or(NONE),
                rest: entries.len() as u32,
            });
            entries.extend(others);
        }
        cells.push(Cell {
            first: NONE,
            second: NONE,
            rest: entries.len() as u32,
        });
        Self {
            r: r as u32,
            pieces,
            cells,
            entries,
        }
    }
}

/// Whether the counter-clockwise triangle `p` and the box `lo..hi` (which
/// overlap on both axes) share a positive area, and if so whether the
/// triangle holds the box's centre: no side of the triangle has the whole
/// box on its outside (the separating axes of a triangle and a box that
/// are left).
fn overlaps_box(p: &[[f64; 2]; 3], lo: [f64; 2], hi: [f64; 2]) -> Option<bool> {
    let corners = [lo, [hi[0], lo[1]], hi, [lo[0], hi[1]]];
    let mid = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
    let mut centre = true;
    for i in 0..3 {
        let (a, b) = (p[i], p[(i + 1) % 3]);
        let side = |q: [f64; 2]| (b[0] - a[0]) * (q[1] - a[1]) - (b[1] - a[1]) * (q[0] - a[0]);
        if corners.iter().all(|&q| side(q) <= 0.0) {
            return None;
        }
        centre &= side(mid) >= 0.0;
    }
    Some(centre)
}

impl Subdivision {
    /// The map of a mesh of `n` triangles left as it was.
    fn unsplit(n: usize) -> Self {
        Self {
            grids: (0..n as u32).map(|t| (0, t)).collect(),
            spans: vec![0; n + 1],
            cells: Vec::new(),
            entries: Vec::new(),
            pieces: Vec::new(),
        }
    }

    /// The grids of the bisection trees `nodes`, nodes `0..roots` the
    /// original triangles' roots (split triangles in parallel).
    fn from_trees(nodes: &[Node], roots: usize) -> Self {
        let parts: Vec<Option<Part>> = (0..roots)
            .into_par_iter()
            .map(|root| match nodes[root] {
                Node::Leaf(_) => None,
                Node::Split { .. } => Some(Part::new(nodes, root)),
            })
            .collect();
        let mut out = Self {
            grids: Vec::with_capacity(roots),
            spans: Vec::with_capacity(roots + 1),
            cells: Vec::new(),
            entries: Vec::new(),
            pieces: Vec::new(),
        };
        for (root, part) in parts.into_iter().enumerate() {
            out.spans.push(out.pieces.len() as u32);
            let Some(part) = part else {
                if let Node::Leaf(t) = nodes[root] {
                    out.grids.push((0, t));
                }
                continue;
            };
            let (pieces, entries) = (out.pieces.len() as u32, out.entries.len() as u32);
            out.grids.push((part.r, out.cells.len() as u32));
            let shift = |k: u32| if k == NONE { NONE } else { k + pieces };
            out.cells.extend(part.cells.iter().map(|c| Cell {
                first: shift(c.first),
                second: shift(c.second),
                rest: c.rest + entries,
            }));
            out.entries.extend(part.entries.iter().map(|k| k + pieces));
            out.pieces.extend(part.pieces);
        }
        out.spans.push(out.pieces.len() as u32);
        out
    }

    /// Triangles of the original mesh.
    #[must_use]
    pub fn original_triangles(&self) -> usize {
        self.grids.len()
    }

    /// Per triangle of the subdivided mesh, the original triangle it is a
    /// piece of.
    #[must_use]
    pub fn originals(&self) -> Vec<u32> {
        let mut pieces: Vec<(u32, u32)> = Vec::with_capacity(self.pieces.len() + self.grids.len());
        for (t, &(r, first)) in self.grids.iter().enumerate() {
            if r == 0 {
                pieces.push((first, t as u32));
            } else {
                let span = self.spans[t] as usize..self.spans[t + 1] as usize;
                pieces.extend(self.pieces[span].iter().map(|p| (p.triangle, t as u32)));
            }
        }
        let mut out = vec![0u32; pieces.len()];
        for (piece, original) in pieces {
            out[piece as usize] = original;
        }
        out
    }

    /// The cell of the point of original triangle `triangle` with weights
    /// `w`, when that triangle was split.
    #[inline]
    fn cell(&self, triangle: u32, w: [f32; 3]) -> Option<usize> {
        match self.grids.get(triangle as usize) {
            Some(&(r, first)) if r > 0 => {
                let r = r as usize;
                let (x, y) = (f64::from(w[1]), f64::from(w[2]));
                Some(first as usize + cell_of(y, r) * r + cell_of(x, r))
            }
            _ => None,
        }
    }

    /// [`locate`](Self::locate) for each of `points` (`(triangle, w)`),
    /// into `out` (cleared first). The points' memory reads are started
    /// together, a few dozen points at a time (their cells, then their
    /// first candidates), so that their cache misses overlap.
    pub fn locate_each(&self, points: &[(u32, [f32; 3])], out: &mut Vec<Option<(u32, [f32; 3])>>) {
        const BATCH: usize = 32;
        out.clear();
        out.reserve(points.len());
        for batch in points.chunks(BATCH) {
            let mut at = [usize::MAX; BATCH];
            for (a, &(t, w)) in at.iter_mut().zip(batch) {
                if let Some(c) = self.cell(t, w) {
                    prefetch(&self.cells[c]);
                    *a = c;
                }
            }
            for &c in &at[..batch.len()] {
                if c != usize::MAX {
                    let cell = &self.cells[c];
                    for k in [cell.first, cell.second] {
                        if k != NONE {
                            prefetch(&self.pieces[k as usize]);
                        }
                    }
                }
            }
            out.extend(at.iter().zip(batch).map(|(&c, &(t, w))| {
                if c == usize::MAX {
                    self.locate(t, w)
                } else {
                    self.locate_in(t as usize, c, [w[1], w[2]])
                }
            }));
        }
    }

    /// The subdivided triangle holding the point of original triangle
    /// `triangle` with barycentric weights `w` (of its corners in order),
    /// and the point's weights in that triangle; `None` when `triangle` is
    /// not an original triangle. A point on a cut goes to either side
    /// (the two agree there); a point just outside the original triangle
    /// (by rounding) to the piece it is least outside of.
    #[must_use]
    pub fn locate(&self, triangle: u32, w: [f32; 3]) -> Option<(u32, [f32; 3])> {
        let &(r, first) = self.grids.get(triangle as usize)?;
        if r == 0 {
            // Not split: the weights as they are.
            return Some((first, w));
        }
        let c = self.cell(triangle, w)?;
        self.locate_in(triangle as usize, c, [w[1], w[2]])
    }

    /// The piece of original triangle `t` holding `q`, from the candidates
    /// of its cell `c`: the first that holds it, or the one it is least
    /// outside of (a point on a cut, or outside by rounding); `None` when
    /// `q` is not finite.
    #[inline]
    fn locate_in(&self, t: usize, c: usize, q: [f32; 2]) -> Option<(u32, [f32; 3])> {
        if !(q[0].is_finite() && q[1].is_finite()) {
            return None;
        }
        let cell = self.cells[c];
        if cell.first == NONE {
            // Only past the triangle's long side, by rounding.
            return Some(self.nearest(t, q));
        }
        let piece = &self.pieces[cell.first as usize];
        let w = piece.weights(q);
        let mut best_min = least(w);
        let mut best = (piece.triangle, w);
        if best_min >= 0.0 {
            return Some(best);
        }
        let second = (cell.second != NONE).then_some(cell.second);
        let rest = &self.entries[cell.rest as usize..self.cells[c + 1].rest as usize];
        for &k in second.iter().chain(rest) {
            let piece = &self.pieces[k as usize];
            let w = piece.weights(q);
            let min = least(w);
            if min > best_min {
                (best, best_min) = ((piece.triangle, w), min);
                if min >= 0.0 {
                    break;
                }
            }
        }
        Some(best)
    }

    /// The pieces of original triangle `t` (none when it was not split).
    fn pieces_of(&self, t: usize) -> &[Piece] {
        &self.pieces[self.spans[t] as usize..self.spans[t + 1] as usize]
    }

    /// The piece of original triangle `t` that `q` is least outside of,
    /// among all of them.
    #[cold]
    fn nearest(&self, t: usize, q: [f32; 2]) -> (u32, [f32; 3]) {
        let pieces = self.pieces_of(t);
        let mut best = (pieces[0].triangle, pieces[0].weights(q));
        for piece in &pieces[1..] {
            let w = piece.weights(q);
            if least(w) > least(best.1) {
                best = (piece.triangle, w);
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

    use rand::{Rng, SeedableRng, rngs::StdRng};

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

    #[test]
    fn each_subdivided_triangle_lies_in_its_original() {
        // By geometry: the original's barycentric weights of each piece's
        // centroid are within 0..=1 and reproduce it; and every original
        // triangle has a piece.
        let mesh = generate::cuboid(Vec3::new(1.0, 0.4, 2.0));
        for max_edge in [0.17, f32::NAN] {
            let (fine, map) = mesh.subdivided_with_map(max_edge);
            let originals = map.originals();
            assert_eq!(originals.len(), fine.triangle_count());
            let mut has_piece = vec![false; mesh.triangle_count()];
            for (tri, &t) in fine.triangles.iter().zip(&originals) {
                has_piece[t as usize] = true;
                let centroid = tri
                    .iter()
                    .map(|&i| fine.positions[i as usize])
                    .sum::<Vec3>()
                    / 3.0;
                let [a, b, c] = mesh.triangles[t as usize].map(|i| mesh.positions[i as usize]);
                let n = (b - a).cross(c - a);
                let w1 = (centroid - a).cross(c - a).dot(n) / n.length_squared();
                let w2 = (b - a).cross(centroid - a).dot(n) / n.length_squared();
                let w = [1.0 - w1 - w2, w1, w2];
                assert!(w.iter().all(|x| (-1e-5..=1.0 + 1e-5).contains(x)), "{w:?}");
                assert!((a * w[0] + b * w[1] + c * w[2]).distance(centroid) < 1e-5);
            }
            assert!(has_piece.iter().all(|&h| h));
        }
    }

    /// The pieces of original triangle `t` that hold `q` (all weights at
    /// least `-slack`), by testing every one of them.
    fn holders(map: &Subdivision, t: usize, q: [f32; 2], slack: f32) -> Vec<(u32, [f32; 3])> {
        map.pieces_of(t)
            .iter()
            .map(|p| (p.triangle, p.weights(q)))
            .filter(|(_, w)| least(*w) >= -slack)
            .collect()
    }

    #[test]
    fn locate_agrees_with_a_search_over_all_pieces() {
        // Random points, and points on the pieces' corners and edges (where
        // grid cells meet cuts), in triangles split a few times and many
        // times: the located piece is one that holds the point, every
        // piece holding it by a margin is the located one, and the point
        // comes back from the subdivided triangle's corners.
        let mut rng = StdRng::seed_from_u64(5);
        for (mesh, max_edge) in [
            (generate::cuboid(Vec3::new(1.0, 0.4, 2.0)), 0.6),
            (generate::cuboid(Vec3::new(1.0, 0.4, 2.0)), 0.05),
            (generate::uv_sphere(1.0, 6, 3), 0.07),
            (generate::cornell_box(), 0.2),
            (generate::cornell_box(), 0.02),
        ] {
            let (fine, map) = mesh.subdivided_with_map(max_edge);
            let mut points = Vec::new();
            let mut random_points = 0;
            for t in 0..mesh.triangle_count() {
                for _ in 0..400 {
                    random_points += 1;
                    let (mut a, mut b): (f32, f32) = (rng.random(), rng.random());
                    if a + b > 1.0 {
                        (a, b) = (1.0 - a, 1.0 - b);
                    }
                    points.push((t as u32, [1.0 - a - b, a, b]));
                }
                // The corners and edge midpoints of its pieces.
                for piece in map.pieces_of(t) {
                    let o = piece.origin;
                    points.push((t as u32, [1.0 - o[0] - o[1], o[0], o[1]]));
                }
            }
            let mut each = Vec::new();
            map.locate_each(&points, &mut each);
            assert_eq!(each.len(), points.len());
            let mut strict = 0;
            for (&(t, w), found) in points.iter().zip(&each) {
                let located = map.locate(t, w);
                assert_eq!(
                    located, *found,
                    "locate_each and locate differ at {t} {w:?}"
                );
                let (sub, u) = located.unwrap();
                let q = [w[1], w[2]];
                assert!(least(u) >= -1e-5, "{t} {w:?}: weights {u:?}");
                let all = holders(&map, t as usize, q, 1e-5);
                if map.grids[t as usize].0 == 0 {
                    // Not split: the weights as they are.
                    assert_eq!((sub, u), (map.grids[t as usize].1, w));
                } else {
                    assert!(
                        all.iter().any(|&(s, _)| s == sub),
                        "{t} {w:?}: {sub} holds it not"
                    );
                }
                for &(s, v) in &all {
                    if least(v) > 1e-4 {
                        strict += 1;
                        assert_eq!(s, sub, "{t} {w:?}: inside {s}, located in {sub}");
                        assert_eq!(v, u);
                    }
                }
                // The same point from the subdivided triangle.
                let [a, b, c] = mesh.triangles[t as usize].map(|i| mesh.positions[i as usize]);
                let want = w[0] * a + w[1] * b + w[2] * c;
                let [p, q, r] = fine.triangles[sub as usize].map(|i| fine.positions[i as usize]);
                let got = u[0] * p + u[1] * q + u[2] * r;
                assert!(got.distance(want) < 1e-5, "{t}: {got} vs {want}");
            }
            assert!(strict > random_points / 2, "{strict} of {random_points}");
        }
    }

    #[test]
    fn a_point_past_the_long_side_goes_to_the_nearest_piece() {
        // Cells beyond the long side (w1 + w2 = 1) of a triangle hold no
        // piece; a point there (outside by rounding) is found by the search
        // over all the triangle's pieces.
        let quad = generate::plane(1.0, 1);
        let (fine, map) = quad.subdivided_with_map(0.1);
        let (r, first) = map.grids[0];
        let r = r as usize;
        // The cell whose lower corner is on the long side.
        let (x, y) = (r / 2, r - r / 2);
        let c = first as usize + y * r + x;
        assert_eq!(map.cells[c].first, NONE);
        let (w1, w2) = (x as f32 / r as f32 + 1e-6, y as f32 / r as f32 + 1e-6);
        let w = [1.0 - w1 - w2, w1, w2];
        assert_eq!(map.cell(0, w), Some(c));
        let (sub, u) = map.locate(0, w).unwrap();
        let best = holders(&map, 0, [w1, w2], 1.0)
            .into_iter()
            .map(|(_, u)| least(u))
            .fold(f32::NEG_INFINITY, f32::max);
        assert_eq!(least(u), best);
        assert!(least(u) > -1e-4, "{u:?}");
        let [a, b, cc] = quad.triangles[0].map(|i| quad.positions[i as usize]);
        let want = w[0] * a + w[1] * b + w[2] * cc;
        let [p, q, s] = fine.triangles[sub as usize].map(|i| fine.positions[i as usize]);
        assert!((u[0] * p + u[1] * q + u[2] * s).distance(want) < 1e-5);
        // Not a point at all.
        assert_eq!(map.locate(0, [0.25, f32::NAN, 0.5]), None);
        assert_eq!(map.locate(0, [0.5, 0.25, f32::NAN]), None);
    }

    #[test]
    fn most_points_are_found_by_the_two_candidates_their_cell_holds() {
        // The grid's purpose: about two cells per piece, the piece holding
        // a cell's centre and one other in the cell itself, so that finding
        // a point usually reads its cell and those two pieces only.
        let room = generate::cornell_box();
        let (_, map) = room.subdivided_with_map(0.05);
        let mut rng = StdRng::seed_from_u64(7);
        let (mut first, mut total) = (0, 0);
        for t in 0..room.triangle_count() {
            for _ in 0..500 {
                let (a, b): (f32, f32) = (rng.random(), rng.random());
                let (a, b) = if a + b > 1.0 {
                    (1.0 - a, 1.0 - b)
                } else {
                    (a, b)
                };
                let c = map.cell(t as u32, [1.0 - a - b, a, b]).unwrap();
                let piece = &map.pieces[map.cells[c].first as usize];
                let second = map.cells[c].second;
                total += 1;
                first += usize::from(
                    least(piece.weights([a, b])) >= 0.0
                        || second != NONE
                            && least(map.pieces[second as usize].weights([a, b])) >= 0.0,
                );
            }
        }
        let cells = map.cells.len() as f64 / 2.0;
        let pieces = map.pieces.len() as f64;
        assert!(
            (cells / pieces - CELLS_PER_PIECE).abs() < 0.5,
            "{cells} cells, {pieces} pieces"
        );
        assert!(first * 100 > 85 * total, "{first} of {total}");
    }
}
