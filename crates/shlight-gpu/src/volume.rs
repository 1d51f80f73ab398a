//! Irradiance-volume shading: a scene and a dynamic object lit per fragment
//! by trilinear interpolation of a volume's valid probes
//! (`shaders/volume.wgsl`), and the probes themselves as small spheres.
//!
//! [`VolumeRenderer::draw`] adds its meshes to a frame that a [`Renderer`]
//! has begun (cleared, background drawn), loading colour and depth, so the
//! plain renderer is unchanged. The probes go to the GPU as one
//! `Rgba32Float` 3D texture of premultiplied texels ([`pack_texels`]): per
//! probe the floats `v, v L_i, ...` (`v` the validity 1 or 0, `L_i` the rgb
//! radiance of coefficient `i` to `lmax_v`, the volume's lmax clipped to
//! [`SHADED_MAX_LMAX`], leaving out degree 3, whose clamped cosine
//! eigenvalue `A_3` is 0 so that it adds nothing to the irradiance), four
//! to a texel; texel `j` of every
//! probe in block `j`, a copy of the grid with one more layer on each side
//! in y and z, the blocks tiling the texture's y and z. Interpolating the
//! texels gives the valid weight and the weighted coefficients at once,
//! divided and dotted with the basis once per fragment. The grid (lower
//! corner, cells per unit length, resolution, the blocks' places) is a
//! uniform block.
//!
//! The texels are interpolated one of two ways ([`VolumeFetch`]): by the
//! sampler's trilinear filter, one sample per texel, on a CPU adapter that
//! filters `Rgba32Float` (wgpu's `FLOAT32_FILTERABLE`, which [`GpuContext`]
//! requests when the adapter has it; lavapipe has it and weighs in f32);
//! else by eight `textureLoad`s per texel weighted in the shader (hardware
//! GPUs round the sampler's weights to 8 bits).
//!
//! A volume that holds probe distance maps ([`VolumeView::visibility`]) is
//! shaded by a module of its own (`shaders/volume_visibility.wgsl`): the
//! eight loads per texel, each probe weighted by its trilinear weight times
//! its visibility of the point, the lookup of
//! [`shlight_baked::visibility::visibility_weights`] (shlight-volume's
//! `PreparedLookup` with `Lookup::Shlight`). The weights differ per probe,
//! so the sampler cannot apply them. The probes' positions (cell centre
//! plus offset, as [`VolumeView::position`] computes them) and their maps
//! go to the GPU as two storage buffers, read exactly (f32 as stored, the
//! octahedral map's bilinear lookup and its folded edges done in the
//! shader, four loads per probe): a filtering texture would round its
//! weights on GPUs and could not fold the edges. A volume without maps is
//! shaded as before, by a module with no trace of them.
//!
//! [`Renderer`]: crate::Renderer

use std::sync::OnceLock;

use glam::{DMat3, Vec3};
use shlight_mesh::{Mesh, Scene};
use wgpu::util::DeviceExt;

use crate::gpu_material::material_layout;
use crate::pipeline::{Pass, READ, UNIFORM, WRITE, buffer_entry, pipeline_layout, pipeline_of};
use crate::scene_draws::SceneDraws;
use crate::shaders::{
    self, VOLUME_LOADS_MODULE, VOLUME_LOADS_SURFACE_MODULE, VOLUME_MODULE, VOLUME_SURFACE_MODULE,
    VOLUME_VISIBILITY_MODULE, VOLUME_VISIBILITY_SURFACE_MODULE,
};
use crate::shading::{FrameInputs, FrameUniform, Shading, shader_encodes_srgb};
use crate::surface_pipelines::{SurfacePipelines, surface_pass};
use crate::volume_expansion::{volume_coefficients, volume_texels};
use crate::volume_fetch::VolumeFetch;
use crate::{Camera, GpuContext, GpuError};
use shlight_baked::visibility::{CHEBYSHEV_FLOOR, CRUSH, NORMAL_BIAS};
use shlight_baked::{ProbeGrid, SHADED_MAX_LMAX, Visibility, VolumeView};

/// Texels per probe at [`SHADED_MAX_LMAX`]: `ceil((3 * 18 + 1) / 4)`.
const MAX_TEXELS: usize = 14;

/// The `probe` of an instance lit by interpolation: a filler, since no
/// shader reads it there (`fs_volume`, the pipeline that draws such
/// instances, does not look at the probe); [`VolumeInstance::probe`]
/// reports it as `None`.
const NO_PROBE: u32 = u32::MAX;

/// Checks `probes` for the volume pass: their shape
/// ([`VolumeView::check`]) and a count the pass can index.
fn check(probes: &VolumeView<'_>) -> Result<(), GpuError> {
    probes.check().map_err(|e| GpuError::Invalid(e.0))?;
    if probes.probe_count() > u32::MAX as usize / 32 {
        return Err(GpuError::Invalid(format!(
            "volume resolution {:?}: {} probes, more than the volume pass can index ({})",
            probes.grid.resolution,
            probes.probe_count(),
            u32::MAX as usize / 32
        )));
    }
    Ok(())
}

/// The probes as the volume pass's 3D texture (`Rgba32Float`, texels x
/// fastest, then y, then z).
#[derive(Clone, Debug, PartialEq)]
pub struct ProbeTexels {
    /// Width, height and depth in texels: `nx`, `by (ny + 2)`, `bz (nz + 2)`.
    pub size: [u32; 3],
    /// Texels per probe `T = ceil((3 c + 1) / 4)`, `c` the coefficients to
    /// `lmax_v` less degree 3's (1, 4, 9, 9, 18 at lmax 0..4).
    pub per_probe: usize,
    /// Per texel `j < T`: where block `j`'s first probe layer lies in y and
    /// z (block `j` is column `j % by`, row `j / by` of the tiling; its
    /// probe `(x, y, z)` at texel `(x, oy + y, oz + z)`).
    pub blocks: Vec<[u32; 2]>,
    /// The texels.
    pub data: Vec<[f32; 4]>,
}

