//! `shlight sample`'s files (its answer as JSON or CSV, the points it
//! reads) and `shlight compare`'s rows (`compare.json`).

use serde_json::Value;

use super::{Header, plain};
use crate::{FormatError, Result, SamplePoints};

/// `shlight sample`'s JSON answer: its quantity, count and what it says
/// of the file it sampled (every key but the values, provenance included).
pub(super) fn describe_samples(v: &Value, name: &str) -> Result<Header> {
    let object = v
        .as_object()
        .ok_or_else(|| FormatError::invalid(name, "a samples file, but not a JSON object"))?;
    let (quantity, values) = ["irradiance", "radiance"]
        .into_iter()
        .find_map(|q| Some((q, object.get(q)?.as_array()?)))
        .ok_or_else(|| {
            FormatError::invalid(
                name,
                "a samples file, but it has no \"irradiance\" or \"radiance\" list of [r, g, b]",
            )
        })?;
    let mut h = Header::new(format!(
        "shlight sample's answer ({}, format_version {})",
        crate::SAMPLES_FORMAT,
        object.get("format_version").map(plain).unwrap_or_default()
    ));
    h.field(
        "holds",
        format!("{} [r, g, b] values of {quantity}", values.len()),
    );
    for (key, value) in object {
        if matches!(
            key.as_str(),
            "format" | "format_version" | "count" | "irradiance" | "radiance"
        ) {
            continue;
        }
        match value.as_object() {
            Some(inner) => {
                for (k, v) in inner {
                    h.field(format!("{key} {k}"), plain(v));
                }
            }
            None => h.field(key.as_str(), plain(value)),
        }
    }
    Ok(h)
}

/// Points to sample a baked file at (`shlight sample --points`, JSON).
pub(super) fn describe_points_json(text: &str, name: &str) -> Result<Header> {
    let points = SamplePoints::from_json_str(text, name)?;
    Ok(points_header(&points, "JSON"))
}

fn points_header(points: &SamplePoints, form: &str) -> Header {
    let mut h = Header::new(format!(
        "points to sample (shlight sample --points, {form})"
    ));
    h.field(
        "holds",
        format!("{} points, each with a unit normal", points.points.len()),
    );
    if let Some(first) = points.points.first() {
        let (mut lo, mut hi) = (*first, *first);
        for p in &points.points {
            for a in 0..3 {
                lo[a] = lo[a].min(p[a]);
                hi[a] = hi[a].max(p[a]);
            }
        }
        h.field("bounds", format!("min {lo:?}, max {hi:?}"));
    }
    h
}

/// CSV: `shlight sample`'s answer (`r,g,b`) or its points
/// (`x,y,z,nx,ny,nz`), by the header line; `None` for other text.
pub(super) fn describe_csv(text: &str, name: &str) -> Result<Option<Header>> {
    let first = text.lines().next().unwrap_or_default().trim();
    if first == "r,g,b" {
        let rows: Vec<&str> = text
            .lines()
            .skip(1)
            .filter(|l| !l.trim().is_empty())
            .collect();
        if let Some((k, line)) = rows.iter().enumerate().find(|(_, l)| {
            l.split(',')
                .filter(|f| f.trim().parse::<f64>().is_ok())
                .count()
                != 3
        }) {
            return Err(FormatError::invalid(
                name,
                format!(
                    "shlight sample's CSV, but line {} is not three numbers: {line:?}",
                    k + 2
                ),
            ));
        }
        let mut h = Header::new("shlight sample's answer as CSV (r,g,b rows)");
        h.field(
            "holds",
            format!(
                "{} [r, g, b] values, one per point (or vertex) in order; the JSON form \
                 also says what they are",
                rows.len()
            ),
        );
        return Ok(Some(h));
    }
    if first.replace(' ', "") == "x,y,z,nx,ny,nz" {
        let points = SamplePoints::from_csv_str(text, name)?;
        return Ok(Some(points_header(&points, "CSV")));
    }
    Ok(None)
}

/// `shlight compare -o DIR`'s `compare.json`: rows of a map, an encoding
/// and its errors; `None` for other JSON.
pub(super) fn describe_compare(v: &Value) -> Option<Header> {
    let rows = v.as_array()?;
    let is_row = |r: &Value| r.get("encoding").is_some() && r.get("floats").is_some();
    if rows.is_empty() || !rows.iter().all(is_row) {
        return None;
    }
    let mut maps: Vec<String> = Vec::new();
    let mut encodings: Vec<String> = Vec::new();
    for r in rows {
        for (list, key) in [(&mut maps, "map"), (&mut encodings, "encoding")] {
            let value = r.get(key).map(plain).unwrap_or_default();
            if !list.contains(&value) {
                list.push(value);
            }
        }
    }
    let mut h = Header::new("shlight compare's rows (compare.json)");
    h.field(
        "holds",
        format!(
            "{} rows: each encoding's floats stored and its mean, max and RMS irradiance \
             error on a map",
            rows.len()
        ),
    );
    h.field("maps", maps.join(", "));
    h.field("encodings", encodings.join(", "));
    Some(h)
}
