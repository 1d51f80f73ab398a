//! Pictures of the suite's errors: log-log plots (SVG, through `plotters`)
//! and error maps over the sphere (equirect PNG with a colour scale).
//!
//! SVG text stays text (no font is rasterised), so plots need no system
//! fonts. Error maps carry their scale as a bar under the map, labelled with
//! a built-in 5x7 pixel font (digits, `.`, `%`, `e`, `-`, `+`).

use std::path::Path;

use glam::DVec3;
use plotters::prelude::*;
use shlight_io::{Image, IoError, WriteOptions, srgb_to_linear, write_atomically, write_image};

use crate::suite::{LmaxCurve, PROJECTION_LMAX, Report, Sweep};

/// Colours of the series, in order (sRGB).
const PALETTE: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
];

/// A plot's failure, as text (plotters' errors are generic over backends).
fn plot_error(e: impl std::fmt::Display) -> std::io::Error {
    std::io::Error::other(format!("drawing the plot: {e}"))
}

/// Bounds `(lo, hi)` of positive values, widened to whole decades.
fn decades(values: impl IntoIterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .into_iter()
        .filter(|v| *v > 0.0 && v.is_finite())
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if !lo.is_finite() {
        return (1e-3, 1.0);
    }
    (
        10f64.powf(lo.log10().floor()),
        10f64.powf(hi.log10().ceil().max(lo.log10().floor() + 1.0)),
    )
}

/// One line of a log-log plot ([`log_log_svg`]).
pub struct Series {
    /// Its name in the legend.
    pub label: String,
    /// Its points `(x, y)`; those not positive and finite are off the
    /// axes' ranges.
    pub points: Vec<(f64, f64)>,
    /// A grey dashed reference line (no markers) instead of a coloured
    /// one with a marker at each point.
    pub dashed: bool,
}

/// A log-log plot of `series` as an SVG document (720x480, text as SVG
/// text): both axes span the points' whole decades, the series coloured
/// in turn, with a legend.
///
/// # Errors
/// What `plotters` reports drawing it.
pub fn log_log_svg(
    title: &str,
    x_desc: &str,
    y_desc: &str,
    series: &[Series],
) -> std::io::Result<String> {
    let (x0, x1) = decades(series.iter().flat_map(|s| s.points.iter().map(|p| p.0)));
    let (y0, y1) = decades(series.iter().flat_map(|s| s.points.iter().map(|p| p.1)));
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (720, 480)).into_drawing_area();
        root.fill(&WHITE).map_err(plot_error)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 20))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(64)
            .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
            .map_err(plot_error)?;
        chart
            .configure_mesh()
            .x_desc(x_desc)
            .y_desc(y_desc)
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .x_label_formatter(&|v| {
                if *v >= 1e4 {
                    format!("{v:.0e}")
                } else {
                    format!("{v:.0}")
                }
            })
            .draw()
            .map_err(plot_error)?;
        for (i, s) in series.iter().enumerate() {
            let colour = if s.dashed {
                RGBColor(120, 120, 120)
            } else {
                PALETTE[i % PALETTE.len()]
            };
            let style = colour.stroke_width(2);
            let drawn = if s.dashed {
                chart
                    .draw_series(DashedLineSeries::new(s.points.clone(), 6, 4, style))
                    .map_err(plot_error)?
            } else {
                chart
                    .draw_series(LineSeries::new(s.points.clone(), style))
                    .map_err(plot_error)?
            };
            drawn.label(s.label.clone()).legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
            });
            if !s.dashed {
                chart
                    .draw_series(s.points.iter().map(|p| Circle::new(*p, 3, colour.filled())))
                    .map_err(plot_error)?;
            }
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::LowerLeft)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(plot_error)?;
        root.present().map_err(plot_error)?;
    }
    Ok(svg)
}

