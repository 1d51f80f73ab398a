//! glTF's punctual lights (`KHR_lights_punctual`): a point, a spot or a
//! directional light, placed by its node, and the light it sends to a
//! point.
//!
//! Punctual lights are deltas: a point `x` receives their light from one
//! direction only, `toward` (unit, from `x` to the light), with
//! irradiance on a surface facing the light head-on
//!
//! ```text
//! point:        E_perp = I c / d^2 . W(d)
//! spot:         E_perp = I c / d^2 . W(d) . S(cos_s)
//! directional:  E_perp = I c
//! W(d) = clamp(1 - (d / range)^4, 0, 1)           (1 without a range)
//! S    = t^2, t = clamp((cos_s - cos_outer) / max(cos_inner - cos_outer, 0.001), 0, 1)
//! ```
//!
//! with `I` the intensity (candela for point and spot, lux for
//! directional, as the file writes them), `c` the linear colour, `d` the
//! distance and `cos_s` the cosine between the spot's axis and the
//! direction from the light to `x`: the window and the cone falloff are
//! the specification's. With [`LightUnits::Blender`] a spot falls off as
//! Cycles renders it instead: Blender's exporter writes a spot of size
//! `2 a` and blend `b` as `outer = a`, `inner = a (1 - b)`, and Cycles
//! (4.x, `spot_attenuation`) scales it by
//!
//! ```text
//! S = smoothstep(t), smoothstep(t) = t^2 (3 - 2 t),
//! t = clamp((cos_s - cos_outer) / ((1 - cos_outer) b), 0, 1),  b = 1 - inner / outer
//! ```
//!
//! (a hard edge at `outer` where `b` is 0): full from a wider angle than
//! `inner`, and a softer edge, so the specification's falloff would give
//! a Blender spot's pool less light. A surface with unit normal `n` at `x` receives
//! `E = E_perp max(n . toward, 0)`, and a light probe at `x` receives the
//! radiance `E_perp delta(s - toward)`, whose SH coefficients are
//! `E_perp Y_lm(toward)` exactly.
//!
//! **Units.** glTF writes photometric units; Blender's exporter writes
//! its radiometric watts times 683 lm/W (a point of `P` W becomes
//! `P / (4 pi) x 683` cd, a sun of `S` W/m2 becomes `683 S` lux), and
//! Cycles lights a surface with the radiometric value. [`LightUnits`]
//! says whether the intensities are divided by 683 (the default, so that
//! a Blender scene bakes to what Cycles renders, in the same units as an
//! environment's radiance) or taken as written.

use glam::Vec3;

/// How a punctual light's intensity becomes radiometric units (W/m2 of
/// irradiance at 1 m, the unit of an environment's radiance times a solid
/// angle).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LightUnits {
    /// The file's candela and lux divided by [`PunctualLight::LUMENS_PER_WATT`]
    /// (what Blender's exporter multiplied them by), and a spot's cone
    /// falling off as Cycles renders the Blender spot the exporter wrote
    /// (the module documentation).
    #[default]
    Blender,
    /// The file's numbers taken as they are (files authored in engines
    /// that treat them as radiometric).
    AsWritten,
}

impl LightUnits {
    /// Both, in the order of the command line's help.
    pub const ALL: [LightUnits; 2] = [LightUnits::Blender, LightUnits::AsWritten];

    /// The name files and messages use: `"blender"` or `"as-written"`.
    pub fn name(self) -> &'static str {
        match self {
            LightUnits::Blender => "blender",
            LightUnits::AsWritten => "as-written",
        }
    }

    /// What the units mean, in words (for help texts).
    pub fn description(self) -> &'static str {
        match self {
            LightUnits::Blender => {
                "glTF's candela and lux divided by 683, as Blender's exporter wrote them: what Cycles renders"
            }
            LightUnits::AsWritten => "glTF's intensities taken as radiometric as they are",
        }
    }

    /// The factor an intensity is multiplied by.
    pub fn scale(self) -> f32 {
        match self {
            LightUnits::Blender => 1.0 / PunctualLight::LUMENS_PER_WATT,
            LightUnits::AsWritten => 1.0,
        }
    }
}

impl std::str::FromStr for LightUnits {
    type Err = String;

    /// One of the [names](LightUnits::name) (trimmed, ASCII
    /// case-insensitive).
    fn from_str(s: &str) -> Result<Self, String> {
        LightUnits::ALL
            .into_iter()
            .find(|u| u.name().eq_ignore_ascii_case(s.trim()))
            .ok_or_else(|| "unknown light units (expected one of blender, as-written)".to_string())
    }
}

/// The kind of a punctual light, with its cone for a spot.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightKind {
    /// Light from a point, equal in every direction.
    Point,
    /// Light from a point within a cone about [`PunctualLight::direction`]:
    /// full inside `inner_cone`, none outside `outer_cone` (radians from
    /// the axis, `0 <= inner < outer <= pi / 2`).
    Spot {
        /// Angle of full intensity, radians.
        inner_cone: f32,
        /// Angle beyond which the light is zero, radians.
        outer_cone: f32,
    },
    /// Parallel light along [`PunctualLight::direction`] (a sun).
    Directional,
}

