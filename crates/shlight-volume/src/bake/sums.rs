//! The probes' sums, one block of directions at a time: each ray's row
//! `v = (Y(s), T(q), E(q))` (the surface's transfer and emitted light
//! interpolated at the hit), then `acc[i][c] = sum_rays Y_i(s) v_c` in
//! `f32`, a small matrix product. With AVX2 and FMA (detected at run time)
//! the product keeps a 3-row by 24-column tile of `acc` in registers, one
//! fused multiply-add per 8 entries and ray; elsewhere a portable loop
//! computes the same sums in the same order (its roundings differ from the
//! fused ones in the last bits).
//!
//! With surfaces the records are incident ([`VertexRecords::incident`]):
//! a front hit's interpolated row is then multiplied by the albedo of the
//! texel it met, per channel, and its emitters' part becomes `Le + rho F`.

use glam::Vec3;
use shlight_prt::{Kernels, VertexRecords};

use super::hit::Hit;

/// What the rows of one probe's block are made from.
pub(super) struct Rows<'a> {
    /// SH coefficients per row.
    pub(super) nc: usize,
    /// Floats per row: `nc + len` rounded up to a multiple of 8.
    pub(super) width: usize,
    /// The subdivided mesh's triangles.
    pub(super) triangles: &'a [[u32; 3]],
    /// Per vertex `rec` floats (`len` of them used, zeros after).
    pub(super) records: &'a [f32],
    pub(super) rec: usize,
    pub(super) len: usize,
    /// Incident records (`Some(channels nc)`, the transfer's floats): a
    /// front hit's row takes its albedo.
    pub(super) incident: Option<usize>,
}

impl Rows<'_> {
    /// Floats [`fill`](Self::fill) needs for `rays` rows: one row more than
    /// they hold, which the last row's interpolation may write into.
    pub(super) fn buffer(&self, rays: usize) -> usize {
        (rays + 1) * self.width
    }

    /// The rows of the rays `hits` (directions' coefficients `ylm`, `nc`
    /// per ray) into `v`: `(Y, 0)` at a back face, `(Y, T, E)` at a front
    /// hit, zeros for an escaped ray. With incident records, `albedo`
    /// holds each ray's albedo at its hit (else it is empty). Returns the
    /// escaped and back-face counts.
    pub(super) fn fill(
        &self,
        kernels: Kernels,
        hits: &[Hit],
        albedo: &[Vec3],
        ylm: &[f32],
        v: &mut [f32],
    ) -> (usize, usize) {
        assert!(v.len() >= self.buffer(hits.len()) && ylm.len() >= hits.len() * self.nc);
        assert!(
            self.rec.is_multiple_of(VertexRecords::LINE)
                && self.len <= self.rec
                && self.nc + self.len <= self.width
        );
        if let Some(stride) = self.incident {
            assert!(
                albedo.len() >= hits.len() || hits.iter().all(|h| h.triangle >= Hit::BACK_ID),
                "an albedo per ray"
            );
            assert!(stride % 3 == 0 && (self.len == stride || self.len == stride + 6));
        }
        #[cfg(target_arch = "x86_64")]
        if kernels == Kernels::Avx2 {
            // SAFETY: AVX2 and FMA were detected (`Kernels::detect`), and the
            // lengths are checked above.
            let counts = unsafe { avx2::fill(self, hits, ylm, v) };
            self.take_albedo(hits, albedo, v);
            return counts;
        }
        let _ = kernels;
        let (nc, width, len) = (self.nc, self.width, self.len);
        let (mut escaped, mut back) = (0, 0);
        for (r, hit) in hits.iter().enumerate() {
            let row = &mut v[r * width..][..width];
            match hit.triangle {
                Hit::ESCAPED_ID => {
                    escaped += 1;
                    row.fill(0.0);
                    continue;
                }
                Hit::BACK_ID => {
                    back += 1;
                    row[nc..].fill(0.0);
                }
                t => {
                    let [a, b, c] = self.triangles[t as usize];
                    let w = [1.0 - hit.b1 - hit.b2, hit.b1, hit.b2];
                    let [ra, rb, rc] =
                        [a, b, c].map(|i| &self.records[i as usize * self.rec..][..len]);
                    for (k, o) in row[nc..nc + len].iter_mut().enumerate() {
                        *o = w[0] * ra[k] + w[1] * rb[k] + w[2] * rc[k];
                    }
                    row[nc + len..].fill(0.0);
                }
            }
            row[..nc].copy_from_slice(&ylm[r * nc..][..nc]);
        }
        self.take_albedo(hits, albedo, v);
        (escaped, back)
    }

    /// With incident records, each front hit's row of `v` (interpolated
    /// records) turned into the light leaving the hit: the transfer of
    /// channel `c` times the albedo's channel `c`, and the emitters' part
    /// `Le + rho F` (the 3 floats of `F` then zero).
    fn take_albedo(&self, hits: &[Hit], albedo: &[Vec3], v: &mut [f32]) {
        let Some(stride) = self.incident else {
            return;
        };
        let (nc, width) = (self.nc, self.width);
        let per = stride / 3;
        for (r, hit) in hits.iter().enumerate() {
            if hit.triangle >= Hit::BACK_ID {
                continue;
            }
            let rho = albedo[r];
            let row = &mut v[r * width + nc..][..self.len];
            for (c, t) in row[..stride].chunks_exact_mut(per).enumerate() {
                t.iter_mut().for_each(|x| *x *= rho[c]);
            }
            if self.len > stride {
                for c in 0..3 {
                    row[stride + c] += rho[c] * row[stride + 3 + c];
                    row[stride + 3 + c] = 0.0;
                }
            }
        }
    }
}

