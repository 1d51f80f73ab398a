//! The engines' lookups against independent routes: `--lookup bevy`
//! against the line-for-line port of Bevy's shader over the KTX2 file read
//! back (shlight-format's `tests/support/bevy_port.rs`), `--lookup
//! threejs` against three.js's formula worked out here by hand for probes
//! that hold a closed-form light.

use std::f64::consts::PI;

use glam::{DVec3, Vec3};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use shlight_baked::VolumeView;
use shlight_format::ShvolFile;
use shlight_format::bevy_volume::bevy_ktx2;
use shlight_volume::{Lookup, PreparedLookup};

#[path = "../../shlight-format/tests/support/bevy_port.rs"]
mod bevy_port;

/// `lookup`'s irradiance at `p` facing `n`, the lookup prepared for the
/// one point.
fn irradiance_at(view: &VolumeView<'_>, lookup: Lookup, lmax: usize, p: Vec3, n: Vec3) -> DVec3 {
    PreparedLookup::new(view, lookup, lmax).irradiance_at(p, n)
}

fn file(resolution: [usize; 3], bounds: ([f32; 3], [f32; 3]), lmax: usize) -> ShvolFile {
    let n = resolution.iter().product();
    ShvolFile {
        lmax,
        resolution,
        bounds,
        frame: "y-up".into(),
        valid: vec![true; n],
        radiance: vec![0.0; n * 3 * (lmax + 1) * (lmax + 1)],
        emitted: None,
        transfer: None,
        offsets: None,
        visibility: None,
        rays_per_probe: 1,
        bounces: 0,
        seed: 0,
        scene: "s".into(),
        scene_hash: 0,
        environment: "e".into(),
        generator: "test".into(),
        lights: None,
    }
}

fn random_unit(rng: &mut StdRng) -> Vec3 {
    loop {
        let v = Vec3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        );
        if (0.01..1.0).contains(&v.length_squared()) {
            return v.normalize();
        }
    }
}

/// At random points and normals, `--lookup bevy` gives pi times what
/// Bevy's shader, ported line for line, reads from the KTX2 export read
/// back with the `ktx2` crate (the irradiance over pi): random probes of
/// lmax 2 with four invalid ones (one of them reachable only in a second
/// dilation pass), points inside the box and outside it (Bevy lights
/// those from elsewhere: 0).
#[test]
fn bevy_lookup_is_bevys_shader_on_the_exported_file() {
    let mut rng = StdRng::seed_from_u64(25);
    let mut f = file([4, 3, 2], ([-1.0, 0.0, 2.0], [3.0, 1.5, 5.0]), 2);
    for (i, v) in f.radiance.iter_mut().enumerate() {
        *v = if i % 27 < 3 {
            rng.random_range(0.5..3.0)
        } else {
            rng.random_range(-0.6..0.6)
        };
    }
    // Probe (x, y, z) is x + 4 (y + 3 z): (0, 0, 0) and its two face
    // neighbours in the z = 0 layer, and (0, 0, 1) above it.
    for i in [0, 1, 4, 12] {
        f.valid[i] = false;
        f.radiance[i * 27..(i + 1) * 27].fill(1e4);
    }
    let tex = bevy_port::Texture::read(&bevy_ktx2(&f, "test"));
    let (lo, hi) = (Vec3::from_array(f.bounds.0), Vec3::from_array(f.bounds.1));
    // The light probe's transform, as docs/shvol.md tells users to place it.
    let transform = ((lo + hi) / 2.0, hi - lo);
    let view = f.view();
    let prepared = PreparedLookup::new(&view, Lookup::Bevy, 2);
    let (mut worst, mut scale, mut outside) = (0.0f64, 0.0f64, 0);
    for k in 0..400 {
        // A tenth of the points outside the box.
        let reach = if k % 10 == 0 { 0.3 } else { 0.0 };
        let t = Vec3::new(
            rng.random_range(-reach..1.0 + reach),
            rng.random_range(-reach..1.0 + reach),
            rng.random_range(-reach..1.0 + reach),
        );
        let p = lo + (hi - lo) * t;
        let n = random_unit(&mut rng);
        let got = irradiance_at(&view, Lookup::Bevy, 2, p, n);
        assert_eq!(prepared.irradiance_at(p, n), got);
        let want = PI * tex.world_light(transform, p, n).as_dvec3();
        if want == DVec3::ZERO {
            outside += 1;
            assert_eq!(got, DVec3::ZERO, "{p}");
        }
        worst = worst.max((got - want).abs().max_element());
        scale = scale.max(want.abs().max_element());
    }
    eprintln!("bevy lookup vs the port of Bevy's shader: worst {worst:.2e} of {scale:.2}");
    assert!(outside > 10, "{outside} points outside");
    // The same half-float texels on both sides: only the filter's
    // arithmetic (f64 here, f32 in the port) differs.
    assert!(worst < 1e-5 * scale, "worst {worst:.2e} of {scale:.2}");
    // The invalid probes' 1e4 never shows: dilated from valid neighbours.
    assert!(scale < 20.0, "{scale}");
}

