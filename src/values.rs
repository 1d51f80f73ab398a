//! clap value parsers: the libraries' enums, which know nothing of clap
//! (each lists its names and their help and maps a name back to its
//! value), and the numbers and lists the commands take (`--size`,
//! `X,Y,Z`, an albedo).

use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use glam::DVec3;
use shlight_core::encoding::Encoding;
use shlight_core::map::Layout;
use shlight_format::{ExportFormat, Quantity, VolumeFormat};
use shlight_mesh::LightUnits;
use shlight_pipeline::RenderLayout;
use shlight_specular::TargetEngine;

/// A parser accepting exactly the names of `all`, with their help lines.
fn one_of<T: Copy + Send + Sync + 'static>(
    all: &'static [T],
    name: fn(T) -> &'static str,
    help: fn(T) -> &'static str,
) -> impl TypedValueParser<Value = T> {
    PossibleValuesParser::new(
        all.iter()
            .map(|&v| PossibleValue::new(name(v)).help(help(v))),
    )
    .map(move |n| {
        *all.iter()
            .find(|&&v| name(v) == n)
            .expect("possible values are the names")
    })
}

/// `--format NAME`.
pub fn export_format() -> impl TypedValueParser<Value = ExportFormat> {
    one_of(
        &ExportFormat::ALL,
        ExportFormat::name,
        ExportFormat::description,
    )
}

/// `shlight volume --format NAME`.
pub fn volume_format() -> impl TypedValueParser<Value = VolumeFormat> {
    one_of(
        &VolumeFormat::ALL,
        VolumeFormat::name,
        VolumeFormat::description,
    )
}

/// `--for ENGINE` of `prefilter` and `dfg`.
pub fn engine() -> impl TypedValueParser<Value = TargetEngine> {
    one_of(&TargetEngine::ALL, TargetEngine::name, |e| match e {
        TargetEngine::Filament => "Filament / cmgen: 16-pixel smallest mip, multiscatter DFG",
        TargetEngine::Babylon => "Babylon.js (EXT_lights_image_based): full mip chain",
        TargetEngine::Bevy => "Bevy EnvironmentMapLight: roughness linear in the mip",
        TargetEngine::Unreal => "Unreal Engine 4 reflection captures",
    })
}

/// `shlight volume --light-units NAME`.
pub fn light_units() -> impl TypedValueParser<Value = LightUnits> {
    one_of(&LightUnits::ALL, LightUnits::name, LightUnits::description)
}

/// `--encoding NAME`.
pub fn encoding() -> impl TypedValueParser<Value = Encoding> {
    one_of(&Encoding::ALL, Encoding::name, |e| match e {
        Encoding::Sh => "plain radiance SH to --lmax",
        Encoding::DominantSh => {
            "the map's compact bright lights kept exactly, the rest as SH to --lmax"
        }
        Encoding::SloanSh => "SH to --lmax; Sloan 2008's light taken out of it when shading",
        Encoding::Zh3 => "ZH3: lmax 1 plus a stored zonal coefficient (Roughton et al. 2024)",
        Encoding::Zh3Hallucinated => "ZH3 with the zonal coefficient hallucinated from lmax 1",
        Encoding::L1NonLinear => "lmax 1 with the non-linear (Geomerics) reconstruction",
        Encoding::AmbientCube => "six colours: the exact irradiance at the axes (Valve 2006)",
    })
}

/// `--quantity NAME`.
pub fn quantity() -> impl TypedValueParser<Value = Quantity> {
    one_of(&Quantity::ALL, Quantity::name, |q| match q {
        Quantity::Radiance => "distant radiance L(w)",
        Quantity::Irradiance => "irradiance E(n) = A_l L_lm (Ramamoorthi & Hanrahan 2001)",
    })
}

/// `--layout NAME` of the maps shlight writes (docs/conventions.md,
/// "Layouts").
pub fn layout() -> impl TypedValueParser<Value = Layout> {
    one_of(&Layout::ALL, Layout::name, layout_help)
}

