//! A CPU preview of a baked mesh: per-vertex exit radiance rasterised with
//! a z-buffer, colours interpolated across each triangle (Gouraud), from an
//! automatically framed perspective camera.
//!
//! The camera looks at the centre of the mesh's bounding box from the
//! direction [`VIEW_FROM`] (in front, to the right and above, for y-up
//! meshes), far enough that the bounding sphere fills the vertical field of
//! view [`FOV_Y_DEGREES`]. Pixels are rendered 2 x 2 supersampled and box
//! filtered. Both sides of every triangle are drawn; the background is 0.
//! [`vertex_exposure`] picks the exposure that shows the colours at a
//! quarter of white.

use glam::Vec3;
use shlight_core::map::luminance;
use shlight_io::Image;
use shlight_mesh::Mesh;

/// Direction from the target to the camera (normalised when used).
pub const VIEW_FROM: Vec3 = Vec3::new(0.6, 0.45, 1.0);
/// Vertical field of view.
pub const FOV_Y_DEGREES: f32 = 35.0;
const SUPERSAMPLE: usize = 2;

/// The exposure in stops that puts the mean Rec.709 luminance
/// ([`luminance`], in `f64`) of `colors` at 0.25
/// ([`shlight_io::auto_exposure`]); 0 for black (or no) colours.
#[must_use]
pub fn vertex_exposure(colors: &[Vec3]) -> f32 {
    let mean =
        colors.iter().map(|c| luminance(c.as_dvec3())).sum::<f64>() / colors.len().max(1) as f64;
    shlight_io::auto_exposure(mean, 0.25)
}

/// Renders `mesh` with one linear RGB value per vertex to a `width x height`
/// image (linear values, for [`shlight_io::write_image`]).
///
/// # Panics
/// If `colors` has another length than the mesh's vertices.
#[must_use]
pub fn render_preview(mesh: &Mesh, colors: &[Vec3], width: usize, height: usize) -> Image {
    assert_eq!(colors.len(), mesh.vertex_count(), "one colour per vertex");
    let (w, h) = (width * SUPERSAMPLE, height * SUPERSAMPLE);
    let cam = Camera::framing(mesh, width as f32 / height.max(1) as f32);
    // Screen x, y (pixels) and 1/depth (affine in screen space: it is both
    // the depth test and the perspective-correct weight).
    let screen: Vec<Option<Vec3>> = mesh
        .positions
        .iter()
        .map(|p| {
            let d = *p - cam.eye;
            let z = d.dot(cam.forward);
            (z > 1e-6 * cam.distance).then(|| {
                let inv_z = 1.0 / z;
                Vec3::new(
                    (d.dot(cam.right) * inv_z * cam.scale_x * 0.5 + 0.5) * w as f32,
                    (0.5 - d.dot(cam.up) * inv_z * cam.scale_y * 0.5) * h as f32,
                    inv_z,
                )
            })
        })
        .collect();
    let mut nearest = vec![0.0f32; w * h];
    let mut pixels = vec![Vec3::ZERO; w * h];
    for tri in &mesh.triangles {
        let [Some(a), Some(b), Some(c)] = tri.map(|i| screen[i as usize]) else {
            continue; // behind the camera (cannot happen with the auto framing)
        };
        let [ca, cb, cc] = tri.map(|i| colors[i as usize]);
        let area = edge(a, b, c);
        if area.abs() < 1e-12 {
            continue;
        }
        let x0 = a.x.min(b.x).min(c.x).floor().max(0.0) as usize;
        let x1 = (a.x.max(b.x).max(c.x).ceil() as usize).min(w);
        let y0 = a.y.min(b.y).min(c.y).floor().max(0.0) as usize;
        let y1 = (a.y.max(b.y).max(c.y).ceil() as usize).min(h);
        for y in y0..y1 {
            for x in x0..x1 {
                let p = Vec3::new(x as f32 + 0.5, y as f32 + 0.5, 0.0);
                let (l0, l1, l2) = (
                    edge(b, c, p) / area,
                    edge(c, a, p) / area,
                    edge(a, b, p) / area,
                );
                if l0 < 0.0 || l1 < 0.0 || l2 < 0.0 {
                    continue;
                }
                let (pa, pb, pc) = (l0 * a.z, l1 * b.z, l2 * c.z);
                let inv_z = pa + pb + pc;
                let k = y * w + x;
                if inv_z <= nearest[k] {
                    continue;
                }
                nearest[k] = inv_z;
                pixels[k] = (ca * pa + cb * pb + cc * pc) / (pa + pb + pc);
            }
        }
    }
    let s2 = (SUPERSAMPLE * SUPERSAMPLE) as f32;
    Image::from_fn(width, height, |x, y| {
        let mut sum = Vec3::ZERO;
        for dy in 0..SUPERSAMPLE {
            for dx in 0..SUPERSAMPLE {
                sum += pixels[(y * SUPERSAMPLE + dy) * w + x * SUPERSAMPLE + dx];
            }
        }
        (sum / s2).to_array()
    })
}

