//! The accuracy suite: every oracle through every method, compared with
//! its analytic irradiance at [`NORMALS`] Fibonacci-sphere normals.
//!
//! # Two error sources, measured apart
//!
//! - **Truncation** (method `truncation`): the oracle's SH irradiance
//!   truncated at `lmax`, from its closed-form zonal coefficients
//!   ([`Oracle::truncated`]), against its closed-form `E`. Bound: the tail
//!   of the zonal series ([`Oracle::truncation_bound`]), and
//!   [`BAND_LIMITED_TOL`] for band-limited oracles from their band on.
//! - **Projection** (methods `quadrature-equirect`, `quadrature-cross`,
//!   `mc-SAMPLER`): SH irradiance of the projected coefficients against the
//!   truncated irradiance at the same `lmax`, so truncation does not count.
//!   Quadrature runs on the oracle rendered as a map of texel means
//!   ([`crate::render::render_texel_means`]) at several resolutions;
//!   Monte Carlo integrates the oracle's radiance function itself (an
//!   infinitely fine map, so that what is measured is the sampling error
//!   alone, not the map's), with each sampler at several
//!   sample counts and [`MC_SEEDS`] seeds.
//!
//! # Bounds
//!
//! - Quadrature (a bound that holds at every resolution): with
//!   `K_n(ω) = Σ_{l≤lmax} A_l (2l+1)/(4π) P_l(n·ω)` (the truncated cosine
//!   kernel), the texel-centre rule errs by at most
//!   `Σ_texels Ω osc_texel(L K_n)`. With `r` the largest distance from a
//!   texel's centre to its points (equirect `(π/H + 2π/W)/2`, cube
//!   `√2/f`), `|K| ≤ K0 = Σ|A_l|(2l+1)/(4π)` and, by Bernstein's
//!   inequality, `|∂K/∂γ| ≤ K1 = Σ|A_l|(2l+1) l/(4π)`:
//!   `|ΔE| ≤ (S + 4ℓr + 4πr²) L_max K1 r + 4π |∇L| K0 r + L_max K0 (4ℓr + 4πr²)`
//!   for support area `S`, edge length `ℓ`; the last term counts texels
//!   within `2r` of an edge (it holds for point samples; texel means only
//!   make the error smaller). It is `O(h)`; the measured error falls
//!   faster (see the rates).
//! - Monte Carlo: three reported standard errors carried to irradiance by
//!   the triangle inequality, `3 Σ |A_l Y_l^m(n)| se_l^m` (valid whatever
//!   the correlation between coefficients), at the worst normal.
//!
//! # Rates (fitted `ln error` against `ln resolution` or `ln samples`)
//!
//! - Quadrature of smooth radiance (sphere, gradient) and of the
//!   hemisphere about the map's up axis (its edge lies on a row boundary,
//!   so every texel is wholly lit or dark): the midpoint rule's `h²`,
//!   error `∝ W^-2`, accepted slope [`SMOOTH_RATE`].
//! - Quadrature of radiance with edges across texels (caps, polygons),
//!   rendered as texel means: a texel the edge crosses holds the right
//!   mean but weighs it by `Y` at its centre, not at the centroid of its
//!   lit part, an `O(h)` error on each of the `O(1/h)` edge texels of area
//!   `h²`: `O(h²)` again, plus the random coverage error of the jittered
//!   texel means, `O(h^1.5)` with a small constant. Accepted
//!   [`EDGE_RATE`] (measured -1.86 to -2.05 on equirect maps, -1.57 to
//!   -2.01 on crosses; point samples at texel centres instead gave -0.6 to
//!   -3.4, as edge texels fall in or out whole).
//! - Monte Carlo, uniform and importance: independent samples,
//!   `N^-1/2`, accepted [`IID_RATE`]. Stratified and Sobol
//!   (Owen-scrambled) converge faster (`N^-3/4` for radiance with edges,
//!   faster for smooth); accepted [`QMC_RATE`] (at least as fast as
//!   `N^-0.6`).

use std::f64::consts::PI;

