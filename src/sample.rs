//! `shlight sample`: what a baked file shades with, at points a user
//! names: a volume's irradiance `E(p, n)` (by a lookup, relit first with
//! `--env`), or a PRT file's exit radiance per vertex under `--light`, by
//! shlight-pipeline's `sample` job.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use glam::DVec3;
use shlight_pipeline::{SampleRequest, Spelling, sample};
use shlight_volume::Lookup;

use crate::input::frame_of;
use crate::progress::{Reporter, Ui};
use crate::values::parse_vec3;

/// Arguments of `shlight sample`.
#[derive(Args, Debug)]
pub struct SampleArgs {
    /// A baked file: an irradiance volume (.shvol), PRT transfer (.shprt),
    /// or a lightmapped scene (.glb from `shlight lightmap`: the irradiance
    /// its lightmap gives at each point, read as the engine's shader does).
    pub file: PathBuf,
    /// Where to sample a volume or lightmap: JSON {"points": [[x, y, z], ...],
    /// "normals": [[x, y, z], ...]}, CSV rows x,y,z,nx,ny,nz (.csv), or a
    /// mesh or glTF scene (.obj, .ply, .off, .gltf, .glb): every vertex
    /// (a scene's flattened into world space) facing its normal.
    #[arg(long, value_name = "POINTS.json|csv|MESH")]
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
    let plan = SampleRequest {
        file: &args.file,
        output: &args.output,
        points: args.points.as_deref(),
        env: args.env.as_deref(),
        light: args.light.as_deref(),
        frame: frame_of(&args.up),
        lookup: args.lookup,
        view: args.view,
        eye: args.eye,
        albedo: args.albedo,
        lmax: args.lmax,
    }
    .check(Spelling::CommandLine)?;
    sample(&plan, &Reporter::new(ui))?;
    Ok(())
}
