//! Whether the triangles of one mesh overlap in a UV set: a lightmap
//! needs every texel to belong to one place on the surface.
//!
//! The triangles' UV boxes go into a uniform grid (cells about the mean
//! box's size, at most about four per triangle), so each triangle is
//! tested only against those sharing a cell with it: near-linear in the
//! triangles for a mesh whose UVs are spread as an unwrap spreads them.
//! Two triangles overlap when their intersection, two triangles clipped
//! in `f64`, has more than [`OVERLAP_TOLERANCE`] of the smaller one's
//! area: triangles sharing an edge or a corner, or merely touching, do
//! not.

use glam::{DVec2, Vec2};
use rayon::prelude::*;
use std::fmt;

use crate::polygon::Polygon;
use crate::uv_error::UvError;
use crate::uv_triangles::{corners, is_degenerate};

/// The share of the smaller triangle's area two triangles must have in
/// common to overlap (far above the rounding of a shared edge, far below
/// any fold or duplicate).
pub const OVERLAP_TOLERANCE: f64 = 1e-4;

/// Two triangles of a mesh whose interiors overlap in UV space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UvOverlap {
    /// The lower triangle index.
    pub first: usize,
    /// The higher triangle index.
    pub second: usize,
    /// The area they share, in UV units.
    pub area: f64,
    /// That area as a fraction of the smaller triangle's.
    pub fraction: f64,
}

impl fmt::Display for UvOverlap {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "triangles {} and {} overlap in UV space ({:.1}% of the smaller one)",
            self.first,
            self.second,
            100.0 * self.fraction
        )
    }
}

/// A triangle ready for the test: corners counter-clockwise, its area,
/// its box.
struct Prepared {
    c: [DVec2; 3],
    area: f64,
    min: DVec2,
    max: DVec2,
}

/// The first pair of triangles (lowest `first`, then lowest `second`)
/// whose interiors overlap in the UVs, or `None`. Triangles of zero UV
/// area overlap nothing. The same pair at any thread count.
///
/// # Errors
/// An index past the UVs or a UV that is not finite (naming the triangle).
pub fn first_uv_overlap(
    uvs: &[Vec2],
    triangles: &[[u32; 3]],
) -> Result<Option<UvOverlap>, UvError> {
    let mut prepared: Vec<Option<Prepared>> = Vec::with_capacity(triangles.len());
    for t in 0..triangles.len() {
        let mut c = corners(uvs, triangles, t)?;
        if is_degenerate(c) {
            prepared.push(None);
            continue;
        }
        let area2 = (c[1] - c[0]).perp_dot(c[2] - c[0]);
        if area2 < 0.0 {
            c.swap(1, 2);
        }
        prepared.push(Some(Prepared {
            c,
            area: 0.5 * area2.abs(),
            min: c[0].min(c[1]).min(c[2]),
            max: c[0].max(c[1]).max(c[2]),
        }));
    }
    let Some(grid) = Grid::new(&prepared) else {
        return Ok(None);
    };
    let found = (0..prepared.len()).into_par_iter().find_map_first(|a| {
        let pa = prepared[a].as_ref()?;
        let mut candidates = Vec::new();
        grid.cells.visit(pa.min, pa.max, |cell| {
            candidates.extend(
                grid.cell(cell)
                    .iter()
                    .map(|&b| b as usize)
                    .filter(|&b| b > a),
            );
        });
        candidates.sort_unstable();
        candidates.dedup();
        candidates.into_iter().find_map(|b| {
            let pb = prepared[b].as_ref()?;
            if pa.max.cmple(pb.min).any() || pb.max.cmple(pa.min).any() {
                return None;
            }
            let area = 0.5 * intersection_area2(pa.c, pb.c);
            let fraction = area / pa.area.min(pb.area);
            (fraction > OVERLAP_TOLERANCE).then_some(UvOverlap {
                first: a,
                second: b,
                area,
                fraction,
            })
        })
    });
    Ok(found)
}

