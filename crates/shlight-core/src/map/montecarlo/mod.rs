//! Monte Carlo projection of a distant radiance field to SH, with standard errors.
//!
//! # Estimator
//!
//! For directions `ω_i` drawn with density `p` on the sphere,
//!
//! ```text
//! L_l^m = ∫ L(ω) Y_l^m(ω) dω  ≈  (1/N) Σ_i L(ω_i) Y_l^m(ω_i) / p(ω_i)
//! ```
//!
//! per RGB channel, accumulated in `f64` ([`project_montecarlo`]). Every
//! sampler below draws each `ω_i` with exactly the density `p` it divides
//! by, so the estimate is unbiased for any integrable map.
//!
//! # Samplers ([`Sampler`])
//!
//! All map the unit square to the sphere by the equal-area map
//! `z = 1 - 2u`, `φ = 2πv`, `ω = (sqrt(1-z²) cos φ, sqrt(1-z²) sin φ, z)`
//! (uniform `(u, v)` gives `p = 1/(4π)`), except importance sampling.
//!
//! - **uniform**: `N` independent uniform points, `p = 1/(4π)`.
//! - **stratified**: [`REPLICATES`] independent jittered grids. Each has
//!   `r x c` cells equal in area in `(cos θ, φ)`, `r = max(1, round(sqrt(n/2)))`,
//!   `c = max(1, round(n/r))` for `n = max(1, round(N/K))` wanted points
//!   per grid, and one uniform point per cell: `N' = K r c` points in all.
//! - **sobol**: [`REPLICATES`] independently scrambled copies of the first
//!   `2^m` points of the 2-D Sobol (0,2)-sequence, `m` the nearest integer to
//!   `log2(N/K)` (at least 0), each coordinate Owen-scrambled (hash-based
//!   nested uniform scrambling with an independent seed per replicate and
//!   dimension) and jittered below `2^-32`, so each point is uniform and each
//!   replicate a (0,m,2)-net. `N' = K 2^m`.
//! - **importance**: `N` independent points from an [`ImportanceGrid`]'s
//!   piecewise-constant density (luminance times a defensive uniform mix),
//!   `p(ω) = P(cell)/Ω(cell)`.
//!
//! # Standard errors ([`McEstimate::std_error`])
//!
//! - uniform, importance (i.i.d. terms `t_i = L(ω_i) Y(ω_i)/p(ω_i)`): the
//!   sample standard deviation over `sqrt(N)`,
//!   `se = sqrt(Σ (t_i - t̄)² / ((N-1) N))`, computed per chunk with a
//!   shifted sum and merged with Chan's update, so it does not cancel when
//!   `t` is nearly constant.
//! - stratified, sobol (points within a grid or net are not independent, and
//!   the i.i.d. formula would overstate the error several-fold): the `K`
//!   replicates are independent and identically distributed, so the
//!   estimate is the mean of the replicate means `m_k` and
//!   `se = sqrt(Σ (m_k - m̄)² / ((K-1) K))`. With `K = 16` this estimate of
//!   the error itself carries about 18% relative noise (15 degrees of
//!   freedom: `|error| > 4 se` has probability about 0.1%). The price is
//!   that one replicate holds only `N/K` points, which costs a factor of
//!   about `sqrt(K)` over one net of `N` points when the error falls as `1/N`.
//!
//! # Reproducibility
//!
//! The points are cut into fixed chunks of at most 2048 (never crossing a
//! replicate); chunk `c` of replicate `k` draws from its own
//! `StdRng::seed_from_u64(hash(seed, sampler, k, c))`, and chunk results are
//! merged in chunk order. The result depends only on the options, the map
//! and the grid: bit-for-bit the same for any number of rayon threads.

pub(crate) mod importance;
pub(crate) mod sobol;

use core::f64::consts::PI;
use core::fmt;
use core::str::FromStr;

use glam::DVec3;
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

use crate::sh::basis::ShBasis;
use crate::sh::sh_coeffs::ShCoeffs;

