//! Projection of equirect maps to SH on the GPU (`shaders/project.wgsl`).
//!
//! The same quadrature as shlight-core's [`shlight_core::projection::project_equirect`]:
//! `L_i = sum_j Omega_j sum_x f(x, j) Y_i(d(x, j))` with the exact row solid
//! angles `Omega_j` ([`equirect_row_solid_angle`]) and texel-centre
//! directions, in `f32` on the GPU: pass 1 sums each row (one workgroup of 64
//! per row, shared-memory tree reduction), pass 2 sums the rows (one
//! workgroup of 256 per coefficient). The row and column tables (`cos θ`,
//! `sin θ`, `Ω` per row; `cos φ`, `sin φ` per column) are computed in `f64`
//! on the CPU. Maps whose texels exceed one storage binding are sent in
//! chunks of rows.

use std::f64::consts::PI;

use glam::{DMat3, DVec3, Mat4};
use shlight_core::ShCoeffs;
use shlight_core::projection::{EquirectView, MapOrientation, equirect_row_solid_angle};
use wgpu::util::DeviceExt;

use crate::shaders::{self, PROJECT_MODULE};
use crate::shading::MAX_LMAX;
use crate::{GpuContext, GpuError};

/// `ProjectParams` of `shaders/project.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct ProjectParams {
    world_from_map: [[f32; 4]; 4],
    width: u32,
    height: u32,
    row_offset: u32,
    lmax: u32,
}

/// The two compute pipelines of the projection.
#[derive(Debug)]
pub struct GpuProjector {
    rows: wgpu::ComputePipeline,
    reduce: wgpu::ComputePipeline,
}

