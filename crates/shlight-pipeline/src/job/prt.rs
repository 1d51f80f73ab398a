//! `prt`: precomputed radiance transfer baked for a mesh — diffuse transfer
//! vectors (unshadowed, shadowed, interreflected) or glossy transfer
//! matrices for a BRDF, compressed or not — written as a `.shprt` file or a
//! glTF with `_SH_TRANSFER_k` attributes, and a preview of the mesh under a
//! light ([`PrtRequest`] → [`PrtPlan`] → [`prt`], or [`prt_of_scene`] for a
//! glTF scene read already). A glTF file is baked as a scene: its instances
//! flattened, the albedo of the texel a bounce hits, rays through its
//! cut-outs, and its punctual lights and emission in a static term per
//! vertex (docs/shprt.md).

use std::borrow::Cow;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use glam::{DVec3, Vec3};
use shlight_core::sh::ShCoeffs;
use shlight_format::{CoeffFile, ShprtFile};
use shlight_io::{ToneMap, WriteOptions, write_image};
use shlight_mesh::{LightUnits, LoadOptions, Mesh, MeshFormat, Scene, Surfaces};
use shlight_prt::{
    Albedo, BakeRequest, Brdf, DEFAULT_ALBEDO, DEFAULT_BOUNCES, MAX_BAKE_LMAX, MAX_GLOSSY_BYTES,
    Mode, SceneLighting, Stage, Transfer, bake_file, bake_glossy_file, bake_scene_file,
    compress_file, file_exit_radiance, glossy_bytes, glossy_channels, parse_cpca, render_preview,
    vertex_exposure, write_gltf,
};

use crate::hooks::{Hooks, Progress};
use crate::job::by_name::by_name;
use crate::output_path::refuse_overwriting;
use crate::spelling::Spelling;
use crate::{PipelineError, Result};

/// The light transport a front end names (`shlight prt --mode`, Python's
/// `mode=`); with the bounces it makes shlight-prt's [`Mode`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PrtMode {
    /// Cosine-weighted only: the SH irradiance transfer.
    Unshadowed,
    /// With self-shadowing.
    Shadowed,
    /// With self-shadowing and bounces of diffuse interreflection.
    Interreflected,
    /// Glossy transfer matrices (shadowed, with diffuse bounces when
    /// given) for a view-dependent BRDF; `.shprt` only.
    Glossy,
}

impl PrtMode {
    /// Every mode, in the order of the command line's help.
    pub const ALL: [PrtMode; 4] = [
        PrtMode::Unshadowed,
        PrtMode::Shadowed,
        PrtMode::Interreflected,
        PrtMode::Glossy,
    ];

    /// The name both front ends take.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            PrtMode::Unshadowed => "unshadowed",
            PrtMode::Shadowed => "shadowed",
            PrtMode::Interreflected => "interreflected",
            PrtMode::Glossy => "glossy",
        }
    }
}

impl std::str::FromStr for PrtMode {
    type Err = String;

    /// One of the [names](PrtMode::name).
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        by_name(&PrtMode::ALL, PrtMode::name, s, "mode")
    }
}

/// A PRT bake as a front end asks for it, before [`PrtRequest::check`].
#[derive(Clone, Copy, Debug)]
pub struct PrtRequest<'a> {
    /// The mesh: `.obj`, `.ply`, `.off`, or a glTF scene (`.gltf`, `.glb`).
    pub mesh: &'a Path,
    /// Highest SH degree of the transfer.
    pub lmax: usize,
    /// Directions per vertex over the whole sphere.
    pub samples: usize,
    /// Light transport.
    pub mode: PrtMode,
    /// Bounces of interreflection [default: 2 interreflected, 0 glossy].
    pub bounces: Option<u32>,
    /// The glossy BRDF (`phong:S`, `ggx:ALPHA[,F0]`).
    pub brdf: Option<&'a str>,
    /// Glossy matrices compressed: `cpca:C,K`.
    pub compress: Option<&'a str>,
    /// Diffuse albedo, linear, for every vertex of a mesh [default: the
    /// mesh's vertex colours, or 0.8]; refused for a glTF scene, whose
    /// materials give it.
    pub albedo: Option<[f32; 3]>,
    /// How a glTF scene's punctual lights' intensities are read [default:
    /// [`LightUnits::Blender`]]; refused for a mesh, which has no lights.
    pub light_units: Option<LightUnits>,
    /// Seed of the direction set.
    pub seed: u64,
    /// The file to write: `.shprt`, or a glTF (`.gltf`, `.glb`) with the
    /// transfer as vertex attributes.
    pub output: Option<&'a Path>,
    /// A radiance coefficient file to shade the preview with.
    pub light: Option<&'a Path>,
    /// A picture of the mesh shaded by `light` (PNG, EXR, HDR).
    pub preview: Option<&'a Path>,
    /// The preview's size.
    pub preview_size: (usize, usize),
    /// The preview's exposure in stops [default: the mean vertex radiance
    /// at 0.25].
    pub preview_exposure: Option<f32>,
}

