//! [`dilate`]: a volume's invalid probes filled from their valid
//! neighbours, for the engines whose lookups know no validity (Bevy's
//! irradiance volume, three.js's `LightProbeGrid`).

use crate::VolumeView;

/// The radiance of `view` (same layout: per probe `(lmax+1)^2` rows of
/// `[r, g, b]`) with every invalid probe filled from its neighbours; valid
/// probes are copied unchanged, and an invalid probe's own values are never
/// read.
///
/// The rule, in passes:
///
/// - **Neighbours** are the up to six face neighbours `(x +- 1, y, z)`,
///   `(x, y +- 1, z)`, `(x, y, z +- 1)` inside the grid (not the 26 of the
///   surrounding block).
/// - **Pass 1** fills every invalid probe that has at least one valid
///   neighbour with the plain mean of those valid neighbours' values.
/// - **Pass `k`** fills every probe still empty that has at least one
///   neighbour filled before pass `k` (valid, or filled in passes `1..k`)
///   with the mean of those neighbours' values; the probes filled in pass
///   `k` do not feed each other.
///
/// So a region of invalid probes fills from its border inwards, nearest
/// first: a probe is filled in pass `d`, `d` its distance in face steps
/// from the nearest valid probe. The passes end when every probe is
/// filled; a grid with no valid probe at all is returned as zeros. Sums
/// are taken in `f64`, in the neighbour order `-x, +x, -y, +y, -z, +z`,
/// and rounded to `f32` once.
///
/// `view` must pass [`VolumeView::check`].
///
/// ```
/// use glam::Vec3;
/// use shlight_baked::{ProbeGrid, VolumeView, dilate};
///
/// // Three probes along x at lmax 0; the middle one is invalid.
/// let grid = ProbeGrid::new([3, 1, 1], Vec3::ZERO, Vec3::ONE).unwrap();
/// let radiance = [1.0, 1.0, 1.0, 7.0, 7.0, 7.0, 3.0, 5.0, 7.0];
/// let view = VolumeView {
///     grid,
///     lmax: 0,
///     valid: &[true, false, true],
///     radiance: &radiance,
///     offsets: None,
///     visibility: None,
/// };
/// assert_eq!(dilate(&view)[3..6], [2.0, 3.0, 4.0]);
/// ```
#[must_use]
pub fn dilate(view: &VolumeView<'_>) -> Vec<f32> {
    let n = view.probe_count();
    let mut out = view.radiance.to_vec();
    if view.valid.iter().all(|&v| v) {
        return out;
    }
    if !view.valid.iter().any(|&v| v) {
        out.fill(0.0);
        return out;
    }
    let stride = view.radiance.len() / n;
    let [nx, ny, nz] = view.grid.resolution;
    let neighbours = |i: usize| {
        let (x, y, z) = (i % nx, i / nx % ny, i / (nx * ny));
        [
            (x > 0).then(|| i - 1),
            (x + 1 < nx).then(|| i + 1),
            (y > 0).then(|| i - nx),
            (y + 1 < ny).then(|| i + nx),
            (z > 0).then(|| i - nx * ny),
            (z + 1 < nz).then(|| i + nx * ny),
        ]
        .into_iter()
        .flatten()
    };
    let mut filled = view.valid.to_vec();
    // Probes already in a pass's list, so that each is listed once.
    let mut listed = view.valid.to_vec();
    let mut pass: Vec<usize> = Vec::new();
    for i in (0..n).filter(|&i| !filled[i]) {
        if neighbours(i).any(|j| filled[j]) {
            listed[i] = true;
            pass.push(i);
        }
    }
    let mut sum = vec![0.0f64; stride];
    let mut values = Vec::new();
    while !pass.is_empty() {
        values.clear();
        for &i in &pass {
            sum.fill(0.0);
            let mut count = 0u32;
            for j in neighbours(i).filter(|&j| filled[j]) {
                for (s, v) in sum.iter_mut().zip(&out[j * stride..(j + 1) * stride]) {
                    *s += f64::from(*v);
                }
                count += 1;
            }
            values.extend(sum.iter().map(|s| (s / f64::from(count)) as f32));
        }
        let mut next = Vec::new();
        for (k, &i) in pass.iter().enumerate() {
            out[i * stride..(i + 1) * stride]
                .copy_from_slice(&values[k * stride..(k + 1) * stride]);
            filled[i] = true;
        }
        for &i in &pass {
            for j in neighbours(i) {
                if !listed[j] {
                    listed[j] = true;
                    next.push(j);
                }
            }
        }
        pass = next;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ProbeGrid;
    use glam::Vec3;

    /// One probe's lmax-0 radiance `[v, 2 v, -v]`.
    fn rgb(v: f32) -> [f32; 3] {
        [v, 2.0 * v, -v]
    }

    /// A 3 x 3 x 1 grid (probe `x + 3 y`) with valid probes 0 (1), 2 (5)
    /// and 6 (9), the others invalid and holding 1e30. Worked out by hand:
    /// pass 1 fills 1 = (1 + 5) / 2 = 3, 3 = (1 + 9) / 2 = 5, 5 = 5 (its one
    /// valid neighbour, 2) and 7 = 9 (6); the centre 4 and the corner 8
    /// have no valid face neighbour (4 touches 0, 2 and 6 only diagonally),
    /// so pass 2 fills 4 = (3 + 5 + 5 + 9) / 4 = 5.5 and 8 = (5 + 9) / 2 = 7.
    #[test]
    fn invalid_probes_take_the_mean_of_their_face_neighbours_pass_by_pass() {
        let grid = ProbeGrid::new([3, 3, 1], Vec3::ZERO, Vec3::ONE).unwrap();
        let valid = [true, false, true, false, false, false, true, false, false];
        let held = [1.0, 1e30, 5.0, 1e30, 1e30, 1e30, 9.0, 1e30, 1e30];
        let radiance: Vec<f32> = held.iter().flat_map(|&v| rgb(v)).collect();
        let view = VolumeView {
            grid,
            lmax: 0,
            valid: &valid,
            radiance: &radiance,
            offsets: None,
            visibility: None,
        };
        view.check().unwrap();
        let want: Vec<f32> = [1.0, 3.0, 5.0, 5.0, 5.5, 5.0, 9.0, 9.0, 7.0]
            .iter()
            .flat_map(|&v| rgb(v))
            .collect();
        assert_eq!(dilate(&view), want);
    }

    /// Along z, at lmax 1: every coefficient is averaged; a probe between
    /// two valid ones takes their mean, the one beyond takes its filled
    /// neighbour's value in pass 2.
    #[test]
    fn every_coefficient_is_filled_along_z() {
        let grid = ProbeGrid::new([1, 1, 4], Vec3::ZERO, Vec3::ONE).unwrap();
        let valid = [true, false, true, false];
        let probe = |v: f32| -> Vec<f32> { (0..12).map(|k| v * (k as f32 - 4.0)).collect() };
        let radiance: Vec<f32> = [2.0, -1.0, 4.0, -1.0].into_iter().flat_map(probe).collect();
        let view = VolumeView {
            grid,
            lmax: 1,
            valid: &valid,
            radiance: &radiance,
            offsets: None,
            visibility: None,
        };
        let want: Vec<f32> = [2.0, 3.0, 4.0, 4.0].into_iter().flat_map(probe).collect();
        assert_eq!(dilate(&view), want);
    }

    /// Nothing to fill: the radiance unchanged; nothing valid: zeros.
    #[test]
    fn all_valid_is_unchanged_and_none_valid_is_black() {
        let grid = ProbeGrid::new([2, 2, 1], Vec3::ZERO, Vec3::ONE).unwrap();
        let radiance: Vec<f32> = (0..12).map(|k| k as f32 + 0.5).collect();
        let all = [true; 4];
        let view = VolumeView {
            grid,
            lmax: 0,
            valid: &all,
            radiance: &radiance,
            offsets: None,
            visibility: None,
        };
        assert_eq!(dilate(&view), radiance);
        let none = [false; 4];
        let view = VolumeView {
            valid: &none,
            ..view
        };
        assert_eq!(dilate(&view), vec![0.0; 12]);
    }
}
