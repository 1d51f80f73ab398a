//! Every encoding ([`shlight_core::encoding`]) of a map against the map's
//! exact irradiance: the table of floats stored against mean / max / RMS
//! error, and its plot.
//!
//! The truth is the brute-force irradiance
//! ([`shlight_core::map`]) at the texel centres of an equirect
//! grid of normals; each encoding's irradiance is evaluated at the same
//! normals; errors are of the luminance, relative to its peak over the
//! normals (as `shlight irradiance` reports them, [`crate::error`]), with
//! the mean and RMS weighted by the normals' solid angles.

use glam::DVec3;
use serde_json::{Value, json};
use shlight_core::encoding::{DominantLightOptions, Encoded, Encoding, encode_map};
use shlight_core::map::{
    EnvMap, MapOrientation, equirect_direction, equirect_row_solid_angle, irradiance_brute_force,
    luminance,
};

use crate::error::{ErrorStats, peak_relative_errors};
use crate::plot::{Series, log_log_svg};

/// The encodings and SH sizes a comparison runs, in table order (no lmax
/// 3: `A_3 = 0`, so its irradiance is lmax 2's).
pub const CASES: [(Encoding, usize); 10] = [
    (Encoding::Sh, 1),
    (Encoding::Sh, 2),
    (Encoding::Sh, 4),
    (Encoding::DominantSh, 1),
    (Encoding::DominantSh, 2),
    (Encoding::DominantSh, 4),
    (Encoding::SloanSh, 2),
    (Encoding::Zh3, 2),
    (Encoding::Zh3Hallucinated, 1),
    (Encoding::L1NonLinear, 1),
];

/// Normals of the default comparison grid (equirect texel centres).
pub const NORMALS: (usize, usize) = (128, 64);

/// The normals of a `w x h` equirect grid (y-up) and their solid angles.
#[must_use]
pub fn normal_grid(w: usize, h: usize) -> (Vec<DVec3>, Vec<f64>) {
    let o = MapOrientation::default();
    (0..w * h)
        .map(|k| {
            let (x, y) = (k % w, k / w);
            (
                equirect_direction(x, y, w, h, o),
                equirect_row_solid_angle(y, w, h),
            )
        })
        .unzip()
}

/// The error of an irradiance estimate against the exact one (module docs).
#[must_use]
pub fn irradiance_error(estimate: &[DVec3], exact: &[DVec3], weights: &[f64]) -> ErrorStats {
    let r: Vec<f64> = exact.iter().map(|e| luminance(*e)).collect();
    let e: Vec<f64> = estimate.iter().map(|e| luminance(*e)).collect();
    ErrorStats::weighted(&peak_relative_errors(&e, &r), weights)
}

/// One line of the table.
#[derive(Clone, Debug, PartialEq)]
pub struct CompareRow {
    /// The map's name.
    pub map: String,
    /// The encoding.
    pub encoding: Encoding,
    /// The SH part's lmax, for the encodings that take one.
    pub lmax: Option<usize>,
    /// Floats stored (RGB).
    pub floats: usize,
    /// Error relative to the peak irradiance.
    pub error: ErrorStats,
    /// Lights kept exactly.
    pub lights: usize,
    /// Degrees between the first light and the map's brightest texel (the
    /// sun's centre, where there is one).
    pub light_angle: Option<f64>,
}

impl CompareRow {
    /// `encoding` or `encoding lmax N`.
    #[must_use]
    pub fn label(&self) -> String {
        match self.lmax {
            Some(l) => format!("{} lmax {l}", self.encoding),
            None => self.encoding.to_string(),
        }
    }
}

/// The direction of the brightest texel (by luminance) of `map`.
#[must_use]
pub fn brightest_direction(map: &EnvMap<'_>) -> Option<DVec3> {
    let mut best: Option<(f64, DVec3)> = None;
    for y in 0..map.height {
        for x in 0..map.width {
            let l = luminance(DVec3::from(map.pixels[y * map.width + x].map(f64::from)));
            if best.is_none_or(|(b, _)| l > b)
                && let Some(d) = map.texel_direction(x, y)
            {
                best = Some((l, d));
            }
        }
    }
    best.map(|(_, d)| d)
}

