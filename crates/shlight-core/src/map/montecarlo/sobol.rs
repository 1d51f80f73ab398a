//! The 2-D Sobol (0,2)-sequence and hash-based nested uniform (Owen) scrambling.
//!
//! Point `i` of the sequence, as 32-bit binary fractions:
//!
//! - dimension 1 is the van der Corput sequence, the bits of `i` mirrored
//!   about the binary point (`i.reverse_bits()`);
//! - dimension 2 is `XOR_k bit_k(i) v_k` with the direction numbers of the
//!   primitive polynomial `x + 1`: `v_1 = 1/2`, `v_k = v_{k-1} XOR (v_{k-1} / 2)`
//!   (Pascal's triangle mod 2).
//!
//! Every prefix of `2^m` points is a (0,m,2)-net: each elementary box
//! `[a 2^-p, (a+1) 2^-p) x [b 2^-q, (b+1) 2^-q)`, `p + q = m`, holds exactly
//! one point.
//!
//! A nested uniform scramble flips bit `k` (counting from the binary point)
//! of a coordinate by a random function of the bits above it. Such a scramble
//! keeps the net property, and when its randomness is uniform every
//! scrambled point is uniform on `[0, 1)` — which makes the estimator
//! unbiased. We use the hash of Burley, "Practical Hash-based Owen
//! Scrambling" (JCGT 2020), with the constants of N. Vegdahl (2021): the
//! hash acts on the bit-reversed value, where each operation changes a bit
//! only as a function of the lower (reversed: higher-order) bits; its first
//! steps add the seed, so for a uniform random seed the output is uniform
//! over all `2^32` values.

/// Point `i` of the unscrambled 2-D Sobol sequence, as 32-bit fractions.
#[inline]
pub(crate) fn sobol2(i: u32) -> (u32, u32) {
    let x = i.reverse_bits();
    let mut y = 0u32;
    let mut v = 1u32 << 31;
    let mut k = i;
    while k != 0 {
        if k & 1 != 0 {
            y ^= v;
        }
        k >>= 1;
        v ^= v >> 1;
    }
    (x, y)
}

/// Nested uniform scramble of a 32-bit binary fraction `x` keyed by `seed`.
#[inline]
pub(crate) fn owen_scramble(x: u32, seed: u32) -> u32 {
    let mut v = x.reverse_bits();
    v ^= v.wrapping_mul(0x3d20_adea);
    v = v.wrapping_add(seed);
    v = v.wrapping_mul((seed >> 16) | 1);
    v ^= v.wrapping_mul(0x0552_6c56);
    v ^= v.wrapping_mul(0x53a2_2864);
    v.reverse_bits()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every elementary box of area `2^-m` holds exactly one of the points.
    fn is_net(points: &[(u32, u32)], m: u32) -> bool {
        for p in 0..=m {
            let q = m - p;
            let mut seen = vec![false; 1 << m];
            for &(x, y) in points {
                let a = if p == 0 { 0 } else { (x >> (32 - p)) as usize };
                let b = if q == 0 { 0 } else { (y >> (32 - q)) as usize };
                let cell = (a << q) | b;
                if seen[cell] {
                    return false;
                }
                seen[cell] = true;
            }
        }
        true
    }

    #[test]
    fn first_points_are_the_known_sobol_points() {
        let want = [(0.0, 0.0), (0.5, 0.5), (0.25, 0.75), (0.75, 0.25)];
        for (i, w) in want.iter().enumerate() {
            let (x, y) = sobol2(i as u32);
            let s = 2f64.powi(-32);
            assert_eq!((x as f64 * s, y as f64 * s), *w, "point {i}");
        }
        // 5th..8th: (0.125, 0.625), (0.625, 0.125), (0.375, 0.375), (0.875, 0.875)
        let (x, y) = sobol2(7);
        assert_eq!((x >> 29, y >> 29), (7, 7));
    }

    #[test]
    fn prefixes_and_blocks_are_nets_scrambled_or_not() {
        for m in 0..=10u32 {
            let n = 1u32 << m;
            let plain: Vec<_> = (0..n).map(sobol2).collect();
            assert!(is_net(&plain, m), "plain m {m}");
            // The second block of 2^m points is a net too.
            let block: Vec<_> = (n..2 * n).map(sobol2).collect();
            assert!(is_net(&block, m), "block m {m}");
            for seed in [1u32, 0xdead_beef, 12345] {
                let s: Vec<_> = plain
                    .iter()
                    .map(|&(x, y)| (owen_scramble(x, seed), owen_scramble(y, seed ^ 0x9e37)))
                    .collect();
                assert!(is_net(&s, m), "scrambled m {m} seed {seed}");
            }
        }
    }

    #[test]
    fn scrambling_moves_points_and_is_a_bijection_on_prefixes() {
        // A nested scramble maps distinct top-8-bit prefixes to distinct prefixes.
        let seed = 0x1234_5678;
        let mut seen = [false; 256];
        for a in 0..256u32 {
            let s = owen_scramble(a << 24, seed) >> 24;
            assert!(!seen[s as usize]);
            seen[s as usize] = true;
        }
        assert_ne!(owen_scramble(0, 1), owen_scramble(0, 2));
    }
}