use glam::DVec3;
use shlight_core::map::montecarlo::{
    ImportanceGrid, McOptions, Sampler, SamplerKind, project_montecarlo,
};
use shlight_core::map::{EnvMap, Layout, MapOrientation, project_map};
use shlight_core::sh::{ShBasis, ShCoeffs, clamped_cosine_eigenvalue, fibonacci_sphere};

use crate::error::{ErrorStats, log_log_slope, peak, relative_to_peak};
use crate::oracle::{Oracle, Shape, Truncated, suite_oracles};
use crate::render::{render_texel_means, texel_radius};

/// Normals at which every case is evaluated (Fibonacci sphere).
pub const NORMALS: usize = 1000;
/// Band-limited oracles at or above their band: truncation error allowed
/// (relative to the peak): rounding only, far below this.
pub const BAND_LIMITED_TOL: f64 = 1e-6;
/// Equirect rows from which band-limited oracles (sphere, hemisphere,
/// gradient) are held to [`BAND_LIMITED_TOL`]: the midpoint rule's `h²`
/// error, 2e-4..9e-4 at 64x32, falls below 1e-6 at 2048x1024.
pub const BAND_LIMITED_ROWS: usize = 1024;
/// Accepted slope of quadrature error against map width, smooth radiance.
pub const SMOOTH_RATE: (f64, f64) = (-2.3, -1.7);
/// Accepted slope of quadrature error against map width, radiance with
/// edges across texels.
pub const EDGE_RATE: (f64, f64) = (-2.4, -1.4);
/// Accepted slope of Monte Carlo error against samples, independent samples.
pub const IID_RATE: (f64, f64) = (-0.6, -0.4);
/// Accepted slope of Monte Carlo error against samples, stratified / Sobol.
pub const QMC_RATE: (f64, f64) = (-2.0, -0.6);
/// Seeds per Monte Carlo case; errors are averaged over them.
pub const MC_SEEDS: u64 = 16;
/// lmax of the projection cases (the 9-term irradiance).
pub const PROJECTION_LMAX: usize = 2;

/// What to run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SuiteOptions {
    /// A subset that runs in a few seconds: fewer lmax, resolutions up to
    /// 512x256, cube faces up to 64, Monte Carlo up to 2^16 samples.
    pub quick: bool,
}

impl SuiteOptions {
    fn truncation_lmax(self) -> &'static [usize] {
        if self.quick {
            &[1, 2, 4]
        } else {
            &[1, 2, 4, 8, 16]
        }
    }
    fn equirect_widths(self) -> &'static [usize] {
        if self.quick {
            &[64, 128, 256, 512]
        } else {
            &[64, 128, 256, 512, 1024, 2048]
        }
    }
    fn cube_faces(self) -> &'static [usize] {
        if self.quick {
            &[16, 32, 64]
        } else {
            &[16, 32, 64, 128, 256]
        }
    }
    fn mc_samples(self) -> Vec<usize> {
        let top = if self.quick { 16 } else { 18 };
        (10..=top).step_by(2).map(|k| 1usize << k).collect()
    }
    fn mc_oracles(self) -> &'static [&'static str] {
        if self.quick {
            &["cap30-el10", "sky-gradient"]
        } else {
            &["cap30-el10", "quad-horizon", "sky-gradient"]
        }
    }
}

