//! Independent geometry for the tests: the intersection of two convex
//! polygons built from their corners inside each other and their edges'
//! crossings (not by clipping), a separating-axis test, a point-in-triangle
//! test by orientations.

#![allow(dead_code)]

use glam::DVec2;

/// Twice the signed area of `a, b, c`.
pub fn orient(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    (b - a).perp_dot(c - a)
}

/// Whether `p` is inside the convex polygon `poly` (either winding), with
/// points within `eps` (in orientation units) of an edge counted in.
pub fn inside_convex(p: DVec2, poly: &[DVec2], eps: f64) -> bool {
    let n = poly.len();
    let sign = if polygon_area(poly) >= 0.0 { 1.0 } else { -1.0 };
    (0..n).all(|k| sign * orient(poly[k], poly[(k + 1) % n], p) >= -eps)
}

/// The signed area (shoelace).
pub fn polygon_area(poly: &[DVec2]) -> f64 {
    let n = poly.len();
    0.5 * (0..n)
        .map(|k| poly[k].perp_dot(poly[(k + 1) % n]))
        .sum::<f64>()
}

/// The area two convex polygons share: the corners of each inside the
/// other and the crossings of their edges, ordered by angle about their
/// mean, then the shoelace formula.
pub fn intersection_area(a: &[DVec2], b: &[DVec2]) -> f64 {
    let mut pts: Vec<DVec2> = Vec::new();
    pts.extend(a.iter().filter(|&&p| inside_convex(p, b, 0.0)));
    pts.extend(b.iter().filter(|&&p| inside_convex(p, a, 0.0)));
    for i in 0..a.len() {
        let (p, q) = (a[i], a[(i + 1) % a.len()]);
        for j in 0..b.len() {
            let (r, s) = (b[j], b[(j + 1) % b.len()]);
            let d = (q - p).perp_dot(s - r);
            if d == 0.0 {
                continue;
            }
            let t = (r - p).perp_dot(s - r) / d;
            let u = (r - p).perp_dot(q - p) / d;
            if (0.0..=1.0).contains(&t) && (0.0..=1.0).contains(&u) {
                pts.push(p + t * (q - p));
            }
        }
    }
    if pts.len() < 3 {
        return 0.0;
    }
    let centre = pts.iter().copied().sum::<DVec2>() / pts.len() as f64;
    pts.sort_by(|p, q| {
        let (a, b) = ((*p - centre).to_angle(), (*q - centre).to_angle());
        a.total_cmp(&b)
    });
    polygon_area(&pts).abs()
}

/// The texel square `(x, y)` as a polygon.
pub fn texel(x: u32, y: u32) -> [DVec2; 4] {
    let (x, y) = (f64::from(x), f64::from(y));
    [
        DVec2::new(x, y),
        DVec2::new(x + 1.0, y),
        DVec2::new(x + 1.0, y + 1.0),
        DVec2::new(x, y + 1.0),
    ]
}

/// Whether some axis (the square's two, the triangle's edge normals)
/// separates the triangle from the square by more than `margin`.
pub fn separated(tri: [DVec2; 3], square: &[DVec2; 4], margin: f64) -> bool {
    let mut axes = vec![DVec2::X, DVec2::Y];
    for k in 0..3 {
        axes.push((tri[(k + 1) % 3] - tri[k]).perp().normalize());
    }
    axes.iter().any(|&axis| {
        let span = |pts: &[DVec2]| {
            pts.iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                    let d = p.dot(axis);
                    (lo.min(d), hi.max(d))
                })
        };
        let (a0, a1) = span(&tri);
        let (b0, b1) = span(square);
        a1 < b0 - margin || b1 < a0 - margin
    })
}
