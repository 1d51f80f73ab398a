//! [`project_streaming`]: `shlight project` of an equirect map file by
//! quadrature with no image buffer: the file's rows, as they are decoded
//! ([`shlight_io::open_rows`]), go straight into the ring sums
//! ([`RingAccumulator`]) and the value statistics.

use std::path::Path;
use std::sync::{Mutex, PoisonError};

use shlight_core::map::{Layout, RingAccumulator};
use shlight_format::SanitizeCounts;
use shlight_io::{PixelStats, RowSource, SanitizeReport, open_rows, sanitize_pixels};

use crate::Result;
use crate::hooks::{Hooks, Progress};
use crate::load::{check_values, layout_for_size, read_error, sanitize_warning};
use crate::map_info::MapInfo;
use crate::projector::Projection;
use crate::settings::Settings;

/// A map projected by [`project_streaming`]: the coefficients, the file's
/// record of the map, and the warnings for the user.
pub(crate) struct Projected {
    pub(crate) projection: Projection,
    pub(crate) info: MapInfo,
    pub(crate) warnings: Vec<String>,
}

/// What [`project_streaming`] did with a map.
pub(crate) enum Streamed {
    /// Projected.
    Projected(Box<Projected>),
    /// A file the reader read whole (see [`shlight_io::open_rows`]): the
    /// image, for the in-memory route.
    Whole(shlight_io::Image),
    /// Not equirect: for the in-memory route, which reads the file.
    NotEquirect,
}

/// Projects the map file at `path` (named `name`) by quadrature as its rows
/// are decoded; a map this route does not take (a layout other than
/// equirect, or a file the reader must hold whole: see
/// [`shlight_io::open_rows`]) is left to the caller's in-memory route.
///
/// The coefficients, statistics, warnings and errors are those of the
/// in-memory route bit for bit: every row's sums are the ring transform's
/// own ([`RingAccumulator`]), the statistics are merged from bands, and
/// `--sanitize` replaces values band by band, with `+inf` by the largest
/// finite value of the whole map; a map holding `+inf` is therefore read
/// twice with `--sanitize` (the first pass finds that value).
///
/// # Errors
/// As [`crate::load_map`], then NaN or infinite texels without
/// `sanitize` ([`check_values`]), after the rows are read.
pub(crate) fn project_streaming(
    path: &Path,
    name: &str,
    s: &Settings,
    hooks: &dyn Hooks,
) -> Result<Streamed> {
    let rows = open_rows(path, &s.read.read).map_err(|e| read_error(e, s.read.spelling))?;
    if !rows.streams() {
        let image = rows
            .into_image()
            .expect("a source that does not stream holds its image");
        return Ok(Streamed::Whole(image));
    }
    let (w, h) = rows.size();
    let mut warnings = Vec::new();
    let layout = layout_for_size(name, s.read.layout, w, h, s.read.spelling, &mut warnings)?;
    if layout != Layout::Equirect {
        return Ok(Streamed::NotEquirect);
    }
    let p = &s.project;
    hooks.progress(Progress::Step(&format!(
        "projecting {name} ({w}x{h}, lmax {})",
        p.lmax
    )));
    // Without `--sanitize`, or with it when the map holds no +inf, one
    // pass; the first pass replaces +inf by 0 and is run again otherwise.
    let (mut acc, stats, mut report) = pass(rows.as_ref(), s, s.read.sanitize.then_some(0.0))?;
    let sanitized = if s.read.sanitize {
        let largest = stats.max_value.max(0.0);
        let mut r = report.take().expect("sanitized");
        if r.positive_infinite > 0 {
            (acc, _, report) = pass(rows.as_ref(), s, Some(largest))?;
            r = report.expect("sanitized");
        }
        r.infinity_replacement = largest;
        let counts = SanitizeCounts::from(r);
        sanitize_warning(name, &counts, s.read.spelling, &mut warnings);
        Some(counts)
    } else {
        check_values(name, &stats, s.read.spelling, &mut warnings)?;
        None
    };
    let coeffs = acc
        .finish()
        .map_err(|e| crate::PipelineError::new(format!("{name}: {e}")))?;
    Ok(Streamed::Projected(Box::new(Projected {
        projection: Projection::exact(coeffs),
        info: MapInfo::new(name, layout.name(), (w, h), stats, sanitized),
        warnings,
    })))
}