/// One line of the report.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// Oracle name.
    pub case: String,
    /// `truncation`, `quadrature-equirect`, `quadrature-cross`, `mc-SAMPLER`.
    pub method: String,
    /// Map size `W x H` (quadrature).
    pub resolution: Option<(usize, usize)>,
    /// Monte Carlo samples used.
    pub samples: Option<usize>,
    /// Highest SH degree.
    pub lmax: usize,
    /// Mean relative irradiance error over the normals (relative to the
    /// peak irradiance, [`crate::error`]).
    pub mean_rel_err: f64,
    /// Largest relative irradiance error over the normals.
    pub max_rel_err: f64,
    /// Root-mean-square relative error over the normals (and seeds), to
    /// which the rates are fitted.
    pub rms_rel_err: f64,
    /// The bound `max_rel_err` is held to; `None` where none is known (the
    /// polygons' truncation).
    pub bound: Option<f64>,
    /// Fitted slope of the row's sweep (error against resolution or
    /// samples), shared by the rows of one sweep.
    pub slope: Option<f64>,
    /// The accepted range of `slope`.
    pub slope_range: Option<(f64, f64)>,
    /// Monte Carlo on zonal oracles: the largest `|error| / se` of a
    /// coefficient, over all seeds.
    pub max_z: Option<f64>,
    /// Monte Carlo on zonal oracles: the fraction of coefficients (over all
    /// seeds) whose error exceeds 3 reported standard errors.
    pub frac_z_over_3: Option<f64>,
    /// `max_rel_err <= bound` and the slope within its range. A Monte
    /// Carlo row's errors and bound are those of its first seed (the
    /// estimate held to its own reported standard errors); its
    /// `rms_rel_err`, slope and z-scores pool all [`MC_SEEDS`] seeds.
    pub pass: bool,
}

impl Row {
    /// The resolution or sample count as printed: `512x256`, `65536`, `-`.
    #[must_use]
    pub fn setting(&self) -> String {
        match (self.resolution, self.samples) {
            (Some((w, h)), _) => format!("{w}x{h}"),
            (None, Some(n)) => n.to_string(),
            _ => "-".into(),
        }
    }

    /// The row as a JSON object: `case`, `method`, `lmax`, `mean_rel_err`,
    /// `max_rel_err`, `bound`, `pass`, and `rms_rel_err`, `resolution` (`[W, H]`),
    /// `samples`, `slope`, `slope_range`, `max_z`, `frac_z_over_3` (each `null` where it
    /// does not apply).
    #[must_use]
    pub fn to_json(&self) -> serde_json::Value {
        serde_json::json!({
            "case": self.case,
            "method": self.method,
            "resolution": self.resolution.map(|(w, h)| [w, h]),
            "samples": self.samples,
            "lmax": self.lmax,
            "mean_rel_err": self.mean_rel_err,
            "max_rel_err": self.max_rel_err,
            "rms_rel_err": self.rms_rel_err,
            "bound": self.bound,
            "slope": self.slope,
            "slope_range": self.slope_range.map(|(a, b)| [a, b]),
            "max_z": self.max_z,
            "frac_z_over_3": self.frac_z_over_3,
            "pass": self.pass,
        })
    }
}

/// The error curve of one sweep, for plots.
#[derive(Clone, Debug, PartialEq)]
pub struct Sweep {
    /// Oracle name.
    pub case: String,
    /// Method (as in [`Row::method`]).
    pub method: String,
    /// Map width or samples.
    pub x: Vec<f64>,
    /// Root-mean-square relative error at each `x` (what the slope is
    /// fitted to).
    pub rms: Vec<f64>,
    /// Fitted slope.
    pub slope: Option<f64>,
}

/// Error against lmax for one oracle, for plots.
#[derive(Clone, Debug, PartialEq)]
pub struct LmaxCurve {
    /// Oracle name.
    pub case: String,
    /// Degrees.
    pub lmax: Vec<usize>,
    /// Mean truncation error at each lmax.
    pub truncation: Vec<f64>,
    /// Mean projection error of a `WxH` equirect quadrature at each lmax.
    pub quadrature: Vec<f64>,
    /// The quadrature's map size.
    pub resolution: (usize, usize),
    /// Mean projection error of Sobol Monte Carlo at each lmax.
    pub montecarlo: Vec<f64>,
    /// The Monte Carlo sample count.
    pub samples: usize,
}

/// Everything the suite measured.
#[derive(Clone, Debug, Default)]
pub struct Report {
    /// The table.
    pub rows: Vec<Row>,
    /// Resolution and sample sweeps.
    pub sweeps: Vec<Sweep>,
    /// Error against lmax.
    pub lmax_curves: Vec<LmaxCurve>,
}

impl Report {
    /// Whether every row passed.
    #[must_use]
    pub fn pass(&self) -> bool {
        self.rows.iter().all(|r| r.pass)
    }
}

