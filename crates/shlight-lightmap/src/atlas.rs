//! Square regions of texels packed into one square lightmap: a region per
//! placed node, rows of regions ("shelves") from the largest down.

/// A square region of a lightmap, in texels: columns `x .. x + side`,
/// rows `y .. y + side`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TexelRect {
    /// The region's first column.
    pub x: u32,
    /// The region's first row.
    pub y: u32,
    /// Its width and height.
    pub side: u32,
}

impl TexelRect {
    /// Whether two regions share a texel.
    #[must_use]
    pub fn overlaps(&self, other: &TexelRect) -> bool {
        self.x < other.x + other.side
            && other.x < self.x + self.side
            && self.y < other.y + other.side
            && other.y < self.y + self.side
    }
}

/// Packs squares of `sides` texels into a `side x side` lightmap, each with
/// `padding` empty texels on every side (so two regions are at least `2
/// padding` apart and a region at least `padding` from the edge): shelves
/// of regions, largest first (ties in the given order), left to right,
/// a new shelf under the last when a row is full. Returns each square's
/// place in the order given, or `None` when they do not fit.
#[must_use]
pub fn pack_squares(sides: &[u32], padding: u32, side: u32) -> Option<Vec<TexelRect>> {
    let mut order: Vec<usize> = (0..sides.len()).collect();
    order.sort_by_key(|&i| std::cmp::Reverse(sides[i]));
    let mut rects = vec![
        TexelRect {
            x: 0,
            y: 0,
            side: 0
        };
        sides.len()
    ];
    let (mut x, mut y, mut shelf) = (0u64, 0u64, 0u64);
    let limit = u64::from(side);
    for i in order {
        let cell = u64::from(sides[i]) + 2 * u64::from(padding);
        if cell > limit {
            return None;
        }
        if x + cell > limit {
            y += shelf;
            x = 0;
            shelf = 0;
        }
        if y + cell > limit {
            return None;
        }
        rects[i] = TexelRect {
            x: (x + u64::from(padding)) as u32,
            y: (y + u64::from(padding)) as u32,
            side: sides[i],
        };
        x += cell;
        shelf = shelf.max(cell);
    }
    Some(rects)
}

/// The smallest power-of-two side, at most `max_side`, that
/// [`pack_squares`] fits `sides` into, with their places.
#[must_use]
pub fn smallest_atlas(sides: &[u32], padding: u32, max_side: u32) -> Option<(u32, Vec<TexelRect>)> {
    let area: u64 = sides
        .iter()
        .map(|&s| (u64::from(s) + 2 * u64::from(padding)).pow(2))
        .sum();
    let mut side = 1u32;
    while u64::from(side) * u64::from(side) < area {
        side = side.checked_mul(2)?;
    }
    while side <= max_side {
        if let Some(rects) = pack_squares(sides, padding, side) {
            return Some((side, rects));
        }
        side = side.checked_mul(2)?;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(rects: &[TexelRect], sides: &[u32], padding: u32, side: u32) {
        for (r, &s) in rects.iter().zip(sides) {
            assert_eq!(r.side, s);
            assert!(r.x >= padding && r.y >= padding);
            assert!(r.x + r.side + padding <= side && r.y + r.side + padding <= side);
        }
        for (i, a) in rects.iter().enumerate() {
            for b in &rects[i + 1..] {
                // Grown by the padding on each side, they still do not meet.
                let grow = |r: &TexelRect| TexelRect {
                    x: r.x - padding,
                    y: r.y - padding,
                    side: r.side + 2 * padding,
                };
                assert!(!grow(a).overlaps(&grow(b)), "{a:?} {b:?}");
            }
        }
    }

    #[test]
    fn squares_are_placed_apart_inside_the_atlas_or_refused() {
        let sides = [30, 7, 64, 12, 12, 3, 40, 9];
        let rects = pack_squares(&sides, 2, 128).unwrap();
        check(&rects, &sides, 2, 128);
        // The total area (with padding) is over 64^2: no 64 side fits.
        assert!(pack_squares(&sides, 2, 64).is_none());
        let (side, rects) = smallest_atlas(&sides, 2, 4096).unwrap();
        assert_eq!(side, 128);
        check(&rects, &sides, 2, side);
        // One square larger than the biggest atlas allowed.
        assert!(smallest_atlas(&[5000], 1, 4096).is_none());
    }

    #[test]
    fn many_equal_squares_fill_shelves_row_by_row() {
        let sides = vec![10u32; 36];
        // Cells of 12: 10 per row of 120 texels, 36 in 4 rows.
        let rects = pack_squares(&sides, 1, 120).unwrap();
        check(&rects, &sides, 1, 120);
        assert_eq!(
            rects[9],
            TexelRect {
                x: 109,
                y: 1,
                side: 10
            }
        );
        assert_eq!(
            rects[10],
            TexelRect {
                x: 1,
                y: 13,
                side: 10
            }
        );
        assert!(pack_squares(&vec![10u32; 101], 1, 120).is_none());
    }
}
