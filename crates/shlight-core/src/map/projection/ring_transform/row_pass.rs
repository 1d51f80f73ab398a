//! The ring transform's row pass: the azimuthal sums
//! `C_m = sum_i f_i cos(m ψ_i)`, `S_m = sum_i f_i sin(m ψ_i)` of one row of
//! texels for every `m <= lmax` ([`Azimuth::row`]). For small lmax, direct
//! sums against a table of `cos(m ψ_i)`, `sin(m ψ_i)`, over the row folded
//! onto its first quarter when `W` is a multiple of 4
//! ([`fold_row`](super::kernels::fold_row)); from lmax [`FFT_FROM_LMAX`] on,
//! a real FFT of the row, `sum_i f_i e^{-i m φ_i} = e^{-i m c} X_m`.

use core::f64::consts::PI;

use realfft::num_complex::Complex;
use realfft::{RealFftPlanner, RealToComplex};

use crate::map::projection::ring_transform::kernels::{FOLD_CHUNK, deinterleave, dots, fold_row};

/// From this lmax on, rows are transformed by FFT instead of direct sums.
/// Chosen by instruction counts (callgrind) of a 2048x1024 projection: the
/// folded direct sums ([`fold_row`]) cost 73 M instructions at lmax 24,
/// 110 M at 40 and 169 M at 63; the FFT path 137 M, 142 M and 150 M.
pub(crate) const FFT_FROM_LMAX: usize = 48;

/// Texels per block of the direct sums.
const DIRECT_BLOCK: usize = 512;

/// Row transform: the table of `cos(m ψ_i)`, `sin(m ψ_i)` or an FFT plan.
pub(crate) struct Azimuth {
    w: usize,
    lmax: usize,
    sign: f64,
    /// `[m][i]` cosines and sines for the direct sums (empty with FFT), of
    /// the first quarter of the row when it is folded.
    cos: Vec<f64>,
    sin: Vec<f64>,
    /// Whether rows are folded into quarters before the direct sums
    /// ([`fold_row`]; needs `W` a multiple of 4).
    folded: bool,
    fft: Option<std::sync::Arc<dyn RealToComplex<f64>>>,
    /// `e^{-i m c}`, `c = π/W - π`, per `m` (FFT path).
    phase: Vec<Complex<f64>>,
}

impl Azimuth {
    pub(crate) fn new(w: usize, lmax: usize, sign: f64) -> Self {
        let angle = |i: usize| 2.0 * PI * ((i as f64 + 0.5) / w as f64 - 0.5);
        if lmax >= FFT_FROM_LMAX && w > 1 {
            let fft = RealFftPlanner::<f64>::new().plan_fft_forward(w);
            let c = PI / w as f64 - PI;
            let phase = (0..=lmax)
                .map(|m| {
                    let (s, co) = (-(m as f64) * c).sin_cos();
                    Complex::new(co, s)
                })
                .collect();
            return Self {
                w,
                lmax,
                sign,
                cos: Vec::new(),
                sin: Vec::new(),
                folded: false,
                fft: Some(fft),
                phase,
            };
        }
        let folded = w.is_multiple_of(4);
        let n = if folded { w / 4 } else { w };
        let mut cos = vec![0.0; (lmax + 1) * n];
        let mut sin = vec![0.0; (lmax + 1) * n];
        for m in 0..=lmax {
            for i in 0..n {
                let (s, c) = (m as f64 * sign * angle(i)).sin_cos();
                cos[m * n + i] = c;
                sin[m * n + i] = s;
            }
        }
        Self {
            w,
            lmax,
            sign,
            cos,
            sin,
            folded,
            fft: None,
            phase: Vec::new(),
        }
    }

