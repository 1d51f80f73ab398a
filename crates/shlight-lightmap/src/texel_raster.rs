//! Conservative rasterisation of a mesh's UV triangles onto a lightmap's
//! texels: which triangle each texel belongs to, where inside that
//! triangle it is sampled, and how much of it the mesh covers.
//!
//! Texel coordinates: UV `(u, v)` lands at `(u W, v H)` on a `W x H`
//! grid; texel `(x, y)` is the square `[x, x + 1] x [y, y + 1]`; row
//! `y = 0` holds `v` from 0 to `1 / H`. glTF's UV origin is the image's
//! top-left corner, so row 0 is the image's first row: no flip. A
//! triangle is cut to each texel its bounding box touches (a strip of
//! rows first, then each texel of the strip) by Sutherland-Hodgman, in
//! `f64`; every texel the triangle overlaps with positive area gets a
//! piece, however thin (conservative), and none that it only touches
//! along an edge or at a corner.
//!
//! The grid is worked in bands of rows in parallel, each band going
//! through the triangles that reach it in index order: the same texels at
//! any thread count, and no more than the texels themselves held for the
//! whole grid (24 bytes each).

use glam::{DVec2, Vec2};
use rayon::prelude::*;
use std::ops::Range;

use crate::placement::Placement;
use crate::polygon::{Keep, Polygon};
use crate::uv_error::UvError;
use crate::uv_triangles::{corners, is_degenerate};

/// The largest width or height of a lightmap (the largest 2D texture
/// GPUs commonly allow).
pub const MAX_SIDE: u32 = 16384;

/// The part of a triangle inside one texel, in texel coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TexelPiece {
    /// The texel's column.
    pub x: u32,
    /// The texel's row.
    pub y: u32,
    /// The piece's area, as a fraction of the texel (`(0, 1]`).
    pub area: f64,
    /// The piece's centroid, in texel coordinates (inside the texel and
    /// the triangle).
    pub centroid: DVec2,
}

/// Visits every texel of a `width x height` grid that the triangle with
/// corners `corners` (texel coordinates, either winding) overlaps with
/// positive area, row by row, with the part of the triangle inside it.
/// The work grows with the texels the triangle's bounding box touches,
/// clipped to the grid; parts outside the grid are dropped. A triangle
/// with a corner that is not finite has no pieces.
pub fn texel_pieces(corners: [DVec2; 3], width: u32, height: u32, visit: impl FnMut(TexelPiece)) {
    pieces_in_rows(corners, width, 0..height, visit);
}

/// [`texel_pieces`] in the rows `rows` only.
fn pieces_in_rows(
    corners: [DVec2; 3],
    width: u32,
    rows: Range<u32>,
    mut visit: impl FnMut(TexelPiece),
) {
    if !corners.iter().all(|c| c.is_finite()) {
        return;
    }
    let min = corners[0].min(corners[1]).min(corners[2]);
    let max = corners[0].max(corners[1]).max(corners[2]);
    let span = |lo: f64, hi: f64, n: u32| {
        let n = f64::from(n);
        (
            lo.floor().clamp(0.0, n) as u32,
            hi.ceil().clamp(0.0, n) as u32,
        )
    };
    let (y0, y1) = span(min.y, max.y, rows.end);
    let (y0, y1) = (y0.max(rows.start), y1.max(rows.start));
    let triangle = Polygon::triangle(corners);
    for y in y0..y1 {
        let row = f64::from(y);
        let strip = triangle
            .clip(Keep::YAbove(row))
            .clip(Keep::YBelow(row + 1.0));
        let c = strip.corners();
        if c.len() < 3 {
            continue;
        }
        let lo = c.iter().fold(f64::INFINITY, |m, p| m.min(p.x));
        let hi = c.iter().fold(f64::NEG_INFINITY, |m, p| m.max(p.x));
        let (x0, x1) = span(lo, hi, width);
        for x in x0..x1 {
            let col = f64::from(x);
            let piece = strip.clip(Keep::XAbove(col)).clip(Keep::XBelow(col + 1.0));
            if let (area2, Some(centroid)) = piece.area2_centroid() {
                visit(TexelPiece {
                    x,
                    y,
                    area: 0.5 * area2.abs(),
                    centroid,
                });
            }
        }
    }
}

/// Rows per band: the raster's unit of parallel work.
const BAND: u32 = 16;

/// The bands of rows a triangle's bounding box overlaps.
fn band_span(p: [DVec2; 3], height: u32) -> Range<usize> {
    let lo = p[0].y.min(p[1].y).min(p[2].y);
    let hi = p[0].y.max(p[1].y).max(p[2].y);
    let h = f64::from(height);
    let first = lo.floor().clamp(0.0, h) as u32;
    let end = hi.ceil().clamp(0.0, h) as u32;
    if end <= first {
        return 0..0;
    }
    (first / BAND) as usize..end.div_ceil(BAND) as usize
}

/// What a covered texel holds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TexelSample {
    /// The triangle that overlaps the texel most (the lowest index among
    /// equals): the texel's owner.
    pub triangle: u32,
    /// The barycentric weights, in the order of the triangle's corners,
    /// of the centroid of the owner's part of the texel: a point inside
    /// both the triangle and the texel, where the texel is sampled.
    pub weights: [f32; 3],
    /// The fraction of the texel the mesh covers: the overlap areas of
    /// every triangle summed (overlapping triangles count twice), at most
    /// 1.
    pub coverage: f32,
}

