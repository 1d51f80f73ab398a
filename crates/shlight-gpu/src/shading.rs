//! What a frame shows and how: [`Shading`], and the uniform block the
//! shaders read (`Frame` in `shaders/scene.wgsl`).

use glam::{DMat3, Mat4};
use shlight_baked::LIGHT_MAX_LMAX;
use shlight_core::sh::{Window, clamped_cosine_eigenvalue};
use shlight_io::ToneMap;

/// What the mesh shows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Mode {
    /// Per-fragment SH irradiance at the normal, times albedo / π.
    #[default]
    Sh,
    /// Per-vertex PRT: a diffuse file's transfer dotted with the light
    /// coefficients, plus its static term where it has one
    /// ([`Renderer::set_transfer_with_static`](crate::Renderer::set_transfer_with_static)),
    /// or a glossy file's exit radiance toward the camera
    /// ([`Renderer::set_glossy`](crate::Renderer::set_glossy)).
    Prt,
    /// World-space unit normals as colours (exposure and tone map not applied).
    Normals,
    /// Per-fragment irradiance of the light's encoding (dominant lights
    /// plus SH, ZH3, non-linear L1, an ambient cube:
    /// [`Renderer::set_encoding`](crate::Renderer::set_encoding)) at the
    /// normal, times albedo / π.
    Encoded,
}

impl Mode {
    /// The mode's name: `sh`, `prt`, `normals`, `encoded`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Sh => "sh",
            Self::Prt => "prt",
            Self::Normals => "normals",
            Self::Encoded => "encoded",
        }
    }

    fn code(self) -> u32 {
        match self {
            Self::Sh => 0,
            Self::Prt => 1,
            Self::Normals => 2,
            Self::Encoded => 3,
        }
    }
}

/// What is drawn behind the mesh.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Background {
    /// Nothing: the clear colour 0.
    #[default]
    None,
    /// The environment map itself (bilinear; columns wrap, rows clamp).
    Map,
    /// The windowed SH reconstruction of the light to the frame's lmax.
    Sh,
}

impl Background {
    /// The background's name: `none`, `map`, `sh`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::None => "none",
            Self::Map => "map",
            Self::Sh => "sh",
        }
    }

    fn code(self) -> u32 {
        match self {
            Self::None => 0,
            Self::Map => 1,
            Self::Sh => 2,
        }
    }
}

/// How a frame is shaded.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shading {
    /// What the mesh shows.
    pub mode: Mode,
    /// Highest degree of the light used (at most [`LIGHT_MAX_LMAX`] and the light's own).
    pub lmax: usize,
    /// Ringing window applied per band at run time.
    pub window: Window,
    /// Exposure in stops (radiance is multiplied by `2^exposure_ev`).
    pub exposure_ev: f32,
    /// Tone map to `[0, 1]`, or `None` for linear output (HDR targets).
    pub tone_map: Option<ToneMap>,
    /// Lambertian albedo (linear RGB) of SH mode.
    pub albedo: [f32; 3],
    /// What is drawn behind the mesh (never in [`Mode::Normals`]).
    pub background: Background,
}

impl Default for Shading {
    fn default() -> Self {
        Self {
            mode: Mode::Sh,
            lmax: 2,
            window: Window::None,
            exposure_ev: 0.0,
            tone_map: None,
            albedo: [0.8; 3],
            background: Background::None,
        }
    }
}

/// `MODE_GLOSSY` of `scene.wgsl`: [`Mode::Prt`] with glossy transfer.
const MODE_GLOSSY: u32 = 4;

/// `Frame` of `shaders/scene.wgsl`, byte for byte.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct FrameUniform {
    view_proj: [[f32; 4]; 4],
    inv_view_proj: [[f32; 4]; 4],
    env_from_world: [[f32; 4]; 4],
    light_from_world: [[f32; 4]; 4],
    irradiance_band: [[f32; 4]; 3],
    radiance_band: [[f32; 4]; 3],
    albedo: [f32; 4],
    exposure: f32,
    lmax: u32,
    mode: u32,
    tone_map: u32,
    prt_lmax: u32,
    prt_channels: u32,
    background: u32,
    encode_srgb: u32,
    eye: [f32; 4],
    glossy_band: [[f32; 4]; 3],
    glossy_vectors: u32,
    glossy_parts: u32,
    ggx_table: u32,
    ggx_rows: u32,
    prt_static: u32,
    lightmap: u32,
    lightmap_scale: f32,
    _pad: u32,
}

/// What the glossy path adds to a frame's uniform block: the lobe's
/// `Lambda_l` per band (element `l / 4`, lane `l % 4`), the basis vectors
/// per cluster `K`, and where the parts start in the transfer buffer (in
/// `f32`s).
#[derive(Clone, Copy, Debug)]
pub(crate) struct GlossyInputs {
    pub band: [[f32; 4]; 3],
    /// A tabulated lobe's direction weights: their first `f32` in the
    /// transfer buffer and their rows.
    pub table: Option<(u32, u32)>,
    pub vectors: u32,
    pub parts: u32,
}