/// The probes packed as the volume pass's texture: probe `k`'s floats
/// `v, v L_i (rgb), ...` for the coefficients `i` to lmax
/// `min(lmax, SHADED_MAX_LMAX)` but those of degree 3 (`A_3 = 0`: they add
/// nothing to the irradiance), four to a texel (the last padded with 0; an
/// invalid probe all 0), texel `j`
/// in block `j`, each block with its first and last y and z layers
/// repeated once beyond them; the blocks tiled in y and z as near a square
/// as `max_dimension` (the device's largest 3D texture side) allows.
///
/// # Errors
/// [`GpuError::Invalid`] when the grid does not fit in a 3D texture of
/// side `max_dimension`, or for the faults [`VolumeRenderer::new`] names.
pub fn pack_texels(probes: &VolumeView<'_>, max_dimension: u32) -> Result<ProbeTexels, GpuError> {
    check(probes)?;
    let lv = probes.lmax.min(SHADED_MAX_LMAX);
    let per_probe = volume_texels(lv);
    let [nx, ny, nz] = probes.grid.resolution;
    let (hy, hz) = (ny + 2, nz + 2);
    let max = max_dimension as usize;
    // Columns by and rows bz of blocks: the smallest larger side, then the
    // smallest area.
    let tiling = (1..=per_probe)
        .map(|by| (by, per_probe.div_ceil(by)))
        .filter(|&(by, bz)| nx <= max && by * hy <= max && bz * hz <= max)
        .min_by_key(|&(by, bz)| ((by * hy).max(bz * hz), by * hy * bz * hz));
    let Some((by, bz)) = tiling else {
        return Err(GpuError::Invalid(format!(
            "volume resolution {:?} at lmax {lv}: {per_probe} copies of the grid do not fit in \
             a 3D texture of side {max_dimension}",
            probes.grid.resolution
        )));
    };
    let (width, height, depth) = (nx, by * hy, bz * hz);
    let nc = (probes.lmax + 1) * (probes.lmax + 1);
    let kept = volume_coefficients(lv);
    // Per probe its T texels.
    let mut floats = vec![0.0f32; 4 * per_probe];
    let mut probe_texels = Vec::with_capacity(probes.valid.len() * per_probe);
    for (k, &valid) in probes.valid.iter().enumerate() {
        floats.fill(0.0);
        if valid {
            floats[0] = 1.0;
            let rows = &probes.radiance[k * nc * 3..][..nc * 3];
            for (slot, &i) in kept.iter().enumerate() {
                floats[1 + 3 * slot..4 + 3 * slot].copy_from_slice(&rows[3 * i..3 * i + 3]);
            }
        }
        probe_texels.extend(floats.chunks_exact(4).map(|t| [t[0], t[1], t[2], t[3]]));
    }
    let blocks: Vec<[u32; 2]> = (0..per_probe)
        .map(|j| [(j % by * hy + 1) as u32, (j / by * hz + 1) as u32])
        .collect();
    let mut data = vec![[0.0f32; 4]; width * height * depth];
    for (j, &[oy, oz]) in blocks.iter().enumerate() {
        let (oy, oz) = (oy as usize - 1, oz as usize - 1);
        for z in 0..hz {
            let pz = z.saturating_sub(1).min(nz - 1);
            for y in 0..hy {
                let py = y.saturating_sub(1).min(ny - 1);
                let row = width * (oy + y + height * (oz + z));
                for x in 0..nx {
                    let k = x + nx * (py + ny * pz);
                    data[row + x] = probe_texels[k * per_probe + j];
                }
            }
        }
    }
    Ok(ProbeTexels {
        size: [width as u32, height as u32, depth as u32],
        per_probe,
        blocks,
        data,
    })
}

/// One instance of the volume pass: `world = position * scale + offset`.
/// Which shading it gets is up to the pipeline that draws it: the scene and
/// the object are lit by interpolation, the probe spheres
/// ([`probe_sphere_instances`]) each by its probe `probe` alone.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct VolumeInstance {
    /// Offset (xyz) and uniform scale (w).
    pub offset_scale: [f32; 4],
    /// The probe a probe sphere shows; `u32::MAX`, a filler, on a mesh lit
    /// by interpolation.
    pub probe: u32,
    pad: [u32; 3],
}

impl VolumeInstance {
    /// A mesh placed by `offset` and `scale`, lit by interpolation.
    #[must_use]
    pub fn interpolated(offset: Vec3, scale: f32) -> Self {
        Self {
            offset_scale: offset.extend(scale).to_array(),
            probe: NO_PROBE,
            pad: [0; 3],
        }
    }

    /// Whether the instance shows one probe (a probe sphere).
    #[must_use]
    pub fn probe(&self) -> Option<u32> {
        (self.probe != NO_PROBE).then_some(self.probe)
    }
}

/// The probe spheres: per probe, in probe order, a unit sphere scaled to
/// [`PROBE_SPHERE_RADIUS`] times the grid's smallest cell extent and moved
/// to where the probe is (its cell's centre plus its offset, where the
/// bake moved it out of geometry), shaded by that probe's own SH (black
/// when it is invalid).
#[must_use]
pub fn probe_sphere_instances(probes: &VolumeView<'_>) -> Vec<VolumeInstance> {
    let cell = probes.grid.cell();
    let radius = PROBE_SPHERE_RADIUS * cell.min_element();
    (0..probes.probe_count())
        .map(|k| VolumeInstance {
            offset_scale: probes.position(k).extend(radius).to_array(),
            probe: k as u32,
            pad: [0; 3],
        })
        .collect()
}

/// Radius of a probe sphere as a fraction of the smallest cell extent.
pub const PROBE_SPHERE_RADIUS: f32 = 0.15;

/// The offset and scale that put a mesh of `bounds` with its bounding-box
/// centre at `at` and its bounding-box diagonal `size` long.
#[must_use]
pub fn place(bounds: (Vec3, Vec3), at: Vec3, size: f32) -> VolumeInstance {
    let diagonal = (bounds.1 - bounds.0).length().max(f32::MIN_POSITIVE);
    let scale = size / diagonal;
    let centre = (bounds.0 + bounds.1) * 0.5;
    VolumeInstance::interpolated(at - centre * scale, scale)
}

/// `Volume` of `shaders/volume.wgsl`, byte for byte.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct VolumeUniform {
    min: [f32; 4],
    inv_cell: [f32; 4],
    resolution: [u32; 4],
    inv_size: [f32; 4],
    blocks: [[f32; 4]; MAX_TEXELS],
    visibility: [f32; 4],
    map: [u32; 4],
}

impl VolumeUniform {
    fn new(probes: &VolumeView<'_>, texels: &ProbeTexels) -> Self {
        let inv_cell = Vec3::from_array(probes.grid.resolution.map(|n| n as f32))
            / (probes.grid.max - probes.grid.min);
        let [nx, ny, nz] = probes.grid.resolution.map(|n| n as u32);
        let [w, h, d] = texels.size.map(|n| n as f32);
        let mut blocks = [[0.0; 4]; MAX_TEXELS];
        for (b, &[oy, oz]) in blocks.iter_mut().zip(&texels.blocks) {
            let (oy, oz) = (oy as f32, oz as f32);
            *b = [oy / h, oz / d, oy, oz];
        }
        // The visibility module's constants as shlight-baked's
        // visibility_weights computes them, in f32.
        let (visibility, map) = match &probes.visibility {
            Some(v) => (
                [
                    NORMAL_BIAS * probes.grid.cell().min_element(),
                    CHEBYSHEV_FLOOR,
                    CRUSH,
                    CRUSH * CRUSH,
                ],
                [v.size as u32, pair_count(v.size) as u32, 0, 0],
            ),
            None => ([0.0; 4], [0; 4]),
        };
        Self {
            min: probes.grid.min.extend(0.0).to_array(),
            inv_cell: inv_cell.extend(0.0).to_array(),
            resolution: [nx, ny, nz, texels.per_probe as u32],
            inv_size: [1.0 / w, 1.0 / h, 1.0 / d, 0.0],
            blocks,
            visibility,
            map,
        }
    }
}