/// Where a bake's transfer is written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PrtOutput {
    /// A `.shprt` file (docs/shprt.md).
    Shprt,
    /// The mesh as glTF (`.gltf`, `.glb`) with `_SH_TRANSFER_k` attributes.
    Gltf,
}

impl PrtOutput {
    /// The kind `path` names by its extension.
    #[must_use]
    pub fn of(path: &Path) -> Option<Self> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("shprt") => Some(Self::Shprt),
            Some("gltf" | "glb") => Some(Self::Gltf),
            _ => None,
        }
    }
}

/// A checked [`PrtRequest`].
#[derive(Clone, Debug)]
pub struct PrtPlan {
    mesh: PathBuf,
    bake: BakeRequest,
    brdf: Option<Brdf>,
    compress: Option<(usize, usize)>,
    output: Option<(PathBuf, PrtOutput)>,
    preview: Option<PreviewPlan>,
    /// A glTF scene: its lights' units (`None`: a mesh).
    scene: Option<LightUnits>,
    spelling: Spelling,
}

#[derive(Clone, Debug)]
struct PreviewPlan {
    light: PathBuf,
    path: PathBuf,
    size: (usize, usize),
    exposure: Option<f32>,
}

impl PrtRequest<'_> {
    /// The plan, after the checks every front end makes: the mode takes
    /// its bounces (interreflected or glossy only); glossy transfer needs
    /// a BRDF, and only it takes one and a compression; a preview needs a
    /// light and diffuse transfer; at least one sample; lmax at most
    /// [`MAX_BAKE_LMAX`]; the output a `.shprt` or glTF file (glTF not for
    /// glossy transfer), not the mesh.
    ///
    /// # Errors
    /// The first check that fails, naming the settings as `spelling` does.
    pub fn check(&self, spelling: Spelling) -> Result<PrtPlan> {
        let fail = |m: String| Err(PipelineError::new(m));
        let mode = self.transport(spelling)?;
        let glossy = self.mode == PrtMode::Glossy;
        let mode_glossy = spelling.option_value("mode", "glossy");
        let brdf = match (self.brdf, glossy) {
            (Some(text), true) => Some(
                Brdf::parse(text)
                    .map_err(|e| PipelineError::new(format!("{}: {e}", spelling.option("brdf"))))?,
            ),
            (None, true) => {
                return fail(format!(
                    "{mode_glossy} needs {} or ggx:ALPHA[,F0] (e.g. {})",
                    spelling.option_value("brdf", "phong:S"),
                    spelling.option_value("brdf", "phong:32")
                ));
            }
            (Some(_), false) => {
                return fail(format!(
                    "{} is the BRDF of {mode_glossy}",
                    spelling.option("brdf")
                ));
            }
            (None, false) => None,
        };
        let compress = match (self.compress, glossy) {
            (Some(text), true) => Some(parse_cpca(text).map_err(|e| {
                PipelineError::new(format!("{}: {e}", spelling.option("compress")))
            })?),
            (Some(_), false) => {
                return fail(format!(
                    "{} compresses the matrices of {mode_glossy}",
                    spelling.option("compress")
                ));
            }
            (None, _) => None,
        };
        let preview = self.preview_plan(glossy, spelling)?;
        let scene = self.scene_plan(spelling)?;
        if self.samples == 0 {
            return fail(format!("{} must be at least 1", spelling.option("samples")));
        }
        if self.lmax > MAX_BAKE_LMAX {
            return fail(format!(
                "{} is beyond {MAX_BAKE_LMAX} (diffuse transfer needs 2 to 6)",
                spelling.option_number("lmax", self.lmax, self.lmax)
            ));
        }
        let output = self
            .output
            .map(|path| self.output_plan(path, brdf, spelling))
            .transpose()?;
        for out in output
            .iter()
            .map(|(p, _)| p)
            .chain(preview.iter().map(|p| &p.path))
        {
            refuse_overwriting(out, &[self.mesh])?;
        }
        Ok(PrtPlan {
            mesh: self.mesh.to_path_buf(),
            bake: BakeRequest {
                lmax: self.lmax,
                samples: self.samples,
                mode,
                albedo: self.albedo,
                seed: self.seed,
            },
            brdf,
            compress,
            output,
            preview,
            scene,
            spelling,
        })
    }

    /// A glTF file is a scene: no albedo of the request's (its materials
    /// give it), its lights read in the units given; a mesh takes no light
    /// units.
    fn scene_plan(&self, spelling: Spelling) -> Result<Option<LightUnits>> {
        let scene = MeshFormat::from_path(self.mesh) == Some(MeshFormat::Gltf);
        if scene && self.albedo.is_some() {
            return Err(PipelineError::new(format!(
                "{}: a glTF scene's albedo is its materials' (base colour, vertex colours and \
                 textures); {} sets one albedo for every vertex of a mesh (.obj, .ply, .off)",
                self.mesh.display(),
                spelling.option("albedo")
            )));
        }
        if !scene && self.light_units.is_some() {
            return Err(PipelineError::new(format!(
                "{} reads a glTF scene's punctual lights; {} is a mesh, without lights",
                spelling.option("light_units"),
                self.mesh.display()
            )));
        }
        Ok(scene.then(|| self.light_units.unwrap_or(LightUnits::Blender)))
    }

    /// shlight-prt's [`Mode`]: the transport with its bounces.
    fn transport(&self, spelling: Spelling) -> Result<Mode> {
        Ok(match (self.mode, self.bounces) {
            (PrtMode::Interreflected, b) => Mode::Interreflected {
                bounces: b.unwrap_or(DEFAULT_BOUNCES),
            },
            (PrtMode::Glossy, None | Some(0)) => Mode::Shadowed,
            (PrtMode::Glossy, Some(bounces)) => Mode::Interreflected { bounces },
            (_, Some(_)) => {
                return Err(PipelineError::new(format!(
                    "{} needs {} or {}",
                    spelling.option("bounces"),
                    spelling.option_value("mode", "interreflected"),
                    spelling.option_value("mode", "glossy")
                )));
            }
            (PrtMode::Unshadowed, None) => Mode::Unshadowed,
            (PrtMode::Shadowed, None) => Mode::Shadowed,
        })
    }

    /// The preview: a light and a picture, together, of diffuse transfer.
    fn preview_plan(&self, glossy: bool, spelling: Spelling) -> Result<Option<PreviewPlan>> {
        let (light, path) = match (self.light, self.preview) {
            (None, None) => return Ok(None),
            (Some(light), Some(path)) => (light, path),
            (light, _) => {
                let (given, missing) = if light.is_some() {
                    ("light", "preview")
                } else {
                    ("preview", "light")
                };
                return Err(PipelineError::new(format!(
                    "{} needs {}: the preview is the mesh shaded by the light",
                    spelling.option(given),
                    spelling.option(missing)
                )));
            }
        };
        if glossy {
            return Err(PipelineError::new(format!(
                "{} shades diffuse transfer; a glossy file is shaded view by view (sample it with a light and a view)",
                spelling.option("preview")
            )));
        }
        Ok(Some(PreviewPlan {
            light: light.to_path_buf(),
            path: path.to_path_buf(),
            size: self.preview_size,
            exposure: self.preview_exposure,
        }))
    }

    /// The output's kind: `.shprt`, or glTF for diffuse transfer.
    fn output_plan(
        &self,
        path: &Path,
        brdf: Option<Brdf>,
        spelling: Spelling,
    ) -> Result<(PathBuf, PrtOutput)> {
        let Some(kind) = PrtOutput::of(path) else {
            return Err(PipelineError::new(format!(
                "{}: unknown output format (use .shprt, .gltf or .glb)",
                path.display()
            )));
        };
        if let (Some(brdf), PrtOutput::Gltf) = (brdf, kind) {
            return Err(PipelineError::new(format!(
                "{}: glTF cannot carry glossy transfer ({brdf}): a matrix per vertex is beyond \
                 what glTF vertex attributes hold; write a .shprt file, or bake without \
                 {} for glTF's transfer vectors",
                path.display(),
                spelling.option_value("mode", "glossy")
            )));
        }
        Ok((path.to_path_buf(), kind))
    }
}