/// The normals of the suite: [`NORMALS`] Fibonacci-sphere points.
#[must_use]
pub fn normals() -> Vec<DVec3> {
    fibonacci_sphere(NORMALS).into_iter().collect()
}

/// An oracle with its reference values at the normals.
struct Case {
    oracle: Oracle,
    exact: Vec<f64>,
    peak: f64,
    /// The irradiance truncated at [`PROJECTION_LMAX`] at the normals: what
    /// the quadrature and Monte Carlo sweeps are measured against.
    projection_reference: Vec<f64>,
}

impl Case {
    fn new(oracle: Oracle, normals: &[DVec3]) -> Self {
        let exact: Vec<f64> = normals.iter().map(|n| oracle.irradiance(*n)).collect();
        let peak = peak(&exact);
        let truncated = oracle.truncated(PROJECTION_LMAX);
        let projection_reference = normals.iter().map(|n| truncated.eval(*n)).collect();
        Self {
            oracle,
            exact,
            peak,
            projection_reference,
        }
    }

    fn truncated_at(&self, t: &Truncated, normals: &[DVec3]) -> Vec<f64> {
        normals.iter().map(|n| t.eval(*n)).collect()
    }

    /// Errors of `estimate` against `reference`, relative to the oracle's
    /// peak irradiance.
    fn errors(&self, estimate: &[f64], reference: &[f64]) -> ErrorStats {
        // relative_to_peak uses the reference's own peak; scale to the
        // exact peak instead (the truncated one may differ slightly).
        let s = relative_to_peak(estimate, reference);
        let k = peak(reference) / self.peak;
        ErrorStats {
            mean: s.mean * k,
            max: s.max * k,
            rms: s.rms * k,
        }
    }
}

/// The truncated cosine kernel's `K0 = Σ|A_l|(2l+1)/(4π)` and
/// `K1 = Σ|A_l|(2l+1) l/(4π)` (suite docs).
fn kernel_bounds(lmax: usize) -> (f64, f64) {
    (0..=lmax).fold((0.0, 0.0), |(k0, k1), l| {
        let a = clamped_cosine_eigenvalue(l).abs() * (2 * l + 1) as f64 / (4.0 * PI);
        (k0 + a, k1 + a * l as f64)
    })
}

/// Support area of the oracle's radiance (steradians).
fn support_area(o: &Oracle) -> f64 {
    match &o.shape {
        Shape::Cap { half_angle, .. } => 2.0 * PI * (1.0 - half_angle.cos()),
        Shape::Polygon { vertices } => {
            // Girard: the sum of interior angles minus (n - 2) π.
            let n = vertices.len();
            let angle: f64 = (0..n)
                .map(|i| {
                    let (p, v, q) = (
                        vertices[(i + n - 1) % n],
                        vertices[i],
                        vertices[(i + 1) % n],
                    );
                    let a = (p - v * v.dot(p)).normalize();
                    let b = (q - v * v.dot(q)).normalize();
                    a.dot(b).clamp(-1.0, 1.0).acos()
                })
                .sum();
            angle - (n as f64 - 2.0) * PI
        }
        _ => 4.0 * PI,
    }
}

/// The quadrature bound of the suite docs, relative to `peak`, for texels
/// whose points lie within `r` of their centre.
fn quadrature_bound(o: &Oracle, lmax: usize, r: f64, peak: f64) -> f64 {
    let (k0, k1) = kernel_bounds(lmax);
    let (l_max, grad) = o.radiance_bounds();
    let edge = o.edge_length();
    let tube = 4.0 * edge * r + 4.0 * PI * r * r;
    let area = (support_area(o) + tube).min(4.0 * PI);
    (area * l_max * k1 * r + 4.0 * PI * grad * k0 * r + l_max * k0 * tube) / peak
}

/// SH irradiance of radiance coefficients `l` at the normals.
fn sh_irradiance(l: &ShCoeffs<f64>, normals: &[DVec3]) -> Vec<f64> {
    let e = shlight_core::sh::irradiance(l);
    normals.iter().map(|n| e.eval(*n)).collect()
}

