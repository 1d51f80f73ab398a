//! The mesh renderer: GPU buffers for a mesh, a light, an environment map
//! and PRT transfer, and the two passes (background, then mesh) that draw a
//! frame into any colour target.

use std::sync::{Mutex, OnceLock};

use glam::{DMat3, DVec3};
use shlight_core::map::MapOrientation;
use shlight_core::sh::ShCoeffs;
use shlight_io::Image;
use shlight_mesh::{Mesh, Scene, Surfaces};
use wgpu::util::DeviceExt;

use crate::gpu_material::material_layout;
use crate::pipeline::{Pass, READ, UNIFORM, buffer_entry, pipeline_layout, pipeline_of};
use crate::scene_draws::SceneDraws;
use crate::shaders::{
    self, BACKGROUND_MODULE, ENCODED_MODULE, MESH_MODULE, MESH_SURFACE_MODULE,
    SURFACE_ENCODED_MODULE,
};
use crate::shading::{FrameInputs, FrameUniform, GlossyInputs, Mode, Shading, shader_encodes_srgb};
use crate::surface_pipelines::{SurfacePipelines, surface_pass};
use shlight_baked::LIGHT_MAX_LMAX;
use shlight_baked::{GlossyView, TransferView};
use shlight_lightmap::{Engine, L1Reconstruction, TexelBasis, TexelFormat};

use crate::{Camera, GpuContext, GpuError};

/// Coefficients the light buffer holds: `(LIGHT_MAX_LMAX + 1)^2`.
const LIGHT_SLOTS: usize = (LIGHT_MAX_LMAX + 1) * (LIGHT_MAX_LMAX + 1);

/// A mesh on the GPU.
struct GpuMesh {
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    index_count: u32,
    vertex_count: usize,
}

/// Glossy PRT transfer on the GPU: the matrices kept on the CPU, where
/// each light's transferred radiance is computed
/// ([`GlossyView::transferred`]) and written after the per-vertex records.
struct GlossyTransfer {
    matrices: GlossyView<'static>,
    /// The lobe's `Lambda_l` per band (zero for a tabulated lobe).
    band: [[f32; 4]; 3],
    /// A tabulated lobe's direction weights: where they start in the
    /// transfer buffer and their rows, in `f32`s (`None`: a zonal lobe).
    table: Option<(usize, usize)>,
    /// Where the parts start in the transfer buffer, in `f32`s.
    parts: usize,
    /// The light coefficients the buffer's parts were computed from.
    computed_for: Mutex<Option<Vec<[f32; 3]>>>,
}

/// The glossy layer's BRDF as [`Renderer::set_glossy`] takes it.
#[derive(Clone, Copy, Debug)]
pub enum GlossyLobe<'a> {
    /// A lobe about the mirror direction: its zonal coefficients
    /// `Lambda_l`, `l = 0..=lmax` (Phong): the layer is
    /// `sum Lambda_l Y_lm(R) T_lm`.
    Zonal(&'a [f64]),
    /// A BRDF projected per view elevation (GGX), as direction weights:
    /// shlight-prt's `GgxLobe::direction_table` (rows of `(lmax + 1)^2`
    /// values: per band `lmax + 1` weights of the bands of `T` at the
    /// directions `psi_k = pi (k + 1/2) / (lmax + 1)` from the normal,
    /// toward the eye, in the plane of the normal and the eye; rows 1 to
    /// `rows - 2` the elevations `pi/2 sin(pi/2 r / (rows - 3))`, 0 and
    /// the last their splines' end points): the layer is `sum_lk w_lk(theta_o)
    /// T_l(d_k)`, the weights Catmull-Rom interpolated.
    Directions(&'a [f32]),
}

/// A lightmapped scene's lightmap as [`Renderer::set_scene_with_lightmap`]
/// takes it: the texel format, the pages (each `side x side` linear RGBA
/// texels, row 0 at `v = 0`, in the format's layer order) and each
/// instance's `scaleOffset` into them (`[0; 4]`: an instance the lightmap
/// skipped).
#[derive(Clone, Copy, Debug)]
pub struct LightmapTexels<'a> {
    /// What a texel holds and how the engine's shader reconstructs it.
    pub format: TexelFormat,
    /// The pages' side in texels.
    pub side: usize,
    /// The pages, [`TexelFormat::layer_count`] of them.
    pub layers: &'a [&'a [[f32; 4]]],
    /// Per instance of the scene (its `instances` order), the `scaleOffset`
    /// `[su, sv, ou, ov]` taking `TEXCOORD_1` into the atlas.
    pub instances: &'a [[f32; 4]],
}

/// `LIGHTMAP_*` of `lightmap.wgsl` for `format`.
fn lightmap_code(format: TexelFormat) -> u32 {
    let non_linear = u32::from(format.reconstruction() == L1Reconstruction::NonLinear);
    match (format.basis(), format.engine()) {
        (TexelBasis::Irradiance, _) => 1,
        (TexelBasis::ShL1, Engine::Godot) => 4,
        (TexelBasis::ShL1, Engine::Unity) => 5 + non_linear,
        (TexelBasis::MonoSh, _) => 7 + non_linear,
        (TexelBasis::ShL1, _) => 2 + non_linear,
    }
}