/// Bevy's lookup to a lower lmax is the lookup of the volume clipped to
/// it; at lmax 0 every direction at a probe is `pi L00 Y00`, the ambient
/// cube of a constant.
#[test]
fn bevy_lookup_clips_the_probes_to_the_lmax_asked() {
    let mut f = file([2, 1, 1], ([0.0; 3], [2.0, 1.0, 1.0]), 1);
    f.radiance[..12].copy_from_slice(&[1.0, 2.0, 3.0, 0.4, 0.1, 0.0, 0.0, 0.3, 0.0, 0.5, 0.0, 0.2]);
    f.radiance[12..15].copy_from_slice(&[2.0, 2.0, 2.0]);
    let view = f.view();
    let y00 = 0.5 / PI.sqrt();
    let p = Vec3::new(0.5, 0.5, 0.5);
    for n in [Vec3::X, Vec3::NEG_Y, Vec3::new(0.3, -0.4, 0.8)] {
        let got = irradiance_at(&view, Lookup::Bevy, 0, p, n);
        let want = PI * y00 * DVec3::new(1.0, 2.0, 3.0);
        // Half floats: 11 significant bits.
        assert!(
            (got - want).abs().max_element() < 1e-3 * want.max_element(),
            "{got} {want}"
        );
    }
    assert_ne!(
        irradiance_at(&view, Lookup::Bevy, 1, p, Vec3::X),
        irradiance_at(&view, Lookup::Bevy, 0, p, Vec3::X)
    );
}

// three.js's constants, as `lightprobes_pars_fragment.glsl.js` (r187)
// writes them.
const C0: f64 = 0.886227;
const C1: f64 = 2.0 * 0.511664;
const C2: f64 = 2.0 * 0.429043;
const C3: f64 = 0.743125;
const C4: f64 = 0.247708;

/// A grid of 4 x 3 x 3 probes over (-1, 0, 2)..(3, 1.5, 5) (spacing 1,
/// 0.5, 1; probes at x = -0.5, 0.5, 1.5, 2.5) whose three.js coefficients
/// are a closed-form light: `c0 = a + b x` (a gradient along x), and
/// constant `c1` (y), `c3` (x), `c6` (`3z^2 - 1`), `c7` (xz). In shlight's
/// basis (Condon-Shortley phase) the odd-`|m|` ones change sign:
/// `L_1-1 = -c1`, `L_11 = -c3`, `L_21 = -c7`, `L_20 = c6`. Probe
/// (1, 1, 1), inside, is invalid and holds 1e6: dilation gives it the mean
/// of its six face neighbours, which for a field linear in x is its own
/// value, so the closed form still holds.
struct Gradient {
    a: DVec3,
    b: DVec3,
    c1: DVec3,
    c3: DVec3,
    c6: DVec3,
    c7: DVec3,
}

impl Gradient {
    fn new() -> Self {
        Self {
            a: DVec3::new(1.0, 0.8, 0.6),
            b: DVec3::new(0.3, 0.1, -0.15),
            c1: DVec3::new(0.1, 0.2, 0.3),
            c3: DVec3::new(0.9, -0.2, 0.1),
            c6: DVec3::splat(0.05),
            c7: DVec3::new(0.07, 0.0, -0.07),
        }
    }

    fn file(&self, lmax: usize) -> ShvolFile {
        let mut f = file([4, 3, 3], ([-1.0, 0.0, 2.0], [3.0, 1.5, 5.0]), lmax);
        let nc = (lmax + 1) * (lmax + 1);
        let grid = f.grid();
        for (i, centre) in grid.centres().into_iter().enumerate() {
            let c0 = self.a + self.b * f64::from(centre.x);
            let mut rows = vec![DVec3::ZERO; nc];
            rows[0] = c0;
            if lmax >= 1 {
                rows[1] = -self.c1;
                rows[3] = -self.c3;
            }
            if lmax >= 2 {
                rows[6] = self.c6;
                rows[7] = -self.c7;
            }
            if lmax >= 3 {
                // Degree 3, which three.js's grid cannot hold.
                rows[12] = DVec3::splat(0.4);
            }
            for (k, r) in rows.iter().enumerate() {
                f.radiance[(i * nc + k) * 3..][..3].copy_from_slice(&r.as_vec3().to_array());
            }
        }
        let inside = grid.index([1, 1, 1]);
        f.valid[inside] = false;
        f.radiance[inside * nc * 3..(inside + 1) * nc * 3].fill(1e6);
        f
    }

