//! The DFG table of the split-sum approximation (Karis 2013): the
//! specular BRDF's directional albedo split into the parts that multiply
//! `F0` and `F90`, per `n·v` and roughness.
//!
//! With Schlick's Fresnel `F = F0 (1 - Fc) + F90 Fc`, `Fc = (1 - v·h)^5`,
//!
//! ```text
//! ∫ f(v, l) (n·l) dl = F0 A + F90 B,
//! A = ∫ D V (1 - Fc) (n·l) dl,   B = ∫ D V Fc (n·l) dl,
//! ```
//!
//! `V = G / (4 (n·l)(n·v))` ([`MaskingShadowing`]). Estimated as Karis and
//! Filament (`DFV`) do: half vectors from `D(h)(n·h)` at Hammersley
//! points, `l = 2(v·h)h - v`, each sample weighing
//! `4 V (n·l) (v·h) / (n·h)`, with `v = (sqrt(1 - (n·v)²), 0, n·v)`.
//!
//! Forms ([`DfgForm`]): Karis' `(A, B)` (scale and bias of `F0`), and
//! Filament's multiscatter `(B, A + B)`, which its shader reads as
//! `mix(dfg.x, dfg.y, F0)` and whose `A + B` gives the energy
//! compensation `1 + F0 (1 / (A + B) - 1)` (Filament's documentation,
//! "Energy loss in specular reflectance").

use glam::DVec3;
use rayon::prelude::*;

use crate::ggx::{MaskingShadowing, hammersley, sample_ggx_half};
use crate::target_engine::TargetEngine;

/// Which two numbers a DFG texel holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DfgForm {
    /// `(A, B)`: scale and bias of `F0` (Karis 2013; Unreal, Bevy's
    /// analytic fit, Babylon's red and green).
    ScaleBias,
    /// `(B, A + B)`: Filament's multiscatter table (`DFV_Multiscatter`).
    Multiscatter,
}

/// `(A, B)` at `n_dot_v` in `(0, 1]` and GGX roughness `alpha`, from
/// `samples` Hammersley points (module docs).
#[must_use]
pub fn dfg(
    n_dot_v: f64,
    alpha: f64,
    masking_shadowing: MaskingShadowing,
    samples: u32,
) -> [f64; 2] {
    let v = DVec3::new((1.0 - n_dot_v * n_dot_v).max(0.0).sqrt(), 0.0, n_dot_v);
    let (mut a, mut b) = (0.0, 0.0);
    for i in 0..samples {
        let h = sample_ggx_half(hammersley(i, samples), alpha);
        let v_dot_h = v.dot(h).clamp(0.0, 1.0);
        let l = 2.0 * v.dot(h) * h - v;
        let n_dot_l = l.z.clamp(0.0, 1.0);
        let n_dot_h = h.z.clamp(0.0, 1.0);
        if n_dot_l > 0.0 && n_dot_h > 0.0 {
            let w = masking_shadowing.eval(n_dot_v, n_dot_l, alpha) * n_dot_l * v_dot_h / n_dot_h;
            let fc = (1.0 - v_dot_h).powi(5);
            a += w * (1.0 - fc);
            b += w * fc;
        }
    }
    let k = 4.0 / f64::from(samples);
    [a * k, b * k]
}

/// Karis' analytic fit of `(A, B)` for mobile (Karis 2014, "Physically
/// Based Shading on Mobile", `EnvBRDFApprox`; Bevy's `F_AB`), at
/// perceptual roughness `perceptual` (`alpha = perceptual²`).
#[must_use]
pub fn dfg_karis_approx(n_dot_v: f64, perceptual: f64) -> [f64; 2] {
    let c0 = [-1.0, -0.0275, -0.572, 0.022];
    let c1 = [1.0, 0.0425, 1.04, -0.04];
    let r: Vec<f64> = (0..4).map(|i| perceptual * c0[i] + c1[i]).collect();
    let a004 = (r[0] * r[0]).min((-9.28 * n_dot_v).exp2()) * r[0] + r[1];
    [-1.04 * a004 + r[2], 1.04 * a004 + r[3]]
}