/// A reference line `y = y0 (x / x0)^p` over `xs`.
fn reference(label: &str, xs: &[f64], x0: f64, y0: f64, p: f64) -> Series {
    Series {
        label: label.into(),
        points: xs.iter().map(|x| (*x, y0 * (x / x0).powf(p))).collect(),
        dashed: true,
    }
}

fn sweep_label(s: &Sweep, name: &str) -> String {
    match s.slope {
        Some(p) => format!("{name} (slope {p:.2})"),
        None => name.to_string(),
    }
}

/// Monte Carlo error against samples for `case`: one line per sampler (the
/// RMS relative irradiance error over normals and seeds) and the `N^-1/2`
/// reference through the uniform sampler's first point.
///
/// # Errors
/// When plotters fails to draw.
pub fn mc_plot(report: &Report, case: &str) -> std::io::Result<String> {
    sweep_plot(
        report,
        |s| s.case == case && s.method.starts_with("mc-"),
        |s| sweep_label(s, s.method.trim_start_matches("mc-")),
        ("N^-1/2", -0.5),
        &format!("Monte Carlo projection error, {case}, lmax {PROJECTION_LMAX}"),
        "samples N",
    )
}

/// Equirect quadrature error against map width, every oracle, with the
/// `W^-2` reference.
///
/// # Errors
/// When plotters fails to draw.
pub fn quadrature_plot(report: &Report) -> std::io::Result<String> {
    sweep_plot(
        report,
        |s| s.method == "quadrature-equirect" && s.rms.iter().any(|v| *v > 0.0),
        |s| sweep_label(s, &s.case),
        ("W^-2", -2.0),
        &format!("Quadrature projection error (equirect W x W/2), lmax {PROJECTION_LMAX}"),
        "map width W",
    )
}

/// The RMS error of the sweeps `keep` picks, one line each (`label`), and
/// a reference power law `(name, exponent)` through the first line's
/// first point.
fn sweep_plot(
    report: &Report,
    keep: impl Fn(&Sweep) -> bool,
    label: impl Fn(&Sweep) -> String,
    (name, exponent): (&str, f64),
    title: &str,
    x_label: &str,
) -> std::io::Result<String> {
    let mut series: Vec<Series> = report
        .sweeps
        .iter()
        .filter(|s| keep(s))
        .map(|s| Series {
            label: label(s),
            points: s.x.iter().copied().zip(s.rms.iter().copied()).collect(),
            dashed: false,
        })
        .collect();
    if let Some(first) = series.first() {
        let xs: Vec<f64> = first.points.iter().map(|p| p.0).collect();
        let (x0, y0) = first.points[0];
        series.push(reference(name, &xs, x0, y0, exponent));
    }
    log_log_svg(title, x_label, "RMS relative irradiance error", &series)
}

/// Truncation and projection error against lmax for one oracle (mean
/// relative error; degrees where an error is 0 are left out of the log
/// scale).
///
/// # Errors
/// When plotters fails to draw.
pub fn lmax_plot(curve: &LmaxCurve) -> std::io::Result<String> {
    let pts = |v: &[f64]| -> Vec<(f64, f64)> {
        curve
            .lmax
            .iter()
            .zip(v)
            .filter(|(_, e)| **e > 0.0)
            .map(|(l, e)| ((*l + 1) as f64, *e))
            .collect()
    };
    let mut series = vec![Series {
        label: "truncation".into(),
        points: pts(&curve.truncation),
        dashed: false,
    }];
    if !curve.quadrature.is_empty() {
        let (w, h) = curve.resolution;
        series.push(Series {
            label: format!("quadrature {w}x{h}"),
            points: pts(&curve.quadrature),
            dashed: false,
        });
        series.push(Series {
            label: format!("sobol {}", curve.samples),
            points: pts(&curve.montecarlo),
            dashed: false,
        });
    }
    log_log_svg(
        &format!("Error against lmax, {}", curve.case),
        "lmax + 1",
        "mean relative irradiance error",
        &series,
    )
}

