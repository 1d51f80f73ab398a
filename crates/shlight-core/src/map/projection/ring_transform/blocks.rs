//! The blocks of row pairs both passes of the ring transform work on:
//! [`LANES`] pairs per block (one vector lane each), the weights the row
//! pass leaves for the column pass ([`BlockWeights`], [`BlockStart`]) and
//! the column pass's per-degree partial sums ([`Partial`]).

/// Lanes (row pairs) per recurrence pass in phase 2.
pub(crate) const LANES: usize = 16;

/// One block of [`LANES`] row pairs for one column `m`: both parities'
/// weights `Ω f_m (A ± B)` (even / odd `l + m`), channel-major as
/// `[parity][C_r, C_g, C_b, S_r, S_g, S_b][lane]`, ready for vector lanes.
pub(crate) type BlockWeights = [[[f64; LANES]; 6]; 2];

/// One block's per-pair data for one column `m`: the sectoral start value
/// `Pbar_m^m(sin θ)` as mantissa and exponent count per lane.
#[derive(Clone, Copy)]
pub(crate) struct BlockStart {
    pub(crate) value: [f64; LANES],
    pub(crate) exponent: [f64; LANES],
}

/// Per-degree partial sums while a column runs: `[channel][lane mod 4]`,
/// added across lanes only at the end.
pub(crate) type Partial = [[f64; 4]; 6];