/// Entries of a probe's map in the pass's storage buffer ([`pair_texels`]):
/// `(size + 1) (size + 2)`.
fn pair_count(size: usize) -> usize {
    (size + 1) * (size + 2)
}

/// Bytes of the two storage buffers of a volume with distance maps: the
/// probes' positions (a `vec4<f32>` each) and their maps
/// ([`pair_texels`]: [`pair_count`] `vec4<f32>` each).
fn visibility_bytes(probes: usize, maps: &Visibility<'_>) -> (u64, u64) {
    let probes = probes as u64;
    let pairs = pair_count(maps.size) as u64;
    (probes * 16, probes.saturating_mul(pairs).saturating_mul(16))
}

/// The probes' distance maps as the pass reads them: per probe, for rows
/// `b` in `0..=size + 1` and columns `a` in `0..=size` (column fastest),
/// the texels `(a - 1, b - 1)` and `(a, b - 1)` of its map, each wrapped
/// into the map across the folded edges (shlight-baked's
/// [`wrap`](shlight_baked::octahedral::wrap)), as `[mean, mean_sq, mean,
/// mean_sq]`. A bilinear lookup with lower left texel `(i0, j0)` then reads
/// the entries `(i0 + 1, j0 + 1)` and `(i0 + 1, j0 + 2)`: two loads of
/// exactly the stored values, where four of single texels and the wrap
/// cost llvmpipe a third more per frame.
fn pair_texels(maps: &Visibility<'_>, probes: usize) -> Vec<[f32; 4]> {
    use shlight_baked::octahedral::wrap;
    let size = maps.size;
    let per_probe = Visibility::floats_per_probe(size);
    let mut out = Vec::with_capacity(probes * pair_count(size));
    for map in maps.moments.chunks_exact(per_probe).take(probes) {
        let texel = |i: i32, j: i32| {
            let (i, j) = wrap(i, j, size);
            let t = 2 * (j * size + i);
            [map[t], map[t + 1]]
        };
        for b in 0..=size as i32 + 1 {
            for a in 0..=size as i32 {
                let [m0, s0] = texel(a - 1, b - 1);
                let [m1, s1] = texel(a, b - 1);
                out.push([m0, s0, m1, s1]);
            }
        }
    }
    out
}

/// Checks that a volume's positions and distance maps fit in storage
/// buffers under `limits` (the largest storage buffer binding and the
/// largest buffer).
///
/// # Errors
/// [`GpuError::Invalid`] naming the volume's size and the adapter's limit.
pub fn check_visibility_limits(
    probes: &VolumeView<'_>,
    limits: &wgpu::Limits,
) -> Result<(), GpuError> {
    let Some(maps) = &probes.visibility else {
        return Ok(());
    };
    let (positions, moments) = visibility_bytes(probes.probe_count(), maps);
    let most = limits
        .max_storage_buffer_binding_size
        .min(limits.max_buffer_size);
    for (what, bytes) in [("positions", positions), ("distance maps", moments)] {
        if bytes > most {
            return Err(GpuError::Invalid(format!(
                "volume resolution {:?} with {size}x{size} distance maps: the probes' {what} \
                 take {bytes} bytes, more than the {most} bytes of the largest storage buffer \
                 the adapter binds; bake fewer probes, or no maps (shlight volume \
                 --no-visibility)",
                probes.grid.resolution,
                size = maps.size,
            )));
        }
    }
    Ok(())
}

/// The storage buffers of a volume with distance maps: per probe its
/// position (`xyz`, cell centre plus offset; `w` 0) and its map of
/// `(mean, mean_sq)` texels as stored, in pairs ([`pair_texels`]).
struct VisibilityBuffers {
    positions: wgpu::Buffer,
    moments: wgpu::Buffer,
}

impl VisibilityBuffers {
    /// The buffers of `probes`, `None` without distance maps.
    fn new(ctx: &GpuContext, probes: &VolumeView<'_>) -> Result<Option<Self>, GpuError> {
        let Some(maps) = &probes.visibility else {
            return Ok(None);
        };
        check_visibility_limits(probes, &ctx.device.limits())?;
        let positions: Vec<[f32; 4]> = (0..probes.probe_count())
            .map(|k| probes.position(k).extend(0.0).to_array())
            .collect();
        let pairs = pair_texels(maps, probes.probe_count());
        let init = |label, contents: &[u8]| {
            ctx.device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(label),
                    contents,
                    usage: wgpu::BufferUsages::STORAGE,
                })
        };
        let buffers = ctx.checked(|| Self {
            positions: init("volume probe positions", bytemuck::cast_slice(&positions)),
            moments: init("volume distance maps", bytemuck::cast_slice(&pairs)),
        })?;
        Ok(Some(buffers))
    }

    /// Bindings 7 (positions) and 8 (maps).
    fn entries(&self) -> [wgpu::BindGroupEntry<'_>; 2] {
        [
            wgpu::BindGroupEntry {
                binding: 7,
                resource: self.positions.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 8,
                resource: self.moments.as_entire_binding(),
            },
        ]
    }
}

/// A mesh of the volume pass: position, normal, albedo, emission per vertex.
struct VolumeMesh {
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    index_count: u32,
    instances: wgpu::Buffer,
    instance_count: u32,
}

impl VolumeMesh {
    fn new(ctx: &GpuContext, mesh: &Mesh, albedo: [f32; 3], instances: &[VolumeInstance]) -> Self {
        let albedo = Vec3::from_array(albedo);
        let vertices: Vec<[f32; 12]> = (0..mesh.vertex_count())
            .map(|v| {
                let (p, n) = (mesh.positions[v], mesh.normals[v]);
                let a = mesh.colors.as_ref().map_or(albedo, |c| c[v]);
                let e = mesh.emission.as_ref().map_or(Vec3::ZERO, |e| e[v]);
                [p.x, p.y, p.z, n.x, n.y, n.z, a.x, a.y, a.z, e.x, e.y, e.z]
            })
            .collect();
        let indices: Vec<u32> = mesh.triangles.iter().flatten().copied().collect();
        let init = |label, contents: &[u8], usage| {
            ctx.device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(label),
                    contents,
                    usage,
                })
        };
        Self {
            vertices: init(
                "volume vertices",
                bytemuck::cast_slice(&vertices),
                wgpu::BufferUsages::VERTEX,
            ),
            indices: init(
                "volume indices",
                bytemuck::cast_slice(&indices),
                wgpu::BufferUsages::INDEX,
            ),
            index_count: indices.len() as u32,
            instances: init(
                "volume instances",
                bytemuck::cast_slice(instances),
                wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
            ),
            instance_count: instances.len() as u32,
        }
    }
}

