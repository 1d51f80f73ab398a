//! The DFG table against a brute-force integral over the hemisphere of
//! light directions, its closed-form limits and Karis' analytic fit.

use std::f64::consts::PI;

use glam::DVec3;
use shlight_specular::d_ggx;
use shlight_specular::{DfgForm, DfgTable, MaskingShadowing, TargetEngine, dfg, dfg_karis_approx};

/// `(A, B)` by the midpoint rule over `l` in `(θ, φ)`: `∫ D V (1 - Fc)
/// (n·l) dl` and `∫ D V Fc (n·l) dl`, no sampling.
fn brute_force(n_dot_v: f64, alpha: f64, vis: MaskingShadowing) -> [f64; 2] {
    let v = DVec3::new((1.0 - n_dot_v * n_dot_v).sqrt(), 0.0, n_dot_v);
    let (nt, np) = (1500, 600);
    let (mut a, mut b) = (0.0, 0.0);
    for i in 0..nt {
        let t = (i as f64 + 0.5) / nt as f64 * PI / 2.0;
        let (st, ct) = t.sin_cos();
        for j in 0..np {
            // φ over [0, π], doubled: the integrand is even in φ.
            let p = (j as f64 + 0.5) / np as f64 * PI;
            let l = DVec3::new(st * p.cos(), st * p.sin(), ct);
            let h = (l + v).normalize();
            let d_omega = st * (PI / 2.0 / nt as f64) * (PI / np as f64) * 2.0;
            let f = d_ggx(h.z, alpha) * vis.eval(n_dot_v, ct, alpha) * ct * d_omega;
            let fc = (1.0 - v.dot(h)).powi(5);
            a += f * (1.0 - fc);
            b += f * fc;
        }
    }
    [a, b]
}

#[test]
fn the_table_matches_a_brute_force_integral() {
    /// 1024 Hammersley samples against a 1500x600 midpoint rule.
    const TOLERANCE: f64 = 0.01;
    for vis in [
        MaskingShadowing::HeightCorrelated,
        MaskingShadowing::SchlickSmith,
    ] {
        for (n_dot_v, p) in [(0.9, 0.3), (0.5, 0.5), (0.2, 0.8), (0.7, 1.0), (0.1, 0.45)] {
            let got = dfg(n_dot_v, p * p, vis, 1024);
            let want = brute_force(n_dot_v, p * p, vis);
            for c in 0..2 {
                assert!(
                    (got[c] - want[c]).abs() < TOLERANCE,
                    "{vis:?} n.v {n_dot_v} r {p}: {got:?} vs {want:?}"
                );
            }
        }
    }
}

/// Facing and smooth: all of `F0` comes back (`A = 1`, `B = 0`); the
/// albedo `A + B` falls with roughness and towards grazing.
#[test]
fn the_limits_are_the_closed_forms() {
    let [a, b] = dfg(1.0, 1e-4, MaskingShadowing::HeightCorrelated, 1024);
    assert!((a - 1.0).abs() < 1e-3 && b.abs() < 1e-3, "{a} {b}");
    // Smooth at any angle: the mirror, A + B = 1, B = (1 - n.v)^5.
    let n_dot_v: f64 = 0.3;
    let [a, b] = dfg(n_dot_v, 1e-4, MaskingShadowing::HeightCorrelated, 1024);
    assert!((a + b - 1.0).abs() < 2e-3, "{a} {b}");
    assert!((b - (1.0 - n_dot_v).powi(5)).abs() < 2e-3, "{b}");
    // alpha = 1: D = 1/π and the height-correlated V = 1 / (2 (n.v + n.l)),
    // so A + B = ∫ μ / (n.v + μ) dμ = 1 - n.v ln((1 + n.v) / n.v).
    for n_dot_v in [0.9f64, 0.5, 0.1] {
        // At grazing 1024 samples are 0.7% off; 16384 converge.
        let [a, b] = dfg(n_dot_v, 1.0, MaskingShadowing::HeightCorrelated, 16384);
        let want = 1.0 - n_dot_v * ((1.0 + n_dot_v) / n_dot_v).ln();
        assert!(
            (a + b - want).abs() < 2e-3,
            "n.v {n_dot_v}: {} vs {want}",
            a + b
        );
    }
}

/// Karis' fit follows the table loosely: close enough that swapped axes,
/// channels or a flipped roughness would fail.
#[test]
fn karis_fit_follows_the_table() {
    /// The mobile fit is crude: measured up to 0.176 below the table's `A`
    /// near `n·v = 1` at middle roughness, 0.173 at grazing.
    const LOOSE: f64 = 0.2;
    let table = DfgTable::for_engine(TargetEngine::Unreal, 16, 512);
    assert_eq!(table.form, DfgForm::ScaleBias);
    let mut sum = 0.0;
    for y in 0..16 {
        for x in 0..16 {
            let got = table.values[y * 16 + x];
            let fit = dfg_karis_approx(table.n_dot_v(x), table.perceptual(y));
            for c in 0..2 {
                assert!(
                    (got[c] - fit[c]).abs() < LOOSE,
                    "({x},{y}): {got:?} vs {fit:?}"
                );
                sum += (got[c] - fit[c]).abs();
            }
        }
    }
    // On average much closer (measured mean 0.04).
    assert!(sum / 512.0 < 0.06, "{}", sum / 512.0);
}

/// Filament's multiscatter table holds `(B, A + B)` of the same integral.
#[test]
fn the_multiscatter_form_is_bias_and_albedo() {
    let table = DfgTable::for_engine(TargetEngine::Filament, 8, 256);
    assert_eq!(table.form, DfgForm::Multiscatter);
    for (i, got) in table.values.iter().enumerate() {
        let (x, y) = (i % 8, i / 8);
        let p = table.perceptual(y);
        let [a, b] = dfg(
            table.n_dot_v(x),
            p * p,
            MaskingShadowing::HeightCorrelated,
            256,
        );
        assert_eq!(*got, [b, a + b]);
    }
    // The top row is the roughest.
    assert!(table.values[0][1] < table.values[7 * 8][1]);
}