use crate::map::radiance_map::RadianceMap;
pub use importance::{DEFENSIVE_FRACTION, ImportanceGrid};

/// Independent replicates `K` of the stratified and Sobol samplers, from
/// whose spread their standard error is estimated (see the module docs).
pub const REPLICATES: usize = 16;

/// The seed of [`McOptions::default`], so that runs repeat bit-for-bit.
pub const DEFAULT_SEED: u64 = 0x5348_4c49_4748_5401;

/// Points per chunk: the unit of parallel work and of random streams.
const CHUNK: usize = 2048;
/// Directions evaluated together by the batch SH evaluator.
const BATCH: usize = 64;
/// Chunks computed in parallel before being merged (bounds memory).
const WINDOW: usize = 64;

/// The name of a [`Sampler`]: what a command line or a settings file
/// chooses before any map (and so any [`ImportanceGrid`]) exists.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum SamplerKind {
    /// Independent uniform directions, `p = 1/(4π)`.
    Uniform,
    /// Jittered equal-area cells in `(cos θ, φ)`, one point per cell,
    /// [`REPLICATES`] independent grids; `p = 1/(4π)` for each point.
    Stratified,
    /// Owen-scrambled 2-D Sobol (0,2)-nets on the equal-area map,
    /// [`REPLICATES`] independent scramblings; `p = 1/(4π)` for each point.
    /// The default.
    #[default]
    Sobol,
    /// Independent directions from an [`ImportanceGrid`]:
    /// `p(ω) = P(cell)/Ω(cell)`, proportional to luminance plus a uniform
    /// floor.
    Importance,
}

/// How directions are drawn on the sphere (see the module docs for each
/// distribution and its density `p`). The importance sampler owns the
/// density it draws from.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum Sampler {
    /// Independent uniform directions, `p = 1/(4π)`.
    Uniform,
    /// Jittered equal-area cells in `(cos θ, φ)`, one point per cell,
    /// [`REPLICATES`] independent grids; `p = 1/(4π)` for each point.
    Stratified,
    /// Owen-scrambled 2-D Sobol (0,2)-nets on the equal-area map,
    /// [`REPLICATES`] independent scramblings; `p = 1/(4π)` for each point.
    /// The default.
    #[default]
    Sobol,
    /// Independent directions from this [`ImportanceGrid`]:
    /// `p(ω) = P(cell)/Ω(cell)`, proportional to luminance plus a uniform
    /// floor.
    Importance(ImportanceGrid),
}

impl Sampler {
    /// Which sampler this is.
    #[must_use]
    pub fn kind(&self) -> SamplerKind {
        match self {
            Sampler::Uniform => SamplerKind::Uniform,
            Sampler::Stratified => SamplerKind::Stratified,
            Sampler::Sobol => SamplerKind::Sobol,
            Sampler::Importance(_) => SamplerKind::Importance,
        }
    }

    /// The sampler's [name](SamplerKind::name).
    #[must_use]
    pub fn name(&self) -> &'static str {
        self.kind().name()
    }
}

impl fmt::Display for Sampler {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl SamplerKind {
    /// Every sampler, in the order of the names `uniform`, `stratified`,
    /// `sobol`, `importance`.
    pub const ALL: [SamplerKind; 4] = [
        SamplerKind::Uniform,
        SamplerKind::Stratified,
        SamplerKind::Sobol,
        SamplerKind::Importance,
    ];

    /// The name parsed by [`FromStr`] and written by [`fmt::Display`].
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            SamplerKind::Uniform => "uniform",
            SamplerKind::Stratified => "stratified",
            SamplerKind::Sobol => "sobol",
            SamplerKind::Importance => "importance",
        }
    }
}

impl SamplerKind {
    /// The sampler of this kind; `grid` is called only for
    /// [`SamplerKind::Importance`], to build the density it draws from.
    #[must_use]
    pub fn sampler(self, grid: impl FnOnce() -> ImportanceGrid) -> Sampler {
        match self {
            SamplerKind::Uniform => Sampler::Uniform,
            SamplerKind::Stratified => Sampler::Stratified,
            SamplerKind::Sobol => Sampler::Sobol,
            SamplerKind::Importance => Sampler::Importance(grid()),
        }
    }
}

