//! A probe volume for engines' own shaders: its probes as three float
//! textures and a WGSL or GLSL snippet that shades with them exactly as
//! `shlight sample --lookup shlight` does (the visibility-weighted lookup of
//! shlight-baked's `visibility.rs`, or the validity-weighted trilinear one
//! for a volume without distance maps).
//!
//! # The textures
//! For an `nx x ny x nz` grid of lmax `L` (`C = (L+1)^2` coefficients),
//! each a KTX2 file of one level ([`crate::ktx2`]):
//!
//! - `sh`: `RGBA32F`, `nx x ny x C nz` texels: texel `(x, y, i nz + z)`
//!   holds `(v L_i, v)` of probe `(x, y, z)`, `L_i` its radiance
//!   coefficient `i = l(l+1)+m` (shlight's basis, the file's frame, linear
//!   Rec.709) and `v` its validity (1, or 0 inside geometry). Coefficient
//!   `i` is a sub-volume of its own, so an engine's plain trilinear sampler
//!   may also filter it (`rgb / a` is then the valid probes' trilinear
//!   mean, as `--lookup trilinear`).
//! - `probes`: `RGBA32F`, `nx x ny x nz`: `(q, v)`, `q` the probe's
//!   position (its cell's centre plus the offset the bake moved it by).
//! - `moments` (volumes with distance maps): `RG32F`, `nx (s+2) x ny (s+2) x
//!   nz` for maps of `s x s` texels: probe `(x, y, z)`'s map is the tile at
//!   `(x (s+2), y (s+2))` of slice `z`, its texel `(a, b)` (each `0..s`) at
//!   `(a + 1, b + 1)` of the tile, `(mean, mean_sq)` of the distance; the
//!   tile's one-texel border repeats the texels across the octahedral map's
//!   folded edges (shlight-baked's `octahedral::wrap`), so a bilinear
//!   lookup reads four texels of one tile, in every direction.
//!
//! Every texel is read with an integer load (`textureLoad`, `texelFetch`):
//! no sampler, no filtering, so the textures may stay non-filterable floats
//! (WebGL2 and WebGPU both load `RGBA32F` and `RG32F`).
//!
//! # The snippet
//! `shlight_volume_irradiance(p, n)` (WGSL: the three textures are its
//! first parameters) returns `E(p, n) = sum_lm A_l L_lm(p) Y_lm(n)`, the
//! irradiance `shlight sample` reports at the point `p` (scene units)
//! facing `n` (the file's frame); a Lambertian surface of albedo `rho`
//! leaves `rho / pi E`. The grid, the lmax and the visibility constants
//! are written into it as constants.

use glam::Vec3;
use shlight_baked::octahedral::wrap;
use shlight_baked::visibility::{CHEBYSHEV_FLOOR, CRUSH, NORMAL_BIAS};
use shlight_baked::{SHADED_MAX_LMAX, VolumeView};
use shlight_core::sh::sh_count;

use crate::export::{band_weight_list, float_literal};
use crate::ktx2::{Ktx2Format, write_ktx2};
use crate::{FormatError, Result, ShvolFile};

/// The shading languages the snippet is written in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShaderLanguage {
    /// WGSL (WebGPU, Bevy, wgpu): the textures are the function's
    /// parameters.
    Wgsl,
    /// GLSL (`#version 300 es` / WebGL2, and desktop 330 and later): the
    /// textures are `sampler3D` uniforms, or whatever the three fetch
    /// macros are defined to first.
    Glsl,
}

/// One of the textures the snippet reads.
#[derive(Clone, Debug, PartialEq)]
pub struct VolumeTexture {
    /// `sh`, `probes` or `moments`: the file is `{stem}.{name}.ktx2`.
    pub name: &'static str,
    /// The texel format (`RGBA32F` or `RG32F`).
    pub format: Ktx2Format,
    /// Width, height, depth.
    pub size: [usize; 3],
    /// The texels' channels, x fastest, then y, then z.
    pub texels: Vec<f32>,
}

impl VolumeTexture {
    /// The texture as a KTX2 file.
    #[must_use]
    pub fn ktx2(&self, writer: &str) -> Vec<u8> {
        let bytes: Vec<u8> = self.texels.iter().flat_map(|v| v.to_le_bytes()).collect();
        write_ktx2(self.format, self.size, &bytes, writer)
    }
}