/// `acc[i][c] = sum_r y[r][i] v[r][c]` over `rays` rays, `acc` being `nc`
/// rows of `width` (a multiple of 8), `y` rows of `nc`, `v` rows of
/// `width`; each entry summed over the rays in order.
pub(super) fn block_sum(
    kernels: Kernels,
    y: &[f32],
    nc: usize,
    v: &[f32],
    width: usize,
    rays: usize,
    acc: &mut [f32],
) {
    assert!(width.is_multiple_of(8) && y.len() >= rays * nc && v.len() >= rays * width);
    assert!(acc.len() >= nc * width);
    #[cfg(target_arch = "x86_64")]
    if kernels == Kernels::Avx2 {
        // SAFETY: AVX2 and FMA were detected, the lengths checked above.
        unsafe { avx2::block_sum(y, nc, v, width, rays, acc) };
        return;
    }
    let _ = kernels;
    acc[..nc * width].fill(0.0);
    for r in 0..rays {
        let row = &v[r * width..][..width];
        for i in 0..nc {
            let yi = y[r * nc + i];
            for (a, x) in acc[i * width..][..width].iter_mut().zip(row) {
                *a += yi * x;
            }
        }
    }
}

#[cfg(target_arch = "x86_64")]
mod avx2 {
    use std::arch::x86_64::*;

    use super::{Hit, Rows};

    /// [`Rows::fill`] with AVX2: a front hit's row is three records'
    /// weighted sum, eight floats at a time (the last eight may run past
    /// the row into the next one, which is written after it; the records'
    /// padding makes them zeros).
    ///
    /// # Safety
    /// AVX2 and FMA must be available and the lengths those `fill` checks.
    #[target_feature(enable = "avx2,fma")]
    pub(super) unsafe fn fill(
        rows: &Rows,
        hits: &[Hit],
        ylm: &[f32],
        v: &mut [f32],
    ) -> (usize, usize) {
        let (nc, width, len) = (rows.nc, rows.width, rows.len);
        let chunks = len.div_ceil(8);
        let (mut escaped, mut back) = (0, 0);
        for (r, hit) in hits.iter().enumerate() {
            let row = &mut v[r * width..];
            match hit.triangle {
                Hit::ESCAPED_ID => {
                    escaped += 1;
                    row[..width].fill(0.0);
                }
                Hit::BACK_ID => {
                    back += 1;
                    row[..nc].copy_from_slice(&ylm[r * nc..][..nc]);
                    row[nc..width].fill(0.0);
                }
                t => {
                    row[..nc].copy_from_slice(&ylm[r * nc..][..nc]);
                    let [a, b, c] = rows.triangles[t as usize];
                    let at = |i: u32| &rows.records[i as usize * rows.rec..][..rows.rec];
                    let (ra, rb, rc) = (at(a), at(b), at(c));
                    // SAFETY: chunk k reads floats 8k..8k+8 < rec of each
                    // record and writes nc+8k..nc+8k+8 <= width + 8 <= the
                    // row and the next one (`Rows::buffer`).
                    unsafe {
                        let wa = _mm256_set1_ps(1.0 - hit.b1 - hit.b2);
                        let wb = _mm256_set1_ps(hit.b1);
                        let wc = _mm256_set1_ps(hit.b2);
                        let out = row.as_mut_ptr().add(nc);
                        for k in 0..chunks {
                            let x = _mm256_mul_ps(wa, _mm256_loadu_ps(ra.as_ptr().add(8 * k)));
                            let x = _mm256_fmadd_ps(wb, _mm256_loadu_ps(rb.as_ptr().add(8 * k)), x);
                            let x = _mm256_fmadd_ps(wc, _mm256_loadu_ps(rc.as_ptr().add(8 * k)), x);
                            _mm256_storeu_ps(out.add(8 * k), x);
                        }
                    }
                    if nc + 8 * chunks < width {
                        row[nc + 8 * chunks..width].fill(0.0);
                    }
                }
            }
        }
        (escaped, back)
    }