/// One read of the rows into a fresh accumulator, with the statistics of
/// the values as read and, with `replace_infinity`, what sanitizing each
/// band (`+inf` by that value) replaced.
fn pass(
    rows: &dyn RowSource,
    s: &Settings,
    replace_infinity: Option<f32>,
) -> Result<(RingAccumulator, PixelStats, Option<SanitizeReport>)> {
    let (w, h) = rows.size();
    let acc = RingAccumulator::new(w, h, s.project.lmax, s.project.orientation);
    let stats = Mutex::new(StatsSum::default());
    let report = Mutex::new(None::<SanitizeReport>);
    rows.read_rows(&|first, band: &[[f32; 3]]| {
        let part = PixelStats::of_pixels(band, w);
        stats
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .add(first, part, 3 * band.len());
        // From a decoder's own threads, each band on the thread that
        // decoded it (summing on rayon's pool could wait forever on
        // workers that wait for this read, in a batch); from the calling
        // thread, on the pool.
        let add = |first, band: &[[f32; 3]]| {
            if rows.calls_from_many_threads() {
                acc.add_rows(first, band);
            } else {
                acc.add_rows_parallel(first, band);
            }
        };
        match replace_infinity {
            None => add(first, band),
            Some(largest) => {
                let mut copy = band.to_vec();
                let r = sanitize_pixels(&mut copy, largest);
                let mut total = report.lock().unwrap_or_else(PoisonError::into_inner);
                *total = Some(total.map_or(r, |t| t.combined(r)));
                drop(total);
                add(first, &copy);
            }
        }
    })?;
    let stats = stats.into_inner().unwrap_or_else(PoisonError::into_inner);
    let report = report.into_inner().unwrap_or_else(PoisonError::into_inner);
    Ok((acc, stats.total(), report))
}

/// [`PixelStats`] of bands of rows that come in any order, merged as
/// [`crate::source_stats`] merges rows: counts added, ranges of the bands
/// with a finite value joined, the first non-finite texel the least in
/// row-major order.
struct StatsSum {
    stats: PixelStats,
    any_finite: bool,
}

impl Default for StatsSum {
    fn default() -> Self {
        Self {
            stats: PixelStats {
                non_finite: 0,
                first_non_finite: None,
                negative: 0,
                min_value: f32::INFINITY,
                max_value: f32::NEG_INFINITY,
            },
            any_finite: false,
        }
    }
}

impl StatsSum {
    /// Adds `part`, the statistics of a band of `values` channel values
    /// whose first row is `first`.
    fn add(&mut self, first: usize, part: PixelStats, values: usize) {
        let t = &mut self.stats;
        t.non_finite += part.non_finite;
        t.negative += part.negative;
        if let Some((x, y)) = part.first_non_finite {
            let at = (x, first + y);
            let earlier = |(ax, ay): (usize, usize), (bx, by): (usize, usize)| (ay, ax) < (by, bx);
            if t.first_non_finite.is_none_or(|old| earlier(at, old)) {
                t.first_non_finite = Some(at);
            }
        }
        // A band without finite values reports a range of 0..0; skip it.
        if part.non_finite < values {
            self.any_finite = true;
            t.min_value = t.min_value.min(part.min_value);
            t.max_value = t.max_value.max(part.max_value);
        }
    }