/// A volume ready for an engine's shader: the snippet, the textures it
/// reads and notes for the user.
#[derive(Clone, Debug, PartialEq)]
pub struct VolumeShader {
    /// The snippet's text.
    pub text: String,
    /// `sh`, `probes`, and `moments` where the volume has distance maps.
    pub textures: Vec<VolumeTexture>,
    /// Remarks for the user, one sentence each.
    pub notes: Vec<String>,
}

/// The snippet in `language` and the textures of `file`, shaded to the
/// lmax `shlight sample` shades it to (the file's, at most
/// [`SHADED_MAX_LMAX`]; a note says when degrees are left out). `stem` is
/// the textures' file stem the snippet's header names.
///
/// # Errors
/// A volume whose coefficients do not fit 32-bit floats.
pub fn volume_shader(
    file: &ShvolFile,
    language: ShaderLanguage,
    stem: &str,
) -> Result<VolumeShader> {
    let view = file.view();
    let lmax = view.lmax.min(SHADED_MAX_LMAX);
    let mut notes = Vec::new();
    if lmax < view.lmax {
        notes.push(format!(
            "the volume holds lmax {}; the snippet shades to lmax {lmax}, as shlight's volume pass and `shlight sample` do",
            view.lmax
        ));
    }
    if let Some(v) = view.radiance.iter().find(|v| !v.is_finite()) {
        return Err(FormatError::Export(format!(
            "a probe coefficient is {v}, which a shader cannot hold"
        )));
    }
    let mut textures = vec![sh_texture(&view, lmax), probes_texture(&view)];
    if view.visibility.is_some() {
        textures.push(moments_texture(&view));
    }
    let constants = Constants::new(&view, lmax, stem, file);
    let text = match language {
        ShaderLanguage::Wgsl => wgsl(&constants),
        ShaderLanguage::Glsl => glsl(&constants),
    };
    Ok(VolumeShader {
        text,
        textures,
        notes,
    })
}

/// The `sh` texture: coefficient `i` of probe `(x, y, z)` at `(x, y, i nz +
/// z)`, premultiplied by the validity, which alpha holds.
fn sh_texture(view: &VolumeView<'_>, lmax: usize) -> VolumeTexture {
    let [nx, ny, nz] = view.grid.resolution;
    let (count, per) = (sh_count(lmax), sh_count(view.lmax));
    let probes = nx * ny * nz;
    let mut texels = vec![0.0f32; 4 * probes * count];
    for k in 0..probes {
        let v = if view.valid[k] { 1.0 } else { 0.0 };
        let [x, y, z] = view.grid.grid_index(k);
        for i in 0..count {
            let rgb = &view.radiance[3 * (k * per + i)..][..3];
            let at = 4 * (x + nx * (y + ny * (i * nz + z)));
            texels[at..at + 4].copy_from_slice(&[v * rgb[0], v * rgb[1], v * rgb[2], v]);
        }
    }
    VolumeTexture {
        name: "sh",
        format: Ktx2Format::Rgba32Float,
        size: [nx, ny, count * nz],
        texels,
    }
}

/// The `probes` texture: each probe's position and validity.
fn probes_texture(view: &VolumeView<'_>) -> VolumeTexture {
    let texels = (0..view.grid.probe_count())
        .flat_map(|k| {
            let q = view.position(k);
            [q.x, q.y, q.z, if view.valid[k] { 1.0 } else { 0.0 }]
        })
        .collect();
    VolumeTexture {
        name: "probes",
        format: Ktx2Format::Rgba32Float,
        size: view.grid.resolution,
        texels,
    }
}

/// The `moments` texture: each probe's map in a tile with a border across
/// the folded edges.
///
/// # Panics
/// If the view holds no distance maps.
fn moments_texture(view: &VolumeView<'_>) -> VolumeTexture {
    let vis = view.visibility.as_ref().expect("distance maps");
    let (s, [nx, ny, nz]) = (vis.size, view.grid.resolution);
    let tile = s + 2;
    let (w, h) = (nx * tile, ny * tile);
    let per = 2 * s * s;
    let mut texels = vec![0.0f32; 2 * w * h * nz];
    for k in 0..view.grid.probe_count() {
        let [x, y, z] = view.grid.grid_index(k);
        let map = &vis.moments[k * per..][..per];
        for b in 0..tile {
            for a in 0..tile {
                let (i, j) = wrap(a as i32 - 1, b as i32 - 1, s);
                let at = 2 * (x * tile + a + w * (y * tile + b + h * z));
                texels[at..at + 2].copy_from_slice(&map[2 * (j * s + i)..][..2]);
            }
        }
    }
    VolumeTexture {
        name: "moments",
        format: Ktx2Format::Rg32Float,
        size: [w, h, nz],
        texels,
    }
}

