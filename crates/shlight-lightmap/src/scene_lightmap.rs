//! A glTF scene's lightmap baked: every placed node's second UV set given
//! a square region of one atlas, its texels rasterised onto its triangles
//! and the light gathered at each ([`bake_scene_lightmap`]).

use std::sync::Arc;

use glam::{DVec3, Mat3, Vec2, Vec3};
use shlight_core::sh::{ShCoeffs, ShL1Rgb};
use shlight_mesh::{PunctualLight, Scene, Surfaces};
use shlight_volume::{Stage, SurfaceLight, SurfacePoint, VolumeOptions, gather_at_surface_points};

use crate::atlas::{TexelRect, pack_squares, smallest_atlas};
use crate::denoise::{TexelGuide, denoise};
use crate::dilate::dilate;
use crate::lightmap_error::LightmapError;
use crate::placement::Placement;
use crate::seams::{SeamCorner, find_seams, footprint, stitch_seams};
use crate::texel_format::{TexelBasis, TexelFormat};
use crate::texel_raster::{MAX_SIDE, TexelRaster};
use crate::uv_overlap::first_uv_overlap;

/// How big the lightmap is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightmapSize {
    /// A square atlas of this many texels a side, the regions as large as
    /// fit (the texel density found by bisection).
    Side(u32),
    /// This many texels per metre (scene unit) on every surface, in the
    /// smallest power-of-two square atlas that holds them.
    Density(f64),
}

/// [`LightmapSettings::denoise`]'s default: a filter of radius 2 texels
/// (the noise of an evenly lit surface divided by about 3).
pub const DEFAULT_DENOISE: u32 = 2;

/// The largest [`LightmapSettings::denoise`]: a window of 33 x 33 texels.
pub const MAX_DENOISE: u32 = 16;

/// What to bake.
#[derive(Clone, Debug, PartialEq)]
pub struct LightmapSettings {
    /// The UV set the lightmap is laid on (1: glTF's `TEXCOORD_1`).
    pub uv_set: usize,
    /// The atlas's size, or the texel density.
    pub size: LightmapSize,
    /// Empty texels around each region, filled by dilation.
    pub padding: u32,
    /// The radius, in texels, of the edge-aware filter over the gathered
    /// texels ([`crate::denoise`]); 0: none.
    pub denoise: u32,
    /// The gather: rays per texel ([`VolumeOptions::samples`]), the
    /// surfaces' bounces and samples, the lmax of the environment read,
    /// the seed, the lights' units, and the back-face fraction above
    /// which a texel is inside geometry ([`VolumeOptions::invalid_backfaces`]).
    pub gather: VolumeOptions,
}

impl Default for LightmapSettings {
    fn default() -> Self {
        Self {
            uv_set: 1,
            size: LightmapSize::Side(512),
            padding: 2,
            denoise: DEFAULT_DENOISE,
            gather: VolumeOptions {
                samples: 256,
                bounces: 8,
                relocate: false,
                visibility_size: 0,
                ..VolumeOptions::default()
            },
        }
    }
}

/// One placed node's region of the atlas.
#[derive(Clone, Debug, PartialEq)]
pub struct LightmapRegion {
    /// The glTF node that placed it (`None` for a scene built in code).
    pub node: Option<usize>,
    /// The node's `EXT_mesh_gpu_instancing` instance, if any.
    pub gpu_instance: Option<u32>,
    /// Names the region in messages: the first primitive's label.
    pub label: String,
    /// The scene's instances (one per primitive of the node's mesh).
    pub instances: Vec<usize>,
    /// Its texels.
    pub rect: TexelRect,
    /// `uv * scale + offset` from the node's UV set to the atlas's (Bevy's
    /// `uv_rect`, Unity's `lightmapScaleOffset`).
    pub placement: Placement,
    /// Texels its triangles cover.
    pub covered: usize,
}

/// What a baked texel holds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TexelLight {
    /// The irradiance for the surface's normal.
    pub irradiance: DVec3,
    /// The lmax-1 SH of the radiance arriving from the surface's
    /// hemisphere (zero from below).
    pub sh: ShL1Rgb<f64>,
    /// The surface normal the texel was gathered for.
    pub normal: Vec3,
}

