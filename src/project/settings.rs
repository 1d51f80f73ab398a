//! Everything `shlight project` decides from its arguments before reading
//! any input: frame, window, rotation, Monte Carlo options, the GPU.

use anyhow::{Result, anyhow, bail};
use glam::{DMat3, DQuat};
use shlight_core::Window;
use shlight_core::montecarlo::{DEFAULT_SEED, McOptions};
use shlight_core::projection::MapOrientation;
use shlight_core::rotation::Frame;
use shlight_format::RotationRecord;
use shlight_io::ReadOptions;
use shlight_pipeline::ProjectSettings;

use crate::preview::PreviewOptions;
use crate::texels::LayoutArg;

use super::args::{DEFAULT_SAMPLES, Method, ProjectArgs};

/// The library's method for `--method`.
type LibMethod = shlight_pipeline::Method;

/// Everything decided from the arguments before any input is read.
pub struct Settings<'a> {
    pub args: &'a ProjectArgs,
    pub orientation: MapOrientation,
    /// lmax, orientation, method, window, rotation and quantity, as the
    /// library's pipeline takes them.
    pub project: ProjectSettings,
    pub read: ReadOptions,
    pub preview: PreviewOptions,
    /// The device and pipelines of `--gpu`.
    #[cfg(feature = "gpu")]
    pub gpu: Option<(shlight_gpu::GpuContext, shlight_gpu::GpuProjector)>,
}

impl<'a> Settings<'a> {
    pub fn new(args: &'a ProjectArgs) -> Result<Self> {
        let frame = crate::input::frame_of(&args.up);
        let window = match args.window.trim() {
            "auto" => None,
            spec => Some(
                spec.parse::<Window>()
                    .map_err(|e| anyhow!("--window {spec}: {e}"))?,
            ),
        };
        let rotation = match &args.rotate {
            None => None,
            Some(spec) => {
                let matrix = parse_rotation(spec, frame)?;
                let record = RotationRecord {
                    spec: spec.trim().to_string(),
                    matrix: matrix.transpose().to_cols_array_2d(),
                };
                Some((record, matrix))
            }
        };
        let method = match args.method {
            Method::MonteCarlo => LibMethod::MonteCarlo {
                options: McOptions {
                    lmax: args.lmax,
                    samples: args.samples.unwrap_or(DEFAULT_SAMPLES),
                    seed: args.seed.unwrap_or(DEFAULT_SEED),
                    ..McOptions::default()
                },
                sampler: args.sampler.unwrap_or_default(),
            },
            Method::Quadrature => {
                let given: Vec<&str> = [
                    ("--samples", args.samples.is_some()),
                    ("--sampler", args.sampler.is_some()),
                    ("--seed", args.seed.is_some()),
                ]
                .into_iter()
                .filter_map(|(flag, given)| given.then_some(flag))
                .collect();
                if !given.is_empty() {
                    bail!(
                        "{} only apply to --method montecarlo (the method is quadrature)",
                        given.join(", ")
                    );
                }
                LibMethod::Quadrature
            }
        };
        #[cfg(not(feature = "gpu"))]
        if args.gpu {
            return Err(crate::gpu_feature::needs_gpu("project --gpu"));
        }
        #[cfg(feature = "gpu")]
        let gpu = if args.gpu {
            if method != LibMethod::Quadrature {
                bail!("--gpu computes the quadrature; it does not apply to --method montecarlo");
            }
            if args.lmax > shlight_gpu::MAX_LMAX {
                bail!(
                    "--gpu projects to lmax {} at most (asked: {})",
                    shlight_gpu::MAX_LMAX,
                    args.lmax
                );
            }
            let ctx = anyhow::Context::context(shlight_gpu::GpuContext::headless(), "--gpu")?;
            let projector = shlight_gpu::GpuProjector::new(&ctx);
            Some((ctx, projector))
        } else {
            None
        };
        if args.preview.is_some() {
            LayoutArg::Equirect
                .check_size(args.preview_size.0, args.preview_size.1)
                .map_err(|e| anyhow!("--preview-size: {e}"))?;
        }
        let orientation = MapOrientation {
            frame,
            mirror: args.mirror,
        };
        Ok(Self {
            args,
            orientation,
            project: ProjectSettings {
                lmax: args.lmax,
                orientation,
                method,
                window,
                rotation,
                quantity: args.quantity,
            },
            read: ReadOptions {
                layer: args.layer.clone(),
                max_pixels: args.max_pixels,
            },
            preview: PreviewOptions {
                panel: args.preview_size,
                exposure: args.preview_exposure,
                tone_map: args.preview_tone_map,
            },
            #[cfg(feature = "gpu")]
            gpu,
        })
    }
}