/// Writes an SVG document atomically.
///
/// # Errors
/// [`IoError`] naming the file.
pub fn write_svg(path: &Path, svg: &str) -> Result<(), IoError> {
    write_atomically(path, |w| w.write_all(svg.as_bytes()))
}

/// Size of the error maps [`write_pictures`] writes (2:1 equirect).
pub const ERROR_MAP_SIZE: (usize, usize) = (360, 180);

/// Oracles whose 9-term (lmax 2) truncation error [`write_pictures`] maps.
pub const MAPPED_ORACLES: [&str; 3] = ["directional", "cap30-el10", "quad-horizon"];

/// Writes every picture of `report` into `dir` (which must exist) and
/// returns their paths:
///
/// - `accuracy-mc-CASE.svg`: Monte Carlo error against samples, each
///   sampler, with the `N^-1/2` line ([`mc_plot`]);
/// - `accuracy-quadrature.svg`: equirect quadrature error against
///   resolution ([`quadrature_plot`]);
/// - `accuracy-lmax-CASE.svg`: truncation and projection error against
///   lmax ([`lmax_plot`]);
/// - `error-CASE-lmax2.png`: the 9-term irradiance's truncation error
///   `|E_2(n) - E(n)| / E_peak` over the sphere (360x180 y-up equirect, with
///   its colour scale), for [`MAPPED_ORACLES`].
///
/// # Errors
/// [`IoError`] naming the file that could not be written.
pub fn write_pictures(report: &Report, dir: &Path) -> Result<Vec<std::path::PathBuf>, IoError> {
    let mut written = Vec::new();
    let svg_error =
        |path: &Path, e: std::io::Error| IoError::new(path, shlight_io::IoErrorKind::Write(e));
    let mut cases: Vec<&str> = report
        .sweeps
        .iter()
        .filter(|s| s.method.starts_with("mc-"))
        .map(|s| s.case.as_str())
        .collect();
    cases.dedup();
    for case in cases {
        let path = dir.join(format!("accuracy-mc-{case}.svg"));
        let svg = mc_plot(report, case).map_err(|e| svg_error(&path, e))?;
        write_svg(&path, &svg)?;
        written.push(path);
    }
    let path = dir.join("accuracy-quadrature.svg");
    let svg = quadrature_plot(report).map_err(|e| svg_error(&path, e))?;
    write_svg(&path, &svg)?;
    written.push(path);
    for curve in &report.lmax_curves {
        let path = dir.join(format!("accuracy-lmax-{}.svg", curve.case));
        let svg = lmax_plot(curve).map_err(|e| svg_error(&path, e))?;
        write_svg(&path, &svg)?;
        written.push(path);
    }
    let normals = crate::suite::normals();
    for oracle in crate::oracle::suite_oracles()
        .into_iter()
        .filter(|o| MAPPED_ORACLES.contains(&o.name.as_str()))
    {
        let t = oracle.truncated(PROJECTION_LMAX);
        let exact: Vec<f64> = normals.iter().map(|n| oracle.irradiance(*n)).collect();
        let peak = crate::error::peak(&exact);
        let (image, _) = error_map(ERROR_MAP_SIZE.0, ERROR_MAP_SIZE.1, None, |d| {
            (t.eval(d) - oracle.irradiance(d)).abs() / peak
        });
        let path = dir.join(format!("error-{}-lmax{PROJECTION_LMAX}.png", oracle.name));
        write_error_map(&path, &image)?;
        written.push(path);
    }
    Ok(written)
}

/// Height of the colour bar and its labels under an error map, in pixels.
const BAR: usize = 36;

