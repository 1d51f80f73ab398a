//! The files of `shlight sample`: [`SamplePoints`] read (where to ask a
//! baked file for its light) and [`SampledValues`] written (what it answers),
//! each as JSON or CSV by the file's extension (docs/cli.md, "sample").

use std::path::Path;

use serde_json::{Value, json};

use crate::{FormatError, Result};

/// Most points one file may ask for (a 4096 x 4096 grid of texels).
pub const MAX_POINTS: usize = 1 << 24;

/// Points and unit normals to sample a baked file at: JSON
/// `{"points": [[x, y, z], ...], "normals": [[x, y, z], ...]}` or CSV rows
/// `x,y,z,nx,ny,nz` (a header line of names is skipped).
#[derive(Clone, Debug, PartialEq)]
pub struct SamplePoints {
    /// Positions, in the scene's units and frame.
    pub points: Vec<[f32; 3]>,
    /// One normal per point, normalised on reading.
    pub normals: Vec<[f32; 3]>,
}

impl SamplePoints {
    /// Reads `path`: CSV when it ends in `.csv`, JSON otherwise.
    ///
    /// # Errors
    /// An unreadable file, one that is not of the layout above, a
    /// coordinate that is not finite, a normal of zero length, counts that
    /// differ, or more than [`MAX_POINTS`] points; messages name the file.
    pub fn read(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path).map_err(|source| FormatError::Read {
            path: path.to_path_buf(),
            source,
        })?;
        let name = path.display().to_string();
        if is_csv(path) {
            Self::from_csv_str(&text, &name)
        } else {
            Self::from_json_str(&text, &name)
        }
    }

    /// Parses the JSON form; `name` names the text in errors.
    ///
    /// # Errors
    /// As [`SamplePoints::read`].
    pub fn from_json_str(text: &str, name: &str) -> Result<Self> {
        // The common case read straight into arrays; anything it does not
        // take is read again as a JSON value, for an error that names the
        // problem.
        #[derive(serde::Deserialize)]
        struct Rows {
            points: Vec<[f32; 3]>,
            normals: Vec<[f32; 3]>,
        }
        if let Ok(rows) = serde_json::from_str::<Rows>(text)
            && rows.points.len() <= MAX_POINTS
            && rows.normals.len() <= MAX_POINTS
        {
            return Self::new(rows.points, rows.normals, name);
        }
        let bad = |m: String| FormatError::invalid(name, m);
        let v: Value = serde_json::from_str(text).map_err(|e| bad(format!("not JSON ({e})")))?;
        let list = |key: &str| -> Result<Vec<[f32; 3]>> {
            let rows = v
                .get(key)
                .and_then(Value::as_array)
                .ok_or_else(|| bad(format!("no \"{key}\" array of [x, y, z] rows")))?;
            if rows.len() > MAX_POINTS {
                return Err(bad(format!(
                    "{} {key}: at most {MAX_POINTS} are read",
                    rows.len()
                )));
            }
            rows.iter()
                .enumerate()
                .map(|(i, r)| {
                    let xyz: Option<Vec<f64>> = r
                        .as_array()
                        .filter(|a| a.len() == 3)
                        .and_then(|a| a.iter().map(Value::as_f64).collect());
                    xyz.map(|c| [c[0] as f32, c[1] as f32, c[2] as f32])
                        .ok_or_else(|| bad(format!("{key}[{i}] is not [x, y, z]")))
                })
                .collect()
        };
        Self::new(list("points")?, list("normals")?, name)
    }

    /// Parses the CSV form; `name` names the text in errors.
    ///
    /// # Errors
    /// As [`SamplePoints::read`].
    pub fn from_csv_str(text: &str, name: &str) -> Result<Self> {
        let (mut points, mut normals) = (Vec::new(), Vec::new());
        for (k, line) in text.lines().enumerate() {
            let line = line.trim();
            if line.is_empty() {
                continue;
            }
            let fields: Vec<&str> = line.split(',').map(str::trim).collect();
            let values: Option<Vec<f32>> = fields.iter().map(|f| f.parse().ok()).collect();
            match values {
                Some(v) if v.len() == 6 => {
                    if points.len() == MAX_POINTS {
                        return Err(FormatError::invalid(
                            name,
                            format!("more than {MAX_POINTS} points"),
                        ));
                    }
                    points.push([v[0], v[1], v[2]]);
                    normals.push([v[3], v[4], v[5]]);
                }
                // A header of names before the first row.
                None if points.is_empty() && k == 0 => {}
                _ => {
                    return Err(FormatError::invalid(
                        name,
                        format!(
                            "line {}: expected x,y,z,nx,ny,nz (six numbers), not {line:?}",
                            k + 1
                        ),
                    ));
                }
            }
        }
        Self::new(points, normals, name)
    }

    /// Points and normals given as values (the Python package's arrays),
    /// checked as a file's are and the normals normalised; `name` names
    /// them in errors.
    ///
    /// # Errors
    /// Counts that differ, a point that is not finite, or a normal that is
    /// not a direction (zero or not finite).
    pub fn new(points: Vec<[f32; 3]>, normals: Vec<[f32; 3]>, name: &str) -> Result<Self> {
        let bad = |m: String| FormatError::invalid(name, m);
        if points.len() != normals.len() {
            return Err(bad(format!(
                "{} points but {} normals: one normal per point",
                points.len(),
                normals.len()
            )));
        }
        if let Some(i) = points.iter().position(|p| !p.iter().all(|c| c.is_finite())) {
            return Err(bad(format!("point {i} is not finite: {:?}", points[i])));
        }
        let mut unit = Vec::with_capacity(normals.len());
        for (i, n) in normals.iter().enumerate() {
            let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            if !(l.is_finite() && l > 0.0) {
                return Err(bad(format!("normal {i} is not a direction: {n:?}")));
            }
            unit.push(n.map(|c| c / l));
        }
        Ok(Self {
            points,
            normals: unit,
        })
    }
}

