//! A glTF scene's surfaces on the GPU, as the surface passes draw them
//! (`shaders/material.wgsl`): vertex buffers, an instance buffer, the
//! materials ([`gpu_materials`]) and the draws.
//!
//! Two forms:
//!
//! - [`SceneDraws::instanced`]: each unique primitive's vertices once, in
//!   its own space, and per instance its transform (and the inverse
//!   transpose for normals) in an instance buffer; a primitive used by `k`
//!   instances is one instanced draw (two when some of its instances
//!   mirror, whose front faces then wind clockwise), so GPU memory grows
//!   with the unique geometry, not with the instances.
//! - [`SceneDraws::flattened`]: the world-space vertices of a flattened
//!   scene (shlight-mesh's [`Surfaces`]), one identity instance, the
//!   triangles grouped by material into one draw each: PRT transfer is per
//!   world vertex, and the vertex index finds it.
//!
//! Per vertex the CPU resolves what depends only on the vertex and its
//! primitive's material: the base colour and metallic-roughness textures'
//! UVs (each texture's own set, its `KHR_texture_transform` applied), the
//! `COLOR_0` (white without one) and the emitted radiance (the volume pass
//! adds it; [`Material::emission`] at the vertex).

use std::ops::Range;

use glam::{Mat3, Mat4, Vec2, Vec3, Vec4};
use shlight_mesh::{MAX_UV_SETS, Material, Scene, Surfaces, TextureRef};
use wgpu::util::DeviceExt;

use crate::gpu_material::{GpuMaterial, gpu_materials};
use crate::{GpuContext, GpuError};

/// One vertex of a surface pass (`SurfaceVertexIn`'s per-vertex part).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
struct SurfaceVertex {
    position: [f32; 3],
    normal: [f32; 3],
    uv: [f32; 2],
    uv_metal: [f32; 2],
    color: [f32; 4],
    emission: [f32; 3],
    uv_lightmap: [f32; 2],
}

/// One instance: world from the primitive's space, the inverse transpose
/// of its linear part for normals (three columns, `w` 0), and its node's
/// lightmap `scaleOffset` (all 0 without one).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
struct SurfaceInstance {
    model: [[f32; 4]; 4],
    normal: [[f32; 4]; 3],
    lightmap: [f32; 4],
}

impl SurfaceInstance {
    fn new(model: Mat4, normal: Mat3) -> Self {
        Self {
            lightmap: [0.0; 4],
            model: model.to_cols_array_2d(),
            normal: [
                normal.x_axis.extend(0.0).to_array(),
                normal.y_axis.extend(0.0).to_array(),
                normal.z_axis.extend(0.0).to_array(),
            ],
        }
    }
}

/// The vertex and instance buffers' layouts of the surface passes.
pub(crate) const SURFACE_VERTEX_BUFFERS: &[Option<wgpu::VertexBufferLayout<'static>>] = &[
    Some(wgpu::VertexBufferLayout {
        array_stride: std::mem::size_of::<SurfaceVertex>() as u64,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &wgpu::vertex_attr_array![
            0 => Float32x3, 1 => Float32x3, 2 => Float32x2, 3 => Float32x2,
            4 => Float32x4, 5 => Float32x3, 13 => Float32x2
        ],
    }),
    Some(wgpu::VertexBufferLayout {
        array_stride: std::mem::size_of::<SurfaceInstance>() as u64,
        step_mode: wgpu::VertexStepMode::Instance,
        attributes: &wgpu::vertex_attr_array![
            6 => Float32x4, 7 => Float32x4, 8 => Float32x4, 9 => Float32x4,
            10 => Float32x4, 11 => Float32x4, 12 => Float32x4, 14 => Float32x4
        ],
    }),
];

/// Which faces a draw shows: single-sided materials lose their back faces,
/// and an instance that mirrors winds its front faces clockwise.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) struct Sides {
    /// The material's `doubleSided`: no culling.
    pub double_sided: bool,
    /// The instance's transform has a negative determinant.
    pub mirrored: bool,
}

impl Sides {
    /// The pipeline's culling.
    pub(crate) fn cull_mode(self) -> Option<wgpu::Face> {
        (!self.double_sided).then_some(wgpu::Face::Back)
    }

    /// The pipeline's front face.
    pub(crate) fn front_face(self) -> wgpu::FrontFace {
        if self.mirrored {
            wgpu::FrontFace::Cw
        } else {
            wgpu::FrontFace::Ccw
        }
    }
}

/// One primitive's buffers.
#[derive(Debug)]
struct GpuPrimitive {
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
}

/// One draw: a range of a primitive's indices, a range of instances, a
/// material.
#[derive(Clone, Debug)]
struct Batch {
    primitive: usize,
    indices: Range<u32>,
    instances: Range<u32>,
    material: usize,
    sides: Sides,
}

