//! [`prefilter`]: an environment convolved with the GGX lobe, one cube mip
//! per roughness, the way engines' split-sum image-based lighting reads it.
//!
//! With `n = v = r` (Karis 2013, "Real Shading in Unreal Engine 4", the
//! `PrefilterEnvMap` listing), mip `k` at output direction `n` holds
//!
//! ```text
//!            ∫ L(l) (n·l)⁺ D(h) dl
//! P(n) = ---------------------------,   h = (n + l) / |n + l|,
//!             ∫ (n·l)⁺ D(h) dl
//! ```
//!
//! `D` the GGX distribution at the mip's roughness ([`crate::TargetEngine`]).
//! The estimate is Karis' and Filament's (`CubemapIBL::roughnessFilter`):
//! half vectors `h` importance-sampled from `D(h)(n·h)` at the points of a
//! fixed Hammersley set, so the density of `l = 2(n·h)h - n` is
//! `D(h) / 4`, and `P ≈ Σ L(l) (n·l) / Σ (n·l)` over the samples with
//! `n·l > 0`. Each sample reads the source cube's mip chain at
//!
//! ```text
//! lod = ½ log2(Ω_s / Ω_p) + 1,   Ω_s = 1 / (N pdf),   Ω_p = 4π / (6 S₀²),
//! ```
//!
//! the mip whose texels are the sample's share of the sphere, one level
//! blurrier (`K = 4`, Colbert & Krivanek 2007, "GPU-Based Importance
//! Sampling", GPU Gems 3, ch. 20; the `+1` as Filament's): a bright sun
//! reaches every sample spread over its footprint, not as a firefly.
//! Roughness 0 reads the source at the output's own texel footprint.
//!
//! The sample count doubles per level from level 2 (cmgen's rule: wider
//! lobes, four times fewer texels). Sums are in `f64`; every texel is
//! independent and the points are fixed, so the result repeats bit for bit
//! on any number of threads.

use core::fmt;

use glam::{DMat3, DVec3, Vec3};
use shlight_core::map::{CubeFace, EnvMap};

use crate::cube_image::CubeImage;
use crate::ggx::{d_ggx, hammersley, sample_ggx_half};
use crate::source_mips::SourceMips;
use crate::target_engine::TargetEngine;

/// What [`prefilter`] makes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrefilterSettings {
    /// Whose roughness per mip and cube axes ([`TargetEngine`]).
    pub engine: TargetEngine,
    /// Face size of mip 0, a power of two.
    pub size: usize,
    /// The number of mips; `None`: [`TargetEngine::default_mips`].
    pub mips: Option<usize>,
    /// GGX samples per texel at levels 0 and 1, doubled per level after
    /// (cmgen's `--ibl-samples`, default 1024).
    pub samples: u32,
}

impl PrefilterSettings {
    /// cmgen's defaults: a 256-pixel cube, 1024 samples.
    pub const DEFAULT_SIZE: usize = 256;
    /// See [`PrefilterSettings::DEFAULT_SIZE`].
    pub const DEFAULT_SAMPLES: u32 = 1024;

    /// The defaults for `engine`.
    #[must_use]
    pub fn new(engine: TargetEngine) -> Self {
        Self {
            engine,
            size: Self::DEFAULT_SIZE,
            mips: None,
            samples: Self::DEFAULT_SAMPLES,
        }
    }

    /// The mip count these settings make.
    #[must_use]
    pub fn mip_count(&self) -> usize {
        self.mips
            .unwrap_or_else(|| self.engine.default_mips(self.size))
    }

    /// Face size of mip `level`.
    #[must_use]
    pub fn mip_size(&self, level: usize) -> usize {
        (self.size >> level).max(1)
    }

    /// Rows of every face of every mip: the steps `progress` counts.
    #[must_use]
    pub fn rows(&self) -> usize {
        (0..self.mip_count()).map(|l| 6 * self.mip_size(l)).sum()
    }

