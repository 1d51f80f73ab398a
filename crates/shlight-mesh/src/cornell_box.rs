//! The Cornell box: the published geometry and colours of the Cornell
//! University Program of Computer Graphics' test scene
//! (<https://www.graphics.cornell.edu/online/box/data.html>), a standard
//! room with an opening, coloured walls, two blocks and a ceiling light.

use glam::Vec3;

use crate::Mesh;

/// Linear RGB albedo of the white surfaces (floor, ceiling, back wall,
/// blocks), the usual RGB fit to the published reflectance spectra.
pub const WHITE: Vec3 = Vec3::new(0.725, 0.71, 0.68);
/// Linear RGB albedo of the red (left, +x) wall.
pub const RED: Vec3 = Vec3::new(0.63, 0.065, 0.05);
/// Linear RGB albedo of the green (right, x = 0) wall.
pub const GREEN: Vec3 = Vec3::new(0.14, 0.45, 0.091);
/// Linear RGB emitted radiance of the ceiling light (the usual RGB fit to
/// the published spectrum).
pub const LIGHT: Vec3 = Vec3::new(17.0, 12.0, 4.0);

/// One quad of the published data: corners in millimetres, its albedo, its
/// emission, and whether it faces the room's inside (walls) or away from
/// its block's centre (blocks).
struct Quad {
    corners: [[f32; 3]; 4],
    albedo: Vec3,
    emission: Vec3,
    facing: Facing,
}

enum Facing {
    Room,
    Away([f32; 3]),
}

const ROOM_CENTRE: [f32; 3] = [278.0, 274.4, 279.6];
const SHORT: [f32; 3] = [186.0, 82.5, 168.5];
const TALL: [f32; 3] = [368.5, 165.0, 351.25];

#[rustfmt::skip]
fn quads() -> Vec<Quad> {
    let wall = |corners, albedo| Quad { corners, albedo, emission: Vec3::ZERO, facing: Facing::Room };
    let block = |corners, centre| Quad { corners, albedo: WHITE, emission: Vec3::ZERO, facing: Facing::Away(centre) };
    vec![
        // The light, just below the ceiling, facing down.
        Quad {
            corners: [[343.0, 548.7, 227.0], [343.0, 548.7, 332.0], [213.0, 548.7, 332.0], [213.0, 548.7, 227.0]],
            albedo: Vec3::splat(0.78),
            emission: LIGHT,
            facing: Facing::Room,
        },
        wall([[552.8, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 559.2], [549.6, 0.0, 559.2]], WHITE),
        wall([[556.0, 548.8, 0.0], [556.0, 548.8, 559.2], [0.0, 548.8, 559.2], [0.0, 548.8, 0.0]], WHITE),
        wall([[549.6, 0.0, 559.2], [0.0, 0.0, 559.2], [0.0, 548.8, 559.2], [556.0, 548.8, 559.2]], WHITE),
        wall([[0.0, 0.0, 559.2], [0.0, 0.0, 0.0], [0.0, 548.8, 0.0], [0.0, 548.8, 559.2]], GREEN),
        wall([[552.8, 0.0, 0.0], [549.6, 0.0, 559.2], [556.0, 548.8, 559.2], [556.0, 548.8, 0.0]], RED),
        block([[130.0, 165.0, 65.0], [82.0, 165.0, 225.0], [240.0, 165.0, 272.0], [290.0, 165.0, 114.0]], SHORT),
        block([[290.0, 0.0, 114.0], [290.0, 165.0, 114.0], [240.0, 165.0, 272.0], [240.0, 0.0, 272.0]], SHORT),
        block([[130.0, 0.0, 65.0], [130.0, 165.0, 65.0], [290.0, 165.0, 114.0], [290.0, 0.0, 114.0]], SHORT),
        block([[82.0, 0.0, 225.0], [82.0, 165.0, 225.0], [130.0, 165.0, 65.0], [130.0, 0.0, 65.0]], SHORT),
        block([[240.0, 0.0, 272.0], [240.0, 165.0, 272.0], [82.0, 165.0, 225.0], [82.0, 0.0, 225.0]], SHORT),
        block([[423.0, 330.0, 247.0], [265.0, 330.0, 296.0], [314.0, 330.0, 456.0], [472.0, 330.0, 406.0]], TALL),
        block([[423.0, 0.0, 247.0], [423.0, 330.0, 247.0], [472.0, 330.0, 406.0], [472.0, 0.0, 406.0]], TALL),
        block([[472.0, 0.0, 406.0], [472.0, 330.0, 406.0], [314.0, 330.0, 456.0], [314.0, 0.0, 456.0]], TALL),
        block([[314.0, 0.0, 456.0], [314.0, 330.0, 456.0], [265.0, 330.0, 296.0], [265.0, 0.0, 296.0]], TALL),
        block([[265.0, 0.0, 296.0], [265.0, 330.0, 296.0], [423.0, 330.0, 247.0], [423.0, 0.0, 247.0]], TALL),
    ]
}