/// Runs the suite; `progress` is told what runs next.
#[must_use]
pub fn run(options: SuiteOptions, progress: &dyn Fn(&str)) -> Report {
    let normals = normals();
    let cases: Vec<Case> = suite_oracles()
        .into_iter()
        .map(|o| Case::new(o, &normals))
        .collect();
    let mut report = Report::default();
    for case in &cases {
        progress(&format!("truncation: {}", case.oracle.name));
        truncation_rows(case, options, &normals, &mut report);
    }
    for case in cases.iter().filter(|c| c.oracle.renderable()) {
        progress(&format!("quadrature: {}", case.oracle.name));
        quadrature_sweep(case, Layout::Equirect, options, &normals, &mut report);
        quadrature_sweep(
            case,
            Layout::CrossHorizontal,
            options,
            &normals,
            &mut report,
        );
    }
    for name in options.mc_oracles() {
        let case = cases
            .iter()
            .find(|c| c.oracle.name == *name)
            .expect("a suite oracle");
        for sampler in SamplerKind::ALL {
            progress(&format!("monte carlo ({sampler}): {name}"));
            mc_sweep(case, sampler, options, &normals, &mut report);
        }
    }
    for name in ["directional", "cap30-el10"] {
        let case = cases
            .iter()
            .find(|c| c.oracle.name == name)
            .expect("a suite oracle");
        progress(&format!("error against lmax: {name}"));
        report.lmax_curves.push(lmax_curve(case, options, &normals));
    }
    report
}

fn truncation_rows(case: &Case, options: SuiteOptions, normals: &[DVec3], report: &mut Report) {
    let o = &case.oracle;
    for &lmax in options.truncation_lmax() {
        let t = o.truncated(lmax);
        let est = case.truncated_at(&t, normals);
        let e = case.errors(&est, &case.exact);
        let bound = o.truncation_bound(lmax).map(|b| {
            if o.band_limit().is_some_and(|b| b <= lmax) {
                BAND_LIMITED_TOL
            } else {
                b / case.peak
            }
        });
        report.rows.push(Row {
            case: o.name.clone(),
            method: "truncation".into(),
            resolution: None,
            samples: None,
            lmax,
            mean_rel_err: e.mean,
            max_rel_err: e.max,
            rms_rel_err: e.rms,
            bound,
            slope: None,
            slope_range: None,
            max_z: None,
            frac_z_over_3: None,
            pass: bound.is_none_or(|b| e.max <= b),
        });
    }
}

fn quadrature_sweep(
    case: &Case,
    layout: Layout,
    options: SuiteOptions,
    normals: &[DVec3],
    report: &mut Report,
) {
    let o = &case.oracle;
    let lmax = PROJECTION_LMAX;
    let reference = &case.projection_reference;
    let sizes: Vec<(usize, usize)> = match layout {
        Layout::Equirect => options
            .equirect_widths()
            .iter()
            .map(|&w| (w, w / 2))
            .collect(),
        _ => options
            .cube_faces()
            .iter()
            .map(|&f| layout.dimensions(f))
            .collect(),
    };
    let method = if layout == Layout::Equirect {
        "quadrature-equirect"
    } else {
        "quadrature-cross"
    };
    // The cube rule integrates polynomials of degree <= 3 exactly (its
    // weights sum to 4π and the cube's symmetries make x², y², z² equal and
    // odd terms cancel), so a radiance of degree <= 1 times Y of degree <= 2
    // is projected without error: only f32 rounding is left.
    let exact_rule =
        layout != Layout::Equirect && o.radiance_degree().is_some_and(|d| d + lmax <= 3);
    let first = report.rows.len();
    let mut x = Vec::new();
    let mut mean = Vec::new();
    for (w, h) in sizes {
        let px = render_texel_means(o, layout, w, h);
        let map = EnvMap::new(layout, MapOrientation::default(), w, h, &px).expect("fits");
        let l = project_map(&map, lmax).channel(0);
        let e = case.errors(&sh_irradiance(&l, normals), reference);
        let mut bound = quadrature_bound(o, lmax, texel_radius(layout, w, h), case.peak);
        if exact_rule || (o.band_limit().is_some() && h >= BAND_LIMITED_ROWS) {
            bound = bound.min(BAND_LIMITED_TOL);
        }
        x.push(w as f64);
        mean.push(e.rms);
        report.rows.push(Row {
            case: o.name.clone(),
            method: method.into(),
            resolution: Some((w, h)),
            samples: None,
            lmax,
            mean_rel_err: e.mean,
            max_rel_err: e.max,
            rms_rel_err: e.rms,
            bound: Some(bound),
            slope: None,
            slope_range: None,
            max_z: None,
            frac_z_over_3: None,
            pass: e.max <= bound,
        });
    }
    // Exact rules leave rounding, which has no rate.
    let range = if exact_rule {
        None
    } else if o.smooth() || o.band_limit().is_some() {
        Some(SMOOTH_RATE)
    } else {
        Some(EDGE_RATE)
    };
    finish_sweep(report, first, o, method, x, mean, range);
}

