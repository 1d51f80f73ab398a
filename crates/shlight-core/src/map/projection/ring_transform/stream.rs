//! [`RingAccumulator`]: the ring transform fed rows as a reader decodes
//! them, in any order and from any thread, with no image buffer.

use std::sync::{Mutex, PoisonError};

use glam::DVec3;

use crate::map::orientation::MapOrientation;
use crate::map::projection::pole::to_frame;
use crate::map::projection::ring_transform::blocks::LANES;
use crate::map::projection::ring_transform::row_pass::Scratch;
use crate::map::projection::ring_transform::{PairSums, RingGeometry};
use crate::sh::sh_coeffs::ShCoeffs;

/// The equirect projection ([`crate::map::project`]) of a map whose rows
/// arrive a block at a time, as a file is decoded: each row's azimuthal
/// sums are taken as it arrives, kept until the row mirrored about the
/// equator arrives, and then folded into the row pass's sums; the rows
/// themselves are not kept.
///
/// Memory is the ring transform's own sums (about `96 (lmax + 1)` bytes a
/// row pair), the azimuthal sums of rows still waiting for their mirror
/// (`48 (lmax + 1)` bytes a row at most, when the rows come top to
/// bottom) and a few rows of scratch per thread; nothing grows with the
/// width but the scratch.
///
/// Rows may come in any order and from several threads at once
/// ([`RingAccumulator::add_rows`] takes `&self`; a reader on one thread
/// calls [`RingAccumulator::add_rows_parallel`]); the coefficients are the
/// same bit for bit as [`crate::map::project`]'s of the same texels,
/// whatever the order, because every row's sums and every pair's
/// combination are computed by the same code from the same values.
///
/// ```
/// use shlight_core::map::{EquirectView, MapOrientation, RingAccumulator, project_equirect};
///
/// let (w, h) = (32, 16);
/// let pixels: Vec<[f32; 3]> = (0..w * h).map(|i| [i as f32, 1.0, (i % 7) as f32]).collect();
/// let o = MapOrientation::default();
/// let acc = RingAccumulator::new(w, h, 4, o);
/// // Bottom half first, then the top half in two blocks.
/// acc.add_rows(8, &pixels[8 * w..]);
/// acc.add_rows(0, &pixels[..3 * w]);
/// acc.add_rows(3, &pixels[3 * w..8 * w]);
/// let streamed = acc.finish().unwrap();
/// let whole = project_equirect(EquirectView { width: w, height: h, pixels: &pixels }, 4, o);
/// assert_eq!(streamed.as_slice(), whole.as_slice());
/// ```
pub struct RingAccumulator {
    geometry: RingGeometry,
    frame: crate::sh::frame::Frame,
    state: Mutex<State>,
    /// Row-pass scratch, reused across calls (one per thread at most).
    scratch: Mutex<Vec<Scratch>>,
}

/// What [`RingAccumulator::add_rows`] has gathered so far.
struct State {
    sums: PairSums,
    /// Per row pair, the azimuthal sums of whichever of its rows came
    /// first, until the other comes.
    waiting: Vec<Option<Vec<[f64; 6]>>>,
    /// Rows seen, per row.
    seen: Vec<bool>,
    rows_seen: usize,
}

/// Rows that [`RingAccumulator::finish`] never received.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MissingRows {
    /// How many rows are missing.
    pub missing: usize,
    /// The map's height.
    pub height: usize,
    /// The first missing row.
    pub first: usize,
}

impl std::fmt::Display for MissingRows {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} of the map's {} rows never arrived (the first is row {})",
            self.missing, self.height, self.first
        )
    }
}

impl std::error::Error for MissingRows {}

