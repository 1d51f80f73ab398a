//! `lightmap`: a glTF scene's lightmap baked on its second UV set under a
//! distant light and the scene's own lights, packed for an engine, and
//! written as the scene with its lightmaps ([`LightmapRequest`] →
//! [`LightmapPlan`] → [`lightmap`]).

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use glam::Vec3;
use serde_json::{Value, json};
use shlight_core::sh::Frame;
use shlight_io::{Image, Ktx2TexelFormat, ToneMap, WriteOptions, encode_ktx2, write_image};
use shlight_lightmap::{
    Engine, L1Reconstruction, LightmapError, LightmapSettings, LightmapSize, SceneLightmap,
    TexelBasis, TexelFormat, TexelUnits, bake_scene_lightmap,
};
use shlight_mesh::{
    BakedNode, LightmapImage, LightmapImageFormat, LightmapRequest as GlbRequest, LoadOptions,
    Scene, write_lightmapped_glb,
};

use crate::environment::Environment;
use crate::hooks::{Hooks, Progress};
use crate::output_path::refuse_overwriting;
use crate::spelling::Spelling;
use crate::{PipelineError, Result};

/// A lightmap bake as a front end asks for it, before
/// [`LightmapRequest::check`].
#[derive(Clone, Debug)]
pub struct LightmapRequest<'a> {
    /// The scene: `.gltf` or `.glb`, every baked mesh with `TEXCOORD_1`.
    pub scene: &'a Path,
    /// The distant light: an equirect map or a radiance coefficient file.
    pub env: &'a Path,
    /// The scene with its lightmaps (`.glb`); none: the lightmap comes
    /// back only.
    pub output: Option<&'a Path>,
    /// What a texel holds.
    pub basis: TexelBasis,
    /// The engine that reads it (units and packing).
    pub engine: Engine,
    /// How an SH texel is read back.
    pub reconstruction: L1Reconstruction,
    /// The atlas, UV set, padding and gather.
    pub settings: LightmapSettings,
    /// The albedo of primitives without a material.
    pub albedo: [f32; 3],
    /// In the written scene, every baked node gets its own copy of its
    /// mesh, its `TEXCOORD_1` moved into its region (always for three.js,
    /// which reads no per-node rectangle).
    pub unshare_instances: bool,
    /// Each layer also as OpenEXR, `PREFIX.LAYER.exr`.
    pub exr: Option<&'a Path>,
    /// A picture of the lightmap's irradiance (PNG, EXR or HDR).
    pub preview: Option<&'a Path>,
}

/// A checked [`LightmapRequest`].
#[derive(Clone, Debug)]
pub struct LightmapPlan {
    scene: PathBuf,
    env: PathBuf,
    output: Option<PathBuf>,
    format: TexelFormat,
    settings: LightmapSettings,
    albedo: [f32; 3],
    unshare_instances: bool,
    exr: Option<PathBuf>,
    preview: Option<PathBuf>,
}

/// What [`lightmap`] baked.
#[derive(Clone, Debug)]
pub struct LightmapBaked {
    /// The atlas, its regions and its texels' light.
    pub lightmap: SceneLightmap,
    /// How its texels are packed.
    pub format: TexelFormat,
    /// The texels packed: one RGBA grid per layer
    /// ([`TexelFormat::layer_names`]), row by row.
    pub layers: Vec<Vec<[f32; 4]>>,
}

