//! UV seams: one edge of a surface laid out twice in a lightmap, once in
//! each of two charts. Left alone, the two sides are filtered from
//! different texels and show a line; stitched ([`stitch_seams`]), the
//! texels along both sides are changed as little as possible so that a
//! bilinear read gives the same value on both.

use glam::{DVec2, Vec3};
use std::collections::HashMap;

/// A seam: an edge from `a[0]` to `a[1]` in one chart and from `b[0]` to
/// `b[1]` in the other (the same 3D edge, end for end), in texel
/// coordinates of the atlas (texel `(x, y)` spans `[x, x + 1] x [y, y +
/// 1]`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Seam {
    /// The edge's ends in the first chart.
    pub a: [DVec2; 2],
    /// The same ends in the second chart.
    pub b: [DVec2; 2],
}

/// One corner of a triangle as [`find_seams`] reads it: its position in
/// the mesh's own space (corners at the same point share it bit for bit,
/// as a mesh split along its seams keeps them), its normal, and its place
/// in the atlas in texel coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SeamCorner {
    /// Position in the mesh's space.
    pub position: Vec3,
    /// Unit normal.
    pub normal: Vec3,
    /// Texel coordinates in the atlas.
    pub texel: DVec2,
}

/// The seams of a mesh's triangles (three [`SeamCorner`]s each): edges
/// whose two ends are met by exactly two triangles at different places of
/// the atlas, where the surface is smooth (the normals at each end agree
/// within `1 - cos` of [`SMOOTH_COS`]): across a hard edge the light may
/// differ, and is left alone.
#[must_use]
pub fn find_seams(triangles: &[[SeamCorner; 3]]) -> Vec<Seam> {
    let key = |p: Vec3| p.to_array().map(f32::to_bits);
    let mut edges: HashMap<EdgeKey, Vec<(SeamCorner, SeamCorner)>> = HashMap::new();
    for t in triangles {
        for i in 0..3 {
            let (p, q) = (t[i], t[(i + 1) % 3]);
            let (kp, kq) = (key(p.position), key(q.position));
            if kp == kq {
                continue;
            }
            // Each edge stored from its lower end.
            let entry = if kp < kq { (p, q) } else { (q, p) };
            edges
                .entry((kp.min(kq), kp.max(kq)))
                .or_default()
                .push(entry);
        }
    }
    let mut keys: Vec<_> = edges.keys().copied().collect();
    keys.sort_unstable();
    let mut seams = Vec::new();
    for k in keys {
        let sides = &edges[&k];
        let [(a0, a1), (b0, b1)] = sides.as_slice() else {
            continue;
        };
        let apart = |p: DVec2, q: DVec2| (p - q).length() > 1e-6;
        if !apart(a0.texel, b0.texel) && !apart(a1.texel, b1.texel) {
            continue;
        }
        let smooth = |p: &SeamCorner, q: &SeamCorner| p.normal.dot(q.normal) >= SMOOTH_COS;
        if !smooth(a0, b0) || !smooth(a1, b1) {
            continue;
        }
        seams.push(Seam {
            a: [a0.texel, a1.texel],
            b: [b0.texel, b1.texel],
        });
    }
    seams
}

/// An edge by its two ends' positions (bit patterns, the lower first).
type EdgeKey = ([u32; 3], [u32; 3]);

/// Normals whose dot product is at least this are one smooth surface.
pub const SMOOTH_COS: f32 = 0.999;

/// Sweeps of [`stitch_seams`] over every seam sample.
pub const STITCH_SWEEPS: usize = 64;

/// The four texels a bilinear read at `p` (texel coordinates) weighs, and
/// their weights: texel centres at `x + 1/2`, clamped at the grid's edge.
pub(crate) fn footprint(p: DVec2, side: usize) -> [(usize, f64); 4] {
    let at = p - 0.5;
    let (x0, y0) = (at.x.floor(), at.y.floor());
    let (fx, fy) = (at.x - x0, at.y - y0);
    let max = side as i64 - 1;
    let index = |dx: i64, dy: i64| {
        let x = (x0 as i64 + dx).clamp(0, max) as usize;
        let y = (y0 as i64 + dy).clamp(0, max) as usize;
        y * side + x
    };
    [
        (index(0, 0), (1.0 - fx) * (1.0 - fy)),
        (index(1, 0), fx * (1.0 - fy)),
        (index(0, 1), (1.0 - fx) * fy),
        (index(1, 1), fx * fy),
    ]
}

/// Stitches `seams` in a `side x side` grid of texels (row by row; `None`
/// texels take no part): each seam is sampled at two points per texel of
/// its length (at least two), and [`STITCH_SWEEPS`] sweeps of Kaczmarz's
/// method project the texels onto each sample's constraint "the bilinear
/// read on side a equals the read on side b" in turn, which from the
/// baked texels converges to the smallest change (in the least-squares
/// sense) that makes every sample agree. Returns the largest difference
/// between the two sides over the samples before and after, in the
/// texels' first component.
pub fn stitch_seams<const N: usize>(
    texels: &mut [Option<[f64; N]>],
    side: usize,
    seams: &[Seam],
) -> (f64, f64) {
    // Each sample's two footprints, with the texels that have light.
    let mut samples: Vec<Vec<(usize, f64)>> = Vec::new();
    for s in seams {
        let length = (s.a[1] - s.a[0]).length().max((s.b[1] - s.b[0]).length());
        let count = ((2.0 * length).ceil() as usize).max(2);
        for k in 0..count {
            let t = (k as f64 + 0.5) / count as f64;
            let pa = s.a[0].lerp(s.a[1], t);
            let pb = s.b[0].lerp(s.b[1], t);
            // Side a with positive weights, side b with negative: the
            // constraint is sum w x = 0.
            let mut terms: Vec<(usize, f64)> = Vec::with_capacity(8);
            for (i, w) in footprint(pa, side) {
                terms.push((i, w));
            }
            for (i, w) in footprint(pb, side) {
                terms.push((i, -w));
            }
            terms.retain(|&(i, w)| w != 0.0 && texels[i].is_some());
            // Merge repeated texels (a seam's two sides can share one).
            terms.sort_by_key(|t| t.0);
            terms.dedup_by(|later, first| {
                if later.0 == first.0 {
                    first.1 += later.1;
                    true
                } else {
                    false
                }
            });
            if terms.iter().any(|t| t.1.abs() > 1e-12) {
                samples.push(terms);
            }
        }
    }
    let gap = |texels: &[Option<[f64; N]>]| {
        samples
            .iter()
            .map(|terms| {
                terms
                    .iter()
                    .map(|&(i, w)| w * texels[i].map_or(0.0, |t| t[0]))
                    .sum::<f64>()
                    .abs()
            })
            .fold(0.0f64, f64::max)
    };
    let before = gap(texels);
    for _ in 0..STITCH_SWEEPS {
        for terms in &samples {
            let norm: f64 = terms.iter().map(|t| t.1 * t.1).sum();
            if norm <= 0.0 {
                continue;
            }
            let mut residual = [0.0f64; N];
            for &(i, w) in terms {
                let t = texels[i].expect("only texels with light");
                for (r, v) in residual.iter_mut().zip(t) {
                    *r += w * v;
                }
            }
            for &(i, w) in terms {
                let t = texels[i].as_mut().expect("only texels with light");
                for (v, r) in t.iter_mut().zip(residual) {
                    *v -= w * r / norm;
                }
            }
        }
    }
    (before, gap(texels))
}