/// Twice the signed area of `(a, b, p)` in screen space.
fn edge(a: Vec3, b: Vec3, p: Vec3) -> f32 {
    (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x)
}

/// The auto-framed pinhole camera: position, orthonormal basis, and the
/// factors from `x/z`, `y/z` to normalised device coordinates.
struct Camera {
    eye: Vec3,
    forward: Vec3,
    right: Vec3,
    up: Vec3,
    scale_x: f32,
    scale_y: f32,
    distance: f32,
}

impl Camera {
    fn framing(mesh: &Mesh, aspect: f32) -> Self {
        let (lo, hi) = mesh.bounds();
        let centre = (lo + hi) * 0.5;
        let radius = mesh
            .positions
            .iter()
            .map(|p| p.distance(centre))
            .fold(0.0f32, f32::max)
            .max(1e-6);
        let tan_y = (FOV_Y_DEGREES.to_radians() * 0.5).tan();
        // Fit the bounding sphere in the narrower of the two directions.
        let half = tan_y.min(tan_y * aspect).atan();
        let distance = radius / half.sin() * 1.02;
        let eye = centre + VIEW_FROM.normalize() * distance;
        let forward = (centre - eye).normalize();
        let right = forward.cross(Vec3::Y).normalize();
        Self {
            eye,
            forward,
            right,
            up: right.cross(forward),
            scale_x: 2.0 / (tan_y * aspect) * 0.5,
            scale_y: 2.0 / tan_y * 0.5,
            distance,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use shlight_mesh::generate;

    #[test]
    fn the_exposure_puts_the_mean_luminance_at_a_quarter() {
        // Mean luminance 0.5 (one grey 1, one black): one stop down.
        assert_eq!(vertex_exposure(&[Vec3::ONE, Vec3::ZERO]), -1.0);
        let green = vertex_exposure(&[Vec3::new(0.0, 1.0, 0.0)]);
        assert!(
            (f64::from(green).exp2() * 0.7152 - 0.25).abs() < 1e-6,
            "{green}"
        );
        assert_eq!(vertex_exposure(&[]), 0.0);
        assert_eq!(vertex_exposure(&[Vec3::ZERO; 3]), 0.0);
    }

    #[test]
    fn a_framed_sphere_fills_its_circle_and_colours_interpolate() {
        let sphere = generate::uv_sphere(1.0, 64, 32);
        // Colour = (normal.y + 1) / 2 in every channel: bright on top.
        let colors: Vec<Vec3> = sphere
            .normals
            .iter()
            .map(|n| Vec3::splat((n.y + 1.0) * 0.5))
            .collect();
        let img = render_preview(&sphere, &colors, 64, 64);
        // The sphere's silhouette from distance d = 1.02/sin(17.5 deg) has
        // angular radius asin(1/d); its share of the square image:
        let d = 1.02 / (FOV_Y_DEGREES.to_radians() * 0.5).sin();
        let r_px = (1.0 / d).asin().tan() / (FOV_Y_DEGREES.to_radians() * 0.5).tan() * 32.0;
        let expected = std::f32::consts::PI * r_px * r_px / (64.0 * 64.0);
        let covered = img.pixels().iter().filter(|p| p[0] > 0.0).count() as f32 / (64.0 * 64.0);
        assert!((covered - expected).abs() < 0.03, "{covered} vs {expected}");
        // The top of the disc is brighter than the bottom.
        let column: Vec<f32> = (0..64)
            .map(|y| img.get(32, y)[0])
            .filter(|&v| v > 0.0)
            .collect();
        assert!(column.first().unwrap() > column.last().unwrap());
        assert!(img.get(0, 0) == [0.0; 3]);
    }
}