/// What [`prt`] baked.
#[derive(Clone, Debug)]
pub struct PrtBaked {
    /// The `.shprt` file (compressed where the plan says).
    pub file: ShprtFile,
    /// Directions in the shared set.
    pub samples: usize,
    /// Rays cast.
    pub rays: u64,
}

/// The label of a bake stage's progress.
fn stage_label(stage: Stage) -> Cow<'static, str> {
    match stage {
        Stage::Rays => "directions".into(),
        Stage::Bounce(k) => format!("bounce {k}").into(),
        Stage::Matrices => "matrices".into(),
    }
}

/// `shlight prt`: reads the preview's light first (a bad light fails before
/// a long bake), reads the mesh, bakes (progress per stage: the
/// directions, each bounce, the matrices), notes what it baked and how
/// fast, compresses a glossy bake where asked, and writes the output and
/// the preview.
///
/// # Errors
/// A light or mesh that cannot be read (a light of irradiance); glossy
/// matrices beyond [`MAX_GLOSSY_BYTES`] or a compression with more basis
/// vectors than a vertex's matrices hold; an output that cannot be written.
pub fn prt(plan: &PrtPlan, hooks: &dyn Hooks) -> Result<PrtBaked> {
    let light = preview_light(plan)?;
    if plan.scene.is_some() {
        let scene = shlight_mesh::load_scene(&plan.mesh, &LoadOptions::default())?;
        return scene_bake(plan, &scene, light.as_ref(), hooks);
    }
    let name = plan.mesh.display().to_string();
    let mesh = shlight_mesh::load(&plan.mesh)?;
    let surfaces: Option<Arc<Surfaces>> = None;
    if mesh.report.degenerate_triangles > 0 {
        hooks.warn(&format!(
            "{name}: skipped {} degenerate triangles",
            mesh.report.degenerate_triangles
        ));
    }
    if matches!(plan.bake.albedo(&mesh).0, Albedo::PerVertex(_)) {
        hooks.note(&format!("{name}: albedo from the mesh's vertex colours"));
    }
    let progress = bake_progress(hooks);
    if let Some(brdf) = plan.brdf {
        return glossy(plan, (&mesh, surfaces.as_ref()), brdf, &progress, hooks);
    }
    let start = Instant::now();
    let baked = bake_file(&mesh, surfaces.as_ref(), &plan.mesh, &plan.bake, &progress);
    finish_diffuse(plan, &mesh, baked, start, light.as_ref(), hooks)
}