/// The help line of each map layout.
fn layout_help(l: Layout) -> &'static str {
    match l {
        Layout::Equirect => "Equirectangular (latitude-longitude), 2:1",
        Layout::CrossHorizontal => "Horizontal cube cross, 4f x 3f",
        Layout::CrossVertical => "Vertical cube cross, 3f x 4f",
        Layout::Strip => "Six cube faces in a row, +X -X +Y -Y +Z -Z, 6f x f",
        Layout::Angular => "Angular map (Debevec light probe), N x N",
        Layout::MirrorBall => "Mirror ball, N x N",
    }
}

/// `shlight render --layout NAME`: [`layout`]'s names and `lobe`.
pub fn render_layout() -> impl TypedValueParser<Value = RenderLayout> {
    one_of(&RenderLayout::ALL, RenderLayout::name, |r| match r {
        RenderLayout::Map(l) => layout_help(l),
        RenderLayout::Lobe => {
            "The luminance as a 3D lobe |f(w)|, red positive, blue negative, seen from --view"
        }
    })
}

/// `--size WxH`, e.g. `1024x512`: two positive whole numbers, at most
/// the reader's default pixel limit in all.
pub fn parse_size(s: &str) -> std::result::Result<(usize, usize), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("{s:?} is not WIDTHxHEIGHT (e.g. 1024x512)"))?;
    let parse = |t: &str| {
        t.trim()
            .parse::<usize>()
            .ok()
            .filter(|&n| n > 0)
            .ok_or_else(|| format!("{s:?}: {t:?} is not a positive whole number"))
    };
    let (w, h) = (parse(w)?, parse(h)?);
    if w.checked_mul(h)
        .is_none_or(|n| n > shlight_io::ReadOptions::DEFAULT_MAX_PIXELS)
    {
        return Err(format!(
            "{s:?}: more than {} pixels",
            shlight_io::ReadOptions::DEFAULT_MAX_PIXELS
        ));
    }
    Ok((w, h))
}

/// `X,Y,Z` (or `R,G,B`): three finite numbers.
pub fn parse_vec3(s: &str) -> std::result::Result<DVec3, String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|t| t.trim().parse::<f64>())
        .collect::<std::result::Result<_, _>>()
        .map_err(|e| format!("{s:?}: {e}"))?;
    match v.as_slice() {
        [x, y, z] if v.iter().all(|c| c.is_finite()) => Ok(DVec3::new(*x, *y, *z)),
        _ => Err(format!("{s:?} is not three finite numbers X,Y,Z")),
    }
}

/// `X,Y,Z` in `f32` ([`parse_vec3`]).
pub fn parse_vec3_f32(s: &str) -> std::result::Result<glam::Vec3, String> {
    parse_vec3(s).map(|v| v.as_vec3())
}

/// A diffuse albedo: one value or `R,G,B`, each in `[0, 1]`.
pub fn parse_albedo(s: &str) -> std::result::Result<[f32; 3], String> {
    let values: Vec<f32> = s
        .split(',')
        .map(|v| v.trim().parse::<f32>())
        .collect::<std::result::Result<_, _>>()
        .map_err(|_| format!("{s:?} is not a number or R,G,B"))?;
    let rgb = match values.as_slice() {
        [v] => [*v; 3],
        [r, g, b] => [*r, *g, *b],
        _ => return Err(format!("{s:?}: give one value or three (R,G,B)")),
    };
    if rgb.iter().any(|v| !(0.0..=1.0).contains(v)) {
        return Err(format!("{s:?}: albedo values must lie in [0, 1]"));
    }
    Ok(rgb)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse() {
        assert_eq!(parse_size("64x32"), Ok((64, 32)));
        assert!(parse_size("64").is_err() && parse_size("0x0").is_err());
    }
}
