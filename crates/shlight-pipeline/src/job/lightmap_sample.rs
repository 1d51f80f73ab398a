//! A lightmapped scene (`shlight lightmap -o OUT.glb`) read at points as
//! a GPU reads it: the surface under each point found, its `TEXCOORD_1`
//! taken to the atlas, each page filtered bilinearly, and the texel
//! reconstructed for the point's normal by the port of the engine's
//! shader ([`lightmap_irradiance`]).

use glam::{Vec2, Vec3};
use serde_json::Value;
use shlight_format::SamplePoints;
use shlight_io::{Ktx2Image, decode_ktx2};
use shlight_lightmap::{L1Reconstruction, PackedTexel, TexelFormat};
use shlight_mesh::{LightmapPages, Scene};
use shlight_rays::{Occluder, Ray};

use super::lightmap::{engine_by_name, texel_basis};
use crate::spelling::Spelling;
use crate::{PipelineError, Result};

/// How far from a surface a point may be, as a fraction of the scene's
/// diagonal, and still be read on it.
pub const SURFACE_REACH: f32 = 1e-3;

/// The texel format the root extension names.
fn format_of(root: &Value, name: &str) -> Result<TexelFormat> {
    let fail = |what: &str| {
        PipelineError::new(format!(
            "{name}: its SHLIGHT_lightmap has no {what} shlight knows"
        ))
    };
    let word = |key: &str| root[key].as_str().unwrap_or_default();
    let basis = texel_basis(word("basis"), Spelling::CommandLine).map_err(|_| fail("basis"))?;
    let engine =
        engine_by_name(word("engine"), Spelling::CommandLine).map_err(|_| fail("engine"))?;
    let reconstruction = [L1Reconstruction::Linear, L1Reconstruction::NonLinear]
        .into_iter()
        .find(|r| r.name() == word("reconstruction"))
        .ok_or_else(|| fail("reconstruction"))?;
    TexelFormat::new(basis, engine, reconstruction).map_err(|e| fail(&e.to_string()))
}

/// A lightmapped scene's atlas as a renderer reads it: the texel format
/// the root `SHLIGHT_lightmap` names and its pages decoded, each `side x
/// side` texels of linear RGBA.
#[derive(Clone, Debug)]
pub struct LightmapAtlas {
    /// What a texel holds and how the engine's shader reconstructs it.
    pub format: TexelFormat,
    /// The pages' side in texels.
    pub side: usize,
    /// The pages, [`TexelFormat::layer_count`] of them, in the format's
    /// layer order.
    pub layers: Vec<Ktx2Image>,
}

impl LightmapAtlas {
    /// The atlas of `pages` (read from `name`).
    ///
    /// # Errors
    /// A root extension whose basis, engine or reconstruction shlight does
    /// not know, pages that do not decode, or pages of another count or
    /// size than the root names.
    pub fn new(name: &str, pages: &LightmapPages) -> Result<Self> {
        let format = format_of(&pages.root, name)?;
        let side = pages.root["size"][0].as_u64().unwrap_or(0) as usize;
        let layers: Vec<Ktx2Image> = pages
            .pages
            .iter()
            .map(|bytes| {
                decode_ktx2(bytes).map_err(|e| PipelineError::new(format!("{name}: a page: {e}")))
            })
            .collect::<Result<_>>()?;
        if side == 0
            || layers.len() != format.layer_count()
            || layers.iter().any(|l| l.width != side || l.height != side)
        {
            return Err(PipelineError::new(format!(
                "{name}: {} pages of {side} x {side} texels expected for {}",
                format.layer_count(),
                format.basis().name()
            )));
        }
        Ok(Self {
            format,
            side,
            layers,
        })
    }

    /// What one divides the reconstructed light by to get the irradiance
    /// `E` in W/m2: the engine's units' scale (1 for `E`, `1/pi` for `E /
    /// pi`).
    #[must_use]
    pub fn units_scale(&self) -> f64 {
        self.format.units().scale()
    }
}

/// The `scaleOffset` `[su, sv, ou, ov]` that takes node `node`'s
/// `TEXCOORD_1` into the atlas (`uv * (su, sv) + (ou, ov)`), from its
/// `SHLIGHT_lightmap` extension `ext` (of the file `name`): `[1, 1, 0,
/// 0]` when the file moved the UVs already (`texCoordMoved`).
///
/// # Errors
/// An extension with neither a moved `TEXCOORD_1` nor a `scaleOffset` of
/// four numbers.
pub fn node_scale_offset(name: &str, node: usize, ext: &Value) -> Result<[f32; 4]> {
    let so: Vec<f32> = ext["scaleOffset"]
        .as_array()
        .map(|a| {
            a.iter()
                .filter_map(Value::as_f64)
                .map(|x| x as f32)
                .collect()
        })
        .unwrap_or_default();
    match (ext["texCoordMoved"].as_bool(), so.as_slice()) {
        (Some(true), _) => Ok([1.0, 1.0, 0.0, 0.0]),
        (_, &[su, sv, ou, ov]) => Ok([su, sv, ou, ov]),
        _ => Err(PipelineError::new(format!(
            "{name}: node {node}'s SHLIGHT_lightmap has no scaleOffset"
        ))),
    }
}

