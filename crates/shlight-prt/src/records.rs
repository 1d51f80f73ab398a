//! Per-vertex records as the summing kernels read them, and which kernels
//! run.
//!
//! A record holds a vertex's transfer (`channels x nc` floats) and, when the
//! mesh emits, its exit radiance due to emitters (3 more), in `f32`, padded
//! with zeros to whole 64-byte [`Line`]s: a kernel reads it eight floats at
//! a time without running past it. A bake with surfaces keeps instead what
//! a hit interpolates before its texel's albedo
//! ([`VertexRecords::incident`]). [`Kernels`] says whether the sums run
//! with AVX2 and FMA or as portable loops (the same sums in the same order;
//! the fused roundings differ in the last bits). The bounces of the diffuse
//! bake ([`crate::bake`]) and shlight-volume's probe sums read them
//! ([`VertexRecords`], from [`crate::Transfer::records`]), both with the
//! kernels [`Kernels::detect`] chooses.

use glam::Vec3;

/// Which summing kernels run: AVX2 and FMA, or portable loops (the same
/// sums in the same order; the fused roundings differ in the last bits).
/// The diffuse bake's bounces and shlight-volume's probe sums choose by it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kernels {
    /// `x86_64` AVX2 and FMA.
    Avx2,
    /// Plain Rust, any processor.
    Portable,
}

impl Kernels {
    /// AVX2 where the processor has it and FMA
    /// ([`shlight_rays::has_avx2_and_fma`]), the portable loops otherwise.
    #[must_use]
    pub fn detect() -> Self {
        if shlight_rays::has_avx2_and_fma() {
            Kernels::Avx2
        } else {
            Kernels::Portable
        }
    }
}

/// Floats in a [`Line`].
pub(crate) const LINE: usize = 16;

/// One 64-byte line of a record.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
pub(crate) struct Line(pub(crate) [f32; LINE]);

impl Line {
    /// A line of zeros.
    pub(crate) const ZERO: Line = Line([0.0; LINE]);
}

/// Per-vertex records, each a vertex's transfer (`channels x nc` floats)
/// and, when the mesh emits, its exit radiance due to emitters (3 more), in
/// `f32`, padded with zeros to whole 64-byte lines, so that a kernel reads
/// a record eight floats at a time without running past it. Record `v`
/// starts at float `v * stride()` of [`floats`](Self::floats).
///
/// The records of a bake with surfaces are [`incident`](Self::incident):
/// what a hit interpolates before the albedo of its texel is applied.
#[derive(Clone, Debug)]
pub struct VertexRecords {
    lines: Vec<Line>,
    len: usize,
    incident: bool,
}

impl VertexRecords {
    /// Floats in a 64-byte line: a record's [`stride`](Self::stride) is a
    /// whole number of them.
    pub const LINE: usize = LINE;

    /// The records of the transfer rows `transfer` and the exit radiances
    /// `emitted`, as [`build`] lays them out.
    pub(crate) fn new(transfer: &[f32], stride: usize, emitted: Option<&[Vec3]>) -> Self {
        Self {
            lines: build(transfer, stride, emitted),
            len: stride + if emitted.is_some() { 3 } else { 0 },
            incident: false,
        }
    }

    /// Incident records ([`incident`](Self::incident)) of the transfer
    /// rows `transfer` before albedo and, when the mesh emits, each
    /// vertex's emitted radiance and the emitters' light arriving there.
    pub(crate) fn new_incident(
        transfer: &[f32],
        stride: usize,
        emitted: Option<&[[Vec3; 2]]>,
    ) -> Self {
        let tail: Option<Vec<f32>> = emitted.map(|e| {
            e.iter()
                .flat_map(|[a, b]| [a.x, a.y, a.z, b.x, b.y, b.z])
                .collect()
        });
        Self {
            lines: build_rows(transfer, stride, tail.as_deref().map(|t| (t, 6))),
            len: stride + if emitted.is_some() { 6 } else { 0 },
            incident: true,
        }
    }

    /// Whether the records are incident: each vertex's transfer of the
    /// light arriving there, over pi, before any albedo (`channels x nc`
    /// floats), and, when the mesh emits, its emitted radiance `Le` and the
    /// emitters' light arriving there over pi, `F` (3 + 3); a point of
    /// albedo `rho` (per channel) where a ray hits then leaves the
    /// radiance `rho T . L + Le + rho F`, `T`, `Le` and `F` interpolated
    /// from its triangle's corners ([`crate::Transfer::incident`]). Not
    /// incident, the records hold the exit transfer and the exit radiance
    /// due to emitters (3), which a hit interpolates as they are.
    #[must_use]
    pub fn incident(&self) -> bool {
        self.incident
    }

    /// Every record's floats, one after another.
    #[must_use]
    pub fn floats(&self) -> &[f32] {
        flat(&self.lines)
    }