    /// The sample count of `level` (the base count, doubled per level from
    /// level 2).
    #[must_use]
    pub fn level_samples(&self, level: usize) -> u32 {
        let doublings = level.saturating_sub(1).min(16) as u32;
        self.samples.saturating_mul(1 << doublings)
    }

    /// The settings checked.
    ///
    /// # Errors
    /// A size that is not a power of two (or over 8192), no samples, no
    /// mips or more mips than the size halves into; the error names the
    /// setting ([`PrefilterError::setting`]).
    pub fn check(&self) -> Result<(), PrefilterError> {
        let fail = |setting, message| Err(PrefilterError::new(setting, message));
        if !self.size.is_power_of_two() || self.size > 8192 {
            return fail(
                "size",
                format!(
                    "the face size {} is not a power of two from 1 to 8192",
                    self.size
                ),
            );
        }
        if self.samples == 0 {
            return fail("samples", "the sample count must be at least 1".into());
        }
        let full = self.size.ilog2() as usize + 1;
        match self.mips {
            Some(0) => fail("mips", "the mip count must be at least 1".into()),
            Some(m) if m > full => fail(
                "mips",
                format!(
                    "{m} mips: a {}-pixel cube halves into at most {full} mips",
                    self.size
                ),
            ),
            _ => Ok(()),
        }
    }
}

/// Settings [`prefilter`] (or [`crate::DfgTable::check`]) refuses: which,
/// and why.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PrefilterError {
    setting: &'static str,
    message: String,
}

impl PrefilterError {
    /// `setting` refused, with `message` saying why (in words, naming no
    /// front end's spelling of the setting).
    #[must_use]
    pub fn new(setting: &'static str, message: String) -> Self {
        Self { setting, message }
    }

    /// The refused field of [`PrefilterSettings`]: `"size"`, `"samples"`
    /// or `"mips"` (front ends name it as their users give it).
    #[must_use]
    pub fn setting(&self) -> &'static str {
        self.setting
    }
}

impl fmt::Display for PrefilterError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for PrefilterError {}

/// One mip of a [`Prefiltered`] cube.
#[derive(Clone, Debug)]
pub struct PrefilteredLevel {
    /// The GGX roughness (`alpha`) it was filtered with.
    pub alpha: f64,
    /// The samples per texel.
    pub samples: u32,
    /// Its six faces, in the engine's cube axes.
    pub cube: CubeImage,
}

/// A prefiltered environment: mip 0 first.
#[derive(Clone, Debug)]
pub struct Prefiltered {
    /// The engine its roughness and axes are for.
    pub engine: TargetEngine,
    /// The mips, each half the size of the one before.
    pub levels: Vec<PrefilteredLevel>,
}

/// One GGX sample as every texel of a level reads it: its direction about
/// `+Z`, its normalised weight `(n·l) / Σ (n·l)`, and its level of detail
/// (`l0 + t`).
#[derive(Clone, Copy, Debug)]
struct LobeSample {
    l: Vec3,
    weight: f64,
    l0: usize,
    t: f32,
}

/// The samples of a level of roughness `alpha` (`count` Hammersley points,
/// those with `n·l > 0` kept), read from a source cube of `base` pixels
/// with mips up to `max_lod`.
fn lobe_samples(alpha: f64, count: u32, base: usize, max_lod: f64) -> Vec<LobeSample> {
    let omega_p = 4.0 * std::f64::consts::PI / (6.0 * (base * base) as f64);
    let mut samples: Vec<LobeSample> = (0..count)
        .filter_map(|i| {
            let h = sample_ggx_half(hammersley(i, count), alpha);
            let n_dot_l = 2.0 * h.z * h.z - 1.0;
            if n_dot_l <= 0.0 {
                return None;
            }
            let l = DVec3::new(2.0 * h.z * h.x, 2.0 * h.z * h.y, n_dot_l);
            let pdf = d_ggx(h.z, alpha) / 4.0;
            let omega_s = 1.0 / (f64::from(count) * pdf);
            let lod = (0.5 * (omega_s / omega_p).log2() + 1.0).clamp(0.0, max_lod);
            Some(LobeSample {
                l: l.as_vec3(),
                weight: n_dot_l,
                l0: lod.floor() as usize,
                t: (lod - lod.floor()) as f32,
            })
        })
        .collect();
    let total: f64 = samples.iter().map(|s| s.weight).sum();
    for s in &mut samples {
        s.weight /= total;
    }
    samples
}

