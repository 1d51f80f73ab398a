//! `sample`: what a baked file shades with at points a user names — a
//! volume's irradiance `E(p, n)` read by a lookup (relit first under
//! another light if asked), or a PRT file's exit radiance per vertex under
//! a light, toward a view for a glossy file ([`SampleRequest`] →
//! [`SamplePlan`] → [`sample`]); and the two halves on files already in
//! memory ([`volume_irradiance`], [`transfer_radiance`]).

use std::path::{Path, PathBuf};

use glam::DVec3;
use serde_json::{Value, json};
use shlight_core::sh::{Frame, ShCoeffs};
use shlight_format::{SamplePoints, SampledValues, ShprtFile, ShvolFile};
use shlight_mesh::{LoadOptions, MeshFormat, Scene};
use shlight_prt::{Observer, file_shade};
use shlight_volume::{Lookup, LookupLmax, PreparedLookup, relight_file};

use super::lightmap_sample::lightmap_irradiance;
use crate::environment::Environment;
use crate::hooks::Hooks;
use crate::output_path::refuse_overwriting;
use crate::spelling::Spelling;
use crate::{PipelineError, Result};

/// A sampling as a front end asks for it, before [`SampleRequest::check`].
#[derive(Clone, Copy, Debug)]
pub struct SampleRequest<'a> {
    /// The baked file: a volume (`.shvol`) or PRT transfer (`.shprt`).
    pub file: &'a Path,
    /// Where the answer goes: JSON, or CSV rows `r,g,b` (`.csv`).
    pub output: &'a Path,
    /// Where to sample a volume: JSON or CSV points and normals, or a mesh
    /// or glTF scene file, whose every vertex is sampled facing its normal
    /// ([`mesh_points`]).
    pub points: Option<&'a Path>,
    /// A light to relight a relightable volume under first.
    pub env: Option<&'a Path>,
    /// The distant light of a `.shprt` file.
    pub light: Option<&'a Path>,
    /// The frame a map light's top row faces.
    pub frame: Frame,
    /// How a volume's light at a point is read off its probes.
    pub lookup: Lookup,
    /// A glossy file's view: one direction from every vertex to the eye.
    pub view: Option<DVec3>,
    /// A glossy file's view: the eye's position.
    pub eye: Option<DVec3>,
    /// A glossy file's diffuse base under its glossy layer.
    pub albedo: Option<[f32; 3]>,
    /// The highest degree shaded (default: each kind's own, see
    /// [`volume_irradiance`] and [`transfer_radiance`]).
    pub lmax: Option<usize>,
}

/// A checked [`SampleRequest`].
#[derive(Clone, Debug)]
pub struct SamplePlan {
    file: PathBuf,
    output: PathBuf,
    kind: Kind,
    frame: Frame,
    lmax: Option<usize>,
    spelling: Spelling,
}

#[derive(Clone, Debug)]
enum Kind {
    Volume {
        points: PathBuf,
        env: Option<PathBuf>,
        lookup: Lookup,
    },
    Transfer {
        light: PathBuf,
        shading: Shading,
    },
    Lightmap {
        points: PathBuf,
    },
}

/// How a PRT file is shaded besides its light: toward a view, over a
/// diffuse base (glossy files only), to an lmax.
#[derive(Clone, Copy, Debug, Default)]
pub struct Shading {
    /// The view of a glossy file.
    pub view: Option<Observer>,
    /// A glossy file's diffuse base.
    pub albedo: Option<[f32; 3]>,
    /// The highest degree shaded [default: the file's, at most
    /// `LIGHT_MAX_LMAX`].
    pub lmax: Option<usize>,
}