/// What the snippets write as constants, as literals.
struct Constants {
    header: String,
    lmax: usize,
    min: [String; 3],
    cell: [String; 3],
    resolution: [usize; 3],
    band_weights: String,
    /// `(bias, map size, floor, crush, crush^2)` where the volume has
    /// distance maps.
    visibility: Option<(String, usize, String, String, String)>,
}

impl Constants {
    fn new(view: &VolumeView<'_>, lmax: usize, stem: &str, file: &ShvolFile) -> Self {
        let (frame, generator) = (&file.frame, &file.generator);
        let grid = &view.grid;
        let lit = |v: f32| float_literal(f64::from(v));
        let vec = |v: Vec3| v.to_array().map(lit);
        let visibility = view.visibility.as_ref().map(|v| {
            let bias = NORMAL_BIAS * grid.cell().min_element();
            (
                lit(bias),
                v.size,
                lit(CHEBYSHEV_FLOOR),
                lit(CRUSH),
                lit(CRUSH * CRUSH),
            )
        });
        let [nx, ny, nz] = grid.resolution;
        let count = sh_count(lmax);
        let mut header = format!(
            "shlight irradiance volume ({generator}): E(p, n) = sum_lm A_l L_lm(p) Y_lm(n), the irradiance\n\
             `shlight sample --lookup {lookup}` gives at the point p facing the unit normal n (a\n\
             Lambertian surface of albedo rho leaves rho / pi E). Real orthonormal SH with the\n\
             Condon-Shortley phase, index l(l+1)+m, lmax {lmax}, the scene's {frame} frame, linear Rec.709.\n\
             Grid: {nx}x{ny}x{nz} probes at the cell centres of the box ({x0}, {y0}, {z0})..({x1}, {y1}, {z1}).\n\
             Textures (KTX2, integer loads only, docs/shvol.md \"Engines' shaders\"):\n\
             - {stem}.sh.ktx2: RGBA32F {nx}x{ny}x{d}: texel (x, y, i*{nz} + z) = (v L_i, v) of probe (x, y, z).\n\
             - {stem}.probes.ktx2: RGBA32F {nx}x{ny}x{nz}: (position, v) of probe (x, y, z).\n",
            lookup = if visibility.is_some() {
                "shlight"
            } else {
                "trilinear"
            },
            d = count * nz,
            x0 = grid.min.x,
            y0 = grid.min.y,
            z0 = grid.min.z,
            x1 = grid.max.x,
            y1 = grid.max.y,
            z1 = grid.max.z,
        );
        if let Some((_, s, ..)) = &visibility {
            let t = s + 2;
            header.push_str(&format!(
                "- {stem}.moments.ktx2: RG32F {}x{}x{nz}: probe (x, y, z)'s {s}x{s} map of (mean, mean_sq)\n  \
                 distance in the tile at ({t} x, {t} y) of slice z, one border texel across the folded edges.\n\
                 Each probe's trilinear weight is multiplied by its Chebyshev visibility of p + bias n\n\
                 (DDGI), floored and crushed, then the weights are renormalised.\n",
                nx * t,
                ny * t,
            ));
        } else {
            header.push_str(
                "The valid probes' trilinear weights, renormalised (the volume holds no distance maps).\n",
            );
        }
        Self {
            header,
            lmax,
            min: vec(grid.min),
            cell: vec(grid.cell()),
            resolution: grid.resolution,
            band_weights: band_weight_list(lmax),
            visibility,
        }
    }

    fn commented(&self, comment: &str) -> String {
        self.header
            .lines()
            .map(|l| format!("{comment} {l}\n"))
            .collect()
    }
}

