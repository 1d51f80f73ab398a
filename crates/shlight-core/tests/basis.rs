//! The real SH basis: orthonormality, the addition theorem, the hard-coded
//! forms against the recurrence, and agreement with closed forms.

use std::f64::consts::PI;

use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use shlight_core::sh::{
    Legendre, ShBasis, SphereQuadrature, gauss_legendre, legendre_count, legendre_index,
    legendre_polynomials, sh_count, sh_index,
};

/// Gram error allowed at lmax 256: the recurrence loses about l * eps per degree.
const GRAM_TOL_256: f64 = 1e-12;
/// Gram error allowed at lmax 2048 (the reference measured 1.4e-10 at 2048).
const GRAM_TOL_2048: f64 = 1e-10;
/// Hard-coded vs recurrence in f64: a few ulps of values of order 1.
const HARDCODED_TOL_F64: f64 = 1e-13;
/// Hard-coded vs recurrence in f32.
const HARDCODED_TOL_F32: f32 = 1e-6;

fn random_unit(rng: &mut StdRng) -> [f64; 3] {
    loop {
        let v = [
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0f64..1.0),
        ];
        let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        if n > 0.1 && n <= 1.0 {
            return [v[0] / n, v[1] / n, v[2] / n];
        }
    }
}

/// max |G_m - I| of the Legendre columns `m` in `ms`, where
/// `G_m[l, l'] = 2 pi sum_j w_j Pbar_l^m(x_j) Pbar_l'^m(x_j)` on `lmax+1`
/// Gauss-Legendre nodes (exact for these polynomials of degree <= 2 lmax).
/// Since `int Y_l^m Y_l'^m = 2 pi int Pbar_l^m Pbar_l'^m dx` for every m, this
/// is the Gram matrix of the SH of order m.
fn legendre_gram_error(lmax: usize, ms: &[usize]) -> f64 {
    let (xs, ws) = gauss_legendre(lmax + 1);
    let leg = Legendre::<f64>::new(lmax);
    let mut p = vec![0.0; legendre_count(lmax)];
    let mut grams: Vec<Vec<f64>> = ms
        .iter()
        .map(|&m| vec![0.0; (lmax + 1 - m).pow(2)])
        .collect();
    let mut col = vec![0.0; lmax + 1];
    for (&x, &w) in xs.iter().zip(&ws) {
        leg.eval(x, &mut p);
        for (g, &m) in grams.iter_mut().zip(ms) {
            let n = lmax + 1 - m;
            for (i, l) in (m..=lmax).enumerate() {
                col[i] = p[legendre_index(l, m)];
            }
            for i in 0..n {
                let a = 2.0 * PI * w * col[i];
                let row = &mut g[i * n..i * n + n];
                for j in i..n {
                    row[j] += a * col[j];
                }
            }
        }
    }
    let mut worst = 0.0f64;
    for (g, &m) in grams.iter().zip(ms) {
        let n = lmax + 1 - m;
        for i in 0..n {
            for j in i..n {
                let want = if i == j { 1.0 } else { 0.0 };
                worst = worst.max((g[i * n + j] - want).abs());
            }
        }
    }
    worst
}

#[test]
fn legendre_columns_are_orthonormal_at_lmax_256_for_every_m() {
    let ms: Vec<usize> = (0..=256).collect();
    let err = legendre_gram_error(256, &ms);
    eprintln!("lmax 256, every m: max |Gram - I| = {err:e}");
    assert!(err <= GRAM_TOL_256, "max |Gram - I| = {err:e}");
}

#[test]
fn legendre_columns_are_orthonormal_at_lmax_2048() {
    // Every m would cost 1e13 operations; these columns include the zonal
    // (longest), low, middle, near-sectoral and sectoral ones, where
    // underflow handling matters most.
    let err = legendre_gram_error(2048, &[0, 700, 1500, 2040, 2048]);
    eprintln!("lmax 2048: max |Gram - I| = {err:e}");
    assert!(err <= GRAM_TOL_2048, "max |Gram - I| = {err:e}");
}

