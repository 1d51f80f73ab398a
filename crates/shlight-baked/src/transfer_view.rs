//! [`TransferView`]: PRT transfer vectors borrowed, as the renderer and
//! every reader of a bake take them.
//!
//! A transfer vector `T_v` per vertex turns distant radiance into the
//! radiance the vertex leaves: `L_out(v) = sum_i T_vi L_i` (Sloan, Kautz &
//! Snyder 2002), one dot product of `(lmax+1)^2` coefficients per channel.
//! The array is vertex-major: vertex `v`, channel `c`, coefficient `i` at
//! `(v * channels + c) * (lmax+1)^2 + i`. One channel is applied to all three
//! colours of the light; three apply channel by channel. The light's
//! coefficients are used up to the smaller of the two degrees.

use crate::ShapeError;

/// Borrowed per-vertex transfer vectors (shlight-prt's `Transfer` owns
/// them; a `.shprt` file holds them).
#[derive(Clone, Copy, Debug)]
pub struct TransferView<'a> {
    /// Highest degree of each vector.
    pub lmax: usize,
    /// 1 (the same for R, G, B) or 3 (one vector per colour channel).
    pub channels: usize,
    /// Vertices: must equal the mesh's vertex count.
    pub vertex_count: usize,
    /// `vertex_count * channels * (lmax+1)^2` values, vertex-major.
    pub data: &'a [f32],
}

impl<'a> TransferView<'a> {
    /// Checks the shape of a transfer array.
    ///
    /// # Errors
    /// [`ShapeError`] for a channel count other than 1 or 3, or a
    /// length that is not `vertex_count * channels * (lmax+1)^2`.
    pub fn new(
        lmax: usize,
        channels: usize,
        vertex_count: usize,
        data: &'a [f32],
    ) -> Result<Self, ShapeError> {
        if channels != 1 && channels != 3 {
            return Err(ShapeError(format!(
                "PRT transfer has {channels} channels (expected 1 or 3)"
            )));
        }
        let expected = vertex_count
            .checked_mul(channels * (lmax + 1) * (lmax + 1))
            .ok_or_else(|| ShapeError("PRT transfer is too large".into()))?;
        if data.len() != expected {
            return Err(ShapeError(format!(
                "PRT transfer holds {} values; {vertex_count} vertices x {channels} channels x \
                 {} coefficients (lmax {lmax}) need {expected}",
                data.len(),
                (lmax + 1) * (lmax + 1)
            )));
        }
        Ok(Self {
            lmax,
            channels,
            vertex_count,
            data,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shapes_are_checked() {
        let data = vec![0.0f32; 2 * 3 * 9];
        let t = TransferView::new(2, 3, 2, &data).unwrap();
        assert_eq!((t.lmax, t.channels, t.vertex_count), (2, 3, 2));
        let e = TransferView::new(2, 2, 2, &data).unwrap_err();
        assert_eq!(e.0, "PRT transfer has 2 channels (expected 1 or 3)");
        let e = TransferView::new(2, 1, 2, &data).unwrap_err();
        assert!(e.0.starts_with("PRT transfer holds 54 values; 2 vertices x 1 channels x 9 coefficients (lmax 2) need 18"), "{e}");
        assert!(TransferView::new(2, 3, usize::MAX, &data).is_err());
    }
}