/// The basis loop shared by both languages up to spelling: `{v3}`, `{f}`
/// (float), `{i}` (int), `{decl}` (a local's opening: `let`/`var` or a
/// type), `{coeff}` (the call that reads coefficient `idx`).
const BASIS_LOOP: &str = r#"    // sum over l, m of A_l L_lm(p) Y_lm(n): the normalised Legendre
    // recurrences and the trig-free azimuth recurrence (shlight's snippets).
    {decl_f_mut} c{ty_f} = 1.0; // sin^m(theta) cos(m phi)
    {decl_f_mut} s{ty_f} = 0.0; // sin^m(theta) sin(m phi)
    {decl_f_mut} pmm{ty_f} = 0.28209479177387814; // Pbar_m^m / sin^m(theta)
    {decl_v3_mut} sum = {v3}(0.0, 0.0, 0.0);
    for ({loop_m} = 0; m <= SHLIGHT_VOLUME_LMAX; m++) {
        if (m > 0) {
            {decl_f} cn = n.x * c - n.y * s;
            s = n.x * s + n.y * c;
            c = cn;
            pmm = pmm * -sqrt({f}(2 * m + 1) / {f}(2 * m));
        }
        {decl_f_mut} p1{ty_f} = 0.0;
        {decl_f_mut} p2{ty_f} = 0.0;
        for ({loop_l} = m; l <= SHLIGHT_VOLUME_LMAX; l++) {
            {decl_f_mut} pl{ty_f} = pmm;
            if (l == m + 1) {
                pl = sqrt({f}(2 * m + 3)) * n.z * pmm;
            } else if (l > m + 1) {
                {decl_f} a = sqrt({f}(4 * l * l - 1) / {f}(l * l - m * m));
                {decl_f} b = sqrt({f}((l - 1) * (l - 1) - m * m) / {f}(4 * (l - 1) * (l - 1) - 1));
                pl = a * (n.z * p1 - b * p2);
            }
            p2 = p1;
            p1 = pl;
            {decl_f} w = SHLIGHT_VOLUME_A[l];
            if (m == 0) {
                sum += {coeff_0} * (w * pl);
            } else {
                {decl_f} t = w * 1.4142135623730951 * pl;
                sum += {coeff_p} * (t * c) + {coeff_n} * (t * s);
            }
        }
    }
"#;

fn fill(template: &str, pairs: &[(&str, &str)]) -> String {
    let mut s = template.to_string();
    for (k, v) in pairs {
        s = s.replace(&format!("{{{k}}}"), v);
    }
    s
}