#[test]
fn full_basis_is_orthonormal_under_exact_sphere_quadrature() {
    // The full Gram matrix, azimuth recurrence included: quadrature exact to
    // degree 2 lmax.
    let lmax = 40;
    let q = SphereQuadrature::exact_to_degree(2 * lmax);
    let basis = ShBasis::<f64>::new(lmax);
    let n = basis.count();
    let mut y = vec![0.0; n];
    let mut gram = vec![0.0; n * n];
    for (d, &w) in q.directions.iter().zip(&q.weights) {
        basis.eval(*d, &mut y);
        for i in 0..n {
            let a = w * y[i];
            for j in i..n {
                gram[i * n + j] += a * y[j];
            }
        }
    }
    let mut worst = 0.0f64;
    for i in 0..n {
        for j in i..n {
            worst = worst.max((gram[i * n + j] - if i == j { 1.0 } else { 0.0 }).abs());
        }
    }
    eprintln!("full basis, lmax {lmax}: max |Gram - I| = {worst:e}");
    assert!(worst <= GRAM_TOL_256, "max |Gram - I| = {worst:e}");
}

#[test]
fn addition_theorem_holds() {
    // sum_m Y_l^m(a) Y_l^m(b) = (2l+1)/(4 pi) P_l(a . b)
    let mut rng = StdRng::seed_from_u64(7);
    for &(lmax, tol) in &[(64usize, 1e-12), (1000, 1e-10)] {
        let basis = ShBasis::<f64>::new(lmax);
        let mut ya = vec![0.0; basis.count()];
        let mut yb = vec![0.0; basis.count()];
        for _ in 0..20 {
            let a = random_unit(&mut rng);
            let b = random_unit(&mut rng);
            basis.eval(glam::DVec3::from(a), &mut ya);
            basis.eval(glam::DVec3::from(b), &mut yb);
            let p = legendre_polynomials(lmax, a[0] * b[0] + a[1] * b[1] + a[2] * b[2]);
            for l in 0..=lmax {
                let s: f64 = (l * l..(l + 1) * (l + 1)).map(|i| ya[i] * yb[i]).sum();
                let want = (2 * l + 1) as f64 / (4.0 * PI) * p[l];
                let scale = (2 * l + 1) as f64 / (4.0 * PI);
                assert!(
                    (s - want).abs() <= tol * scale,
                    "lmax {lmax} l {l}: {s} vs {want}"
                );
            }
        }
    }
}

#[test]
fn azimuth_recurrence_matches_trigonometry_at_high_degree() {
    let lmax = 1500;
    let basis = ShBasis::<f64>::new(lmax);
    let leg = Legendre::<f64>::new(lmax);
    let mut y = vec![0.0; sh_count(lmax)];
    let mut p = vec![0.0; legendre_count(lmax)];
    let mut rng = StdRng::seed_from_u64(3);
    for _ in 0..4 {
        let d = random_unit(&mut rng);
        basis.eval(glam::DVec3::from(d), &mut y);
        leg.eval(d[2], &mut p);
        let phi = d[1].atan2(d[0]);
        let mut worst = 0.0f64;
        for l in (0..=lmax).step_by(13) {
            for m in 0..=l {
                let pl = p[legendre_index(l, m)];
                let (c, s) = if m == 0 {
                    (pl, 0.0)
                } else {
                    (
                        2f64.sqrt() * pl * (m as f64 * phi).cos(),
                        2f64.sqrt() * pl * (m as f64 * phi).sin(),
                    )
                };
                worst = worst.max((y[sh_index(l, m as isize)] - c).abs());
                if m > 0 {
                    worst = worst.max((y[sh_index(l, -(m as isize))] - s).abs());
                }
            }
        }
        // Values are up to ~sqrt((2l+1)/(2 pi)) ~ 15; trig of m phi for m ~ 1500
        // itself carries ~1e-13 of argument error.
        assert!(worst < 1e-10, "{worst:e}");
    }
}