    /// Floats from one record to the next: [`used`](Self::used) rounded up
    /// to whole lines of [`LINE`](Self::LINE).
    #[must_use]
    pub fn stride(&self) -> usize {
        lines(self.len) * LINE
    }

    /// Floats used in each record: the transfer's `channels x nc`, and 3
    /// when the mesh emits (6 when [`incident`](Self::incident)).
    #[must_use]
    pub fn used(&self) -> usize {
        self.len
    }
}

/// Lines per record of `len` floats.
#[must_use]
pub(crate) fn lines(len: usize) -> usize {
    len.div_ceil(LINE)
}

/// The records of the transfer rows `transfer` (`stride` floats each) and,
/// when given, the exit radiances `emitted` (one per row), in their order:
/// each `stride` floats, then the three of its exit radiance, padded with
/// zeros to whole lines.
///
/// # Panics
/// If `stride` is 0, or `emitted` holds fewer values than `transfer` has
/// rows.
#[must_use]
pub(crate) fn build(transfer: &[f32], stride: usize, emitted: Option<&[Vec3]>) -> Vec<Line> {
    let tail: Option<Vec<f32>> = emitted.map(|e| e.iter().flat_map(|v| v.to_array()).collect());
    build_rows(transfer, stride, tail.as_deref().map(|t| (t, 3)))
}

/// [`build`] with `tail.1` floats per row from `tail.0` after each row.
fn build_rows(transfer: &[f32], stride: usize, tail: Option<(&[f32], usize)>) -> Vec<Line> {
    let extra = tail.map_or(0, |t| t.1);
    let per = lines(stride + extra);
    let count = transfer.len() / stride;
    let mut out = vec![Line::ZERO; count * per];
    for (v, (r, t)) in out
        .chunks_exact_mut(per)
        .zip(transfer.chunks_exact(stride))
        .enumerate()
    {
        let r = flat_mut(r);
        r[..stride].copy_from_slice(t);
        if let Some((e, n)) = tail {
            r[stride..stride + n].copy_from_slice(&e[v * n..][..n]);
        }
    }
    out
}

/// The floats of `lines`.
#[must_use]
pub(crate) fn flat(lines: &[Line]) -> &[f32] {
    // SAFETY: a `Line` is 16 `f32` with no padding (`repr(C)`, 64 bytes).
    unsafe { std::slice::from_raw_parts(lines.as_ptr().cast::<f32>(), lines.len() * LINE) }
}

/// The floats of `lines`, mutable.
#[must_use]
pub(crate) fn flat_mut(lines: &mut [Line]) -> &mut [f32] {
    // SAFETY: as in `flat`.
    unsafe { std::slice::from_raw_parts_mut(lines.as_mut_ptr().cast::<f32>(), lines.len() * LINE) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn records_hold_their_rows_padded_to_whole_lines() {
        // Rows of 15 floats and an exit radiance: 18 floats in two lines.
        let transfer: Vec<f32> = (0..45).map(|x| x as f32 + 1.0).collect();
        let emitted = [Vec3::splat(-1.0), Vec3::splat(-2.0), Vec3::splat(-3.0)];
        let records = build(&transfer, 15, Some(&emitted));
        assert_eq!(records.len(), 6);
        for (v, r) in records.chunks_exact(2).enumerate() {
            let r = flat(r);
            assert_eq!(&r[..15], &transfer[v * 15..][..15]);
            assert_eq!(&r[15..18], &emitted[v].to_array());
            assert!(r[18..].iter().all(|&x| x == 0.0));
        }
        // Without one, 15 floats fit one line.
        let records = build(&transfer, 15, None);
        assert_eq!(records.len(), 3);
        assert_eq!(records[1].0[..15], transfer[15..30]);
        assert_eq!(records[1].0[15], 0.0);
        // Incident records: each row, then its emitted radiance and the
        // emitters' light arriving, 21 floats in two lines.
        let arriving = [
            [Vec3::splat(-1.0), Vec3::splat(-4.0)],
            [Vec3::splat(-2.0), Vec3::splat(-5.0)],
            [Vec3::splat(-3.0), Vec3::splat(-6.0)],
        ];
        let records = VertexRecords::new_incident(&transfer, 15, Some(&arriving));
        assert!(records.incident() && records.used() == 21 && records.stride() == 32);
        for (v, r) in records.floats().chunks_exact(32).enumerate() {
            assert_eq!(&r[..15], &transfer[v * 15..][..15]);
            assert_eq!(&r[15..18], &arriving[v][0].to_array());
            assert_eq!(&r[18..21], &arriving[v][1].to_array());
            assert!(r[21..].iter().all(|&x| x == 0.0));
        }
        assert!(!VertexRecords::new(&transfer, 15, None).incident());
    }
}