/// Draws meshes lit by SH coefficients into targets of one colour format.
pub struct Renderer {
    color_format: wgpu::TextureFormat,
    /// Per lmax, built on first use (each compiles its own `sh_reconstruct`).
    mesh_pipelines: [OnceLock<wgpu::RenderPipeline>; LIGHT_MAX_LMAX + 1],
    background_pipelines: [OnceLock<wgpu::RenderPipeline>; LIGHT_MAX_LMAX + 1],
    mesh_pipeline_layout: wgpu::PipelineLayout,
    background_pipeline_layout: wgpu::PipelineLayout,
    mesh_layout: wgpu::BindGroupLayout,
    background_layout: wgpu::BindGroupLayout,
    uniform: wgpu::Buffer,
    light: wgpu::Buffer,
    transfer: wgpu::Buffer,
    environment: wgpu::TextureView,
    mesh_bind: wgpu::BindGroup,
    background_bind: wgpu::BindGroup,
    mesh: Option<GpuMesh>,
    /// The light's lmax as uploaded (at most [`LIGHT_MAX_LMAX`]).
    light_lmax: usize,
    /// The light's coefficients as uploaded (glossy transfer's `M L`).
    light_coeffs: Vec<[f32; 3]>,
    prt: Option<(usize, usize)>,
    /// Where a diffuse transfer's static term starts in the transfer
    /// buffer, in `f32`s (`None`: no static term).
    prt_static: Option<usize>,
    glossy: Option<GlossyTransfer>,
    /// Draw the mesh's vertices as points instead of its triangles.
    points: bool,
    point_pipelines: [OnceLock<wgpu::RenderPipeline>; LIGHT_MAX_LMAX + 1],
    /// [`Mode::Encoded`]'s pipeline, compiled with the encoding's snippet.
    encoded_pipeline: Option<wgpu::RenderPipeline>,
    map_orientation: MapOrientation,
    environment_rotation: DMat3,
    /// A glTF scene's surfaces, drawn instead of a mesh
    /// ([`Renderer::set_scene`], [`Renderer::set_surfaces`]).
    surfaces: Option<SceneDraws>,
    /// Bind group 1 of the surface pipelines: a material.
    material_layout: wgpu::BindGroupLayout,
    /// `surface.wgsl`'s module per lmax, compiled on first use.
    surface_modules: [OnceLock<wgpu::ShaderModule>; LIGHT_MAX_LMAX + 1],
    surface_pipelines: SurfacePipelines,
    /// `surface_encoded.wgsl` with the encoding's snippet
    /// ([`Renderer::set_encoding`]), and its pipelines.
    surface_encoded_module: Option<wgpu::ShaderModule>,
    surface_encoded_pipelines: SurfacePipelines,
    /// A lightmapped scene's pages (a 1x1 black page without one) and
    /// their linear, clamp-to-edge sampler: bindings 3 and 4 of the mesh
    /// bind group.
    lightmap_pages: wgpu::TextureView,
    lightmap_sampler: wgpu::Sampler,
    /// The lightmap's `LIGHTMAP_*` code and units' scale, when set.
    lightmap: Option<(u32, f32)>,
}

/// The surface pass of SH, PRT and normals modes (`surface.wgsl`).
const SURFACE_PASS: Pass = surface_pass("surfaces", "vs_surface", "fs_surface");
/// The surface pass of an encoding (`surface_encoded.wgsl`).
const SURFACE_ENCODED_PASS: Pass =
    surface_pass("encoded surfaces", "vs_surface", "fs_surface_encoded");

impl std::fmt::Debug for Renderer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Renderer")
            .field("color_format", &self.color_format)
            .field("light_lmax", &self.light_lmax)
            .field("prt", &self.prt)
            .field("prt_static", &self.prt_static)
            .finish_non_exhaustive()
    }
}

