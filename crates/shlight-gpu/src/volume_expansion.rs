//! The WGSL of the volume pass that depends on lmax, written out as
//! straight-line code: the weighted basis `ShBasis`, and `volume_sum` and
//! `probe_sum`, which dot it with the probes' texels.
//!
//! ```text
//! sh_basis(d, factors).y{i} = f_l Y_i(d),   f_l = factors[l / 4][l % 4]  (A_l w_l)
//! volume_sum(p, n, y)       = (sum_i y{i} S_i, S_v)   S = the texels weighted at p
//! probe_sum(a, y)           = sum_i y{i} v L_i         the texels of the probe at a
//! ```
//!
//! with `S_v = sum_k w_k v_k` and `S_i = sum_k w_k v_k L_k,i` over the eight
//! probes around `p`, `w_k` the trilinear weight, times the probe's
//! visibility of `p` (moved along `n`) in [`VolumeVariant::Visibility`]
//! (`shaders/volume.wgsl`: texel `j` holds floats
//! `4j..4j+3` of `v, v L_i0 (rgb), v L_i1, ...`), so that
//! `volume_sum(p, sh_basis(n, irradiance_band))` divided by its `w` is the
//! renormalised interpolation of the probes' irradiance
//! `E(n) = sum_l A_l w_l sum_m L_lm Y_lm(n)`. The sums run over the
//! coefficients of [`volume_coefficients`] only: the degrees whose clamped
//! cosine eigenvalue `A_l` is 0 (odd `l >= 3`: degree 3 at lmax 4) add
//! nothing to `E`, so the texels leave them out (14 texels at lmax 4
//! instead of 19). `volume_sum` reads its texels filtered
//! (`volume_filtered`, one trilinear sample each) or by eight loads each
//! (`volume_loads`), one text per [`VolumeFetch`], or by the same eight
//! loads with the weights of `volume_visibility_at`
//! (`shaders/volume_visibility.wgsl`). The basis's statements are the
//! render passes' (shlight-shader's [`basis_statements`]): the recurrences of
//! shlight-core's [`Legendre`](shlight_core::sh::Legendre) with `sin(theta)^m` carried by
//! `C_m + i S_m = (x + i y)^m`, every factor an f32 literal, no loops and no
//! local array (a struct of named scalars stays in registers; an array
//! indexed at run time is what Mesa's llvmpipe keeps in memory lane by
//! lane, shaders/README.md).

use std::fmt::Write;

use shlight_core::sh::clamped_cosine_eigenvalue;

use crate::volume_fetch::VolumeFetch;
use shlight_baked::SHADED_MAX_LMAX;
use shlight_shader::basis::{BasisNames, basis_statements};
use shlight_shader::visibility::{VisibilityInputs, visibility_code};
use shlight_shader::{Language, ShaderLanguage, Type};

/// How `volume_sum` reads and weighs the texels of the eight probes around
/// a point: one shader module each.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum VolumeVariant {
    /// Trilinear weights (a volume without distance maps), the texels read
    /// as the [`VolumeFetch`] says.
    Trilinear(VolumeFetch),
    /// Eight loads per texel, each probe's trilinear weight times its
    /// visibility of the point (`volume_visibility_at`; a volume with
    /// distance maps).
    Visibility,
}

/// The volume module's generated WGSL for `lmax`, texels filtered.
pub(crate) fn volume_wgsl_filtered(lmax: usize) -> String {
    volume_wgsl(lmax, VolumeVariant::Trilinear(VolumeFetch::Filtered))
}

/// The volume module's generated WGSL for `lmax`, texels by eight loads.
pub(crate) fn volume_wgsl_loads(lmax: usize) -> String {
    volume_wgsl(lmax, VolumeVariant::Trilinear(VolumeFetch::Loads))
}

/// The volume module's generated WGSL for `lmax`, texels by eight loads
/// weighted by the probes' visibility, then the visibility lookup
/// ([`visibility_wgsl`]).
pub(crate) fn volume_wgsl_visibility(lmax: usize) -> String {
    let mut text = volume_wgsl(lmax, VolumeVariant::Visibility);
    text.push_str(&visibility_wgsl());
    text
}