impl RingAccumulator {
    /// An accumulator for a `width x height` equirect map projected to
    /// `lmax`, read in `orientation`.
    ///
    /// # Panics
    /// If `width` or `height` is 0.
    #[must_use]
    pub fn new(width: usize, height: usize, lmax: usize, orientation: MapOrientation) -> Self {
        assert!(width > 0 && height > 0, "an empty map");
        let geometry = RingGeometry::new(width, height, lmax, orientation.pole_azimuth_sign());
        let state = State {
            sums: geometry.zero_sums(),
            waiting: (0..geometry.pairs()).map(|_| None).collect(),
            seen: vec![false; height],
            rows_seen: 0,
        };
        Self {
            geometry,
            frame: orientation.frame,
            state: Mutex::new(state),
            scratch: Mutex::new(Vec::new()),
        }
    }

    /// The map's `(width, height)`.
    #[must_use]
    pub fn size(&self) -> (usize, usize) {
        (self.geometry.w, self.geometry.h)
    }

    /// Folds in rows `first_row..`, `rows` holding whole rows of `width`
    /// texels one after another, on the calling thread. Calls may come
    /// from several threads at once (a decoder on every core).
    ///
    /// # Panics
    /// If `rows` is not a whole number of rows, runs past the last row, or
    /// holds a row already added (a reader's bug: files that repeat or
    /// miss blocks are refused by the reader).
    pub fn add_rows(&self, first_row: usize, rows: &[[f32; 3]]) {
        let n = self.check_rows(first_row, rows);
        let mut s = self.take_scratch();
        for (k, row) in rows.chunks(self.geometry.w).take(n).enumerate() {
            self.add_row(first_row + k, row, &mut s);
        }
        self.put_scratch(s);
    }

    /// [`RingAccumulator::add_rows`] with the rows of the call summed in
    /// parallel on rayon's pool (with the `rayon` feature), for a reader
    /// that hands rows from one thread. Not to be called from a thread
    /// that a rayon worker is blocked on (a decoding thread a pool task
    /// spawned and waits for): the pool's workers could all be waiting,
    /// and the rows never summed.
    pub fn add_rows_parallel(&self, first_row: usize, rows: &[[f32; 3]]) {
        #[cfg(feature = "rayon")]
        {
            use rayon::prelude::*;
            let n = self.check_rows(first_row, rows);
            rows.par_chunks(self.geometry.w)
                .take(n)
                .enumerate()
                .for_each(|(k, row)| {
                    let mut s = self.take_scratch();
                    self.add_row(first_row + k, row, &mut s);
                    self.put_scratch(s);
                });
        }
        #[cfg(not(feature = "rayon"))]
        self.add_rows(first_row, rows);
    }

    /// The number of rows in `rows`, checked (see the panics of
    /// [`RingAccumulator::add_rows`]).
    fn check_rows(&self, first_row: usize, rows: &[[f32; 3]]) -> usize {
        let w = self.geometry.w;
        assert!(rows.len().is_multiple_of(w), "whole rows of {w} texels");
        let n = rows.len() / w;
        assert!(first_row + n <= self.geometry.h, "rows past the map");
        n
    }

    fn put_scratch(&self, s: Scratch) {
        self.scratch
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .push(s);
    }

    fn take_scratch(&self) -> Scratch {
        let pooled = self
            .scratch
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .pop();
        pooled.unwrap_or_else(|| self.geometry.scratch())
    }

    /// Row `y`'s azimuthal sums, then, if its mirror row has come, the
    /// pair's lane of the sums.
    fn add_row(&self, y: usize, row: &[[f32; 3]], s: &mut Scratch) {
        let g = &self.geometry;
        let mut ring = vec![[0.0; 6]; g.lmax + 1];
        g.azimuth.row(row, &mut ring, &mut s.bufs);
        let p = y.min(g.h - 1 - y);
        let mut state = self.state.lock().unwrap_or_else(PoisonError::into_inner);
        assert!(!state.seen[y], "row {y} added twice");
        state.seen[y] = true;
        state.rows_seen += 1;
        let other = if g.h - 1 - p == p {
            // The middle row of an odd height pairs with zeros.
            Some(vec![[0.0; 6]; g.lmax + 1])
        } else {
            state.waiting[p].take()
        };
        let Some(other) = other else {
            state.waiting[p] = Some(ring);
            return;
        };
        // `a` is always the upper row's, `b` the lower's.
        let (a, b) = if y == p {
            (&ring, &other)
        } else {
            (&other, &ring)
        };
        let cols = g.lmax + 1;
        let (block, lane) = (p / LANES, p % LANES);
        let sums = &mut state.sums;
        let range = block * cols..(block + 1) * cols;
        g.fill_pair(
            p,
            lane,
            a,
            b,
            &mut s.sectoral,
            &mut sums.weights[range.clone()],
            &mut sums.starts[range],
            &mut sums.xs[block],
        );
    }

