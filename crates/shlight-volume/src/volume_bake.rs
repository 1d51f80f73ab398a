//! [`VolumeBake`]: a volume's bake, per probe a transfer matrix per
//! channel and the emitters' light, relit for any environment into its
//! lit probes; and [`relight_file`], the same for a `.shvol` file.

use glam::DVec3;
use shlight_core::sh::{ShCoeffs, sh_count};
use shlight_format::{ShvolFile, VolumeLights};

use shlight_baked::{ProbeGrid, ProbeVisibility, VolumeView};

use crate::error::VolumeError;

/// A volume's bake ([`crate::bake()`]): per probe a transfer matrix per
/// channel and the emitters' light, so that [`VolumeBake::relight`] gives
/// its lit probes under any environment, and what the bake found (probes
/// invalid, moved, their distance maps).
#[derive(Clone, Debug, PartialEq)]
pub struct VolumeBake {
    /// Where the probes are.
    pub grid: ProbeGrid,
    /// Highest SH degree.
    pub lmax: usize,
    /// Per probe: whether interpolation may use it.
    pub valid: Vec<bool>,
    /// Per probe `[dx, dy, dz]` from its cell's centre, where the bake
    /// moved it out of geometry (`None`: baked without relocation).
    pub offsets: Option<Vec<f32>>,
    /// The probes' distance maps (`None`: baked without them).
    pub visibility: Option<ProbeVisibility>,
    /// Per probe: the fraction of its rays that hit back faces.
    pub backfaces: Vec<f32>,
    /// Per probe, per channel, a row-major `(lmax+1)^2` square matrix `M`
    /// with `L_probe = M L_env + L_emitted`.
    pub transfer: Vec<f32>,
    /// Per probe `(lmax+1)^2` rows of `[r, g, b]`: the incident radiance
    /// from emitters and punctual lights (directly and through the
    /// surfaces they light).
    pub emitted: Vec<f32>,
    /// Rays per probe.
    pub samples: usize,
    /// Interreflection bounces.
    pub bounces: u32,
    /// Seed of the directions.
    pub seed: u64,
    /// Rays cast in all (surfaces and probes).
    pub rays: u64,
    /// The scene mesh's content hash (0 for an empty scene).
    pub scene_hash: u64,
    /// The punctual lights baked in (`None`: none), their units and how
    /// many of each kind ([`crate::bake_with_lights`]).
    pub lights: Option<VolumeLights>,
}

impl VolumeBake {
    /// Number of probes.
    #[must_use]
    pub fn probe_count(&self) -> usize {
        self.valid.len()
    }

    /// Number of probes the bake moved out of geometry.
    #[must_use]
    pub fn relocated_count(&self) -> usize {
        self.offsets
            .as_deref()
            .map_or(0, |o| shlight_baked::moved_probes(o).len())
    }

    /// The farthest the bake moved a probe along an axis, as a fraction of
    /// that axis's cell side (0 without relocation).
    #[must_use]
    pub fn largest_move(&self) -> f32 {
        self.offsets
            .as_deref()
            .map_or(0.0, |o| shlight_baked::largest_move(&self.grid, o))
    }

    /// Number of probes marked invalid.
    #[must_use]
    pub fn invalid_count(&self) -> usize {
        self.valid.iter().filter(|v| !**v).count()
    }

    /// Every probe's radiance under `env` (radiance coefficients in the
    /// volume's frame, resized to its lmax): per probe `(lmax+1)^2` rows of
    /// `[r, g, b]`, `L_probe = M L_env + L_emitted`. To rotate the
    /// environment, rotate `env` first ([`shlight_core::sh::ShRotation`]).
    #[must_use]
    pub fn relight(&self, env: &ShCoeffs<DVec3>) -> Vec<f32> {
        let mut out = vec![0.0f32; self.emitted.len()];
        self.relight_into(env, &mut out);
        out
    }

    /// [`VolumeBake::relight`] into a buffer of `probes * (lmax+1)^2 * 3`.
    ///
    /// # Panics
    /// If `out` has another length.
    pub fn relight_into(&self, env: &ShCoeffs<DVec3>, out: &mut [f32]) {
        relight(&self.transfer, &self.emitted, self.lmax, env, out);
    }

