//! Glossy transfer matrices (Sloan, Kautz & Snyder 2002, §5).
//! [`GlossyTransfer`] states the matrices and their exit radiance;
//! [`bake_glossy`] the estimator.

use core::f64::consts::PI;

use glam::{DVec3, Vec3};
use rayon::prelude::*;
use std::borrow::Cow;

use shlight_baked::{GlossyMatrices, GlossyView, TransferredRadiance};
use shlight_core::sh::{ShBasis, clamped_cosine_eigenvalue, sh_count};
use shlight_format::{GlossyData, ShprtFile};
use shlight_mesh::Mesh;

use crate::brdf::{Brdf, BrdfLobe};
use crate::cast::Cast;
use crate::options::{BakeOptions, Mode, Stage};
use crate::records::Kernels;

/// The most bytes a glossy bake's matrices may take (the file's data, and
/// the bake's memory for them): 4 GiB.
pub const MAX_GLOSSY_BYTES: u64 = 4 << 30;

/// Vertices per task of the matrices' sums.
const CHUNK: usize = 64;

/// Per-vertex glossy transfer matrices (Sloan, Kautz & Snyder 2002, §5)
/// and what produced them.
///
/// For a vertex at `p` with unit normal `n`, under distant radiance
/// `L(w) = sum_j L_j Y_j(w)`, the *transferred radiance* (the light arriving
/// at `p` after shadows and interreflections) is `T_p = M_p L`, with `M_p`
/// the `(lmax+1)^2 x (lmax+1)^2` matrix
///
/// ```text
/// M_p,ij = int Y_i(w) V_p(w) Y_j(w) dw                       (shadowed)
///        + int Y_i(w) (1 - V_p(w)) T^{B-1}_j(q(p, w)) dw      (with B = --bounces > 0)
/// ```
///
/// in the global frame (turning the light is turning `L`), one matrix per
/// colour channel where the albedo is coloured and there are bounces (the
/// bounce light is the only place the albedo enters; otherwise one). `V_p`
/// is 1 where the ray from `p` along `w` escapes the mesh and 0 where it
/// meets it or where `w` is below the tangent plane (`n.w <= 0`: the
/// surface itself). `q(p, w)` is the point the ray meets, and
/// `T^{B-1}(q)` its diffuse transfer vector ([`crate::Transfer`]: shadowed,
/// with `B - 1` bounces, albedo over pi folded in; barycentric
/// interpolation of its triangle's vertices), so `T^{B-1}(q) . L` is the
/// radiance the diffuse mesh sends from `q` towards `p`: light that reached
/// `p` after 1 to `B` diffuse bounces (with surfaces,
/// [`BakeOptions::surfaces`], `T^{B-1}(q)` is the albedo of the texel hit
/// times the light arriving there, interpolated, as in [`crate::Transfer`],
/// and cut-outs let rays through). A ray meeting the back of a triangle
/// brings nothing. Unshadowed, `V_p = 1` everywhere (the whole sphere) and
/// `M_p` is the identity but for sampling error.
///
/// Exit radiance towards the unit view direction `w_o` (from `p` to the
/// eye) for a [`Brdf`] with zonal coefficients `Lambda_l`:
///
/// ```text
/// L_o = sum_lm Lambda_l T_p,lm Y_lm(R),   R = 2 (n.w_o) n - w_o
/// ```
///
/// the transferred radiance convolved with the lobe about the mirror
/// direction `R` ([`Brdf`]). Nothing is clamped: a view from below
/// the surface gives the formula's value.
///
/// For `ggx:ALPHA[,F0]`, not a lobe about `R`, the exit radiance is the
/// transferred radiance integrated against the BRDF times the cosine over
/// the hemisphere, through the BRDF's projection tabulated per view
/// elevation ([`crate::GgxLobe`] states it); 0 for a view from below.
#[derive(Clone, Debug)]
pub struct GlossyTransfer {
    /// Highest SH degree.
    pub lmax: usize,
    /// 1, or 3 where a coloured albedo reflects the bounces.
    pub channels: usize,
    /// Vertices, in the mesh's order.
    pub vertex_count: usize,
    /// `vertex_count * channels * (lmax+1)^4` values: vertex-major, then
    /// channel, then row `i` (the transferred radiance's coefficient), then
    /// column `j` (the light's): `T_i = sum_j M_ij L_j`.
    pub matrices: Vec<f32>,
    /// The transport: unshadowed, shadowed, or interreflected with its
    /// bounces.
    pub transport: Mode,
    /// Directions in the shared set.
    pub samples: usize,
    /// Rays cast.
    pub rays: u64,
}