/// What a baked file answers: one linear RGB value per point (or vertex),
/// the quantity it is, and how it was found.
#[derive(Clone, Debug, PartialEq)]
pub struct SampledValues {
    /// `"irradiance"` (a volume: `E(p, n)`, which a Lambertian surface of
    /// albedo `rho` turns into `rho / pi E`) or `"radiance"` (PRT: each
    /// vertex's exit radiance).
    pub quantity: &'static str,
    /// One `[r, g, b]` per point.
    pub values: Vec<[f64; 3]>,
    /// What else the JSON file says: the baked file, the lookup, the
    /// light, lmax, the file's provenance (an object; its keys are written
    /// beside `format`, `format_version`, the quantity and the values).
    pub about: Value,
}

/// The `format` of a samples JSON file.
pub const SAMPLES_FORMAT: &str = "shlight-samples";

impl SampledValues {
    /// The JSON document: `{"format": "shlight-samples", "format_version":
    /// 1, ...about, QUANTITY: [[r, g, b], ...]}`.
    #[must_use]
    pub fn to_json(&self) -> Value {
        let mut o = match &self.about {
            Value::Object(m) => m.clone(),
            _ => serde_json::Map::new(),
        };
        o.insert("format".into(), json!(SAMPLES_FORMAT));
        o.insert("format_version".into(), json!(1));
        o.insert("count".into(), json!(self.values.len()));
        o.insert(self.quantity.into(), json!(self.values));
        Value::Object(o)
    }

    /// [`SampledValues::to_json`] as text: indented, one `[r, g, b]` row a line.
    #[must_use]
    pub fn to_json_text(&self) -> String {
        let mut head = self.to_json();
        let object = head.as_object_mut().expect("an object");
        object.remove(self.quantity);
        let mut t = serde_json::to_string_pretty(&head).expect("JSON of numbers");
        // Reopen the object for the values, one row a line.
        t.truncate(t.trim_end().len() - 1);
        let t = t.trim_end().to_string();
        let mut out = String::with_capacity(t.len() + 64 * self.values.len());
        out.push_str(&t);
        out.push_str(&format!(",\n  \"{}\": [", self.quantity));
        for (i, v) in self.values.iter().enumerate() {
            out.push_str(if i == 0 { "\n    " } else { ",\n    " });
            out.push_str(&serde_json::to_string(v).expect("finite numbers"));
        }
        out.push_str(if self.values.is_empty() {
            "]\n}\n"
        } else {
            "\n  ]\n}\n"
        });
        out
    }