impl SampleRequest<'_> {
    /// The plan, after the checks every front end makes: the file is a
    /// `.shvol` or `.shprt`; a volume needs points and takes no PRT light,
    /// a PRT file needs a light and takes no points or relighting; a view
    /// is a direction or an eye, not both; nothing is written over an
    /// input.
    ///
    /// # Errors
    /// The first check that fails, naming the settings as `spelling` does.
    pub fn check(&self, spelling: Spelling) -> Result<SamplePlan> {
        let inputs: Vec<&Path> = [Some(self.file), self.points, self.env, self.light]
            .into_iter()
            .flatten()
            .collect();
        refuse_overwriting(self.output, &inputs)?;
        if self.view.is_some() && self.eye.is_some() {
            return Err(PipelineError::new(format!(
                "give {} or {}, not both",
                spelling.option("view"),
                spelling.option("eye")
            )));
        }
        let ext = self
            .file
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        let kind = match ext.as_deref() {
            Some("shvol") => self.volume_kind(spelling)?,
            Some("shprt") => self.transfer_kind(spelling)?,
            Some("glb") => self.lightmap_kind(spelling)?,
            _ => {
                return Err(PipelineError::new(format!(
                    "{}: sample reads irradiance volumes (.shvol), PRT transfer (.shprt) and lightmapped scenes (.glb)",
                    self.file.display()
                )));
            }
        };
        Ok(SamplePlan {
            file: self.file.to_path_buf(),
            output: self.output.to_path_buf(),
            kind,
            frame: self.frame,
            lmax: self.lmax,
            spelling,
        })
    }

    /// The points file, which sampling `what` (a volume, a lightmapped
    /// scene) needs: where to `verb` it.
    fn required_points(&self, what: &str, verb: &str, spelling: Spelling) -> Result<&Path> {
        self.points.ok_or_else(|| {
            PipelineError::new(format!(
                "sampling {what} needs {}: where to {verb} it",
                spelling.pick(
                    "--points POINTS.json (or .csv)",
                    "points (a .json or .csv file)"
                )
            ))
        })
    }

    fn volume_kind(&self, spelling: Spelling) -> Result<Kind> {
        let points = self.required_points("a volume", "sample", spelling)?;
        if self.light.is_some() {
            return Err(PipelineError::new(format!(
                "{} is the light of a .shprt file; a volume is relit by {}",
                spelling.option("light"),
                spelling.option("env")
            )));
        }
        Ok(Kind::Volume {
            points: points.to_path_buf(),
            env: self.env.map(Path::to_path_buf),
            lookup: self.lookup,
        })
    }

    fn lightmap_kind(&self, spelling: Spelling) -> Result<Kind> {
        let points = self.required_points("a lightmapped scene", "read", spelling)?;
        for (given, what) in [(self.env.is_some(), "env"), (self.light.is_some(), "light")] {
            if given {
                return Err(PipelineError::new(format!(
                    "{} does not apply to a lightmap, whose light is baked",
                    spelling.option(what)
                )));
            }
        }
        Ok(Kind::Lightmap {
            points: points.to_path_buf(),
        })
    }

    fn transfer_kind(&self, spelling: Spelling) -> Result<Kind> {
        let Some(light) = self.light else {
            return Err(PipelineError::new(format!(
                "sampling a .shprt file needs {} (an equirect map or a radiance coefficient file)",
                spelling.pick("--light LIGHT", "light")
            )));
        };
        for (given, what) in [
            (self.points.is_some(), "points"),
            (self.env.is_some(), "env"),
        ] {
            if given {
                return Err(PipelineError::new(format!(
                    "{} samples a volume; a .shprt file gives every vertex's exit radiance under {}",
                    spelling.option(what),
                    spelling.option("light")
                )));
            }
        }
        let view = match (self.view, self.eye) {
            (Some(d), _) => Some(Observer::Direction(d)),
            (None, Some(e)) => Some(Observer::Eye(e)),
            (None, None) => None,
        };
        Ok(Kind::Transfer {
            light: light.to_path_buf(),
            shading: Shading {
                view,
                albedo: self.albedo,
                lmax: self.lmax,
            },
        })
    }
}

/// `shlight sample`: reads the baked file and what it is sampled with,
/// computes the values ([`volume_irradiance`] or [`transfer_radiance`])
/// and writes them to the plan's output (JSON with the file's provenance,
/// or CSV), atomically.
///
/// # Errors
/// A file that cannot be read; the checks of [`volume_irradiance`] and
/// [`transfer_radiance`]; the output cannot be written.
pub fn sample(plan: &SamplePlan, hooks: &dyn Hooks) -> Result<SampledValues> {
    sample_with(plan, None, hooks)
}

/// [`sample`] of a volume at points read already (a glTF scene's
/// vertices, [`scene_points`]), in place of the plan's points file, whose
/// path names them in the answer; a `.shprt` plan as [`sample`].
///
/// # Errors
/// As [`sample`].
pub fn sample_at(
    plan: &SamplePlan,
    points: &SamplePoints,
    hooks: &dyn Hooks,
) -> Result<SampledValues> {
    sample_with(plan, Some(points), hooks)
}