/// Channels of a glossy bake of `options`: 3 when its albedo is coloured
/// (or it has surfaces, [`BakeOptions::channels`]) and it gathers bounces,
/// 1 otherwise.
#[must_use]
pub fn glossy_channels(options: &BakeOptions) -> usize {
    if options.mode.bounces() > 0 {
        options.channels()
    } else {
        1
    }
}

/// Bytes of the matrices of `vertex_count` vertices, `channels` each, to
/// `lmax`, with the positions and normals a `.shprt` file keeps beside
/// them; `None` when that overflows.
#[must_use]
pub fn glossy_bytes(vertex_count: usize, channels: usize, lmax: usize) -> Option<u64> {
    let nc = sh_count(lmax) as u64;
    let per_vertex = (channels as u64)
        .checked_mul(nc.checked_mul(nc)?)?
        .checked_add(6)?;
    (vertex_count as u64)
        .checked_mul(per_vertex)?
        .checked_mul(4)
}

/// Bakes the glossy transfer matrix of every vertex of `mesh`, with
/// `options.mode` the transport ([`Mode::Unshadowed`], [`Mode::Shadowed`],
/// [`Mode::Interreflected`] with `B` bounces: the matrices' light after 1
/// to `B` diffuse bounces). The emission is not part of glossy transfer
/// and is ignored. [`GlossyTransfer`] states what the matrices are.
///
/// # Estimator
///
/// The diffuse bake's seeded stratified directions `s_j` (equal solid
/// angles `4 pi / N`, [`crate::bake`]), its ray origins and its rays:
/// `M_p ~ 4 pi / N sum_j Y(s_j) (V_j Y(s_j) + (1 - V_j) T^{B-1}(q_j))^T`,
/// summed per vertex in `f64` (the visible part's symmetric half only),
/// stored as `f32`, vertices in parallel, the same bit for bit at any
/// thread count.
///
/// `progress` as [`crate::bake`]'s, with [`Stage::Matrices`] in
/// vertices.
///
/// # Panics
/// If a per-vertex albedo has another length than the mesh's vertices.
#[must_use]
pub fn bake_glossy(
    mesh: &Mesh,
    options: &BakeOptions,
    progress: &(dyn Fn(Stage, usize, usize) + Sync),
) -> GlossyTransfer {
    let options = BakeOptions {
        emission: None,
        direct_irradiance: None,
        ..options.clone()
    };
    let transport = options.mode;
    let bounces = transport.bounces();
    let shadowed = transport != Mode::Unshadowed;
    let cast = Cast::new(mesh, None, &options, None, shadowed, bounces > 0, progress);
    // The diffuse transfer the mesh sends back: B - 1 bounces.
    // With surfaces, what arrives at the vertices, which a hit multiplies
    // by its texel's albedo.
    let diffuse = if bounces > 0 {
        let d = cast.diffuse(&options, bounces - 1, Kernels::detect(), progress);
        match d.incident {
            Some(arriving) => arriving.coeffs,
            None => d.total,
        }
    } else {
        Vec::new()
    };
    let channels = glossy_channels(&options);
    let (nc, n) = (cast.nc, cast.order.len());
    let nn = nc * nc;
    let stride = channels * nn;
    // The diffuse records' stride (the albedo's channels; equal to
    // `channels` whenever there are bounces).
    let dstride = cast.channels * nc;
    let weight = 4.0 * PI / cast.dirs.len() as f64;
    let done = std::sync::atomic::AtomicUsize::new(0);
    let mut ranked = vec![0.0f32; n * stride];
    ranked
        .par_chunks_mut(CHUNK * stride)
        .enumerate()
        .for_each(|(chunk, out)| {
            let first = chunk * CHUNK;
            // Per direction, the next of its front hits for this chunk's
            // vertices, taken in rank order.
            let mut cursor: Vec<usize> = if bounces > 0 {
                cast.front_hits
                    .iter()
                    .map(|h| h.partition_point(|x| (x.rank as usize) < first))
                    .collect()
            } else {
                Vec::new()
            };
            let mut visible = vec![0.0f64; nn];
            let mut bounced = vec![0.0f64; stride];
            let mut tq = vec![0.0f64; dstride];
            for (k, m) in out.chunks_exact_mut(stride).enumerate() {
                let s = first + k;
                let normal = cast.normals[s];
                visible.fill(0.0);
                bounced.fill(0.0);
                for (j, d) in cast.dirs.iter().enumerate() {
                    let hit = if bounces > 0 {
                        let hits = &cast.front_hits[j];
                        let c = &mut cursor[j];
                        while *c < hits.len() && (hits[*c].rank as usize) < s {
                            *c += 1;
                        }
                        (*c < hits.len() && hits[*c].rank as usize == s).then(|| (hits[*c], *c))
                    } else {
                        None
                    };
                    let y = &cast.ylm[j * nc..][..nc];
                    let escaped = if shadowed {
                        if normal.dot(*d) <= 0.0 {
                            continue;
                        }
                        cast.visible[j * cast.words + s / 64] >> (s % 64) & 1 == 1
                    } else {
                        true
                    };
                    if escaped {
                        // The symmetric Y Y^T, upper half.
                        for i in 0..nc {
                            let a = y[i];
                            for (r, b) in visible[i * nc + i..(i + 1) * nc].iter_mut().zip(&y[i..])
                            {
                                *r += a * b;
                            }
                        }
                    } else if let Some((h, index)) = hit {
                        let [a, b, c] = cast.triangles[h.triangle as usize];
                        let ws = [1.0 - h.b1 - h.b2, h.b1, h.b2];
                        tq.fill(0.0);
                        for (corner, wc) in [a, b, c].into_iter().zip(ws) {
                            let r = &diffuse[corner as usize * dstride..][..dstride];
                            for (t, x) in tq.iter_mut().zip(r) {
                                *t += f64::from(wc) * f64::from(*x);
                            }
                        }
                        if cast.texel {
                            let rho = cast.hit_albedo[j][index];
                            for (ch, t) in tq.chunks_exact_mut(nc).enumerate() {
                                t.iter_mut().for_each(|x| *x *= f64::from(rho[ch]));
                            }
                        }
                        for ch in 0..channels {
                            let t = &tq[ch * nc..][..nc];
                            for (i, a) in y.iter().enumerate() {
                                let row = &mut bounced[ch * nn + i * nc..][..nc];
                                for (r, b) in row.iter_mut().zip(t) {
                                    *r += a * b;
                                }
                            }
                        }
                    }
                }
                for ch in 0..channels {
                    for i in 0..nc {
                        for jj in 0..nc {
                            let v = visible[i.min(jj) * nc + i.max(jj)];
                            m[ch * nn + i * nc + jj] =
                                (weight * (v + bounced[ch * nn + i * nc + jj])) as f32;
                        }
                    }
                }
            }
            let rows = out.len() / stride;
            progress(
                Stage::Matrices,
                done.fetch_add(rows, std::sync::atomic::Ordering::Relaxed) + rows,
                n,
            );
        });
    // By vertex.
    let mut matrices = vec![0.0f32; ranked.len()];
    for (row, &v) in ranked.chunks_exact(stride).zip(&cast.order) {
        matrices[v as usize * stride..][..stride].copy_from_slice(row);
    }
    GlossyTransfer {
        lmax: options.lmax,
        channels,
        vertex_count: n,
        matrices,
        transport,
        samples: cast.dirs.len(),
        rays: cast.rays,
    }
}