/// An orthonormal frame whose third axis is `n` (Filament's choice of
/// helper axis: `+Z` unless `n` is within 2.6° of it, then `+X`).
fn frame_about(n: DVec3) -> DMat3 {
    let up = if n.z.abs() < 0.999 {
        DVec3::Z
    } else {
        DVec3::X
    };
    let t = up.cross(n).normalize();
    DMat3::from_cols(t, n.cross(t), n)
}

/// Prefilters `map` as `settings` ask (module docs), calling
/// `progress(rows)` as rows of faces are done ([`PrefilterSettings::rows`]
/// in all).
///
/// # Errors
/// The settings' ([`PrefilterSettings::check`]).
pub fn prefilter(
    map: &EnvMap,
    settings: &PrefilterSettings,
    progress: &(dyn Fn(usize) + Sync),
) -> Result<Prefiltered, PrefilterError> {
    settings.check()?;
    let base = SourceMips::base_size(map, settings.size);
    let source = SourceMips::new(map, settings.engine.world_from_cube(), base);
    Ok(prefilter_source(&source, settings, progress))
}

/// [`prefilter`] of a source already resampled to a cube with mips, in the
/// engine's cube axes. `settings` must pass [`PrefilterSettings::check`].
#[must_use]
pub fn prefilter_source(
    source: &SourceMips,
    settings: &PrefilterSettings,
    progress: &(dyn Fn(usize) + Sync),
) -> Prefiltered {
    let mips = settings.mip_count();
    let base = source.size();
    let levels = (0..mips)
        .map(|level| {
            let size = settings.mip_size(level);
            let alpha = settings.engine.mip_alpha(level, mips, settings.size);
            let samples = settings.level_samples(level);
            let cube = if alpha <= 0.0 {
                // The source at the output texel's own footprint.
                let lod = (base as f64 / size as f64).log2().max(0.0);
                filter_rows(size, progress, |c| source.trilinear(c, lod))
            } else {
                let lobe = lobe_samples(alpha, samples, base, source.max_level() as f64);
                filter_rows(size, progress, |n| {
                    // Directions in f32, sums in f64.
                    let frame = frame_about(n).as_mat3();
                    lobe.iter()
                        .map(|s| source.trilinear_f32(frame * s.l, s.l0, s.t).as_dvec3() * s.weight)
                        .sum()
                })
            };
            PrefilteredLevel {
                alpha,
                samples: if alpha <= 0.0 { 1 } else { samples },
                cube,
            }
        })
        .collect();
    Prefiltered {
        engine: settings.engine,
        levels,
    }
}

/// A cube of `size` whose texel in direction `n` is `value(n)`, a row of
/// faces at a time, reporting each row done.
fn filter_rows(
    size: usize,
    progress: &(dyn Fn(usize) + Sync),
    value: impl Fn(DVec3) -> DVec3 + Sync,
) -> CubeImage {
    let f = size as f64;
    CubeImage::from_fn(size, |face: CubeFace, i, j| {
        let c = |k: usize| (2.0 * k as f64 + 1.0) / f - 1.0;
        let v = value(face.point(c(i), c(j)).normalize());
        if i + 1 == size {
            progress(1);
        }
        v.as_vec3().to_array()
    })
}