impl LightmapRequest<'_> {
    /// The plan, after the checks every front end makes before anything is
    /// read: an engine that reads the basis, a positive density or a side
    /// within the limits, an lmax a bake takes, no output over an input.
    ///
    /// # Errors
    /// The first check that fails, naming the settings as `spelling` does.
    pub fn check(&self, spelling: Spelling) -> Result<LightmapPlan> {
        let format =
            TexelFormat::new(self.basis, self.engine, self.reconstruction).map_err(|e| {
                PipelineError::new(format!(
                    "{} with {}: {e}",
                    spelling.option_value("basis", self.basis.name()),
                    spelling.option_value(
                        match spelling {
                            // `for` is a keyword in Python.
                            Spelling::CommandLine => "for",
                            Spelling::Python => "engine",
                        },
                        engine_name(self.engine)
                    )
                ))
            })?;
        if let Some(out) = self.output
            && !out
                .extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("glb"))
        {
            return Err(PipelineError::new(format!(
                "{}: the lightmapped scene is written as binary glTF, a .glb file",
                out.display()
            )));
        }
        for out in self.output.iter().chain(&self.preview) {
            refuse_overwriting(out, &[self.scene, self.env])?;
        }
        match self.settings.size {
            LightmapSize::Side(side) if !(4..=shlight_lightmap::MAX_SIDE).contains(&side) => {
                return Err(PipelineError::new(format!(
                    "{} is not from 4 to {}",
                    spelling.option_number("size", side, side),
                    shlight_lightmap::MAX_SIDE
                )));
            }
            LightmapSize::Density(d) if !(d.is_finite() && d > 0.0) => {
                return Err(PipelineError::new(format!(
                    "{} is not a positive number of texels per metre",
                    spelling.option_number("texel_density", d, d)
                )));
            }
            _ => {}
        }
        let lmax = self.settings.gather.lmax;
        if lmax > shlight_baked::MAX_LMAX {
            return Err(PipelineError::new(format!(
                "{} is beyond {}",
                spelling.option_number("lmax", lmax, lmax),
                shlight_baked::MAX_LMAX
            )));
        }
        Ok(LightmapPlan {
            scene: self.scene.to_path_buf(),
            env: self.env.to_path_buf(),
            output: self.output.map(Path::to_path_buf),
            format,
            settings: self.settings.clone(),
            albedo: self.albedo,
            unshare_instances: self.unshare_instances || self.engine == Engine::ThreeJs,
            exr: self.exr.map(Path::to_path_buf),
            preview: self.preview.map(Path::to_path_buf),
        })
    }
}

/// The lightmap's size from a front end's two settings: a side (`--size`,
/// `size=`), a texel density (`--texel-density`, `texel_density=`), or
/// neither (a 512 x 512 atlas).
///
/// # Errors
/// Both given, named as `spelling` names them.
pub fn lightmap_size(
    size: Option<u32>,
    texel_density: Option<f64>,
    spelling: Spelling,
) -> Result<LightmapSize> {
    match (size, texel_density) {
        (Some(_), Some(_)) => Err(PipelineError::new(format!(
            "give {} or {}, not both",
            spelling.option("size"),
            spelling.option("texel_density")
        ))),
        (_, Some(d)) => Ok(LightmapSize::Density(d)),
        (Some(s), None) => Ok(LightmapSize::Side(s)),
        (None, None) => Ok(LightmapSize::Side(DEFAULT_SIDE)),
    }
}

/// How SH texels are read back: Geomerics' non-linear reconstruction
/// (`--non-linear`, `non_linear=True`) or the linear one.
#[must_use]
pub fn reconstruction(non_linear: bool) -> L1Reconstruction {
    if non_linear {
        L1Reconstruction::NonLinear
    } else {
        L1Reconstruction::Linear
    }
}

/// The atlas's side without a size or density.
pub const DEFAULT_SIDE: u32 = 512;

/// The basis named `name` (`irradiance`, `sh-l1`, `monosh`).
///
/// # Errors
/// Another name, with the names there are.
pub fn texel_basis(name: &str, spelling: Spelling) -> Result<TexelBasis> {
    [TexelBasis::Irradiance, TexelBasis::ShL1, TexelBasis::MonoSh]
        .into_iter()
        .find(|b| b.name() == name)
        .ok_or_else(|| {
            PipelineError::new(format!(
                "{}: expected irradiance, sh-l1 or monosh",
                spelling.option_value("basis", name)
            ))
        })
}