impl GlossyTransfer {
    /// The `.shprt` file of this bake of `mesh` for `brdf` (format version
    /// 2, docs/shprt.md): the matrices, the vertices' positions and
    /// normals, and what produced them.
    #[must_use]
    pub fn to_shprt(
        &self,
        mesh: &Mesh,
        brdf: Brdf,
        seed: u64,
        albedo: Option<[f32; 3]>,
        name: &str,
    ) -> ShprtFile {
        ShprtFile {
            lmax: self.lmax,
            channels: self.channels,
            vertex_count: self.vertex_count,
            transfer: self.matrices.clone(),
            mode: "glossy".into(),
            rays_per_vertex: self.samples as u64,
            bounces: self.transport.bounces(),
            seed,
            albedo,
            mesh_hash: mesh.content_hash(),
            mesh: name.to_string(),
            static_light: None,
            glossy: Some(GlossyData {
                brdf: brdf.name(),
                transport: self.transport.name().to_string(),
                positions: mesh.positions.iter().map(|p| p.to_array()).collect(),
                normals: mesh.normals.iter().map(|n| n.to_array()).collect(),
                cpca: None,
            }),
        }
    }

    /// Exit radiance per vertex of `mesh` (the baked one) under `light`
    /// seen from `view`, for `brdf` ([`glossy_exit_radiance`]).
    #[must_use]
    pub fn exit_radiance(
        &self,
        mesh: &Mesh,
        brdf: Brdf,
        light: &[DVec3],
        view: Observer,
    ) -> Vec<DVec3> {
        glossy_exit_radiance(
            &self.matrices,
            self.lmax,
            self.channels,
            &mesh.positions,
            &mesh.normals,
            &brdf.lobe(self.lmax),
            light,
            view,
        )
    }
}