    /// [`super::block_sum`] by tiles of up to 3 rows by 3 vectors of 8.
    ///
    /// # Safety
    /// AVX2 and FMA must be available and the lengths those `block_sum`
    /// checks.
    #[target_feature(enable = "avx2,fma")]
    pub(super) unsafe fn block_sum(
        y: &[f32],
        nc: usize,
        v: &[f32],
        width: usize,
        rays: usize,
        acc: &mut [f32],
    ) {
        let vectors = width / 8;
        let mut i = 0;
        while i < nc {
            let rg = (nc - i).min(3);
            let mut c = 0;
            while c < vectors {
                let cr = (vectors - c).min(3);
                let at = (y, nc, v, width, rays, i, c);
                // SAFETY: rows i..i+rg < nc and vectors c..c+cr < width/8.
                unsafe {
                    match (rg, cr) {
                        (3, 3) => tile::<3, 3>(at, acc),
                        (3, 2) => tile::<3, 2>(at, acc),
                        (3, _) => tile::<3, 1>(at, acc),
                        (2, 3) => tile::<2, 3>(at, acc),
                        (2, 2) => tile::<2, 2>(at, acc),
                        (2, _) => tile::<2, 1>(at, acc),
                        (_, 3) => tile::<1, 3>(at, acc),
                        (_, 2) => tile::<1, 2>(at, acc),
                        _ => tile::<1, 1>(at, acc),
                    }
                }
                c += cr;
            }
            i += rg;
        }
    }

