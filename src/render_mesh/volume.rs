//! `render-mesh --volume`: the scene (MESH) and the object lit per fragment
//! by the irradiance volume, over the environment's background.

use anyhow::{Result, bail};
use shlight_core::sh::ShRotation;
use shlight_gpu::{Background, GpuContext, HEADLESS_FORMAT, Mode, Offscreen, Renderer, Shading};
use shlight_io::Format;

use crate::input::frame_of;
use crate::progress::Ui;
use shlight_pipeline::Environment;
use shlight_viewer::VolumeLight;

use super::gpu::{camera_for, rotation, write_frame};
use super::{BackgroundArg, RenderMeshArgs, RenderMode};

/// Renders the checked `args` (with `--volume`) to `format`.
pub fn render(args: &RenderMeshArgs, format: Option<Format>, ui: &Ui) -> Result<()> {
    if args.prt.is_some() || args.mode.is_some_and(|m| m != RenderMode::Sh) {
        bail!("--volume shades by the volume's SH: it takes neither --prt nor --mode prt/normals");
    }
    if args.encoding != shlight_core::encoding::Encoding::Sh {
        bail!(
            "--volume shades by the volume's SH probes: it does not take --encoding {}",
            args.encoding
        );
    }
    let mut inputs = vec![args.mesh.clone(), args.env.clone()];
    inputs.extend(args.volume.volume.clone());
    inputs.extend(args.volume.object.clone());
    crate::output_path::refuse_overwriting(&args.output, &inputs)?;
    let bar = ui.spinner("reading the scene");
    let mesh = shlight_mesh::load(&args.mesh)?;
    let mut volume = crate::volume_shading::load_volume(&args.volume, &mesh, &args.mesh, ui)?;
    bar.set_message("reading the environment");
    let mut env = Environment::load(&args.env, frame_of(&args.up), shlight_baked::LIGHT_MAX_LMAX)?;
    env.warnings.iter().for_each(|w| ui.warn(w));
    if args.background == BackgroundArg::Map && env.map.is_none() {
        bail!(
            "--background map needs an environment map; {} holds coefficients (use --background sh)",
            env.path.display()
        );
    }
    let r = rotation(args)?;
    env.radiance = ShRotation::from_mat3(env.radiance.lmax(), r).apply(&env.radiance);
    match volume.light() {
        VolumeLight::Stored if args.rotate.is_some() => bail!(
            "{}: baked --static (no transfer matrices), so --rotate cannot relight it; bake it without --static",
            volume.path.display()
        ),
        VolumeLight::Stored => ui.note(format!(
            "{}: static volume, its stored light is shown (--env is the background only)",
            volume.path.display()
        )),
        VolumeLight::Relit => {
            if env.radiance.lmax() < volume.file.lmax {
                ui.note(format!(
                    "{} holds lmax {}; the volume's lmax {} is relit with the higher bands zero",
                    env.path.display(),
                    env.radiance.lmax(),
                    volume.file.lmax
                ));
            }
            volume.relight(&env.radiance);
        }
    }
    bar.set_message("opening the GPU");
    let ctx = GpuContext::headless()?;
    let mut background = Renderer::new(&ctx, HEADLESS_FORMAT);
    background.set_light(&ctx, &env.radiance);
    if let Some(map) = &env.map {
        background.set_environment(
            &ctx,
            map.width(),
            map.height(),
            map.pixels(),
            env.orientation,
        );
    }
    background.set_environment_rotation(r);
    let albedo = args.albedo.unwrap_or(glam::Vec3::splat(0.8)).to_array();
    let shaded = volume.renderer(&ctx, HEADLESS_FORMAT, Some(&mesh), albedo)?;
    let lmax = args.lmax.unwrap_or(shaded.lmax());
    let (w, h) = args.size;
    let camera = camera_for(
        mesh.bounds(),
        args.camera,
        args.target,
        args.fov,
        w as f32 / h as f32,
    )?;
    let shading = Shading {
        mode: Mode::Sh,
        lmax,
        window: args.window,
        exposure_ev: 0.0,
        tone_map: None,
        albedo,
        background: match args.background {
            BackgroundArg::None => Background::None,
            BackgroundArg::Map => Background::Map,
            BackgroundArg::Sh => Background::Sh,
        },
    };
    bar.set_message(format!("rendering {w}x{h} on {}", ctx.adapter_name()));
    let target = Offscreen::new(&ctx, w, h)?;
    let aspect = target.aspect();
    let frame = target
        .render_with(&ctx, true, |encoder, color, depth| {
            background.draw(&ctx, encoder, color, depth, &camera, aspect, &shading)?;
            shaded.draw(
                &ctx, encoder, color, depth, &camera, aspect, &shading, false,
            );
            Ok(())
        })?
        .expect("read back");
    bar.finish_and_clear();
    write_frame(args, format, frame.rgb(), (w, h))
}
