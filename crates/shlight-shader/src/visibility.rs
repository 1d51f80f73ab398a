//! DDGI's probe visibility (Majercik et al. 2019) as shader code: the
//! factor a probe's trilinear weight is multiplied by, from its octahedral
//! map of distance moments. The one definition is shlight-baked's
//! `visibility.rs` (`visibility_weights`, `Visibility::moments_at`) and
//! `octahedral.rs` (`oct_encode`, `bilinear`); this writes the same f32
//! operations in the same order, for every place shlight ships it: the
//! volume snippet's textures ([`crate::volume`]) and shlight-gpu's volume
//! pass (storage buffers). Only where the four texels of a bilinear lookup
//! come from differs, and the caller writes that.
//!
//! For the probe at `q` and the point `p' = p + b n` (moved along its
//! normal by the bias `b`):
//!
//! ```text
//! d     = |p' - q|,  (mean, mean_sq) = the probe's map at (p' - q) / d, bilinear
//! cheb  = 1 where d <= mean (or d = 0), else (v / (v + (d - mean)^2))^3,
//!         v = |mean_sq - mean^2|
//! w     = max(floor, cheb);  w = w (w^2 / crush^2) where w < crush
//! ```
//!
//! The map is `size x size` texels over the octahedral square `[-1, 1]^2`
//! (`oct_encode`: `(x, y) / (|x| + |y| + |z|)`, folded for `z < 0` with the
//! sign 1 at zero), texel centres at `(k + 1/2) / size` of the square; the
//! four texels around a direction's point are `a - 1 .. a` on each axis,
//! `a = clamp(floor(s) + 1, 0, size)`, where `-1` and `size` lie across the
//! map's folded edges (shlight-baked's `octahedral::wrap`): both layouts
//! store those texels beside the map, so the lookup reads them as they
//! are.

use crate::language::Lanes;
use crate::{Code, Language, ShaderLanguage, Type};

/// What the visibility code reads besides the point.
pub struct VisibilityInputs<'a> {
    /// The parameters that name a probe and its map, in the functions'
    /// signatures (the last one the probe, which the comments name).
    pub probe: &'a [(Type, &'a str)],
    /// Statements that define `t00`, `t10`, `t01` and `t11` (each a `vec2`
    /// `(mean, mean_sq)`), the probe's texels `(a.x - 1 + i, a.y - 1 + j)`
    /// of the map, from `a` (a `vec2<i32>` in `0..=size`) and the probe
    /// parameters.
    pub texels: &'a [String],
    /// The map's texels per side, an `i32` expression.
    pub map_size: &'a str,
    /// The least Chebyshev factor (shlight-baked's `CHEBYSHEV_FLOOR`).
    pub floor: &'a str,
    /// Weights below this are crushed (shlight-baked's `CRUSH`).
    pub crush: &'a str,
    /// Its square, as the f32 product `CRUSH * CRUSH`.
    pub crush_sq: &'a str,
}

/// The name of the bilinear moments lookup in `lang`: GLSL's
/// `shlight_volume_moments_at`, as the volume snippet's default uniform is
/// `shlight_volume_moments`.
#[must_use]
pub fn moments_function(lang: ShaderLanguage) -> &'static str {
    match lang {
        ShaderLanguage::Wgsl => "shlight_volume_moments",
        ShaderLanguage::Glsl => "shlight_volume_moments_at",
    }
}

