//! [`parse_rotation`]: a rotation as the command line's `--rotate` and
//! Python's `rotate=` spell it.

use glam::{DMat3, DQuat};
use shlight_core::sh::Frame;

use crate::spelling::Spelling;
use crate::{PipelineError, Result};

/// Parses a rotation spec into the matrix `R` (a light from `a` comes from
/// `R a` afterwards) in the frame `frame`: `yaw:DEG` (about the frame's up
/// axis, right-handed), `quat:X,Y,Z,W` (normalised), or `euler:X,Y,Z`
/// (degrees; about world X, then Y, then Z: `R = Rz Ry Rx`).
///
/// # Errors
/// An unknown kind, a wrong count of numbers, a number that does not parse
/// or is not finite, the zero quaternion; the message names the setting as
/// `spelling` does.
pub fn parse_rotation(spec: &str, frame: Frame, spelling: Spelling) -> Result<DMat3> {
    let err = |why: &str| {
        PipelineError::new(format!(
            "{}: {why} (expected yaw:DEG, quat:X,Y,Z,W or euler:X,Y,Z in degrees)",
            spelling.option_value("rotate", spec)
        ))
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
        let r = parse_rotation("yaw:90", Frame::YUp, Spelling::CommandLine).unwrap();
        assert!((r * DVec3::X - DVec3::NEG_Z).length() < 1e-12);
        let r = parse_rotation("yaw:90", Frame::ZUp, Spelling::CommandLine).unwrap();
        assert!((r * DVec3::X - DVec3::Y).length() < 1e-12);
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let q = parse_rotation("quat:0,0,2,2", Frame::YUp, Spelling::CommandLine).unwrap();
        assert!(close(q, DMat3::from_quat(DQuat::from_xyzw(0.0, 0.0, s, s))));
        let e = parse_rotation("euler:90,0,90", Frame::YUp, Spelling::CommandLine).unwrap();
        // X first: +Y -> +Z; then Z: +Z stays.
        assert!((e * DVec3::Y - DVec3::Z).length() < 1e-12);
        assert!((e * DVec3::X - DVec3::Y).length() < 1e-12);
        for bad in ["yaw", "yaw:1,2", "quat:0,0,0,0", "spin:3", "yaw:nan"] {
            assert!(
                parse_rotation(bad, Frame::YUp, Spelling::CommandLine).is_err(),
                "{bad}"
            );
        }
    }
}