/// The visibility lookup of the pass (`shlight_volume_visibility(k, q,
/// biased)`, probe `k` at `q`): shlight-shader's, the one the volume
/// snippets ship, reading the probe's map from the storage buffer
/// `probe_moments` as `volume.rs`'s `pair_texels` writes it (entry `(a, b)`
/// of a probe, `a` fastest over `0..=size`, holds its map's texels
/// `(a - 1, b - 1)` and `(a, b - 1)`: a bilinear lookup is two loads) and
/// its constants from the `Volume` uniform (`volume.map`,
/// `volume.visibility`), as shlight-baked's `visibility.rs` computes them.
#[must_use]
pub(crate) fn visibility_wgsl() -> String {
    let texels = [
        "// Entries (a.x, a.y) and (a.x, a.y + 1) of probe k's pairs: its map's texels".to_string(),
        "// (a.x - 1, a.y - 1), (a.x, a.y - 1) and (a.x - 1, a.y), (a.x, a.y).".to_string(),
        "let row = volume.map.x + 1u;".to_string(),
        "let at = k * volume.map.y + u32(a.y) * row + u32(a.x);".to_string(),
        "let lower = probe_moments[at];".to_string(),
        "let upper = probe_moments[at + row];".to_string(),
        "let t00 = lower.xy;".to_string(),
        "let t10 = lower.zw;".to_string(),
        "let t01 = upper.xy;".to_string(),
        "let t11 = upper.zw;".to_string(),
    ];
    let mut text = String::from(
        "\n// The visibility lookup (crates/shlight-gpu/src/volume_expansion.rs: shlight-shader's).\n",
    );
    text.push_str(&visibility_code(
        ShaderLanguage::Wgsl,
        &VisibilityInputs {
            probe: &[(Type::Uint, "k")],
            texels: &texels,
            map_size: "i32(volume.map.x)",
            floor: "volume.visibility.y",
            crush: "volume.visibility.z",
            crush_sq: "volume.visibility.w",
        },
    ));
    text
}

/// The WGSL text of `ShBasis`, `sh_basis`, `volume_sum` and `probe_sum`
/// for `lmax` (clamped to [`SHADED_MAX_LMAX`]) and `variant`.
#[must_use]
pub(crate) fn volume_wgsl(lmax: usize, variant: VolumeVariant) -> String {
    let lmax = lmax.min(SHADED_MAX_LMAX);
    let count = (lmax + 1) * (lmax + 1);
    let kept = volume_coefficients(lmax);
    let mut out = String::new();
    let _ = writeln!(
        out,
        "// Generated for lmax {lmax} (crates/shlight-gpu/src/volume_expansion.rs)."
    );
    let _ = writeln!(
        out,
        "// y{{i}} = f_l Y_i(d), i = l(l+1)+m, for the degrees whose A_l is not 0."
    );
    out.push_str("struct ShBasis {\n");
    for &i in &kept {
        let _ = writeln!(out, "    y{i}: f32,");
    }
    out.push_str("}\n\n");
    out.push_str("fn sh_basis(d: vec3<f32>, factors: array<vec4<f32>, 3>) -> ShBasis {\n");
    let mut fields = vec![String::new(); count];
    let body = basis_statements(Language::Wgsl, lmax, BasisNames::default(), |l, m, _| {
        let centre = l * (l + 1);
        if m == 0 {
            fields[centre] = format!("factors[{}][{}] * q{l}_0", l / 4, l % 4);
        } else {
            fields[centre + m] = format!("t{l}_{m} * c{m}");
            fields[centre - m] = format!("t{l}_{m} * s{m}");
        }
    });
    for line in body {
        let _ = writeln!(out, "    {line}");
    }
    let fields: Vec<&str> = kept.iter().map(|&i| fields[i].as_str()).collect();
    let _ = writeln!(out, "    return ShBasis({});", fields.join(", "));
    out.push_str("}\n\n");
    let texels = volume_texels(lmax);
    let dot = texel_dot(lmax);
    let (at, fetch) = match variant {
        VolumeVariant::Trilinear(VolumeFetch::Filtered) => {
            ("volume_filtered_at(p)", "volume_filtered")
        }
        VolumeVariant::Trilinear(VolumeFetch::Loads) => ("volume_loads_at(p)", "volume_loads"),
        VolumeVariant::Visibility => ("volume_visibility_at(p, n)", "volume_loads"),
    };
    out.push_str(
        "// (sum_i y{i} S_i, S_v) with S the texels weighted at p: S_v = sum_k w_k v_k,\n\
         // S_i = sum_k w_k v_k L_k,i.\n",
    );
    out.push_str("fn volume_sum(p: vec3<f32>, n: vec3<f32>, y: ShBasis) -> vec4<f32> {\n");
    let _ = writeln!(out, "    let at = {at};");
    for j in 0..texels {
        let _ = writeln!(out, "    let t{j} = {fetch}(at, {j}u);");
    }
    let _ = writeln!(out, "    return vec4<f32>({dot}, t0.x);");
    out.push_str("}\n\n");
    out.push_str("// sum_i y{i} v L_i of the probe whose texels start at a.\n");
    out.push_str("fn probe_sum(a: vec3<u32>, y: ShBasis) -> vec3<f32> {\n");
    for j in 0..texels {
        let _ = writeln!(out, "    let t{j} = probe_load(a, {j}u);");
    }
    let _ = writeln!(out, "    return {dot};");
    out.push_str("}\n");
    out
}