fn sample_with(
    plan: &SamplePlan,
    given: Option<&SamplePoints>,
    hooks: &dyn Hooks,
) -> Result<SampledValues> {
    let values = match &plan.kind {
        Kind::Volume {
            points,
            env,
            lookup,
        } => sample_volume(plan, (points, given), env.as_deref(), *lookup, hooks)?,
        Kind::Transfer { light, shading } => sample_transfer(plan, light, shading, hooks)?,
        Kind::Lightmap { points } => sample_lightmap(plan, (points, given))?,
    };
    values.write(&plan.output)?;
    Ok(values)
}

fn sample_volume(
    plan: &SamplePlan,
    (points_path, given): (&Path, Option<&SamplePoints>),
    env: Option<&Path>,
    lookup: Lookup,
    hooks: &dyn Hooks,
) -> Result<SampledValues> {
    let name = plan.file.display().to_string();
    let mut file = ShvolFile::read(&plan.file)?;
    // The lookup and lmax are checked before the points and light are read.
    let settled = volume_lookup(&file, Some(&name), lookup, plan.lmax, plan.spelling)?;
    let (points, at) = points_at(points_path, given)?;
    if let Some(env) = env {
        let light = light_of(env, plan.frame, shlight_baked::MAX_LMAX, hooks)?;
        relight_volume(&mut file, Some(&name), &light, plan.spelling)?;
    }
    let values = volume_irradiance(&file, Some(&name), lookup, &settled, &points, hooks);
    let LookupLmax { lmax, note } = settled;
    Ok(SampledValues {
        quantity: "irradiance",
        values,
        about: json!({
            "file": name,
            "points": points_path.display().to_string(),
            "at": at,
            "lookup": lookup.effective(&file.view()).name(),
            "visibility": file.visibility.is_some(),
            "relocated": file.relocated().len(),
            "lmax": lmax,
            "notes": note.into_iter().collect::<Vec<_>>(),
            "light": env.map(|p| p.display().to_string()),
            "frame": file.frame,
            "provenance": {
                "scene": file.scene,
                "scene_hash": format!("fnv1a64:{:016x}", file.scene_hash),
                "environment": file.environment,
                "generator": file.generator,
                "samples": file.rays_per_probe,
                "bounces": file.bounces,
                "seed": file.seed,
                "relightable": file.relightable(),
            },
        }),
    })
}

/// The points to sample at, with what they are: those given (a scene or
/// points Python loaded), else read from `path`, a mesh's vertices or a
/// points file.
fn points_at(path: &Path, given: Option<&SamplePoints>) -> Result<(SamplePoints, &'static str)> {
    let mesh = MeshFormat::from_path(path).is_some();
    let at = if mesh { "vertices" } else { "points" };
    let points = match given {
        Some(p) => p.clone(),
        None if mesh => mesh_points(path)?,
        None => SamplePoints::read(path)?,
    };
    Ok((points, at))
}

fn sample_lightmap(
    plan: &SamplePlan,
    (points_path, given): (&Path, Option<&SamplePoints>),
) -> Result<SampledValues> {
    let name = plan.file.display().to_string();
    // One read of the file for its pages and its scene.
    let bytes = std::fs::read(&plan.file).map_err(|source| shlight_mesh::MeshError::Io {
        path: plan.file.clone(),
        source,
    })?;
    let pages = shlight_mesh::lightmap_pages_from_bytes(&plan.file, &bytes)?;
    let scene = shlight_mesh::load_scene_bytes(&plan.file, &bytes, &LoadOptions::default())?;
    let (points, at) = points_at(points_path, given)?;
    let values = lightmap_irradiance(&name, &scene, &pages, &points)?;
    let root = &pages.root;
    Ok(SampledValues {
        quantity: "irradiance",
        values,
        about: json!({
            "file": name,
            "points": points_path.display().to_string(),
            "at": at,
            "lightmap": {
                "basis": root["basis"],
                "engine": root["engine"],
                "reconstruction": root["reconstruction"],
                "units": root["units"],
                "size": root["size"],
                "read": "bilinear, as the engine's shader reconstructs it, over its units",
            },
            "provenance": {
                "generator": root["generator"],
                "environment": root["environment"],
                "samples": root["samples"],
                "bounces": root["bounces"],
                "seed": root["seed"],
            },
        }),
    })
}