/// Meshes lit by interpolation (`fs_volume`): per vertex position,
/// normal, albedo and emission, per instance offset and scale and the
/// probe ([`VolumeInstance`]); depth tested and written, both faces drawn.
const VOLUME_PASS: Pass = Pass {
    label: "volume",
    vertex_entry: "vs_volume",
    fragment_entry: "fs_volume",
    vertex_buffers: &[
        Some(wgpu::VertexBufferLayout {
            array_stride: 48,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![
                0 => Float32x3, 1 => Float32x3, 2 => Float32x3, 3 => Float32x3
            ],
        }),
        Some(wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<VolumeInstance>() as u64,
            step_mode: wgpu::VertexStepMode::Instance,
            attributes: &wgpu::vertex_attr_array![4 => Float32x4, 5 => Uint32],
        }),
    ],
    depth_write: true,
    depth_compare: wgpu::CompareFunction::Less,
    topology: wgpu::PrimitiveTopology::TriangleList,
    cull_mode: None,
    front_face: wgpu::FrontFace::Ccw,
};

/// A glTF scene's surfaces lit by interpolation (`volume_surface.wgsl`),
/// their albedo from their materials.
const VOLUME_SURFACE_PASS: Pass =
    surface_pass("volume surfaces", "vs_volume_surface", "fs_volume_surface");

/// The probe spheres, each lit by its own probe: [`VOLUME_PASS`] with the
/// fragment stage `fs_probe`.
const PROBE_PASS: Pass = Pass {
    label: "probe spheres",
    fragment_entry: "fs_probe",
    ..VOLUME_PASS
};

/// Draws meshes lit by an irradiance volume into targets of one colour
/// format, after a [`Renderer`](crate::Renderer) has begun the frame.
pub struct VolumeRenderer {
    color_format: wgpu::TextureFormat,
    fetch: VolumeFetch,
    /// The probes' positions and distance maps, for a volume that has
    /// maps: then the texels are read by loads and weighted by visibility.
    visibility: Option<VisibilityBuffers>,
    /// Per shading lmax, compiled on first use: `volume.wgsl` as `fetch`
    /// reads the texels (with `volume_visibility.wgsl` for a volume with
    /// maps), one module for the three pipelines below.
    modules: [OnceLock<wgpu::ShaderModule>; SHADED_MAX_LMAX + 1],
    /// Per shading lmax, built on first use: meshes lit by interpolation
    /// (`VOLUME_PASS`), probe spheres (`PROBE_PASS`) and the interpolation
    /// as a compute pass (`cs_volume`).
    pipelines: [OnceLock<wgpu::RenderPipeline>; SHADED_MAX_LMAX + 1],
    probe_pipelines: [OnceLock<wgpu::RenderPipeline>; SHADED_MAX_LMAX + 1],
    computes: [OnceLock<wgpu::ComputePipeline>; SHADED_MAX_LMAX + 1],
    pipeline_layout: wgpu::PipelineLayout,
    compute_layout: wgpu::BindGroupLayout,
    compute_pipeline_layout: wgpu::PipelineLayout,
    frame: wgpu::Buffer,
    volume: wgpu::Buffer,
    texture: wgpu::Texture,
    texture_view: wgpu::TextureView,
    sampler: wgpu::Sampler,
    bind: wgpu::BindGroup,
    resolution: [usize; 3],
    lmax: usize,
    probe_count: usize,
    valid: Vec<bool>,
    scene: Option<VolumeMesh>,
    /// The scene as a glTF scene's surfaces ([`VolumeRenderer::set_scene_surfaces`]),
    /// in place of `scene`.
    surfaces: Option<SceneDraws>,
    material_layout: wgpu::BindGroupLayout,
    /// `volume_surface.wgsl`'s module per shading lmax, as `modules`.
    surface_modules: [OnceLock<wgpu::ShaderModule>; SHADED_MAX_LMAX + 1],
    surface_pipelines: SurfacePipelines,
    object: Option<VolumeMesh>,
    spheres: VolumeMesh,
}

impl std::fmt::Debug for VolumeRenderer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("VolumeRenderer")
            .field("color_format", &self.color_format)
            .field("fetch", &self.fetch)
            .field("visibility", &self.visibility.is_some())
            .field("resolution", &self.resolution)
            .field("lmax", &self.lmax)
            .finish_non_exhaustive()
    }
}

/// The probes' texture (binding 2) and, filtered, its sampler (binding 6).
fn texture_entries(
    visibility: wgpu::ShaderStages,
    fetch: VolumeFetch,
) -> Vec<wgpu::BindGroupLayoutEntry> {
    let filterable = fetch == VolumeFetch::Filtered;
    let mut out = vec![wgpu::BindGroupLayoutEntry {
        binding: 2,
        visibility,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable },
            view_dimension: wgpu::TextureViewDimension::D3,
            multisampled: false,
        },
        count: None,
    }];
    if filterable {
        out.push(wgpu::BindGroupLayoutEntry {
            binding: 6,
            visibility,
            ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
            count: None,
        });
    }
    out
}

/// The bindings of the render and the compute bind groups alike: the
/// frame uniform (0), the probes' texture (2), the `Volume` uniform (3)
/// and, filtered, the sampler (6).
fn probe_bindings<'a>(
    frame: &'a wgpu::Buffer,
    texture_view: &'a wgpu::TextureView,
    volume: &'a wgpu::Buffer,
    sampler: &'a wgpu::Sampler,
    fetch: VolumeFetch,
) -> Vec<wgpu::BindGroupEntry<'a>> {
    let mut entries = vec![
        wgpu::BindGroupEntry {
            binding: 0,
            resource: frame.as_entire_binding(),
        },
        wgpu::BindGroupEntry {
            binding: 2,
            resource: wgpu::BindingResource::TextureView(texture_view),
        },
        wgpu::BindGroupEntry {
            binding: 3,
            resource: volume.as_entire_binding(),
        },
    ];
    if fetch == VolumeFetch::Filtered {
        entries.push(wgpu::BindGroupEntry {
            binding: 6,
            resource: wgpu::BindingResource::Sampler(sampler),
        });
    }
    entries
}

impl VolumeRenderer {
    /// A volume pass for colour targets of `color_format` over `probes`
    /// (clipped to lmax [`SHADED_MAX_LMAX`]), with no scene and no object
    /// yet, interpolating as [`VolumeFetch::best`] says; a volume with
    /// distance maps by loads weighted by visibility
    /// ([`VolumeRenderer::visibility`]).
    ///
    /// # Errors
    /// [`GpuError::Invalid`] for an empty grid, bad bounds, arrays of the
    /// wrong length, a grid too large for the device's 3D textures
    /// ([`pack_texels`]), or distance maps larger than the device's largest
    /// storage buffer ([`check_visibility_limits`]).
    pub fn new(
        ctx: &GpuContext,
        color_format: wgpu::TextureFormat,
        probes: &VolumeView<'_>,
    ) -> Result<Self, GpuError> {
        Self::with_fetch(ctx, color_format, probes, VolumeFetch::best(ctx))
    }

