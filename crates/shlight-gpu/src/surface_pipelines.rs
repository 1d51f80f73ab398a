//! The render pipelines of a surface pass (a glTF scene's surfaces,
//! `shaders/material.wgsl`), built on first use: one per shader module the
//! pass compiles (one per lmax, or an encoding's) and per [`Sides`] (the
//! faces culled and the front winding), over two bind groups, the pass's
//! own (0) and the material's (1).

use std::collections::HashMap;
use std::sync::Mutex;

use crate::pipeline::{Pass, pipeline_of};
use crate::scene_draws::{SURFACE_VERTEX_BUFFERS, Sides};

/// The surface pass of `vertex_entry` and `fragment_entry`: the surface
/// vertex and instance buffers, depth tested and written; culling and
/// winding set per [`Sides`].
pub(crate) const fn surface_pass(
    label: &'static str,
    vertex_entry: &'static str,
    fragment_entry: &'static str,
) -> Pass {
    Pass {
        label,
        vertex_entry,
        fragment_entry,
        vertex_buffers: SURFACE_VERTEX_BUFFERS,
        depth_write: true,
        depth_compare: wgpu::CompareFunction::Less,
        topology: wgpu::PrimitiveTopology::TriangleList,
        cull_mode: None,
        front_face: wgpu::FrontFace::Ccw,
    }
}

/// A surface pass's pipelines (module documentation).
pub(crate) struct SurfacePipelines {
    layout: wgpu::PipelineLayout,
    color_format: wgpu::TextureFormat,
    pass: Pass,
    /// By the caller's key of the module, and the faces.
    built: Mutex<HashMap<(usize, Sides), wgpu::RenderPipeline>>,
}

impl SurfacePipelines {
    /// Pipelines of `pass` over the bind groups `group0` (the pass's own)
    /// and `material` (gpu_material's layout), into targets of
    /// `color_format`.
    pub(crate) fn new(
        device: &wgpu::Device,
        group0: &wgpu::BindGroupLayout,
        material: &wgpu::BindGroupLayout,
        color_format: wgpu::TextureFormat,
        pass: Pass,
    ) -> Self {
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(pass.label),
            bind_group_layouts: &[Some(group0), Some(material)],
            immediate_size: 0,
        });
        Self {
            layout,
            color_format,
            pass,
            built: Mutex::new(HashMap::new()),
        }
    }

    /// The pipeline of the module the caller keys `key` (compiled by
    /// `module` on first use of the key) for faces `sides`.
    pub(crate) fn get(
        &self,
        device: &wgpu::Device,
        key: usize,
        module: impl FnOnce() -> wgpu::ShaderModule,
        sides: Sides,
    ) -> wgpu::RenderPipeline {
        let mut built = self
            .built
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        if let Some(p) = built.get(&(key, sides)) {
            return p.clone();
        }
        let pass = Pass {
            cull_mode: sides.cull_mode(),
            front_face: sides.front_face(),
            ..self.pass
        };
        let pipeline = pipeline_of(device, &self.layout, self.color_format, &pass, &module());
        built.insert((key, sides), pipeline.clone());
        pipeline
    }

    /// Forgets the pipelines of `key` (its module changed: a new encoding).
    pub(crate) fn forget(&self, key: usize) {
        self.built
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .retain(|(k, _), _| *k != key);
    }
}

impl std::fmt::Debug for SurfacePipelines {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SurfacePipelines")
            .field("pass", &self.pass.label)
            .finish_non_exhaustive()
    }
}