/// Twice the area two counter-clockwise triangles share: `a` clipped by
/// each edge of `b`.
fn intersection_area2(a: [DVec2; 3], b: [DVec2; 3]) -> f64 {
    let mut p = Polygon::triangle(a);
    for k in 0..3 {
        p = p.clip_left_of(b[k], b[(k + 1) % 3]);
        if p.corners().len() < 3 {
            return 0.0;
        }
    }
    p.area2().abs()
}

/// The cells of a uniform grid: where a box lands in it.
#[derive(Clone, Copy)]
struct Cells {
    origin: DVec2,
    inv_cell: f64,
    nx: usize,
    ny: usize,
}

impl Cells {
    /// Calls `f` with each cell the box from `min` to `max` touches.
    fn visit(self, min: DVec2, max: DVec2, mut f: impl FnMut(usize)) {
        let at = |v: f64, n: usize| ((v * self.inv_cell).floor().max(0.0) as usize).min(n - 1);
        let (lo, hi) = (min - self.origin, max - self.origin);
        let (x0, x1) = (at(lo.x, self.nx), at(hi.x, self.nx));
        let (y0, y1) = (at(lo.y, self.ny), at(hi.y, self.ny));
        for y in y0..=y1 {
            for x in x0..=x1 {
                f(y * self.nx + x);
            }
        }
    }
}

/// A uniform grid over the triangles' UV boxes, each cell listing the
/// triangles whose box touches it (compressed rows).
struct Grid {
    cells: Cells,
    starts: Vec<usize>,
    entries: Vec<u32>,
}

impl Grid {
    /// `None` where no triangle has area.
    fn new(prepared: &[Option<Prepared>]) -> Option<Grid> {
        let boxes = || prepared.iter().flatten();
        let count = boxes().count();
        if count == 0 {
            return None;
        }
        let origin = boxes().fold(DVec2::INFINITY, |m, p| m.min(p.min));
        let top = boxes().fold(DVec2::NEG_INFINITY, |m, p| m.max(p.max));
        let extent = (top - origin).max(DVec2::splat(f64::MIN_POSITIVE));
        let mean = boxes().map(|p| (p.max - p.min).max_element()).sum::<f64>() / count as f64;
        // Cells of the mean box's size, but no more than about four per
        // triangle (a few far-flung triangles must not make the grid huge).
        let most = 4.0 * count as f64 + 16.0;
        let mut cell = mean.max(extent.max_element() * 1e-6);
        if (extent.x / cell).ceil() * (extent.y / cell).ceil() > most {
            cell = (extent.x * extent.y / most)
                .sqrt()
                .max(extent.max_element() / most);
        }
        let side = |e: f64| ((e / cell).ceil() as usize).clamp(1, 1 << 16);
        let cells = Cells {
            origin,
            inv_cell: 1.0 / cell,
            nx: side(extent.x),
            ny: side(extent.y),
        };
        // Counts per cell, then their running sums: where each cell starts.
        let mut starts = vec![0usize; cells.nx * cells.ny + 1];
        for p in boxes() {
            cells.visit(p.min, p.max, |c| starts[c] += 1);
        }
        let mut total = 0usize;
        for s in starts.iter_mut() {
            let n = *s;
            *s = total;
            total += n;
        }
        let mut entries = vec![0u32; total];
        let mut fill = starts.clone();
        for (t, p) in prepared.iter().enumerate() {
            if let Some(p) = p {
                cells.visit(p.min, p.max, |c| {
                    entries[fill[c]] = t as u32;
                    fill[c] += 1;
                });
            }
        }
        Some(Grid {
            cells,
            starts,
            entries,
        })
    }

    /// The triangles listed in a cell.
    fn cell(&self, c: usize) -> &[u32] {
        &self.entries[self.starts[c]..self.starts[c + 1]]
    }
}