    /// [`VolumeRenderer::new`] interpolating by `fetch`. A volume with
    /// distance maps is read by loads whatever `fetch` says (the sampler
    /// cannot weigh each probe by its own visibility); [`VolumeRenderer::fetch`]
    /// tells.
    ///
    /// # Errors
    /// As [`VolumeRenderer::new`], and [`GpuError::Invalid`] for
    /// [`VolumeFetch::Filtered`] on a device that does not filter
    /// `Rgba32Float`.
    pub fn with_fetch(
        ctx: &GpuContext,
        color_format: wgpu::TextureFormat,
        probes: &VolumeView<'_>,
        fetch: VolumeFetch,
    ) -> Result<Self, GpuError> {
        if fetch == VolumeFetch::Filtered && !VolumeFetch::can_filter(ctx) {
            return Err(GpuError::Invalid(format!(
                "filtered volume interpolation on {}: the device does not filter Rgba32Float \
                 textures (FLOAT32_FILTERABLE); use VolumeFetch::Loads",
                ctx.adapter_name()
            )));
        }
        let device = &ctx.device;
        let texels = pack_texels(probes, device.limits().max_texture_dimension_3d)?;
        let visibility = VisibilityBuffers::new(ctx, probes)?;
        let fetch = if visibility.is_some() {
            VolumeFetch::Loads
        } else {
            fetch
        };
        let vf = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let fragment = wgpu::ShaderStages::FRAGMENT;
        let mut entries = vec![
            buffer_entry(0, vf, UNIFORM),
            buffer_entry(3, fragment, UNIFORM),
        ];
        entries.extend(texture_entries(fragment, fetch));
        if visibility.is_some() {
            entries.extend([
                buffer_entry(7, fragment, READ),
                buffer_entry(8, fragment, READ),
            ]);
        }
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("volume"),
            entries: &entries,
        });
        let compute = wgpu::ShaderStages::COMPUTE;
        let mut entries = vec![
            buffer_entry(0, compute, UNIFORM),
            buffer_entry(3, compute, UNIFORM),
            buffer_entry(4, compute, READ),
            buffer_entry(5, compute, WRITE),
        ];
        entries.extend(texture_entries(compute, fetch));
        if visibility.is_some() {
            entries.extend([
                buffer_entry(7, compute, READ),
                buffer_entry(8, compute, READ),
            ]);
        }
        let compute_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("volume compute"),
            entries: &entries,
        });
        let frame = FrameUniform::buffer(device, "volume frame");
        let lmax = probes.lmax.min(SHADED_MAX_LMAX);
        let volume = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("volume grid"),
            contents: bytemuck::bytes_of(&VolumeUniform::new(probes, &texels)),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let [width, height, depth] = texels.size;
        let texture = device.create_texture_with_data(
            &ctx.queue,
            &wgpu::TextureDescriptor {
                label: Some("volume probes"),
                size: wgpu::Extent3d {
                    width,
                    height,
                    depth_or_array_layers: depth,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D3,
                format: wgpu::TextureFormat::Rgba32Float,
                usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
                view_formats: &[],
            },
            wgpu::util::TextureDataOrder::LayerMajor,
            bytemuck::cast_slice(&texels.data),
        );
        let texture_view = texture.create_view(&Default::default());
        let sampler = crate::context::linear_clamp_sampler(device, "volume probes");
        let mut entries = probe_bindings(&frame, &texture_view, &volume, &sampler, fetch);
        entries.extend(visibility.iter().flat_map(VisibilityBuffers::entries));
        let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("volume"),
            layout: &layout,
            entries: &entries,
        });
        let sphere = shlight_mesh::generate::uv_sphere(1.0, 16, 8);
        let spheres = VolumeMesh::new(ctx, &sphere, [1.0; 3], &probe_sphere_instances(probes));
        let material_layout = material_layout(device);
        let surface_pipelines = SurfacePipelines::new(
            device,
            &layout,
            &material_layout,
            color_format,
            VOLUME_SURFACE_PASS,
        );
        Ok(Self {
            color_format,
            fetch,
            visibility,
            modules: Default::default(),
            pipelines: Default::default(),
            probe_pipelines: Default::default(),
            computes: Default::default(),
            pipeline_layout: pipeline_layout(device, &layout),
            compute_pipeline_layout: pipeline_layout(device, &compute_layout),
            compute_layout,
            frame,
            volume,
            texture,
            texture_view,
            sampler,
            bind,
            resolution: probes.grid.resolution,
            lmax,
            probe_count: probes.probe_count(),
            valid: probes.valid.to_vec(),
            scene: None,
            surfaces: None,
            material_layout,
            surface_modules: Default::default(),
            surface_pipelines,
            object: None,
            spheres,
        })
    }

    /// The lmax the probes are shaded at (the volume's, at most
    /// [`SHADED_MAX_LMAX`]).
    #[must_use]
    pub fn lmax(&self) -> usize {
        self.lmax
    }

    /// How this pass reads the probes' texels ([`VolumeFetch::Loads`] for
    /// a volume with distance maps).
    #[must_use]
    pub fn fetch(&self) -> VolumeFetch {
        self.fetch
    }

    /// Whether this pass weighs each probe by its visibility of the shaded
    /// point (the volume holds distance maps), as shlight-volume's
    /// `PreparedLookup` does with `Lookup::Shlight`; else by its trilinear
    /// weight alone.
    #[must_use]
    pub fn visibility(&self) -> bool {
        self.visibility.is_some()
    }

    /// Uploads new radiance for the same probes (e.g. relit after the
    /// environment turned): per probe `(lmax+1)^2` rows of `[r, g, b]` at
    /// the volume's own lmax `lmax` (clipped here as in [`VolumeRenderer::new`]).
    ///
    /// # Errors
    /// [`GpuError::Invalid`] when `radiance` has another length.
    pub fn set_radiance(
        &mut self,
        ctx: &GpuContext,
        lmax: usize,
        radiance: &[f32],
    ) -> Result<(), GpuError> {
        let (min, max) = (Vec3::ZERO, Vec3::ONE);
        let probes = VolumeView {
            grid: ProbeGrid {
                resolution: self.resolution,
                min,
                max,
            },
            lmax,
            valid: &self.valid,
            radiance,
            offsets: None,
            visibility: None,
        };
        check(&probes)?;
        if lmax.min(SHADED_MAX_LMAX) != self.lmax {
            return Err(GpuError::Invalid(format!(
                "radiance of lmax {lmax} for a volume shaded at lmax {}",
                self.lmax
            )));
        }
        let texels = pack_texels(&probes, ctx.device.limits().max_texture_dimension_3d)?;
        let [width, height, depth] = texels.size;
        ctx.queue.write_texture(
            self.texture.as_image_copy(),
            bytemuck::cast_slice(&texels.data),
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(width * 16),
                rows_per_image: Some(height),
            },
            wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: depth,
            },
        );
        Ok(())
    }

    /// The scene the volume was baked in: its vertex colours as albedo
    /// (else `albedo`), its emission added, in place.
    pub fn set_scene(&mut self, ctx: &GpuContext, mesh: &Mesh, albedo: [f32; 3]) {
        let instance = VolumeInstance::interpolated(Vec3::ZERO, 1.0);
        self.scene = Some(VolumeMesh::new(ctx, mesh, albedo, &[instance]));
        self.surfaces = None;
    }

    /// The scene the volume was baked in as a glTF scene, in place of
    /// [`VolumeRenderer::set_scene`]'s mesh: each unique primitive once,
    /// drawn once per instance, its albedo from its material per fragment
    /// (textures, cut-outs, double-sided faces; as
    /// [`Renderer::set_scene`](crate::Renderer::set_scene) draws it, lit by
    /// the volume), its emission added; primitives without a material of
    /// `albedo`.
    ///
    /// # Errors
    /// As [`Renderer::set_scene`](crate::Renderer::set_scene).
    pub fn set_scene_surfaces(
        &mut self,
        ctx: &GpuContext,
        scene: &Scene,
        albedo: [f32; 3],
    ) -> Result<(), GpuError> {
        self.surfaces = Some(SceneDraws::instanced(
            ctx,
            &self.material_layout,
            scene,
            albedo,
            &[],
        )?);
        self.scene = None;
        Ok(())
    }

    /// The dynamic object (its vertex colours as albedo, else `albedo`),
    /// placed by `placement` ([`place`]).
    pub fn set_object(
        &mut self,
        ctx: &GpuContext,
        mesh: &Mesh,
        albedo: [f32; 3],
        placement: VolumeInstance,
    ) {
        self.object = Some(VolumeMesh::new(ctx, mesh, albedo, &[placement]));
    }

    /// Moves the object ([`place`]); nothing without one.
    pub fn set_object_placement(&mut self, ctx: &GpuContext, placement: VolumeInstance) {
        if let Some(object) = &self.object {
            ctx.queue
                .write_buffer(&object.instances, 0, bytemuck::bytes_of(&placement));
        }
    }

    /// The frame uniform of `shading` (SH at the clipped lmax).
    fn write_frame(
        &self,
        ctx: &GpuContext,
        camera: &Camera,
        aspect: f32,
        shading: &Shading,
    ) -> usize {
        let lmax = shading.lmax.min(self.lmax);
        let uniform = FrameUniform::new(&FrameInputs {
            shading,
            view_proj: camera.view_proj(aspect),
            env_from_world: DMat3::IDENTITY,
            light_from_world: DMat3::IDENTITY,
            lmax,
            prt: None,
            prt_static: None,
            glossy: None,
            eye: camera.eye,
            encode_srgb: shader_encodes_srgb(self.color_format),
            lightmap: None,
        });
        ctx.queue
            .write_buffer(&self.frame, 0, bytemuck::bytes_of(&uniform));
        lmax
    }

    /// Records the volume pass into `encoder`, loading `color` and `depth`
    /// as a [`Renderer::draw`](crate::Renderer::draw) before it left them:
    /// the scene and the object lit by interpolation, and with
    /// `show_probes` every probe as a sphere lit by its own SH. Shades to
    /// `shading.lmax` (at most [`VolumeRenderer::lmax`]) with its window,
    /// exposure and tone map.
    pub fn draw(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        color: &wgpu::TextureView,
        depth: &wgpu::TextureView,
        camera: &Camera,
        aspect: f32,
        shading: &Shading,
        show_probes: bool,
    ) {
        let lmax = self.write_frame(ctx, camera, aspect, shading);
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("volume"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: color,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        let draw = |pass: &mut wgpu::RenderPass<'_>, mesh: &VolumeMesh| {
            pass.set_vertex_buffer(0, mesh.vertices.slice(..));
            pass.set_vertex_buffer(1, mesh.instances.slice(..));
            pass.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..mesh.index_count, 0, 0..mesh.instance_count);
        };
        pass.set_bind_group(0, &self.bind, &[]);
        pass.set_pipeline(
            self.pipelines[lmax].get_or_init(|| self.pipeline(ctx, &VOLUME_PASS, lmax)),
        );
        for mesh in [self.scene.as_ref(), self.object.as_ref()]
            .into_iter()
            .flatten()
        {
            draw(&mut pass, mesh);
        }
        if let Some(draws) = &self.surfaces {
            let module = || {
                self.surface_modules[lmax]
                    .get_or_init(|| self.surface_module(ctx, lmax))
                    .clone()
            };
            draws.draw(&mut pass, |sides| {
                self.surface_pipelines.get(&ctx.device, lmax, module, sides)
            });
        }
        if show_probes {
            pass.set_pipeline(
                self.probe_pipelines[lmax].get_or_init(|| self.pipeline(ctx, &PROBE_PASS, lmax)),
            );
            draw(&mut pass, &self.spheres);
        }
    }

    /// The module at `lmax`, compiled on first use: `volume.wgsl` with its
    /// generated code for `lmax` and this pass's [`VolumeFetch`], or with
    /// `volume_visibility.wgsl` for a volume with distance maps.
    fn module(&self, ctx: &GpuContext, lmax: usize) -> &wgpu::ShaderModule {
        self.modules[lmax].get_or_init(|| {
            let source = match (self.visibility.is_some(), self.fetch) {
                (true, _) => VOLUME_VISIBILITY_MODULE,
                (false, VolumeFetch::Filtered) => VOLUME_MODULE,
                (false, VolumeFetch::Loads) => VOLUME_LOADS_MODULE,
            };
            shaders::create(&ctx.device, source, lmax)
        })
    }

    /// `volume_surface.wgsl`'s module at `lmax`, read as
    /// [`VolumeRenderer::module`] reads the texels.
    fn surface_module(&self, ctx: &GpuContext, lmax: usize) -> wgpu::ShaderModule {
        let source = match (self.visibility.is_some(), self.fetch) {
            (true, _) => VOLUME_VISIBILITY_SURFACE_MODULE,
            (false, VolumeFetch::Filtered) => VOLUME_SURFACE_MODULE,
            (false, VolumeFetch::Loads) => VOLUME_LOADS_SURFACE_MODULE,
        };
        shaders::create(&ctx.device, source, lmax)
    }

    /// The render pipeline of `pass` (`VOLUME_PASS` or `PROBE_PASS`) at
    /// `lmax`.
    fn pipeline(&self, ctx: &GpuContext, pass: &Pass, lmax: usize) -> wgpu::RenderPipeline {
        pipeline_of(
            &ctx.device,
            &self.pipeline_layout,
            self.color_format,
            pass,
            self.module(ctx, lmax),
        )
    }

    /// The interpolated irradiance the fragments see, evaluated by the same
    /// WGSL function in a compute pass: for each `(point, unit normal)`,
    /// `[E_r, E_g, E_b, W]` with `E` the renormalised interpolation of the
    /// valid probes' irradiance (windowed by `shading.window`, to
    /// `shading.lmax` at most [`VolumeRenderer::lmax`]) and `W` the summed
    /// weight of the valid probes (`E = 0` where `W = 0`): their trilinear
    /// weights, each times the probe's visibility factor for a volume with
    /// distance maps ([`VolumeRenderer::visibility`]).
    ///
    /// # Errors
    /// GPU errors while running or reading back.
    pub fn irradiance_at(
        &self,
        ctx: &GpuContext,
        shading: &Shading,
        queries: &[(Vec3, Vec3)],
    ) -> Result<Vec<[f32; 4]>, GpuError> {
        if queries.is_empty() {
            return Ok(Vec::new());
        }
        let camera = Camera::looking_at(Vec3::Z, Vec3::ZERO, 1.0, 1.0);
        let lmax = self.write_frame(ctx, &camera, 1.0, shading);
        let device = &ctx.device;
        let pipeline = self.computes[lmax].get_or_init(|| {
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("volume compute"),
                layout: Some(&self.compute_pipeline_layout),
                module: self.module(ctx, lmax),
                entry_point: Some("cs_volume"),
                compilation_options: Default::default(),
                cache: None,
            })
        });
        let input: Vec<[f32; 4]> = queries
            .iter()
            .flat_map(|(p, n)| [p.extend(1.0).to_array(), n.extend(0.0).to_array()])
            .collect();
        let size = (queries.len() * 16) as u64;
        let query_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("volume queries"),
            contents: bytemuck::cast_slice(&input),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let answers = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("volume answers"),
            size,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("volume answers readback"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut entries = probe_bindings(
            &self.frame,
            &self.texture_view,
            &self.volume,
            &self.sampler,
            self.fetch,
        );
        entries.extend(self.visibility.iter().flat_map(VisibilityBuffers::entries));
        entries.extend([
            wgpu::BindGroupEntry {
                binding: 4,
                resource: query_buffer.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 5,
                resource: answers.as_entire_binding(),
            },
        ]);
        let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("volume compute"),
            layout: &self.compute_layout,
            entries: &entries,
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, &bind, &[]);
            pass.dispatch_workgroups(queries.len().div_ceil(64) as u32, 1, 1);
        }
        encoder.copy_buffer_to_buffer(&answers, 0, &readback, 0, None);
        ctx.checked(|| ctx.queue.submit([encoder.finish()]))?;
        let bytes = crate::readback::read_buffer(ctx, &readback)?;
        Ok(bytemuck::cast_slice::<u8, [f32; 4]>(&bytes).to_vec())
    }

    /// Number of probes and of valid ones.
    #[must_use]
    pub fn probe_counts(&self) -> (usize, usize) {
        (self.probe_count, self.valid.iter().filter(|v| **v).count())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_uniform_block_has_the_wgsl_size() {
        // Volume in volume.wgsl: vec4<f32> x 2, vec4<u32>, vec4<f32>, then
        // array<vec4<f32>, 14>, vec4<f32>, vec4<u32>.
        assert_eq!(std::mem::size_of::<VolumeUniform>(), 64 + 14 * 16 + 32);
        assert_eq!(MAX_TEXELS, volume_texels(SHADED_MAX_LMAX));
        // Instances: vec4 then u32, padded to 32 bytes.
        assert_eq!(std::mem::size_of::<VolumeInstance>(), 32);
    }

    #[test]
    fn texels_pack_premultiplied_clipped_and_padded() {
        // lmax 5 volume of 2 x 1 x 1 probes: 36 rows each, clipped to 25,
        // less degree 3's rows 9..15: 18 rows (14 texels); probe 1 invalid.
        let nc = 36;
        let radiance: Vec<f32> = (0..2 * nc * 3).map(|x| x as f32 + 1.0).collect();
        let valid = [true, false];
        let probes = VolumeView {
            grid: ProbeGrid {
                resolution: [2, 1, 1],
                min: Vec3::ZERO,
                max: Vec3::ONE,
            },
            lmax: 5,
            valid: &valid,
            radiance: &radiance,
            offsets: None,
            visibility: None,
        };
        let t = pack_texels(&probes, 2048).unwrap();
        assert_eq!(t.per_probe, 14);
        // Blocks of 3 x 3 layers (one probe in y and z, a layer each side),
        // 14 of them: 4 x 4 blocks, 12 x 12 texels, the squarest.
        let [w, h, d] = t.size;
        assert_eq!(w, 2);
        assert_eq!([h, d], [12, 12], "{:?}", t.size);
        assert_eq!(t.data.len(), (w * h * d) as usize);
        let at = |x: u32, y: u32, z: u32| t.data[(x + w * (y + h * z)) as usize];
        for (j, &[oy, oz]) in t.blocks.iter().enumerate() {
            // Probe 0: floats 1, 1, 2, ..., 27 (its rows 0..8), 49, ..., 75
            // (rows 16..24), then 0.
            let f = |i: usize| match i {
                0 => 1.0,
                1..=27 => i as f32,
                28..=54 => (i + 21) as f32,
                _ => 0.0,
            };
            let want = [f(4 * j), f(4 * j + 1), f(4 * j + 2), f(4 * j + 3)];
            // The probe layer and its repeats above and below in y and z.
            for dy in [0, 1, 2] {
                for dz in [0, 1, 2] {
                    assert_eq!(at(0, oy - 1 + dy, oz - 1 + dz), want, "block {j}");
                    // The invalid probe is 0 whatever its radiance.
                    assert_eq!(at(1, oy - 1 + dy, oz - 1 + dz), [0.0; 4], "block {j}");
                }
            }
        }
        // The blocks tile without overlap.
        let mut seen = std::collections::BTreeSet::new();
        for &[oy, oz] in &t.blocks {
            assert!(oy >= 1 && oz >= 1 && oy + 1 < h && oz + 1 < d);
            assert!(oy % 3 == 1 && oz % 3 == 1);
            assert!(seen.insert((oy, oz)));
        }
        // Too large for the device: an error naming the resolution.
        let e = pack_texels(&probes, 8).unwrap_err().to_string();
        assert!(e.contains("[2, 1, 1]") && e.contains("side 8"), "{e}");
    }

    #[test]
    fn distance_maps_beyond_the_largest_storage_buffer_are_refused() {
        let valid = [true, false];
        let radiance = [0.0f32; 2 * 3];
        let maps = vec![1.0f32; 2 * 2 * 16 * 16];
        let probes = VolumeView {
            grid: ProbeGrid {
                resolution: [2, 1, 1],
                min: Vec3::ZERO,
                max: Vec3::ONE,
            },
            lmax: 0,
            valid: &valid,
            radiance: &radiance,
            offsets: None,
            visibility: Some(Visibility {
                size: 16,
                max_distance: 1.0,
                moments: &maps,
            }),
        };
        // 2 probes of 17 x 18 pairs of texels of 16 bytes: 9792 bytes of
        // maps, 32 of positions.
        let limits = |binding: u64, buffer: u64| wgpu::Limits {
            max_storage_buffer_binding_size: binding,
            max_buffer_size: buffer,
            ..wgpu::Limits::default()
        };
        assert!(check_visibility_limits(&probes, &limits(9792, 9792)).is_ok());
        for (binding, buffer) in [(9791, 1 << 20), (1 << 20, 9791)] {
            let e = check_visibility_limits(&probes, &limits(binding, buffer))
                .unwrap_err()
                .to_string();
            assert!(
                e.contains("[2, 1, 1]")
                    && e.contains("16x16 distance maps")
                    && e.contains("9792 bytes")
                    && e.contains("9791 bytes")
                    && e.contains("--no-visibility"),
                "{e}"
            );
        }
        let e = check_visibility_limits(&probes, &limits(31, 31))
            .unwrap_err()
            .to_string();
        assert!(e.contains("positions take 32 bytes"), "{e}");
        // Without maps there is nothing to hold.
        let plain = VolumeView {
            visibility: None,
            ..probes
        };
        assert!(check_visibility_limits(&plain, &limits(1, 1)).is_ok());
        // wgpu's default binding limit, 128 MiB, holds 16 x 16 maps of
        // 27,413 probes (a 32 x 32 x 26 grid).
        let per_probe = visibility_bytes(1, &probes.visibility.unwrap()).1;
        assert_eq!(
            wgpu::Limits::default().max_storage_buffer_binding_size / per_probe,
            27_413
        );
    }

    /// The shader's lookup of the paired texels, written out here, gives
    /// exactly shlight-baked's `Visibility::moments_at`: the same texels
    /// with the same weights summed in the same order, across the folded
    /// edges too.
    #[test]
    fn paired_texels_give_the_bilinear_moments_exactly() {
        use shlight_baked::octahedral::oct_encode;
        let size = 8;
        let probes = 3;
        let moments: Vec<f32> = (0..probes * 2 * size * size)
            .map(|k| ((k * 7919) % 1000) as f32 / 100.0)
            .collect();
        let maps = Visibility {
            size,
            max_distance: 10.0,
            moments: &moments,
        };
        let pairs = pair_texels(&maps, probes);
        assert_eq!(pairs.len(), probes * pair_count(size));
        let mut dirs = Vec::new();
        for k in 0..2000 {
            // A spiral over the sphere, and the folds' own directions.
            let z = 1.0 - 2.0 * (k as f32 + 0.5) / 2000.0;
            let phi = k as f32 * 2.399_963;
            let r = (1.0 - z * z).sqrt();
            dirs.push(Vec3::new(r * phi.cos(), r * phi.sin(), z));
        }
        dirs.extend([
            Vec3::X,
            Vec3::NEG_X,
            Vec3::Y,
            Vec3::NEG_Y,
            Vec3::Z,
            Vec3::NEG_Z,
            Vec3::new(1e-4, 0.3, -1.0).normalize(),
            Vec3::new(-1e-4, 0.3, -1.0).normalize(),
            Vec3::new(0.5, -1e-4, -1.0).normalize(),
        ]);
        for k in 0..probes {
            for &d in &dirs {
                // volume_visibility.wgsl's probe_moments_at.
                let e = oct_encode(d);
                let s = (e + 1.0) * 0.5 * size as f32 - 0.5;
                let base = s.floor();
                let f = s - base;
                let g = glam::Vec2::ONE - f;
                let a = (base.x as i32 + 1).clamp(0, size as i32) as usize;
                let b = (base.y as i32 + 1).clamp(0, size as i32) as usize;
                let row = size + 1;
                let at = k * pair_count(size) + b * row + a;
                let (lower, upper) = (pairs[at], pairs[at + row]);
                let mean = g.x * g.y * lower[0]
                    + f.x * g.y * lower[2]
                    + g.x * f.y * upper[0]
                    + f.x * f.y * upper[2];
                let mean_sq = g.x * g.y * lower[1]
                    + f.x * g.y * lower[3]
                    + g.x * f.y * upper[1]
                    + f.x * f.y * upper[3];
                assert_eq!(
                    (mean, mean_sq),
                    maps.moments_at(k, d),
                    "probe {k} along {d}"
                );
            }
        }
    }

    #[test]
    fn probe_spheres_sit_where_the_probes_are_and_placement_centres_the_object() {
        let valid = [true; 12];
        let radiance = [0.0; 12 * 3];
        let probes = VolumeView {
            grid: ProbeGrid {
                resolution: [2, 3, 2],
                min: Vec3::new(-1.0, 0.0, 0.0),
                max: Vec3::new(1.0, 3.0, 4.0),
            },
            lmax: 0,
            valid: &valid,
            radiance: &radiance,
            offsets: None,
            visibility: None,
        };
        let spheres = probe_sphere_instances(&probes);
        assert_eq!(spheres.len(), 12);
        // Cells 1 x 1 x 2: probe (1, 2, 1) = 1 + 2 (2 + 3 * 1) = 11.
        assert_eq!(spheres[11].offset_scale, [0.5, 2.5, 3.0, 0.15]);
        assert_eq!(spheres[0].offset_scale, [-0.5, 0.5, 1.0, 0.15]);
        assert_eq!(spheres[1].offset_scale[0], 0.5);
        assert_eq!(spheres[2].offset_scale[1], 1.5);
        assert_eq!(spheres[6].offset_scale[2], 3.0);
        assert_eq!(spheres[11].probe(), Some(11));
        // A probe the bake moved is drawn where it went.
        let mut offsets = [0.0f32; 36];
        offsets[33..].copy_from_slice(&[0.25, -0.5, 0.125]);
        let moved = probe_sphere_instances(&VolumeView {
            offsets: Some(&offsets),
            ..probes
        });
        assert_eq!(moved[11].offset_scale, [0.75, 2.0, 3.125, 0.15]);
        assert_eq!(moved[0].offset_scale, spheres[0].offset_scale);
        // A box of diagonal 2 centred at (1, 1, 1), put at (5, 0, 0) 4 long.
        let p = place(
            (Vec3::ZERO, Vec3::splat(2.0)),
            Vec3::new(5.0, 0.0, 0.0),
            4.0,
        );
        let s = p.offset_scale[3];
        assert!((s - 4.0 / 12f32.sqrt()).abs() < 1e-6);
        let moved = Vec3::ONE * s + Vec3::from_slice(&p.offset_scale[..3]);
        assert!(moved.distance(Vec3::new(5.0, 0.0, 0.0)) < 1e-6);
        assert_eq!(p.probe(), None);
    }
}
