//! clap value parsers for the libraries' enums, which know nothing of clap:
//! each lists its names (and their help) and maps a name back to its value.

use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use shlight_core::Encoding;
use shlight_format::{ExportFormat, Quantity};

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
