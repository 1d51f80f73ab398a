//! Padding: texels without a value filled from their valid neighbours,
//! so that bilinear filtering and mip levels near a chart's edge read
//! light, not the empty background.
//!
//! Each pass gives every empty texel with at least one valid texel among
//! its 8 neighbours the plain mean of those (diagonal and side neighbours
//! weigh the same), reading only the values the previous pass left: the
//! result does not depend on the order texels are visited in, and `n`
//! passes grow the valid region by exactly `n` rings (Chebyshev
//! distance). Valid texels never change.

use glam::{DVec3, DVec4, Vec3, Vec4};
use std::fmt;

/// A value that can be averaged: what a lightmap texel holds.
pub trait Blend: Copy {
    /// The mean of `values` (never empty), accumulated in `f64`.
    fn mean(values: &[Self]) -> Self;
}

impl Blend for f64 {
    fn mean(values: &[Self]) -> Self {
        values.iter().sum::<f64>() / values.len() as f64
    }
}

impl Blend for f32 {
    fn mean(values: &[Self]) -> Self {
        (values.iter().map(|&v| f64::from(v)).sum::<f64>() / values.len() as f64) as f32
    }
}

impl<const N: usize> Blend for [f32; N] {
    fn mean(values: &[Self]) -> Self {
        let mut sum = [0.0f64; N];
        for v in values {
            for (s, &x) in sum.iter_mut().zip(v) {
                *s += f64::from(x);
            }
        }
        sum.map(|s| (s / values.len() as f64) as f32)
    }
}

impl<const N: usize> Blend for [f64; N] {
    fn mean(values: &[Self]) -> Self {
        let mut sum = [0.0f64; N];
        for v in values {
            for (s, &x) in sum.iter_mut().zip(v) {
                *s += x;
            }
        }
        sum.map(|s| s / values.len() as f64)
    }
}

impl Blend for Vec3 {
    fn mean(values: &[Self]) -> Self {
        let sum = values.iter().fold(DVec3::ZERO, |s, v| s + v.as_dvec3());
        (sum / values.len() as f64).as_vec3()
    }
}

impl Blend for Vec4 {
    fn mean(values: &[Self]) -> Self {
        let sum = values.iter().fold(DVec4::ZERO, |s, v| s + v.as_dvec4());
        (sum / values.len() as f64).as_vec4()
    }
}

/// A grid whose texel count is not a whole number of rows of the width
/// given (or a width of 0).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GridShapeError {
    /// The texels given.
    pub texels: usize,
    /// The width given.
    pub width: usize,
}

impl fmt::Display for GridShapeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} texels do not make whole rows of {} texels",
            self.texels, self.width
        )
    }
}

impl std::error::Error for GridShapeError {}

/// Fills the empty (`None`) texels of a grid `width` texels wide, stored
/// row by row, for `passes` passes (stopping early once a pass fills
/// nothing); returns how many texels were filled.
///
/// # Errors
/// A width of 0, or a texel count that is not a multiple of the width.
pub fn dilate<T: Blend>(
    texels: &mut [Option<T>],
    width: usize,
    passes: u32,
) -> Result<usize, GridShapeError> {
    if width == 0 || !texels.len().is_multiple_of(width) {
        return Err(GridShapeError {
            texels: texels.len(),
            width,
        });
    }
    let height = texels.len() / width;
    let mut filled = 0;
    let mut neighbours: Vec<T> = Vec::with_capacity(8);
    for _ in 0..passes {
        let mut fills: Vec<(usize, T)> = Vec::new();
        for y in 0..height {
            for x in 0..width {
                if texels[y * width + x].is_some() {
                    continue;
                }
                neighbours.clear();
                for ny in y.saturating_sub(1)..=(y + 1).min(height - 1) {
                    for nx in x.saturating_sub(1)..=(x + 1).min(width - 1) {
                        if let Some(v) = texels[ny * width + nx] {
                            neighbours.push(v);
                        }
                    }
                }
                if !neighbours.is_empty() {
                    fills.push((y * width + x, T::mean(&neighbours)));
                }
            }
        }
        if fills.is_empty() {
            break;
        }
        filled += fills.len();
        for (k, v) in fills {
            texels[k] = Some(v);
        }
    }
    Ok(filled)
}
