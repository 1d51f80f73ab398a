//! Projection of equirect maps to SH on the GPU (`shaders/project.wgsl`).
//!
//! The same quadrature as shlight-core's [`shlight_core::map::project_equirect`],
//! by the same ring transform about the map's pole:
//!
//! ```text
//! L_l^m = sum_j w_l^m(j) C_m(j),  L_l^-m = sum_j w_l^m(j) S_m(j),
//! C_m(j) + i S_m(j) = sum_x f(x, j) e^{i m psi_x},
//! w_l^m(j) = Omega_j Pbar_l^m(cos theta_j)  (times sqrt2 for m > 0)
//! ```
//!
//! with the exact row solid angles `Omega_j` ([`equirect_row_solid_angle`])
//! and texel-centre angles, in `f32` on the GPU. Pass 1 computes each row's
//! ring sums (one workgroup of 32 per row, code written out per lmax by
//! `ring_sums.rs`, rows padded with zero texels to whole quads of 4), pass 2
//! the Legendre sums (one workgroup of 64 per coefficient, a shared-memory
//! tree). The tables are computed in `f64` on
//! the CPU: `(cos psi, sin psi)` per column and `w_l^m(j)` per row, from
//! shlight-core's [`Legendre`]. The CPU then turns the coefficients from
//! the map's pole to its frame in `f64`
//! ([`shlight_core::map::to_frame`]). Maps whose texels exceed one
//! storage binding are sent in chunks of rows.
//!
//! Per texel this is `2 lmax + 1` multiply-adds per channel and the powers
//! of `e^{i psi}`, against `(lmax + 1)^2` basis values and multiply-adds for
//! a per-texel basis; no basis is evaluated per texel at all.

use std::f64::consts::SQRT_2;
use std::sync::OnceLock;

use glam::DVec3;
use shlight_core::map::{
    EquirectView, MapOrientation, equirect_angles, equirect_row_solid_angle, to_frame,
};
use shlight_core::sh::{Legendre, ShCoeffs, legendre_count, legendre_index};
use wgpu::util::DeviceExt;

use crate::ring_sums::ring_slots;
use crate::shaders::{self, PROJECT_MODULE};
use crate::{GpuContext, GpuError};
use shlight_baked::LIGHT_MAX_LMAX;

/// `ProjectParams` of `shaders/project.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct ProjectParams {
    quads: u32,
    height: u32,
    row_offset: u32,
    pad: u32,
}

/// The two compute pipelines of the projection at one lmax.
#[derive(Debug)]
struct Pipelines {
    rows: wgpu::ComputePipeline,
    reduce: wgpu::ComputePipeline,
}

/// The projection's compute pipelines, one pair per lmax (0..=[`LIGHT_MAX_LMAX`]),
/// each built on first use.
#[derive(Debug, Default)]
pub struct GpuProjector {
    pipelines: [OnceLock<Pipelines>; LIGHT_MAX_LMAX + 1],
}

impl Pipelines {
    fn new(ctx: &GpuContext, lmax: usize) -> Self {
        let module = shaders::create(&ctx.device, PROJECT_MODULE, lmax);
        let pipeline = |entry: &str| {
            ctx.device
                .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some(entry),
                    layout: None,
                    module: &module,
                    entry_point: Some(entry),
                    compilation_options: wgpu::PipelineCompilationOptions {
                        // Every workgroup variable is written before it is read.
                        zero_initialize_workgroup_memory: false,
                        ..Default::default()
                    },
                    cache: None,
                })
        };
        Self {
            rows: pipeline("project_rows"),
            reduce: pipeline("legendre_sums"),
        }
    }
}