/// The irradiance `E` (W/m2, whatever the engine's units) a GPU shading
/// the lightmapped scene `scene` (read from `name`, its lightmaps
/// `pages`) reads at each of `points` for its normal: the first surface a
/// ray meets coming back along the normal from [`SURFACE_REACH`] of the
/// scene's diagonal above the point,
/// its `TEXCOORD_1` (moved into the node's region by its `scaleOffset`
/// unless the file moved it already: [`node_scale_offset`]), each page
/// read with bilinear filtering (texel centres at `(x + 1/2) / side`,
/// clamped to the edge), and the texel turned into light by the port of
/// the engine's shader ([`TexelFormat::reconstruct`]), divided by the
/// engine's units.
///
/// # Errors
/// A file whose extension or pages shlight cannot read
/// ([`LightmapAtlas::new`]), or a point on no surface with a lightmap
/// (named by its number).
pub fn lightmap_irradiance(
    name: &str,
    scene: &Scene,
    pages: &LightmapPages,
    points: &SamplePoints,
) -> Result<Vec<[f64; 3]>> {
    let atlas = LightmapAtlas::new(name, pages)?;
    let (format, layers) = (atlas.format, &atlas.layers);
    let surfaces = scene.flatten(Vec3::splat(0.5))?;
    let layout = scene.flat_layout()?;
    if surfaces.uv_sets < 2 || scene.instance_sources.len() != scene.instances.len() {
        return Err(PipelineError::new(format!(
            "{name}: its meshes have no TEXCOORD_1 placed by nodes"
        )));
    }
    let occluder = Occluder::new(&surfaces.mesh);
    let (lo, hi) = surfaces.mesh.bounds();
    let reach = SURFACE_REACH * (hi - lo).length();
    let scale = atlas.units_scale();
    points
        .points
        .iter()
        .zip(&points.normals)
        .enumerate()
        .map(|(i, (p, n))| {
            let (p, n) = (Vec3::from_array(*p), Vec3::from_array(*n));
            let hit = occluder
                .closest_hit(&Ray::new(p + reach * n, -n, 2.0 * reach))
                .ok_or_else(|| {
                    PipelineError::new(format!(
                        "{name}: point {i} ({p}) is on no surface (none within {reach:.2e} along its normal)"
                    ))
                })?;
            let corners = surfaces.mesh.triangles[hit.triangle as usize];
            let mut uv = Vec2::ZERO;
            for (&v, &w) in corners.iter().zip(&hit.barycentrics) {
                uv += w * surfaces.uvs[v as usize * surfaces.uv_sets + 1];
            }
            let (instance, _) = layout.locate(hit.triangle);
            let node = scene.instance_sources[instance].node;
            let ext = pages.nodes.get(&node).ok_or_else(|| {
                PipelineError::new(format!(
                    "{name}: point {i} ({p}) lies on node {node}, which has no lightmap"
                ))
            })?;
            let [su, sv, ou, ov] = node_scale_offset(name, node, ext)?;
            let atlas = uv * Vec2::new(su, sv) + Vec2::new(ou, ov);
            let texel: Vec<[f32; 4]> = layers.iter().map(|l| bilinear(l, atlas)).collect();
            let light = format.reconstruct(&PackedTexel::from_layers(&texel), n);
            Ok(light.as_dvec3().to_array().map(|c| c / scale))
        })
        .collect()
}

/// `image` read at `uv` as a GPU's bilinear filter with clamp-to-edge
/// reads it.
fn bilinear(image: &Ktx2Image, uv: Vec2) -> [f32; 4] {
    let (w, h) = (image.width as f32, image.height as f32);
    let at = Vec2::new(uv.x * w - 0.5, uv.y * h - 0.5);
    let (x0, y0) = (at.x.floor(), at.y.floor());
    let (fx, fy) = (at.x - x0, at.y - y0);
    let texel = |x: f32, y: f32| {
        let x = (x as i64).clamp(0, image.width as i64 - 1) as usize;
        let y = (y as i64).clamp(0, image.height as i64 - 1) as usize;
        image.texels[y * image.width + x]
    };
    let mut out = [0.0f32; 4];
    for (dy, wy) in [(0.0, 1.0 - fy), (1.0, fy)] {
        for (dx, wx) in [(0.0, 1.0 - fx), (1.0, fx)] {
            let t = texel(x0 + dx, y0 + dy);
            for (o, v) in out.iter_mut().zip(t) {
                *o += wx * wy * v;
            }
        }
    }
    out
}