/// A mesh's UV triangles rasterised onto a lightmap's texels.
#[derive(Clone, Debug)]
pub struct TexelRaster {
    width: u32,
    height: u32,
    texels: Vec<Option<TexelSample>>,
    degenerate: usize,
    outside: usize,
}

impl TexelRaster {
    /// Rasterises the triangles (indices into `uvs`) onto a `width x
    /// height` grid, their UVs first moved by `placement` where given.
    /// Triangles of zero UV area (collinear corners, to rounding) are
    /// skipped and counted ([`TexelRaster::degenerate_triangles`]).
    ///
    /// # Errors
    /// A side of 0 or over [`MAX_SIDE`]; a placement that is not finite
    /// (or takes a UV out of range of `f64`); an index past the UVs; a UV
    /// that is not finite (the error names the triangle).
    pub fn new(
        uvs: &[Vec2],
        triangles: &[[u32; 3]],
        placement: Option<Placement>,
        width: u32,
        height: u32,
    ) -> Result<Self, UvError> {
        if width == 0 || height == 0 || width > MAX_SIDE || height > MAX_SIDE {
            return Err(UvError::GridSize {
                width,
                height,
                max_side: MAX_SIDE,
            });
        }
        let placement = placement.unwrap_or_default();
        if !placement.is_finite() {
            return Err(UvError::NonFinitePlacement);
        }
        let size = DVec2::new(f64::from(width), f64::from(height));
        // Every triangle's corners in texel coordinates (None: degenerate),
        // and the bands of rows each one touches.
        let (mut degenerate, mut outside) = (0, 0);
        let mut placed: Vec<Option<[DVec2; 3]>> = Vec::with_capacity(triangles.len());
        let bands = height.div_ceil(BAND) as usize;
        let mut band_count = vec![0usize; bands + 1];
        for t in 0..triangles.len() {
            let p = corners(uvs, triangles, t)?.map(|uv| placement.apply(uv) * size);
            if !p.iter().all(|c| c.is_finite()) {
                return Err(UvError::NonFinitePlacement);
            }
            if is_degenerate(p) {
                degenerate += 1;
                placed.push(None);
                continue;
            }
            if p.iter()
                .any(|c| c.cmplt(DVec2::ZERO).any() || c.cmpgt(size).any())
            {
                outside += 1;
            }
            for b in band_span(p, height) {
                band_count[b] += 1;
            }
            placed.push(Some(p));
        }
        // Each band's triangles, in index order (compressed rows).
        let mut starts = band_count;
        let mut total = 0;
        for s in starts.iter_mut() {
            let n = *s;
            *s = total;
            total += n;
        }
        let mut listed = vec![0u32; total];
        let mut fill = starts.clone();
        for (t, p) in placed.iter().enumerate() {
            if let Some(p) = p {
                for b in band_span(*p, height) {
                    listed[fill[b]] = t as u32;
                    fill[b] += 1;
                }
            }
        }
        // The bands in parallel, each with its own running sums: the same
        // texels at any thread count (each band's triangles in order).
        let w = width as usize;
        let mut texels: Vec<Option<TexelSample>> = vec![None; w * height as usize];
        texels
            .par_chunks_mut(w * BAND as usize)
            .enumerate()
            .for_each(|(b, out)| {
                let first = b as u32 * BAND;
                let rows = first..(first + BAND).min(height);
                let mut best = vec![0.0f64; out.len()];
                let mut sum = vec![0.0f64; out.len()];
                for &t in &listed[starts[b]..starts[b + 1]] {
                    let Some(p) = placed[t as usize] else {
                        continue;
                    };
                    let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
                    let inv = 1.0 / e1.perp_dot(e2);
                    pieces_in_rows(p, width, rows.clone(), |piece| {
                        let k = (piece.y - first) as usize * w + piece.x as usize;
                        sum[k] += piece.area;
                        if piece.area > best[k] {
                            best[k] = piece.area;
                            let d = piece.centroid - p[0];
                            let w1 = d.perp_dot(e2) * inv;
                            let w2 = e1.perp_dot(d) * inv;
                            out[k] = Some(TexelSample {
                                triangle: t,
                                weights: [(1.0 - w1 - w2) as f32, w1 as f32, w2 as f32],
                                coverage: 0.0,
                            });
                        }
                    });
                }
                for (texel, s) in out.iter_mut().zip(&sum) {
                    if let Some(texel) = texel {
                        texel.coverage = s.min(1.0) as f32;
                    }
                }
            });
        Ok(TexelRaster {
            width,
            height,
            texels,
            degenerate,
            outside,
        })
    }

    /// The grid's width in texels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// The grid's height in texels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Texel `(x, y)`: `None` where no triangle overlaps it (or outside
    /// the grid).
    pub fn get(&self, x: u32, y: u32) -> Option<&TexelSample> {
        if x >= self.width || y >= self.height {
            return None;
        }
        self.texels[y as usize * self.width as usize + x as usize].as_ref()
    }

    /// Every texel, row by row (texel `(x, y)` at `y * width + x`).
    pub fn texels(&self) -> &[Option<TexelSample>] {
        &self.texels
    }

    /// How many texels a triangle overlaps.
    pub fn covered_texels(&self) -> usize {
        self.texels.iter().filter(|t| t.is_some()).count()
    }

    /// How many triangles were skipped for having no UV area.
    pub fn degenerate_triangles(&self) -> usize {
        self.degenerate
    }

    /// How many triangles reach outside the unit square (after the
    /// placement); their parts outside are dropped.
    pub fn triangles_outside(&self) -> usize {
        self.outside
    }
}