/// A baked lightmap: one square atlas.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneLightmap {
    /// Texels a side.
    pub side: u32,
    /// Texels per metre (scene unit) of surface.
    pub density: f64,
    /// A region per placed node, in the scene's order.
    pub regions: Vec<LightmapRegion>,
    /// The nodes not baked, none of their primitives having the UV set
    /// (named by their first primitive): they still cast shadows and
    /// reflect light.
    pub skipped: Vec<String>,
    /// Row by row, texel `(x, y)` at `y side + x`: the texels the surfaces
    /// cover (filtered, [`LightmapSettings::denoise`]), the texels inside
    /// geometry and the padding filled from their neighbours (dilation, in
    /// `max(padding, 1) + 8` passes), then the UV seams stitched; `None`
    /// beyond.
    pub texels: Vec<Option<TexelLight>>,
    /// Texels found inside geometry (seeing mostly back faces) and filled.
    pub invalid: usize,
    /// UV seams stitched ([`crate::find_seams`]).
    pub seams: usize,
    /// The largest difference of the red irradiance read on the two sides
    /// of a seam, before and after stitching ([`crate::stitch_seams`]).
    pub seam_gap: [f64; 2],
    /// Rays per texel.
    pub samples: usize,
    /// Rays cast in all.
    pub rays: u64,
}

impl SceneLightmap {
    /// The light a GPU's bilinear filter reads at `uv` of region `region`'s
    /// UV set: the region's placement takes it to the atlas, where texel
    /// `(x, y)` is centred at `((x + 1/2) / side, (y + 1/2) / side)`; the
    /// four texels around the point are weighted bilinearly (clamped at
    /// the atlas's edge), those without light left out and the rest's
    /// weights renormalised. `None` when none of the four has light or the
    /// region does not exist.
    #[must_use]
    pub fn bilinear(&self, region: usize, uv: Vec2) -> Option<TexelLight> {
        let r = self.regions.get(region)?;
        let at = r.placement.apply(uv.as_dvec2()) * f64::from(self.side);
        let mut sum = [0.0f64; 15];
        let mut weight = 0.0;
        let mut normal = Vec3::ZERO;
        for (k, w) in footprint(at, self.side as usize) {
            if w <= 0.0 {
                continue;
            }
            let Some(t) = self.texels[k] else {
                continue;
            };
            for (s, v) in sum.iter_mut().zip(to_array(t)) {
                *s += w * v;
            }
            normal += w as f32 * t.normal;
            weight += w;
        }
        if weight <= 0.0 {
            return None;
        }
        let mut t = from_array(sum.map(|s| s / weight));
        t.normal = normal.normalize_or(t.normal);
        Some(t)
    }

    /// The lightmap's texels as `format` stores them: one grid of RGBA
    /// per layer ([`TexelFormat::layer_count`]), row by row; texels with
    /// no light are zero. The irradiance basis stores the gathered
    /// irradiance itself (not its lmax-1 reading), in the engine's units.
    #[must_use]
    pub fn layers(&self, format: TexelFormat) -> Vec<Vec<[f32; 4]>> {
        let count = format.layer_count();
        let mut layers = vec![vec![[0.0f32; 4]; self.texels.len()]; count];
        let scale = format.units().scale();
        for (k, texel) in self.texels.iter().enumerate() {
            let Some(t) = texel else { continue };
            if format.basis() == TexelBasis::Irradiance {
                let e = (t.irradiance * scale).as_vec3();
                layers[0][k] = [e.x, e.y, e.z, 1.0];
                continue;
            }
            let packed = format.pack(&t.sh, t.normal.as_dvec3());
            for (layer, v) in layers.iter_mut().zip(packed.layers()) {
                layer[k] = *v;
            }
        }
        layers
    }
}

/// Dilation passes beyond the padding: how deep a patch of texels inside
/// geometry is filled from its valid neighbours.
const DILATE_EXTRA: u32 = 8;

/// A node's triangles in its UV set: the primitives' UVs one after the
/// other, and per triangle its instance and the triangle's index in its
/// primitive.
struct NodeUvs {
    uvs: Vec<Vec2>,
    triangles: Vec<[u32; 3]>,
    owners: Vec<(usize, u32)>,
}

