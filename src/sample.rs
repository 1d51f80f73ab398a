//! `shlight sample`: what a baked file shades with, at points a user
//! names: a volume's irradiance `E(p, n)` (by a lookup, relit first with
//! `--env`), or a PRT file's exit radiance per vertex under `--light`.

use std::path::{Path, PathBuf};

use anyhow::{Result, bail};
use clap::Args;
use glam::DVec3;
use serde_json::{Value, json};
use shlight_format::{SamplePoints, Samples, ShprtFile, ShvolFile};
use shlight_pipeline::Environment;
use shlight_prt::{View, file_shade};
use shlight_volume::{Lookup, LookupLmax, PreparedLookup, lookup_lmax};

use crate::input::frame_of;
use crate::output_path::refuse_overwriting;
use crate::progress::Ui;
use crate::values::parse_vec3;

/// Arguments of `shlight sample`.
#[derive(Args, Debug)]
pub struct SampleArgs {
    /// A baked file: an irradiance volume (.shvol) or PRT transfer (.shprt).
    pub file: PathBuf,
    /// Where to sample a volume: JSON {"points": [[x, y, z], ...],
    /// "normals": [[x, y, z], ...]}, or CSV rows x,y,z,nx,ny,nz (.csv).
    #[arg(long, value_name = "POINTS.json|csv")]
    pub points: Option<PathBuf>,
    /// The answer: JSON (the values, the lookup, the file's provenance), or
    /// CSV rows r,g,b (.csv); written atomically.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Relight a relightable volume under this light first (an equirect
    /// map or a radiance coefficient file), as render-mesh --volume does.
    #[arg(long)]
    pub env: Option<PathBuf>,
    /// The distant light of a .shprt file (an equirect map or a radiance
    /// coefficient file).
    #[arg(long)]
    pub light: Option<PathBuf>,
    /// Which world axis a map's top row faces.
    #[arg(long, default_value = "y", value_parser = ["y", "z"])]
    pub up: String,
    /// How a volume's light at a point is read off its probes: shlight (the
    /// best shlight has: trilinear weights times each probe's visibility
    /// of the point, from the file's distance maps; trilinear for a file
    /// without them); trilinear (the valid probes of
    /// the eight around the point, weights renormalised); bevy (what Bevy
    /// shows from the --format bevy export: half-float ambient cubes,
    /// filtered and blended as its shader does; 0 outside the volume's
    /// box); threejs (what three.js's LightProbeGrid shows: the point moved
    /// half a probe spacing along the normal, trilinear L2 SH, three.js's
    /// constants; 0 where that point leaves the box). The engines' lookups
    /// read invalid probes dilated from their valid neighbours.
    #[arg(long, default_value = "shlight")]
    pub lookup: Lookup,
    /// The view of a glossy .shprt file: one direction X,Y,Z for every
    /// vertex, from the vertex towards the eye (an orthographic camera
    /// looking along -X,-Y,-Z); ignored for a diffuse file.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true, conflicts_with = "eye")]
    pub view: Option<DVec3>,
    /// The view of a glossy .shprt file as a camera position X,Y,Z: each
    /// vertex seen from there; ignored for a diffuse file.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub eye: Option<DVec3>,
    /// A glossy .shprt file's diffuse base: its albedo R,G,B (linear; one
    /// value for grey, each in [0, 1]) under the glossy layer, as
    /// render-mesh --prt --albedo shades it [default: none, the glossy
    /// layer alone].
    #[arg(long, value_parser = crate::values::parse_albedo)]
    pub albedo: Option<[f32; 3]>,
    /// Highest degree shaded [default: a volume's lmax, at most 4 (what the
    /// GPU shades) for shlight and trilinear, all of it for bevy, at most 2
    /// for threejs; a PRT file's lmax, at most 8].
    #[arg(long)]
    pub lmax: Option<usize>,
}

/// Runs `shlight sample`.
pub fn run(args: &SampleArgs, ui: &Ui) -> Result<()> {
    let mut inputs = vec![args.file.clone()];
    inputs.extend(args.points.clone());
    inputs.extend(args.env.clone());
    inputs.extend(args.light.clone());
    refuse_overwriting(&args.output, &inputs)?;
    let ext = args
        .file
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let samples = match ext.as_deref() {
        Some("shvol") => volume(args, ui)?,
        Some("shprt") => transfer(args, ui)?,
        _ => bail!(
            "{}: sample reads irradiance volumes (.shvol) and PRT transfer (.shprt)",
            args.file.display()
        ),
    };
    samples.write(&args.output)?;
    Ok(())
}

/// The light of `path` as radiance coefficients to `lmax` at most.
fn light(path: &Path, up: &str, lmax: usize) -> Result<Environment> {
    Ok(Environment::load(path, frame_of(up), lmax)?)
}

