//! The edge-aware filter (`denoise`) on grids whose answers are known:
//! noise on a flat surface divided as the weights' variance says, a linear
//! ramp kept, and light never mixed across a crease, between stacked
//! planes, between charts apart in the scene, or between regions.

use glam::Vec3;
use rand::{Rng, SeedableRng, rngs::StdRng};
use shlight_lightmap::{TexelGuide, denoise};

const W: usize = 48;
/// A texel's size on the surface (metres).
const H: f32 = 0.05;

/// A flat floor (y = 0, facing up) laid on the whole grid.
fn floor_guides() -> Vec<Option<TexelGuide>> {
    (0..W * W)
        .map(|k| {
            let (x, y) = ((k % W) as f32, (k / W) as f32);
            Some(TexelGuide {
                position: Vec3::new((x + 0.5) * H, 0.0, (y + 0.5) * H),
                normal: Vec3::Y,
                region: 0,
            })
        })
        .collect()
}

fn values(mut f: impl FnMut(usize, usize) -> f64) -> Vec<Option<[f64; 1]>> {
    (0..W * W).map(|k| Some([f(k % W, k / W)])).collect()
}

fn at(v: &[Option<[f64; 1]>], x: usize, y: usize) -> f64 {
    v[y * W + x].unwrap()[0]
}

/// Interior texels: at least `radius` from the grid's edge.
fn interior(radius: usize) -> impl Iterator<Item = (usize, usize)> {
    (radius..W - radius).flat_map(move |y| (radius..W - radius).map(move |x| (x, y)))
}

#[test]
fn noise_on_a_flat_floor_falls_as_the_weights_variance_says() {
    let mut rng = StdRng::seed_from_u64(7);
    let noisy = values(|_, _| 1.0 + 0.1 * (rng.random::<f64>() - 0.5) * 12f64.sqrt());
    let guides = floor_guides();
    let filtered = denoise(&noisy, &guides, W, 2, f64::from(H));
    let stats = |v: &[Option<[f64; 1]>]| {
        let xs: Vec<f64> = interior(2).map(|(x, y)| at(v, x, y)).collect();
        let mean = xs.iter().sum::<f64>() / xs.len() as f64;
        let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / xs.len() as f64;
        (mean, var.sqrt())
    };
    let (m0, s0) = stats(&noisy);
    let (m1, s1) = stats(&filtered);
    // The weights on a flat floor: a Gaussian of s = 1 texel over 5 x 5.
    let w: Vec<f64> = (-2i32..=2)
        .flat_map(|dy| (-2i32..=2).map(move |dx| (-f64::from(dx * dx + dy * dy) / 2.0).exp()))
        .collect();
    let gain = (w.iter().map(|w| w * w).sum::<f64>()).sqrt() / w.iter().sum::<f64>();
    assert!((m1 - m0).abs() < 1e-3, "mean {m0} -> {m1}");
    assert!(
        (s1 / s0 - gain).abs() < 0.1 * gain,
        "noise {s0} -> {s1}: ratio {}, the weights say {gain}",
        s1 / s0
    );
    assert!(s1 / s0 < 0.35, "{}", s1 / s0);
}

#[test]
fn a_linear_ramp_on_a_flat_floor_is_kept() {
    // The local plane fit keeps a linear function everywhere: within f32
    // positions' rounding where the window is whole, and within the
    // ridge's pull at the grid's edges and corners (a weighted mean would
    // be off there by about a texel's change, 0.03).
    let ramp = values(|x, y| 2.0 + 0.03 * x as f64 - 0.02 * y as f64);
    let filtered = denoise(&ramp, &floor_guides(), W, 3, f64::from(H));
    for (x, y) in interior(0) {
        let err = (at(&filtered, x, y) - at(&ramp, x, y)).abs();
        let whole = (3..W - 3).contains(&x) && (3..W - 3).contains(&y);
        assert!(err < if whole { 1e-6 } else { 1e-3 }, "({x}, {y}): {err}");
    }
}

/// `guides` with the wall (the texels facing +x) laid back to `degrees`
/// from the floor's plane, turning about the crease.
fn leaning(guides: &[Option<TexelGuide>], degrees: f32) -> Vec<Option<TexelGuide>> {
    let tilt = degrees.to_radians();
    guides
        .iter()
        .map(|g| {
            let mut g = g.unwrap();
            if g.normal == Vec3::X {
                let along = g.position.y;
                g.position = Vec3::new(along * tilt.cos(), along * tilt.sin(), g.position.z);
                g.normal = Vec3::new(-tilt.sin(), tilt.cos(), 0.0);
            }
            Some(g)
        })
        .collect()
}

