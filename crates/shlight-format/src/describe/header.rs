//! [`Header`]: what a file is and the facts its header holds, printed as
//! a two-column table.

/// What a file is and its header's facts (`shlight show` of any file but
/// a coefficient file).
///
/// The table ([`Header::to_table`]) is a first line `# KIND`, one line per
/// field (its name padded to a column, then its value), then `rows` as
/// they are:
///
/// ```text
/// # shlight irradiance volume (.shvol, format_version 2)
/// lmax         2 (9 coefficients per probe and channel)
/// grid         4 x 4 x 4 = 64 probes
/// ```
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Header {
    /// What the file is, in words (the table's first line).
    pub kind: String,
    /// The facts, in order: a name and its value.
    pub fields: Vec<(String, String)>,
    /// Lines after the fields (a light's coefficients read back, a
    /// snippet's own header comment), each ending in a newline; empty
    /// when there are none.
    pub rows: String,
}

impl Header {
    /// A header of `kind` without fields.
    pub(crate) fn new(kind: impl Into<String>) -> Self {
        Self {
            kind: kind.into(),
            fields: Vec::new(),
            rows: String::new(),
        }
    }

    /// Adds a field.
    pub(crate) fn field(&mut self, name: impl Into<String>, value: impl Into<String>) {
        self.fields.push((name.into(), value.into()));
    }

    /// The value of the first field called `name`.
    #[must_use]
    pub fn get(&self, name: &str) -> Option<&str> {
        self.fields
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_str())
    }

    /// The table (the type's documentation).
    #[must_use]
    pub fn to_table(&self) -> String {
        let width = self.fields.iter().map(|(n, _)| n.len()).max().unwrap_or(0) + 2;
        let mut s = format!("# {}\n", self.kind);
        for (name, value) in &self.fields {
            s.push_str(&format!("{name:width$}{value}\n"));
        }
        s.push_str(&self.rows);
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_line_up_after_the_longest_name() {
        let mut h = Header::new("a thing");
        h.field("lmax", "2");
        h.field("environment", "park.json");
        h.rows = "# more\n".into();
        assert_eq!(
            h.to_table(),
            "# a thing\nlmax         2\nenvironment  park.json\n# more\n"
        );
        assert_eq!(h.get("environment"), Some("park.json"));
        assert_eq!(h.get("grid"), None);
    }
}