/// The engine named `name` as `--for` names it (`threejs`, `bevy`,
/// `godot`, `unity`).
///
/// # Errors
/// Another name, with the names there are.
pub fn engine_by_name(name: &str, spelling: Spelling) -> Result<Engine> {
    [Engine::ThreeJs, Engine::Bevy, Engine::Godot, Engine::Unity]
        .into_iter()
        .find(|e| engine_name(*e) == name)
        .ok_or_else(|| {
            PipelineError::new(format!(
                "{}: expected threejs, bevy, godot or unity",
                spelling.option_value(engine_option(spelling), name)
            ))
        })
}

/// How a front end names the engine's setting (`for` is a keyword in
/// Python).
fn engine_option(spelling: Spelling) -> &'static str {
    match spelling {
        Spelling::CommandLine => "for",
        Spelling::Python => "engine",
    }
}

/// The engine as `--for` names it.
pub fn engine_name(engine: Engine) -> &'static str {
    match engine {
        Engine::ThreeJs => "threejs",
        Engine::Bevy => "bevy",
        Engine::Godot => "godot",
        Engine::Unity => "unity",
    }
}

/// `shlight lightmap`: reads the light, then the scene; then as
/// [`lightmap_of_scene`].
///
/// # Errors
/// A light or scene that cannot be read; UVs or settings the bake refuses
/// (naming the mesh); a file that cannot be written.
pub fn lightmap(plan: &LightmapPlan, hooks: &dyn Hooks) -> Result<LightmapBaked> {
    let scene = shlight_mesh::load_scene(&plan.scene, &LoadOptions::default())?;
    lightmap_of_scene(plan, &scene, hooks)
}