impl fmt::Display for SamplerKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The error of parsing a [`SamplerKind`] from an unknown name.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ParseSamplerError {
    input: String,
}

impl fmt::Display for ParseSamplerError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "unknown sampler {:?}: expected one of uniform, stratified, sobol, importance",
            self.input
        )
    }
}

impl std::error::Error for ParseSamplerError {}

impl FromStr for SamplerKind {
    type Err = ParseSamplerError;
    /// `uniform`, `stratified`, `sobol` or `importance`, ASCII case-insensitive.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        SamplerKind::ALL
            .into_iter()
            .find(|k| s.eq_ignore_ascii_case(k.name()))
            .ok_or_else(|| ParseSamplerError {
                input: s.to_owned(),
            })
    }
}

/// What [`project_montecarlo`] estimates and how.
#[derive(Clone, Debug, PartialEq)]
pub struct McOptions {
    /// Highest degree estimated: `(lmax+1)²` coefficients.
    pub lmax: usize,
    /// Directions wanted, `N`. Uniform and importance use `max(N, 2)`;
    /// stratified and Sobol round to their grids (module docs); the count
    /// used is [`McEstimate::samples`].
    pub samples: usize,
    /// How directions are drawn.
    pub sampler: Sampler,
    /// Seed of every random stream; equal options give bit-identical results.
    pub seed: u64,
}

impl Default for McOptions {
    /// lmax 2, `2^16` samples, [`Sampler::Sobol`], [`DEFAULT_SEED`].
    fn default() -> Self {
        Self {
            lmax: 2,
            samples: 1 << 16,
            sampler: Sampler::Sobol,
            seed: DEFAULT_SEED,
        }
    }
}

/// A Monte Carlo estimate of radiance coefficients and its uncertainty.
#[derive(Clone, Debug, PartialEq)]
pub struct McEstimate {
    /// `L_l^m ≈ (1/N) Σ L(ω_i) Y_l^m(ω_i) / p(ω_i)` per RGB channel.
    pub coeffs: ShCoeffs<DVec3>,
    /// One standard error of each coefficient, per channel (the standard
    /// deviation of the estimator, estimated as the module docs state).
    pub std_error: ShCoeffs<DVec3>,
    /// Directions actually used, `N`.
    pub samples: usize,
}