/// A volume's irradiance at the points.
fn volume(args: &SampleArgs, ui: &Ui) -> Result<Samples> {
    let Some(points_path) = &args.points else {
        bail!("sampling a volume needs --points POINTS.json (or .csv): where to sample it");
    };
    if args.light.is_some() {
        bail!("--light is the light of a .shprt file; a volume is relit by --env");
    }
    let mut file = ShvolFile::read(&args.file)?;
    let LookupLmax { lmax, note } =
        lookup_lmax(&file.view(), args.lookup, args.lmax).map_err(|e| {
            let lmax = args
                .lmax
                .map(|l| format!("--lmax {l}: "))
                .unwrap_or_default();
            anyhow::anyhow!(
                "{}: --lookup {}: {lmax}{e}",
                args.file.display(),
                args.lookup
            )
        })?;
    let points = SamplePoints::read(points_path)?;
    if let Some(env) = &args.env {
        let env = light(env, &args.up, shlight_baked::MAX_LMAX)?;
        shlight_volume::relight_file(&mut file, &env.radiance)
            .map_err(|e| anyhow::anyhow!("{}: {e}", args.file.display()))?;
    }
    if let Some(note) = &note {
        ui.note(format!("{}: {note}", args.file.display()));
    }
    let lookup = PreparedLookup::new(&file.view(), args.lookup, lmax);
    let values = lookup.irradiance_all(&points.points, &points.normals);
    Ok(Samples {
        quantity: "irradiance",
        values,
        about: json!({
            "file": args.file.display().to_string(),
            "points": points_path.display().to_string(),
            "lookup": args.lookup.effective(&file.view()).name(),
            "visibility": file.visibility.is_some(),
            "relocated": file.relocated().len(),
            "lmax": lmax,
            "notes": note.into_iter().collect::<Vec<_>>(),
            "light": args.env.as_ref().map(|p| p.display().to_string()),
            "frame": file.frame,
            "provenance": {
                "scene": file.scene,
                "scene_hash": format!("fnv1a64:{:016x}", file.scene_hash),
                "environment": file.environment,
                "generator": file.generator,
                "samples": file.samples,
                "bounces": file.bounces,
                "seed": file.seed,
                "relightable": file.relightable(),
            },
        }),
    })
}

/// A PRT file's exit radiance per vertex (toward `--view` or `--eye` for
/// a glossy file).
fn transfer(args: &SampleArgs, ui: &Ui) -> Result<Samples> {
    let Some(light_path) = &args.light else {
        bail!(
            "sampling a .shprt file needs --light LIGHT (an equirect map or a radiance coefficient file)"
        );
    };
    for (given, what) in [
        (args.points.is_some(), "--points"),
        (args.env.is_some(), "--env"),
    ] {
        if given {
            bail!(
                "{what} samples a volume; a .shprt file gives every vertex's exit radiance under --light"
            );
        }
    }
    let file = ShprtFile::read(&args.file)?;
    let env = light(light_path, &args.up, shlight_baked::LIGHT_MAX_LMAX)?;
    let lmax = args
        .lmax
        .unwrap_or(file.lmax)
        .min(file.lmax)
        .min(shlight_baked::LIGHT_MAX_LMAX);
    let l = env.radiance.resized(lmax.min(env.radiance.lmax()));
    let view = match (args.view, args.eye) {
        (Some(d), _) => Some(View::Direction(d)),
        (None, Some(e)) => Some(View::Eye(e)),
        (None, None) => None,
    };
    if let Some(glossy) = &file.glossy {
        if view.is_none() {
            bail!(
                "{}: glossy transfer ({}) is seen from somewhere: give --view X,Y,Z (from the \
                 vertices towards the eye) or --eye X,Y,Z",
                args.file.display(),
                glossy.brdf
            );
        }
        if args.view.is_some_and(|d| d.length_squared() == 0.0) {
            bail!(
                "--view 0,0,0 has zero length: give the direction from the vertices towards the eye"
            );
        }
    } else if args.albedo.is_some() {
        bail!(
            "{}: --albedo is the diffuse base under a glossy file's glossy layer; a diffuse \
             file's albedo is in its transfer",
            args.file.display()
        );
    } else if view.is_some() {
        ui.note(format!(
            "{}: diffuse transfer looks the same from everywhere; --view and --eye are ignored",
            args.file.display()
        ));
    }
    let values = file_shade(
        &file,
        l.as_slice(),
        view,
        args.albedo
            .map_or(DVec3::ZERO, |a| DVec3::from(a.map(f64::from))),
    )
    .map_err(|e| anyhow::anyhow!("{}: {e}", args.file.display()))?
    .into_iter()
    .map(|v| v.to_array())
    .collect();
    Ok(Samples {
        quantity: "radiance",
        values,
        about: json!({
            "file": args.file.display().to_string(),
            "lmax": lmax,
            "light": light_path.display().to_string(),
            "view": file.glossy.as_ref().and(args.view).map(|d| d.normalize().to_array()),
            "eye": file.glossy.as_ref().and(args.eye).map(|e| e.to_array()),
            "brdf": file.glossy.as_ref().map(|g| g.brdf.clone()),
            "albedo": args.albedo,
            "provenance": {
                "mode": file.mode,
                "transport": file.glossy.as_ref().map(|g| g.transport.clone()),
                "samples": file.samples,
                "bounces": file.bounces,
                "seed": file.seed,
                "albedo": file.albedo.map_or(Value::Null, |a| json!(a)),
                "vertex_count": file.vertex_count,
            },
        }),
    })
}