    fn total(self) -> PixelStats {
        let mut t = self.stats;
        if !self.any_finite {
            t.min_value = 0.0;
            t.max_value = 0.0;
        }
        t
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cpu_projector::CpuProjector;
    use crate::hooks::Collected;
    use crate::project::{Source, project};
    use crate::projector::Projector;
    use crate::settings::{Method, ProjectSettings};
    use shlight_core::map::{MapOrientation, TexelSource};
    use shlight_core::sh::Frame;
    use shlight_format::Quantity;
    use shlight_io::{Image, WriteOptions, write_image};

    /// The CPU projector on the whole map: the in-memory route.
    struct InMemory;

    impl Projector for InMemory {
        fn project(&self, texels: &dyn TexelSource, s: &ProjectSettings) -> Result<Projection> {
            CpuProjector.project(texels, s)
        }
    }

    /// The coefficient file as JSON and the warnings, or the error.
    fn run(path: &Path, s: &Settings, projector: &dyn Projector) -> (String, Vec<String>) {
        let hooks = Collected::new();
        let out = match project(Source::Path(path), s, projector, &hooks) {
            Ok(file) => file.to_json_string(),
            Err(e) => format!("error: {e}"),
        };
        (out, hooks.into_warnings())
    }

    /// Files streamed into the ring sums give the in-memory route's file,
    /// warnings and errors exactly: clean maps and maps with NaN, +inf,
    /// -inf and negatives, with and without `--sanitize` (the +inf map
    /// takes the second pass), both frames, direct sums and FFT, scan
    /// lines and a non-2:1 map.
    #[test]
    fn streamed_files_give_the_in_memory_file_bit_for_bit() {
        let dir = std::env::temp_dir().join(format!("shlight-stream-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let (w, h) = (96, 47);
        let base = Image::from_fn(w, h, |x, y| {
            let v = ((x * 7919 + y * 104_729) % 1009) as f32 / 100.0;
            [v, 0.5 * v + 0.25, (x % 13) as f32]
        });
        let mut special = base.clone();
        special.set(4, 2, [f32::NAN, 1.0, 2.0]);
        special.set(90, 40, [f32::INFINITY, -3.0, f32::NEG_INFINITY]);
        special.set(17, 20, [-0.5, 1e6, 0.0]);
        let mut negative = base.clone();
        negative.set(3, 3, [-1.0, 2.0, 3.0]);
        let mut maps = Vec::new();
        for (name, image) in [
            ("clean", &base),
            ("special", &special),
            ("negative", &negative),
        ] {
            let path = dir.join(format!("{name}.exr"));
            write_image(&path, image, &WriteOptions::default()).unwrap();
            maps.push(path);
        }
        let mut streamed_any = false;
        for path in &maps {
            for (lmax, frame, sanitize) in [
                (4, Frame::YUp, false),
                (4, Frame::YUp, true),
                (60, Frame::ZUp, true),
                (60, Frame::ZUp, false),
            ] {
                let orientation = MapOrientation {
                    frame,
                    mirror: false,
                };
                // The automatic window at lmax 60 would take seconds; the
                // windows are not what is tested here.
                let mut p =
                    ProjectSettings::new(lmax, orientation, Method::Quadrature, Quantity::Radiance);
                if lmax < 10 {
                    p.window = None;
                }
                let mut s = Settings::new(p);
                s.read.sanitize = sanitize;
                s.read.layout = crate::InputLayout::Image(Layout::Equirect);
                let name = path.display().to_string();
                let streamed = project_streaming(path, &name, &s, &crate::Silent);
                streamed_any |= matches!(streamed, Ok(Streamed::Projected(_)));
                let want = run(path, &s, &InMemory);
                let got = run(path, &s, &CpuProjector);
                assert_eq!(got, want, "{name} lmax {lmax} {frame} sanitize {sanitize}");
            }
        }
        assert!(streamed_any, "no map took the streaming route");
        let mut s = Settings::new(ProjectSettings::new(
            2,
            MapOrientation::default(),
            Method::Quadrature,
            Quantity::Radiance,
        ));
        s.read.layout = crate::InputLayout::Image(Layout::Equirect);
        let (special_error, _) = run(&maps[1], &s, &CpuProjector);
        assert!(
            special_error.contains("texels are NaN or infinite (the first at x=4, y=2)"),
            "{special_error}"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
