//! An irradiance volume's lookup over three float textures, as `shlight
//! sample` shades: `shlight_volume_irradiance(p, n)` returns
//! `E(p, n) = sum_lm A_l L_lm(p) Y_lm(n)`, the probes' radiance
//! interpolated at the point `p` facing the unit normal `n`.
//!
//! Of the eight probes around `p` (trilinear weights from the cell
//! centres, clamped to the grid: shlight-baked's `ProbeGrid::trilinear`),
//! each weighs its trilinear weight times its validity, times its
//! visibility of `p` ([`crate::visibility`]) where the volume has distance
//! maps; the weights are renormalised, and `E = 0` where they sum to 0.
//! The coefficients are interpolated first and the SH sum
//! ([`crate::sh_sum`]) taken once.
//!
//! The textures (written by shlight-format's `volume_shader`), read with
//! integer loads only:
//!
//! - `sh`: texel `(x, y, i nz + z)` holds `(v L_i, v)` of probe `(x, y,
//!   z)`, `v` its validity;
//! - `probes`: texel `(x, y, z)` holds `(q, v)`, `q` the probe's position;
//! - `moments` (with visibility): probe `(x, y, z)`'s `s x s` map of
//!   `(mean, mean_sq)` in the tile at `(x (s+2), y (s+2))` of slice `z`, its
//!   texel `(a, b)` at `(a + 1, b + 1)` of the tile, the border across the
//!   map's folded edges.
//!
//! WGSL takes the textures as the function's first parameters; GLSL reads
//! them through the macros `SHLIGHT_VOLUME_SH(c)`, `SHLIGHT_VOLUME_PROBES(c)`
//! and `SHLIGHT_VOLUME_MOMENTS(c)`, each a `sampler3D` uniform's
//! `texelFetch` unless defined before the snippet.

use crate::coefficients::{BAND_WEIGHT_COMMENT, band_weight_list};
use crate::language::Lanes;
use crate::sh_sum::{ShSum, write_sh_sum};
use crate::visibility::{VisibilityInputs, visibility_code};
use crate::{Code, Language, ShaderLanguage, Type, float_literal};

/// A volume's numbers, written into the code as constants.
#[derive(Clone, Debug, PartialEq)]
pub struct VolumeConstants {
    /// The lmax the code shades to.
    pub lmax: usize,
    /// The grid box's lower corner.
    pub min: [f32; 3],
    /// A cell's size along each axis.
    pub cell: [f32; 3],
    /// Probes along x, y and z.
    pub resolution: [usize; 3],
    /// The visibility's constants, where the volume has distance maps.
    pub visibility: Option<VisibilityConstants>,
}

/// The visibility weights' constants (shlight-baked's `visibility.rs`, in
/// f32).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VisibilityConstants {
    /// How far the point is moved along its normal (`NORMAL_BIAS` times
    /// the smallest cell side).
    pub bias: f32,
    /// Texels per side of a probe's map.
    pub map_size: usize,
    /// The least Chebyshev factor (`CHEBYSHEV_FLOOR`).
    pub floor: f32,
    /// Weights below this are crushed (`CRUSH`).
    pub crush: f32,
}

/// A texture of the snippet read at the integer coordinates `at`: WGSL's
/// `textureLoad` of the parameter `name`, GLSL's macro
/// `SHLIGHT_VOLUME_{NAME}`.
fn fetch(lang: Language, name: &str, at: &str) -> String {
    match lang {
        Language::Wgsl => format!("textureLoad({name}, {at}, 0)"),
        _ => format!("SHLIGHT_VOLUME_{}({at})", name.to_ascii_uppercase()),
    }
}

/// The textures `names` as parameters (WGSL) or nothing (GLSL's are
/// global).
fn textures<'a>(lang: Language, names: &[&'a str]) -> Vec<(Type, &'a str)> {
    match lang {
        Language::Wgsl => names.iter().map(|n| (Type::Texture3d, *n)).collect(),
        _ => Vec::new(),
    }
}

/// `name(args)` with the textures `names` first in WGSL.
fn call(lang: Language, name: &str, names: &[&str], args: &str) -> String {
    let mut all: Vec<&str> = textures(lang, names).iter().map(|t| t.1).collect();
    all.push(args);
    format!("{name}({})", all.join(", "))
}