/// Bakes the lightmap of `scene` (its flattened surfaces `surfaces`), lit
/// by the environment `env` (radiance SH) and the scene's punctual lights.
///
/// - **Regions.** The instances a glTF node places (its mesh's
///   primitives) share one square region; a node's GPU instances each get
///   their own. A node none of whose primitives has the UV set
///   [`LightmapSettings::uv_set`] is not baked ([`SceneLightmap::skipped`]:
///   it still casts shadows and reflects light); in a baked node every
///   primitive needs it, within the unit square, with no two
///   triangles of one mesh overlapping there. A region's side is `density
///   sqrt(A_world / A_uv)` texels (at least 2), so that a texel covers about
///   `1 / density` metres of its surface whatever the UVs' scale.
/// - **Texels.** Each region's triangles are rasterised conservatively
///   ([`TexelRaster`]): every texel a triangle overlaps is sampled at a
///   point inside both, in world space through the instance's transform,
///   facing the interpolated normal; the light there is gathered by
///   [`gather_at_surface_points`], seeded by the texel's index in the
///   atlas.
/// - **Noise.** The gathered texels are filtered by [`denoise`] over
///   [`LightmapSettings::denoise`] texels, guided by their positions and
///   normals (never across a geometric edge).
/// - **Invalid texels.** A texel whose rays meet back faces more than
///   [`VolumeOptions::invalid_backfaces`] of the time is inside geometry
///   (under a wall standing on the floor); it is emptied and filled from
///   its valid neighbours, then the padding is dilated.
///
/// `progress(stage, done, total)` as [`gather_at_surface_points`] reports.
///
/// # Errors
/// No node with the UV set, a baked node's primitive without it, UVs that
/// are not finite, leave the
/// unit square or overlap (naming the mesh and triangles), a layout that
/// does not fit [`MAX_SIDE`], and what the gather refuses.
pub fn bake_scene_lightmap(
    scene: &Scene,
    surfaces: &Arc<Surfaces>,
    env: &ShCoeffs<DVec3>,
    lights: &[PunctualLight],
    settings: &LightmapSettings,
    progress: &(dyn Fn(Stage, usize, usize) + Sync),
) -> Result<SceneLightmap, LightmapError> {
    if settings.denoise > MAX_DENOISE {
        return Err(LightmapError::Settings(format!(
            "a denoising radius of {} texels: it must be at most {MAX_DENOISE}",
            settings.denoise
        )));
    }
    let layout = scene.flat_layout().map_err(LightmapError::Scene)?;
    // Nodes none of whose primitives has the UV set are not baked (they
    // still cast shadows and reflect light).
    let (groups, skipped): (Vec<NodeGroup>, Vec<NodeGroup>) =
        node_groups(scene).into_iter().partition(|g| {
            g.instances.iter().any(|&i| {
                scene.primitives[scene.instances[i].primitive].uvs.len() > settings.uv_set
            })
        });
    if groups.is_empty() {
        let label = skipped
            .first()
            .map_or_else(String::new, |g| g.label.clone());
        return Err(LightmapError::NoUvs {
            label,
            uv_set: settings.uv_set,
        });
    }
    let mut nodes = Vec::with_capacity(groups.len());
    let mut checked = std::collections::HashSet::new();
    let mut naturals = Vec::with_capacity(groups.len());
    for g in &groups {
        let uvs = node_uvs(scene, &g.instances, settings.uv_set)?;
        // One check per mesh: its nodes share its UVs.
        if checked.insert(g.mesh_key.clone()) {
            check_uvs(scene, &uvs)?;
        }
        let (world, uv) = areas(scene, &uvs);
        if !(uv.is_finite() && uv > 0.0 && world.is_finite() && world > 0.0) {
            return Err(LightmapError::Uv {
                label: g.label.clone(),
                message: format!(
                    "its UV set {} covers no area (or its surface has none)",
                    settings.uv_set
                ),
            });
        }
        naturals.push((world / uv).sqrt());
        nodes.push(uvs);
    }
    let padding = settings.padding;
    let sides_at = |density: f64| -> Vec<u32> {
        naturals
            .iter()
            .map(|n| (density * n).ceil().clamp(2.0, f64::from(MAX_SIDE)) as u32)
            .collect()
    };
    let (side, density, rects) = match settings.size {
        LightmapSize::Density(d) => {
            if !(d.is_finite() && d > 0.0) {
                return Err(LightmapError::Settings(format!(
                    "a texel density of {d} per metre: it must be positive"
                )));
            }
            let sides = sides_at(d);
            let (side, rects) = smallest_atlas(&sides, padding, MAX_SIDE).ok_or_else(|| {
                LightmapError::Settings(format!(
                    "{} regions at {d} texels per metre do not fit a {MAX_SIDE} x {MAX_SIDE} lightmap",
                    sides.len()
                ))
            })?;
            (side, d, rects)
        }
        LightmapSize::Side(side) => {
            if !(4..=MAX_SIDE).contains(&side) {
                return Err(LightmapError::Settings(format!(
                    "a lightmap of {side} texels a side: it must be from 4 to {MAX_SIDE}"
                )));
            }
            // The largest density whose regions fit, by bisection.
            let fits = |d: f64| pack_squares(&sides_at(d), padding, side);
            let mut lo = 0.0f64;
            let max_natural = naturals.iter().copied().fold(0.0, f64::max);
            let mut hi = f64::from(side) / max_natural.max(1e-30);
            if fits(lo).is_none() {
                return Err(LightmapError::Settings(format!(
                    "{} regions of at least 2 x 2 texels do not fit a {side} x {side} lightmap",
                    naturals.len()
                )));
            }
            for _ in 0..48 {
                let mid = 0.5 * (lo + hi);
                if fits(mid).is_some() {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            let rects = fits(lo).expect("the lower end fits");
            (side, lo, rects)
        }
    };

    // Each region rasterised in its own square, its texels then placed in
    // the atlas.
    let width = side as usize;
    let mut points = Vec::new();
    let mut slots = Vec::new();
    let mut owners = Vec::new();
    let mut regions = Vec::with_capacity(groups.len());
    for ((g, uvs), rect) in groups.iter().zip(&nodes).zip(&rects) {
        let raster = TexelRaster::new(&uvs.uvs, &uvs.triangles, None, rect.side, rect.side)
            .map_err(|e| LightmapError::Uv {
                label: g.label.clone(),
                message: e.to_string(),
            })?;
        let mut covered = 0;
        for (k, texel) in raster.texels().iter().enumerate() {
            let Some(t) = texel else { continue };
            let (instance, local) = uvs.owners[t.triangle as usize];
            if layout.triangle(instance, local).is_none() {
                // Dropped from the flattened scene as degenerate.
                continue;
            }
            let (x, y) = (k as u32 % rect.side, k as u32 / rect.side);
            let at = (rect.y + y) as usize * width + (rect.x + x) as usize;
            let (position, normal) = surface_point(scene, instance, local, t.weights);
            points.push(SurfacePoint {
                position,
                normal,
                id: at as u64,
            });
            slots.push(at);
            owners.push(regions.len() as u32);
            covered += 1;
        }
        let scale = rect.side as f32 / side as f32;
        regions.push(LightmapRegion {
            node: g.node,
            gpu_instance: g.gpu_instance,
            label: g.label.clone(),
            instances: g.instances.clone(),
            rect: *rect,
            placement: Placement {
                scale: Vec2::splat(scale),
                offset: Vec2::new(rect.x as f32, rect.y as f32) / side as f32,
            },
            covered,
        });
    }
    let gathered =
        gather_at_surface_points(surfaces, lights, env, &points, &settings.gather, progress)
            .map_err(LightmapError::Gather)?;
    // The texels' light as numbers to filter and blend, their normals and
    // guides; what the gather returned is let go before the filter doubles
    // the light's memory.
    let (samples, rays) = (gathered.samples, gathered.rays);
    let mut blend: Vec<Option<[f64; 15]>> = vec![None; width * width];
    let mut normals: Vec<Option<Vec3>> = vec![None; width * width];
    let mut guides: Vec<Option<TexelGuide>> = vec![None; width * width];
    let mut invalid = 0;
    for (((&slot, p), l), &region) in slots.iter().zip(&points).zip(&gathered.light).zip(&owners) {
        // A texel inside geometry keeps its guide with no light: a barrier
        // to the filter.
        guides[slot] = Some(TexelGuide {
            position: p.position,
            normal: p.normal,
            region,
        });
        if l.backfaces > settings.gather.invalid_backfaces {
            invalid += 1;
            continue;
        }
        blend[slot] = Some(to_array(texel_light(p, l)));
        normals[slot] = Some(p.normal);
    }
    drop((gathered, points, slots, owners));
    // The noise filtered, guided by the texels' places on the surface.
    if settings.denoise > 0 {
        blend = denoise(&blend, &guides, width, settings.denoise, 1.0 / density);
    }
    drop(guides);
    // Invalid texels, then the padding: filled from their neighbours.
    dilate(&mut blend, width, padding.max(1) + DILATE_EXTRA)
        .map_err(|e| LightmapError::Settings(e.to_string()))?;
    // Then the seams of each node's charts.
    let mut seams = Vec::new();
    for (uvs, rect) in nodes.iter().zip(&rects) {
        seams.extend(find_seams(&seam_corners(scene, uvs, rect)));
    }
    let (before, after) = stitch_seams(&mut blend, width, &seams);
    // A baked texel keeps the normal it was gathered for; a filled one
    // takes its light's direction.
    let texels: Vec<Option<TexelLight>> = blend
        .into_iter()
        .zip(normals)
        .map(|(b, normal)| {
            b.map(|b| {
                let t = from_array(b);
                TexelLight {
                    normal: normal.unwrap_or(t.normal),
                    ..t
                }
            })
        })
        .collect();
    Ok(SceneLightmap {
        side,
        density,
        regions,
        skipped: skipped.into_iter().map(|g| g.label).collect(),
        texels,
        invalid,
        seams: seams.len(),
        seam_gap: [before, after],
        samples,
        rays,
    })
}

/// A texel's light from what its point gathered.
fn texel_light(p: &SurfacePoint, l: &SurfaceLight) -> TexelLight {
    let ch = |c: usize| l.sh.map(|v| v[c]);
    TexelLight {
        irradiance: l.irradiance,
        sh: ShL1Rgb {
            r: ch(0),
            g: ch(1),
            b: ch(2),
        },
        normal: p.normal,
    }
}

/// A texel's light as numbers to average (dilation).
fn to_array(t: TexelLight) -> [f64; 15] {
    let mut a = [0.0; 15];
    a[..3].copy_from_slice(&t.irradiance.to_array());
    a[3..7].copy_from_slice(&t.sh.r);
    a[7..11].copy_from_slice(&t.sh.g);
    a[11..15].copy_from_slice(&t.sh.b);
    a
}

/// [`to_array`] back; the normal of a filled texel is not known, and the
/// SH's own direction is used (`+y` where it has none).
fn from_array(a: [f64; 15]) -> TexelLight {
    let sh = ShL1Rgb {
        r: [a[3], a[4], a[5], a[6]],
        g: [a[7], a[8], a[9], a[10]],
        b: [a[11], a[12], a[13], a[14]],
    };
    // The mean L1 over the channels, in shlight's basis (y, z, x with the
    // Condon-Shortley signs): -L_1^1, -L_1^-1, L_1^0.
    let l1 = |c: &[f64; 4]| DVec3::new(-c[3], -c[1], c[2]);
    let dir = (l1(&sh.r) + l1(&sh.g) + l1(&sh.b)).normalize_or(DVec3::Y);
    TexelLight {
        irradiance: DVec3::new(a[0], a[1], a[2]),
        sh,
        normal: dir.as_vec3(),
    }
}

/// The instances placed together: a glTF node's (per GPU instance), or
/// each instance alone in a scene built in code.
struct NodeGroup {
    node: Option<usize>,
    gpu_instance: Option<u32>,
    instances: Vec<usize>,
    label: String,
    /// The mesh whose UVs the group reads (its primitives).
    mesh_key: Vec<usize>,
}

fn node_groups(scene: &Scene) -> Vec<NodeGroup> {
    let sourced = scene.instance_sources.len() == scene.instances.len();
    let mut groups: Vec<NodeGroup> = Vec::new();
    for (i, instance) in scene.instances.iter().enumerate() {
        let key = sourced.then(|| {
            let s = scene.instance_sources[i];
            (s.node, s.gpu_instance)
        });
        match groups.last_mut() {
            Some(g) if key.is_some() && key == g.node.map(|n| (n, g.gpu_instance)) => {
                g.instances.push(i);
                g.mesh_key.push(instance.primitive);
            }
            _ => groups.push(NodeGroup {
                node: key.map(|k| k.0),
                gpu_instance: key.and_then(|k| k.1),
                instances: vec![i],
                label: scene.primitives[instance.primitive].label.clone(),
                mesh_key: vec![instance.primitive],
            }),
        }
    }
    groups
}

fn node_uvs(scene: &Scene, instances: &[usize], uv_set: usize) -> Result<NodeUvs, LightmapError> {
    let mut out = NodeUvs {
        uvs: Vec::new(),
        triangles: Vec::new(),
        owners: Vec::new(),
    };
    for &i in instances {
        let p = &scene.primitives[scene.instances[i].primitive];
        let Some(set) = p.uvs.get(uv_set) else {
            return Err(LightmapError::NoUvs {
                label: p.label.clone(),
                uv_set,
            });
        };
        let base = out.uvs.len() as u32;
        out.uvs.extend_from_slice(set);
        for (k, t) in p.mesh.triangles.iter().enumerate() {
            out.triangles.push(t.map(|v| v + base));
            out.owners.push((i, k as u32));
        }
    }
    Ok(out)
}

/// Refuses UVs that leave the unit square or overlap.
fn check_uvs(scene: &Scene, uvs: &NodeUvs) -> Result<(), LightmapError> {
    let label = |t: usize| {
        let (i, _) = uvs.owners[t];
        scene.primitives[scene.instances[i].primitive].label.clone()
    };
    for (t, tri) in uvs.triangles.iter().enumerate() {
        for &v in tri {
            let uv = uvs.uvs[v as usize];
            if !uv.is_finite() || uv.min_element() < -1e-4 || uv.max_element() > 1.0 + 1e-4 {
                return Err(LightmapError::Uv {
                    label: label(t),
                    message: format!(
                        "triangle {} has UV {uv} outside the unit square, where a lightmap's texels are",
                        uvs.owners[t].1
                    ),
                });
            }
        }
    }
    match first_uv_overlap(&uvs.uvs, &uvs.triangles) {
        Ok(None) => Ok(()),
        Ok(Some(o)) => Err(LightmapError::Uv {
            label: label(o.first),
            message: format!(
                "triangles {} and {} overlap in its lightmap UVs ({:.1}% of the smaller): each texel must belong to one place on the surface",
                uvs.owners[o.first].1,
                uvs.owners[o.second].1,
                100.0 * o.fraction
            ),
        }),
        Err(e) => Err(LightmapError::Uv {
            label: label(0),
            message: e.to_string(),
        }),
    }
}

/// The node's surface area in the world and its triangles' area in the UV
/// set (a unit square being 1).
fn areas(scene: &Scene, uvs: &NodeUvs) -> (f64, f64) {
    let (mut world, mut uv) = (0.0, 0.0);
    for (tri, &(i, local)) in uvs.triangles.iter().zip(&uvs.owners) {
        let instance = &scene.instances[i];
        let mesh = &scene.primitives[instance.primitive].mesh;
        let [a, b, c] = mesh.triangles[local as usize].map(|v| {
            instance
                .transform
                .transform_point3(mesh.positions[v as usize])
                .as_dvec3()
        });
        world += 0.5 * (b - a).cross(c - a).length();
        let [p, q, r] = tri.map(|v| uvs.uvs[v as usize].as_dvec2());
        uv += 0.5 * (q - p).perp_dot(r - p).abs();
    }
    (world, uv)
}

/// The world position and unit normal at barycentric weights `w` of
/// triangle `local` of instance `instance`'s primitive.
fn surface_point(scene: &Scene, instance: usize, local: u32, w: [f32; 3]) -> (Vec3, Vec3) {
    let placed = &scene.instances[instance];
    let mesh = &scene.primitives[placed.primitive].mesh;
    let corners = mesh.triangles[local as usize];
    let (mut p, mut n) = (Vec3::ZERO, Vec3::ZERO);
    for (&v, &w) in corners.iter().zip(&w) {
        p += w * mesh.positions[v as usize];
        n += w * mesh.normals[v as usize];
    }
    let linear = Mat3::from_mat4(placed.transform);
    let normal_matrix = linear.inverse().transpose();
    let world_n = (normal_matrix * n).normalize_or_zero();
    let world_n = if world_n == Vec3::ZERO {
        // Opposite normals cancel: the face's own.
        let [a, b, c] = corners.map(|v| {
            placed
                .transform
                .transform_point3(mesh.positions[v as usize])
        });
        let face = (b - a).cross(c - a).normalize_or(Vec3::Y);
        if linear.determinant() < 0.0 {
            -face
        } else {
            face
        }
    } else {
        world_n
    };
    (placed.transform.transform_point3(p), world_n)
}

/// A node's triangles as [`find_seams`] reads them: corners in the mesh's
/// space with their normals, and their place in the atlas (the region's
/// square at `rect`).
fn seam_corners(scene: &Scene, uvs: &NodeUvs, rect: &TexelRect) -> Vec<[SeamCorner; 3]> {
    let origin = glam::DVec2::new(f64::from(rect.x), f64::from(rect.y));
    uvs.triangles
        .iter()
        .zip(&uvs.owners)
        .map(|(tri, &(i, local))| {
            let mesh = &scene.primitives[scene.instances[i].primitive].mesh;
            let corners = mesh.triangles[local as usize];
            std::array::from_fn(|k| SeamCorner {
                position: mesh.positions[corners[k] as usize],
                normal: mesh.normals[corners[k] as usize],
                texel: origin + uvs.uvs[tri[k] as usize].as_dvec2() * f64::from(rect.side),
            })
        })
        .collect()
}