/// The SH coefficients `i = l(l+1)+m` to `lmax` (clamped to
/// [`SHADED_MAX_LMAX`]) that the volume pass keeps, in order: those of the
/// degrees whose clamped cosine eigenvalue `A_l` is not 0 (all but odd
/// `l >= 3`), the only ones the irradiance `sum_l A_l w_l sum_m L_lm Y_lm`
/// depends on.
#[must_use]
pub(crate) fn volume_coefficients(lmax: usize) -> Vec<usize> {
    let lmax = lmax.min(SHADED_MAX_LMAX);
    (0..=lmax)
        .filter(|&l| clamped_cosine_eigenvalue(l) != 0.0)
        .flat_map(|l| l * l..(l + 1) * (l + 1))
        .collect()
}

/// Texels per probe at `lmax` (clamped to [`SHADED_MAX_LMAX`]): the floats
/// `v, v L_i (rgb)` for the coefficients `i` of [`volume_coefficients`],
/// four to a texel.
#[must_use]
pub(crate) fn volume_texels(lmax: usize) -> usize {
    (3 * volume_coefficients(lmax).len() + 1).div_ceil(4)
}

/// `sum_i y.y{i} * vec3(rgb of coefficient i)` over texels `t{j}`, the
/// coefficient in slot `s` of [`volume_coefficients`] at floats
/// `f = 1 + 3 s + c` (channel `c`): texel `f / 4`, lane `f % 4`.
fn texel_dot(lmax: usize) -> String {
    const LANES: [char; 4] = ['x', 'y', 'z', 'w'];
    let terms: Vec<String> = volume_coefficients(lmax)
        .into_iter()
        .enumerate()
        .map(|(slot, i)| {
            let f = 1 + 3 * slot;
            let rgb = if f / 4 == (f + 2) / 4 {
                let lanes: String = (0..3).map(|c| LANES[(f + c) % 4]).collect();
                format!("t{}.{lanes}", f / 4)
            } else {
                let parts: Vec<String> = (0..3)
                    .map(|c| format!("t{}.{}", (f + c) / 4, LANES[(f + c) % 4]))
                    .collect();
                format!("vec3<f32>({})", parts.join(", "))
            };
            format!("y.y{i} * {rgb}")
        })
        .collect();
    terms.join("\n        + ")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The float each `t{j}.{lane}` of `text` names, in order of appearance
    /// within the dot product of coefficient `i` (`y.y{i} * ...`).
    fn floats_of(text: &str, i: usize) -> Vec<usize> {
        let start = text
            .find(&format!("y.y{i} * "))
            .unwrap_or_else(|| panic!("coefficient {i} missing:\n{text}"));
        let term = text[start..].split('+').next().unwrap();
        let term = term.split_once(" * ").unwrap().1.trim();
        let lane = |c: char| "xyzw".find(c).unwrap();
        if let Some(inner) = term.strip_prefix("vec3<f32>(") {
            inner
                .split(')')
                .next()
                .unwrap()
                .split(", ")
                .map(|p| {
                    let (t, l) = p.trim_start_matches('t').split_once('.').unwrap();
                    4 * t.parse::<usize>().unwrap() + lane(l.chars().next().unwrap())
                })
                .collect()
        } else {
            let (t, lanes) = term.trim_start_matches('t').split_once('.').unwrap();
            let t: usize = t.parse().unwrap();
            lanes
                .chars()
                .take_while(|c| c.is_ascii_lowercase())
                .map(|c| 4 * t + lane(c))
                .collect()
        }
    }

    #[test]
    fn every_coefficient_reads_its_own_three_floats_once() {
        for variant in [
            VolumeVariant::Trilinear(VolumeFetch::Filtered),
            VolumeVariant::Trilinear(VolumeFetch::Loads),
            VolumeVariant::Visibility,
        ] {
            for lmax in 0..=SHADED_MAX_LMAX {
                let text = volume_wgsl(lmax, variant);
                let count = (lmax + 1) * (lmax + 1);
                let texels = volume_texels(lmax);
                let kept = volume_coefficients(lmax);
                // Counted by hand: 1, 4, 9, 16, 25 coefficients less degree
                // 3's seven (A_3 = 0), 3 floats each, plus the validity.
                assert_eq!(kept.len(), [1, 4, 9, 9, 18][lmax]);
                assert_eq!(texels, [1, 4, 7, 7, 14][lmax]);
                for (slot, &i) in kept.iter().enumerate() {
                    // Float 0 is the validity; the kept coefficients' rgb
                    // follow in order.
                    let want = vec![1 + 3 * slot, 2 + 3 * slot, 3 + 3 * slot];
                    // Twice: volume_sum and probe_sum.
                    assert_eq!(text.matches(&format!("y.y{i} * ")).count(), 2, "{text}");
                    assert_eq!(floats_of(&text, i), want, "lmax {lmax} coefficient {i}");
                    assert!(text.contains(&format!("    y{i}: f32,")), "{text}");
                }
                for i in (0..count).filter(|i| !kept.contains(i)) {
                    // Degree 3: in the basis's recurrence, not in the sums.
                    assert!((9..16).contains(&i), "{i}");
                    assert!(!text.contains(&format!("y.y{i} ")), "{text}");
                    assert!(!text.contains(&format!("    y{i}: f32,")), "{text}");
                }
                assert!(!text.contains(&format!("y.y{count} ")), "{text}");
                for j in 0..texels {
                    assert!(text.contains(&format!("let t{j} = probe_load(a, {j}u);")));
                }
                assert!(!text.contains(&format!("let t{texels} ")), "{text}");
                let (own, others): (&str, &[&str]) = match variant {
                    VolumeVariant::Trilinear(VolumeFetch::Filtered) => {
                        ("volume_filtered_at(p)", &["volume_loads", "visibility"])
                    }
                    VolumeVariant::Trilinear(VolumeFetch::Loads) => {
                        ("volume_loads_at(p)", &["volume_filtered", "visibility"])
                    }
                    VolumeVariant::Visibility => (
                        "volume_visibility_at(p, n)",
                        &["volume_filtered", "volume_loads_at"],
                    ),
                };
                assert!(text.contains(&format!("let at = {own};")), "{text}");
                for other in others {
                    assert!(!text.contains(other), "{other} in {text}");
                }
            }
            // Beyond the volume's highest degree the text is the clamped one's.
            assert_eq!(
                volume_wgsl(8, variant),
                volume_wgsl(SHADED_MAX_LMAX, variant)
            );
        }
    }
}
