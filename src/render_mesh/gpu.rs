//! The GPU half of `shlight render-mesh` (the `gpu` feature): the camera,
//! the headless context, the frame and its file.

use anyhow::{Context, Result, anyhow, bail};
use glam::{DMat3, Vec3};
use shlight_core::encoding::Encoding;
use shlight_core::sh::ShRotation;
use shlight_gpu::{Background, Camera, GpuContext, HEADLESS_FORMAT, Mode, Shading, render_frame};
use shlight_io::{Format, Image, WriteOptions, write_image};

use crate::input::frame_of;
use crate::progress::Ui;
use shlight_baked::LIGHT_MAX_LMAX;
use shlight_pipeline::Environment;

use super::{BackgroundArg, RenderMeshArgs, RenderMode};

/// The camera for a mesh of `bounds`: `--camera`/`--target`, or framed
/// (`Camera::aimed`).
pub fn camera_for(
    bounds: (Vec3, Vec3),
    eye: Option<Vec3>,
    target: Option<Vec3>,
    fov_degrees: f32,
    aspect: f32,
) -> Result<Camera> {
    if !(fov_degrees > 1.0 && fov_degrees < 179.0) {
        bail!("--fov {fov_degrees}: expected degrees between 1 and 179");
    }
    Camera::aimed(bounds, eye, target, fov_degrees.to_radians(), aspect)
        .ok_or_else(|| anyhow!("--camera and --target are the same point"))
}

/// Renders the checked `args` (without `--volume`: `volume.rs`) to
/// `format` on the GPU.
pub fn render(args: &RenderMeshArgs, format: Option<Format>, ui: &Ui) -> Result<()> {
    shlight_viewer::check_lmax(args.lmax)?;
    let mode = match (args.mode, &args.prt) {
        (Some(RenderMode::Prt), None) => bail!("--mode prt needs --prt FILE.shprt"),
        (Some(mode), _) => mode,
        (None, Some(_)) => RenderMode::Prt,
        (None, None) => RenderMode::Sh,
    };
    let mut inputs = vec![args.mesh.clone(), args.env.clone()];
    inputs.extend(args.prt.clone());
    crate::output_path::refuse_overwriting(&args.output, &inputs)?;
    let bar = ui.spinner("reading the mesh");
    let mesh = shlight_mesh::load(&args.mesh)?;
    let transfer = match &args.prt {
        Some(path) => Some(crate::prt_input::load_transfer(path, &mesh, &args.mesh)?),
        None => None,
    };
    bar.set_message("reading the environment");
    let mut env = Environment::load(&args.env, frame_of(&args.up), LIGHT_MAX_LMAX)?;
    env.warnings.iter().for_each(|w| ui.warn(w));
    // Encoded before the light is turned: the renderer turns the normal back.
    let snippet = match args.encoding {
        Encoding::Sh => None,
        encoding => {
            if mode != RenderMode::Sh {
                bail!(
                    "--encoding {encoding} shades the mesh by the light's irradiance: it does not take --mode {}",
                    mode.name()
                );
            }
            bar.set_message(format!("encoding the light as {encoding}"));
            let lmax = args.lmax.unwrap_or(2);
            let (encoded, snippet) = env.encoded_light(encoding, lmax)?;
            if matches!(encoding, Encoding::DominantSh | Encoding::SloanSh) {
                ui.note(format!(
                    "{encoding}: {} light(s) kept apart from the SH",
                    encoded.lights().len()
                ));
            }
            Some(snippet)
        }
    };
    let rotation = rotation(args)?;
    env.radiance = ShRotation::from_mat3(env.radiance.lmax(), rotation).apply(&env.radiance);
    if args.background == BackgroundArg::Map && env.map.is_none() {
        bail!(
            "--background map needs an environment map; {} holds coefficients (use --background sh)",
            env.path.display()
        );
    }
    bar.set_message("opening the GPU");
    let ctx = GpuContext::headless()?;
    let mut renderer =
        shlight_viewer::renderer(&ctx, HEADLESS_FORMAT, &mesh, transfer.as_ref(), &env)?;
    renderer.set_environment_rotation(rotation);
    if let Some(snippet) = &snippet {
        renderer.set_encoding(&ctx, snippet)?;
    }
    let lmax = shlight_viewer::shading_lmax(
        args.lmax,
        transfer.as_ref().filter(|_| mode == RenderMode::Prt),
    );
    let (w, h) = args.size;
    let camera = camera_for(
        mesh.bounds(),
        args.camera,
        args.target,
        args.fov,
        w as f32 / h as f32,
    )?;
    let shading = Shading {
        mode: match mode {
            RenderMode::Sh if snippet.is_some() => Mode::Encoded,
            RenderMode::Sh => Mode::Sh,
            RenderMode::Prt => Mode::Prt,
            RenderMode::Normals => Mode::Normals,
        },
        lmax,
        window: args.window,
        exposure_ev: 0.0,
        tone_map: None,
        albedo: match (
            args.albedo,
            transfer.as_ref().and_then(|t| t.glossy.as_ref()),
        ) {
            (Some(a), _) => a.to_array(),
            // A glossy file's layer alone.
            (None, Some(_)) => [0.0; 3],
            (None, None) => [0.8; 3],
        },
        background: match args.background {
            BackgroundArg::None => Background::None,
            BackgroundArg::Map => Background::Map,
            BackgroundArg::Sh => Background::Sh,
        },
    };
    if env.radiance.lmax() < lmax {
        ui.note(format!(
            "{} holds lmax {}; shading to lmax {}",
            env.path.display(),
            env.radiance.lmax(),
            env.radiance.lmax()
        ));
    }
    bar.set_message(format!("rendering {w}x{h} on {}", ctx.adapter_name()));
    let frame = render_frame(&ctx, &renderer, &camera, &shading, w, h)?;
    bar.finish_and_clear();
    write_frame(args, format, frame.rgb(), (w, h))
}

/// Writes a rendered frame to `--output`: linear for EXR, with
/// `--exposure` and `--tone-map` for PNG.
pub fn write_frame(
    args: &RenderMeshArgs,
    format: Option<Format>,
    rgb: Vec<[f32; 3]>,
    (w, h): (usize, usize),
) -> Result<()> {
    let out = args.output.display().to_string();
    let image = Image::new(w, h, rgb).map_err(|e| anyhow!("{e}"))?;
    let options = match format {
        Some(Format::Png) => WriteOptions {
            exposure_ev: args.exposure,
            tone_map: args.tone_map,
            ..WriteOptions::default()
        },
        _ => WriteOptions::default(),
    };
    write_image(&args.output, &image, &options).with_context(|| format!("{out}: writing"))
}

/// `--rotate` as a matrix (identity without it): a light from `a` then
/// comes from `R a`.
pub fn rotation(args: &RenderMeshArgs) -> Result<DMat3> {
    Ok(match &args.rotate {
        Some(spec) => shlight_pipeline::parse_rotation(
            spec,
            frame_of(&args.up),
            shlight_pipeline::Spelling::CommandLine,
        )?,
        None => DMat3::IDENTITY,
    })
}