#[test]
fn light_is_not_mixed_across_a_crease() {
    // Columns x < 24: a floor facing up; x >= 24: a wall rising from the
    // floor's edge, facing +x, one chart in the atlas. Lit floor, dark wall.
    let guides: Vec<Option<TexelGuide>> = (0..W * W)
        .map(|k| {
            let (x, y) = ((k % W) as f32, (k / W) as f32);
            let z = (y + 0.5) * H;
            Some(if x < 24.0 {
                TexelGuide {
                    position: Vec3::new((x + 0.5 - 24.0) * H, 0.0, z),
                    normal: Vec3::Y,
                    region: 0,
                }
            } else {
                TexelGuide {
                    position: Vec3::new(0.0, (x + 0.5 - 24.0) * H, z),
                    normal: Vec3::X,
                    region: 0,
                }
            })
        })
        .collect();
    let light = values(|x, _| if x < 24 { 1.0 } else { 0.0 });
    let filtered = denoise(&light, &guides, W, 2, f64::from(H));
    for (x, y) in interior(0) {
        assert!(
            (at(&filtered, x, y) - at(&light, x, y)).abs() < 1e-6,
            "({x}, {y}): {}",
            at(&filtered, x, y)
        );
    }
    // A wall leaning back by 20 degrees from the floor's plane does mix.
    let bent = leaning(&guides, 20.0);
    let mixed = denoise(&light, &bent, W, 2, f64::from(H));
    assert!(at(&mixed, 23, 20) < 0.97 && at(&mixed, 24, 20) > 0.03);
    // At 60 degrees the facing term (0.5^16) keeps them apart to 1e-3; a
    // facing power of 1 would mix a fifth.
    let steep = leaning(&guides, 60.0);
    let apart = denoise(&light, &steep, W, 2, f64::from(H));
    for (x, y) in interior(0) {
        assert!(
            (at(&apart, x, y) - at(&light, x, y)).abs() < 1e-3,
            "60 degrees: ({x}, {y}) {}",
            at(&apart, x, y)
        );
    }
}

#[test]
fn texels_inside_a_wall_keep_its_two_sides_apart() {
    // One floor chart with a wall one texel thick standing on column 24:
    // its texels are inside geometry (a guide, no light). Lit on the left,
    // dark on the right.
    let light: Vec<Option<[f64; 1]>> = (0..W * W)
        .map(|k| match k % W {
            24 => None,
            x if x < 24 => Some([1.0]),
            _ => Some([0.0]),
        })
        .collect();
    let filtered = denoise(&light, &floor_guides(), W, 2, f64::from(H));
    for (x, y) in interior(0) {
        if x != 24 {
            assert!(
                (at(&filtered, x, y) - at(&light, x, y)).abs() < 1e-12,
                "({x}, {y}): {}",
                at(&filtered, x, y)
            );
        }
    }
    // Where nothing stands (no texel there at all), the two sides mix.
    let mut open = floor_guides();
    for y in 0..W {
        open[y * W + 24] = None;
    }
    let mixed = denoise(&light, &open, W, 2, f64::from(H));
    assert!(at(&mixed, 23, 10) < 0.99 && at(&mixed, 25, 10) > 0.01);
}

#[test]
fn a_one_sided_window_does_not_overshoot_the_values_it_fits() {
    // A chart three texels wide, dark, dark, lit: the plane through them
    // passes below 0 at the dark edge; the filter holds it at the darkest.
    let light: Vec<Option<[f64; 1]>> = (0..W * W)
        .map(|k| match k % W {
            0 | 1 => Some([0.0]),
            2 => Some([1.0]),
            _ => None,
        })
        .collect();
    let filtered = denoise(&light, &floor_guides(), W, 2, f64::from(H));
    for y in 0..W {
        for x in 0..3 {
            let v = at(&filtered, x, y);
            assert!((0.0..=1.0).contains(&v), "({x}, {y}): {v}");
        }
    }
}

#[test]
fn stacked_planes_charts_apart_and_other_regions_are_not_mixed() {
    // Left half a floor at y = 0, right half a table top 0.5 m above it,
    // both facing up, side by side in the atlas; then the right half as a
    // chart of the same height far away; then as another region.
    let guide = |x: usize, y: usize, lift: f32, shift: f32, region: u32| TexelGuide {
        position: Vec3::new((x as f32 + 0.5) * H + shift, lift, (y as f32 + 0.5) * H),
        normal: Vec3::Y,
        region,
    };
    let light = values(|x, _| if x < 24 { 1.0 } else { 3.0 });
    // The lift of 3 texels is within the filter's reach (2 (2 + 1) texels):
    // the off-plane term alone keeps the table top apart.
    for (lift, shift, region) in [(3.0 * H, 0.0, 0), (0.0, 10.0, 0), (0.0, 0.0, 1)] {
        let guides: Vec<Option<TexelGuide>> = (0..W * W)
            .map(|k| {
                let (x, y) = (k % W, k / W);
                Some(if x < 24 {
                    guide(x, y, 0.0, 0.0, 0)
                } else {
                    guide(x, y, lift, shift, region)
                })
            })
            .collect();
        let filtered = denoise(&light, &guides, W, 2, f64::from(H));
        for (x, y) in interior(0) {
            assert!(
                (at(&filtered, x, y) - at(&light, x, y)).abs() < 1e-6,
                "lift {lift}, shift {shift}, region {region}: ({x}, {y}) {}",
                at(&filtered, x, y)
            );
        }
    }
    // The same halves on one continuous floor are mixed at the boundary.
    let filtered = denoise(&light, &floor_guides(), W, 2, f64::from(H));
    assert!(at(&filtered, 23, 10) > 1.1 && at(&filtered, 24, 10) < 2.9);
}

#[test]
fn empty_texels_stay_empty_and_radius_0_changes_nothing() {
    let mut light = values(|x, y| (x * y) as f64);
    light[5] = None;
    let mut guides = floor_guides();
    guides[7] = None;
    let filtered = denoise(&light, &guides, W, 2, f64::from(H));
    assert!(filtered[5].is_none() && filtered[7].is_none());
    assert!(filtered[6].is_some());
    assert_eq!(denoise(&light, &guides, W, 0, f64::from(H)), light);
}