/// The lightmap job through a glTF scene loaded already: reads the light,
/// notes the scene, bakes (progress per stage: the surfaces' rays and
/// bounces, then the texels), notes the atlas, packs the texels for the
/// engine, and writes the files asked for.
///
/// # Errors
/// As [`lightmap`], the scene's reading aside.
pub fn lightmap_of_scene(
    plan: &LightmapPlan,
    scene: &Scene,
    hooks: &dyn Hooks,
) -> Result<LightmapBaked> {
    let light = Environment::load(&plan.env, Frame::YUp, plan.settings.gather.lmax)?;
    light.warnings.iter().for_each(|w| hooks.warn(w));
    let radiance = light.radiance_in(Frame::YUp);
    let name = plan.scene.display().to_string();
    for note in &scene.notes {
        hooks.note(&format!("{name}: {note}"));
    }
    let surfaces = Arc::new(scene.flatten(Vec3::from_array(plan.albedo))?);
    hooks.note(&format!(
        "{name}: {} triangles in {} placed primitives, {} materials, {} textures, {} punctual lights ({})",
        surfaces.mesh.triangle_count(),
        scene.instances.len(),
        surfaces.materials.len() - 1,
        surfaces.textures.len(),
        scene.lights.len(),
        match plan.settings.gather.light_units {
            shlight_mesh::LightUnits::Blender => "intensities divided by 683 (blender units)",
            shlight_mesh::LightUnits::AsWritten => "intensities as written",
        }
    ));
    if let Some(note) = super::volume::two_level_note(&surfaces) {
        hooks.note(&format!("{name}: {note}"));
    }
    let start = Instant::now();
    let map = bake_scene_lightmap(
        scene,
        &surfaces,
        &radiance,
        &scene.lights,
        &plan.settings,
        &|stage, done, total| {
            hooks.progress(Progress::Count {
                stage: &super::volume::stage_label(stage),
                done,
                total,
            });
        },
    )
    .map_err(|e| {
        let hint = match e {
            LightmapError::NoUvs { .. } => {
                "; shlight does not unwrap meshes yet: give the meshes to bake a second UV map (in Blender, a second UV map laid out with Lightmap Pack), which glTF's exporters write as TEXCOORD_1"
            }
            _ => "",
        };
        PipelineError::new(format!("{name}: {e}{hint}"))
    })?;
    let seconds = start.elapsed().as_secs_f64();
    if !map.skipped.is_empty() {
        hooks.note(&format!(
            "{name}: {} node{} without TEXCOORD_1 not baked (they still cast shadows and reflect light): {}",
            map.skipped.len(),
            if map.skipped.len() == 1 { "" } else { "s" },
            map.skipped.join(", ")
        ));
    }
    let covered: usize = map.regions.iter().map(|r| r.covered).sum();
    hooks.note(&format!(
        "{} x {} lightmap, {} regions at {:.1} texels per metre; {covered} texels baked ({} inside geometry, filled), {} rays each; {} rays in {seconds:.2} s ({:.1} M rays/s)",
        map.side,
        map.side,
        map.regions.len(),
        map.density,
        map.invalid,
        map.samples,
        map.rays,
        map.rays as f64 / seconds.max(1e-9) / 1e6
    ));
    let layers = map.layers(plan.format);
    if let Some(prefix) = &plan.exr {
        for (layer, name) in layers.iter().zip(plan.format.layer_names()) {
            let path = layer_path(prefix, name);
            write_layer(&path, map.side, layer, &WriteOptions::default())?;
            hooks.note(&format!("wrote {}", path.display()));
        }
    }
    if let Some(path) = &plan.preview {
        let irradiance: Vec<[f32; 4]> = map
            .texels
            .iter()
            .map(|t| {
                t.map_or([0.0; 4], |t| {
                    let e = t.irradiance.as_vec3();
                    [e.x, e.y, e.z, 1.0]
                })
            })
            .collect();
        let peak = irradiance
            .iter()
            .map(|p| p[0].max(p[1]).max(p[2]))
            .fold(0.0f32, f32::max);
        let options = WriteOptions {
            exposure_ev: if peak > 0.0 { -peak.log2() } else { 0.0 },
            tone_map: ToneMap::Clamp,
            ..WriteOptions::default()
        };
        write_layer(path, map.side, &irradiance, &options)?;
        hooks.note(&format!("wrote {}", path.display()));
    }
    let baked = LightmapBaked {
        lightmap: map,
        format: plan.format,
        layers,
    };
    if let Some(out) = &plan.output {
        for note in write_scene(plan, &baked, out)? {
            hooks.note(&format!("{}: {note}", out.display()));
        }
        hooks.note(&format!("wrote {}", out.display()));
    }
    Ok(baked)
}

/// `PREFIX.LAYER.exr`.
fn layer_path(prefix: &Path, layer: &str) -> PathBuf {
    let mut name = prefix.as_os_str().to_os_string();
    name.push(format!(".{layer}.exr"));
    PathBuf::from(name)
}

/// One layer's RGB as an image file.
fn write_layer(path: &Path, side: u32, layer: &[[f32; 4]], options: &WriteOptions) -> Result<()> {
    let pixels = layer.iter().map(|p| [p[0], p[1], p[2]]).collect();
    let image = Image::new(side as usize, side as usize, pixels)
        .map_err(|e| PipelineError::new(format!("{}: {e}", path.display())))?;
    write_image(path, &image, options)?;
    Ok(())
}