/// The light of the plan's preview picture, read before anything is
/// baked (none without a preview).
fn preview_light(plan: &PrtPlan) -> Result<Option<ShCoeffs<DVec3>>> {
    Ok(plan
        .preview
        .as_ref()
        .map(|p| {
            CoeffFile::read_radiance(&p.light, "PRT shading", "project the map as radiance")
                .map(|f| f.coeffs)
        })
        .transpose()?)
}

/// [`prt`] on a glTF scene read (or built) already, for a plan made from
/// a glTF path (whose name the notes and the file take).
///
/// # Errors
/// A plan made for a mesh; as [`prt`], the reading of the scene aside.
pub fn prt_of_scene(plan: &PrtPlan, scene: &Scene, hooks: &dyn Hooks) -> Result<PrtBaked> {
    if plan.scene.is_none() {
        return Err(PipelineError::new(format!(
            "{}: a scene is baked from a .gltf or .glb path",
            plan.mesh.display()
        )));
    }
    let light = preview_light(plan)?;
    scene_bake(plan, scene, light.as_ref(), hooks)
}

/// A glTF scene's bake: flattened (primitives without a material taking
/// [`DEFAULT_ALBEDO`]), its lights noted, glTF output of a static term
/// refused before the bake, then [`bake_scene_file`] (glossy transfer
/// through the surfaces, the lights and emission left out with a warning)
/// and the outputs as [`prt`] writes them.
fn scene_bake(
    plan: &PrtPlan,
    scene: &Scene,
    light: Option<&ShCoeffs<DVec3>>,
    hooks: &dyn Hooks,
) -> Result<PrtBaked> {
    let name = plan.mesh.display().to_string();
    let units = plan.scene.unwrap_or(LightUnits::Blender);
    let surfaces = Arc::new(scene.flatten(Vec3::from_array(DEFAULT_ALBEDO))?);
    let mesh = &surfaces.mesh;
    if mesh.report.degenerate_triangles > 0 {
        hooks.warn(&format!(
            "{name}: skipped {} degenerate triangles",
            mesh.report.degenerate_triangles
        ));
    }
    hooks.note(&format!(
        "{name}: a glTF scene, {} instances of {} primitives, {} materials{}: albedo from its materials{}",
        scene.instances.len(),
        scene.primitives.len(),
        scene.materials.len(),
        if surfaces.any_cut_out() { " (cut-outs let rays through)" } else { "" },
        match scene.lights.len() {
            0 => String::new(),
            n => format!(
                "; {n} punctual light{}, intensities {}",
                if n == 1 { "" } else { "s" },
                match units {
                    LightUnits::Blender => "divided by 683 (blender units)",
                    LightUnits::AsWritten => "as written",
                }
            ),
        }
    ));
    if let Some(note) = super::volume::two_level_note(&surfaces) {
        hooks.note(&format!("{name}: {note}"));
    }
    let own_light = !scene.lights.is_empty() || mesh.emission.is_some();
    let progress = bake_progress(hooks);
    if let Some(brdf) = plan.brdf {
        if own_light {
            hooks.warn(&format!(
                "{name}: glossy transfer holds the distant light only: the scene's punctual \
                 lights and emission are left out (bake diffuse transfer for their static term)"
            ));
        }
        return glossy(plan, (mesh, Some(&surfaces)), brdf, &progress, hooks);
    }
    if let (Some((path, PrtOutput::Gltf)), true) = (&plan.output, own_light) {
        return Err(PipelineError::new(format!(
            "{}: glTF's transfer attributes cannot carry the static light of {name}'s punctual \
             lights and emission; write a .shprt file (format version 3 holds it)",
            path.display()
        )));
    }
    let lighting = SceneLighting {
        surfaces: &surfaces,
        lights: &scene.lights,
        units,
    };
    let start = Instant::now();
    let baked = bake_scene_file(lighting, &plan.mesh, &plan.bake, &progress);
    finish_diffuse(plan, mesh, baked, start, light, hooks)
}