#[test]
fn low_degree_forms_match_the_recurrence() {
    // ShBasis uses the hard-coded polynomials for lmax <= 4 and the general
    // recurrence above; compare the first 25 values.
    let hard64 = ShBasis::<f64>::new(4);
    let rec64 = ShBasis::<f64>::new(5);
    let hard32 = ShBasis::<f32>::new(4);
    let rec32 = ShBasis::<f32>::new(5);
    let mut rng = StdRng::seed_from_u64(11);
    let mut dirs: Vec<[f64; 3]> = (0..500).map(|_| random_unit(&mut rng)).collect();
    dirs.extend([
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
    ]);
    let (mut a, mut b) = (vec![0.0; 36], vec![0.0; 36]);
    let (mut a32, mut b32) = (vec![0.0f32; 36], vec![0.0f32; 36]);
    for d in dirs {
        hard64.eval(glam::DVec3::from(d), &mut a);
        rec64.eval(glam::DVec3::from(d), &mut b);
        let d32 = [d[0] as f32, d[1] as f32, d[2] as f32];
        hard32.eval(glam::Vec3::from(d32), &mut a32);
        rec32.eval(glam::Vec3::from(d32), &mut b32);
        for i in 0..25 {
            assert!(
                (a[i] - b[i]).abs() <= HARDCODED_TOL_F64,
                "f64 i={i} d={d:?}: {} vs {}",
                a[i],
                b[i]
            );
            assert!(
                (a32[i] - b32[i]).abs() <= HARDCODED_TOL_F32,
                "f32 i={i} d={d:?}"
            );
            assert!((a32[i] as f64 - a[i]).abs() <= 2e-6, "f32 vs f64 i={i}");
        }
    }
}

#[test]
fn bands_one_and_two_match_their_closed_forms() {
    let mut rng = StdRng::seed_from_u64(5);
    let basis = ShBasis::<f64>::new(2);
    let mut y = vec![0.0; 9];
    let k1 = (3.0 / (4.0 * PI)).sqrt();
    let k2 = (15.0 / (4.0 * PI)).sqrt();
    let k20 = (5.0 / (16.0 * PI)).sqrt();
    for _ in 0..100 {
        let [x, yy, z] = random_unit(&mut rng);
        basis.eval(glam::DVec3::from([x, yy, z]), &mut y);
        let want = [
            1.0 / (2.0 * PI.sqrt()),
            -k1 * yy,
            k1 * z,
            -k1 * x,
            k2 * x * yy,
            -k2 * yy * z,
            k20 * (3.0 * z * z - 1.0),
            -k2 * x * z,
            k2 / 2.0 * (x * x - yy * yy),
        ];
        for i in 0..9 {
            assert!((y[i] - want[i]).abs() < 1e-15, "i={i}");
        }
    }
    assert!((k1 - 0.488603).abs() < 1e-6);
}

#[test]
fn f32_batch_tracks_f64_scalar() {
    let mut rng = StdRng::seed_from_u64(9);
    let dirs: Vec<[f64; 3]> = (0..100).map(|_| random_unit(&mut rng)).collect();
    for lmax in [2usize, 8, 16, 64] {
        let b64 = ShBasis::<f64>::new(lmax);
        let b32 = ShBasis::<f32>::new(lmax);
        let n = dirs.len();
        let x: Vec<f32> = dirs.iter().map(|d| d[0] as f32).collect();
        let y: Vec<f32> = dirs.iter().map(|d| d[1] as f32).collect();
        let z: Vec<f32> = dirs.iter().map(|d| d[2] as f32).collect();
        let mut out = vec![0.0f32; b32.count() * n];
        b32.eval_batch(&x, &y, &z, &mut out);
        let mut one = vec![0.0; b64.count()];
        for (k, d) in dirs.iter().enumerate() {
            // Compare at the rounded direction so only evaluation error counts.
            let dr = [x[k] as f64, y[k] as f64, z[k] as f64];
            let nrm = (dr[0] * dr[0] + dr[1] * dr[1] + dr[2] * dr[2]).sqrt();
            b64.eval(
                glam::DVec3::from([dr[0] / nrm, dr[1] / nrm, dr[2] / nrm]),
                &mut one,
            );
            for i in 0..b64.count() {
                let tol = 1e-6 * (lmax as f64 + 1.0);
                assert!(
                    (out[i * n + k] as f64 - one[i]).abs() < tol,
                    "lmax {lmax} i {i} {d:?}"
                );
            }
        }
    }
}