impl GpuProjector {
    /// A projector; each lmax's pipelines are compiled by its first
    /// projection (`ctx` is the context every projection will use).
    #[must_use]
    pub fn new(_ctx: &GpuContext) -> Self {
        Self::default()
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
        if lmax > LIGHT_MAX_LMAX {
            return Err(GpuError::Invalid(format!(
                "GPU projection goes to lmax {LIGHT_MAX_LMAX}; lmax {lmax} needs the CPU path"
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
        // Rows padded with zero texels to whole quads (4 texels, 3 vec4).
        let padded = w.next_multiple_of(4);
        let row_bytes = (padded * 12) as u64;
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
        let slots = ring_slots(lmax);
        let pipelines = self.pipelines[lmax].get_or_init(|| Pipelines::new(ctx, lmax));
        let device = &ctx.device;
        // Azimuth about the map's pole, as shlight-core's ring transform
        // (the padding columns hold zero texels; their angles do not matter).
        let sign = o.pole_azimuth_sign();
        let columns: Vec<[f32; 2]> = (0..padded)
            .map(|i| {
                let psi = sign * equirect_angles(i, 0, w, h).1;
                [psi.cos() as f32, psi.sin() as f32]
            })
            .collect();
        let legendre = Legendre::<f64>::new(lmax);
        let per_row = legendre_count(lmax);
        let mut pbar = vec![0.0; per_row];
        let mut weights = Vec::with_capacity(h * per_row);
        for j in 0..h {
            let theta = equirect_angles(0, j, w, h).0;
            legendre.eval(theta.cos(), &mut pbar);
            let omega = equirect_row_solid_angle(j, w, h);
            let row = weights.len();
            weights.resize(row + per_row, 0.0);
            for l in 0..=lmax {
                for m in 0..=l {
                    let p = legendre_index(l, m);
                    let scale = if m == 0 { omega } else { SQRT_2 * omega };
                    weights[row + p] = (scale * pbar[p]) as f32;
                }
            }
        }
        let storage = |label, contents: &[u8]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage: wgpu::BufferUsages::STORAGE,
            })
        };
        let columns_buffer = storage("columns", bytemuck::cast_slice(&columns));
        let weights_buffer = storage("legendre weights", bytemuck::cast_slice(&weights));
        let texels = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("texels"),
            size: chunk_rows as u64 * row_bytes,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let rings = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("ring sums"),
            size: (h * 3 * slots * 4) as u64,
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
        fn entry(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
            wgpu::BindGroupEntry {
                binding,
                resource: buffer.as_entire_binding(),
            }
        }
        // At lmax 0 the first pass reads no azimuths, so its layout (derived
        // from the shader) has no binding 2.
        let rows_entries = [
            entry(0, &params),
            entry(1, &texels),
            entry(3, &rings),
            entry(2, &columns_buffer),
        ];
        let rows_bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("project rows"),
            layout: &pipelines.rows.get_bind_group_layout(0),
            entries: &rows_entries[..if lmax == 0 { 3 } else { 4 }],
        });
        let reduce_bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("legendre sums"),
            layout: &pipelines.reduce.get_bind_group_layout(0),
            entries: &[
                entry(0, &params),
                entry(3, &rings),
                entry(4, &weights_buffer),
                entry(5, &result),
            ],
        });
        ctx.checked(|| {
            let mut start = 0;
            while start < h {
                let n = chunk_rows.min(h - start);
                let p = ProjectParams {
                    quads: (padded / 4) as u32,
                    height: h as u32,
                    row_offset: start as u32,
                    pad: 0,
                };
                ctx.queue.write_buffer(&params, 0, bytemuck::bytes_of(&p));
                let chunk = &map.pixels[start * w..(start + n) * w];
                if padded == w {
                    ctx.queue
                        .write_buffer(&texels, 0, bytemuck::cast_slice(chunk));
                } else {
                    let mut rows = vec![[0.0f32; 3]; n * padded];
                    for (to, from) in rows.chunks_mut(padded).zip(chunk.chunks(w)) {
                        to[..w].copy_from_slice(from);
                    }
                    ctx.queue
                        .write_buffer(&texels, 0, bytemuck::cast_slice(&rows));
                }
                let mut encoder = device.create_command_encoder(&Default::default());
                {
                    let mut pass = encoder.begin_compute_pass(&Default::default());
                    pass.set_pipeline(&pipelines.rows);
                    pass.set_bind_group(0, &rows_bind, &[]);
                    pass.dispatch_workgroups(n as u32, 1, 1);
                    if start + n == h {
                        pass.set_pipeline(&pipelines.reduce);
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
        let about_pole = ShCoeffs::from_vec(coeffs).expect("(lmax+1)^2 coefficients");
        Ok(to_frame(about_pole, o.frame))
    }
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