/// A glTF scene's surfaces ready to draw (module documentation).
#[derive(Debug)]
pub(crate) struct SceneDraws {
    primitives: Vec<GpuPrimitive>,
    instances: wgpu::Buffer,
    materials: Vec<GpuMaterial>,
    batches: Vec<Batch>,
    /// The vertices uploaded, all primitives together.
    vertex_count: usize,
    /// The flattened form's world vertices (`None`: instanced).
    world_vertices: Option<usize>,
}

/// The UV of `texture` (if any) at a vertex whose sets are `uvs` (a
/// missing set reads as (0, 0)), its transform applied.
fn texture_uv(texture: Option<&TextureRef>, uvs: &[Vec2]) -> Vec2 {
    texture.map_or(Vec2::ZERO, |t| {
        let uv = uvs.get(t.tex_coord).copied().unwrap_or(Vec2::ZERO);
        t.transform.transform_point2(uv)
    })
}

/// A vertex of `material` at `position` and `normal` with UV sets `uvs`,
/// colour `color` and emission `emission`.
fn vertex(
    material: &Material,
    (position, normal): (Vec3, Vec3),
    uvs: &[Vec2],
    color: Vec4,
    emission: Vec3,
) -> SurfaceVertex {
    SurfaceVertex {
        position: position.to_array(),
        normal: normal.to_array(),
        uv: texture_uv(material.base_color_texture.as_ref(), uvs).to_array(),
        uv_metal: texture_uv(material.metallic_roughness_texture.as_ref(), uvs).to_array(),
        color: color.to_array(),
        emission: emission.to_array(),
        uv_lightmap: uvs.get(1).copied().unwrap_or(Vec2::ZERO).to_array(),
    }
}

impl SceneDraws {
    /// `scene`'s unique primitives, each drawn once per instance; a
    /// primitive without a material gets an untextured, opaque,
    /// single-sided one of albedo `default_albedo`. `lightmap` holds each
    /// instance's lightmap `scaleOffset` (`[0; 4]`: none); empty, none
    /// has one.
    ///
    /// # Errors
    /// [`GpuError::Invalid`] for an instance of a primitive the scene does
    /// not hold, a non-finite or singular transform, a material or texture
    /// index beyond the scene's, a UV set or colour array of the wrong
    /// length (each naming the primitive); GPU errors while uploading.
    pub(crate) fn instanced(
        ctx: &GpuContext,
        layout: &wgpu::BindGroupLayout,
        scene: &Scene,
        default_albedo: [f32; 3],
        lightmap: &[[f32; 4]],
    ) -> Result<Self, GpuError> {
        let invalid =
            |message: String| GpuError::Invalid(format!("{}: {message}", scene.source.display()));
        let mut materials = scene.materials.clone();
        materials.push(Material {
            base_color: Vec3::from_array(default_albedo).extend(1.0),
            ..Material::default()
        });
        let default_material = materials.len() - 1;
        // Per primitive its instances, those that mirror last.
        let mut placed: Vec<[Vec<SurfaceInstance>; 2]> = (0..scene.primitives.len())
            .map(|_| [Vec::new(), Vec::new()])
            .collect();
        for (k, instance) in scene.instances.iter().enumerate() {
            let slot = placed.get_mut(instance.primitive).ok_or_else(|| {
                invalid(format!(
                    "instance {k} places primitive {}; the scene has {}",
                    instance.primitive,
                    scene.primitives.len()
                ))
            })?;
            let linear = Mat3::from_mat4(instance.transform);
            let det = linear.determinant();
            if !instance.transform.is_finite() || det == 0.0 || !det.is_finite() {
                return Err(invalid(format!(
                    "{} is placed by a non-finite or singular transform",
                    scene.primitives[instance.primitive].label
                )));
            }
            let normal = linear.inverse().transpose();
            let mut placed = SurfaceInstance::new(instance.transform, normal);
            placed.lightmap = lightmap.get(k).copied().unwrap_or([0.0; 4]);
            slot[usize::from(det < 0.0)].push(placed);
        }
        let device = &ctx.device;
        let mut primitives = Vec::new();
        let mut batches = Vec::new();
        let mut instances = Vec::new();
        let mut vertex_count = 0;
        for (primitive, placed) in scene.primitives.iter().zip(placed) {
            if placed.iter().all(Vec::is_empty) {
                continue;
            }
            let material = match primitive.material {
                None => default_material,
                Some(i) if i < scene.materials.len() => i,
                Some(i) => {
                    return Err(invalid(format!(
                        "{} uses material {i}; the scene has {}",
                        primitive.label,
                        scene.materials.len()
                    )));
                }
            };
            let m = &materials[material];
            let mesh = &primitive.mesh;
            let n = mesh.vertex_count();
            let wrong = |what: &str| {
                invalid(format!(
                    "{} has a {what} of the wrong length",
                    primitive.label
                ))
            };
            if primitive.uvs.iter().any(|set| set.len() != n) {
                return Err(wrong("UV set"));
            }
            if primitive.color_alpha.as_ref().is_some_and(|a| a.len() != n) {
                return Err(wrong("COLOR_0 alpha"));
            }
            for t in [
                &m.base_color_texture,
                &m.metallic_roughness_texture,
                &m.emissive_texture,
            ]
            .into_iter()
            .flatten()
            {
                if t.texture >= scene.textures.len() {
                    return Err(invalid(format!(
                        "{} reads texture {}; the scene has {}",
                        primitive.label,
                        t.texture,
                        scene.textures.len()
                    )));
                }
            }
            let vertices: Vec<SurfaceVertex> = (0..n)
                .map(|v| {
                    let mut uvs = [Vec2::ZERO; MAX_UV_SETS];
                    let sets = primitive.uvs.len().min(MAX_UV_SETS);
                    for (k, uv) in uvs.iter_mut().enumerate().take(sets) {
                        *uv = primitive.uvs[k][v];
                    }
                    let uvs = &uvs[..sets];
                    let rgb = mesh.colors.as_ref().map_or(Vec3::ONE, |c| c[v]);
                    let a = primitive.color_alpha.as_ref().map_or(1.0, |a| a[v]);
                    vertex(
                        m,
                        (mesh.positions[v], mesh.normals[v]),
                        uvs,
                        rgb.extend(a),
                        m.emission(&scene.textures, uvs),
                    )
                })
                .collect();
            let indices: Vec<u32> = mesh.triangles.iter().flatten().copied().collect();
            let at = primitives.len();
            for (mirrored, group) in placed.into_iter().enumerate() {
                if group.is_empty() {
                    continue;
                }
                let first = instances.len() as u32;
                instances.extend(group);
                batches.push(Batch {
                    primitive: at,
                    indices: 0..indices.len() as u32,
                    instances: first..instances.len() as u32,
                    material,
                    sides: Sides {
                        double_sided: m.double_sided,
                        mirrored: mirrored == 1,
                    },
                });
            }
            vertex_count += n;
            primitives.push(upload_primitive(device, &vertices, &indices));
        }
        Ok(Self {
            primitives,
            instances: upload_instances(device, &instances),
            materials: gpu_materials(ctx, layout, &materials, &scene.textures)?,
            batches,
            vertex_count,
            world_vertices: None,
        })
    }