/// Where a glossy surface is seen from: the eye, at infinity along one
/// direction or at a point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Observer {
    /// One direction for every vertex, from the vertex to the eye (an
    /// orthographic camera looking along its negative); need not be unit,
    /// must not be zero.
    Direction(DVec3),
    /// A camera at this point: `w_o` is from each vertex to it (where the
    /// eye sits on a vertex, that vertex's normal).
    Eye(DVec3),
}

impl Observer {
    /// `w_o` at a vertex at `p` with normal `n`: unit, from `p` to the eye.
    #[must_use]
    pub fn towards_eye(&self, p: DVec3, n: DVec3) -> DVec3 {
        match self {
            Observer::Direction(d) => d.normalize_or(n),
            Observer::Eye(e) => (*e - p).normalize_or(n),
        }
    }
}

/// Each vertex's exit radiance `sum_lm Lambda_l T_lm Y_lm(R)`,
/// `T = M L` per channel (one channel applying to every colour of the
/// light), `R` the mirror of `w_o` ([`Observer::towards_eye`]) about the
/// vertex's normal, over the light's coefficients up to the matrices'
/// lmax (missing ones count as 0). `matrices` as
/// [`GlossyTransfer::matrices`], `lobe` the BRDF's to lmax
/// ([`Brdf::lobe`]; for GGX its tabulated projection instead of `Lambda_l`,
/// [`crate::GgxLobe`]).
/// The glossy layer alone: [`glossy_shade`] with no diffuse base.
///
/// # Panics
/// If the slices' lengths do not fit `lmax`, `channels` and the vertex
/// count of `positions`.
#[allow(clippy::too_many_arguments)]
#[must_use]
pub fn glossy_exit_radiance(
    matrices: &[f32],
    lmax: usize,
    channels: usize,
    positions: &[Vec3],
    normals: &[Vec3],
    lobe: &BrdfLobe,
    light: &[DVec3],
    view: Observer,
) -> Vec<DVec3> {
    let matrices = GlossyView::new(
        lmax,
        channels,
        positions.len(),
        GlossyMatrices::Full(Cow::Borrowed(matrices)),
    )
    .expect("matrices of the vertices' count");
    glossy_shade(
        &matrices,
        &matrices.transferred(light),
        positions,
        normals,
        lobe,
        DVec3::ZERO,
        view,
    )
}

/// The exit radiance of the glossy material of `shlight render-mesh
/// --prt` and `shlight sample`, per vertex: a diffuse base of albedo
/// `diffuse` under the glossy layer,
///
/// ```text
/// L_o = sum_lm (diffuse / pi A_l Y_lm(n) + Lambda_l Y_lm(R)) T_lm
/// ```
///
/// with `T` each vertex's transferred radiance (`transferred`, from
/// [`GlossyView::transferred`] of `matrices`: per cluster once, then
/// summed per vertex), `n` the vertex's unit normal, `R` the mirror of
/// `w_o` ([`Observer::towards_eye`]) about it, `A_l` the clamped cosine's
/// zonal coefficients (`shlight_core::sh::clamped_cosine_eigenvalue`: the
/// base is Lambertian under the transferred radiance, shadows and bounces
/// included) and `Lambda_l` the lobe's ([`BrdfLobe::Zonal`], to lmax). For a
/// [`BrdfLobe::Ggx`] (to at least the matrices' lmax) the glossy layer is
/// instead [`crate::GgxLobe::exit_radiance`]. Sums in `f64`.
///
/// # Panics
/// If the slices' lengths do not fit `matrices`' vertex count and lmax.
#[must_use]
pub fn glossy_shade(
    matrices: &GlossyView<'_>,
    transferred: &TransferredRadiance,
    positions: &[Vec3],
    normals: &[Vec3],
    lobe: &BrdfLobe,
    diffuse: DVec3,
    view: Observer,
) -> Vec<DVec3> {
    let lmax = matrices.lmax;
    let nc = sh_count(lmax);
    assert_eq!(positions.len(), matrices.vertex_count);
    assert_eq!(normals.len(), positions.len());
    match lobe {
        BrdfLobe::Zonal(lambda) => assert!(lambda.len() > lmax),
        BrdfLobe::Ggx(g) => assert!(g.lmax() >= lmax),
    }
    let basis = ShBasis::<f64>::new(lmax);
    let base = diffuse / PI;
    let cosine: Vec<f64> = (0..=lmax).map(clamped_cosine_eigenvalue).collect();
    (0..positions.len())
        .into_par_iter()
        .map_init(
            || {
                let size = match lobe {
                    BrdfLobe::Ggx(g) => sh_count(g.lmax()),
                    BrdfLobe::Zonal(_) => nc,
                };
                (
                    vec![0.0f64; size],
                    vec![0.0f64; nc],
                    vec![DVec3::ZERO; size],
                )
            },
            |(yr, yn, t), v| {
                let n = normals[v].as_dvec3().normalize_or_zero();
                let w_o = view.towards_eye(positions[v].as_dvec3(), n);
                basis.eval(n, yn);
                transferred.vertex(matrices, v, &mut t[..nc]);
                let under = (0..nc)
                    .map(|i| {
                        let l = shlight_core::sh::lm_from_index(i).0;
                        base * (cosine[l] * yn[i]) * t[i]
                    })
                    .sum::<DVec3>();
                let layer = match lobe {
                    BrdfLobe::Zonal(lambda) => {
                        let r = 2.0 * n.dot(w_o) * n - w_o;
                        basis.eval(r.normalize_or(n), yr);
                        (0..nc)
                            .map(|i| lambda[shlight_core::sh::lm_from_index(i).0] * yr[i] * t[i])
                            .sum()
                    }
                    // Coefficients above the matrices' lmax stay zero.
                    BrdfLobe::Ggx(g) => g.exit_radiance(n, w_o, t, yr),
                };
                under + layer
            },
        )
        .collect()
}

