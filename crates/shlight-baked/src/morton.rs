//! Morton (Z-order) codes: cells numbered along a curve that visits each
//! `2x2x2` block before the next, so that neighbours in the order are
//! neighbours in space (probes and vertices baked together cast coherent
//! rays).

/// The Morton code of cell `(x, y, z)`, each coordinate below `2^21`: the
/// bits of x, y and z interleaved, x lowest.
#[must_use]
pub fn morton_code(x: u32, y: u32, z: u32) -> u64 {
    spread(x) | spread(y) << 1 | spread(z) << 2
}

/// The low 21 bits of `v`, two zero bits after each.
fn spread(v: u32) -> u64 {
    let mut x = u64::from(v) & 0x1f_ffff;
    x = (x | x << 32) & 0x001f_0000_0000_ffff;
    x = (x | x << 16) & 0x001f_0000_ff00_00ff;
    x = (x | x << 8) & 0x100f_00f0_0f00_f00f;
    x = (x | x << 4) & 0x10c3_0c30_c30c_30c3;
    (x | x << 2) & 0x1249_2492_4924_9249
}

/// The indices `0..keys.len()` ordered by their Morton codes (ties by
/// index): `order[r]` is the item of rank `r`.
#[must_use]
pub fn morton_order(codes: impl IntoIterator<Item = u64>) -> Vec<u32> {
    let mut keyed: Vec<(u64, u32)> = codes
        .into_iter()
        .enumerate()
        .map(|(i, c)| (c, i as u32))
        .collect();
    keyed.sort_unstable();
    keyed.into_iter().map(|(_, i)| i).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The interleaving, bit by bit, against a loop over the bits.
    #[test]
    fn codes_interleave_the_bits() {
        let by_loop = |x: u32, y: u32, z: u32| {
            let mut code = 0u64;
            for bit in 0..21 {
                code |= u64::from(x >> bit & 1) << (3 * bit);
                code |= u64::from(y >> bit & 1) << (3 * bit + 1);
                code |= u64::from(z >> bit & 1) << (3 * bit + 2);
            }
            code
        };
        for (x, y, z) in [
            (0, 0, 0),
            (1, 0, 0),
            (0, 1, 0),
            (0, 0, 1),
            (1023, 5, 700),
            (0x1f_ffff, 0, 0x1f_ffff),
            (123_456, 654_321, 1_000_000),
        ] {
            assert_eq!(morton_code(x, y, z), by_loop(x, y, z), "{x} {y} {z}");
        }
        // The first eight cells are the 2x2x2 block at the origin.
        let order = morton_order(
            (0..4u32)
                .flat_map(|z| (0..4u32).flat_map(move |y| (0..4u32).map(move |x| (x, y, z))))
                .map(|(x, y, z)| morton_code(x, y, z)),
        );
        let mut first: Vec<u32> = order[..8].to_vec();
        first.sort_unstable();
        assert_eq!(first, [0, 1, 4, 5, 16, 17, 20, 21]);
    }
}