/// The bakes' progress, told to `hooks` under each stage's label.
fn bake_progress(hooks: &dyn Hooks) -> impl Fn(Stage, usize, usize) + Sync + '_ {
    move |stage, done, total| {
        hooks.progress(Progress::Count {
            stage: &stage_label(stage),
            done,
            total,
        });
    }
}

/// The end of a diffuse bake of [`prt`] begun at `start`: its figures
/// noted, its file written (`.shprt` or glTF) and its preview drawn under
/// `light`.
fn finish_diffuse(
    plan: &PrtPlan,
    mesh: &Mesh,
    (transfer, file): (Transfer, ShprtFile),
    start: Instant,
    light: Option<&ShCoeffs<DVec3>>,
    hooks: &dyn Hooks,
) -> Result<PrtBaked> {
    let seconds = start.elapsed().as_secs_f64();
    hooks.note(&format!(
        "{}: {} vertices, {} triangles, {} transfer{}, lmax {}, {} directions; {} rays in {seconds:.2} s ({:.1} M rays/s)",
        plan.mesh.display(),
        mesh.vertex_count(),
        mesh.triangle_count(),
        plan.bake.mode.name(),
        if file.static_light.is_some() { " and a static term" } else { "" },
        plan.bake.lmax,
        transfer.samples,
        transfer.rays,
        transfer.rays as f64 / seconds.max(1e-9) / 1e6,
    ));
    match &plan.output {
        Some((path, PrtOutput::Shprt)) => file.write(path)?,
        Some((path, PrtOutput::Gltf)) => write_gltf(path, mesh, &file)?,
        None => {}
    }
    if let (Some(preview), Some(light)) = (&plan.preview, light) {
        write_preview(preview, mesh, &file, light)?;
    }
    Ok(PrtBaked {
        file,
        samples: transfer.samples,
        rays: transfer.rays,
    })
}

/// Mebibytes of `bytes`.
fn mib(bytes: u64) -> f64 {
    bytes as f64 / f64::from(1u32 << 20)
}