/// Estimates the radiance coefficients `L_l^m`, `l <= options.lmax`, of
/// `map` by Monte Carlo integration,
/// `L_l^m ≈ (1/N) Σ_i L(ω_i) Y_l^m(ω_i) / p(ω_i)`, with the standard error
/// of every coefficient (see the module docs for the samplers and the error
/// estimates).
///
/// Work runs in parallel with the `rayon` feature; the result is identical
/// for any thread count.
///
/// ```
/// use glam::DVec3;
/// use shlight_core::map::montecarlo::{McOptions, Sampler, project_montecarlo};
/// let sky = |d: DVec3| DVec3::splat(1.0 + 0.5 * d.z);
/// let opts = McOptions { samples: 4096, sampler: Sampler::Sobol, ..McOptions::default() };
/// let est = project_montecarlo(&sky, &opts);
/// let l00 = 2.0 * std::f64::consts::PI.sqrt(); // ∫ 1 · Y_0^0
/// assert!((est.coeffs[0].x - l00).abs() < 4.0 * est.std_error[0].x + 1e-12);
/// ```
#[must_use]
pub fn project_montecarlo(map: &impl RadianceMap, options: &McOptions) -> McEstimate {
    let k = REPLICATES;
    let tag = options.sampler.kind() as u64 + 1;
    let (source, reps, per_rep) = match &options.sampler {
        Sampler::Uniform => (Source::Uniform, 1, options.samples.max(2)),
        Sampler::Importance(grid) => (Source::Importance(grid), 1, options.samples.max(2)),
        Sampler::Stratified => {
            let n = ((options.samples as f64 / k as f64).round() as usize).max(1);
            let rows = (((n as f64) / 2.0).sqrt().round() as usize).max(1);
            let cols = (((n as f64) / rows as f64).round() as usize).max(1);
            (Source::Stratified { rows, cols }, k, rows * cols)
        }
        Sampler::Sobol => {
            let n = (options.samples as f64 / k as f64).max(1.0);
            let m = (n.log2().round() as u32).min(31);
            let seeds = (0..k)
                .map(|r| {
                    let mut rng =
                        StdRng::seed_from_u64(stream(options.seed, tag, r as u64, u64::MAX));
                    (rng.random::<u32>(), rng.random::<u32>())
                })
                .collect();
            (Source::Sobol { seeds }, k, 1usize << m)
        }
    };

    let mut jobs = Vec::new();
    for rep in 0..reps {
        for (c, start) in (0..per_rep).step_by(CHUNK).enumerate() {
            jobs.push(Job {
                rep,
                start,
                end: (start + CHUNK).min(per_rep),
                stream: stream(options.seed, tag, rep as u64, c as u64),
            });
        }
    }

    let basis = ShBasis::<f64>::new(options.lmax);
    let count = basis.count();
    let mut merged: Vec<Partial> = (0..reps).map(|_| Partial::empty(count)).collect();
    for window in jobs.chunks(WINDOW) {
        let parts = map_ordered(window, |job| run_chunk(map, &basis, &source, job));
        for (job, part) in window.iter().zip(parts) {
            merged[job.rep].merge(&part);
        }
    }

    let lmax = options.lmax;
    let (coeffs, std_error) = if reps == 1 {
        let p = &merged[0];
        let n = p.n as f64;
        let se =
            p.m2.iter()
                .map(|&m2| (m2 / ((n - 1.0) * n)).max(DVec3::ZERO).sqrt());
        (from_iter(lmax, p.mean.iter().copied()), from_iter(lmax, se))
    } else {
        let kf = reps as f64;
        let mean: Vec<DVec3> = (0..count)
            .map(|c| {
                merged
                    .iter()
                    .map(|p| p.mean[c])
                    .fold(DVec3::ZERO, |a, b| a + b)
                    / kf
            })
            .collect();
        let se = (0..count).map(|c| {
            let ss = merged
                .iter()
                .map(|p| (p.mean[c] - mean[c]) * (p.mean[c] - mean[c]))
                .fold(DVec3::ZERO, |a, b| a + b);
            (ss / ((kf - 1.0) * kf)).sqrt()
        });
        (from_iter(lmax, mean.iter().copied()), from_iter(lmax, se))
    };
    McEstimate {
        coeffs,
        std_error,
        samples: reps * per_rep,
    }
}

/// One jittered equal-area grid of about `count` unit directions over the
/// whole sphere, the `stratified` sampler's grid with a single replicate:
/// `r = max(1, round(sqrt(count/2)))` rows equal in `cos θ`, `c = max(1,
/// round(count/r))` columns equal in `φ`, one uniform point per cell (so
/// every direction has density `1/(4π)`), `r c` directions in all, row by row
/// from `+z`. The same `seed` gives the same directions bit for bit.
///
/// For estimators that reuse one set of directions many times (PRT baking
/// shares it between all vertices of a mesh).
#[must_use]
pub fn stratified_directions(count: usize, seed: u64) -> Vec<DVec3> {
    let rows = (((count as f64) / 2.0).sqrt().round() as usize).max(1);
    let cols = (((count as f64) / rows as f64).round() as usize).max(1);
    let source = Source::Stratified { rows, cols };
    let tag = SamplerKind::Stratified as u64 + 1;
    let mut rng = StdRng::seed_from_u64(stream(seed, tag, u64::MAX, u64::MAX));
    (0..rows * cols)
        .map(|k| source.point(0, k, &mut rng).0)
        .collect()
}

fn from_iter(lmax: usize, it: impl Iterator<Item = DVec3>) -> ShCoeffs<DVec3> {
    let mut out = ShCoeffs::zeros(lmax);
    for (o, v) in out.as_mut_slice().iter_mut().zip(it) {
        *o = v;
    }
    out
}