/// The snippet's code below its header comment: how to call it, the
/// constants, the visibility functions (with distance maps), then
/// `shlight_volume_coeff` and `shlight_volume_irradiance`.
#[must_use]
pub fn volume_code(language: ShaderLanguage, k: &VolumeConstants) -> String {
    let lang = Language::from(language);
    let lit = |v: f32| float_literal(f64::from(v));
    let (f, v3, iv3) = (Type::Float, Type::Vec3, Type::IVec3);
    let vis = k.visibility.is_some();
    let mut names = vec!["sh", "probes"];
    if vis {
        names.push("moments");
    }
    let mut c = Code::new();
    match lang {
        Language::Wgsl => {
            c.line(format!(
                "// Call shlight_volume_irradiance({}, p, n) with the textures bound as texture_3d<f32>.",
                names.join(", ")
            ));
            c.line("");
        }
        _ => {
            c.line(
                "// Call shlight_volume_irradiance(p, n). The textures are read through the macros",
            );
            c.line("// SHLIGHT_VOLUME_SH(c), SHLIGHT_VOLUME_PROBES(c) and SHLIGHT_VOLUME_MOMENTS(c) (c an");
            c.line("// ivec3); each not defined before this snippet reads a sampler3D uniform of its name");
            c.line("// in lower case with texelFetch.");
            c.line("");
            for name in &names {
                let (mac, uniform) = (
                    format!("SHLIGHT_VOLUME_{}", name.to_ascii_uppercase()),
                    format!("shlight_volume_{name}"),
                );
                c.line(format!("#ifndef {mac}"));
                c.line(format!("uniform highp sampler3D {uniform};"));
                c.line(format!("#define {mac}(c) texelFetch({uniform}, c, 0)"));
                c.line("#endif");
            }
            c.line("");
        }
    }
    let vec3_lit = |v: [f32; 3]| lang.vector(v3, &v.map(lit).join(", "));
    let [nx, ny, nz] = k.resolution;
    c.line(lang.constant(Type::Int, "SHLIGHT_VOLUME_LMAX", &k.lmax.to_string()));
    c.line(lang.constant(v3, "SHLIGHT_VOLUME_MIN", &vec3_lit(k.min)));
    c.line(lang.constant(v3, "SHLIGHT_VOLUME_CELL", &vec3_lit(k.cell)));
    c.line(lang.constant(
        iv3,
        "SHLIGHT_VOLUME_RESOLUTION",
        &lang.vector(iv3, &format!("{nx}, {ny}, {nz}")),
    ));
    c.line(BAND_WEIGHT_COMMENT);
    c.line(format!(
        "{}{}{}",
        lang.array_open(f, "SHLIGHT_VOLUME_A", &(k.lmax + 1).to_string()),
        band_weight_list(k.lmax),
        lang.array_close()
    ));
    c.line("// The eight probes around the point and their weights.");
    c.line(lang.private_array(iv3, "shlight_volume_corner", 8));
    c.line(lang.private_array(f, "shlight_volume_weight", 8));
    if let Some(v) = &k.visibility {
        c.line(lang.constant(f, "SHLIGHT_VOLUME_BIAS", &lit(v.bias)));
        c.line(lang.constant(
            Type::Int,
            "SHLIGHT_VOLUME_MAP_SIZE",
            &v.map_size.to_string(),
        ));
        c.line(lang.constant(f, "SHLIGHT_VOLUME_FLOOR", &lit(v.floor)));
        c.line(lang.constant(f, "SHLIGHT_VOLUME_CRUSH", &lit(v.crush)));
        c.line(lang.constant(f, "SHLIGHT_VOLUME_CRUSH_SQ", &lit(v.crush * v.crush)));
        // Probe g's map is the tile at (g.x (size + 2), g.y (size + 2)) of
        // slice g.z, map texel (i, j) at (i + 1, j + 1): tile texel a is
        // map texel a - 1.
        let mut probe = textures(lang, &["moments"]);
        probe.push((iv3, "g"));
        let mut texels =
            vec![lang.let_(Type::IVec2, "o", "g.xy * (SHLIGHT_VOLUME_MAP_SIZE + 2) + a")];
        for (name, dx, dy) in [
            ("t00", "", ""),
            ("t10", " + 1", ""),
            ("t01", "", " + 1"),
            ("t11", " + 1", " + 1"),
        ] {
            let at = lang.vector(iv3, &format!("o.x{dx}, o.y{dy}, g.z"));
            texels.push(lang.let_(
                Type::Vec2,
                name,
                &format!("{}.xy", fetch(lang, "moments", &at)),
            ));
        }
        c.raw(visibility_code(
            language,
            &VisibilityInputs {
                probe: &probe,
                texels: &texels,
                map_size: "SHLIGHT_VOLUME_MAP_SIZE",
                floor: "SHLIGHT_VOLUME_FLOOR",
                crush: "SHLIGHT_VOLUME_CRUSH",
                crush_sq: "SHLIGHT_VOLUME_CRUSH_SQ",
            },
        ));
    }
    c.line("");
    c.line("// Coefficient idx of the point: the eight probes' weighted sum.");
    let mut params = textures(lang, &["sh"]);
    params.push((Type::Int, "idx"));
    c.open(format!(
        "{} {{",
        lang.signature(Some(v3), "shlight_volume_coeff", &params)
    ));
    c.line(lang.var(v3, "sum", &lang.vector(v3, "0.0")));
    c.open(lang.for_open("k", "0", "k < 8", false));
    c.line(lang.let_(iv3, "g", "shlight_volume_corner[k]"));
    c.line(lang.let_(
        iv3,
        "at",
        &lang.vector(iv3, "g.x, g.y, idx * SHLIGHT_VOLUME_RESOLUTION.z + g.z"),
    ));
    c.line(format!(
        "sum += shlight_volume_weight[k] * {}.rgb;",
        fetch(lang, "sh", "at")
    ));
    c.close("}");
    c.line("return sum;");
    c.close("}");
    c.line("");
    c.line(format!(
        "// The irradiance E(p, normal) ({}).",
        match lang {
            Language::Wgsl => "module header",
            _ => "header above",
        }
    ));
    let mut params = textures(lang, &names);
    params.extend([(v3, "p"), (v3, "normal")]);
    c.open(format!(
        "{} {{",
        lang.signature(Some(v3), "shlight_volume_irradiance", &params)
    ));
    let splat = |v: &str| lang.vector(v3, v);
    c.line(lang.let_(v3, "n", "normalize(normal)"));
    c.line("// The trilinear cell of p, clamped to the grid (probes at cell centres).");
    c.line(lang.let_(v3, "res", &lang.cast(v3, "SHLIGHT_VOLUME_RESOLUTION")));
    c.line(lang.let_(
        v3,
        "u",
        &format!(
            "(p - SHLIGHT_VOLUME_MIN) / SHLIGHT_VOLUME_CELL - {}",
            splat("0.5")
        ),
    ));
    c.line(lang.let_(
        v3,
        "f",
        &format!(
            "clamp(u, {}, max(res - {}, {}))",
            splat("0.0"),
            splat("1.0"),
            splat("0.0")
        ),
    ));
    c.line(lang.let_(
        v3,
        "i0",
        &format!(
            "min(floor(f), max(res - {}, {}))",
            splat("2.0"),
            splat("0.0")
        ),
    ));
    c.line(lang.let_(v3, "t", "f - i0"));
    c.line(lang.let_(iv3, "lower", &lang.cast(iv3, "i0")));
    c.line(lang.let_(
        iv3,
        "upper",
        &format!(
            "min(lower + {}, SHLIGHT_VOLUME_RESOLUTION - {})",
            lang.vector(iv3, "1"),
            lang.vector(iv3, "1")
        ),
    ));
    c.line(lang.var(f, "total", "0.0"));
    c.open(lang.for_open("k", "0", "k < 8", false));
    c.line(lang.let_(
        Type::BVec3,
        "up",
        &lang.vector(Type::BVec3, "(k & 1) != 0, (k & 2) != 0, (k & 4) != 0"),
    ));
    c.line(lang.let_(
        iv3,
        "g",
        &lang.select_lanes(
            iv3,
            Lanes::Name("lower"),
            Lanes::Name("upper"),
            Lanes::Name("up"),
        ),
    ));
    c.line(lang.let_(
        v3,
        "tw",
        &lang.select_lanes(
            v3,
            Lanes::OneMinus("t"),
            Lanes::Name("t"),
            Lanes::Name("up"),
        ),
    ));
    c.line(lang.let_(Type::Vec4, "probe", &fetch(lang, "probes", "g")));
    c.line(lang.var(f, "w", "tw.x * tw.y * tw.z * probe.w"));
    if vis {
        c.line(format!(
            "w = w * {};",
            call(
                lang,
                "shlight_volume_visibility",
                &["moments"],
                "g, probe.xyz, p + n * SHLIGHT_VOLUME_BIAS"
            )
        ));
    }
    c.line("shlight_volume_corner[k] = g;");
    c.line("shlight_volume_weight[k] = w;");
    c.line("total += w;");
    c.close("}");
    c.open("if (total <= 0.0) {");
    c.line(format!("return {};", splat("0.0")));
    c.close("}");
    c.line("// sum over l, m of A_l L_lm(p) Y_lm(n): the normalised Legendre");
    c.line("// recurrences and the trig-free azimuth recurrence (shlight's snippets).");
    let coefficient = |i: &str| call(lang, "shlight_volume_coeff", &["sh"], i);
    write_sh_sum(
        lang,
        &mut c,
        &ShSum {
            lmax: "SHLIGHT_VOLUME_LMAX",
            direction: ["n.x", "n.y", "n.z"],
            legendre: "pl",
            comments: false,
            weight: &[lang.let_(f, "w", "SHLIGHT_VOLUME_A[l]")],
            coefficient: &coefficient,
        },
    );
    c.line("return sum / total;");
    c.close("}");
    c.finish()
}