    /// A flattened scene's world-space vertices, one draw per material.
    ///
    /// # Errors
    /// [`GpuError::Invalid`] for per-vertex or per-triangle arrays of the
    /// wrong length, a material or texture index beyond the scene's; GPU
    /// errors while uploading.
    pub(crate) fn flattened(
        ctx: &GpuContext,
        layout: &wgpu::BindGroupLayout,
        surfaces: &Surfaces,
    ) -> Result<Self, GpuError> {
        let mesh = &surfaces.mesh;
        let n = mesh.vertex_count();
        let sets = surfaces.uv_sets;
        let tris = mesh.triangle_count();
        if surfaces.uvs.len() != n * sets
            || surfaces.colors.len() != n
            || surfaces.triangle_material.len() != tris
            || mesh.emission.as_ref().is_some_and(|e| e.len() != n)
        {
            return Err(GpuError::Invalid(format!(
                "a flattened scene's per-vertex or per-triangle arrays do not match its {n} \
                 vertices and {tris} triangles"
            )));
        }
        if let Some(&m) = surfaces
            .triangle_material
            .iter()
            .find(|&&m| m as usize >= surfaces.materials.len())
        {
            return Err(GpuError::Invalid(format!(
                "a flattened scene's triangle uses material {m}; it has {}",
                surfaces.materials.len()
            )));
        }
        // Each vertex takes the material of a triangle that uses it.
        let fallback = surfaces.materials.len().saturating_sub(1) as u32;
        let mut vertex_material = vec![fallback; n];
        for (t, tri) in mesh.triangles.iter().enumerate().rev() {
            for &v in tri {
                vertex_material[v as usize] = surfaces.triangle_material[t];
            }
        }
        let vertices: Vec<SurfaceVertex> = (0..n)
            .map(|v| {
                let m = &surfaces.materials[vertex_material[v] as usize];
                vertex(
                    m,
                    (mesh.positions[v], mesh.normals[v]),
                    &surfaces.uvs[v * sets..][..sets],
                    surfaces.colors[v],
                    mesh.emission.as_ref().map_or(Vec3::ZERO, |e| e[v]),
                )
            })
            .collect();
        // Triangles grouped by material, in order within each.
        let mut order: Vec<usize> = (0..tris).collect();
        order.sort_by_key(|&t| surfaces.triangle_material[t]);
        let indices: Vec<u32> = order.iter().flat_map(|&t| mesh.triangles[t]).collect();
        let mut batches: Vec<Batch> = Vec::new();
        for (k, &t) in order.iter().enumerate() {
            let material = surfaces.triangle_material[t] as usize;
            let end = 3 * (k as u32 + 1);
            match batches.last_mut() {
                Some(b) if b.material == material => b.indices.end = end,
                _ => batches.push(Batch {
                    primitive: 0,
                    indices: end - 3..end,
                    instances: 0..1,
                    material,
                    sides: Sides {
                        double_sided: surfaces.materials[material].double_sided,
                        mirrored: false,
                    },
                }),
            }
        }
        let device = &ctx.device;
        let identity = SurfaceInstance::new(Mat4::IDENTITY, Mat3::IDENTITY);
        Ok(Self {
            primitives: vec![upload_primitive(device, &vertices, &indices)],
            instances: upload_instances(device, &[identity]),
            materials: gpu_materials(ctx, layout, &surfaces.materials, &surfaces.textures)?,
            batches,
            vertex_count: n,
            world_vertices: Some(n),
        })
    }