    /// three.js's `getLightProbeGridIrradiance` for this grid, by hand: the
    /// point moved half a spacing along the normal, outside the box (grown
    /// by 1% of a cell) nothing, `x` clamped to the first and last probes,
    /// the interpolated `c0 = a + b x`, three.js's constants, clamped at 0.
    /// `lmax` 1 leaves out `c6` and `c7`, 0 everything but `c0`.
    fn want(&self, p: Vec3, n: Vec3, lmax: usize) -> DVec3 {
        let n = n.normalize().as_dvec3();
        let spacing = DVec3::new(1.0, 0.5, 1.0);
        let s = p.as_dvec3() + n * spacing * 0.5;
        let (lo, hi) = (DVec3::new(-1.0, 0.0, 2.0), DVec3::new(3.0, 1.5, 5.0));
        let margin = 0.01 * spacing;
        if s.cmplt(lo - margin).any() || s.cmpgt(hi + margin).any() {
            return DVec3::ZERO;
        }
        let x = s.x.clamp(-0.5, 2.5);
        let c0 = self.a + self.b * x;
        let mut e = c0 * C0;
        if lmax >= 1 {
            e += self.c1 * C1 * n.y + self.c3 * C1 * n.x;
        }
        if lmax >= 2 {
            e += self.c6 * (C3 * n.z * n.z - C4) + self.c7 * C2 * n.x * n.z;
        }
        e.max(DVec3::ZERO)
    }
}

/// At random points (a fifth of them near or beyond the box) and
/// normals, `--lookup threejs` gives three.js's formula worked out by
/// hand, at lmax 2 (the grid's), 1 and 0 (zero-padded), and for a volume
/// of lmax 3 clipped to 2.
#[test]
fn threejs_lookup_is_threejs_formula_on_a_closed_form_light() {
    let g = Gradient::new();
    let mut rng = StdRng::seed_from_u64(33);
    let (lo, hi) = (Vec3::new(-1.0, 0.0, 2.0), Vec3::new(3.0, 1.5, 5.0));
    let mut worst = 0.0f64;
    let (mut outside, mut clamped) = (0, 0);
    for (file_lmax, lmax) in [(2, 2), (1, 1), (0, 0), (3, 2), (2, 1)] {
        let f = g.file(file_lmax);
        let view = f.view();
        let prepared = PreparedLookup::new(&view, Lookup::ThreeJs, lmax);
        for k in 0..300 {
            let reach = if k % 5 == 0 { 0.2 } else { 0.0 };
            let t = Vec3::new(
                rng.random_range(-reach..1.0 + reach),
                rng.random_range(-reach..1.0 + reach),
                rng.random_range(-reach..1.0 + reach),
            );
            let p = lo + (hi - lo) * t;
            let n = random_unit(&mut rng);
            let got = irradiance_at(&view, Lookup::ThreeJs, lmax, p, n);
            assert_eq!(prepared.irradiance_at(p, n), got);
            let want = g.want(p, n, lmax);
            outside += usize::from(want == DVec3::ZERO);
            clamped += usize::from(want.min_element() == 0.0 && want.max_element() > 0.0);
            worst = worst.max((got - want).abs().max_element());
        }
    }
    eprintln!("threejs lookup vs three.js's formula by hand: worst {worst:.2e}");
    assert!(
        outside > 20 && clamped > 5,
        "{outside} outside, {clamped} clamped"
    );
    assert!(worst < 1e-5, "worst {worst:.2e}");
}

/// Which degrees each lookup reads, and what it refuses.
#[test]
fn each_lookup_reads_its_own_lmax() {
    let g = Gradient::new();
    let f3 = g.file(3);
    let v3 = f3.view();
    let three = Lookup::ThreeJs.lmax_for(&v3, None).unwrap();
    assert_eq!(three.lmax, 2);
    assert!(three.note.unwrap().contains("degree 3 is left out"));
    let mut f5 = file([1, 1, 1], ([0.0; 3], [1.0; 3]), 5);
    f5.radiance[0] = 1.0;
    let five = Lookup::ThreeJs.lmax_for(&f5.view(), None).unwrap();
    assert!(five.note.unwrap().contains("degrees 3 to 5 are left out"));
    assert!(
        Lookup::ThreeJs
            .lmax_for(&v3, Some(3))
            .unwrap_err()
            .to_string()
            .contains("lmax 2 at most")
    );
    assert_eq!(Lookup::ThreeJs.lmax_for(&v3, Some(1)).unwrap().lmax, 1);
    let f1 = g.file(1);
    let one = Lookup::ThreeJs.lmax_for(&f1.view(), None).unwrap();
    assert_eq!((one.lmax, one.note), (1, None));
    // Bevy's export reads every degree; shlight's lookups what the GPU
    // shades.
    let mut f6 = file([1, 1, 1], ([0.0; 3], [1.0; 3]), 6);
    f6.radiance[0] = 1.0;
    let v6 = f6.view();
    assert_eq!(Lookup::Bevy.lmax_for(&v6, None).unwrap().lmax, 6);
    assert_eq!(Lookup::Bevy.lmax_for(&v6, Some(8)).unwrap().lmax, 6);
    assert_eq!(Lookup::Trilinear.lmax_for(&v6, None).unwrap().lmax, 4);
    assert!(
        Lookup::Shlight
            .lmax_for(&v6, Some(5))
            .unwrap_err()
            .to_string()
            .contains("lmax 4 at most")
    );
    // A view is what the lookups take.
    let _: VolumeView<'_> = v6;
}