impl Renderer {
    /// Pipeline layouts and empty buffers for colour targets of
    /// `color_format`. The pipelines are built on first use, one per lmax
    /// of SH shading (a frame at a new lmax compiles its shaders first).
    ///
    /// A float format (e.g. `Rgba32Float`) receives linear radiance when the
    /// shading has no tone map; an `*Srgb` format is encoded by the
    /// hardware, `Rgba8Unorm` and `Bgra8Unorm` by the shader (when a tone
    /// map is set).
    #[must_use]
    pub fn new(ctx: &GpuContext, color_format: wgpu::TextureFormat) -> Self {
        let device = &ctx.device;
        let vf = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let mesh_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("mesh"),
            entries: &[
                buffer_entry(0, vf, UNIFORM),
                buffer_entry(1, vf, UNIFORM),
                buffer_entry(2, wgpu::ShaderStages::VERTEX, READ),
                wgpu::BindGroupLayoutEntry {
                    binding: 3,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: true },
                        view_dimension: wgpu::TextureViewDimension::D2Array,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 4,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
            ],
        });
        let background_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("background"),
            entries: &[
                buffer_entry(0, vf, UNIFORM),
                buffer_entry(1, vf, UNIFORM),
                wgpu::BindGroupLayoutEntry {
                    binding: 2,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: false },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
            ],
        });
        let mesh_pipeline_layout = pipeline_layout(device, &mesh_layout);
        let background_pipeline_layout = pipeline_layout(device, &background_layout);
        let material_layout = material_layout(device);
        let surfaces = |pass| {
            SurfacePipelines::new(device, &mesh_layout, &material_layout, color_format, pass)
        };
        let (surface_pipelines, surface_encoded_pipelines) =
            (surfaces(SURFACE_PASS), surfaces(SURFACE_ENCODED_PASS));
        let uniform = FrameUniform::buffer(device, "frame");
        let light = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("light"),
            size: (LIGHT_SLOTS * 16) as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let transfer = no_transfer(device);
        let environment = environment_texture(ctx, 1, 1, &[[0.0; 3]]);
        let lightmap_pages = lightmap_texture(ctx, 1, &[&[[0.0; 4]]]);
        let lightmap_sampler = crate::context::linear_clamp_sampler(device, "lightmap");
        let mesh_bind = mesh_bind_group(
            device,
            &mesh_layout,
            [&uniform, &light, &transfer],
            &lightmap_pages,
            &lightmap_sampler,
        );
        let background_bind = bind_group(
            device,
            &background_layout,
            "background",
            &uniform,
            &light,
            wgpu::BindingResource::TextureView(&environment),
        );
        Self {
            color_format,
            mesh_pipelines: Default::default(),
            background_pipelines: Default::default(),
            mesh_pipeline_layout,
            background_pipeline_layout,
            mesh_layout,
            background_layout,
            uniform,
            light,
            transfer,
            environment,
            mesh_bind,
            background_bind,
            mesh: None,
            light_lmax: 0,
            light_coeffs: Vec::new(),
            prt: None,
            prt_static: None,
            glossy: None,
            points: false,
            point_pipelines: Default::default(),
            encoded_pipeline: None,
            map_orientation: MapOrientation::default(),
            environment_rotation: DMat3::IDENTITY,
            surfaces: None,
            material_layout,
            surface_modules: Default::default(),
            surface_pipelines,
            surface_encoded_module: None,
            surface_encoded_pipelines,
            lightmap_pages,
            lightmap_sampler,
            lightmap: None,
        }
    }

    /// The colour format this renderer draws into.
    #[must_use]
    pub fn color_format(&self) -> wgpu::TextureFormat {
        self.color_format
    }

    /// Uploads a mesh (positions and unit normals, in world space); drops
    /// any PRT transfer of the previous mesh.
    pub fn set_mesh(&mut self, ctx: &GpuContext, mesh: &Mesh) {
        let interleaved: Vec<[f32; 6]> = mesh
            .positions
            .iter()
            .zip(&mesh.normals)
            .map(|(p, n)| [p.x, p.y, p.z, n.x, n.y, n.z])
            .collect();
        let indices: Vec<u32> = mesh.triangles.iter().flatten().copied().collect();
        let device = &ctx.device;
        let vertices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("vertices"),
            contents: bytemuck::cast_slice(&interleaved),
            usage: wgpu::BufferUsages::VERTEX,
        });
        let index_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("indices"),
            contents: bytemuck::cast_slice(&indices),
            usage: wgpu::BufferUsages::INDEX,
        });
        self.mesh = Some(GpuMesh {
            vertices,
            indices: index_buffer,
            index_count: indices.len() as u32,
            vertex_count: mesh.vertex_count(),
        });
        self.surfaces = None;
        if self.prt.is_some() {
            self.clear_transfer(ctx);
        }
    }

    /// Uploads a glTF scene to draw instead of a mesh: each unique
    /// primitive once, drawn once per instance (an instance buffer of
    /// transforms), each with its material (`shaders/material.wgsl`): the
    /// diffuse albedo `baseColorFactor x baseColorTexture x COLOR_0 x (1 -
    /// metallic)` per fragment, the texture sRGB-decoded by the GPU and
    /// mip-mapped, `MASK` cut out at its cutoff, `BLEND` as coverage by an
    /// ordered dither, single-sided materials without back faces and
    /// double-sided ones lit on the side seen. Primitives without a
    /// material are untextured, opaque and single-sided, of albedo
    /// `default_albedo`; [`Shading::albedo`] does not apply to the scene.
    /// Drops the previous mesh or scene and any PRT transfer (which needs
    /// [`Renderer::set_surfaces`]).
    ///
    /// # Errors
    /// As shlight-gpu's scene draws: an instance of a missing primitive, a
    /// singular transform, an index beyond the scene's materials or
    /// textures, per-vertex arrays of the wrong length; GPU errors.
    pub fn set_scene(
        &mut self,
        ctx: &GpuContext,
        scene: &Scene,
        default_albedo: [f32; 3],
    ) -> Result<(), GpuError> {
        let draws = SceneDraws::instanced(ctx, &self.material_layout, scene, default_albedo, &[])?;
        self.use_surfaces(ctx, draws);
        Ok(())
    }

    /// [`Renderer::set_scene`] with a lightmap baked for the scene
    /// (`shaders/lightmap.wgsl`): in [`Mode::Sh`] each instance with a
    /// `scaleOffset` shows `albedo / pi E`, `E` the lightmap's irradiance
    /// at the fragment as `shlight sample` reads a lightmapped scene (its
    /// `TEXCOORD_1` through the `scaleOffset`, each page filtered
    /// bilinearly, clamped to the edge, the engine's reconstruction at the
    /// normal seen, the engine's units undone); the other instances keep
    /// the SH light ([`Renderer::set_light`]). The pages are uploaded as
    /// an `Rgba16Float` array, the half floats of shlight's KTX2 pages
    /// unchanged.
    ///
    /// # Errors
    /// As [`Renderer::set_scene`]; pages of another count than the
    /// format's layers or another size than `side x side`, or larger than
    /// the device's textures.
    pub fn set_scene_with_lightmap(
        &mut self,
        ctx: &GpuContext,
        scene: &Scene,
        default_albedo: [f32; 3],
        lightmap: &LightmapTexels<'_>,
    ) -> Result<(), GpuError> {
        let side = lightmap.side;
        let limit = ctx.device.limits().max_texture_dimension_2d as usize;
        if side == 0
            || side > limit
            || lightmap.layers.len() != lightmap.format.layer_count()
            || lightmap.layers.iter().any(|l| l.len() != side * side)
        {
            return Err(GpuError::Invalid(format!(
                "a lightmap of {} pages for {} ({} expected) of {side} x {side} texels \
                 (at most {limit} on this device)",
                lightmap.layers.len(),
                lightmap.format.basis().name(),
                lightmap.format.layer_count()
            )));
        }
        let draws = SceneDraws::instanced(
            ctx,
            &self.material_layout,
            scene,
            default_albedo,
            lightmap.instances,
        )?;
        self.use_surfaces(ctx, draws);
        self.lightmap_pages = ctx.checked(|| lightmap_texture(ctx, side, lightmap.layers))?;
        self.lightmap = Some((
            lightmap_code(lightmap.format),
            lightmap.format.units().scale() as f32,
        ));
        self.rebind_mesh(ctx);
        Ok(())
    }

    /// Uploads a flattened glTF scene (shlight-mesh's [`Surfaces`]: every
    /// instance's triangles in world space) to draw as
    /// [`Renderer::set_scene`] draws a scene, one vertex per world vertex,
    /// so that PRT transfer baked for the flattened mesh
    /// ([`Renderer::set_transfer`], diffuse only) reaches each vertex. In
    /// PRT mode each fragment shows the transferred radiance interpolated
    /// times its albedo: the transfer must be per unit albedo (divided by
    /// the albedo it was baked with).
    ///
    /// # Errors
    /// Arrays of the wrong length, indices beyond the materials or
    /// textures; GPU errors.
    pub fn set_surfaces(&mut self, ctx: &GpuContext, surfaces: &Surfaces) -> Result<(), GpuError> {
        let draws = SceneDraws::flattened(ctx, &self.material_layout, surfaces)?;
        self.use_surfaces(ctx, draws);
        Ok(())
    }

    /// Draws `draws` from now on, instead of a mesh (without a lightmap
    /// until one is set).
    fn use_surfaces(&mut self, ctx: &GpuContext, draws: SceneDraws) {
        self.surfaces = Some(draws);
        self.mesh = None;
        self.lightmap = None;
        if self.prt.is_some() {
            self.clear_transfer(ctx);
        }
    }

    /// The vertices on the GPU: the mesh's, or the scene's unique
    /// primitives' together (an instanced scene's do not grow with its
    /// instances); 0 with neither.
    #[must_use]
    pub fn vertex_count(&self) -> usize {
        match (&self.surfaces, &self.mesh) {
            (Some(s), _) => s.vertex_count(),
            (None, Some(m)) => m.vertex_count,
            (None, None) => 0,
        }
    }

    /// Uploads radiance coefficients (linear RGB, world frame, shlight's
    /// basis), kept to lmax [`LIGHT_MAX_LMAX`].
    pub fn set_light(&mut self, ctx: &GpuContext, radiance: &ShCoeffs<DVec3>) {
        let lmax = radiance.lmax().min(LIGHT_MAX_LMAX);
        let mut slots = [[0.0f32; 4]; LIGHT_SLOTS];
        for (slot, c) in slots.iter_mut().zip(radiance.as_slice()) {
            *slot = [c.x as f32, c.y as f32, c.z as f32, 0.0];
        }
        ctx.queue
            .write_buffer(&self.light, 0, bytemuck::cast_slice(&slots));
        self.light_lmax = lmax;
        self.light_coeffs = slots[..(lmax + 1) * (lmax + 1)]
            .iter()
            .map(|s| [s[0], s[1], s[2]])
            .collect();
    }

    /// Draws the mesh's vertices as points, one pixel each, instead of its
    /// triangles (`true`), with the same shading: each vertex's own value
    /// where it lands, uninterpolated (what a test reads a vertex's
    /// shading from).
    pub fn set_points(&mut self, points: bool) {
        self.points = points;
    }

    /// Uploads an equirect environment map (`width x height` linear RGB
    /// texels, row 0 at the top) for the background, read in `orientation`.
    /// Maps larger than the device's texture limit are halved (2x2 box
    /// averages) until they fit.
    pub fn set_environment(
        &mut self,
        ctx: &GpuContext,
        width: usize,
        height: usize,
        pixels: &[[f32; 3]],
        orientation: MapOrientation,
    ) {
        let max = ctx.device.limits().max_texture_dimension_2d as usize;
        if width > max || height > max {
            let mut image = Image::new(width, height, pixels.to_vec())
                .expect("width * height texels (the caller's map)");
            while image.width() > max || image.height() > max {
                image = image.halve();
            }
            self.environment =
                environment_texture(ctx, image.width(), image.height(), image.pixels());
        } else {
            self.environment = environment_texture(ctx, width, height, pixels);
        }
        self.map_orientation = orientation;
        self.background_bind = bind_group(
            &ctx.device,
            &self.background_layout,
            "background",
            &self.uniform,
            &self.light,
            wgpu::BindingResource::TextureView(&self.environment),
        );
    }

    /// The rotation `R` the light was turned by (a light from `a` now comes
    /// from `R a`), so that the map background turns with it. The caller
    /// rotates the coefficients themselves ([`shlight_core::sh::ShRotation`]).
    pub fn set_environment_rotation(&mut self, r: DMat3) {
        self.environment_rotation = r;
    }

    /// Sets the light of [`Mode::Encoded`]: `snippet` is the WGSL that
    /// shlight-format writes for an encoding (`shlight project MAP
    /// --encoding E --format wgsl`), which defines `shlight_irradiance(n:
    /// vec3<f32>) -> vec3<f32>`, the encoding's irradiance at a unit normal
    /// in world axes, its constants baked in. The snippet holds the
    /// unturned light: the renderer evaluates it at `R^T n` for the
    /// rotation `R` of [`Renderer::set_environment_rotation`] (the SH
    /// coefficients of [`Renderer::set_light`], by contrast, are turned by
    /// the caller). Compiles the pipeline now.
    ///
    /// # Errors
    /// [`GpuError::Runtime`] when the snippet does not compile with the
    /// module (a snippet of another shading language, or without
    /// `shlight_irradiance`).
    pub fn set_encoding(&mut self, ctx: &GpuContext, snippet: &str) -> Result<(), GpuError> {
        let source = shaders::encoded_source(snippet);
        let pipeline = ctx
            .checked(|| {
                let module = ctx
                    .device
                    .create_shader_module(wgpu::ShaderModuleDescriptor {
                        label: Some(ENCODED_MODULE.name),
                        source: wgpu::ShaderSource::Wgsl(source.into()),
                    });
                let pipeline = pipeline_of(
                    &ctx.device,
                    &self.mesh_pipeline_layout,
                    self.color_format,
                    &ENCODED_PASS,
                    &module,
                );
                let surfaces = ctx
                    .device
                    .create_shader_module(wgpu::ShaderModuleDescriptor {
                        label: Some(SURFACE_ENCODED_MODULE.name),
                        source: wgpu::ShaderSource::Wgsl(
                            shaders::surface_encoded_source(snippet).into(),
                        ),
                    });
                (pipeline, surfaces)
            })
            .map_err(|e| match e {
                GpuError::Runtime(why) => GpuError::Runtime(format!(
                    "the encoding's WGSL snippet does not compile: {why}"
                )),
                other => other,
            })?;
        let (pipeline, surfaces) = pipeline;
        self.encoded_pipeline = Some(pipeline);
        self.surface_encoded_module = Some(surfaces);
        self.surface_encoded_pipelines.forget(0);
        Ok(())
    }

    /// `what`, made for `count` vertices, fits the current mesh.
    fn check_vertices(&self, what: &str, count: usize) -> Result<(), GpuError> {
        if let Some(s) = &self.surfaces {
            return match s.world_vertices() {
                Some(n) if n == count => Ok(()),
                Some(n) => Err(GpuError::Invalid(format!(
                    "{what} is for {count} vertices but the flattened scene has {n}"
                ))),
                None => Err(GpuError::Invalid(format!(
                    "{what} is per world vertex: it needs the scene flattened (set_surfaces), \
                     not instanced"
                ))),
            };
        }
        match self.mesh.as_ref().map(|m| m.vertex_count) {
            Some(n) if n == count => Ok(()),
            None => Err(GpuError::Invalid(format!("{what} given before a mesh"))),
            Some(n) => Err(GpuError::Invalid(format!(
                "{what} is for {count} vertices but the mesh has {n}"
            ))),
        }
    }

    /// Uploads PRT transfer vectors for the current mesh.
    ///
    /// # Errors
    /// [`GpuError::Invalid`] without a mesh, or when the vertex counts differ.
    pub fn set_transfer(&mut self, ctx: &GpuContext, t: &TransferView<'_>) -> Result<(), GpuError> {
        self.set_transfer_with_static(ctx, t, &[])
    }

    /// Uploads PRT transfer vectors for the current mesh with a static
    /// exit radiance per vertex (linear RGB; a `.shprt` file's static term,
    /// a glTF scene's punctual lights and emission, docs/shprt.md "Format
    /// version 3"), so that [`Mode::Prt`] shades vertex `v` with `T_v . L +
    /// static_radiance[v]`. The term is added after the fragment's albedo
    /// multiplies a glTF scene's transfer ([`Renderer::set_surfaces`]): it
    /// is exit radiance, its albedo already in it. An empty
    /// `static_radiance` is none: [`Renderer::set_transfer`].
    ///
    /// # Errors
    /// [`GpuError::Invalid`] without a mesh, when the vertex counts differ,
    /// or for a static term of another length than the vertices.
    pub fn set_transfer_with_static(
        &mut self,
        ctx: &GpuContext,
        t: &TransferView<'_>,
        static_radiance: &[[f32; 3]],
    ) -> Result<(), GpuError> {
        self.check_vertices("PRT transfer", t.vertex_count)?;
        if !static_radiance.is_empty() && static_radiance.len() != t.vertex_count {
            return Err(GpuError::Invalid(format!(
                "the static term holds {} vertices but the PRT transfer {}",
                static_radiance.len(),
                t.vertex_count
            )));
        }
        // The static term after the transfer, in the same buffer: a file
        // without one binds nothing more. A non-empty transfer puts it at
        // a non-zero offset, so the shaders read 0 as none.
        let (data, prt_static) = if static_radiance.is_empty() || t.data.is_empty() {
            (std::borrow::Cow::Borrowed(t.data), None)
        } else {
            let mut data = Vec::with_capacity(t.data.len() + 3 * static_radiance.len());
            data.extend_from_slice(t.data);
            data.extend(static_radiance.iter().flatten());
            (std::borrow::Cow::Owned(data), Some(t.data.len()))
        };
        self.transfer = ctx
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("transfer"),
                contents: bytemuck::cast_slice(&data),
                usage: wgpu::BufferUsages::STORAGE,
            });
        self.prt = Some((t.lmax, t.channels));
        self.prt_static = prt_static;
        self.glossy = None;
        self.rebind_mesh(ctx);
        Ok(())
    }

    /// Uploads glossy PRT transfer matrices for the current mesh (docs/shprt.md,
    /// "Glossy transfer"), with the BRDF's `lobe`. [`Mode::Prt`] then
    /// shades each vertex view by view toward the camera:
    /// `sum_lm rho/pi A_l Y_lm(n) T_lm` (`rho` [`Shading::albedo`]'s
    /// diffuse base; zero: the glossy layer alone) plus the glossy layer,
    /// `sum_lm Lambda_l Y_lm(R) T_lm` for [`GlossyLobe::Zonal`], the
    /// weighted bands of [`GlossyLobe::Directions`]; `T = M L` the
    /// transferred radiance. `T` is computed on the CPU when the light (or
    /// the shading lmax) changes: per cluster once for a compressed file,
    /// each vertex then summing its cluster's parts with its weights on the
    /// GPU.
    ///
    /// # Errors
    /// [`GpuError::Invalid`] without a mesh, for another vertex count, an
    /// lmax above [`LIGHT_MAX_LMAX`], zonal coefficients fewer than lmax +
    /// 1, a direction table not of whole rows (four or more) for the lmax,
    /// or more transferred radiance than the device's largest storage
    /// buffer.
    pub fn set_glossy(
        &mut self,
        ctx: &GpuContext,
        matrices: &GlossyView<'_>,
        lobe: GlossyLobe<'_>,
    ) -> Result<(), GpuError> {
        if self.surfaces.is_some() {
            return Err(GpuError::Invalid(
                "glossy transfer is shaded on a mesh, not on a glTF scene's surfaces".into(),
            ));
        }
        self.check_vertices("glossy transfer", matrices.vertex_count)?;
        let lmax = matrices.lmax;
        if lmax > LIGHT_MAX_LMAX {
            return Err(GpuError::Invalid(format!(
                "glossy transfer of lmax {lmax}: the GPU shades to lmax {LIGHT_MAX_LMAX}"
            )));
        }
        let directions = lmax + 1;
        match lobe {
            GlossyLobe::Zonal(lambda) if lambda.len() <= lmax => {
                return Err(GpuError::Invalid(format!(
                    "the lobe has {} zonal coefficients; lmax {lmax} needs {}",
                    lambda.len(),
                    lmax + 1
                )));
            }
            GlossyLobe::Directions(table)
                if table.len() < 4 * directions * directions
                    || table.len() % (directions * directions) != 0 =>
            {
                return Err(GpuError::Invalid(format!(
                    "the lobe's direction table has {} values: not rows of {} at lmax {lmax}, four or more",
                    table.len(),
                    directions * directions
                )));
            }
            _ => {}
        }
        let vectors = matrices.vectors();
        let groups = match &matrices.matrices {
            shlight_baked::GlossyMatrices::Full(_) => matrices.vertex_count,
            shlight_baked::GlossyMatrices::Cpca { clusters, .. } => *clusters,
        };
        let nc = (lmax + 1) * (lmax + 1);
        let mut records = Vec::with_capacity(matrices.vertex_count * (vectors + 1));
        for v in 0..matrices.vertex_count {
            let (g, w) = matrices.vertex_group(v);
            records.push(f32::from_bits(g as u32));
            records.extend_from_slice(w);
        }
        let table = match lobe {
            GlossyLobe::Directions(t) => {
                let at = records.len();
                records.extend_from_slice(t);
                Some((at, t.len() / (directions * directions)))
            }
            GlossyLobe::Zonal(_) => None,
        };
        let parts = records.len();
        let floats = parts as u64 + (groups * (vectors + 1) * nc * 3) as u64;
        let bytes = 4 * floats;
        let limit = ctx
            .device
            .limits()
            .max_storage_buffer_binding_size
            .min(ctx.device.limits().max_buffer_size);
        if bytes > limit || u32::try_from(floats).is_err() {
            return Err(GpuError::Invalid(format!(
                "glossy transfer: {groups} group(s) x {} part(s) of {nc} RGB coefficients and the                  vertices' records take {bytes} bytes; the device's storage buffers hold {limit}                  (compress its matrices by clustered PCA, cpca:C,K, first)",
                vectors + 1
            )));
        }
        let buffer = ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("glossy transfer"),
            size: bytes.max(16),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        if !records.is_empty() {
            ctx.queue
                .write_buffer(&buffer, 0, bytemuck::cast_slice(&records));
        }
        let mut band = [[0.0f32; 4]; 3];
        if let GlossyLobe::Zonal(lambda) = lobe {
            for (l, x) in lambda.iter().take(lmax + 1).enumerate() {
                band[l / 4][l % 4] = *x as f32;
            }
        }
        self.transfer = buffer;
        self.prt = Some((lmax, matrices.channels));
        self.prt_static = None;
        self.glossy = Some(GlossyTransfer {
            matrices: matrices.clone().into_owned(),
            band,
            table,
            parts,
            computed_for: Mutex::new(None),
        });
        self.rebind_mesh(ctx);
        Ok(())
    }

    /// Glossy transfer's parts for the light to `lmax`, computed and
    /// written unless the buffer holds them already.
    fn update_glossy(&self, ctx: &GpuContext, lmax: usize) {
        let Some(g) = &self.glossy else { return };
        let light = &self.light_coeffs[..((lmax + 1) * (lmax + 1)).min(self.light_coeffs.len())];
        let mut computed = g
            .computed_for
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        if computed.as_deref() == Some(light) {
            return;
        }
        let coeffs: Vec<DVec3> = light
            .iter()
            .map(|c| DVec3::from(c.map(f64::from)))
            .collect();
        let t = g.matrices.transferred(&coeffs);
        let values: Vec<f32> = t
            .parts
            .iter()
            .flat_map(|p| [p.x as f32, p.y as f32, p.z as f32])
            .collect();
        if !values.is_empty() {
            ctx.queue.write_buffer(
                &self.transfer,
                4 * g.parts as u64,
                bytemuck::cast_slice(&values),
            );
        }
        *computed = Some(light.to_vec());
    }

    fn clear_transfer(&mut self, ctx: &GpuContext) {
        self.prt = None;
        self.prt_static = None;
        self.glossy = None;
        self.transfer = no_transfer(&ctx.device);
        self.rebind_mesh(ctx);
    }

    /// The mesh pass's bind group over the current transfer buffer.
    fn rebind_mesh(&mut self, ctx: &GpuContext) {
        self.mesh_bind = mesh_bind_group(
            &ctx.device,
            &self.mesh_layout,
            [&self.uniform, &self.light, &self.transfer],
            &self.lightmap_pages,
            &self.lightmap_sampler,
        );
    }

    /// Records a frame into `encoder`: clears `color` to 0 and `depth` to 1,
    /// draws the background (unless none, or normals mode), then the mesh.
    ///
    /// # Errors
    /// [`GpuError::Invalid`] for PRT mode without transfer vectors, or
    /// encoded mode without [`Renderer::set_encoding`].
    pub fn draw(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        color: &wgpu::TextureView,
        depth: &wgpu::TextureView,
        camera: &Camera,
        aspect: f32,
        shading: &Shading,
    ) -> Result<(), GpuError> {
        if shading.mode == Mode::Prt && self.prt.is_none() {
            return Err(GpuError::Invalid(
                "PRT mode needs transfer vectors (none are loaded)".into(),
            ));
        }
        if shading.mode == Mode::Encoded && self.encoded_pipeline.is_none() {
            return Err(GpuError::Invalid(
                "encoded mode needs an encoding's snippet (none is set)".into(),
            ));
        }
        let env_from_world =
            orientation_matrix(self.map_orientation) * self.environment_rotation.transpose();
        let lmax = shading.lmax.min(self.light_lmax);
        let glossy = self
            .glossy
            .as_ref()
            .filter(|_| shading.mode == Mode::Prt)
            .map(|g| {
                self.update_glossy(ctx, lmax);
                GlossyInputs {
                    band: g.band,
                    table: g.table.map(|(at, rows)| (at as u32, rows as u32)),
                    vectors: g.matrices.vectors() as u32,
                    parts: g.parts as u32,
                }
            });
        let uniform = FrameUniform::new(&FrameInputs {
            shading,
            view_proj: camera.view_proj(aspect),
            env_from_world,
            light_from_world: self.environment_rotation.transpose(),
            lmax,
            prt: self.prt,
            prt_static: self.prt_static,
            glossy,
            eye: camera.eye,
            encode_srgb: shader_encodes_srgb(self.color_format),
            lightmap: self.lightmap,
        });
        ctx.queue
            .write_buffer(&self.uniform, 0, bytemuck::bytes_of(&uniform));
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("frame"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: color,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        let device = &ctx.device;
        if shading.mode != Mode::Normals && shading.background != crate::Background::None {
            // Only the SH background evaluates sh_reconstruct.
            let l = if shading.background == crate::Background::Sh {
                lmax
            } else {
                0
            };
            pass.set_pipeline(self.background_pipelines[l].get_or_init(|| {
                pipeline_of(
                    device,
                    &self.background_pipeline_layout,
                    self.color_format,
                    &BACKGROUND_PASS,
                    &shaders::create(device, BACKGROUND_MODULE, l),
                )
            }));
            pass.set_bind_group(0, &self.background_bind, &[]);
            pass.draw(0..3, 0..1);
        }
        if let Some(draws) = &self.surfaces {
            pass.set_bind_group(0, &self.mesh_bind, &[]);
            match (shading.mode, &self.surface_encoded_module) {
                (Mode::Encoded, Some(module)) => draws.draw(&mut pass, |sides| {
                    self.surface_encoded_pipelines
                        .get(device, 0, || module.clone(), sides)
                }),
                (mode, _) => {
                    // Only SH mode evaluates sh_reconstruct.
                    let l = if mode == Mode::Sh { lmax } else { 0 };
                    let module = || {
                        self.surface_modules[l]
                            .get_or_init(|| shaders::create(device, MESH_SURFACE_MODULE, l))
                            .clone()
                    };
                    draws.draw(&mut pass, |sides| {
                        self.surface_pipelines.get(device, l, module, sides)
                    });
                }
            }
        } else if let Some(mesh) = &self.mesh {
            // Only SH mode evaluates sh_reconstruct, and glossy PRT
            // glossy_radiance (to the transfer's lmax).
            let l = match (shading.mode, glossy, self.prt) {
                (Mode::Sh, _, _) => lmax,
                (Mode::Prt, Some(_), Some((prt_lmax, _))) => prt_lmax,
                _ => 0,
            };
            let (pipelines, pass_kind) = if self.points {
                (&self.point_pipelines, &POINTS_PASS)
            } else {
                (&self.mesh_pipelines, &MESH_PASS)
            };
            pass.set_pipeline(match (&self.encoded_pipeline, shading.mode, self.points) {
                (Some(encoded), Mode::Encoded, false) => encoded,
                _ => pipelines[l].get_or_init(|| {
                    pipeline_of(
                        device,
                        &self.mesh_pipeline_layout,
                        self.color_format,
                        pass_kind,
                        &shaders::create(device, MESH_MODULE, l),
                    )
                }),
            });
            pass.set_bind_group(0, &self.mesh_bind, &[]);
            pass.set_vertex_buffer(0, mesh.vertices.slice(..));
            if self.points {
                pass.draw(0..mesh.vertex_count as u32, 0..1);
            } else {
                pass.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed(0..mesh.index_count, 0, 0..1);
            }
        }
        Ok(())
    }
}