/// The functions `shlight_volume_oct_encode(d)`, the moments lookup
/// ([`moments_function`]: `(probe..., dir)`, the bilinear `(mean,
/// mean_sq)` of the probe's map along the unit `dir`) and
/// `shlight_volume_visibility(probe..., q, biased)`, the probe's (at `q`)
/// factor for the biased point `p'` (the module docs' `w`), each preceded
/// by a blank line and its comment.
#[must_use]
pub fn visibility_code(lang: ShaderLanguage, inputs: &VisibilityInputs<'_>) -> String {
    let moments = moments_function(lang);
    let lang = Language::from(lang);
    let (f, v2, v3) = (Type::Float, Type::Vec2, Type::Vec3);
    let splat2 = |v: &str| lang.vector(v2, v);
    let probe = inputs.probe.last().map_or("", |p| p.1);
    let probe_args: Vec<&str> = inputs.probe.iter().map(|p| p.1).collect();
    let probe_args = probe_args.join(", ");
    let with_probe = |rest: &[(Type, &'static str)]| {
        let mut params = inputs.probe.to_vec();
        params.extend_from_slice(rest);
        params
    };
    let mut c = Code::new();
    c.line("");
    c.line("// The point of [-1, 1]^2 of the unit direction d (octahedral map).");
    c.open(format!(
        "{} {{",
        lang.signature(Some(v2), "shlight_volume_oct_encode", &[(v3, "d")])
    ));
    c.line(lang.let_(f, "l1", "abs(d.x) + abs(d.y) + abs(d.z)"));
    c.line(lang.let_(v2, "q", &lang.vector(v2, "d.x / l1, d.y / l1")));
    c.line(lang.let_(
        v2,
        "s",
        &lang.select_lanes(
            v2,
            Lanes::Splat("-1.0"),
            Lanes::Splat("1.0"),
            Lanes::Compare("q", ">=", "0.0"),
        ),
    ));
    c.line(lang.let_(
        v2,
        "folded",
        &format!("({} - abs(q.yx)) * s", splat2("1.0")),
    ));
    c.line(format!(
        "return {};",
        lang.select_all(v2, "q", "folded", "d.z < 0.0")
    ));
    c.close("}");
    c.line("");
    c.line(format!(
        "// The bilinear (mean, mean_sq) of probe {probe}'s distance map along dir."
    ));
    c.open(format!(
        "{} {{",
        lang.signature(Some(v2), moments, &with_probe(&[(v3, "dir")]))
    ));
    let (size, iv2) = (inputs.map_size, Type::IVec2);
    c.line(lang.let_(v2, "e", "shlight_volume_oct_encode(dir)"));
    c.line(lang.let_(
        v2,
        "s",
        &format!(
            "(e + {}) * 0.5 * {} - {}",
            splat2("1.0"),
            lang.cast(f, size),
            splat2("0.5")
        ),
    ));
    c.line(lang.let_(v2, "base", "floor(s)"));
    c.line(lang.let_(v2, "f", "s - base"));
    c.line(lang.let_(v2, "h", &format!("{} - f", splat2("1.0"))));
    c.line(lang.let_(
        iv2,
        "a",
        &format!(
            "clamp({} + {}, {}, {})",
            lang.cast(iv2, "base"),
            lang.vector(iv2, "1"),
            lang.vector(iv2, "0"),
            lang.vector(iv2, size)
        ),
    ));
    c.lines(inputs.texels);
    c.line("return h.x * h.y * t00 + f.x * h.y * t10 + h.x * f.y * t01 + f.x * f.y * t11;");
    c.close("}");
    c.line("");
    c.line(format!(
        "// Probe {probe}'s (at q) visibility of the biased point: Chebyshev's bound,"
    ));
    c.line("// floored, small values crushed.");
    c.open(format!(
        "{} {{",
        lang.signature(
            Some(f),
            "shlight_volume_visibility",
            &with_probe(&[(v3, "q"), (v3, "biased")])
        )
    ));
    c.line(lang.let_(v3, "v", "biased - q"));
    c.line(lang.let_(f, "d", "length(v)"));
    c.line(lang.var(f, "cheb", "1.0"));
    c.open("if (d > 0.0) {");
    c.line(lang.let_(v2, "m", &format!("{moments}({probe_args}, v / d)")));
    c.open("if (d > m.x) {");
    c.line(lang.let_(f, "variance", "abs(m.y - m.x * m.x)"));
    c.line(lang.let_(f, "x", "d - m.x"));
    c.line(lang.let_(f, "c", "variance / (variance + x * x)"));
    c.line("cheb = c * c * c;");
    c.close("}");
    c.close("}");
    c.line(lang.var(f, "w", &lang.max("cheb", inputs.floor)));
    c.open(format!("if (w < {}) {{", inputs.crush));
    c.line(format!("w = w * (w * w / {});", inputs.crush_sq));
    c.close("}");
    c.line("return w;");
    c.close("}");
    c.finish()
}
