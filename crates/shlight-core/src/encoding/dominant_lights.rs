//! Dominant lights of an environment map: its bright, compact sources (a
//! sun, a lamp, a window) taken out as [`CapLight`]s with exact irradiance,
//! and the map without them (the residual) left to be projected to SH.

use core::f64::consts::PI;
use std::collections::HashMap;

use glam::DVec3;

use crate::encoding::cap_light::CapLight;
use crate::map::layout::env_map::EnvMap;
use crate::map::radiance_map::luminance;

/// The rules of [`extract_dominant_lights`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DominantLightOptions {
    /// Candidates are texels brighter than this many times the mean luminance.
    pub threshold: f64,
    /// Most lights kept.
    pub max_lights: usize,
    /// A light must carry at least this fraction of the map's luminance power.
    pub min_power_fraction: f64,
    /// Every texel of a light within this angle (radians) of its direction.
    pub max_half_angle: f64,
}

impl Default for DominantLightOptions {
    /// 20 times the mean, at most 4 lights, each at least 5% of the power
    /// and within 20 degrees.
    fn default() -> Self {
        Self {
            threshold: 20.0,
            max_lights: 4,
            min_power_fraction: 0.05,
            max_half_angle: 20f64.to_radians(),
        }
    }
}

/// The lights taken out of a map and the map without them.
#[derive(Clone, Debug)]
pub struct DominantLights {
    /// The lights, most powerful first.
    pub lights: Vec<CapLight<DVec3>>,
    /// The map's texels with each light's texels replaced by its background.
    pub residual: Vec<[f32; 3]>,
}

impl DominantLights {
    /// The lights' exact irradiance at unit normal `n`.
    #[must_use]
    pub fn irradiance(&self, n: DVec3) -> DVec3 {
        self.lights.iter().map(|l| l.irradiance(n)).sum()
    }
}

/// One texel of the map that holds a direction.
struct Texel {
    index: usize,
    d: DVec3,
    omega: f64,
    radiance: DVec3,
}