/// A DFG table: `size x size` texels, `n·v = (x + ½) / size` left to
/// right, perceptual roughness `1 - (y + ½) / size` from the top row
/// (roughness 1) to the bottom (smooth): a texture uploaded bottom row
/// first (OpenGL order) is read at `(n·v, perceptual roughness)`.
#[derive(Clone, Debug, PartialEq)]
pub struct DfgTable {
    /// Texels per side.
    pub size: usize,
    /// What each texel holds.
    pub form: DfgForm,
    /// The masking-shadowing term it integrates.
    pub masking_shadowing: MaskingShadowing,
    /// `size * size` texels, row-major from the top-left.
    pub values: Vec<[f64; 2]>,
}

impl DfgTable {
    /// cmgen's `DFG_LUT_DEFAULT_SIZE`.
    pub const DEFAULT_SIZE: usize = 128;
    /// cmgen's samples per texel.
    pub const DEFAULT_SAMPLES: u32 = 1024;
    /// The largest table made: 4096 texels per side (16M texels, 256 MiB
    /// of `f64` pairs).
    pub const MAX_SIZE: usize = 4096;

    /// Refuses a table of `size` texels per side from `samples` per texel
    /// that shlight does not make: a size from 1 to [`DfgTable::MAX_SIZE`]
    /// and at least one sample.
    ///
    /// # Errors
    /// The first refused setting, naming it ([`crate::PrefilterError`]'s
    /// form: the setting and why).
    pub fn check(size: usize, samples: u32) -> Result<(), crate::PrefilterError> {
        if size == 0 || size > Self::MAX_SIZE {
            return Err(crate::PrefilterError::new(
                "size",
                format!(
                    "a DFG table of {size} texels per side: the size must be from 1 to {}",
                    Self::MAX_SIZE
                ),
            ));
        }
        if samples == 0 {
            return Err(crate::PrefilterError::new(
                "samples",
                "the sample count must be at least 1".into(),
            ));
        }
        Ok(())
    }

    /// `n·v` of column `x`.
    #[must_use]
    pub fn n_dot_v(&self, x: usize) -> f64 {
        (x as f64 + 0.5) / self.size as f64
    }

    /// Perceptual roughness of row `y`.
    #[must_use]
    pub fn perceptual(&self, y: usize) -> f64 {
        1.0 - (y as f64 + 0.5) / self.size as f64
    }

    /// The table `engine` reads ([`TargetEngine::multiscatter_dfg`],
    /// [`TargetEngine::masking_shadowing`]), rows in parallel.
    #[must_use]
    pub fn for_engine(engine: TargetEngine, size: usize, samples: u32) -> Self {
        let form = if engine.multiscatter_dfg() {
            DfgForm::Multiscatter
        } else {
            DfgForm::ScaleBias
        };
        Self::new(size, form, engine.masking_shadowing(), samples)
    }

    /// A table of `size` (at least 1) in `form`.
    #[must_use]
    pub fn new(
        size: usize,
        form: DfgForm,
        masking_shadowing: MaskingShadowing,
        samples: u32,
    ) -> Self {
        let size = size.max(1);
        let mut table = Self {
            size,
            form,
            masking_shadowing,
            values: vec![[0.0; 2]; size * size],
        };
        let rows: Vec<Vec<[f64; 2]>> = (0..size)
            .into_par_iter()
            .map(|y| {
                let p = table.perceptual(y);
                (0..size)
                    .map(|x| {
                        let [a, b] = dfg(table.n_dot_v(x), p * p, masking_shadowing, samples);
                        match form {
                            DfgForm::ScaleBias => [a, b],
                            DfgForm::Multiscatter => [b, a + b],
                        }
                    })
                    .collect()
            })
            .collect();
        table.values = rows.concat();
        table
    }
}
