//! Cube faces: the OpenGL / Vulkan / D3D sampling convention, where each
//! face sits in a cross or strip image, and the exact solid angle of a texel.

use core::fmt;

use glam::DVec3;

/// One face of the cube map, in the order of a strip image and of six face
/// files: `+X -X +Y -Y +Z -Z` ([`CubeFace::ALL`]).
///
/// Face coordinates follow the OpenGL / Vulkan / D3D cube-map sampling rule
/// in the map's own y-up frame. For a direction `r` with major axis `ma`
/// (the component of largest magnitude):
///
/// | face | `sc` | `tc` | point [`CubeFace::point`]`(sc, tc)` |
/// |---|---|---|---|
/// | `+X` | `-rz/abs(ma)` | `-ry/abs(ma)` | `( 1, -tc, -sc)` |
/// | `-X` | `+rz/abs(ma)` | `-ry/abs(ma)` | `(-1, -tc,  sc)` |
/// | `+Y` | `+rx/abs(ma)` | `+rz/abs(ma)` | `(sc,   1,  tc)` |
/// | `-Y` | `+rx/abs(ma)` | `-rz/abs(ma)` | `(sc,  -1, -tc)` |
/// | `+Z` | `+rx/abs(ma)` | `-ry/abs(ma)` | `(sc, -tc,   1)` |
/// | `-Z` | `-rx/abs(ma)` | `-ry/abs(ma)` | `(-sc, -tc, -1)` |
///
/// `s = (sc + 1)/2` runs left to right and `t = (tc + 1)/2` top to bottom of
/// the face image, so texel `(i, j)` of an `f x f` face has its centre at
/// `sc = (2i + 1)/f - 1`, `tc = (2j + 1)/f - 1`. Seen from the cube's
/// centre, every face is upright the way a y-up viewer expects: the top row
/// of `+X`, `-X`, `+Z`, `-Z` is toward `+Y`, the top row of `+Y` toward
/// `-Z`, the top row of `-Y` toward `+Z`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CubeFace {
    /// The face the `+X` axis pierces.
    PosX,
    /// The face the `-X` axis pierces.
    NegX,
    /// The face the `+Y` axis pierces.
    PosY,
    /// The face the `-Y` axis pierces.
    NegY,
    /// The face the `+Z` axis pierces.
    PosZ,
    /// The face the `-Z` axis pierces.
    NegZ,
}

impl CubeFace {
    /// The six faces in strip and face-file order: `+X -X +Y -Y +Z -Z`
    /// (the OpenGL `GL_TEXTURE_CUBE_MAP_POSITIVE_X + i` order).
    pub const ALL: [CubeFace; 6] = [
        CubeFace::PosX,
        CubeFace::NegX,
        CubeFace::PosY,
        CubeFace::NegY,
        CubeFace::PosZ,
        CubeFace::NegZ,
    ];

    /// The outward unit axis through the face's centre, e.g. `(0, 0, -1)`
    /// for [`CubeFace::NegZ`].
    #[must_use]
    pub fn axis(self) -> DVec3 {
        match self {
            CubeFace::PosX => DVec3::X,
            CubeFace::NegX => DVec3::NEG_X,
            CubeFace::PosY => DVec3::Y,
            CubeFace::NegY => DVec3::NEG_Y,
            CubeFace::PosZ => DVec3::Z,
            CubeFace::NegZ => DVec3::NEG_Z,
        }
    }

    /// The point of the face's plane (at distance 1 from the centre) with
    /// face coordinates `(sc, tc)`, `sc, tc` in `[-1, 1]` on the face (see
    /// the table on [`CubeFace`]); not normalised. Values outside `[-1, 1]`
    /// extend the plane beyond the face (used to find neighbours across a
    /// seam). Inverse of [`CubeFace::from_direction`] on the face.
    #[must_use]
    pub fn point(self, sc: f64, tc: f64) -> DVec3 {
        match self {
            CubeFace::PosX => DVec3::new(1.0, -tc, -sc),
            CubeFace::NegX => DVec3::new(-1.0, -tc, sc),
            CubeFace::PosY => DVec3::new(sc, 1.0, tc),
            CubeFace::NegY => DVec3::new(sc, -1.0, -tc),
            CubeFace::PosZ => DVec3::new(sc, -tc, 1.0),
            CubeFace::NegZ => DVec3::new(-sc, -tc, -1.0),
        }
    }

    /// The face that direction `d` hits and its face coordinates
    /// `(sc, tc)` in `[-1, 1]` (table on [`CubeFace`]). The major axis is the
    /// component of largest magnitude; ties go to X before Y before Z, and a
    /// zero component counts as positive. `d` need not be unit length.
    ///
    /// Precondition: `d` is finite and non-zero (else the coordinates are NaN).
    #[must_use]
    pub fn from_direction(d: DVec3) -> (CubeFace, f64, f64) {
        let a = d.abs();
        if a.x >= a.y && a.x >= a.z {
            if d.x >= 0.0 {
                (CubeFace::PosX, -d.z / a.x, -d.y / a.x)
            } else {
                (CubeFace::NegX, d.z / a.x, -d.y / a.x)
            }
        } else if a.y >= a.z {
            if d.y >= 0.0 {
                (CubeFace::PosY, d.x / a.y, d.z / a.y)
            } else {
                (CubeFace::NegY, d.x / a.y, -d.z / a.y)
            }
        } else if d.z >= 0.0 {
            (CubeFace::PosZ, d.x / a.z, -d.y / a.z)
        } else {
            (CubeFace::NegZ, -d.x / a.z, -d.y / a.z)
        }
    }

    /// The face's position in [`CubeFace::ALL`] (0 for `+X` … 5 for `-Z`).
    #[must_use]
    pub fn index(self) -> usize {
        self as usize
    }
}