/// Sets the slope of rows `first..` and records the sweep.
fn finish_sweep(
    report: &mut Report,
    first: usize,
    o: &Oracle,
    method: &str,
    x: Vec<f64>,
    mean: Vec<f64>,
    range: Option<(f64, f64)>,
) {
    let slope = range.and_then(|_| log_log_slope(&x, &mean));
    for row in &mut report.rows[first..] {
        row.slope = slope;
        row.slope_range = range;
        if let (Some(s), Some((lo, hi))) = (slope, range) {
            row.pass &= (lo..=hi).contains(&s);
        }
    }
    report.sweeps.push(Sweep {
        case: o.name.clone(),
        method: method.into(),
        x,
        rms: mean,
        slope,
    });
}

/// The oracle's radiance as the (grey) function Monte Carlo integrates.
fn radiance_fn(o: &Oracle) -> impl Fn(DVec3) -> DVec3 + Sync + '_ {
    move |d| DVec3::splat(o.radiance(d))
}

/// One Monte Carlo estimate: relative errors, the bound from its standard
/// errors, and the largest coefficient z-score (zonal oracles).
struct McOutcome {
    errors: ErrorStats,
    samples: usize,
    bound: f64,
    /// `|error| / se` of each coefficient with `se > 0` (zonal oracles).
    z: Option<Vec<f64>>,
}

fn mc_once(case: &Case, options: &McOptions, normals: &[DVec3], reference: &[f64]) -> McOutcome {
    let o = &case.oracle;
    let f = radiance_fn(o);
    let est = project_montecarlo(&f, options);
    let (l, se) = (est.coeffs.channel(0), est.std_error.channel(0));
    let e = case.errors(&sh_irradiance(&l, normals), reference);
    let lmax = options.lmax;
    let a: Vec<f64> = (0..=lmax).map(clamped_cosine_eigenvalue).collect();
    // sigma(n) = sum_i |A_l Y_i(n)| se_i, at its largest over the normals.
    let weights: Vec<f64> = (0..se.len())
        .map(|i| a[shlight_core::sh::lm_from_index(i).0].abs() * se[i])
        .collect();
    let basis = ShBasis::<f64>::new(lmax);
    let mut y = vec![0.0; basis.count()];
    let mut sigma = 0.0f64;
    for n in normals {
        basis.eval(*n, &mut y);
        sigma = sigma.max(
            y.iter()
                .zip(&weights)
                .map(|(y, w)| y.abs() * w)
                .sum::<f64>(),
        );
    }
    let z = o.coefficients(lmax).map(|exact| {
        (0..exact.len())
            .filter(|&i| se[i] > 0.0)
            .map(|i| (l[i] - exact[i]).abs() / se[i])
            .collect()
    });
    McOutcome {
        errors: e,
        samples: est.samples,
        bound: 3.0 * sigma / case.peak,
        z,
    }
}