fn sample_transfer(
    plan: &SamplePlan,
    light_path: &Path,
    shading: &Shading,
    hooks: &dyn Hooks,
) -> Result<SampledValues> {
    let file = ShprtFile::read(&plan.file)?;
    let name = plan.file.display().to_string();
    let light = light_of(light_path, plan.frame, shlight_baked::LIGHT_MAX_LMAX, hooks)?;
    let (values, lmax) =
        transfer_radiance(&file, Some(&name), &light, shading, plan.spelling, hooks)?;
    let glossy = file.glossy.as_ref();
    let (view, eye) = match shading.view {
        Some(Observer::Direction(d)) => (Some(d.normalize().to_array()), None),
        Some(Observer::Eye(e)) => (None, Some(e.to_array())),
        None => (None, None),
    };
    Ok(SampledValues {
        quantity: "radiance",
        values: values.into_iter().map(|v| v.to_array()).collect(),
        about: json!({
            "file": name,
            "lmax": lmax,
            "light": light_path.display().to_string(),
            "view": glossy.and(view),
            "eye": glossy.and(eye),
            "brdf": glossy.map(|g| g.brdf.clone()),
            "albedo": shading.albedo,
            "provenance": {
                "mode": file.mode,
                "transport": glossy.map(|g| g.transport.clone()),
                "samples": file.rays_per_vertex,
                "bounces": file.bounces,
                "seed": file.seed,
                "albedo": file.albedo.map_or(Value::Null, |a| json!(a)),
                "vertex_count": file.vertex_count,
            },
        }),
    })
}

/// The points a volume is sampled at from a mesh or scene file: every
/// vertex, facing its normal, in the vertex order of a `.shprt` file baked
/// from it (docs/shprt.md). A glTF file is read as a scene and flattened
/// ([`scene_points`]); `.obj`, `.ply` and `.off` as a mesh.
///
/// # Errors
/// A file the loader refuses.
pub fn mesh_points(path: &Path) -> Result<SamplePoints> {
    if MeshFormat::from_path(path) == Some(MeshFormat::Gltf) {
        let scene = shlight_mesh::load_scene(path, &LoadOptions::default())?;
        return scene_points(&scene);
    }
    let mesh = shlight_mesh::load(path)?;
    vertex_points(&mesh, &path.display().to_string())
}

/// Every vertex of a glTF scene flattened into world space
/// ([`Scene::flatten`]: each instance's vertices by its transform, normals
/// by its inverse transpose), facing its normal.
///
/// # Errors
/// A transform or mesh the flattening refuses.
pub fn scene_points(scene: &Scene) -> Result<SamplePoints> {
    let surfaces = scene.flatten(glam::Vec3::ONE)?;
    vertex_points(&surfaces.mesh, &scene.source.display().to_string())
}

/// A mesh's vertices and normals as sample points, named `name`.
fn vertex_points(mesh: &shlight_mesh::Mesh, name: &str) -> Result<SamplePoints> {
    let points = mesh.positions.iter().map(|p| p.to_array()).collect();
    let normals = mesh.normals.iter().map(|n| n.to_array()).collect();
    Ok(SamplePoints::new(points, normals, name)?)
}

/// The radiance coefficients of the light at `path` (a map projected, or a
/// radiance coefficient file) to `lmax` at most, its warnings to `hooks`.
fn light_of(path: &Path, frame: Frame, lmax: usize, hooks: &dyn Hooks) -> Result<ShCoeffs<DVec3>> {
    let env = Environment::load(path, frame, lmax)?;
    env.warnings.iter().for_each(|w| hooks.warn(w));
    Ok(env.radiance)
}

/// A volume's probes relit under `light` (radiance coefficients in the
/// volume's frame; shlight-volume's [`relight_file`]), refused for a static
/// volume with the setting that bakes one named as `spelling` does, after
/// `name` where given.
///
/// # Errors
/// A static volume (no transfer matrices).
pub fn relight_volume(
    file: &mut ShvolFile,
    name: Option<&str>,
    light: &ShCoeffs<DVec3>,
    spelling: Spelling,
) -> Result<()> {
    let named = |m: String| match name {
        Some(name) => format!("{name}: {m}"),
        None => m,
    };
    if !file.relightable() {
        return Err(PipelineError::new(named(format!(
            "the volume of {} was baked {} (no transfer matrices), so it cannot be relit",
            file.scene,
            spelling.option("static")
        ))));
    }
    relight_file(file, light).map_err(|e| PipelineError::new(named(e.to_string())))
}

