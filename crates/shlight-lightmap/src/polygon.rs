//! Small convex polygons in `f64`, clipped by Sutherland-Hodgman: against
//! the lines `x = c` and `y = c` (a triangle cut to a texel) and against a
//! triangle's edges (the overlap of two triangles).
//!
//! A point on the clipping line counts as inside; a vertex made where an
//! edge crosses an axis line takes the line's coordinate exactly, so a
//! polygon lying on the line clips to one of zero area, never a sliver.

use glam::{DVec2, Vec2Swizzles};

/// Enough for a triangle clipped by four lines (7 corners) or by another
/// triangle's three edges (6).
const CAPACITY: usize = 9;

/// A convex polygon of at most [`CAPACITY`] corners, in order.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Polygon {
    corners: [DVec2; CAPACITY],
    len: usize,
}

/// Which side of an axis line a clip keeps.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Keep {
    /// `x >= c`.
    XAbove(f64),
    /// `x <= c`.
    XBelow(f64),
    /// `y >= c`.
    YAbove(f64),
    /// `y <= c`.
    YBelow(f64),
}

impl Keep {
    fn inside(self, p: DVec2) -> bool {
        match self {
            Keep::XAbove(c) => p.x >= c,
            Keep::XBelow(c) => p.x <= c,
            Keep::YAbove(c) => p.y >= c,
            Keep::YBelow(c) => p.y <= c,
        }
    }

    /// Where the segment `a`-`b` (one end strictly on each side) crosses
    /// the line: interpolated from the end with the smaller coordinate
    /// across the line, so both directions of an edge give the same point.
    fn crossing(self, a: DVec2, b: DVec2) -> DVec2 {
        let (c, across) = match self {
            Keep::XAbove(c) | Keep::XBelow(c) => (c, true),
            Keep::YAbove(c) | Keep::YBelow(c) => (c, false),
        };
        let (a, b) = if across { (a, b) } else { (a.yx(), b.yx()) };
        let (lo, hi) = if a.x <= b.x { (a, b) } else { (b, a) };
        let t = (c - lo.x) / (hi.x - lo.x);
        let along = lo.y + t * (hi.y - lo.y);
        if across {
            DVec2::new(c, along)
        } else {
            DVec2::new(along, c)
        }
    }
}

impl Polygon {
    /// The triangle `a`, `b`, `c`.
    pub(crate) fn triangle(corners: [DVec2; 3]) -> Self {
        let mut p = Polygon {
            corners: [DVec2::ZERO; CAPACITY],
            len: 3,
        };
        p.corners[..3].copy_from_slice(&corners);
        p
    }

    fn empty() -> Self {
        Polygon {
            corners: [DVec2::ZERO; CAPACITY],
            len: 0,
        }
    }

    fn push(&mut self, p: DVec2) {
        // Convex input clipped by one line gains at most one corner; the
        // capacity covers every clip this crate makes.
        if self.len < CAPACITY {
            self.corners[self.len] = p;
            self.len += 1;
        }
    }

    /// The corners, in order.
    pub(crate) fn corners(&self) -> &[DVec2] {
        &self.corners[..self.len]
    }

    /// The part on the kept side of an axis line.
    pub(crate) fn clip(&self, keep: Keep) -> Self {
        let mut out = Polygon::empty();
        let n = self.len;
        for k in 0..n {
            let s = self.corners[(k + n - 1) % n];
            let e = self.corners[k];
            match (keep.inside(s), keep.inside(e)) {
                (true, true) => out.push(e),
                (false, true) => {
                    out.push(keep.crossing(s, e));
                    out.push(e);
                }
                (true, false) => out.push(keep.crossing(s, e)),
                (false, false) => {}
            }
        }
        out
    }

    /// The part on the left of the directed line through `a` and `b`
    /// (where `cross(b - a, p - a) >= 0`).
    pub(crate) fn clip_left_of(&self, a: DVec2, b: DVec2) -> Self {
        let d = b - a;
        let side = |p: DVec2| d.perp_dot(p - a);
        let mut out = Polygon::empty();
        let n = self.len;
        for k in 0..n {
            let s = self.corners[(k + n - 1) % n];
            let e = self.corners[k];
            let (ss, se) = (side(s), side(e));
            let cross = |out: &mut Polygon| {
                let t = ss / (ss - se);
                out.push(s + t * (e - s));
            };
            match (ss >= 0.0, se >= 0.0) {
                (true, true) => out.push(e),
                (false, true) => {
                    cross(&mut out);
                    out.push(e);
                }
                (true, false) => cross(&mut out),
                (false, false) => {}
            }
        }
        out
    }

    /// Twice the signed area (positive counter-clockwise in x right, y
    /// up) and the centroid, by a fan from the first corner; the
    /// centroid is `None` where the area is zero.
    pub(crate) fn area2_centroid(&self) -> (f64, Option<DVec2>) {
        let c = self.corners();
        if c.len() < 3 {
            return (0.0, None);
        }
        let o = c[0];
        let mut area2 = 0.0;
        let mut moment = DVec2::ZERO;
        for k in 1..c.len() - 1 {
            let (a, b) = (c[k] - o, c[k + 1] - o);
            let w = a.perp_dot(b);
            area2 += w;
            moment += w * (a + b);
        }
        if area2 == 0.0 {
            (0.0, None)
        } else {
            (area2, Some(o + moment / (3.0 * area2)))
        }
    }

    /// Twice the signed area.
    pub(crate) fn area2(&self) -> f64 {
        let c = self.corners();
        if c.len() < 3 {
            return 0.0;
        }
        let o = c[0];
        (1..c.len() - 1)
            .map(|k| (c[k] - o).perp_dot(c[k + 1] - o))
            .sum()
    }
}
