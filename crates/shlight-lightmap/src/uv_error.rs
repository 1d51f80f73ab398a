//! What is wrong with a mesh's UVs or a grid, named for the caller.

use std::fmt;

/// Bad input to [`crate::TexelRaster::new`] or
/// [`crate::first_uv_overlap`]: each names the triangle (by its index in
/// the triangle list) or the setting at fault.
#[derive(Clone, Debug, PartialEq)]
pub enum UvError {
    /// A corner of a triangle names a vertex past the end of the UVs.
    IndexOutOfRange {
        /// The triangle's index.
        triangle: usize,
        /// The vertex index it names.
        vertex: u32,
        /// How many UVs there are.
        vertices: usize,
    },
    /// A corner's UV is NaN or infinite.
    NonFiniteUv {
        /// The triangle's index.
        triangle: usize,
        /// The vertex index of the corner.
        vertex: u32,
        /// The UV as given.
        uv: [f32; 2],
    },
    /// The placement's scale or offset is NaN or infinite.
    NonFinitePlacement,
    /// The texel grid is empty or wider or taller than [`crate::MAX_SIDE`].
    GridSize {
        /// The width asked for.
        width: u32,
        /// The height asked for.
        height: u32,
        /// The largest side allowed ([`crate::MAX_SIDE`]).
        max_side: u32,
    },
}

impl fmt::Display for UvError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            UvError::IndexOutOfRange {
                triangle,
                vertex,
                vertices,
            } => write!(
                f,
                "triangle {triangle} names vertex {vertex}, but the mesh has {vertices} UVs"
            ),
            UvError::NonFiniteUv {
                triangle,
                vertex,
                uv,
            } => write!(
                f,
                "triangle {triangle} has a UV that is not finite at vertex {vertex}: ({}, {})",
                uv[0], uv[1]
            ),
            UvError::NonFinitePlacement => {
                write!(f, "the lightmap placement's scale or offset is not finite")
            }
            UvError::GridSize {
                width,
                height,
                max_side,
            } => write!(
                f,
                "a lightmap of {width} x {height} texels: each side must be 1 to {max_side}"
            ),
        }
    }
}

impl std::error::Error for UvError {}