/// Parses `--rotate` into the rotation matrix `R` (a light from `a` comes
/// from `R a` afterwards) in the frame `frame`.
fn parse_rotation(spec: &str, frame: Frame) -> Result<DMat3> {
    let err = |why: &str| {
        anyhow!("--rotate {spec}: {why} (expected yaw:DEG, quat:X,Y,Z,W or euler:X,Y,Z in degrees)")
    };
    let (kind, rest) = spec.trim().split_once(':').ok_or_else(|| err("no kind"))?;
    let numbers: Vec<f64> = rest
        .split(',')
        .map(|t| t.trim().parse::<f64>())
        .collect::<std::result::Result<_, _>>()
        .map_err(|e| err(&e.to_string()))?;
    if !numbers.iter().all(|v| v.is_finite()) {
        return Err(err("not finite"));
    }
    let deg = f64::to_radians;
    match (
        kind.trim().to_ascii_lowercase().as_str(),
        numbers.as_slice(),
    ) {
        ("yaw", [a]) => Ok(DMat3::from_axis_angle(
            frame.direction(0.0, 0.0).normalize(),
            deg(*a),
        )),
        ("quat", [x, y, z, w]) => {
            let q = DQuat::from_xyzw(*x, *y, *z, *w);
            if q.length_squared() == 0.0 {
                return Err(err("the zero quaternion is no rotation"));
            }
            Ok(DMat3::from_quat(q.normalize()))
        }
        ("euler", [x, y, z]) => Ok(DMat3::from_rotation_z(deg(*z))
            * DMat3::from_rotation_y(deg(*y))
            * DMat3::from_rotation_x(deg(*x))),
        ("yaw" | "quat" | "euler", _) => Err(err("wrong count of numbers")),
        _ => Err(err("unknown kind")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn rotations_parse_to_the_documented_matrices() {
        let close = |a: DMat3, b: DMat3| (a - b).to_cols_array().iter().all(|v| v.abs() < 1e-12);
        // yaw about +Y (y-up) takes +X to -Z; about +Z (z-up) +X to +Y.
        let r = parse_rotation("yaw:90", Frame::YUp).unwrap();
        assert!((r * DVec3::X - DVec3::NEG_Z).length() < 1e-12);
        let r = parse_rotation("yaw:90", Frame::ZUp).unwrap();
        assert!((r * DVec3::X - DVec3::Y).length() < 1e-12);
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let q = parse_rotation("quat:0,0,2,2", Frame::YUp).unwrap();
        assert!(close(q, DMat3::from_quat(DQuat::from_xyzw(0.0, 0.0, s, s))));
        let e = parse_rotation("euler:90,0,90", Frame::YUp).unwrap();
        // X first: +Y -> +Z; then Z: +Z stays.
        assert!((e * DVec3::Y - DVec3::Z).length() < 1e-12);
        assert!((e * DVec3::X - DVec3::Y).length() < 1e-12);
        for bad in ["yaw", "yaw:1,2", "quat:0,0,0,0", "spin:3", "yaw:nan"] {
            assert!(parse_rotation(bad, Frame::YUp).is_err(), "{bad}");
        }
    }
}