/// The colour of `t` in `[0, 1]` on a perceptually ordered scale (dark
/// blue, purple, orange, pale yellow; the "inferno" family), as sRGB.
#[must_use]
pub fn colour_scale(t: f64) -> [f64; 3] {
    const STOPS: [[f64; 3]; 6] = [
        [0.001, 0.000, 0.014],
        [0.258, 0.039, 0.406],
        [0.578, 0.148, 0.404],
        [0.865, 0.317, 0.226],
        [0.988, 0.645, 0.040],
        [0.988, 0.998, 0.645],
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        1.0
    };
    let x = t * (STOPS.len() - 1) as f64;
    let i = (x.floor() as usize).min(STOPS.len() - 2);
    let f = x - i as f64;
    std::array::from_fn(|c| STOPS[i][c] * (1.0 - f) + STOPS[i + 1][c] * f)
}

/// `value` as a short label: a percentage for values from 0.1%, else
/// scientific (`3.2e-5`).
#[must_use]
pub fn format_error(value: f64) -> String {
    if value == 0.0 {
        "0".into()
    } else if value >= 1e-3 {
        format!("{:.2}%", value * 100.0)
    } else {
        format!("{value:.1e}")
    }
}

/// An error map: `error(d)` at the centre of each texel of a `w x h` y-up
/// equirect map (as [`shlight_core::map::equirect_direction`]),
/// coloured from 0 to `max` (the largest value if `None`), with a colour bar
/// labelled `0`, `max/2` and `max` underneath. Returns the image (linear
/// values whose PNG encoding is the scale's sRGB colours) and the scale's
/// top.
#[must_use]
pub fn error_map(
    w: usize,
    h: usize,
    max: Option<f64>,
    error: impl Fn(DVec3) -> f64 + Sync,
) -> (Image, f64) {
    let o = shlight_core::map::MapOrientation::default();
    let values: Vec<f64> = (0..w * h)
        .map(|k| error(shlight_core::map::equirect_direction(k % w, k / w, w, h, o)))
        .collect();
    error_map_values(w, h, max, &values)
}

/// [`error_map`] of values already computed, one per texel of the `w x h`
/// map, row-major (top row first).
///
/// Panics if `values.len() != w * h`.
#[must_use]
pub fn error_map_values(w: usize, h: usize, max: Option<f64>, values: &[f64]) -> (Image, f64) {
    assert_eq!(values.len(), w * h, "one value per texel");
    let top = max
        .unwrap_or_else(|| values.iter().copied().fold(0.0, f64::max))
        .max(f64::MIN_POSITIVE);
    let linear = |srgb: [f64; 3]| srgb.map(|c| srgb_to_linear(c as f32));
    let mut image = Image::from_fn(w, h + BAR, |x, y| {
        if y < h {
            linear(colour_scale(values[y * w + x] / top))
        } else if y < h + 4 {
            [1.0; 3]
        } else if y < h + 16 {
            linear(colour_scale(x as f64 / (w - 1).max(1) as f64))
        } else {
            [1.0; 3]
        }
    });
    for (text, at) in [
        ("0".to_string(), 0.0),
        (format_error(top / 2.0), 0.5),
        (format_error(top), 1.0),
    ] {
        let width = text.len() * 6;
        let x = ((at * w as f64) as usize).saturating_sub(width / 2);
        let x = x.min(w.saturating_sub(width + 1)).max(1);
        draw_text(&mut image, x, h + 20, &text);
    }
    (image, top)
}

/// Writes an error map as PNG (8-bit sRGB, values already in `[0, 1]`).
///
/// # Errors
/// [`IoError`] naming the file.
pub fn write_error_map(path: &Path, image: &Image) -> Result<(), IoError> {
    write_image(path, image, &WriteOptions::default())
}

