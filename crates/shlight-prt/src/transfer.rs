//! [`Transfer`]: a diffuse bake's transfer vectors per vertex, what
//! produced them, and what is made of them (the `.shprt` file, the exit
//! radiance under a light, the records the bounces and the volume bake's
//! probe sums read).

use glam::Vec3;
use shlight_core::sh::{ShCoeffs, sh_count};
use shlight_format::ShprtFile;

use crate::back_sides::BackSides;
use crate::options::Mode;
use crate::records::VertexRecords;

/// Diffuse transfer vectors per vertex (Sloan, Kautz & Snyder 2002, §5).
///
/// For a vertex at `p` with unit normal `n` and albedo `rho`, under distant
/// radiance `L(s) = sum_i L_i Y_i(s)`, the exit radiance is one dot product
/// `L_o = sum_i T_i L_i` with
///
/// ```text
/// unshadowed      T_i = rho/pi int max(n.s, 0)          Y_i(s) ds
/// shadowed        T_i = rho/pi int max(n.s, 0) V(p, s)  Y_i(s) ds
/// interreflected  T   = T^0 + T^1 + ... + T^B,  T^0 the shadowed transfer,
///                 T^b_i(p) = rho/pi int max(n.s, 0) (1 - V(p, s)) T^{b-1}_i(q(p, s)) ds
/// ```
///
/// where `V` is 1 when the ray from `p` along `s` escapes the mesh, and
/// `q(p, s)` is the point it hits, whose transfer `T^{b-1}(q)` is the
/// barycentric interpolation of its triangle's vertex transfers (the
/// radiance a diffuse point leaves in every direction, so bounce `b` gathers
/// bounce `b-1` as in the paper's iteration). Albedo over pi is folded into
/// `T`, so a renderer computes `T . L` and nothing else.
///
/// With surfaces ([`BakeOptions::surfaces`](crate::BakeOptions::surfaces))
/// the point hit leaves the albedo of its texel times the light arriving
/// there, interpolated from the vertices, and cut-out surfaces let rays
/// through (`V` is 1 for a ray that passes them):
///
/// ```text
/// T   = rho(p) (G^0 + G^1 + ... + G^B)
/// G^0_i(p) = 1/pi int max(n.s, 0) V(p, s) Y_i(s) ds
/// G^b_i(p) = 1/pi int max(n.s, 0) (1 - V(p, s)) rho(q) G^{b-1}_i(q) ds
/// ```
///
/// `rho(q)` the surface's albedo at the texel hit and `G^{b-1}(q)` the
/// barycentric interpolation of its triangle's vertex values (kept in
/// [`Transfer::incident`]). Where the albedo is one colour per triangle
/// corner, `rho(q)` is their interpolation, and `rho(q) G(q)` differs from
/// the interpolated product above only where the corners differ in colour.
///
/// A bake ([`crate::bake`]) holds the vectors it made, and what produced
/// them.
#[derive(Clone, Debug)]
pub struct Transfer {
    /// Highest SH degree.
    pub lmax: usize,
    /// 1 (grey albedo) or 3 (linear RGB).
    pub channels: usize,
    /// Vertices, in the mesh's order.
    pub vertex_count: usize,
    /// `vertex_count * channels * (lmax+1)^2` coefficients: vertex-major,
    /// then channel, then SH index `l(l+1)+m`.
    pub coeffs: Vec<f32>,
    /// Directions in the shared set (the grid's size).
    pub samples: usize,
    /// Rays cast (directions above each vertex's tangent plane).
    pub rays: u64,
    /// With [`BakeOptions::emission`](crate::BakeOptions::emission) or
    /// [`BakeOptions::direct_irradiance`](crate::BakeOptions::direct_irradiance):
    /// each vertex's exit radiance due to the emitters and those lights
    /// alone (linear RGB), `E = E^0 + ... + E^B` with
    /// `E^0 = Le + rho/pi E_direct` and `E^b(p) = rho/pi int max(n.s, 0)
    /// (1 - V(p, s)) E^{b-1}(q(p, s)) ds`, the transfer's own iteration with
    /// the emission and the directly lit surface as the source, so the exit
    /// radiance of a vertex under light `L` is `T . L + E`. With surfaces,
    /// `E = Le + rho(p) (F^0 + F^1 + ... + F^B)`, `F^0 = E_direct / pi`
    /// (the lights' light arriving),
    /// `F^1(p) = 1/pi int max(n.s, 0) (1 - V(p, s)) (Le(q) + rho(q) F^0(q)) ds`
    /// and `F^b(p) = 1/pi int max(n.s, 0) (1 - V(p, s)) rho(q) F^{b-1}(q) ds`:
    /// emission is not multiplied by the albedo, the lights' light is (that
    /// of the texel a ray hits).
    pub emitted: Option<Vec<Vec3>>,
    /// With surfaces: what a hit interpolates before its texel's albedo.
    pub incident: Option<IncidentTransfer>,
    /// With surfaces that have double-sided triangles
    /// ([`crate::BakeOptions::surfaces`]): the light gathered on their back
    /// sides ([`BackTransfer`]), which the bounces read where a ray meets a
    /// back face; `None` for a one-sided scene. Everything above is the
    /// mesh's own vertices (their front side) only.
    pub back: Option<BackTransfer>,
}