/// One punctual light in world space.
#[derive(Clone, Debug, PartialEq)]
pub struct PunctualLight {
    /// The light's name in the file, if any.
    pub name: Option<String>,
    /// Point, spot or directional.
    pub kind: LightKind,
    /// Linear Rec.709 colour (the file's `color`).
    pub color: Vec3,
    /// The file's `intensity`: candela (point, spot) or lux (directional).
    pub intensity: f32,
    /// Distance beyond which the light is zero (point and spot), if any.
    pub range: Option<f32>,
    /// World position (unused by a directional light).
    pub position: Vec3,
    /// Unit world direction the light travels along (the node's -Z): a
    /// spot's axis, a directional light's rays.
    pub direction: Vec3,
}

/// The light a punctual light sends to a point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Arrival {
    /// Unit direction from the point toward the light.
    pub toward: Vec3,
    /// Distance to the light (`f32::INFINITY` for a directional light):
    /// a shadow ray is cast this far.
    pub distance: f32,
    /// Irradiance on a surface facing the light head-on, per channel,
    /// after [`LightUnits`].
    pub irradiance: Vec3,
}

impl PunctualLight {
    /// Lumens per watt of Blender's exporter (the luminous efficacy of
    /// 555 nm light).
    pub const LUMENS_PER_WATT: f32 = 683.0;

