//! Every encoding on the bundled maps against their exact irradiance
//! (`shlight_accuracy::compare`), held to what the docs publish: the
//! encodings tables of README.md and docs/accuracy.md are parsed out of the
//! files themselves and every cell is recomputed at the docs' resolution
//! (128x64 normals), so a doc edit without a code change (or a code change
//! without a doc edit) fails here. The prose around the tables (the cut
//! the dominant lights make, the share of the lmax 1 to lmax 2 gap ZH3
//! closes) is checked to the digits it prints.

use std::collections::BTreeMap;
use std::path::Path;

use glam::DVec3;
use shlight_accuracy::compare::{self, CompareRow, compare_map};
use shlight_core::encoding::{DominantLightOptions, Encoding};
use shlight_core::map::{EnvMap, Layout, MapOrientation};
use shlight_io::{Image, ReadOptions, read_image};

/// A table cell may be this far (relative) from the published figure: the
/// figures are rounded, and the sums behind them may be ordered
/// differently on another machine.
const CELL: f64 = 0.05;

/// What "not worse beyond noise" allows: the residual's SH differs from the
/// map's only where the lights were, and the cap model from the texels only
/// at each light's horizon (a few texels' worth of its power).
const NOISE: f64 = 0.02;

fn repo_file(rel: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(rel);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn bundled(name: &str) -> Image {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../../envmaps/{name}.exr"));
    read_image(&path, &ReadOptions::default()).expect("bundled map")
}

fn equirect(image: &Image) -> EnvMap<'_> {
    EnvMap::new(
        Layout::Equirect,
        MapOrientation::default(),
        image.width(),
        image.height(),
        image.pixels(),
    )
    .unwrap()
}

/// Every map's rows at the docs' normals, as `shlight compare` makes them.
fn computed(maps: &[String]) -> BTreeMap<String, Vec<CompareRow>> {
    maps.iter()
        .map(|name| {
            let image = bundled(name);
            let rows = compare_map(
                name,
                &equirect(&image),
                compare::NORMALS,
                &DominantLightOptions::default(),
            );
            eprint!("{}", compare::table(&rows));
            (name.clone(), rows)
        })
        .collect()
}

fn row<'a>(rows: &'a [CompareRow], label: &str) -> &'a CompareRow {
    rows.iter()
        .find(|r| r.label() == label)
        .unwrap_or_else(|| panic!("no computed row {label:?}"))
}

/// The cells of the Markdown table whose header line is `header`: one
/// vector of trimmed cells per body line.
fn table_after(doc: &str, header: &str) -> Vec<Vec<String>> {
    let mut lines = doc.lines().skip_while(|l| l.trim() != header);
    assert!(lines.next().is_some(), "no table headed {header:?}");
    assert!(lines.next().is_some_and(|l| l.starts_with("|---")));
    lines
        .take_while(|l| l.starts_with('|'))
        .map(|l| {
            l.trim()
                .trim_matches('|')
                .split('|')
                .map(|c| c.trim().to_string())
                .collect()
        })
        .collect()
}

fn percent(cell: &str) -> f64 {
    cell.strip_suffix('%')
        .and_then(|v| v.parse::<f64>().ok())
        .unwrap_or_else(|| panic!("not a percentage: {cell:?}"))
        / 100.0
}

/// Tracks the largest relative distance of a computed cell from its
/// published figure, and fails on any beyond [`CELL`].
#[derive(Default)]
struct Cells {
    worst: f64,
    count: usize,
}

impl Cells {
    fn check(&mut self, what: &str, got: f64, published: f64) {
        let rel = (got - published).abs() / published.abs();
        eprintln!("{what}: computed {got:.6}, published {published:.6} ({rel:+.4})");
        assert!(rel <= CELL, "{what}: computed {got}, published {published}");
        self.worst = self.worst.max(rel);
        self.count += 1;
    }
}

/// Whitespace runs as one space (so prose wrapped across lines reads as
/// one line).
fn squash(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// The text of `doc` after the first `start` and before the next `end`.
fn between<'a>(doc: &'a str, start: &str, end: &str) -> &'a str {
    let from = doc
        .find(start)
        .unwrap_or_else(|| panic!("the docs no longer say {start:?}"))
        + start.len();
    let len = doc[from..]
        .find(end)
        .unwrap_or_else(|| panic!("no {end:?} after {start:?}"));
    &doc[from..from + len]
}