/// 5x7 glyphs, rows top to bottom, bit 4 the leftmost pixel.
fn glyph(c: char) -> Option<[u8; 7]> {
    Some(match c {
        '0' => [0x0e, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0e],
        '1' => [0x04, 0x0c, 0x04, 0x04, 0x04, 0x04, 0x0e],
        '2' => [0x0e, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1f],
        '3' => [0x1f, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0e],
        '4' => [0x02, 0x06, 0x0a, 0x12, 0x1f, 0x02, 0x02],
        '5' => [0x1f, 0x10, 0x1e, 0x01, 0x01, 0x11, 0x0e],
        '6' => [0x06, 0x08, 0x10, 0x1e, 0x11, 0x11, 0x0e],
        '7' => [0x1f, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08],
        '8' => [0x0e, 0x11, 0x11, 0x0e, 0x11, 0x11, 0x0e],
        '9' => [0x0e, 0x11, 0x11, 0x0f, 0x01, 0x02, 0x0c],
        '.' => [0, 0, 0, 0, 0, 0x0c, 0x0c],
        '%' => [0x18, 0x19, 0x02, 0x04, 0x08, 0x13, 0x03],
        '-' => [0, 0, 0, 0x1f, 0, 0, 0],
        '+' => [0, 0x04, 0x04, 0x1f, 0x04, 0x04, 0],
        'e' => [0, 0, 0x0e, 0x11, 0x1f, 0x10, 0x0e],
        _ => return None,
    })
}

/// Draws `text` in black with its top-left corner at `(x, y)`; characters
/// without a glyph leave a gap.
fn draw_text(image: &mut Image, x: usize, y: usize, text: &str) {
    for (k, c) in text.chars().enumerate() {
        let Some(rows) = glyph(c) else { continue };
        for (dy, bits) in rows.iter().enumerate() {
            for dx in 0..5 {
                let (px, py) = (x + 6 * k + dx, y + dy);
                if bits & (0x10 >> dx) != 0 && px < image.width() && py < image.height() {
                    image.set(px, py, [0.0; 3]);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_colour_scale_runs_from_dark_to_light() {
        let lum = |c: [f64; 3]| 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
        let mut last = -1.0;
        for k in 0..=20 {
            let l = lum(colour_scale(k as f64 / 20.0));
            assert!(l > last, "not increasing at {k}");
            last = l;
        }
    }

    #[test]
    fn error_maps_put_the_scale_under_the_map() {
        let (image, top) = error_map(64, 32, None, |d| d.y.max(0.0));
        assert_eq!((image.width(), image.height()), (64, 32 + BAR));
        assert!((top - 0.9988).abs() < 1e-3, "{top}");
        // Left end of the bar is the scale's bottom, right end its top.
        let bar = |x| image.get(x, 32 + 8);
        let want = |t| colour_scale(t).map(|c| srgb_to_linear(c as f32));
        assert_eq!(bar(0), want(0.0));
        assert_eq!(bar(63), want(1.0));
        // Labels are drawn in black.
        assert!((0..64).any(|x| image.get(x, 32 + 22) == [0.0; 3]));
        assert_eq!(format_error(0.09375), "9.38%");
        assert_eq!(format_error(3.2e-5), "3.2e-5");
    }

    #[test]
    fn error_maps_of_values_use_a_fixed_scale_when_given() {
        // Row 0 at 0, row 1 at half the scale, row 2 above it (clamped).
        let values: Vec<f64> = (0..12).map(|k| [0.0, 0.05, 0.3][k / 4]).collect();
        let (image, top) = error_map_values(4, 3, Some(0.1), &values);
        assert_eq!(top, 0.1);
        let want = |t| colour_scale(t).map(|c| srgb_to_linear(c as f32));
        assert_eq!(image.get(1, 0), want(0.0));
        assert_eq!(image.get(2, 1), want(0.5));
        assert_eq!(image.get(3, 2), want(1.0));
    }

    #[test]
    fn plots_are_svg_with_their_series() {
        let report = Report {
            sweeps: vec![Sweep {
                case: "c".into(),
                method: "mc-uniform".into(),
                x: vec![1e3, 1e4, 1e5],
                rms: vec![1e-2, 3e-3, 1e-3],
                slope: Some(-0.5),
            }],
            ..Report::default()
        };
        let svg = mc_plot(&report, "c").unwrap();
        assert!(svg.starts_with("<svg"));
        assert!(svg.contains("uniform (slope -0.50)") && svg.contains("N^-1/2"));
    }
}