    /// Rows `i..i+R` by vectors `c..c+C` of the block sum, in registers.
    ///
    /// # Safety
    /// As [`block_sum`], with the tile inside `acc`.
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn tile<const R: usize, const C: usize>(
        (y, nc, v, width, rays, i, c): (&[f32], usize, &[f32], usize, usize, usize, usize),
        acc: &mut [f32],
    ) {
        unsafe {
            let mut sum = [[_mm256_setzero_ps(); C]; R];
            let (y, v) = (y.as_ptr(), v.as_ptr());
            for r in 0..rays {
                let row = v.add(r * width + 8 * c);
                let x: [__m256; C] = std::array::from_fn(|k| _mm256_loadu_ps(row.add(8 * k)));
                for (g, s) in sum.iter_mut().enumerate() {
                    let b = _mm256_broadcast_ss(&*y.add(r * nc + i + g));
                    for (sk, xk) in s.iter_mut().zip(&x) {
                        *sk = _mm256_fmadd_ps(b, *xk, *sk);
                    }
                }
            }
            let out = acc.as_mut_ptr();
            for (g, s) in sum.iter().enumerate() {
                for (k, sk) in s.iter().enumerate() {
                    _mm256_storeu_ps(out.add((i + g) * width + 8 * (c + k)), *sk);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng, rngs::StdRng};

    /// A seeded stream of random numbers in `-1..1`.
    fn numbers(seed: u64) -> impl FnMut() -> f32 {
        let mut rng = StdRng::seed_from_u64(seed);
        move || rng.random_range(-1.0..1.0)
    }

    #[test]
    fn block_sums_match_f64_sums_with_both_kernels() {
        // Every tile shape: 1 to 10 rows, widths of 8 to 56 (one to seven
        // vectors), 64 rays, entries of either sign.
        if Kernels::detect() == Kernels::Portable {
            shlight_rays::skip_test(
                "block_sums_match_f64_sums_with_both_kernels",
                "no AVX2 and FMA here: only the portable sums are held to the f64 ones",
            );
        }
        let mut next = numbers(7);
        // Without AVX2 and FMA both are the portable kernel.
        let kernels = [Kernels::Portable, Kernels::detect()];
        for nc in 1..=10 {
            for width in (8..=56).step_by(8) {
                let rays = 64;
                let y: Vec<f32> = (0..rays * nc).map(|_| next()).collect();
                let v: Vec<f32> = (0..rays * width).map(|_| next()).collect();
                let mut want = vec![0.0f64; nc * width];
                let mut bound = vec![0.0f64; nc * width];
                for r in 0..rays {
                    for i in 0..nc {
                        for c in 0..width {
                            let p = f64::from(y[r * nc + i]) * f64::from(v[r * width + c]);
                            want[i * width + c] += p;
                            bound[i * width + c] += p.abs();
                        }
                    }
                }
                for k in kernels {
                    let mut acc = vec![f32::NAN; nc * width];
                    block_sum(k, &y, nc, &v, width, rays, &mut acc);
                    for ((a, w), b) in acc.iter().zip(&want).zip(&bound) {
                        // Each of the 64 f32 additions rounds by at most
                        // half an ulp of the running sum, which is below
                        // the sum of magnitudes: 64 u sum|p| bounds it.
                        let tol = 64.0 * f64::from(f32::EPSILON) * b + 1e-30;
                        assert!(
                            (f64::from(*a) - w).abs() <= tol,
                            "{k:?} {nc}x{width}: {a} vs {w}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn rows_are_the_same_with_both_kernels() {
        // Records of 12 floats (9 transfer, 3 emitted) in 16-float lines;
        // rows of 9 + 12 = 21 padded to 24: the AVX2 fill writes 16 floats
        // from 9 and so runs into the next row.
        if Kernels::detect() == Kernels::Portable {
            shlight_rays::skip_test(
                "rows_are_the_same_with_both_kernels",
                "no AVX2 and FMA here: only the portable rows are checked",
            );
        }
        let mut next = numbers(3);
        let (nc, len, rec, width) = (9, 12, VertexRecords::LINE, 24);
        let vertices = 10;
        let mut records = vec![0.0f32; vertices * rec];
        for v in 0..vertices {
            for k in 0..len {
                records[v * rec + k] = next();
            }
        }
        let triangles = [[0, 1, 2], [3, 4, 5], [7, 8, 9], [2, 6, 9]];
        let rows = Rows {
            nc,
            width,
            triangles: &triangles,
            records: &records,
            rec,
            len,
            incident: None,
        };
        let mut hits = Vec::new();
        for k in 0..40 {
            hits.push(match k % 5 {
                0 => Hit::ESCAPED,
                1 => Hit::BACK,
                _ => {
                    let (b1, b2) = (0.5 * (next() + 1.0), 0.25 * (next() + 1.0));
                    Hit {
                        triangle: (k % 4) as u32,
                        b1: b1 * (1.0 - b2),
                        b2,
                        t: 1.0,
                    }
                }
            });
        }
        let ylm: Vec<f32> = (0..hits.len() * nc).map(|_| next()).collect();
        let mut portable = vec![f32::NAN; rows.buffer(hits.len())];
        let mut simd = vec![f32::NAN; rows.buffer(hits.len())];
        let counts = rows.fill(Kernels::Portable, &hits, &[], &ylm, &mut portable);
        assert_eq!(counts, (8, 8));
        // Without AVX2 and FMA this compares the portable fill with itself.
        assert_eq!(
            rows.fill(Kernels::detect(), &hits, &[], &ylm, &mut simd),
            counts
        );
        let used = hits.len() * width;
        for (r, (p, s)) in portable[..used]
            .chunks_exact(width)
            .zip(simd[..used].chunks_exact(width))
            .enumerate()
        {
            for (c, (a, b)) in p.iter().zip(s).enumerate() {
                // The same weighted sum, fused or not: a few ulps of the
                // largest term.
                assert!(
                    (a - b).abs() <= 4.0 * f32::EPSILON,
                    "row {r} column {c}: {a} vs {b}"
                );
            }
            match hits[r].triangle {
                Hit::ESCAPED_ID => assert!(p.iter().all(|&x| x == 0.0)),
                Hit::BACK_ID => {
                    assert_eq!(&p[..nc], &ylm[r * nc..][..nc]);
                    assert!(p[nc..].iter().all(|&x| x == 0.0));
                }
                t => {
                    assert_eq!(&p[..nc], &ylm[r * nc..][..nc]);
                    assert!(p[nc + len..].iter().all(|&x| x == 0.0));
                    let w = [1.0 - hits[r].b1 - hits[r].b2, hits[r].b1, hits[r].b2];
                    for k in 0..len {
                        let want: f32 = (0..3)
                            .map(|j| w[j] * records[triangles[t as usize][j] as usize * rec + k])
                            .sum();
                        assert!((p[nc + k] - want).abs() < 1e-6);
                    }
                }
            }
        }
    }
}