/// Every [`CASES`] encoding of `map` (named `name`) against its exact
/// irradiance at a `normals` grid.
#[must_use]
pub fn compare_map(
    name: &str,
    map: &EnvMap<'_>,
    normals: (usize, usize),
    options: &DominantLightOptions,
) -> Vec<CompareRow> {
    let (dirs, weights) = normal_grid(normals.0, normals.1);
    let exact = irradiance_brute_force(map, &dirs, &|_| {});
    let sun = brightest_direction(map);
    let mut rows = Vec::new();
    let mut cases: Vec<(Encoding, usize)> = CASES.to_vec();
    cases.push((Encoding::AmbientCube, 0));
    for (encoding, lmax) in cases {
        let encoded = encode_map(map, encoding, lmax, options);
        rows.push(row(
            name, encoding, lmax, &encoded, &dirs, &exact, &weights, sun,
        ));
    }
    rows
}

#[allow(clippy::too_many_arguments)]
fn row(
    name: &str,
    encoding: Encoding,
    lmax: usize,
    encoded: &Encoded,
    dirs: &[DVec3],
    exact: &[DVec3],
    weights: &[f64],
    sun: Option<DVec3>,
) -> CompareRow {
    let estimate = encoded.irradiance_at(dirs);
    let lights = encoded.lights();
    CompareRow {
        map: name.to_string(),
        encoding,
        lmax: encoding.takes_lmax().then_some(lmax),
        floats: encoded.floats(encoding),
        error: irradiance_error(&estimate, exact, weights),
        lights: lights.len(),
        light_angle: lights
            .first()
            .zip(sun)
            .map(|(l, s)| l.direction.angle_between(s).to_degrees()),
    }
}

/// The rows as a Markdown table (errors in percent of the peak).
#[must_use]
pub fn table(rows: &[CompareRow]) -> String {
    let mut out = String::from(
        "| map | encoding | floats | mean | max | RMS | lights | light to brightest texel |\n\
         |---|---|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in rows {
        let angle = r
            .light_angle
            .map_or_else(|| "-".to_string(), |a| format!("{a:.2}°"));
        out.push_str(&format!(
            "| {} | {} | {} | {:.3}% | {:.3}% | {:.3}% | {} | {} |\n",
            r.map,
            r.label(),
            r.floats,
            100.0 * r.error.mean,
            100.0 * r.error.max,
            100.0 * r.error.rms,
            r.lights,
            angle
        ));
    }
    out
}

/// The rows as JSON: an array of objects with the table's fields (errors
/// as fractions of the peak).
#[must_use]
pub fn rows_json(rows: &[CompareRow]) -> Value {
    Value::Array(
        rows.iter()
            .map(|r| {
                json!({
                    "map": r.map,
                    "encoding": r.encoding.name(),
                    "lmax": r.lmax,
                    "floats": r.floats,
                    "mean": r.error.mean,
                    "max": r.error.max,
                    "rms": r.error.rms,
                    "lights": r.lights,
                    "light_angle_degrees": r.light_angle,
                })
            })
            .collect(),
    )
}

/// Max and mean error against floats stored for one map's rows (log-log
/// SVG): a line per encoding that takes an lmax, a point for the others.
///
/// # Errors
/// When plotters fails to draw.
pub fn floats_plot(map: &str, rows: &[CompareRow]) -> std::io::Result<String> {
    let mut series: Vec<Series> = Vec::new();
    for encoding in Encoding::ALL {
        let of: Vec<&CompareRow> = rows
            .iter()
            .filter(|r| r.map == map && r.encoding == encoding)
            .collect();
        if of.is_empty() {
            continue;
        }
        let pts = |f: fn(&ErrorStats) -> f64| -> Vec<(f64, f64)> {
            of.iter()
                .map(|r| (r.floats as f64, f(&r.error)))
                .filter(|p| p.1 > 0.0)
                .collect()
        };
        series.push(Series {
            label: format!("{encoding} (max)"),
            points: pts(|e| e.max),
            dashed: false,
        });
    }
    log_log_svg(
        &format!("Irradiance error against floats stored, {map}"),
        "floats stored (RGB)",
        "max error / peak irradiance",
        &series,
    )
}
