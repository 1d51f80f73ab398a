//! [`Spelling`]: how a front end names its settings in messages, so that a
//! library's refusal reads as the user gave the setting (`--lmax 9` on the
//! command line, `lmax=9` in Python) while the library names no flag.

use std::fmt::Display;
use std::str::FromStr;

use crate::{PipelineError, Result};

/// How a front end names its settings in messages.
///
/// The default is the command line's, shlight's first front end (what the
/// library's own callers see without saying).
///
/// Settings are named in snake case (`max_pixels`, `preview_size`); the
/// command line spells them as flags with hyphens (`--max-pixels`), Python
/// as keyword arguments (`max_pixels`). A setting whose flag is not its
/// name (`shlight prefilter --for`, `engine=` in Python) is passed to the
/// methods under each front end's own name by the caller of
/// [`Spelling::pick`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Spelling {
    /// The command line's flags: `--rotate`, `--method montecarlo`.
    #[default]
    CommandLine,
    /// Python's keyword arguments: `rotate`, `method="montecarlo"`.
    Python,
}

impl Spelling {
    /// The setting `name` (words joined by `_` or `-`) alone: `--rotate`,
    /// `rotate`; `--object-size`, `object_size`.
    #[must_use]
    pub fn option(self, name: &str) -> String {
        match self {
            Spelling::CommandLine => format!("--{}", name.replace('_', "-")),
            Spelling::Python => name.replace('-', "_"),
        }
    }

    /// The setting `name` given `value` (a word or a spec):
    /// `--method montecarlo`, `method="montecarlo"`.
    #[must_use]
    pub fn option_value(self, name: &str, value: impl Display) -> String {
        match self {
            Spelling::CommandLine => format!("{} {value}", self.option(name)),
            Spelling::Python => format!("{}=\"{value}\"", self.option(name)),
        }
    }

    /// The setting `name` given a number or numbers as the front end
    /// writes them: `--lmax 9`, `lmax=9`; `--size 64x32`, `size=(64, 32)`
    /// (`cli` and `python` are the value as each writes it).
    #[must_use]
    pub fn option_number(self, name: &str, cli: impl Display, python: impl Display) -> String {
        match self {
            Spelling::CommandLine => format!("{} {cli}", self.option(name)),
            Spelling::Python => format!("{}={python}", self.option(name)),
        }
    }

    /// `cli` on the command line, `python` in Python: for a setting the
    /// two front ends name differently (`for`, `engine`).
    #[must_use]
    pub fn pick<'a>(self, cli: &'a str, python: &'a str) -> &'a str {
        match self {
            Spelling::CommandLine => cli,
            Spelling::Python => python,
        }
    }

    /// `text` parsed as a `T`, or an error naming the setting as given:
    /// `--quantity bogus: ...`, `quantity="bogus": ...`.
    ///
    /// # Errors
    /// `T`'s parse error after the setting.
    pub fn parse<T>(self, name: &str, text: &str) -> Result<T>
    where
        T: FromStr,
        T::Err: Display,
    {
        text.trim()
            .parse()
            .map_err(|e| PipelineError::new(format!("{}: {e}", self.option_value(name, text))))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use shlight_format::Quantity;

    #[test]
    fn settings_are_spelled_as_each_front_end_takes_them() {
        use Spelling::{CommandLine, Python};
        assert_eq!(CommandLine.option("max_pixels"), "--max-pixels");
        assert_eq!(Python.option("max_pixels"), "max_pixels");
        assert_eq!(Python.option("object-size"), "object_size");
        assert_eq!(CommandLine.option("object-size"), "--object-size");
        assert_eq!(
            CommandLine.option_value("method", "montecarlo"),
            "--method montecarlo"
        );
        assert_eq!(
            Python.option_value("method", "montecarlo"),
            "method=\"montecarlo\""
        );
        assert_eq!(CommandLine.option_number("lmax", 9, 9), "--lmax 9");
        assert_eq!(
            Python.option_number("size", "64x32", "(64, 32)"),
            "size=(64, 32)"
        );
        assert_eq!(CommandLine.pick("for", "engine"), "for");
        assert_eq!(Python.pick("for", "engine"), "engine");
    }

    #[test]
    fn a_bad_value_names_its_setting() {
        let q: Quantity = Spelling::Python.parse("quantity", " irradiance ").unwrap();
        assert_eq!(q, Quantity::Irradiance);
        let e = Spelling::Python
            .parse::<Quantity>("quantity", "bogus")
            .unwrap_err();
        assert!(e.message().starts_with("quantity=\"bogus\": "), "{e}");
        let e = Spelling::CommandLine
            .parse::<Quantity>("quantity", "bogus")
            .unwrap_err();
        assert!(e.message().starts_with("--quantity bogus: "), "{e}");
    }
}
