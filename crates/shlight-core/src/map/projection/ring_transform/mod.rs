//! The ring transform behind equirect projection: azimuthal sums per row,
//! then Legendre sums per column `m`, with the map's pole as the basis's
//! polar axis (z-up).
//!
//! For rows `j` (colatitude `θ_j`, texel solid angle `Ω_j`) and texel
//! azimuths `ψ_i` about the pole,
//!
//! ```text
//! L_l^m    = sqrt2 sum_j Ω_j Pbar_l^m(cos θ_j) C_m(j),  C_m(j) = sum_i f_ji cos(m ψ_i)
//! L_l^-m   = sqrt2 sum_j Ω_j Pbar_l^m(cos θ_j) S_m(j),  S_m(j) = sum_i f_ji sin(m ψ_i)
//! ```
//!
//! (no `sqrt2` at `m = 0`). Two phases:
//!
//! 1. **Azimuthal sums**, row by row: for small lmax, direct sums against a
//!    table of `cos(m ψ_i)`, `sin(m ψ_i)` over the row folded onto its first
//!    quarter by the symmetries `ψ -> -ψ` and `ψ -> ψ + π` (`fold_row`;
//!    `W/4` multiply-adds per `m` instead of `W`); for large lmax, a real FFT
//!    of each row (`O(W log W)` instead of `O(W lmax)`). With
//!    `ψ_i = ∓φ_i`, `φ_i = 2π i/W + c`, `c = π/W - π`:
//!    `sum_i f_i e^{-i m φ_i} = e^{-i m c} X_m`, `X` the DFT of the row
//!    (`X_m` for `m >= W` wraps around, as the sum does).
//! 2. **Legendre sums**, column `m` by column: rows `j` and `H-1-j` sit at
//!    `±cos θ` with the same `Ω`, and `Pbar_l^m(-x) = (-1)^(l+m) Pbar_l^m(x)`,
//!    so each pair enters through `Ω (C(j) ± C(H-1-j))` and the recurrence
//!    runs once per pair, on 16 pairs at a time (vector lanes), with the
//!    extended exponent of [`crate::sh::Legendre`] near the poles; lanes worth
//!    less than `2^-200` are left out, and a block whose lanes are all such
//!    skips its sums. The recurrence is taken in the form with a unit
//!    coefficient on `l - 2` ([`UnitRecurrence`]: two operations per lane
//!    and degree), its state held in registers, and the degrees are run in
//!    tiles of [`TILE`], every block of a column through one tile before
//!    the next, so that the tile's sums stay in the L1 cache.
//!
//! Columns are independent, so phase 2 runs in parallel over `m`; phase 1
//! in parallel over row pairs. All sums are in `f64`. On x86-64 CPUs with
//! AVX and FMA both phases run in code compiled for them (runtime check).

use core::f64::consts::PI;

use glam::DVec3;

use crate::map::equirect::equirect_row_solid_angle;
use crate::map::texel_source::{TexelSource, read_row};
use crate::sh::index::sh_index;
use crate::sh::legendre::Legendre;
use crate::sh::real::Real;
use crate::sh::sh_coeffs::ShCoeffs;

use crate::map::projection::ring_transform::blocks::{BlockStart, BlockWeights, LANES};
use crate::map::projection::ring_transform::column_pass::{ColumnInput, column};
use crate::map::projection::ring_transform::row_pass::{Azimuth, Scratch};

mod blocks;
mod column_pass;
mod kernels;
mod row_pass;
pub(crate) mod stream;

/// What the row pass needs about the map, shared by the in-memory route
/// ([`project_rings`]) and the streaming one ([`RingAccumulator`]).
pub(crate) struct RingGeometry {
    pub(crate) w: usize,
    pub(crate) h: usize,
    pub(crate) lmax: usize,
    pub(crate) leg: Legendre<f64>,
    pub(crate) azimuth: Azimuth,
}

/// The row pass's output for every block of row pairs: weights and
/// sectoral start values `[block][m]`, and `cos θ` per lane. Lanes past the
/// last pair stay zero.
pub(crate) struct PairSums {
    pub(crate) weights: Vec<BlockWeights>,
    pub(crate) starts: Vec<BlockStart>,
    pub(crate) xs: Vec<[f64; LANES]>,
}

impl RingGeometry {
    pub(crate) fn new(w: usize, h: usize, lmax: usize, sign: f64) -> Self {
        Self {
            w,
            h,
            lmax,
            leg: Legendre::<f64>::new(lmax),
            azimuth: Azimuth::new(w, lmax, sign),
        }
    }

    pub(crate) fn pairs(&self) -> usize {
        self.h.div_ceil(2)
    }

    pub(crate) fn blocks(&self) -> usize {
        self.pairs().div_ceil(LANES)
    }

    pub(crate) fn scratch(&self) -> Scratch {
        Scratch::new(self.w, self.lmax, &self.azimuth)
    }

    pub(crate) fn zero_sums(&self) -> PairSums {
        let (blocks, cols) = (self.blocks(), self.lmax + 1);
        let zero_start = BlockStart {
            value: [0.0; LANES],
            exponent: [0.0; LANES],
        };
        PairSums {
            weights: vec![[[[0.0; LANES]; 6]; 2]; blocks * cols],
            starts: vec![zero_start; blocks * cols],
            xs: vec![[0.0; LANES]; blocks],
        }
    }

