//! [`ViewVolume`], the viewer's `--volume`: the object moved through the volume by keys,
//! the probes as spheres on a key, the volume relit every frame under the
//! turned environment, and the panel's lines about it.
//!
//! Keys: `j`/`l` move the object along -X/+X, `u`/`o` along +Y/-Y, `i`/`k`
//! along -Z/+Z, each press a quarter of the smallest cell, clamped to the
//! volume's box; `g` shows or hides the probes.

use std::time::Duration;

use glam::{DVec3, Vec3};
use shlight_core::sh::ShCoeffs;
use shlight_gpu::{
    Camera, GpuContext, GpuError, SceneGeometry, SceneVolume, Shading, VolumeLight, VolumeRenderer,
    wgpu,
};

/// The keys that move the object and the direction of each.
pub const MOVE_KEYS: [(&str, Vec3); 6] = [
    ("j", Vec3::NEG_X),
    ("l", Vec3::X),
    ("u", Vec3::Y),
    ("o", Vec3::NEG_Y),
    ("i", Vec3::NEG_Z),
    ("k", Vec3::Z),
];

/// The key that shows or hides the probes.
pub const PROBE_KEY: &str = "g";

/// Where the object goes when `key` is pressed at `at`: one `step` along
/// the key's direction ([`MOVE_KEYS`]), clamped to `bounds`; `None` for
/// any other key.
pub fn moved(at: Vec3, key: &str, step: f32, bounds: (Vec3, Vec3)) -> Option<Vec3> {
    let (_, dir) = MOVE_KEYS.iter().find(|(k, _)| *k == key)?;
    Some((at + *dir * step).clamp(bounds.0, bounds.1))
}

/// The volume of the viewer: its input, its GPU pass once the window
/// exists, the object's position and the last relight's time.
pub struct ViewVolume {
    input: SceneVolume,
    renderer: Option<VolumeRenderer>,
    at: Vec3,
    step: f32,
    show_probes: bool,
    relight: Option<Duration>,
}

impl ViewVolume {
    /// The volume's state in the viewer, the object at its start.
    pub fn new(input: SceneVolume) -> Self {
        let (lo, hi) = input.bounds();
        let cell = (hi - lo) / Vec3::from_array(input.file.resolution.map(|n| n as f32));
        Self {
            at: input.at,
            step: cell.min_element() * 0.25,
            input,
            renderer: None,
            show_probes: false,
            relight: None,
        }
    }

    /// The GPU pass for targets of `format`, lighting `scene`.
    pub fn start(
        &mut self,
        ctx: &GpuContext,
        format: wgpu::TextureFormat,
        scene: SceneGeometry<'_>,
        albedo: [f32; 3],
    ) -> Result<(), GpuError> {
        self.renderer = Some(self.input.renderer(ctx, format, Some(scene), albedo)?);
        Ok(())
    }

    /// Relights the probes under `env` (already turned) and uploads them;
    /// a static volume stays as stored.
    pub fn relight(&mut self, ctx: &GpuContext, env: &ShCoeffs<DVec3>) -> Result<(), GpuError> {
        self.relight = self.input.relight(env);
        if let (Some(r), Some(_)) = (&mut self.renderer, self.relight) {
            r.set_radiance(ctx, self.input.file.lmax, &self.input.file.radiance)?;
        }
        Ok(())
    }

    /// Handles a key of [`MOVE_KEYS`] or [`PROBE_KEY`]; false for others.
    pub fn key(&mut self, ctx: &GpuContext, key: &str) -> bool {
        if key == PROBE_KEY {
            self.show_probes = !self.show_probes;
            return true;
        }
        let Some(at) = moved(self.at, key, self.step, self.input.bounds()) else {
            return false;
        };
        self.at = at;
        if let Some(r) = &mut self.renderer {
            r.set_object_placement(ctx, self.input.placement(at));
        }
        true
    }

    /// Records the volume pass after the renderer's.
    #[allow(clippy::too_many_arguments)]
    pub fn draw(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        view: &wgpu::TextureView,
        depth: &wgpu::TextureView,
        camera: &Camera,
        aspect: f32,
        shading: &Shading,
    ) {
        if let Some(r) = &self.renderer {
            r.draw(
                ctx,
                encoder,
                view,
                depth,
                camera,
                aspect,
                shading,
                self.show_probes,
            );
        }
    }

    /// The panel's lines: probes, light, relight time, object, keys.
    pub fn panel_lines(&self) -> Vec<String> {
        let file = &self.input.file;
        let valid = file.valid.iter().filter(|v| **v).count();
        let lmax = self.input.shaded_lmax();
        vec![
            format!(
                "volume {}: {valid} valid of {} probes ({}x{}x{}), shaded to lmax {lmax}",
                self.input.path.display(),
                file.valid.len(),
                file.resolution[0],
                file.resolution[1],
                file.resolution[2]
            ),
            match (self.input.light(), self.relight) {
                (VolumeLight::Relit, Some(t)) => {
                    format!("relit every frame: {:.3} ms", t.as_secs_f64() * 1e3)
                }
                (VolumeLight::Relit, None) => "relit every frame".to_string(),
                (VolumeLight::Stored, _) => {
                    "static volume: turning the environment moves the background only".to_string()
                }
            },
            format!(
                "object {} at ({:.3}, {:.3}, {:.3})",
                self.input.object_name, self.at.x, self.at.y, self.at.z
            ),
            format!(
                "j/l x, u/o y, i/k z: move the object · g: probes ({})",
                if self.show_probes { "shown" } else { "hidden" }
            ),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_move_the_object_one_step_within_the_box() {
        let bounds = (Vec3::ZERO, Vec3::ONE);
        let at = Vec3::splat(0.5);
        assert_eq!(moved(at, "l", 0.1, bounds), Some(Vec3::new(0.6, 0.5, 0.5)));
        assert_eq!(moved(at, "j", 0.1, bounds), Some(Vec3::new(0.4, 0.5, 0.5)));
        assert_eq!(moved(at, "u", 0.1, bounds), Some(Vec3::new(0.5, 0.6, 0.5)));
        assert_eq!(moved(at, "o", 0.1, bounds), Some(Vec3::new(0.5, 0.4, 0.5)));
        assert_eq!(moved(at, "i", 0.1, bounds), Some(Vec3::new(0.5, 0.5, 0.4)));
        assert_eq!(moved(at, "k", 0.1, bounds), Some(Vec3::new(0.5, 0.5, 0.6)));
        // Clamped at the box's faces.
        assert_eq!(
            moved(Vec3::new(0.95, 0.5, 0.5), "l", 0.1, bounds),
            Some(Vec3::new(1.0, 0.5, 0.5))
        );
        assert_eq!(moved(at, "m", 0.1, bounds), None);
        // No key of the viewer's own is taken.
        for (k, _) in MOVE_KEYS {
            assert!(!["m", "b", "w", "t", "p", "h", "q", PROBE_KEY].contains(&k));
        }
    }
}