/// The SplitMix64 finaliser: a bijective 64-bit mix.
fn splitmix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// Seed of the random stream of chunk `c` of replicate `rep`.
fn stream(seed: u64, tag: u64, rep: u64, c: u64) -> u64 {
    seed ^ splitmix(splitmix(splitmix(tag) ^ rep) ^ c)
}

/// Points `start..end` of replicate `rep`, drawn from the stream `stream`.
#[derive(Clone, Copy, Debug)]
struct Job {
    rep: usize,
    start: usize,
    end: usize,
    stream: u64,
}

/// Where the directions come from.
enum Source<'a> {
    Uniform,
    Stratified { rows: usize, cols: usize },
    Sobol { seeds: Vec<(u32, u32)> },
    Importance(&'a ImportanceGrid),
}

impl Source<'_> {
    /// Point `k` of replicate `rep` and its weight `1/p`.
    #[inline]
    fn point(&self, rep: usize, k: usize, rng: &mut StdRng) -> (DVec3, f64) {
        const INV_P: f64 = 4.0 * PI;
        match self {
            Source::Uniform => {
                let (u, v): (f64, f64) = (rng.random(), rng.random());
                (sphere(2.0 * u, v), INV_P)
            }
            Source::Stratified { rows, cols } => {
                let (a, b) = (k / cols, k % cols);
                let (u, v): (f64, f64) = (rng.random(), rng.random());
                let omz = 2.0 * (a as f64 + u) / *rows as f64;
                (sphere(omz, (b as f64 + v) / *cols as f64), INV_P)
            }
            Source::Sobol { seeds } => {
                let (sx, sy) = seeds[rep];
                let (x, y) = sobol::sobol2(k as u32);
                let scale = 2f64.powi(-32);
                let u = (sobol::owen_scramble(x, sx) as f64 + rng.random::<f64>()) * scale;
                let v = (sobol::owen_scramble(y, sy) as f64 + rng.random::<f64>()) * scale;
                (sphere(2.0 * u, v), INV_P)
            }
            Source::Importance(grid) => {
                let u: [f64; 4] = core::array::from_fn(|_| rng.random());
                let (d, p) = grid.sample(u);
                (d, 1.0 / p)
            }
        }
    }
}

/// The equal-area map with `omz = 1 - z` given directly (no cancellation
/// near the poles) and `φ = 2πv`.
#[inline]
fn sphere(omz: f64, v: f64) -> DVec3 {
    let s = (omz * (2.0 - omz)).max(0.0).sqrt();
    let (sp, cp) = (2.0 * PI * v).sin_cos();
    DVec3::new(s * cp, s * sp, 1.0 - omz)
}

/// Count, mean and sum of squared deviations of the terms, per coefficient.
struct Partial {
    n: usize,
    mean: Vec<DVec3>,
    m2: Vec<DVec3>,
}

impl Partial {
    fn empty(count: usize) -> Self {
        Self {
            n: 0,
            mean: vec![DVec3::ZERO; count],
            m2: vec![DVec3::ZERO; count],
        }
    }

    /// Chan et al.'s pairwise update: `δ = b̄ - ā`,
    /// `mean = ā + δ n_b/n`, `M2 = M2_a + M2_b + δ² n_a n_b / n`.
    fn merge(&mut self, other: &Partial) {
        if other.n == 0 {
            return;
        }
        if self.n == 0 {
            self.n = other.n;
            self.mean.clone_from(&other.mean);
            self.m2.clone_from(&other.m2);
            return;
        }
        let (na, nb) = (self.n as f64, other.n as f64);
        let n = na + nb;
        for c in 0..self.mean.len() {
            let delta = other.mean[c] - self.mean[c];
            self.mean[c] += delta * (nb / n);
            self.m2[c] += other.m2[c] + delta * delta * (na * nb / n);
        }
        self.n += other.n;
    }
}

/// Lanes of the accumulators (independent partial sums the compiler can
/// keep in vector registers).
const LANES: usize = 8;