/// Everything a frame's uniform block is made from.
pub(crate) struct FrameInputs<'a> {
    pub shading: &'a Shading,
    pub view_proj: Mat4,
    pub env_from_world: DMat3,
    /// The unturned light's frame from world: `R^T` for a light turned by
    /// `R` (encoded shading evaluates the unturned encoding at `R^T n`).
    pub light_from_world: DMat3,
    /// The light's lmax after clamping.
    pub lmax: usize,
    pub prt: Option<(usize, usize)>,
    /// Where a diffuse transfer's static term starts in the transfer
    /// buffer, in `f32`s (`None`: none).
    pub prt_static: Option<usize>,
    /// The glossy transfer's lobe and layout, when the PRT transfer is
    /// glossy (PRT mode then shades it view by view).
    pub glossy: Option<GlossyInputs>,
    /// The camera's position (glossy shading's `w_o`).
    pub eye: glam::Vec3,
    pub encode_srgb: bool,
    /// A lightmapped scene's texel format (`LIGHTMAP_*` of
    /// `lightmap.wgsl`) and its engine's units' scale; `None` without a
    /// lightmap.
    pub lightmap: Option<(u32, f32)>,
}

/// Whether the shaders sRGB-encode a frame for targets of `format`: 8-bit
/// unorm targets without the hardware's sRGB encoding.
pub(crate) fn shader_encodes_srgb(format: wgpu::TextureFormat) -> bool {
    matches!(
        format,
        wgpu::TextureFormat::Rgba8Unorm | wgpu::TextureFormat::Bgra8Unorm
    )
}

impl FrameUniform {
    /// A uniform buffer (written with `COPY_DST`) that holds one frame's
    /// block.
    pub(crate) fn buffer(device: &wgpu::Device, label: &str) -> wgpu::Buffer {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: std::mem::size_of::<Self>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        })
    }

    pub(crate) fn new(f: &FrameInputs<'_>) -> Self {
        let mut irradiance_band = [[0.0f32; 4]; 3];
        let mut radiance_band = [[0.0f32; 4]; 3];
        for l in 0..=LIGHT_MAX_LMAX {
            let w = f.shading.window.factor(l);
            irradiance_band[l / 4][l % 4] = (clamped_cosine_eigenvalue(l) * w) as f32;
            radiance_band[l / 4][l % 4] = w as f32;
        }
        let e = f.env_from_world.as_mat3();
        let env = Mat4::from_mat3(e);
        let [r, g, b] = f.shading.albedo;
        let (prt_lmax, prt_channels) = f.prt.unwrap_or((0, 1));
        let background = if f.shading.mode == Mode::Normals {
            Background::None
        } else {
            f.shading.background
        };
        Self {
            view_proj: f.view_proj.to_cols_array_2d(),
            inv_view_proj: f.view_proj.inverse().to_cols_array_2d(),
            env_from_world: env.to_cols_array_2d(),
            light_from_world: Mat4::from_mat3(f.light_from_world.as_mat3()).to_cols_array_2d(),
            irradiance_band,
            radiance_band,
            albedo: [r, g, b, 1.0],
            exposure: 2f32.powf(f.shading.exposure_ev),
            lmax: f.lmax as u32,
            mode: match (f.shading.mode, f.glossy) {
                (Mode::Prt, Some(_)) => MODE_GLOSSY,
                (mode, _) => mode.code(),
            },
            tone_map: match f.shading.tone_map {
                None => 0,
                Some(ToneMap::Clamp) => 1,
                Some(ToneMap::Reinhard) => 2,
                Some(ToneMap::Aces) => 3,
            },
            prt_lmax: prt_lmax as u32,
            prt_channels: prt_channels as u32,
            background: background.code(),
            encode_srgb: u32::from(f.encode_srgb),
            eye: [f.eye.x, f.eye.y, f.eye.z, 1.0],
            glossy_band: f.glossy.map_or([[0.0; 4]; 3], |g| g.band),
            glossy_vectors: f.glossy.map_or(0, |g| g.vectors),
            glossy_parts: f.glossy.map_or(0, |g| g.parts),
            ggx_table: f.glossy.and_then(|g| g.table).map_or(0, |t| t.0),
            ggx_rows: f.glossy.and_then(|g| g.table).map_or(0, |t| t.1),
            prt_static: f.prt_static.map_or(0, |at| at as u32),
            lightmap: f.lightmap.map_or(0, |l| l.0),
            lightmap_scale: f.lightmap.map_or(1.0, |l| l.1),
            _pad: 0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_uniform_block_has_the_wgsl_size() {
        // Frame in scene.wgsl: four mat4x4 (256), two array<vec4, 3> (96),
        // one vec4 (16), eight 4-byte scalars (32); then the eye (16), the
        // lobe's bands (48), four scalars (16), and the static term's
        // offset, the lightmap's format and scale, and the padding to 16
        // bytes (16).
        assert_eq!(std::mem::size_of::<FrameUniform>(), 496);
    }
}