fn wgsl(k: &Constants) -> String {
    let [nx, ny, nz] = k.resolution;
    let mut s = k.commented("//");
    s.push_str(&format!(
        "// Call shlight_volume_irradiance(sh, probes{moments}, p, n) with the textures bound as texture_3d<f32>.\n\n",
        moments = if k.visibility.is_some() {
            ", moments"
        } else {
            ""
        }
    ));
    s.push_str(&format!(
        "const SHLIGHT_VOLUME_LMAX: i32 = {};\n\
         const SHLIGHT_VOLUME_MIN: vec3<f32> = vec3<f32>({}, {}, {});\n\
         const SHLIGHT_VOLUME_CELL: vec3<f32> = vec3<f32>({}, {}, {});\n\
         const SHLIGHT_VOLUME_RESOLUTION: vec3<i32> = vec3<i32>({nx}, {ny}, {nz});\n\
         // A_l, the clamped-cosine eigenvalues: irradiance is A_l times radiance, band by band.\n\
         var<private> SHLIGHT_VOLUME_A: array<f32, {n}> = array<f32, {n}>({});\n\
         // The eight probes around the point and their weights.\n\
         var<private> shlight_volume_corner: array<vec3<i32>, 8>;\n\
         var<private> shlight_volume_weight: array<f32, 8>;\n",
        k.lmax,
        k.min[0],
        k.min[1],
        k.min[2],
        k.cell[0],
        k.cell[1],
        k.cell[2],
        k.band_weights,
        n = k.lmax + 1,
    ));
    let (moments_param, weight) = if let Some((bias, size, floor, crush, crush2)) = &k.visibility {
        s.push_str(&format!(
            "const SHLIGHT_VOLUME_BIAS: f32 = {bias};\n\
             const SHLIGHT_VOLUME_MAP_SIZE: i32 = {size};\n\
             const SHLIGHT_VOLUME_FLOOR: f32 = {floor};\n\
             const SHLIGHT_VOLUME_CRUSH: f32 = {crush};\n\
             const SHLIGHT_VOLUME_CRUSH_SQ: f32 = {crush2};\n"
        ));
        s.push_str(WGSL_VISIBILITY);
        (
            ", moments: texture_3d<f32>",
            "        w = w * shlight_volume_visibility(moments, g, probe.xyz, p + n * SHLIGHT_VOLUME_BIAS);\n",
        )
    } else {
        ("", "")
    };
    s.push_str(
        r#"
// Coefficient idx of the point: the eight probes' weighted sum.
fn shlight_volume_coeff(sh: texture_3d<f32>, idx: i32) -> vec3<f32> {
    var sum = vec3<f32>(0.0);
    for (var k = 0; k < 8; k++) {
        let g = shlight_volume_corner[k];
        let at = vec3<i32>(g.x, g.y, idx * SHLIGHT_VOLUME_RESOLUTION.z + g.z);
        sum += shlight_volume_weight[k] * textureLoad(sh, at, 0).rgb;
    }
    return sum;
}
"#,
    );
    s.push_str(&format!(
        r#"
// The irradiance E(p, normal) (module header).
fn shlight_volume_irradiance(sh: texture_3d<f32>, probes: texture_3d<f32>{moments_param}, p: vec3<f32>, normal: vec3<f32>) -> vec3<f32> {{
    let n = normalize(normal);
    // The trilinear cell of p, clamped to the grid (probes at cell centres).
    let res = vec3<f32>(SHLIGHT_VOLUME_RESOLUTION);
    let u = (p - SHLIGHT_VOLUME_MIN) / SHLIGHT_VOLUME_CELL - vec3<f32>(0.5);
    let f = clamp(u, vec3<f32>(0.0), max(res - vec3<f32>(1.0), vec3<f32>(0.0)));
    let i0 = min(floor(f), max(res - vec3<f32>(2.0), vec3<f32>(0.0)));
    let t = f - i0;
    let lower = vec3<i32>(i0);
    let upper = min(lower + vec3<i32>(1), SHLIGHT_VOLUME_RESOLUTION - vec3<i32>(1));
    var total = 0.0;
    for (var k = 0; k < 8; k++) {{
        let up = vec3<bool>((k & 1) != 0, (k & 2) != 0, (k & 4) != 0);
        let g = select(lower, upper, up);
        let tw = select(vec3<f32>(1.0) - t, t, up);
        let probe = textureLoad(probes, g, 0);
        var w = tw.x * tw.y * tw.z * probe.w;
{weight}        shlight_volume_corner[k] = g;
        shlight_volume_weight[k] = w;
        total += w;
    }}
    if (total <= 0.0) {{
        return vec3<f32>(0.0);
    }}
"#
    ));
    s.push_str(&fill(
        BASIS_LOOP,
        &[
            ("decl_f_mut", "var"),
            ("decl_v3_mut", "var"),
            ("decl_f", "let"),
            ("ty_f", ": f32"),
            ("v3", "vec3<f32>"),
            ("f", "f32"),
            ("loop_m", "var m: i32"),
            ("loop_l", "var l: i32"),
            ("coeff_0", "shlight_volume_coeff(sh, l * l + l)"),
            ("coeff_p", "shlight_volume_coeff(sh, l * l + l + m)"),
            ("coeff_n", "shlight_volume_coeff(sh, l * l + l - m)"),
        ],
    ));
    s.push_str("    return sum / total;\n}\n");
    s
}

/// The WGSL of the visibility factor (the GLSL below is the same, line
/// for line).
const WGSL_VISIBILITY: &str = r#"
// The point of [-1, 1]^2 of the unit direction d (octahedral map).
fn shlight_volume_oct_encode(d: vec3<f32>) -> vec2<f32> {
    let l1 = abs(d.x) + abs(d.y) + abs(d.z);
    let q = vec2<f32>(d.x / l1, d.y / l1);
    let s = select(vec2<f32>(-1.0), vec2<f32>(1.0), q >= vec2<f32>(0.0));
    let folded = (vec2<f32>(1.0) - abs(q.yx)) * s;
    return select(q, folded, vec2<bool>(d.z < 0.0));
}

// The bilinear (mean, mean_sq) of probe g's distance map along dir.
fn shlight_volume_moments(moments: texture_3d<f32>, g: vec3<i32>, dir: vec3<f32>) -> vec2<f32> {
    let e = shlight_volume_oct_encode(dir);
    let s = (e + vec2<f32>(1.0)) * 0.5 * f32(SHLIGHT_VOLUME_MAP_SIZE) - vec2<f32>(0.5);
    let base = floor(s);
    let f = s - base;
    let h = vec2<f32>(1.0) - f;
    let a = clamp(vec2<i32>(base) + vec2<i32>(1), vec2<i32>(0), vec2<i32>(SHLIGHT_VOLUME_MAP_SIZE));
    let o = g.xy * (SHLIGHT_VOLUME_MAP_SIZE + 2) + a;
    let t00 = textureLoad(moments, vec3<i32>(o.x, o.y, g.z), 0).xy;
    let t10 = textureLoad(moments, vec3<i32>(o.x + 1, o.y, g.z), 0).xy;
    let t01 = textureLoad(moments, vec3<i32>(o.x, o.y + 1, g.z), 0).xy;
    let t11 = textureLoad(moments, vec3<i32>(o.x + 1, o.y + 1, g.z), 0).xy;
    return h.x * h.y * t00 + f.x * h.y * t10 + h.x * f.y * t01 + f.x * f.y * t11;
}

// Probe g's (at q) visibility of the biased point: Chebyshev's bound,
// floored, small values crushed.
fn shlight_volume_visibility(moments: texture_3d<f32>, g: vec3<i32>, q: vec3<f32>, biased: vec3<f32>) -> f32 {
    let v = biased - q;
    let d = length(v);
    var cheb = 1.0;
    if (d > 0.0) {
        let m = shlight_volume_moments(moments, g, v / d);
        if (d > m.x) {
            let variance = abs(m.y - m.x * m.x);
            let x = d - m.x;
            let c = variance / (variance + x * x);
            cheb = c * c * c;
        }
    }
    var w = max(cheb, SHLIGHT_VOLUME_FLOOR);
    if (w < SHLIGHT_VOLUME_CRUSH) {
        w = w * (w * w / SHLIGHT_VOLUME_CRUSH_SQ);
    }
    return w;
}
"#;

fn glsl(k: &Constants) -> String {
    let [nx, ny, nz] = k.resolution;
    let mut s = k.commented("//");
    s.push_str(
        "// Call shlight_volume_irradiance(p, n). The textures are read through the macros\n\
         // SHLIGHT_VOLUME_SH(c), SHLIGHT_VOLUME_PROBES(c) and SHLIGHT_VOLUME_MOMENTS(c) (c an\n\
         // ivec3); each not defined before this snippet reads a sampler3D uniform of its name\n\
         // in lower case with texelFetch.\n\n",
    );
    for (mac, uniform) in [
        ("SHLIGHT_VOLUME_SH", "shlight_volume_sh"),
        ("SHLIGHT_VOLUME_PROBES", "shlight_volume_probes"),
    ]
    .into_iter()
    .chain(
        k.visibility
            .is_some()
            .then_some(("SHLIGHT_VOLUME_MOMENTS", "shlight_volume_moments")),
    ) {
        s.push_str(&format!(
            "#ifndef {mac}\nuniform highp sampler3D {uniform};\n#define {mac}(c) texelFetch({uniform}, c, 0)\n#endif\n"
        ));
    }
    s.push_str(&format!(
        "\nconst int SHLIGHT_VOLUME_LMAX = {};\n\
         const vec3 SHLIGHT_VOLUME_MIN = vec3({}, {}, {});\n\
         const vec3 SHLIGHT_VOLUME_CELL = vec3({}, {}, {});\n\
         const ivec3 SHLIGHT_VOLUME_RESOLUTION = ivec3({nx}, {ny}, {nz});\n\
         // A_l, the clamped-cosine eigenvalues: irradiance is A_l times radiance, band by band.\n\
         const float SHLIGHT_VOLUME_A[{n}] = float[{n}]({});\n\
         // The eight probes around the point and their weights.\n\
         ivec3 shlight_volume_corner[8];\n\
         float shlight_volume_weight[8];\n",
        k.lmax,
        k.min[0],
        k.min[1],
        k.min[2],
        k.cell[0],
        k.cell[1],
        k.cell[2],
        k.band_weights,
        n = k.lmax + 1,
    ));
    let weight = if let Some((bias, size, floor, crush, crush2)) = &k.visibility {
        s.push_str(&format!(
            "const float SHLIGHT_VOLUME_BIAS = {bias};\n\
             const int SHLIGHT_VOLUME_MAP_SIZE = {size};\n\
             const float SHLIGHT_VOLUME_FLOOR = {floor};\n\
             const float SHLIGHT_VOLUME_CRUSH = {crush};\n\
             const float SHLIGHT_VOLUME_CRUSH_SQ = {crush2};\n"
        ));
        s.push_str(GLSL_VISIBILITY);
        "        w = w * shlight_volume_visibility(g, probe.xyz, p + n * SHLIGHT_VOLUME_BIAS);\n"
    } else {
        ""
    };
    s.push_str(
        r#"
// Coefficient idx of the point: the eight probes' weighted sum.
vec3 shlight_volume_coeff(int idx) {
    vec3 sum = vec3(0.0);
    for (int k = 0; k < 8; k++) {
        ivec3 g = shlight_volume_corner[k];
        ivec3 at = ivec3(g.x, g.y, idx * SHLIGHT_VOLUME_RESOLUTION.z + g.z);
        sum += shlight_volume_weight[k] * SHLIGHT_VOLUME_SH(at).rgb;
    }
    return sum;
}
"#,
    );
    s.push_str(&format!(
        r#"
// The irradiance E(p, normal) (header above).
vec3 shlight_volume_irradiance(vec3 p, vec3 normal) {{
    vec3 n = normalize(normal);
    // The trilinear cell of p, clamped to the grid (probes at cell centres).
    vec3 res = vec3(SHLIGHT_VOLUME_RESOLUTION);
    vec3 u = (p - SHLIGHT_VOLUME_MIN) / SHLIGHT_VOLUME_CELL - vec3(0.5);
    vec3 f = clamp(u, vec3(0.0), max(res - vec3(1.0), vec3(0.0)));
    vec3 i0 = min(floor(f), max(res - vec3(2.0), vec3(0.0)));
    vec3 t = f - i0;
    ivec3 lower = ivec3(i0);
    ivec3 upper = min(lower + ivec3(1), SHLIGHT_VOLUME_RESOLUTION - ivec3(1));
    float total = 0.0;
    for (int k = 0; k < 8; k++) {{
        bvec3 up = bvec3((k & 1) != 0, (k & 2) != 0, (k & 4) != 0);
        ivec3 g = ivec3(up.x ? upper.x : lower.x, up.y ? upper.y : lower.y, up.z ? upper.z : lower.z);
        vec3 tw = vec3(up.x ? t.x : 1.0 - t.x, up.y ? t.y : 1.0 - t.y, up.z ? t.z : 1.0 - t.z);
        vec4 probe = SHLIGHT_VOLUME_PROBES(g);
        float w = tw.x * tw.y * tw.z * probe.w;
{weight}        shlight_volume_corner[k] = g;
        shlight_volume_weight[k] = w;
        total += w;
    }}
    if (total <= 0.0) {{
        return vec3(0.0);
    }}
"#
    ));
    s.push_str(&fill(
        BASIS_LOOP,
        &[
            ("decl_f_mut", "float"),
            ("decl_v3_mut", "vec3"),
            ("decl_f", "float"),
            ("ty_f", ""),
            ("v3", "vec3"),
            ("f", "float"),
            ("loop_m", "int m"),
            ("loop_l", "int l"),
            ("coeff_0", "shlight_volume_coeff(l * l + l)"),
            ("coeff_p", "shlight_volume_coeff(l * l + l + m)"),
            ("coeff_n", "shlight_volume_coeff(l * l + l - m)"),
        ],
    ));
    s.push_str("    return sum / total;\n}\n");
    s
}

/// The GLSL of the visibility factor (the WGSL above, line for line).
const GLSL_VISIBILITY: &str = r#"
// The point of [-1, 1]^2 of the unit direction d (octahedral map).
vec2 shlight_volume_oct_encode(vec3 d) {
    float l1 = abs(d.x) + abs(d.y) + abs(d.z);
    vec2 q = vec2(d.x / l1, d.y / l1);
    vec2 s = vec2(q.x >= 0.0 ? 1.0 : -1.0, q.y >= 0.0 ? 1.0 : -1.0);
    vec2 folded = (vec2(1.0) - abs(q.yx)) * s;
    return d.z < 0.0 ? folded : q;
}

// The bilinear (mean, mean_sq) of probe g's distance map along dir.
vec2 shlight_volume_moments_at(ivec3 g, vec3 dir) {
    vec2 e = shlight_volume_oct_encode(dir);
    vec2 s = (e + vec2(1.0)) * 0.5 * float(SHLIGHT_VOLUME_MAP_SIZE) - vec2(0.5);
    vec2 base = floor(s);
    vec2 f = s - base;
    vec2 h = vec2(1.0) - f;
    ivec2 a = clamp(ivec2(base) + ivec2(1), ivec2(0), ivec2(SHLIGHT_VOLUME_MAP_SIZE));
    ivec2 o = g.xy * (SHLIGHT_VOLUME_MAP_SIZE + 2) + a;
    vec2 t00 = SHLIGHT_VOLUME_MOMENTS(ivec3(o.x, o.y, g.z)).xy;
    vec2 t10 = SHLIGHT_VOLUME_MOMENTS(ivec3(o.x + 1, o.y, g.z)).xy;
    vec2 t01 = SHLIGHT_VOLUME_MOMENTS(ivec3(o.x, o.y + 1, g.z)).xy;
    vec2 t11 = SHLIGHT_VOLUME_MOMENTS(ivec3(o.x + 1, o.y + 1, g.z)).xy;
    return h.x * h.y * t00 + f.x * h.y * t10 + h.x * f.y * t01 + f.x * f.y * t11;
}

// Probe g's (at q) visibility of the biased point: Chebyshev's bound,
// floored, small values crushed.
float shlight_volume_visibility(ivec3 g, vec3 q, vec3 biased) {
    vec3 v = biased - q;
    float d = length(v);
    float cheb = 1.0;
    if (d > 0.0) {
        vec2 m = shlight_volume_moments_at(g, v / d);
        if (d > m.x) {
            float variance = abs(m.y - m.x * m.x);
            float x = d - m.x;
            float c = variance / (variance + x * x);
            cheb = c * c * c;
        }
    }
    float w = max(cheb, SHLIGHT_VOLUME_FLOOR);
    if (w < SHLIGHT_VOLUME_CRUSH) {
        w = w * (w * w / SHLIGHT_VOLUME_CRUSH_SQ);
    }
    return w;
}
"#;

/// What [`write_volume_shader`] wrote.
#[derive(Clone, Debug, PartialEq)]
pub struct WrittenVolumeShader {
    /// The snippet, then each texture.
    pub paths: Vec<std::path::PathBuf>,
    /// Remarks for the user, one sentence each.
    pub notes: Vec<String>,
}

/// Writes [`volume_shader`] of `file`: the snippet to `path` and each
/// texture beside it as `{stem}.{name}.ktx2` (`stem` the snippet's file
/// stem), each file atomically, the textures first.
///
/// # Errors
/// As [`volume_shader`]; [`FormatError::Write`] naming a file that cannot
/// be written.
pub fn write_volume_shader(
    file: &ShvolFile,
    language: ShaderLanguage,
    path: &std::path::Path,
) -> Result<WrittenVolumeShader> {
    let stem = path
        .file_stem()
        .map_or_else(|| "volume".into(), |s| s.to_string_lossy().into_owned());
    let shader = volume_shader(file, language, &stem)?;
    let dir = path.parent().unwrap_or_else(|| std::path::Path::new(""));
    let mut paths = Vec::new();
    for texture in &shader.textures {
        let at = dir.join(format!("{stem}.{}.ktx2", texture.name));
        let bytes = texture.ktx2(&file.generator);
        shlight_io::write_atomically(&at, |w| w.write_all(&bytes))?;
        paths.push(at);
    }
    shlight_io::write_atomically(path, |w| w.write_all(shader.text.as_bytes()))?;
    paths.insert(0, path.to_path_buf());
    Ok(WrittenVolumeShader {
        paths,
        notes: shader.notes,
    })
}