/// Runs one chunk: its directions, the map, the basis in batches, and
/// shifted sums `Σ (t - K)`, `Σ (t - K)²` with `K` the chunk's first term,
/// kept in [`LANES`] partial sums per channel that are added up in a fixed
/// order at the end.
fn run_chunk(
    map: &impl RadianceMap,
    basis: &ShBasis<f64>,
    source: &Source<'_>,
    job: &Job,
) -> Partial {
    let mut rng = StdRng::seed_from_u64(job.stream);
    let count = basis.count();
    let mut ybuf = vec![0.0; count * BATCH];
    // Unused lanes of the last batch look up +Z with weight and mask 0.
    let (mut xs, mut ys, mut zs) = ([0.0; BATCH], [0.0; BATCH], [1.0; BATCH]);
    let mut w = [[0.0; BATCH]; 3];
    let mut mask = [0.0; BATCH];
    let mut shift = vec![DVec3::ZERO; count];
    // Per coefficient: Σ(t-K) for r, g, b, then Σ(t-K)² for r, g, b.
    let mut acc = vec![[0.0; LANES]; 6 * count];
    let mut k = job.start;
    while k < job.end {
        let len = BATCH.min(job.end - k);
        for i in 0..BATCH {
            if i < len {
                let (d, inv_p) = source.point(job.rep, k + i, &mut rng);
                (xs[i], ys[i], zs[i]) = (d.x, d.y, d.z);
                let f = map.radiance(d) * inv_p;
                (w[0][i], w[1][i], w[2][i], mask[i]) = (f.x, f.y, f.z, 1.0);
            } else {
                (xs[i], ys[i], zs[i]) = (0.0, 0.0, 1.0);
                (w[0][i], w[1][i], w[2][i], mask[i]) = (0.0, 0.0, 0.0, 0.0);
            }
        }
        basis.eval_batch(&xs, &ys, &zs, &mut ybuf);
        for c in 0..count {
            let yc: &[f64; BATCH] = ybuf[c * BATCH..(c + 1) * BATCH].try_into().unwrap();
            if k == job.start {
                shift[c] = DVec3::new(w[0][0], w[1][0], w[2][0]) * yc[0];
            }
            let a: &mut [[f64; LANES]; 6] = (&mut acc[6 * c..6 * c + 6]).try_into().unwrap();
            for ch in 0..3 {
                let kc = shift[c][ch];
                let (mut s1, mut s2) = (a[ch], a[3 + ch]);
                for g in 0..BATCH / LANES {
                    for j in 0..LANES {
                        let i = g * LANES + j;
                        let t = (w[ch][i] * yc[i] - kc) * mask[i];
                        s1[j] += t;
                        s2[j] += t * t;
                    }
                }
                (a[ch], a[3 + ch]) = (s1, s2);
            }
        }
        k += len;
    }
    let n = (job.end - job.start) as f64;
    let sum = |v: &[f64; LANES]| v.iter().fold(0.0, |a, b| a + b);
    let mut mean = Vec::with_capacity(count);
    let mut m2 = Vec::with_capacity(count);
    for c in 0..count {
        let a = &acc[6 * c..6 * c + 6];
        let s1 = DVec3::new(sum(&a[0]), sum(&a[1]), sum(&a[2]));
        let s2 = DVec3::new(sum(&a[3]), sum(&a[4]), sum(&a[5]));
        mean.push(shift[c] + s1 / n);
        m2.push((s2 - s1 * s1 / n).max(DVec3::ZERO));
    }
    Partial {
        n: job.end - job.start,
        mean,
        m2,
    }
}

/// `f` over `jobs`, results in job order (in parallel with `rayon`).
#[cfg(feature = "rayon")]
fn map_ordered<T: Send>(jobs: &[Job], f: impl Fn(&Job) -> T + Sync + Send) -> Vec<T> {
    use rayon::prelude::*;
    jobs.par_iter().map(f).collect()
}

