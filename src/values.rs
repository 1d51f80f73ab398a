//! clap value parsers for the libraries' enums, which know nothing of clap:
//! each lists its names (and their help) and maps a name back to its value.

use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
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

/// `--quantity NAME`.
pub fn quantity() -> impl TypedValueParser<Value = Quantity> {
    one_of(&Quantity::ALL, Quantity::name, |q| match q {
        Quantity::Radiance => "distant radiance L(w)",
        Quantity::Irradiance => "irradiance E(n) = A_l L_lm (Ramamoorthi & Hanrahan 2001)",
    })
}
