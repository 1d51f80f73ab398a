//! A triangle's UV corners read from a mesh's UVs and indices, checked:
//! every index in range, every UV finite.

use glam::{DVec2, Vec2};

use crate::uv_error::UvError;

/// The UVs of triangle `t`'s corners, widened to `f64`.
pub(crate) fn corners(
    uvs: &[Vec2],
    triangles: &[[u32; 3]],
    t: usize,
) -> Result<[DVec2; 3], UvError> {
    let mut out = [DVec2::ZERO; 3];
    for (k, &vertex) in triangles[t].iter().enumerate() {
        let uv = *uvs.get(vertex as usize).ok_or(UvError::IndexOutOfRange {
            triangle: t,
            vertex,
            vertices: uvs.len(),
        })?;
        if !uv.is_finite() {
            return Err(UvError::NonFiniteUv {
                triangle: t,
                vertex,
                uv: uv.to_array(),
            });
        }
        out[k] = uv.as_dvec2();
    }
    Ok(out)
}

/// Whether a triangle has no area to speak of: twice its area at most
/// `1e-12` of its longest edge squared (its corners collinear to
/// rounding), or exactly zero.
pub(crate) fn is_degenerate(c: [DVec2; 3]) -> bool {
    let area2 = (c[1] - c[0]).perp_dot(c[2] - c[0]).abs();
    let longest = (c[1] - c[0])
        .length_squared()
        .max((c[2] - c[1]).length_squared())
        .max((c[0] - c[2]).length_squared());
    area2 == 0.0 || area2 <= 1e-12 * longest
}