    /// Lane `lane` of a block (`wts`, `st`, `x` that block's slices) from
    /// the azimuthal sums `a` of row `p` and `b` of row `H-1-p` (zero for
    /// the middle row of an odd height): the one formula both routes use,
    /// so they agree bit for bit.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn fill_pair(
        &self,
        p: usize,
        lane: usize,
        a: &[[f64; 6]],
        b: &[[f64; 6]],
        sectoral: &mut [[f64; 2]],
        wts: &mut [BlockWeights],
        st: &mut [BlockStart],
        x: &mut [f64; LANES],
    ) {
        let (w, h) = (self.w, self.h);
        let omega = equirect_row_solid_angle(p, w, h);
        let theta = PI * (p as f64 + 0.5) / h as f64;
        x[lane] = theta.cos();
        sectoral_values(&self.leg, theta.sin(), sectoral);
        for m in 0..=self.lmax {
            let f = omega * if m == 0 { 1.0 } else { 2f64.sqrt() };
            let (a, b) = (a[m], b[m]);
            for c in 0..6 {
                wts[m][0][c][lane] = f * (a[c] + b[c]);
                wts[m][1][c][lane] = f * (a[c] - b[c]);
            }
            [st[m].value[lane], st[m].exponent[lane]] = sectoral[m];
        }
    }

    /// Phase 2 on the row pass's sums: the coefficients about the pole.
    pub(crate) fn columns(&self, sums: PairSums) -> ShCoeffs<DVec3> {
        let lmax = self.lmax;
        let cols = lmax + 1;
        let input = ColumnInput {
            leg: &self.leg,
            lmax,
            xs: &sums.xs,
            weights: &sums.weights,
            starts: &sums.starts,
        };
        // Long columns (small m) and short ones interleaved for load balance.
        let order = |i: usize| {
            if i.is_multiple_of(2) {
                i / 2
            } else {
                lmax - i / 2
            }
        };
        #[cfg(feature = "rayon")]
        let columns: Vec<(usize, Vec<[f64; 6]>)> = {
            use rayon::prelude::*;
            (0..cols)
                .into_par_iter()
                .with_max_len(1)
                .map(|i| (order(i), column(&input, order(i))))
                .collect()
        };
        #[cfg(not(feature = "rayon"))]
        let columns: Vec<(usize, Vec<[f64; 6]>)> = (0..cols)
            .map(|i| (order(i), column(&input, order(i))))
            .collect();

        // The phases' buffers (tens of MB at high lmax) go back before the
        // coefficients are allocated, which can then reuse their memory.
        drop(sums);
        let mut out = ShCoeffs::<DVec3>::zeros(lmax);
        for (m, col) in columns {
            for (i, v) in col.iter().enumerate() {
                let l = m + i;
                out[sh_index(l, m as isize)] = DVec3::new(v[0], v[1], v[2]);
                if m > 0 {
                    out[sh_index(l, -(m as isize))] = DVec3::new(v[3], v[4], v[5]);
                }
            }
        }
        out
    }
}

/// Radiance coefficients of an equirect map about its own pole (z-up), the
/// azimuth of texel column `i` being `sign * φ_i`. Rows are read through
/// [`read_row`]: straight from the source when it stores them contiguously.
pub(crate) fn project_rings<S: TexelSource + ?Sized>(
    map: &S,
    lmax: usize,
    sign: f64,
) -> ShCoeffs<DVec3> {
    let (w, h) = map.size();
    let g = RingGeometry::new(w, h, lmax, sign);
    let pairs = g.pairs();
    let cols = lmax + 1;
    let mut sums = g.zero_sums();

    // Phase 1, per block of row pairs.
    let phase1 = |b: usize,
                  wts: &mut [BlockWeights],
                  st: &mut [BlockStart],
                  x: &mut [f64; LANES],
                  s: &mut Scratch| {
        for lane in 0..LANES.min(pairs - b * LANES) {
            let p = b * LANES + lane;
            let j2 = h - 1 - p;
            let row = read_row(map, p, &mut s.texels);
            g.azimuth.row(row, &mut s.ring_a, &mut s.bufs);
            if j2 != p {
                let row = read_row(map, j2, &mut s.texels);
                g.azimuth.row(row, &mut s.ring_b, &mut s.bufs);
            } else {
                s.ring_b.iter_mut().for_each(|r| *r = [0.0; 6]);
            }
            g.fill_pair(p, lane, &s.ring_a, &s.ring_b, &mut s.sectoral, wts, st, x);
        }
    };
    let new_scratch = || g.scratch();
    #[cfg(feature = "rayon")]
    {
        use rayon::prelude::*;
        sums.weights
            .par_chunks_mut(cols)
            .zip(sums.starts.par_chunks_mut(cols))
            .zip(sums.xs.par_iter_mut())
            .enumerate()
            .for_each_init(new_scratch, |s, (b, ((wts, st), x))| {
                phase1(b, wts, st, x, s)
            });
    }
    #[cfg(not(feature = "rayon"))]
    {
        let mut s = new_scratch();
        for (b, ((wts, st), x)) in sums
            .weights
            .chunks_mut(cols)
            .zip(sums.starts.chunks_mut(cols))
            .zip(sums.xs.iter_mut())
            .enumerate()
        {
            phase1(b, wts, st, x, &mut s);
        }
    }
    g.columns(sums)
}

/// `Pbar_m^m(sin θ)` for every `m`, as `(mantissa, exponent count k <= 0)`
/// with the true value `mantissa * SMALL^(-k)` ([`crate::sh::Legendre`]).
fn sectoral_values(leg: &Legendre<f64>, s: f64, out: &mut [[f64; 2]]) {
    let (big, small) = (f64::BIG, f64::SMALL);
    let mut p = 0.5 / PI.sqrt();
    let mut k = 0.0;
    for (m, o) in out.iter_mut().enumerate() {
        if m > 0 {
            p *= leg.sectoral_factor(m) * s;
            if p.abs() < small {
                p *= big;
                k -= 1.0;
            }
        }
        *o = [p, k];
    }
}