/// The mesh: positions and normals interleaved, depth tested and written,
/// both faces drawn (meshes with inconsistent winding still show).
const MESH_PASS: Pass = Pass {
    label: "mesh",
    vertex_entry: "vs_mesh",
    fragment_entry: "fs_mesh",
    vertex_buffers: &[Some(wgpu::VertexBufferLayout {
        array_stride: 24,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3],
    })],
    depth_write: true,
    depth_compare: wgpu::CompareFunction::Less,
    topology: wgpu::PrimitiveTopology::TriangleList,
    cull_mode: None,
    front_face: wgpu::FrontFace::Ccw,
};

/// The mesh's vertices as points ([`Renderer::set_points`]): [`MESH_PASS`]
/// drawn as a point list.
const POINTS_PASS: Pass = Pass {
    label: "points",
    topology: wgpu::PrimitiveTopology::PointList,
    ..MESH_PASS
};

/// The mesh shaded with an encoding: [`MESH_PASS`] with `encoded.wgsl`'s
/// fragment stage.
const ENCODED_PASS: Pass = Pass {
    label: "encoded",
    fragment_entry: "fs_encoded",
    ..MESH_PASS
};

/// The background: one full-screen triangle behind everything.
const BACKGROUND_PASS: Pass = Pass {
    label: "background",
    vertex_entry: "vs_background",
    fragment_entry: "fs_background",
    vertex_buffers: &[],
    depth_write: false,
    depth_compare: wgpu::CompareFunction::Always,
    topology: wgpu::PrimitiveTopology::TriangleList,
    cull_mode: None,
    front_face: wgpu::FrontFace::Ccw,
};

