//! [`RowSink`] and [`BLOCK_TEXELS`]: where a row reader hands its rows,
//! and how many at once.

/// Where rows go: `sink(first_row, rows)`, `rows` whole rows of the
/// image's width from `first_row` on.
pub type RowSink<'a> = dyn Fn(usize, &[[f32; 3]]) + Sync + 'a;

/// Texels per band that the row-by-row readers hand on at once (whole
/// rows; at least one).
pub(crate) const BLOCK_TEXELS: usize = 1 << 16;