/// The lmax `lookup` reads `file` to when asked for `lmax`
/// ([`Lookup::lmax_for`]), refused with the lookup and lmax
/// named as `spelling` does, after `name` where given.
///
/// # Errors
/// An lmax the lookup cannot shade.
pub fn volume_lookup(
    file: &ShvolFile,
    name: Option<&str>,
    lookup: Lookup,
    lmax: Option<usize>,
    spelling: Spelling,
) -> Result<LookupLmax> {
    lookup.lmax_for(&file.view(), lmax).map_err(|e| {
        let lmax = lmax
            .map(|l| format!("{}: ", spelling.option_number("lmax", l, l)))
            .unwrap_or_default();
        let lookup = spelling.option_number("lookup", lookup, lookup);
        let name = name.map(|n| format!("{n}: ")).unwrap_or_default();
        PipelineError::new(format!("{name}{lookup}: {lmax}{e}"))
    })
}

/// A volume's irradiance `E(p, n)` at `points` facing their normals, read
/// by `lookup` to the lmax [`volume_lookup`] settled (its note, when
/// degrees are left out, to `hooks`, after `name` where given), on every
/// core.
#[must_use]
pub fn volume_irradiance(
    file: &ShvolFile,
    name: Option<&str>,
    lookup: Lookup,
    settled: &LookupLmax,
    points: &SamplePoints,
    hooks: &dyn Hooks,
) -> Vec<[f64; 3]> {
    if let Some(note) = &settled.note {
        hooks.note(&match name {
            Some(name) => format!("{name}: {note}"),
            None => note.clone(),
        });
    }
    let prepared = PreparedLookup::new(&file.view(), lookup, settled.lmax);
    prepared.irradiance_all(&points.points, &points.normals)
}

/// A PRT file's exit radiance per vertex under the distant radiance
/// `light` (shlight-prt's `file_shade`): a diffuse file's `T . L`, a
/// glossy file's glossy layer toward its view, over its diffuse base.
/// The degrees shaded: `shading.lmax`, at most the file's and
/// `LIGHT_MAX_LMAX` (returned beside the values), and at most the
/// light's.
///
/// # Errors
/// A glossy file without a view or with a zero view direction; a diffuse
/// file given a diffuse base; a file whose arrays do not fit its counts;
/// each naming the settings as `spelling` does, after `name` where given.
pub fn transfer_radiance(
    file: &ShprtFile,
    name: Option<&str>,
    light: &ShCoeffs<DVec3>,
    shading: &Shading,
    spelling: Spelling,
    hooks: &dyn Hooks,
) -> Result<(Vec<DVec3>, usize)> {
    let named = |m: String| {
        PipelineError::new(match name {
            Some(name) => format!("{name}: {m}"),
            None => m,
        })
    };
    if let Some(glossy) = &file.glossy {
        match shading.view {
            None => {
                return Err(named(format!(
                    "glossy transfer ({}) is seen from somewhere: give {} (from the vertices towards the eye) or {}",
                    glossy.brdf,
                    spelling.option_number("view", "X,Y,Z", "(x, y, z)"),
                    spelling.option_number("eye", "X,Y,Z", "(x, y, z)"),
                )));
            }
            Some(Observer::Direction(d)) if d.length_squared() == 0.0 => {
                return Err(PipelineError::new(format!(
                    "{} has zero length: give the direction from the vertices towards the eye",
                    spelling.option_number("view", "0,0,0", "(0, 0, 0)")
                )));
            }
            _ => {}
        }
    } else if shading.albedo.is_some() {
        return Err(named(format!(
            "{} is the diffuse base under a glossy file's glossy layer; a diffuse file's albedo is in its transfer",
            spelling.option("albedo")
        )));
    } else if shading.view.is_some() {
        hooks.note(
            &named(format!(
                "diffuse transfer looks the same from everywhere; {} and {} are ignored",
                spelling.option("view"),
                spelling.option("eye")
            ))
            .to_string(),
        );
    }
    let lmax = shading
        .lmax
        .unwrap_or(file.lmax)
        .min(file.lmax)
        .min(shlight_baked::LIGHT_MAX_LMAX);
    let l = light.resized(lmax.min(light.lmax()));
    let view = file.glossy.as_ref().and(shading.view);
    let base = shading
        .albedo
        .map_or(DVec3::ZERO, |a| DVec3::from(a.map(f64::from)));
    let values = file_shade(file, l.as_slice(), view, base).map_err(named)?;
    Ok((values, lmax))
}