fn mc_sweep(
    case: &Case,
    kind: SamplerKind,
    options: SuiteOptions,
    normals: &[DVec3],
    report: &mut Report,
) {
    let o = &case.oracle;
    let lmax = PROJECTION_LMAX;
    let reference = &case.projection_reference;
    let sampler = kind
        .sampler(|| ImportanceGrid::from_fn(128, 64, MapOrientation::default(), |d| o.radiance(d)));
    let method = format!("mc-{kind}");
    let first = report.rows.len();
    let (mut x, mut mean) = (Vec::new(), Vec::new());
    for n in options.mc_samples() {
        let mut outcomes = Vec::new();
        let mut used = n;
        for seed in 0..MC_SEEDS {
            let opts = McOptions {
                lmax,
                samples: n,
                sampler: sampler.clone(),
                seed: 0x5eed_0000 + seed,
            };
            let out = mc_once(case, &opts, normals, reference);
            used = out.samples;
            outcomes.push(out);
        }
        // The row is the first seed's estimate, held to its own reported
        // errors; the rate is fitted to the RMS over all seeds.
        let first_seed = &outcomes[0];
        let k = outcomes.len() as f64;
        let rms = (outcomes.iter().map(|o| o.errors.rms.powi(2)).sum::<f64>() / k).sqrt();
        let z: Vec<f64> = outcomes
            .iter()
            .filter_map(|o| o.z.as_deref())
            .flatten()
            .copied()
            .collect();
        let (max_z, frac_z_over_3) = if z.is_empty() {
            (None, None)
        } else {
            let over = z.iter().filter(|&&z| z > 3.0).count();
            (
                Some(z.iter().copied().fold(0.0, f64::max)),
                Some(over as f64 / z.len() as f64),
            )
        };
        x.push(used as f64);
        mean.push(rms);
        report.rows.push(Row {
            case: o.name.clone(),
            method: method.clone(),
            resolution: None,
            samples: Some(used),
            lmax,
            mean_rel_err: first_seed.errors.mean,
            max_rel_err: first_seed.errors.max,
            rms_rel_err: rms,
            bound: Some(first_seed.bound),
            slope: None,
            slope_range: None,
            max_z,
            frac_z_over_3,
            pass: first_seed.errors.max <= first_seed.bound,
        });
    }
    let range = match kind {
        SamplerKind::Uniform | SamplerKind::Importance => IID_RATE,
        _ => QMC_RATE,
    };
    finish_sweep(report, first, o, &method, x, mean, Some(range));
}

fn lmax_curve(case: &Case, options: SuiteOptions, normals: &[DVec3]) -> LmaxCurve {
    let o = &case.oracle;
    let top = if options.quick { 8 } else { 16 };
    let lmax: Vec<usize> = (0..=top).collect();
    let resolution = if options.quick {
        (256, 128)
    } else {
        (1024, 512)
    };
    let samples = 1 << 16;
    // Quadrature coefficients do not depend on lmax: project once, to the
    // top, and keep the first bands of it.
    let projected = o.renderable().then(|| {
        let px = render_texel_means(o, Layout::Equirect, resolution.0, resolution.1);
        let map = EnvMap::new(
            Layout::Equirect,
            MapOrientation::default(),
            resolution.0,
            resolution.1,
            &px,
        )
        .expect("fits");
        project_map(&map, top).channel(0)
    });
    let (mut truncation, mut quadrature, mut montecarlo) = (Vec::new(), Vec::new(), Vec::new());
    for &l in &lmax {
        let reference = case.truncated_at(&o.truncated(l), normals);
        truncation.push(case.errors(&reference, &case.exact).mean);
        if let Some(projected) = &projected {
            let c = projected.resized(l);
            quadrature.push(case.errors(&sh_irradiance(&c, normals), &reference).mean);
            let opts = McOptions {
                lmax: l,
                samples,
                sampler: Sampler::Sobol,
                seed: 0x5eed_0000,
            };
            montecarlo.push(mc_once(case, &opts, normals, &reference).errors.mean);
        }
    }
    LmaxCurve {
        case: o.name.clone(),
        lmax,
        truncation,
        quadrature,
        resolution,
        montecarlo,
        samples,
    }
}