    /// The lit probes of this bake with `radiance` (from
    /// [`VolumeBake::relight`]): what a lookup
    /// ([`crate::PreparedLookup`]) or the GPU's volume pass reads.
    ///
    /// # Panics
    /// If `radiance` holds another number of values than
    /// [`VolumeBake::relight`] gives.
    #[must_use]
    pub fn view<'a>(&'a self, radiance: &'a [f32]) -> VolumeView<'a> {
        assert_eq!(radiance.len(), self.emitted.len(), "the bake's lit probes");
        VolumeView {
            grid: self.grid,
            lmax: self.lmax,
            valid: &self.valid,
            radiance,
            offsets: self.offsets.as_deref(),
            visibility: self.visibility.as_ref().map(ProbeVisibility::view),
        }
    }

    /// The file of this volume with `radiance` (from [`VolumeBake::relight`]
    /// under the bake's environment); with `relightable`, the transfer and
    /// emitted light too.
    #[must_use]
    pub fn to_shvol(&self, radiance: Vec<f32>, relightable: bool, meta: &FileMeta) -> ShvolFile {
        ShvolFile {
            lmax: self.lmax,
            resolution: self.grid.resolution,
            bounds: (self.grid.min.to_array(), self.grid.max.to_array()),
            frame: meta.frame.clone(),
            valid: self.valid.clone(),
            radiance,
            emitted: relightable.then(|| self.emitted.clone()),
            transfer: relightable.then(|| self.transfer.clone()),
            offsets: self.offsets.clone(),
            visibility: self.visibility.clone(),
            rays_per_probe: self.samples as u64,
            bounces: self.bounces,
            seed: self.seed,
            scene: meta.scene.clone(),
            scene_hash: self.scene_hash,
            environment: meta.environment.clone(),
            generator: meta.generator.clone(),
            lights: self.lights.clone(),
        }
    }
}

/// What a file records beside the bake.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct FileMeta {
    /// `"y-up"` or `"z-up"`.
    pub frame: String,
    /// The scene's file name.
    pub scene: String,
    /// The environment's file name.
    pub environment: String,
    /// The writing program, e.g. `shlight 0.1.0`.
    pub generator: String,
}

/// Relights a `.shvol` file's probes for a new environment (its
/// `radiance` replaced), e.g. after rotating the environment: `env` of any
/// lmax, kept to the file's (degrees it lacks are zero).
///
/// # Errors
/// A static file (no transfer matrices).
pub fn relight_file(file: &mut ShvolFile, env: &ShCoeffs<DVec3>) -> Result<(), VolumeError> {
    let (Some(transfer), Some(emitted)) = (&file.transfer, &file.emitted) else {
        return Err(VolumeError::Invalid(format!(
            "the volume of {} was baked static (no transfer matrices), so it cannot be relit",
            file.scene
        )));
    };
    relight(transfer, emitted, file.lmax, env, &mut file.radiance);
    Ok(())
}

fn relight(transfer: &[f32], emitted: &[f32], lmax: usize, env: &ShCoeffs<DVec3>, out: &mut [f32]) {
    let nc = sh_count(lmax);
    assert_eq!(out.len(), emitted.len(), "one radiance per emitted value");
    let env = env.resized(lmax);
    let l: Vec<[f32; 3]> = env
        .as_slice()
        .iter()
        .map(|c| c.as_vec3().to_array())
        .collect();
    for ((o, m), e) in out
        .chunks_exact_mut(3 * nc)
        .zip(transfer.chunks_exact(3 * nc * nc))
        .zip(emitted.chunks_exact(3 * nc))
    {
        for ch in 0..3 {
            let mc = &m[ch * nc * nc..][..nc * nc];
            for (i, row) in mc.chunks_exact(nc).enumerate() {
                let mut s = 0.0f32;
                for (mik, lk) in row.iter().zip(&l) {
                    s += mik * lk[ch];
                }
                o[i * 3 + ch] = s + e[i * 3 + ch];
            }
        }
    }
}