    /// The vertices uploaded (all primitives together).
    pub(crate) fn vertex_count(&self) -> usize {
        self.vertex_count
    }

    /// The flattened form's world vertices; `None` when instanced.
    pub(crate) fn world_vertices(&self) -> Option<usize> {
        self.world_vertices
    }

    /// Records every draw into `pass` (bind group 0 already set), each with
    /// the pipeline `pipeline` gives for its faces and its material as
    /// bind group 1.
    pub(crate) fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        pipeline: impl Fn(Sides) -> wgpu::RenderPipeline,
    ) {
        pass.set_vertex_buffer(1, self.instances.slice(..));
        for b in &self.batches {
            let primitive = &self.primitives[b.primitive];
            pass.set_pipeline(&pipeline(b.sides));
            pass.set_bind_group(1, &self.materials[b.material].bind, &[]);
            pass.set_vertex_buffer(0, primitive.vertices.slice(..));
            pass.set_index_buffer(primitive.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(b.indices.clone(), 0, b.instances.clone());
        }
    }
}

/// A primitive's vertex and index buffers.
fn upload_primitive(
    device: &wgpu::Device,
    vertices: &[SurfaceVertex],
    indices: &[u32],
) -> GpuPrimitive {
    GpuPrimitive {
        vertices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("surface vertices"),
            contents: bytemuck::cast_slice(vertices),
            usage: wgpu::BufferUsages::VERTEX,
        }),
        indices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("surface indices"),
            contents: bytemuck::cast_slice(indices),
            usage: wgpu::BufferUsages::INDEX,
        }),
    }
}

/// The instance buffer (one identity instance when there are none, so the
/// buffer is never empty).
fn upload_instances(device: &wgpu::Device, instances: &[SurfaceInstance]) -> wgpu::Buffer {
    let filler = [SurfaceInstance::new(Mat4::IDENTITY, Mat3::IDENTITY)];
    let contents = if instances.is_empty() {
        &filler[..]
    } else {
        instances
    };
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("surface instances"),
        contents: bytemuck::cast_slice(contents),
        usage: wgpu::BufferUsages::VERTEX,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vertex_and_instance_records_have_the_layouts_sizes() {
        // position, normal (3 + 3), two UVs (2 + 2), colour (4), emission
        // (3), TEXCOORD_1 (2).
        assert_eq!(std::mem::size_of::<SurfaceVertex>(), 19 * 4);
        // Four model columns, three normal columns and the lightmap's
        // scaleOffset, each a vec4.
        assert_eq!(std::mem::size_of::<SurfaceInstance>(), 8 * 16);
    }

    #[test]
    fn a_texture_reads_its_own_set_through_its_transform() {
        let t = TextureRef {
            texture: 0,
            tex_coord: 1,
            transform: glam::Affine2::from_scale_angle_translation(
                Vec2::splat(2.0),
                0.0,
                Vec2::new(0.5, 0.0),
            ),
        };
        let uvs = [Vec2::new(9.0, 9.0), Vec2::new(0.25, 0.125)];
        assert_eq!(texture_uv(Some(&t), &uvs), Vec2::new(1.0, 0.25));
        // A set the vertex lacks reads (0, 0), transformed; no texture: 0.
        let missing = TextureRef { tex_coord: 3, ..t };
        assert_eq!(texture_uv(Some(&missing), &uvs), Vec2::new(0.5, 0.0));
        assert_eq!(texture_uv(None, &uvs), Vec2::ZERO);
    }
}