/// `f` over `jobs`, results in job order.
#[cfg(not(feature = "rayon"))]
fn map_ordered<T>(jobs: &[Job], f: impl Fn(&Job) -> T) -> Vec<T> {
    jobs.iter().map(f).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stratified_directions_fill_each_cell_once() {
        let d = stratified_directions(1024, 7);
        // rows = round(sqrt(512)) = 23, cols = round(1024 / 23) = 45.
        assert_eq!(d.len(), 23 * 45);
        assert_eq!(d, stratified_directions(1024, 7));
        assert_ne!(d, stratified_directions(1024, 8));
        for (k, w) in d.iter().enumerate() {
            assert!((w.length() - 1.0).abs() < 1e-12);
            let (row, col) = (k / 45, k % 45);
            let omz = 1.0 - w.z;
            assert!(omz >= 2.0 * row as f64 / 23.0 && omz <= 2.0 * (row + 1) as f64 / 23.0);
            let phi = w.y.atan2(w.x).rem_euclid(2.0 * PI);
            let cell = (phi / (2.0 * PI) * 45.0).floor() as usize;
            assert!(cell == col || (phi - 2.0 * PI * col as f64 / 45.0).abs() < 1e-9);
        }
    }

    #[test]
    fn sampler_names_round_trip_and_errors_list_them() {
        for s in SamplerKind::ALL {
            assert_eq!(s.to_string().parse::<SamplerKind>().unwrap(), s);
            assert_eq!(s.name().to_uppercase().parse::<SamplerKind>().unwrap(), s);
        }
        let e = "halton".parse::<SamplerKind>().unwrap_err().to_string();
        for name in ["uniform", "stratified", "sobol", "importance", "halton"] {
            assert!(e.contains(name), "{e}");
        }
    }

    #[test]
    fn sample_counts_follow_the_documented_rounding() {
        let map = |_: DVec3| DVec3::ONE;
        let run = |sampler, samples| {
            let o = McOptions {
                lmax: 0,
                samples,
                sampler,
                seed: 1,
            };
            project_montecarlo(&map, &o).samples
        };
        assert_eq!(run(Sampler::Uniform, 1000), 1000);
        assert_eq!(run(Sampler::Uniform, 0), 2);
        // n = 4096 per grid: r = round(sqrt(2048)) = 45, c = round(4096/45) = 91.
        assert_eq!(run(Sampler::Stratified, 65536), 16 * 45 * 91);
        assert_eq!(run(Sampler::Stratified, 1), 16);
        assert_eq!(run(Sampler::Sobol, 65536), 65536);
        // 100000 / 16 = 6250, log2 = 12.6: nets of 2^13.
        assert_eq!(run(Sampler::Sobol, 100_000), 16 * 8192);
        assert_eq!(run(Sampler::Sobol, 0), 16);
    }

    #[test]
    fn a_sampler_names_its_kind() {
        let grid = ImportanceGrid::from_fn(
            4,
            2,
            crate::map::orientation::MapOrientation::default(),
            |_| 1.0,
        );
        let samplers = [
            Sampler::Uniform,
            Sampler::Stratified,
            Sampler::Sobol,
            Sampler::Importance(grid),
        ];
        for (s, k) in samplers.iter().zip(SamplerKind::ALL) {
            assert_eq!(s.kind(), k);
            assert_eq!(s.to_string(), k.name());
        }
    }

    #[test]
    fn shifted_sums_do_not_cancel_on_a_nearly_constant_integrand() {
        // L00 of a constant map under uniform sampling: every term is equal,
        // so the standard error must be (nearly) exactly zero.
        let map = |_: DVec3| DVec3::splat(1.0e6);
        let o = McOptions {
            lmax: 1,
            samples: 10_000,
            sampler: Sampler::Uniform,
            seed: 3,
        };
        let e = project_montecarlo(&map, &o);
        let want = 2.0 * PI.sqrt() * 1.0e6;
        assert!((e.coeffs[0].x - want).abs() < 1e-9 * want);
        assert!(e.std_error[0].x < 1e-9 * want, "{}", e.std_error[0].x);
        assert!(e.std_error[1].x > 1e3);
    }
}