/// A glossy bake of [`prt`]: the matrices' size checked and noted, the
/// bake, the compression, the `.shprt` file.
fn glossy(
    plan: &PrtPlan,
    (mesh, surfaces): (&Mesh, Option<&Arc<Surfaces>>),
    brdf: Brdf,
    progress: &(dyn Fn(Stage, usize, usize) + Sync),
    hooks: &dyn Hooks,
) -> Result<PrtBaked> {
    let name = plan.mesh.display().to_string();
    let (lmax, spelling) = (plan.bake.lmax, plan.spelling);
    let mut options = plan.bake.options(mesh).0;
    options.surfaces = surfaces.cloned();
    let channels = glossy_channels(&options);
    let size = |lmax| glossy_bytes(mesh.vertex_count(), channels, lmax).unwrap_or(u64::MAX);
    let bytes = size(lmax);
    let plural = if channels == 1 { "" } else { "s" };
    let lmax_of = |l: usize| spelling.option_number("lmax", l, l);
    if bytes > MAX_GLOSSY_BYTES {
        let fits = (0..lmax).rev().find(|&l| size(l) <= MAX_GLOSSY_BYTES);
        return Err(PipelineError::new(format!(
            "{name}: {}: glossy matrices of {} vertices x {channels} channel{plural} x {}^2 \
             floats would take {:.0} MiB, beyond the {:.0} MiB shlight bakes{}",
            lmax_of(lmax),
            mesh.vertex_count(),
            (lmax + 1) * (lmax + 1),
            mib(bytes),
            mib(MAX_GLOSSY_BYTES),
            fits.map_or(String::new(), |l| format!(
                " ({} takes {:.0} MiB)",
                lmax_of(l),
                mib(size(l))
            ))
        )));
    }
    let dim = channels * (lmax + 1).pow(4);
    if let Some((_, vectors)) = plan.compress.filter(|&(_, k)| k > dim) {
        return Err(PipelineError::new(format!(
            "{}: a vertex's matrices hold {dim} values at {}: at most {dim} basis \
             vectors per cluster, not {vectors}",
            spelling.option("compress"),
            lmax_of(lmax)
        )));
    }
    hooks.note(&format!(
        "{name}: glossy matrices take {:.1} MiB ({} vertices x {channels} channel{plural} x {}^2 floats, with positions and normals)",
        mib(bytes),
        mesh.vertex_count(),
        (lmax + 1) * (lmax + 1),
    ));
    let start = Instant::now();
    let (transfer, mut file) =
        bake_glossy_file(mesh, surfaces, &plan.mesh, &plan.bake, brdf, progress);
    let seconds = start.elapsed().as_secs_f64();
    hooks.note(&format!(
        "{name}: {} vertices, {} triangles, glossy {} transfer for {brdf}, lmax {lmax}, {} directions; {} rays in {seconds:.2} s",
        mesh.vertex_count(),
        mesh.triangle_count(),
        plan.bake.mode.name(),
        transfer.samples,
        transfer.rays,
    ));
    if let Some((clusters, vectors)) = plan.compress {
        hooks.progress(Progress::Step("compressing (CPCA)"));
        let e = compress_file(&mut file, clusters, vectors, plan.bake.seed)
            .map_err(|e| PipelineError::new(format!("{}: {e}", spelling.option("compress"))))?;
        hooks.note(&format!(
            "{name}: cpca:{clusters},{vectors}: {:.1} MiB of matrices in {:.1} MiB; RMS error {:.3e} ({:.2}% of the entries' RMS)",
            mib(e.bytes_before),
            mib(e.bytes_after),
            e.rms,
            100.0 * e.rms / e.rms_entries.max(f64::MIN_POSITIVE),
        ));
    }
    if let Some((path, _)) = &plan.output {
        file.write(path)?;
    }
    Ok(PrtBaked {
        file,
        samples: transfer.samples,
        rays: transfer.rays,
    })
}