    /// The CSV text: a header `r,g,b`, then one row per point.
    #[must_use]
    pub fn to_csv(&self) -> String {
        let mut out = String::from("r,g,b\n");
        for v in &self.values {
            out.push_str(&format!("{},{},{}\n", v[0], v[1], v[2]));
        }
        out
    }

    /// Writes `path` atomically: CSV when it ends in `.csv`, JSON
    /// otherwise.
    ///
    /// # Errors
    /// The file cannot be written, or a value is not finite.
    pub fn write(&self, path: &Path) -> Result<()> {
        if let Some(i) = self
            .values
            .iter()
            .position(|v| !v.iter().all(|c| c.is_finite()))
        {
            return Err(FormatError::Export(format!(
                "{}: value {i} is not finite: {:?}",
                path.display(),
                self.values[i]
            )));
        }
        let text = if is_csv(path) {
            self.to_csv()
        } else {
            self.to_json_text()
        };
        shlight_io::write_atomically(path, |w| w.write_all(text.as_bytes()))?;
        Ok(())
    }
}

fn is_csv(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("csv"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_json_text_is_the_json_document() {
        for values in [
            vec![],
            vec![[1.0, 0.25, 1e-7]],
            vec![[0.5, 2.0, 3.0], [4.0, -0.0, 1e300]],
        ] {
            let s = SampledValues {
                quantity: "irradiance",
                values,
                about: json!({"lookup": "shlight", "provenance": {"seed": 3}}),
            };
            let text = s.to_json_text();
            let back: Value = serde_json::from_str(&text).unwrap();
            assert_eq!(back, s.to_json(), "{text}");
            assert!(text.ends_with("}\n"));
        }
    }

    #[test]
    fn points_read_as_json_and_csv_alike() {
        let json = r#"{"points": [[0, 1, 2], [0.5, -1, 3]], "normals": [[0, 2, 0], [1, 0, 0]]}"#;
        let a = SamplePoints::from_json_str(json, "p.json").unwrap();
        let csv = "x,y,z,nx,ny,nz\n0,1,2,0,2,0\n0.5,-1,3,1,0,0\n";
        let b = SamplePoints::from_csv_str(csv, "p.csv").unwrap();
        assert_eq!(a, b);
        assert_eq!(a.normals[0], [0.0, 1.0, 0.0]);
        for (text, want) in [
            (r#"{"points": [[0, 1, 2]]}"#, "no \"normals\""),
            (
                r#"{"points": [[0, 1]], "normals": [[0, 1, 0]]}"#,
                "points[0] is not [x, y, z]",
            ),
            (
                r#"{"points": [[0, 1, 2]], "normals": [[0, 0, 0]]}"#,
                "normal 0 is not a direction",
            ),
            (
                r#"{"points": [[0, 1, 2]], "normals": []}"#,
                "1 points but 0 normals",
            ),
            ("[", "not JSON"),
        ] {
            let e = SamplePoints::from_json_str(text, "p.json")
                .unwrap_err()
                .to_string();
            assert!(e.starts_with("p.json: ") && e.contains(want), "{e}");
        }
        let e = SamplePoints::from_csv_str("0,1,2,0,1,0\n1,2\n", "p.csv")
            .unwrap_err()
            .to_string();
        assert!(e.contains("line 2: expected x,y,z,nx,ny,nz"), "{e}");
    }

    #[test]
    fn samples_write_as_json_and_csv() {
        let s = SampledValues {
            quantity: "irradiance",
            values: vec![[1.0, 2.0, 3.0], [0.5, 0.25, 0.0]],
            about: json!({"lookup": "trilinear"}),
        };
        let j = s.to_json();
        assert_eq!(j["format"], "shlight-samples");
        assert_eq!(j["lookup"], "trilinear");
        assert_eq!(j["irradiance"][1], json!([0.5, 0.25, 0.0]));
        assert_eq!(s.to_csv(), "r,g,b\n1,2,3\n0.5,0.25,0\n");
        let bad = SampledValues {
            values: vec![[f64::NAN, 0.0, 0.0]],
            ..s
        };
        let e = bad
            .write(Path::new("/nonexistent/x.json"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("not finite"), "{e}");
    }
}