    /// The radiance coefficients, in the orientation's frame, once every
    /// row has been added.
    ///
    /// # Errors
    /// [`MissingRows`] when some row never came.
    pub fn finish(self) -> Result<ShCoeffs<DVec3>, MissingRows> {
        let state = self
            .state
            .into_inner()
            .unwrap_or_else(PoisonError::into_inner);
        let h = self.geometry.h;
        if state.rows_seen != h {
            let first = state.seen.iter().position(|s| !s).unwrap_or(0);
            return Err(MissingRows {
                missing: h - state.rows_seen,
                height: h,
                first,
            });
        }
        drop(state.waiting);
        let zup = self.geometry.columns(state.sums);
        Ok(to_frame(zup, self.frame))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::equirect::EquirectView;
    use crate::map::projection::project_equirect;
    use crate::sh::frame::Frame;

    fn noise(w: usize, h: usize) -> Vec<[f32; 3]> {
        (0..w * h)
            .map(|i| {
                let a = ((i * 7919) % 1009) as f32 / 500.0;
                [a, 1.0 + (i % 17) as f32 * 0.1, ((i * 31) % 97) as f32]
            })
            .collect()
    }

    /// Rows in a scrambled order and uneven blocks, from two threads at
    /// once, give the in-memory coefficients bit for bit: odd and even
    /// heights, folded and plain direct sums, the FFT path, every
    /// orientation.
    #[test]
    fn any_row_order_gives_the_in_memory_coefficients_bit_for_bit() {
        for (w, h, lmax) in [(48, 24, 6), (47, 23, 5), (64, 33, 60), (40, 80, 300)] {
            let px = noise(w, h);
            for o in MapOrientation::ALL {
                let want = project_equirect(
                    EquirectView {
                        width: w,
                        height: h,
                        pixels: &px,
                    },
                    lmax,
                    o,
                );
                let acc = RingAccumulator::new(w, h, lmax, o);
                // Blocks of 5 rows, odd blocks from a second thread,
                // bottom up.
                let blocks: Vec<usize> = (0..h).step_by(5).rev().collect();
                std::thread::scope(|scope| {
                    let (acc, px) = (&acc, &px);
                    for (i, &y) in blocks.iter().enumerate() {
                        let end = (y + 5).min(h);
                        if i % 2 == 1 {
                            scope.spawn(move || acc.add_rows(y, &px[y * w..end * w]));
                        } else {
                            acc.add_rows_parallel(y, &px[y * w..end * w]);
                        }
                    }
                });
                let got = acc.finish().unwrap();
                assert_eq!(got.as_slice(), want.as_slice(), "{w}x{h} lmax {lmax} {o:?}");
            }
        }
    }

    #[test]
    fn missing_rows_are_reported() {
        let (w, h) = (16, 8);
        let px = noise(w, h);
        let o = MapOrientation {
            frame: Frame::YUp,
            mirror: false,
        };
        let acc = RingAccumulator::new(w, h, 2, o);
        acc.add_rows(0, &px[..3 * w]);
        acc.add_rows(5, &px[5 * w..]);
        assert_eq!(
            acc.finish().unwrap_err(),
            MissingRows {
                missing: 2,
                height: 8,
                first: 3
            }
        );
    }
}
