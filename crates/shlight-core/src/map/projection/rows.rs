//! The parallel loop over image rows that the projections share: rows cut
//! into a fixed number of bands, one partial sum per band, the bands summed
//! in order, so the result is the same bit for bit for any thread count and
//! from run to run.

use glam::DVec3;

use crate::sh::sh_coeffs::ShCoeffs;

/// Bands of rows per loop: enough for load balance on a many-core machine,
/// few enough that the per-band scratch stays small. The bands depend only
/// on the row count, never on the threads.
const BANDS: usize = 64;

/// Per-band state of a loop over rows that ends in coefficients.
pub(crate) trait RowState: Send {
    /// Fresh state for degree `lmax`.
    fn new(lmax: usize) -> Self;
    /// The partial sums this state holds.
    fn into_coeffs(self) -> ShCoeffs<DVec3>;
}

/// Runs `row(j, state)` for every row `j < h`, rows `b k..(b+1) k` of band
/// `b` into one state (`k = ceil(h / BANDS)`), bands in parallel with
/// rayon, and sums the bands' coefficients in band order.
pub(crate) fn run_rows<S: RowState>(
    h: usize,
    lmax: usize,
    row: impl Fn(usize, &mut S) + Sync,
) -> ShCoeffs<DVec3> {
    let per_band = h.div_ceil(BANDS).max(1);
    let band = |b: usize| {
        let mut acc = S::new(lmax);
        for j in b * per_band..((b + 1) * per_band).min(h) {
            row(j, &mut acc);
        }
        acc.into_coeffs()
    };
    let bands = h.div_ceil(per_band);
    #[cfg(feature = "rayon")]
    let parts: Vec<ShCoeffs<DVec3>> = {
        use rayon::prelude::*;
        (0..bands).into_par_iter().map(band).collect()
    };
    #[cfg(not(feature = "rayon"))]
    let parts: Vec<ShCoeffs<DVec3>> = (0..bands).map(band).collect();
    let mut sum = ShCoeffs::zeros(lmax);
    for p in &parts {
        sum += p;
    }
    sum
}