/// What the lightmap holds, as shlight's glTF extension `SHLIGHT_lightmap`
/// states it at the file's root (docs/lightmaps.md).
#[must_use]
pub fn lightmap_description(plan: &LightmapPlan, baked: &LightmapBaked) -> Value {
    let map = &baked.lightmap;
    let g = &plan.settings.gather;
    json!({
        "basis": plan.format.basis().name(),
        "engine": engine_name(plan.format.engine()),
        "reconstruction": plan.format.reconstruction().name(),
        "units": match plan.format.units() {
            TexelUnits::Irradiance => "irradiance",
            TexelUnits::IrradianceOverPi => "irradiance/pi",
        },
        "layers": plan.format.layer_names(),
        "texCoord": plan.settings.uv_set,
        "size": [map.side, map.side],
        "texelsPerMetre": map.density,
        "padding": plan.settings.padding,
        "denoise": plan.settings.denoise,
        "frame": "glTF (y up, metres)",
        "colorSpace": "linear Rec.709",
        "basisConvention": "real orthonormal SH, index l(l+1)+m, Condon-Shortley phase",
        "samples": map.samples,
        "bounces": g.bounces,
        "surfaceSamples": g.surface_samples,
        "lmax": g.lmax,
        "seed": g.seed,
        "lightUnits": match g.light_units {
            shlight_mesh::LightUnits::Blender => "blender",
            shlight_mesh::LightUnits::AsWritten => "as-written",
        },
        "environment": plan.env.display().to_string(),
        "generator": format!("shlight {}", env!("CARGO_PKG_VERSION")),
    })
}

/// Writes the scene with its lightmaps: the input glTF kept as it was,
/// each layer a half-float KTX2 page (`KHR_texture_basisu`) named
/// `"<scene> lightmap <layer>"`, appended in the layers' order; the
/// materials of every baked node reading the first layer through
/// `MOZ_lightmap` (its `intensity` turning the engine's units back into
/// irradiance); `SHLIGHT_lightmap` on the root ([`lightmap_description`])
/// and on each baked node (its region and `TEXCOORD_1` scale and offset);
/// each node's mesh copied with its `TEXCOORD_1` moved into its region
/// where the plan unshares instances. Returns the writer's notes.
fn write_scene(plan: &LightmapPlan, baked: &LightmapBaked, out: &Path) -> Result<Vec<String>> {
    let map = &baked.lightmap;
    let stem = plan
        .scene
        .file_stem()
        .map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned());
    let intensity = (1.0 / plan.format.units().scale()) as f32;
    let mut images = Vec::with_capacity(baked.layers.len());
    for (layer, name) in baked.layers.iter().zip(plan.format.layer_names()) {
        let bytes = encode_ktx2(
            Ktx2TexelFormat::Rgba16Float,
            map.side as usize,
            map.side as usize,
            layer,
        )
        .map_err(|e| PipelineError::new(format!("{}: {e}", out.display())))?;
        images.push(LightmapImage {
            name: format!("{stem} lightmap {name}"),
            format: LightmapImageFormat::Ktx2,
            bytes,
            intensity,
        });
    }
    let mut nodes = Vec::with_capacity(map.regions.len());
    for r in &map.regions {
        let Some(node) = r.node else {
            return Err(PipelineError::new(format!(
                "{}: {} was not placed by a node of the file",
                out.display(),
                r.label
            )));
        };
        if r.gpu_instance.is_some() {
            return Err(PipelineError::new(format!(
                "{}: node {node} ({}) places its mesh by EXT_mesh_gpu_instancing, whose instances glTF gives no lightmap of their own",
                out.display(),
                r.label
            )));
        }
        let (scale, offset) = (r.placement.scale, r.placement.offset);
        nodes.push(BakedNode {
            node,
            scale: scale.to_array(),
            offset: offset.to_array(),
            image: Some(0),
            unshare: plan.unshare_instances,
            extension: json!({
                "rect": [r.rect.x, r.rect.y, r.rect.side],
                "scaleOffset": [scale.x, scale.y, offset.x, offset.y],
                "texCoordMoved": plan.unshare_instances,
            }),
        });
    }
    let mut root = lightmap_description(plan, baked);
    root["images"] = json!(images.iter().map(|i| i.name.clone()).collect::<Vec<_>>());
    let request = GlbRequest {
        images,
        nodes,
        root_extension: root,
        load_options: LoadOptions::default(),
    };
    let made = write_lightmapped_glb(&plan.scene, out, &request)?;
    Ok(made.notes)
}