/// Shades every vertex (`T . L`, shlight-baked's `TransferView`, plus a
/// scene's static term: shlight-prt's `file_exit_radiance`) and
/// rasterises the mesh into the preview's picture, ACES tone mapped.
fn write_preview(
    preview: &PreviewPlan,
    mesh: &Mesh,
    file: &ShprtFile,
    light: &ShCoeffs<DVec3>,
) -> Result<()> {
    // `T . L`, plus a scene's static term.
    let radiance: Vec<Vec3> = file_exit_radiance(file, light.as_slice(), None)
        .map_err(|e| PipelineError::new(format!("{}: {e}", preview.path.display())))?
        .iter()
        .map(|c| c.as_vec3())
        .collect();
    let (w, h) = preview.size;
    let image = render_preview(mesh, &radiance, w, h);
    let exposure = preview
        .exposure
        .unwrap_or_else(|| vertex_exposure(&radiance));
    write_image(
        &preview.path,
        &image,
        &WriteOptions {
            exposure_ev: exposure,
            tone_map: ToneMap::Aces,
            ..WriteOptions::default()
        },
    )?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn request() -> PrtRequest<'static> {
        PrtRequest {
            mesh: Path::new("bunny.obj"),
            lmax: 4,
            samples: 64,
            mode: PrtMode::Shadowed,
            bounces: None,
            brdf: None,
            compress: None,
            albedo: None,
            light_units: None,
            seed: 0,
            output: Some(Path::new("bunny.shprt")),
            light: None,
            preview: None,
            preview_size: (64, 64),
            preview_exposure: None,
        }
    }

    fn message(r: &PrtRequest<'_>, spelling: Spelling) -> String {
        r.check(spelling).unwrap_err().message().to_string()
    }

    #[test]
    fn a_scene_takes_no_albedo_and_a_mesh_no_light_units() {
        let coloured = PrtRequest {
            mesh: Path::new("room.glb"),
            albedo: Some([0.5; 3]),
            ..request()
        };
        assert_eq!(
            message(&coloured, Spelling::CommandLine),
            "room.glb: a glTF scene's albedo is its materials' (base colour, vertex colours and \
             textures); --albedo sets one albedo for every vertex of a mesh (.obj, .ply, .off)"
        );
        let lit = PrtRequest {
            light_units: Some(LightUnits::AsWritten),
            ..request()
        };
        assert_eq!(
            message(&lit, Spelling::Python),
            "light_units reads a glTF scene's punctual lights; bunny.obj is a mesh, without lights"
        );
        let plan = PrtRequest {
            mesh: Path::new("room.gltf"),
            ..request()
        }
        .check(Spelling::Python)
        .unwrap();
        assert_eq!(plan.scene, Some(LightUnits::Blender));
        assert_eq!(request().check(Spelling::Python).unwrap().scene, None);
    }

    /// A hand-built glTF scene: a 4 m floor (y = 0, 8 x 8 cells) of albedo
    /// (0.2, 0.4, 0.6), a second 4 m sheet over it at y = 0.5 (`blocker`:
    /// its material), and a white point light of 683 x 10 cd at (0, 1, 0),
    /// 10 W/sr in Blender's units.
    fn floor_scene(blocker: shlight_mesh::Material) -> Scene {
        use shlight_mesh::{Instance, LightKind, Material, Primitive, PunctualLight, generate};
        let primitive = |mesh: Mesh, material| {
            Primitive::new(mesh, Some(material), format!("primitive {material}"))
        };
        let mut sheet = generate::plane(4.0, 1);
        sheet.positions.iter_mut().for_each(|p| p.y = 0.5);
        Scene {
            source: "floor.glb".into(),
            primitives: vec![primitive(generate::plane(4.0, 8), 0), primitive(sheet, 1)],
            instances: (0..2)
                .map(|primitive| Instance {
                    primitive,
                    transform: glam::Mat4::IDENTITY,
                })
                .collect(),
            materials: vec![
                Material {
                    base_color: glam::Vec4::new(0.2, 0.4, 0.6, 1.0),
                    ..Material::default()
                },
                blocker,
            ],
            lights: vec![PunctualLight {
                name: Some("Lamp".into()),
                kind: LightKind::Point,
                color: Vec3::ONE,
                intensity: 6830.0,
                range: None,
                position: Vec3::new(0.0, 1.0, 0.0),
                direction: Vec3::NEG_Z,
            }],
            ..Scene::default()
        }
    }

    #[test]
    fn a_scene_bakes_its_lights_through_its_cut_outs_into_a_static_term() {
        use crate::hooks::Collected;
        use shlight_core::sh::closed_form;
        use shlight_mesh::{AlphaMode, Material};
        let dir = std::env::temp_dir().join(format!("shlight-prt-scene-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let out = dir.join("floor.shprt");
        let plan = PrtRequest {
            mesh: Path::new("floor.glb"),
            lmax: 2,
            samples: 256,
            output: Some(&out),
            ..request()
        }
        .check(Spelling::Python)
        .unwrap();
        // The sheet cut out everywhere (alpha 0 under a mask): the light and
        // the sky reach the floor through it.
        let cut = Material {
            base_color: glam::Vec4::new(1.0, 1.0, 1.0, 0.0),
            alpha_mode: AlphaMode::Mask { cutoff: 0.5 },
            ..Material::default()
        };
        let hooks = Collected::new();
        let baked = prt_of_scene(&plan, &floor_scene(cut), &hooks).unwrap();
        assert!(
            hooks.notes().iter().any(|n| n.contains("1 punctual light,")
                && n.contains("cut-outs let rays through")),
            "{:?}",
            hooks.notes()
        );
        let file = ShprtFile::read(&out).unwrap();
        assert_eq!(file, baked.file);
        assert_eq!((file.channels, file.albedo), (3, None));
        let lit = file.static_light.as_ref().expect("a static term");
        assert_eq!(
            (lit.lights.as_ref().unwrap().units.as_str(), lit.emission),
            ("blender", false)
        );
        let bytes = std::fs::read(&out).unwrap();
        let nl = bytes.iter().position(|&b| b == b'\n').unwrap();
        let header: serde_json::Value = serde_json::from_slice(&bytes[..nl]).unwrap();
        assert_eq!(header["format_version"], 3);
        // Each floor vertex (the first 81) leaves rho / pi E, E = I h / d^3;
        // under constant radiance 1 it leaves rho more (every ray escapes).
        let rho = DVec3::new(0.2, 0.4, 0.6);
        let white = closed_form::constant(2, DVec3::ONE);
        let lit_up = file_exit_radiance(&file, white.as_slice(), None).unwrap();
        let floor = generate_floor();
        for (v, p) in floor.positions.iter().enumerate() {
            let d = f64::from(p.distance(Vec3::new(0.0, 1.0, 0.0)));
            let want = rho / std::f64::consts::PI * 10.0 / (d * d * d);
            let got = Vec3::from_array(lit.radiance[v]).as_dvec3();
            assert!(
                (got - want).abs().max_element() <= 1e-5 * want.max_element(),
                "{p}: {got} vs {want}"
            );
            let total = lit_up[v] - got;
            assert!((total - rho).abs().max_element() <= 1e-5, "{p}: {total}");
        }
        // The sheet opaque: no light reaches the floor.
        std::fs::remove_file(&out).unwrap();
        let dark = prt_of_scene(&plan, &floor_scene(Material::default()), &hooks).unwrap();
        let dark = dark.file.static_light.unwrap();
        assert!(
            dark.radiance[..floor.vertex_count()]
                .iter()
                .all(|r| *r == [0.0; 3])
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    fn generate_floor() -> Mesh {
        shlight_mesh::generate::plane(4.0, 8)
    }

    #[test]
    fn modes_parse_by_name() {
        for m in PrtMode::ALL {
            assert_eq!(m.name().parse::<PrtMode>(), Ok(m));
        }
        assert!("ambient".parse::<PrtMode>().is_err());
    }

    #[test]
    fn modes_take_their_bounces() {
        let plan = |mode, bounces| {
            PrtRequest {
                mode,
                bounces,
                brdf: (mode == PrtMode::Glossy).then_some("phong:8"),
                ..request()
            }
            .check(Spelling::Python)
            .unwrap()
            .bake
            .mode
        };
        assert_eq!(
            plan(PrtMode::Interreflected, None),
            Mode::Interreflected {
                bounces: DEFAULT_BOUNCES
            }
        );
        assert_eq!(plan(PrtMode::Glossy, Some(0)), Mode::Shadowed);
        assert_eq!(
            plan(PrtMode::Glossy, Some(2)),
            Mode::Interreflected { bounces: 2 }
        );
        assert_eq!(plan(PrtMode::Unshadowed, None), Mode::Unshadowed);
    }

    #[test]
    fn refusals_name_the_settings_of_each_front_end() {
        use Spelling::{CommandLine, Python};
        let bounced = PrtRequest {
            bounces: Some(3),
            ..request()
        };
        assert_eq!(
            message(&bounced, CommandLine),
            "--bounces needs --mode interreflected or --mode glossy"
        );
        assert_eq!(
            message(&bounced, Python),
            "bounces needs mode=\"interreflected\" or mode=\"glossy\""
        );
        let deep = PrtRequest {
            lmax: 33,
            ..request()
        };
        assert_eq!(
            message(&deep, Python),
            "lmax=33 is beyond 32 (diffuse transfer needs 2 to 6)"
        );
        let bare = PrtRequest {
            mode: PrtMode::Glossy,
            ..request()
        };
        assert!(message(&bare, CommandLine).starts_with("--mode glossy needs --brdf phong:S"));
        let squeezed = PrtRequest {
            compress: Some("cpca:2,2"),
            ..request()
        };
        assert_eq!(
            message(&squeezed, Python),
            "compress compresses the matrices of mode=\"glossy\""
        );
        let glb = PrtRequest {
            mode: PrtMode::Glossy,
            brdf: Some("phong:8"),
            output: Some(Path::new("x.glb")),
            ..request()
        };
        assert!(message(&glb, Python).contains("glTF cannot carry glossy transfer"));
        let half = PrtRequest {
            light: Some(Path::new("light.json")),
            ..request()
        };
        assert_eq!(
            message(&half, CommandLine),
            "--light needs --preview: the preview is the mesh shaded by the light"
        );
        let over = PrtRequest {
            output: Some(Path::new("bunny.obj.shprt")),
            ..request()
        };
        assert!(over.check(Python).is_ok());
        let unknown = PrtRequest {
            output: Some(Path::new("x.png")),
            ..request()
        };
        assert!(message(&unknown, Python).contains("unknown output format"));
    }
}