    /// The light arriving at `point`, unshadowed; `None` where the light
    /// gives nothing (behind a spot's cone, beyond the range, at the
    /// light's own position).
    pub fn arriving(&self, point: Vec3, units: LightUnits) -> Option<Arrival> {
        let strength = self.color * (self.intensity * units.scale());
        if let LightKind::Directional = self.kind {
            return (strength != Vec3::ZERO).then_some(Arrival {
                toward: -self.direction,
                distance: f32::INFINITY,
                irradiance: strength,
            });
        }
        let to_light = self.position - point;
        let d2 = to_light.length_squared();
        if d2 <= 0.0 || !d2.is_finite() {
            return None;
        }
        let d = d2.sqrt();
        let toward = to_light / d;
        let window = match self.range {
            Some(range) if range > 0.0 => (1.0 - (d / range).powi(4)).clamp(0.0, 1.0),
            _ => 1.0,
        };
        let cone = match self.kind {
            LightKind::Spot {
                inner_cone,
                outer_cone,
            } => {
                let (cos_inner, cos_outer) = (inner_cone.cos(), outer_cone.cos());
                let cos_s = self.direction.dot(-toward);
                if units == LightUnits::Blender {
                    let blend = if outer_cone > 0.0 {
                        (1.0 - inner_cone / outer_cone).clamp(0.0, 1.0)
                    } else {
                        0.0
                    };
                    let smooth = (1.0 - cos_outer) * blend;
                    if smooth > 0.0 {
                        let t = ((cos_s - cos_outer) / smooth).clamp(0.0, 1.0);
                        t * t * (3.0 - 2.0 * t)
                    } else if cos_s > cos_outer {
                        1.0
                    } else {
                        0.0
                    }
                } else {
                    let scale = 1.0 / (cos_inner - cos_outer).max(0.001);
                    let t = ((cos_s - cos_outer) * scale).clamp(0.0, 1.0);
                    t * t
                }
            }
            _ => 1.0,
        };
        let irradiance = strength * (window * cone / d2);
        (irradiance != Vec3::ZERO).then_some(Arrival {
            toward,
            distance: d,
            irradiance,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(kind: LightKind) -> PunctualLight {
        PunctualLight {
            name: None,
            kind,
            color: Vec3::new(1.0, 0.5, 0.25),
            intensity: 683.0 * 100.0 / (4.0 * std::f32::consts::PI),
            range: None,
            position: Vec3::new(0.0, 1.0, 0.0),
            direction: Vec3::NEG_Y,
        }
    }

    #[test]
    fn a_100_w_blender_point_gives_100_over_4_pi_at_one_metre() {
        let a = point(LightKind::Point)
            .arriving(Vec3::ZERO, LightUnits::Blender)
            .unwrap();
        let e = 100.0 / (4.0 * std::f32::consts::PI);
        assert!((a.irradiance.x - e).abs() < 1e-4 * e, "{a:?}");
        assert!((a.irradiance.y - 0.5 * e).abs() < 1e-4 * e);
        assert_eq!(a.toward, Vec3::Y);
        assert_eq!(a.distance, 1.0);
        let as_written = point(LightKind::Point)
            .arriving(Vec3::new(0.0, -1.0, 0.0), LightUnits::AsWritten)
            .unwrap();
        assert!((as_written.irradiance.x - 683.0 * e / 4.0).abs() < 1e-3 * e);
    }

    #[test]
    fn units_are_read_by_name() {
        for u in LightUnits::ALL {
            assert_eq!(u.name().parse::<LightUnits>(), Ok(u));
        }
        assert_eq!(" As-Written ".parse(), Ok(LightUnits::AsWritten));
        let e = "watts".parse::<LightUnits>().unwrap_err();
        assert!(e.contains("blender, as-written"), "{e}");
    }

    #[test]
    fn a_spot_as_written_falls_off_as_the_specification_says() {
        let spot = point(LightKind::Spot {
            inner_cone: 0.3,
            outer_cone: 0.5,
        });
        let full = point(LightKind::Point);
        let at = |angle: f32| Vec3::new(angle.tan(), 0.0, 0.0);
        let inside = spot.arriving(at(0.29), LightUnits::AsWritten).unwrap();
        let reference = full.arriving(at(0.29), LightUnits::AsWritten).unwrap();
        assert_eq!(inside.irradiance, reference.irradiance);
        assert!(spot.arriving(at(0.51), LightUnits::AsWritten).is_none());
        // Half way in cosine: t = 0.5, S = 0.25.
        let mid = ((0.3f32.cos() + 0.5f32.cos()) / 2.0).acos();
        let half = spot.arriving(at(mid), LightUnits::AsWritten).unwrap();
        let r = full.arriving(at(mid), LightUnits::AsWritten).unwrap();
        assert!((half.irradiance.x / r.irradiance.x - 0.25).abs() < 1e-3);
    }

    #[test]
    fn a_blender_spot_falls_off_as_cycles_renders_it() {
        // Blender's spot of size 60 degrees and blend 0.25, as its exporter
        // writes it: outer 30 degrees, inner 22.5. Cycles keeps it full to
        // acos(cos 30 + (1 - cos 30) 0.25) = 0.452129 rad (25.9 degrees),
        // where the specification's t^2 has fallen to about 0.35, and at
        // half way in cosine gives smoothstep(1/2) = 1/2.
        let (outer, inner) = (30f32.to_radians(), 22.5f32.to_radians());
        let spot = point(LightKind::Spot {
            inner_cone: inner,
            outer_cone: outer,
        });
        let full = point(LightKind::Point);
        let at = |angle: f32| Vec3::new(angle.tan(), 0.0, 0.0);
        let ratio = |angle: f32, units| {
            spot.arriving(at(angle), units)
                .map_or(0.0, |a| a.irradiance.x)
                / full.arriving(at(angle), units).unwrap().irradiance.x
        };
        let edge = 0.452129f32;
        assert!((ratio(edge - 0.002, LightUnits::Blender) - 1.0).abs() < 1e-5);
        assert!(ratio(edge + 0.01, LightUnits::Blender) < 1.0);
        let written = ratio(edge, LightUnits::AsWritten);
        assert!(written > 0.3 && written < 0.4, "{written}");
        let cos_mid = outer.cos() + 0.5 * (1.0 - outer.cos()) * 0.25;
        assert!((ratio(cos_mid.acos(), LightUnits::Blender) - 0.5).abs() < 1e-3);
        assert_eq!(ratio(outer + 0.01, LightUnits::Blender), 0.0);
        // No blend: a hard edge.
        let hard = point(LightKind::Spot {
            inner_cone: outer,
            outer_cone: outer,
        });
        assert_eq!(
            hard.arriving(at(outer - 0.01), LightUnits::Blender)
                .unwrap()
                .irradiance,
            full.arriving(at(outer - 0.01), LightUnits::Blender)
                .unwrap()
                .irradiance
        );
        assert!(
            hard.arriving(at(outer + 0.01), LightUnits::Blender)
                .is_none()
        );
    }

    #[test]
    fn the_range_window_follows_the_specification() {
        let mut light = point(LightKind::Point);
        light.range = Some(2.0);
        let near = light.arriving(Vec3::ZERO, LightUnits::Blender).unwrap();
        let free = point(LightKind::Point)
            .arriving(Vec3::ZERO, LightUnits::Blender)
            .unwrap();
        // d = 1, range 2: 1 - 1/16.
        assert!((near.irradiance.x / free.irradiance.x - 15.0 / 16.0).abs() < 1e-5);
        assert!(
            light
                .arriving(Vec3::new(0.0, -1.5, 0.0), LightUnits::Blender)
                .is_none()
        );
    }

    #[test]
    fn a_directional_light_is_parallel_and_unattenuated() {
        let sun = PunctualLight {
            kind: LightKind::Directional,
            intensity: 683.0 * 3.0,
            direction: Vec3::new(0.0, -0.6, -0.8),
            ..point(LightKind::Directional)
        };
        for p in [Vec3::ZERO, Vec3::splat(100.0)] {
            let a = sun.arriving(p, LightUnits::Blender).unwrap();
            assert!((a.irradiance.x - 3.0).abs() < 1e-5);
            assert_eq!(a.toward, Vec3::new(0.0, 0.6, 0.8));
            assert!(a.distance.is_infinite());
        }
    }
}