/// Finds the dominant lights of `map` and the residual (the method below).
///
/// 1. **Candidates.** Texels whose luminance exceeds `threshold` times the
///    map's mean luminance `Σ Y_k Ω_k / Σ Ω_k`.
/// 2. **Clusters.** Connected components of the candidates on the sphere:
///    two candidates are linked when their centres lie closer than
///    `2 sqrt(max_k Ω_k)` (twice the largest texel's side, so texel
///    neighbours in any layout — across the equirect seam, the poles and
///    cube edges — are linked and texels a gap apart are not), found with a
///    3-D grid of that cell size and union-find. Two lamps apart stay two
///    clusters: a light is never put between them.
/// 3. **Background.** The mean radiance `B` of the non-candidate texels in
///    a ring around each cluster (within its angular extent plus two link
///    radii); the cluster's texels are set to `B` in the residual.
/// 4. **The light** from the excess `ΔL_k = max(L_k - B, 0)`: power
///    `P = Σ ΔL_k Ω_k`, first moment `m = Σ Y(ΔL_k) Ω_k d_k`, direction
///    `m / |m|`, and the half-angle of the uniform cap with the same mean
///    resultant length `R = |m| / Σ Y(ΔL_k) Ω_k = (1 + cos α)/2`. With that
///    α the cap's irradiance, `P R (n · d)` wherever the whole cap is above
///    the horizon, equals the cluster's own `n · Σ ΔL_k Ω_k d_k` for any
///    shape: only normals near the cluster's horizon see a difference.
/// 5. **The test** of compactness and dominance, before anything is
///    extracted: a cluster is kept only if every texel lies within
///    `max_half_angle` of its direction and its luminance power is at least
///    `min_power_fraction` of the map's. At most `max_lights` are kept, the
///    most powerful first; a map with no such cluster yields none.
#[must_use]
pub fn extract_dominant_lights(map: &EnvMap<'_>, options: &DominantLightOptions) -> DominantLights {
    let omega = map.texel_solid_angles();
    let mut texels = Vec::with_capacity(map.pixels.len());
    for y in 0..map.height {
        for x in 0..map.width {
            let index = y * map.width + x;
            if omega[index] <= 0.0 {
                continue;
            }
            if let Some(d) = map.texel_direction(x, y) {
                let radiance = DVec3::from(map.pixels[index].map(f64::from));
                texels.push(Texel {
                    index,
                    d,
                    omega: omega[index],
                    radiance,
                });
            }
        }
    }
    let mut residual = map.pixels.to_vec();
    let total_omega: f64 = texels.iter().map(|t| t.omega).sum();
    let total_power: f64 = texels.iter().map(|t| luminance(t.radiance) * t.omega).sum();
    if total_power <= 0.0 || total_omega <= 0.0 {
        return DominantLights {
            lights: Vec::new(),
            residual,
        };
    }
    let level = options.threshold * total_power / total_omega;
    let bright: Vec<usize> = (0..texels.len())
        .filter(|&k| luminance(texels[k].radiance) > level)
        .collect();
    let link = 2.0 * texels.iter().map(|t| t.omega).fold(0.0, f64::max).sqrt();
    let clusters = connected_components(&texels, &bright, link);

    let mut is_bright = vec![false; texels.len()];
    for &k in &bright {
        is_bright[k] = true;
    }
    let mut found: Vec<(CapLight<DVec3>, Vec<usize>, DVec3)> = Vec::new();
    for members in clusters {
        // Direction and extent of the raw cluster, to find its ring.
        let raw: DVec3 = members
            .iter()
            .map(|&k| texels[k].d * luminance(texels[k].radiance) * texels[k].omega)
            .sum();
        let Some(centre) = raw.try_normalize() else {
            continue;
        };
        let extent = members
            .iter()
            .map(|&k| texels[k].d.angle_between(centre))
            .fold(0.0, f64::max);
        let raw_power: f64 = members
            .iter()
            .map(|&k| luminance(texels[k].radiance) * texels[k].omega)
            .sum();
        if extent > options.max_half_angle || raw_power < options.min_power_fraction * total_power {
            continue;
        }
        let ring_cos = (extent + 2.0 * link).min(PI).cos();
        let (mut sum, mut area) = (DVec3::ZERO, 0.0);
        for (k, t) in texels.iter().enumerate() {
            if !is_bright[k] && t.d.dot(centre) >= ring_cos {
                sum += t.radiance * t.omega;
                area += t.omega;
            }
        }
        let background = if area > 0.0 { sum / area } else { DVec3::ZERO };
        let (mut power, mut moment, mut lum) = (DVec3::ZERO, DVec3::ZERO, 0.0);
        for &k in &members {
            let t = &texels[k];
            let excess = (t.radiance - background).max(DVec3::ZERO) * t.omega;
            power += excess;
            moment += t.d * luminance(excess);
            lum += luminance(excess);
        }
        if lum < options.min_power_fraction * total_power {
            continue;
        }
        let Some(direction) = moment.try_normalize() else {
            continue;
        };
        let resultant = (moment.length() / lum).min(1.0);
        let half_angle = (2.0 * resultant - 1.0).clamp(-1.0, 1.0).acos();
        found.push((
            CapLight {
                direction,
                half_angle,
                power,
            },
            members,
            background,
        ));
    }
    found.sort_by(|a, b| luminance(b.0.power).total_cmp(&luminance(a.0.power)));
    found.truncate(options.max_lights);
    let mut lights = Vec::with_capacity(found.len());
    for (light, members, background) in found {
        for k in members {
            residual[texels[k].index] = background.as_vec3().to_array();
        }
        lights.push(light);
    }
    DominantLights { lights, residual }
}

