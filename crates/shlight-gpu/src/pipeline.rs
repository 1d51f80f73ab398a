//! What every render pass shares: the depth format, bind group layout
//! entries, pipeline layouts, and [`Pass`], what the render pipelines
//! differ in, with [`pipeline_of`], which builds one.

/// Depth buffer format of every frame.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// A uniform block.
pub(crate) const UNIFORM: wgpu::BufferBindingType = wgpu::BufferBindingType::Uniform;
/// A read-only storage buffer.
pub(crate) const READ: wgpu::BufferBindingType =
    wgpu::BufferBindingType::Storage { read_only: true };
/// A read-write storage buffer.
pub(crate) const WRITE: wgpu::BufferBindingType =
    wgpu::BufferBindingType::Storage { read_only: false };

/// A bind group layout entry for a buffer of type `ty` (the whole buffer,
/// no dynamic offset).
pub(crate) fn buffer_entry(
    binding: u32,
    visibility: wgpu::ShaderStages,
    ty: wgpu::BufferBindingType,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// A pipeline layout of one bind group, `layout`, without immediates.
pub(crate) fn pipeline_layout(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
) -> wgpu::PipelineLayout {
    device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: None,
        bind_group_layouts: &[Some(layout)],
        immediate_size: 0,
    })
}

/// What the render pipelines ([`pipeline_of`]) differ in besides their
/// shader module and layout: the mesh, encoded and background passes in
/// `renderer.rs`, the volume pass's in `volume.rs`, the surface passes'
/// in `surface_pipelines.rs`.
pub(crate) struct Pass {
    /// The pipeline's label.
    pub label: &'static str,
    /// The vertex and fragment entry points in the module.
    pub vertex_entry: &'static str,
    pub fragment_entry: &'static str,
    /// The vertex buffers' layouts, in slot order.
    pub vertex_buffers: &'static [Option<wgpu::VertexBufferLayout<'static>>],
    /// Whether fragments write depth, and how they are tested against it.
    pub depth_write: bool,
    pub depth_compare: wgpu::CompareFunction,
    /// Triangles, or one point per vertex.
    pub topology: wgpu::PrimitiveTopology,
    /// The faces culled (`None`: both drawn) and which winding is the
    /// front.
    pub cull_mode: Option<wgpu::Face>,
    pub front_face: wgpu::FrontFace,
}

/// The render pipeline of `pass` over a compiled `module`, for colour
/// targets of `color_format` (written whole, no blending) and a
/// [`DEPTH_FORMAT`] depth target, the faces the pass culls left out.
pub(crate) fn pipeline_of(
    device: &wgpu::Device,
    layout: &wgpu::PipelineLayout,
    color_format: wgpu::TextureFormat,
    pass: &Pass,
    module: &wgpu::ShaderModule,
) -> wgpu::RenderPipeline {
    let targets = [Some(wgpu::ColorTargetState {
        format: color_format,
        blend: None,
        write_mask: wgpu::ColorWrites::ALL,
    })];
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(pass.label),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some(pass.vertex_entry),
            compilation_options: Default::default(),
            buffers: pass.vertex_buffers,
        },
        primitive: wgpu::PrimitiveState {
            topology: pass.topology,
            cull_mode: pass.cull_mode,
            front_face: pass.front_face,
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: Some(pass.depth_write),
            depth_compare: Some(pass.depth_compare),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some(pass.fragment_entry),
            compilation_options: Default::default(),
            targets: &targets,
        }),
        multiview_mask: None,
        cache: None,
    })
}
