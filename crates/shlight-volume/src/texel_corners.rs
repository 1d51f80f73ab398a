//! [`texel_corners`]: the eight texels a linear filter reads around a
//! point of a 3D texture, and their weights; the engines' lookups
//! ([`crate::bevy_lookup`], [`crate::threejs_lookup`]) filter their
//! textures with it.

use glam::DVec3;

/// The eight corners of a texel-space cell with fractions `f` (each in
/// `[0, 1]`) and their trilinear weights, corner `d` (per axis 0 for the
/// lower, 1 for the upper texel) weighing `prod f_a` or `1 - f_a`; corners
/// of weight 0 left out.
pub(crate) fn texel_corners(f: DVec3) -> impl Iterator<Item = ([usize; 3], f64)> {
    (0..8usize).filter_map(move |corner| {
        let d = [corner & 1, corner >> 1 & 1, corner >> 2 & 1];
        let w = [f.x, f.y, f.z]
            .iter()
            .zip(d)
            .map(|(f, d)| if d == 1 { *f } else { 1.0 - f })
            .product::<f64>();
        (w != 0.0).then_some((d, w))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The weights are the products of the fractions, as a linear filter
    /// weighs texels: they sum to 1 and reproduce the point's own texel
    /// coordinates; a fraction of 0 drops the upper texels.
    #[test]
    fn the_weights_are_products_of_the_fractions() {
        let f = DVec3::new(0.25, 0.5, 0.75);
        let corners: Vec<_> = texel_corners(f).collect();
        assert_eq!(corners.len(), 8);
        assert_eq!(corners[0], ([0, 0, 0], 0.75 * 0.5 * 0.25));
        assert_eq!(corners[7], ([1, 1, 1], 0.25 * 0.5 * 0.75));
        let sum: f64 = corners.iter().map(|c| c.1).sum();
        assert!((sum - 1.0).abs() < 1e-15);
        let back: DVec3 = corners
            .iter()
            .map(|(d, w)| *w * DVec3::new(d[0] as f64, d[1] as f64, d[2] as f64))
            .sum();
        assert!((back - f).abs().max_element() < 1e-15);
        let on_x: Vec<_> = texel_corners(DVec3::new(0.5, 0.0, 0.0)).collect();
        assert_eq!(on_x, vec![([0, 0, 0], 0.5), ([1, 0, 0], 0.5)]);
    }
}
