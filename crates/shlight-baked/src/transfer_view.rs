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

impl TransferView<'_> {
    /// Each vertex's exit radiance under the distant light `light` (its
    /// radiance SH coefficients, index `l(l+1)+m`, one `[r, g, b]` each):
    /// `L_out(v, c) = sum_i T[v, c, i] L_i[c]` over the coefficients both
    /// hold (the smaller lmax of the two), one channel applying to all
    /// three colours; what the renderer's PRT mode shades each vertex with.
    #[must_use]
    pub fn exit_radiance(&self, light: &[glam::DVec3]) -> Vec<glam::DVec3> {
        let nc = (self.lmax + 1) * (self.lmax + 1);
        let n = nc.min(light.len());
        self.data
            .chunks_exact(self.channels * nc)
            .map(|v| {
                let mut out = [0.0f64; 3];
                for (c, o) in out.iter_mut().enumerate() {
                    let t = &v[if self.channels == 1 { 0 } else { c * nc }..][..n];
                    *o = t.iter().zip(light).map(|(t, l)| f64::from(*t) * l[c]).sum();
                }
                glam::DVec3::from_array(out)
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    /// Worked by hand: two vertices, lmax 1 (4 coefficients), a light of
    /// lmax 0 uses only the first of each.
    #[test]
    fn exit_radiance_dots_each_channel() {
        let grey: Vec<f32> = vec![1.0, 2.0, 3.0, 4.0, 0.5, 0.0, 0.0, 0.0];
        let t = TransferView::new(1, 1, 2, &grey).unwrap();
        let light = [
            DVec3::new(1.0, 2.0, 3.0),
            DVec3::splat(1.0),
            DVec3::ZERO,
            DVec3::splat(-1.0),
        ];
        let out = t.exit_radiance(&light);
        // Vertex 0: 1 L0 + 2 L1 + 3 L2 + 4 L3 = (1 + 2 - 4, 2 + 2 - 4, 3 + 2 - 4).
        assert_eq!(
            out,
            vec![DVec3::new(-1.0, 0.0, 1.0), DVec3::new(0.5, 1.0, 1.5)]
        );
        assert_eq!(t.exit_radiance(&light[..1])[0], DVec3::new(1.0, 2.0, 3.0));
        let rgb: Vec<f32> = (0..12).map(|i| i as f32).collect();
        let t = TransferView::new(1, 3, 1, &rgb).unwrap();
        let out = t.exit_radiance(&[DVec3::new(1.0, 10.0, 100.0)]);
        assert_eq!(out, vec![DVec3::new(0.0, 40.0, 800.0)]);
    }

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
