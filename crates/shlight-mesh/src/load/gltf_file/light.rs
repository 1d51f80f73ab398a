//! A `KHR_lights_punctual` light on a node to a world-space
//! [`PunctualLight`]: the node's world translation is its position, the
//! world transform applied to the node's -Z (normalised) its direction.
//! The specification's defaults (intensity 1, white, a spot's cone from 0
//! to pi/4) come from the `gltf` crate's parser; the values are checked
//! here (finite, a non-negative intensity and colour, a positive range,
//! `0 <= inner < outer <= pi/2`).

use glam::{Mat4, Vec3};
use gltf::json;
use json::extensions::scene::khr_lights_punctual::{Light, Type};
use json::validation::Checked;

use crate::punctual_light::{LightKind, PunctualLight};

/// Light `index` of the file, placed by a node whose world transform is
/// `world`; an error is a phrase naming the light.
pub(super) fn place(root: &json::Root, index: usize, world: Mat4) -> Result<PunctualLight, String> {
    let light: &Light = root
        .extensions
        .as_ref()
        .and_then(|e| e.khr_lights_punctual.as_ref())
        .and_then(|l| l.lights.get(index))
        .ok_or_else(|| format!("light {index} does not exist"))?;
    let name = match &light.name {
        Some(n) => format!("light {index} ({n})"),
        None => format!("light {index}"),
    };
    let color = Vec3::from_array(light.color);
    if !color.is_finite() || color.min_element() < 0.0 {
        return Err(format!(
            "{name} has the colour {color}: not finite and non-negative"
        ));
    }
    if !light.intensity.is_finite() || light.intensity < 0.0 {
        return Err(format!(
            "{name} has the intensity {}: not finite and non-negative",
            light.intensity
        ));
    }
    if let Some(range) = light.range
        && !(range.is_finite() && range > 0.0)
    {
        return Err(format!(
            "{name} has the range {range}: not finite and positive"
        ));
    }
    let kind = match &light.type_ {
        Checked::Valid(Type::Point) => LightKind::Point,
        Checked::Valid(Type::Directional) => LightKind::Directional,
        Checked::Valid(Type::Spot) => {
            let spot = light.spot.clone().unwrap_or_default();
            let (inner, outer) = (spot.inner_cone_angle, spot.outer_cone_angle);
            if !(inner >= 0.0 && inner < outer && outer <= std::f32::consts::FRAC_PI_2) {
                return Err(format!(
                    "{name} is a spot with the cone angles {inner} and {outer} \
                     (glTF needs 0 <= innerConeAngle < outerConeAngle <= pi/2)"
                ));
            }
            LightKind::Spot {
                inner_cone: inner,
                outer_cone: outer,
            }
        }
        Checked::Invalid => return Err(format!("{name} has an unknown type")),
    };
    let direction = world
        .transform_vector3(Vec3::NEG_Z)
        .try_normalize()
        .ok_or_else(|| format!("{name}'s node transform gives it no direction"))?;
    Ok(PunctualLight {
        name: light.name.clone(),
        kind,
        color,
        intensity: light.intensity,
        range: light.range,
        position: world.w_axis.truncate(),
        direction,
    })
}