impl fmt::Display for CubeFace {
    /// `+X`, `-X`, `+Y`, `-Y`, `+Z` or `-Z`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            CubeFace::PosX => "+X",
            CubeFace::NegX => "-X",
            CubeFace::PosY => "+Y",
            CubeFace::NegY => "-Y",
            CubeFace::PosZ => "+Z",
            CubeFace::NegZ => "-Z",
        })
    }
}

/// Where a face sits in a cross or strip image: the cell in column `col`,
/// row `row` of the layout's grid of `f x f` cells (texels
/// `col*f .. (col+1)*f` by `row*f .. (row+1)*f`).
///
/// When `rotated` is true the face is stored turned by 180 degrees (the
/// `-Z` face of the vertical cross): face texel `(i, j)` is cell texel
/// `(f-1-i, f-1-j)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct FaceCell {
    /// Column of the cell in the grid, from the left.
    pub col: usize,
    /// Row of the cell in the grid, from the top.
    pub row: usize,
    /// The face is stored turned by 180 degrees.
    pub rotated: bool,
}

/// Exact solid angle of texel `(i, j)` of an `f x f` cube face
/// (`f = face_size`, either face orientation: the value is symmetric).
///
/// The texel is the rectangle `[x0, x1] x [y0, y1]` of face coordinates,
/// `x0 = 2i/f - 1`, `x1 = 2(i+1)/f - 1` (same for `y` with `j`), on the
/// plane at distance 1. Its solid angle equals the reference closed form
/// `A(x0,y0) - A(x0,y1) - A(x1,y0) + A(x1,y1)`,
/// `A(x, y) = atan2(x y, sqrt(x^2 + y^2 + 1))`, but that difference of
/// `O(1)` terms loses relative accuracy `~1e-16 f^2` on small texels
/// (`~1e-9` at `f = 2048`). shlight evaluates the same quantity as two
/// spherical triangles by Van Oosterom & Strackee (IEEE Trans. Biomed. Eng.
/// 30, 1983): for corners `a, b, c` (not normalised)
/// `tan(Ω/2) = det[a b c] / (|a||b||c| + (a.b)|c| + (a.c)|b| + (b.c)|a|)`,
/// where `det = (x1 - x0)(y1 - y0)` exactly and every term of the
/// denominator is positive, so the result is accurate to a few ulps
/// relative. The `6 f^2` texels sum to `4π` (to `1e-13` measured at
/// `f = 512`).
///
/// Panics (debug) unless `i, j < face_size`.
#[must_use]
pub fn cube_texel_solid_angle(i: usize, j: usize, face_size: usize) -> f64 {
    debug_assert!(i < face_size && j < face_size, "texel outside the face");
    let f = face_size as f64;
    let edge = |k: usize| (2.0 * k as f64 - f) / f;
    rectangle_solid_angle(edge(i), edge(i + 1), edge(j), edge(j + 1))
}

/// Solid angle of the rectangle `[x0, x1] x [y0, y1]` of the plane `z = 1`
/// seen from the origin, as two Van Oosterom-Strackee triangles.
pub(super) fn rectangle_solid_angle(x0: f64, x1: f64, y0: f64, y1: f64) -> f64 {
    let det = (x1 - x0) * (y1 - y0);
    let p00 = DVec3::new(x0, y0, 1.0);
    let p10 = DVec3::new(x1, y0, 1.0);
    let p11 = DVec3::new(x1, y1, 1.0);
    let p01 = DVec3::new(x0, y1, 1.0);
    triangle_solid_angle(det, p00, p10, p11) + triangle_solid_angle(det, p00, p11, p01)
}

/// `2 atan2(det, |a||b||c| + (a.b)|c| + (a.c)|b| + (b.c)|a|)` for a
/// positively oriented triangle `a, b, c` with `det[a b c] = det`.
fn triangle_solid_angle(det: f64, a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let (la, lb, lc) = (a.length(), b.length(), c.length());
    let denominator = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    2.0 * det.atan2(denominator)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The reference corner form, for comparison.
    fn corner_form(x0: f64, x1: f64, y0: f64, y1: f64) -> f64 {
        let a = |x: f64, y: f64| (x * y).atan2((x * x + y * y + 1.0).sqrt());
        a(x0, y0) - a(x0, y1) - a(x1, y0) + a(x1, y1)
    }

    #[test]
    fn triangles_match_the_corner_form() {
        for f in [1usize, 2, 3, 7, 64] {
            for j in 0..f {
                for i in 0..f {
                    let e = |k: usize| (2.0 * k as f64 - f as f64) / f as f64;
                    let want = corner_form(e(i), e(i + 1), e(j), e(j + 1));
                    let got = cube_texel_solid_angle(i, j, f);
                    assert!(
                        (got - want).abs() < 1e-15,
                        "f {f} ({i},{j}): {got} vs {want}"
                    );
                }
            }
        }
        // One face is a sixth of the sphere.
        assert!(
            (cube_texel_solid_angle(0, 0, 1) - 4.0 * core::f64::consts::PI / 6.0).abs() < 1e-15
        );
    }

    #[test]
    fn from_direction_inverts_point() {
        for face in CubeFace::ALL {
            for (sc, tc) in [(0.0, 0.0), (0.3, -0.7), (-0.99, 0.99), (0.5, 0.25)] {
                let p = face.point(sc, tc);
                let (g, s, t) = CubeFace::from_direction(p * 3.5);
                assert_eq!(g, face);
                assert!((s - sc).abs() < 1e-15 && (t - tc).abs() < 1e-15, "{face}");
            }
            assert_eq!(CubeFace::from_direction(face.axis()).0, face);
            assert_eq!(CubeFace::ALL[face.index()], face);
        }
    }
}