/// The figure written just before `({map}` in `text`, as printed (digits
/// and point), with its unit `unit` stripped: `2.6x (park` gives `2.6`.
fn figure_before(text: &str, map: &str, unit: char) -> String {
    let at = text
        .find(&format!("({map}"))
        .unwrap_or_else(|| panic!("{map} not named in {text:?}"));
    let before = text[..at].trim_end();
    let before = before
        .strip_suffix(unit)
        .unwrap_or_else(|| panic!("no {unit} figure before ({map} in {text:?}"));
    let start = before
        .rfind(|c: char| !(c.is_ascii_digit() || c == '.'))
        .map_or(0, |i| i + 1);
    before[start..].to_string()
}

/// `value` printed to as many decimals as `published` has.
fn as_printed(value: f64, published: &str) -> String {
    let decimals = published.split('.').nth(1).map_or(0, str::len);
    format!("{value:.decimals$}")
}

/// Lights taken out of each bundled map, as README.md says in words ("one
/// each in park, sky and studio; none in the overcast city").
const LIGHTS: [(&str, usize); 4] = [("park", 1), ("city", 0), ("sky", 1), ("studio", 1)];

/// Every figure of the encodings tables and the prose around them.
#[test]
fn the_docs_encodings_tables_hold_at_128x64_normals() {
    let readme = repo_file("README.md");
    let accuracy = repo_file("docs/accuracy.md");

    // The docs' resolution is the one computed at.
    assert_eq!(compare::NORMALS, (128, 64));
    assert!(
        squash(&readme).contains(
            "Max irradiance error relative to the peak (`shlight compare`, 128x64 normals)"
        ),
        "README.md's table no longer states its resolution"
    );
    assert!(squash(&accuracy).contains("at the 128x64 texel centres of an equirect grid"));

    let header = "| encoding | floats | park | city | sky | studio |";
    let maps: Vec<String> = header
        .trim_matches('|')
        .split('|')
        .skip(2)
        .map(|m| m.trim().to_string())
        .collect();
    let rows = computed(&maps);
    let mut cells = Cells::default();

    // README.md: max error per map, floats per encoding.
    let readme_rows = table_after(&readme, header);
    assert_eq!(
        readme_rows.len(),
        9,
        "README.md's table lost or gained rows"
    );
    for cells_of in &readme_rows {
        let label = &cells_of[0];
        for (m, map) in maps.iter().enumerate() {
            let r = row(&rows[map], label);
            cells.check(
                &format!("README {map} {label} max"),
                r.error.max,
                percent(&cells_of[2 + m]),
            );
            // `34 (city 27)`: a map named in brackets stores another count.
            let floats = &cells_of[1];
            let published: usize = floats
                .split_once(&format!("({map} "))
                .map_or_else(
                    || floats.split_whitespace().next().unwrap_or(""),
                    |(_, rest)| rest.trim_end_matches(')'),
                )
                .parse()
                .unwrap_or_else(|_| panic!("floats cell {floats:?}"));
            assert_eq!(r.floats, published, "README {map} {label} floats");
        }
    }

    // docs/accuracy.md: every row of every map, and no other.
    let accuracy_rows = table_after(
        &accuracy,
        "| map | encoding | floats | mean | max | RMS | lights | light to brightest texel |",
    );
    let published: Vec<(String, String)> = accuracy_rows
        .iter()
        .map(|c| (c[0].clone(), c[1].clone()))
        .collect();
    let all: Vec<(String, String)> = rows
        .values()
        .flatten()
        .map(|r| (r.map.clone(), r.label()))
        .collect();
    let mut sorted = published.clone();
    sorted.sort();
    let mut all_sorted = all.clone();
    all_sorted.sort();
    assert_eq!(
        sorted, all_sorted,
        "docs/accuracy.md's rows against the computed ones"
    );
    for c in &accuracy_rows {
        let (map, label) = (&c[0], &c[1]);
        let r = row(&rows[map], label);
        let what = format!("accuracy.md {map} {label}");
        assert_eq!(r.floats.to_string(), c[2], "{what} floats");
        cells.check(&format!("{what} mean"), r.error.mean, percent(&c[3]));
        cells.check(&format!("{what} max"), r.error.max, percent(&c[4]));
        cells.check(&format!("{what} RMS"), r.error.rms, percent(&c[5]));
        assert_eq!(r.lights.to_string(), c[6], "{what} lights");
        match c[7].strip_suffix('°') {
            Some(deg) => cells.check(
                &format!("{what} light angle"),
                r.light_angle.expect("a light"),
                deg.parse().unwrap(),
            ),
            None => assert_eq!((c[7].as_str(), r.light_angle), ("-", None), "{what}"),
        }
    }
    eprintln!(
        "{} cells, the furthest {:.2}% from its published figure",
        cells.count,
        100.0 * cells.worst
    );

    // The lights found, as README.md says them.
    for (map, n) in LIGHTS {
        assert_eq!(
            row(&rows[map], "dominant+sh lmax 2").lights,
            n,
            "{map}: lights taken out"
        );
    }

    // Dominant lights + lmax 2 is never worse than lmax 2 (beyond noise),
    // and cuts its max error by the factors the docs print.
    let mut cuts = Vec::new();
    let falls = squash(between(
        &accuracy,
        "the max error falls",
        "for 7 more floats",
    ));
    for map in &maps {
        let sh2 = row(&rows[map], "sh lmax 2").error;
        let dom = row(&rows[map], "dominant+sh lmax 2");
        for (d, s) in [(dom.error.max, sh2.max), (dom.error.mean, sh2.mean)] {
            assert!(
                d <= s * (1.0 + NOISE),
                "{map}: dominant+sh {:?} against sh {sh2:?}",
                dom.error
            );
        }
        if dom.lights > 0 {
            let cut = sh2.max / dom.error.max;
            let printed = figure_before(&falls, map, 'x');
            eprintln!("{map}: cut {cut:.4}, docs/accuracy.md {printed}x");
            assert_eq!(as_printed(cut, &printed), printed, "{map}: the cut");
            cuts.push(cut);
        }
    }
    let readme = squash(&readme);
    let range = between(&readme, "cuts lmax 2's max error ", " and is never worse");
    let (lo, hi) = range.split_once(" to ").expect("A to B");
    let (lo, hi) = (lo.trim_end_matches('x'), hi.trim_end_matches('x'));
    let least = cuts.iter().copied().fold(f64::INFINITY, f64::min);
    let most = cuts.iter().copied().fold(0.0, f64::max);
    assert_eq!(
        (as_printed(least, lo), as_printed(most, hi)),
        (lo.to_string(), hi.to_string()),
        "README.md's range of cuts"
    );

    // ZH3 between lmax 1 and lmax 2, and the share of the gap it closes.
    let closes = squash(between(&accuracy, "(RMS_1 - RMS_2)` =", "of the gap"));
    let mut gaps = Vec::new();
    for map in &maps {
        let (l1, l2, zh3) = (
            row(&rows[map], "sh lmax 1").error.rms,
            row(&rows[map], "sh lmax 2").error.rms,
            row(&rows[map], "zh3").error.rms,
        );
        assert!(
            l2 <= zh3 && zh3 <= l1,
            "{map}: ZH3 {zh3} not in [{l2}, {l1}]"
        );
        let gap = 100.0 * (l1 - zh3) / (l1 - l2);
        let printed = figure_before(&closes, map, '%');
        eprintln!("{map}: ZH3 closes {gap:.4}% of the gap, docs/accuracy.md {printed}%");
        assert_eq!(as_printed(gap, &printed), printed, "{map}: ZH3's share");
        gaps.push((gap, printed));
    }
    let range = between(
        &readme,
        "ZH3 sits between lmax 1 and 2, closing ",
        " of the gap",
    );
    let (lo, hi) = range.split_once(" to ").expect("A to B");
    let (lo, hi) = (lo.trim_end_matches('%'), hi.trim_end_matches('%'));
    let least = gaps.iter().min_by(|a, b| a.0.total_cmp(&b.0)).unwrap();
    let most = gaps.iter().max_by(|a, b| a.0.total_cmp(&b.0)).unwrap();
    // README.md quotes the ends of docs/accuracy.md's list, figure for figure.
    assert_eq!(
        (lo, hi),
        (least.1.as_str(), most.1.as_str()),
        "README.md's ZH3 range against docs/accuracy.md"
    );
}

#[test]
fn the_ambient_cube_reproduces_the_exact_irradiance_at_the_axes() {
    let image = bundled("studio");
    let map = equirect(&image);
    let cube = match shlight_core::encoding::encode_map(
        &map,
        Encoding::AmbientCube,
        0,
        &DominantLightOptions::default(),
    ) {
        shlight_core::encoding::Encoded::AmbientCube(c) => c,
        other => panic!("{other:?}"),
    };
    // The irradiance at each axis summed here, texel by texel.
    let omega = map.texel_solid_angles();
    for axis in shlight_core::encoding::AMBIENT_CUBE_AXES {
        let mut e = DVec3::ZERO;
        for y in 0..map.height {
            for x in 0..map.width {
                let d = map.texel_direction(x, y).unwrap();
                let l = DVec3::from(map.pixels[y * map.width + x].map(f64::from));
                e += l * omega[y * map.width + x] * axis.dot(d).max(0.0);
            }
        }
        let got = cube.irradiance(axis);
        assert!(
            (got - e).abs().max_element() <= 1e-9 * e.max_element(),
            "{axis}: {got} {e}"
        );
    }
}