/// The Cornell box in metres (the published millimetres / 1000), +Y up, the
/// opening towards -Z (the published camera looks along +Z from
/// `(0.278, 0.273, -0.8)`): five walls facing inside, two white blocks
/// facing outside, and the ceiling light (0.13 x 0.105 m, 1 mm below the
/// ceiling, facing down, emitting [`LIGHT`]).
///
/// Vertex colours are the albedos ([`WHITE`], [`RED`], [`GREEN`]), the
/// emission is [`LIGHT`] on the light's vertices; each quad has four vertices
/// of its own (area-weighted normals of its two triangles) in the published order: light, floor, ceiling,
/// back wall, right (green) wall, left (red) wall, short block (top, then
/// sides), tall block.
#[must_use]
pub fn cornell_box() -> Mesh {
    let (mut positions, mut colors, mut emission, mut triangles) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for q in quads() {
        let p = q.corners.map(|c| Vec3::from_array(c) / 1000.0);
        let centre = (p[0] + p[1] + p[2] + p[3]) / 4.0;
        let n = (p[1] - p[0]).cross(p[2] - p[0]);
        let towards = match q.facing {
            Facing::Room => Vec3::from_array(ROOM_CENTRE) / 1000.0 - centre,
            Facing::Away(c) => centre - Vec3::from_array(c) / 1000.0,
        };
        let flip = n.dot(towards) < 0.0;
        let base = positions.len() as u32;
        positions.extend(p);
        colors.extend([q.albedo; 4]);
        emission.extend([q.emission; 4]);
        let tris = [[0, 1, 2], [0, 2, 3]];
        for t in tris {
            let t = if flip { [t[0], t[2], t[1]] } else { t };
            triangles.push(t.map(|i| base + i));
        }
    }
    // Some published quads are not quite planar: the vertex normals are
    // the area-weighted ones Mesh::new computes, as for the OBJ file.
    Mesh::new("Cornell box", positions, triangles, None, Some(colors))
        .and_then(|m| m.with_emission("Cornell box", emission))
        .expect("the Cornell box is a valid mesh")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn faces_point_into_the_room_and_the_light_down() {
        let m = cornell_box();
        assert_eq!(m.triangle_count(), 32);
        let centre = Vec3::from_array(ROOM_CENTRE) / 1000.0;
        for (k, t) in m.triangles.iter().enumerate() {
            let [a, b, c] = t.map(|i| m.positions[i as usize]);
            let face = (b - a).cross(c - a);
            // Winding agrees with the vertex normals.
            assert!(face.dot(m.normals[t[0] as usize]) > 0.0, "triangle {k}");
            // The walls (triangles 2..12) face the room's centre.
            if (2..12).contains(&k) {
                assert!(face.dot(centre - a) > 0.0, "wall triangle {k}");
            }
        }
        assert!(m.normals[0].y < -0.99, "the light faces down");
        let e = m.emission.as_ref().unwrap();
        assert_eq!(e.iter().filter(|e| **e == LIGHT).count(), 4);
        let (lo, hi) = m.bounds();
        assert!(
            lo.abs().max_element() < 1e-6
                && (hi - Vec3::new(0.556, 0.5488, 0.5592)).abs().max_element() < 1e-6
        );
    }
}