/// The back sides of a bake's double-sided triangles ([`BackSides`]: a
/// copy of each of their vertices, facing the other way) and what the bake
/// gathered on them: per back copy, what [`Transfer`] holds per vertex
/// (`coeffs`, `emitted`, `incident`, in the same layout). A `.shprt` file
/// or glTF export holds the front side only; these are what a ray meeting
/// the back of a double-sided triangle reads, in the bounces and in
/// shlight-volume's probes ([`Transfer::records`]).
#[derive(Clone, Debug)]
pub struct BackTransfer {
    /// Which vertices were copied, and the back triangles.
    pub sides: BackSides,
    /// As [`Transfer::coeffs`], per back copy.
    pub coeffs: Vec<f32>,
    /// As [`Transfer::emitted`], per back copy.
    pub emitted: Option<Vec<Vec3>>,
    /// As [`Transfer::incident`], per back copy.
    pub incident: Option<IncidentTransfer>,
}

/// The light arriving at each vertex of a bake with surfaces, before any
/// albedo ([`Transfer`] states `G` and `F`): what a ray that hits the
/// surface interpolates from the corners of the triangle it met, and then
/// multiplies by the albedo of the texel there.
#[derive(Clone, Debug, PartialEq)]
pub struct IncidentTransfer {
    /// Per vertex `channels x (lmax+1)^2`, laid out as
    /// [`Transfer::coeffs`]: `G^0 + ... + G^B`, the transfer of the
    /// irradiance over pi (so [`Transfer::coeffs`] is the vertex's albedo
    /// times it).
    pub coeffs: Vec<f32>,
    /// With emitters or direct irradiance, per vertex: `[Le, F^0 + F^1 +
    /// ... + F^B]`, the emitted radiance and the light of the emitters and
    /// of the lights arriving over pi, so that a point of albedo `rho`
    /// leaves `Le + rho F`.
    pub emitted: Option<Vec<[Vec3; 2]>>,
}

impl Transfer {
    /// The transfer vectors borrowed, as the renderer and every reader of a
    /// bake take them.
    #[must_use]
    pub fn view(&self) -> shlight_baked::TransferView<'_> {
        shlight_baked::TransferView {
            lmax: self.lmax,
            channels: self.channels,
            vertex_count: self.vertex_count,
            data: &self.coeffs,
        }
    }

    /// The `.shprt` file of this bake and what produced it.
    #[must_use]
    pub fn to_shprt(
        &self,
        mode: Mode,
        seed: u64,
        albedo: Option<[f32; 3]>,
        mesh_hash: u64,
        mesh: &str,
    ) -> ShprtFile {
        ShprtFile {
            lmax: self.lmax,
            channels: self.channels,
            vertex_count: self.vertex_count,
            transfer: self.coeffs.clone(),
            mode: mode.name().to_string(),
            rays_per_vertex: self.samples as u64,
            bounces: mode.bounces(),
            seed,
            albedo,
            mesh_hash,
            mesh: mesh.to_string(),
            glossy: None,
            static_light: None,
        }
    }

    /// Exit radiance per vertex under the radiance coefficients `light`:
    /// `sum_i T_i L_i` per channel, over the coefficients both have (a grey
    /// transfer is applied to each colour channel of the light), as
    /// [`shlight_baked::TransferView::exit_radiance`] computes it for every
    /// reader of a bake, in `f32`.
    #[must_use]
    pub fn exit_radiance(&self, light: &ShCoeffs<glam::DVec3>) -> Vec<Vec3> {
        self.view()
            .exit_radiance(light.as_slice())
            .iter()
            .map(|c| c.as_vec3())
            .collect()
    }

    /// The vectors as records for the summing kernels ([`VertexRecords`]):
    /// each vertex's `channels x (lmax+1)^2` transfer and, when the bake
    /// gathered emitters' light ([`BakeOptions::emission`](crate::BakeOptions::emission)), its exit
    /// radiance due to them; for a bake with surfaces, what a hit
    /// interpolates before its texel's albedo ([`IncidentTransfer`],
    /// [`VertexRecords::incident`]). With [`Transfer::back`], the records
    /// of the two-sided mesh ([`BackSides::two_sided`]): the mesh's
    /// vertices, then the back copies.
    #[must_use]
    pub fn records(&self) -> VertexRecords {
        let stride = self.channels * sh_count(self.lmax);
        let Some(back) = &self.back else {
            return match &self.incident {
                Some(i) => VertexRecords::new_incident(&i.coeffs, stride, i.emitted.as_deref()),
                None => VertexRecords::new(&self.coeffs, stride, self.emitted.as_deref()),
            };
        };
        // The vertices of the two-sided mesh: the front's, then the back
        // copies'.
        fn joined<T: Copy>(front: &[T], back: &[T]) -> Vec<T> {
            [front, back].concat()
        }
        match (&self.incident, &back.incident) {
            (Some(i), Some(b)) => {
                let emitted = match (&i.emitted, &b.emitted) {
                    (Some(f), Some(e)) => Some(joined(f, e)),
                    _ => None,
                };
                VertexRecords::new_incident(
                    &joined(&i.coeffs, &b.coeffs),
                    stride,
                    emitted.as_deref(),
                )
            }
            _ => {
                let emitted = match (&self.emitted, &back.emitted) {
                    (Some(f), Some(e)) => Some(joined(f, e)),
                    _ => None,
                };
                VertexRecords::new(
                    &joined(&self.coeffs, &back.coeffs),
                    stride,
                    emitted.as_deref(),
                )
            }
        }
    }
}