    /// `ring[m] = [C_r, C_g, C_b, S_r, S_g, S_b]` of one row of texels.
    pub(crate) fn row(&self, texels: &[[f32; 3]], ring: &mut [[f64; 6]], s: &mut RowBuffers) {
        match &self.fft {
            None if self.folded => {
                // Chunks of the quarter small enough that the folded values
                // and the trig rows they meet stay in the L1 cache.
                ring.iter_mut().for_each(|r| *r = [0.0; 6]);
                let q = self.w / 4;
                for start in (0..q).step_by(FOLD_CHUNK) {
                    let n = FOLD_CHUNK.min(q - start);
                    fold_row(texels, start, &mut s.quarters);
                    let [p_even, p_odd, q_even, q_odd] = &s.quarters;
                    for (m, out) in ring.iter_mut().enumerate() {
                        let (p, q_) = if m % 2 == 0 {
                            (p_even, q_even)
                        } else {
                            (p_odd, q_odd)
                        };
                        let trig = m * q + start..m * q + start + n;
                        let d = dots(p, q_, &self.cos[trig.clone()], &self.sin[trig]);
                        for c in 0..6 {
                            out[c] += d[c];
                        }
                    }
                }
            }
            None => {
                // Blocks of texels small enough that the channels and the
                // trig rows they meet stay in the L1 cache.
                ring.iter_mut().for_each(|r| *r = [0.0; 6]);
                for start in (0..self.w).step_by(DIRECT_BLOCK) {
                    let end = (start + DIRECT_BLOCK).min(self.w);
                    deinterleave(&texels[start..end], &mut s.channels);
                    for (m, out) in ring.iter_mut().enumerate() {
                        let cos = &self.cos[m * self.w + start..m * self.w + end];
                        let sin = &self.sin[m * self.w + start..m * self.w + end];
                        let d = dots(&s.channels, &s.channels, cos, sin);
                        for c in 0..6 {
                            out[c] += d[c];
                        }
                    }
                }
            }
            Some(fft) => {
                deinterleave(texels, &mut s.channels);
                let half = self.w / 2;
                for c in 0..3 {
                    // The transform reuses the input as scratch; the channel
                    // buffer is refilled for every row anyway.
                    fft.process_with_scratch(
                        &mut s.channels[c],
                        &mut s.spectrum,
                        &mut s.fft_scratch,
                    )
                    .expect("buffer sizes come from the plan");
                    // k = m mod W, stepped (a division per m cost more
                    // than the rest of this loop).
                    let mut k = 0;
                    for m in 0..=self.lmax {
                        let x = if k <= half {
                            s.spectrum[k]
                        } else {
                            s.spectrum[self.w - k].conj()
                        };
                        let mut z = self.phase[m] * x;
                        if self.sign > 0.0 {
                            z = z.conj();
                        }
                        ring[m][c] = z.re;
                        ring[m][c + 3] = z.im;
                        k = if k + 1 == self.w { 0 } else { k + 1 };
                    }
                }
            }
        }
    }
}

/// Per-thread buffers of phase 1.
pub(crate) struct Scratch {
    pub(crate) ring_a: Vec<[f64; 6]>,
    pub(crate) ring_b: Vec<[f64; 6]>,
    pub(crate) sectoral: Vec<[f64; 2]>,
    /// A row read texel by texel from a source that does not store it
    /// contiguously.
    pub(crate) texels: Vec<[f32; 3]>,
    pub(crate) bufs: RowBuffers,
}

impl Scratch {
    pub(crate) fn new(w: usize, lmax: usize, az: &Azimuth) -> Self {
        let (spectrum, fft_scratch) = match &az.fft {
            Some(f) => (f.make_output_vec(), f.make_scratch_vec()),
            None => (Vec::new(), Vec::new()),
        };
        Self {
            ring_a: vec![[0.0; 6]; lmax + 1],
            ring_b: vec![[0.0; 6]; lmax + 1],
            sectoral: vec![[0.0; 2]; lmax + 1],
            texels: Vec::new(),
            bufs: RowBuffers {
                channels: [vec![0.0; w], vec![0.0; w], vec![0.0; w]],
                quarters: core::array::from_fn(|_| {
                    core::array::from_fn(|_| vec![0.0; FOLD_CHUNK.min(w / 4)])
                }),
                spectrum,
                fft_scratch,
            },
        }
    }
}

/// Buffers for [`Azimuth::row`].
pub(crate) struct RowBuffers {
    channels: [Vec<f64>; 3],
    /// Folded rows `[P_even, P_odd, Q_even, Q_odd][channel]` ([`fold_row`]).
    quarters: [[Vec<f64>; 3]; 4],
    spectrum: Vec<Complex<f64>>,
    fft_scratch: Vec<Complex<f64>>,
}