impl GpuProjector {
    /// Compiles the pipelines.
    #[must_use]
    pub fn new(ctx: &GpuContext) -> Self {
        // The projection has no sh_reconstruct: its lmax is a run-time parameter.
        let module = shaders::create(&ctx.device, PROJECT_MODULE, 0);
        let pipeline = |entry: &str| {
            ctx.device
                .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some(entry),
                    layout: None,
                    module: &module,
                    entry_point: Some(entry),
                    compilation_options: Default::default(),
                    cache: None,
                })
        };
        Self {
            rows: pipeline("project_rows"),
            reduce: pipeline("reduce_rows"),
        }
    }

    /// Radiance coefficients to `lmax` of an equirect map read in `o`.
    ///
    /// # Errors
    /// [`GpuError::Invalid`] for `lmax > 8`, an empty map, a pixel count
    /// other than `width * height`, or a row too long for one storage
    /// binding; [`GpuError::Runtime`] when the GPU fails.
    pub fn project(
        &self,
        ctx: &GpuContext,
        map: EquirectView<'_>,
        lmax: usize,
        o: MapOrientation,
    ) -> Result<ShCoeffs<DVec3>, GpuError> {
        let (w, h) = (map.width, map.height);
        if lmax > MAX_LMAX {
            return Err(GpuError::Invalid(format!(
                "GPU projection goes to lmax {MAX_LMAX}; lmax {lmax} needs the CPU path"
            )));
        }
        if w == 0 || h == 0 || map.pixels.len() != w * h {
            return Err(GpuError::Invalid(format!(
                "a {w}x{h} map needs {} texels, got {}",
                w * h,
                map.pixels.len()
            )));
        }
        let limits = ctx.device.limits();
        let row_bytes = (w * 12) as u64;
        let max_binding = limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size);
        let chunk_rows = (max_binding / row_bytes)
            .min(u64::from(limits.max_compute_workgroups_per_dimension))
            .min(h as u64) as usize;
        if chunk_rows == 0 {
            return Err(GpuError::Invalid(format!(
                "a row of {w} texels exceeds this GPU's storage buffer limit"
            )));
        }
        let count = (lmax + 1) * (lmax + 1);
        let device = &ctx.device;
        let rows: Vec<[f32; 4]> = (0..h)
            .map(|j| {
                let theta = PI * (j as f64 + 0.5) / h as f64;
                let omega = equirect_row_solid_angle(j, w, h);
                [theta.cos() as f32, theta.sin() as f32, omega as f32, 0.0]
            })
            .collect();
        let columns: Vec<[f32; 2]> = (0..w)
            .map(|i| {
                let phi = 2.0 * PI * ((i as f64 + 0.5) / w as f64 - 0.5);
                [phi.cos() as f32, phi.sin() as f32]
            })
            .collect();
        let storage = |label, contents: &[u8]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage: wgpu::BufferUsages::STORAGE,
            })
        };
        let rows_buffer = storage("rows", bytemuck::cast_slice(&rows));
        let columns_buffer = storage("columns", bytemuck::cast_slice(&columns));
        let texels = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("texels"),
            size: chunk_rows as u64 * row_bytes,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let partials = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("row sums"),
            size: (h * count * 16) as u64,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
        let result = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("coefficients"),
            size: (count * 16) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("coefficients readback"),
            size: (count * 16) as u64,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("project params"),
            size: std::mem::size_of::<ProjectParams>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let world_from_map = world_from_map(o);
        fn entry(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
            wgpu::BindGroupEntry {
                binding,
                resource: buffer.as_entire_binding(),
            }
        }
        let rows_bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("project rows"),
            layout: &self.rows.get_bind_group_layout(0),
            entries: &[
                entry(0, &params),
                entry(1, &texels),
                entry(2, &rows_buffer),
                entry(3, &columns_buffer),
                entry(4, &partials),
            ],
        });
        let reduce_bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("reduce rows"),
            layout: &self.reduce.get_bind_group_layout(0),
            entries: &[entry(0, &params), entry(4, &partials), entry(5, &result)],
        });
        ctx.checked(|| {
            let mut start = 0;
            while start < h {
                let n = chunk_rows.min(h - start);
                let p = ProjectParams {
                    world_from_map,
                    width: w as u32,
                    height: h as u32,
                    row_offset: start as u32,
                    lmax: lmax as u32,
                };
                ctx.queue.write_buffer(&params, 0, bytemuck::bytes_of(&p));
                ctx.queue.write_buffer(
                    &texels,
                    0,
                    bytemuck::cast_slice(&map.pixels[start * w..(start + n) * w]),
                );
                let mut encoder = device.create_command_encoder(&Default::default());
                {
                    let mut pass = encoder.begin_compute_pass(&Default::default());
                    pass.set_pipeline(&self.rows);
                    pass.set_bind_group(0, &rows_bind, &[]);
                    pass.dispatch_workgroups(n as u32, 1, 1);
                    if start + n == h {
                        pass.set_pipeline(&self.reduce);
                        pass.set_bind_group(0, &reduce_bind, &[]);
                        pass.dispatch_workgroups(count as u32, 1, 1);
                    }
                }
                if start + n == h {
                    encoder.copy_buffer_to_buffer(&result, 0, &readback, 0, None);
                }
                ctx.queue.submit([encoder.finish()]);
                start += n;
            }
        })?;
        let bytes = crate::readback::read_buffer(ctx, &readback)?;
        let values: &[[f32; 4]] = bytemuck::cast_slice(&bytes);
        let coeffs: Vec<DVec3> = values
            .iter()
            .map(|v| DVec3::new(f64::from(v[0]), f64::from(v[1]), f64::from(v[2])))
            .collect();
        Ok(ShCoeffs::from_vec(coeffs).expect("(lmax+1)^2 coefficients"))
    }
}

/// World from the map's own y-up frame, as the shader's 4x4 matrix
/// ([`MapOrientation::world_from_map`] applied to the axes).
fn world_from_map(o: MapOrientation) -> [[f32; 4]; 4] {
    let m = DMat3::from_cols(
        o.world_from_map(DVec3::X),
        o.world_from_map(DVec3::Y),
        o.world_from_map(DVec3::Z),
    );
    Mat4::from_mat3(m.as_mat3()).to_cols_array_2d()
}

/// [`GpuProjector::project`] with pipelines compiled for this one call.
///
/// # Errors
/// As [`GpuProjector::project`].
pub fn project_equirect(
    ctx: &GpuContext,
    map: EquirectView<'_>,
    lmax: usize,
    o: MapOrientation,
) -> Result<ShCoeffs<DVec3>, GpuError> {
    GpuProjector::new(ctx).project(ctx, map, lmax, o)
}