/// The map's own y-up frame from world, as a matrix
/// ([`MapOrientation::map_from_world`] applied to the axes).
fn orientation_matrix(o: MapOrientation) -> DMat3 {
    DMat3::from_cols(
        o.map_from_world(DVec3::X),
        o.map_from_world(DVec3::Y),
        o.map_from_world(DVec3::Z),
    )
}

/// The bind group of a pass: the frame uniform, the light, and the pass's
/// own third binding (the mesh's transfer or the background's map).
fn bind_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    label: &str,
    uniform: &wgpu::Buffer,
    light: &wgpu::Buffer,
    third: wgpu::BindingResource<'_>,
) -> wgpu::BindGroup {
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: uniform.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: light.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: third,
            },
        ],
    })
}

/// The mesh pass's bind group: the frame uniform, the light, the transfer
/// (`buffers`), and the lightmap's pages and sampler.
fn mesh_bind_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    buffers: [&wgpu::Buffer; 3],
    pages: &wgpu::TextureView,
    sampler: &wgpu::Sampler,
) -> wgpu::BindGroup {
    let [uniform, light, transfer] = buffers;
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("mesh"),
        layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: uniform.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: light.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: transfer.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 3,
                resource: wgpu::BindingResource::TextureView(pages),
            },
            wgpu::BindGroupEntry {
                binding: 4,
                resource: wgpu::BindingResource::Sampler(sampler),
            },
        ],
    })
}