/// The connected components of `bright` (indices into `texels`) under
/// "centres closer than `link`", by a 3-D grid of cell `link` and
/// union-find; each component's members in ascending order.
fn connected_components(texels: &[Texel], bright: &[usize], link: f64) -> Vec<Vec<usize>> {
    let cell = |d: DVec3| {
        let c = (d / link).floor();
        (c.x as i64, c.y as i64, c.z as i64)
    };
    let mut grid: HashMap<(i64, i64, i64), Vec<usize>> = HashMap::new();
    for (i, &k) in bright.iter().enumerate() {
        grid.entry(cell(texels[k].d)).or_default().push(i);
    }
    let mut parent: Vec<usize> = (0..bright.len()).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    let link2 = link * link;
    for (i, &k) in bright.iter().enumerate() {
        let d = texels[k].d;
        let (cx, cy, cz) = cell(d);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let Some(others) = grid.get(&(cx + dx, cy + dy, cz + dz)) else {
                        continue;
                    };
                    for &j in others {
                        if j > i && (texels[bright[j]].d - d).length_squared() < link2 {
                            let (a, b) = (root(&mut parent, i), root(&mut parent, j));
                            if a != b {
                                parent[a.max(b)] = a.min(b);
                            }
                        }
                    }
                }
            }
        }
    }
    let mut groups: HashMap<usize, Vec<usize>> = HashMap::new();
    for (i, &k) in bright.iter().enumerate() {
        let r = root(&mut parent, i);
        groups.entry(r).or_default().push(k);
    }
    let mut out: Vec<Vec<usize>> = groups.into_values().collect();
    out.sort_by_key(|g| g[0]);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::layout::kind::Layout;
    use crate::map::layout::texel_grid::TexelGrid;
    use crate::map::orientation::MapOrientation;
    use crate::map::texel_means::texel_means;

    /// The bounds: direction within half a degree, power within 1%.
    const ANGLE: f64 = 0.5;
    const POWER: f64 = 0.01;
    const W: usize = 512;
    const H: usize = 256;

    /// A sun: a uniform cap of half-angle `deg` degrees about `d` of power `p`.
    struct Sun {
        d: DVec3,
        deg: f64,
        p: DVec3,
    }

    impl Sun {
        fn radiance(&self, w: DVec3) -> DVec3 {
            let a = self.deg.to_radians();
            if w.dot(self.d) >= a.cos() {
                self.p / crate::sh::zonal::cap_solid_angle(a)
            } else {
                DVec3::ZERO
            }
        }
    }

    /// The maps' texels.
    fn grid() -> TexelGrid {
        TexelGrid::new(Layout::Equirect, (W, H), MapOrientation::default()).unwrap()
    }

    /// A blue gradient sky (brighter up) plus `suns`, as texel means.
    fn map_with(suns: &[Sun]) -> Vec<[f32; 3]> {
        texel_means(
            &grid(),
            8,
            |w| {
                let sky = DVec3::new(0.2, 0.3, 0.5) * (1.0 + 0.5 * w.y);
                sky + suns.iter().map(|s| s.radiance(w)).sum::<DVec3>()
            },
            &|_| {},
        )
    }

    fn extract(px: &[[f32; 3]]) -> DominantLights {
        let map = EnvMap::new(Layout::Equirect, MapOrientation::default(), W, H, px).unwrap();
        extract_dominant_lights(&map, &DominantLightOptions::default())
    }

    fn check(light: &CapLight<DVec3>, sun: &Sun) {
        let angle = light.direction.angle_between(sun.d).to_degrees();
        assert!(angle < ANGLE, "direction off by {angle}°");
        let rel = ((light.power - sun.p) / sun.p).abs().max_element();
        assert!(rel < POWER, "power {:?} against {:?}", light.power, sun.p);
    }

    #[test]
    fn one_sun_is_found_with_its_direction_and_power() {
        let sun = Sun {
            d: DVec3::new(0.3, 0.8, 0.5).normalize(),
            deg: 1.5,
            p: DVec3::new(20.0, 18.0, 14.0),
        };
        let found = extract(&map_with(&[sun]));
        let sun = Sun {
            d: DVec3::new(0.3, 0.8, 0.5).normalize(),
            deg: 1.5,
            p: DVec3::new(20.0, 18.0, 14.0),
        };
        assert_eq!(found.lights.len(), 1, "{:?}", found.lights);
        check(&found.lights[0], &sun);
        // Its half-angle is the sun's, to about a texel (0.7°).
        assert!((found.lights[0].half_angle.to_degrees() - 1.5).abs() < 0.7);
    }

    #[test]
    fn a_sun_across_the_seam_and_one_near_the_pole() {
        for d in [DVec3::new(-1.0, 0.1, 0.01), DVec3::new(0.05, 0.995, 0.02)] {
            let sun = || Sun {
                d: d.normalize(),
                deg: 1.0,
                p: DVec3::splat(10.0),
            };
            let found = extract(&map_with(&[sun()]));
            assert_eq!(found.lights.len(), 1, "{d}: {:?}", found.lights);
            check(&found.lights[0], &sun());
        }
    }

    #[test]
    fn two_lamps_give_two_lights_never_one_between() {
        let a = DVec3::new(0.6, 0.2, 0.7).normalize();
        for b in [-a, (a + DVec3::new(0.0, 0.25, 0.0)).normalize()] {
            let suns = || {
                [
                    Sun {
                        d: a,
                        deg: 1.0,
                        p: DVec3::new(8.0, 6.0, 4.0),
                    },
                    Sun {
                        d: b,
                        deg: 2.0,
                        p: DVec3::new(5.0, 5.0, 6.0),
                    },
                ]
            };
            let found = extract(&map_with(&suns()));
            assert_eq!(found.lights.len(), 2, "{b}: {:?}", found.lights);
            let [sa, sb] = suns();
            check(&found.lights[0], &sa);
            check(&found.lights[1], &sb);
        }
    }

    #[test]
    fn no_compact_source_extracts_none() {
        // A sky alone; a broad bright cap (40°); a thin bright band all
        // round the horizon (candidates, but not compact).
        let broad = texel_means(
            &grid(),
            4,
            |w| {
                DVec3::splat(if w.y > 40f64.to_radians().cos() {
                    10.0
                } else {
                    0.1
                })
            },
            &|_| {},
        );
        let band = texel_means(
            &grid(),
            4,
            |w| DVec3::splat(if w.y.abs() < 0.01 { 100.0 } else { 0.1 }),
            &|_| {},
        );
        for px in [map_with(&[]), broad, band] {
            let found = extract(&px);
            assert!(found.lights.is_empty(), "{:?}", found.lights);
            assert_eq!(found.residual, px, "nothing extracted, nothing changed");
        }
    }

    #[test]
    fn light_plus_residual_keeps_the_maps_irradiance() {
        let sun = Sun {
            d: DVec3::new(0.0, 0.5, -0.8).normalize(),
            deg: 2.0,
            p: DVec3::splat(30.0),
        };
        let px = map_with(&[sun]);
        let found = extract(&px);
        assert_eq!(found.lights.len(), 1);
        let o = MapOrientation::default();
        let full = EnvMap::new(Layout::Equirect, o, W, H, &px).unwrap();
        let rest = EnvMap::new(Layout::Equirect, o, W, H, &found.residual).unwrap();
        let normals = crate::sh::quadrature::fibonacci_sphere(300);
        let e_full = crate::map::irradiance_map::irradiance_brute_force(&full, &normals, &|_| {});
        let e_rest = crate::map::irradiance_map::irradiance_brute_force(&rest, &normals, &|_| {});
        let peak = e_full.iter().map(|e| e.max_element()).fold(0.0, f64::max);
        for ((n, a), b) in normals.iter().zip(&e_full).zip(&e_rest) {
            let d = (*b + found.irradiance(*n) - *a).abs().max_element() / peak;
            // The cap model differs from the texels only near its horizon.
            assert!(d < 2e-3, "{n}: {d}");
        }
    }
}