/// A `.shprt` file's exit radiance per vertex under `light` (radiance
/// coefficients, index `l(l+1)+m`, any lmax): a diffuse file's `T . L`
/// (plus its static term `S` where it has one, a scene's lights)
/// (`view` ignored), a glossy file's glossy layer [`glossy_exit_radiance`] seen
/// from `view` ([`file_shade`] with no diffuse base).
///
/// # Errors
/// A glossy file without a view, a zero view direction, an unknown BRDF
/// in the file, or a file whose arrays do not fit its counts.
pub fn file_exit_radiance(
    file: &ShprtFile,
    light: &[DVec3],
    view: Option<Observer>,
) -> Result<Vec<DVec3>, String> {
    file_shade(file, light, view, DVec3::ZERO)
}

/// [`file_exit_radiance`] with a glossy file's diffuse base of albedo
/// `diffuse` ([`glossy_shade`]); `diffuse` is ignored for a diffuse file, whose
/// albedo is in its transfer.
///
/// # Errors
/// As [`file_exit_radiance`].
pub fn file_shade(
    file: &ShprtFile,
    light: &[DVec3],
    view: Option<Observer>,
    diffuse: DVec3,
) -> Result<Vec<DVec3>, String> {
    let Some(glossy) = &file.glossy else {
        let mut radiance = file.view().map_err(|e| e.to_string())?.exit_radiance(light);
        // A scene's static term: `T . L + S`.
        if let Some(s) = &file.static_light {
            for (r, s) in radiance.iter_mut().zip(&s.radiance) {
                *r += Vec3::from_array(*s).as_dvec3();
            }
        }
        return Ok(radiance);
    };
    let Some(view) = view else {
        return Err(
            "a glossy file's exit radiance depends on the view: give a view direction or an eye"
                .into(),
        );
    };
    match view {
        Observer::Direction(d) if !(d.length_squared() > 0.0 && d.is_finite()) => {
            return Err(format!(
                "the view direction {d} has zero length (or is not finite)"
            ));
        }
        Observer::Eye(e) if !e.is_finite() => {
            return Err(format!("the eye {e} is not finite"));
        }
        _ => {}
    }
    let brdf = Brdf::parse(&glossy.brdf)?;
    let positions: Vec<Vec3> = glossy.positions.iter().map(|p| Vec3::from(*p)).collect();
    let normals: Vec<Vec3> = glossy.normals.iter().map(|n| Vec3::from(*n)).collect();
    let matrices = file
        .glossy_view()
        .map_err(|e| e.to_string())?
        .expect("a glossy file");
    Ok(glossy_shade(
        &matrices,
        &matrices.transferred(light),
        &positions,
        &normals,
        &brdf.lobe(file.lmax),
        diffuse,
        view,
    ))
}