/// An `Rgba16Float` array texture of `layers`, each `side x side` linear
/// RGBA texels (rounded to half floats: exact for shlight's half-float
/// pages).
fn lightmap_texture(ctx: &GpuContext, side: usize, layers: &[&[[f32; 4]]]) -> wgpu::TextureView {
    let halves: Vec<u16> = layers
        .iter()
        .flat_map(|l| l.iter().flatten())
        .map(|&x| half::f16::from_f32(x).to_bits())
        .collect();
    let texture = ctx.device.create_texture_with_data(
        &ctx.queue,
        &wgpu::TextureDescriptor {
            label: Some("lightmap"),
            size: wgpu::Extent3d {
                width: side as u32,
                height: side as u32,
                depth_or_array_layers: layers.len() as u32,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba16Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        bytemuck::cast_slice(&halves),
    );
    texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    })
}

/// The storage buffer bound while no PRT transfer is set.
fn no_transfer(device: &wgpu::Device) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("transfer (none)"),
        size: 16,
        usage: wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    })
}

/// An `Rgba32Float` texture of linear RGB texels (read with `textureLoad`).
fn environment_texture(
    ctx: &GpuContext,
    width: usize,
    height: usize,
    pixels: &[[f32; 3]],
) -> wgpu::TextureView {
    let rgba: Vec<[f32; 4]> = pixels.iter().map(|p| [p[0], p[1], p[2], 1.0]).collect();
    let texture = ctx.device.create_texture_with_data(
        &ctx.queue,
        &wgpu::TextureDescriptor {
            label: Some("environment"),
            size: wgpu::Extent3d {
                width: width as u32,
                height: height as u32,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba32Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        bytemuck::cast_slice(&rgba),
    );
    texture.create_view(&Default::default())
}
