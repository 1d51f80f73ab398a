//! Projects a cube map given as six separate face images to SH and shades a
//! few surface normals with its irradiance.
//!
//! The faces are built at run time: a blue sky brightening toward the
//! horizon over a dark ground, and a small sun. They are projected through
//! [`shlight_core::map::TexelSource`] ([`CubeFaces`]) without being assembled
//! into a cross or strip, the radiance coefficients are convolved with the
//! clamped cosine ([`irradiance`]), and the irradiance `E(n)` of a few
//! normals is printed next to the brute-force sum over every texel.
//!
//! Run with `cargo run --release -p shlight-core --example project_cubemap`.

use glam::DVec3;
use shlight_core::map::{CubeFace, CubeFaces, Layout, MapOrientation, TexelSource, project};
use shlight_core::sh::irradiance;

/// Texels along a face's edge.
const FACE: usize = 64;

/// Radiance of the sky in the map's y-up frame: linear RGB.
fn sky(d: DVec3) -> DVec3 {
    let sun = DVec3::new(0.4, 0.6, -0.7).normalize();
    // A sun of about 2.9 degrees radius.
    let sun_disc = if d.dot(sun) > 0.9987 { 2000.0 } else { 0.0 };
    let base = if d.y >= 0.0 {
        // Zenith blue to a paler horizon.
        DVec3::new(0.25, 0.45, 1.0).lerp(DVec3::new(0.8, 0.85, 1.0), (1.0 - d.y).powi(3))
    } else {
        DVec3::new(0.12, 0.1, 0.08)
    };
    base + DVec3::splat(sun_disc)
}

/// One `FACE x FACE` face image, texel `(i, j)` at face coordinates
/// `sc = (2i+1)/f - 1`, `tc = (2j+1)/f - 1` ([`CubeFace::point`]).
fn face_image(face: CubeFace) -> Vec<[f32; 3]> {
    let c = |k: usize| (2 * k + 1) as f64 / FACE as f64 - 1.0;
    (0..FACE)
        .flat_map(|j| (0..FACE).map(move |i| (i, j)))
        .map(|(i, j)| sky(face.point(c(i), c(j)).normalize()).as_vec3().to_array())
        .collect()
}

fn main() {
    let faces: Vec<Vec<[f32; 3]>> = CubeFace::ALL.into_iter().map(face_image).collect();
    let cube = CubeFaces::new(FACE, core::array::from_fn(|k| faces[k].as_slice()))
        .expect("six faces of FACE x FACE texels");
    let o = MapOrientation::default();
    let radiance = project(&cube, 2, o).expect("the faces make a strip");
    let e = irradiance(&radiance);

    // The same map, every texel cosine-weighted: the irradiance SH
    // approximates.
    let (w, h) = cube.size();
    let map = shlight_core::map::EnvMap {
        layout: Layout::Strip,
        orientation: o,
        width: w,
        height: h,
        pixels: &[],
    };
    let brute = |n: DVec3| {
        let mut sum = DVec3::ZERO;
        for y in 0..h {
            for x in 0..w {
                let d = map.texel_direction(x, y).expect("every strip texel");
                let f = DVec3::from(cube.texel(x, y).map(f64::from));
                sum += f * (n.dot(d).max(0.0) * map.texel_solid_angle(x, y));
            }
        }
        sum
    };

    println!("irradiance E(n) = sum A_l L_lm Y_lm(n), lmax 2, of a {FACE}^2-texel cube map");
    println!(
        "{:>22}  {:>28}  {:>28}",
        "normal", "SH (r, g, b)", "every texel (r, g, b)"
    );
    for n in [
        DVec3::Y,
        DVec3::NEG_Y,
        DVec3::X,
        DVec3::new(0.4, 0.6, -0.7).normalize(),
    ] {
        let sh = e.eval(n);
        let exact = brute(n);
        println!(
            "({:>6.3}, {:>6.3}, {:>6.3})  ({:>8.3}, {:>8.3}, {:>8.3})  ({:>8.3}, {:>8.3}, {:>8.3})",
            n.x, n.y, n.z, sh.x, sh.y, sh.z, exact.x, exact.y, exact.z
        );
    }
    println!(
        "(nine coefficients cannot hold the sun: the SH irradiance rings, below zero facing \
         away from it; shlight_core::sh::auto_window finds the weakest window that prevents that)"
    );
}
