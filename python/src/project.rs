//! `shlight.project` and `shlight.project_many`.

use std::borrow::Cow;
use std::path::PathBuf;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use pyo3::prelude::*;
use rayon::prelude::*;
use shlight_core::map::{CubeFaces, Layout, contiguous_pixels};
use shlight_format::CoeffFile;
use shlight_pipeline::{Settings, Source as MapSource, layout_for_size, project_with_warnings};

use crate::errors::{pipeline_error, shlight_error, warn_all};
use crate::guard::{guard, panic_text};
use crate::options::RawOptions;
use crate::sh::Sh;
use crate::source::{ArrayMap, Source};

/// The name arrays go by in messages and in the file's provenance.
const ARRAY_NAME: &str = "<array>";

/// project(source, lmax=2, *, up="y", layout="auto", method="quadrature",
/// samples=None, sampler=None, seed=None, window=None, quantity="radiance",
/// mirror=False, sanitize=False, rotate=None, layer=None, max_pixels=None,
/// encoding="sh")
/// --
///
/// See the package documentation (`help(shlight.project)`).
#[pyfunction]
#[pyo3(signature = (source, lmax=2, *, up="y".to_string(), layout="auto".to_string(),
    method="quadrature".to_string(), samples=None, sampler=None, seed=None, window=None,
    quantity="radiance".to_string(), mirror=false, sanitize=false, rotate=None, layer=None,
    max_pixels=None, encoding="sh".to_string()))]
pub fn project(
    py: Python<'_>,
    source: &Bound<'_, PyAny>,
    lmax: usize,
    up: String,
    layout: String,
    method: String,
    samples: Option<usize>,
    sampler: Option<String>,
    seed: Option<u64>,
    window: Option<String>,
    quantity: String,
    mirror: bool,
    sanitize: bool,
    rotate: Option<String>,
    layer: Option<String>,
    max_pixels: Option<usize>,
    encoding: String,
) -> PyResult<Sh> {
    let options = RawOptions {
        lmax,
        up,
        layout,
        method,
        samples,
        sampler,
        seed,
        window,
        quantity,
        mirror,
        sanitize,
        rotate,
        layer,
        max_pixels,
        encoding,
    }
    .resolve()?;
    let source = Source::from_py(source)?;
    let (file, warnings) = match &source {
        Source::Path(path) => {
            let path = path.clone();
            py.detach(|| guard(|| project_one(&path, &options)))?
        }
        Source::Array(array) => project_array(py, array, &options)?,
        Source::Faces(faces) => project_faces(py, faces, &options)?,
    };
    warn_all(py, &warnings, 2)?;
    Ok(Sh::new(file))
}

/// The projection of one file: every step of `shlight project`.
fn project_one(path: &std::path::Path, o: &Settings) -> PyResult<(CoeffFile, Vec<String>)> {
    project_with_warnings(MapSource::Path(path), o).map_err(pipeline_error)
}

/// The projection of an `(H, W, 3)` array in the options' layout, read in
/// place with the GIL released.
fn project_array(
    py: Python<'_>,
    array: &ArrayMap<'_>,
    o: &Settings,
) -> PyResult<(CoeffFile, Vec<String>)> {
    let mut warnings = Vec::new();
    let layout = layout_for_size(
        ARRAY_NAME,
        o.read.layout,
        array.width,
        array.height,
        &mut warnings,
    )
    .map_err(pipeline_error)?;
    let view = array.view(layout);
    let (file, more) = py.detach(|| {
        guard(|| {
            let source = MapSource::Texels {
                texels: &view,
                name: ARRAY_NAME,
                layout_name: layout.name(),
            };
            project_with_warnings(source, o).map_err(pipeline_error)
        })
    })?;
    warnings.extend(more);
    Ok((file, warnings))
}

/// The projection of six `(N, N, 3)` face arrays (+X -X +Y -Y +Z -Z), read
/// in place when they are C-contiguous float32.
fn project_faces(
    py: Python<'_>,
    faces: &[ArrayMap<'_>],
    o: &Settings,
) -> PyResult<(CoeffFile, Vec<String>)> {
    if !matches!(
        o.read.layout,
        shlight_pipeline::InputLayout::Auto | shlight_pipeline::InputLayout::Faces
    ) {
        return Err(shlight_error(
            "six face arrays need layout=\"faces\" or \"auto\"",
        ));
    }
    let n = faces[0].width;
    for (k, f) in faces.iter().enumerate() {
        if f.width != f.height || f.width != n {
            return Err(shlight_error(format!(
                "face {k} ({}): {}x{}; the six faces must be square and of one size ({n}x{n} like the first)",
                shlight_pipeline::FACE_NAMES[k],
                f.width,
                f.height
            )));
        }
    }
    let views: Vec<_> = faces.iter().map(|f| f.view(Layout::Strip)).collect();
    let pixels: Vec<Cow<'_, [[f32; 3]]>> = views
        .iter()
        .map(|v| {
            v.contiguous()
                .map_or_else(|| contiguous_pixels(v), Cow::Borrowed)
        })
        .collect();
    let slices: Vec<&[[f32; 3]]> = pixels.iter().map(|p| &p[..]).collect();
    let cube = CubeFaces::new(n, slices.try_into().expect("six faces"))
        .map_err(|e| shlight_error(format!("{ARRAY_NAME}: {e}")))?;
    py.detach(|| {
        guard(|| {
            let source = MapSource::Texels {
                texels: &cube,
                name: ARRAY_NAME,
                layout_name: "faces",
            };
            project_with_warnings(source, o).map_err(pipeline_error)
        })
    })
}

/// project_many(paths, lmax=2, *, errors="raise", progress=False, **options)
/// --
///
/// See the package documentation (`help(shlight.project_many)`).
#[pyfunction]
#[pyo3(signature = (paths, lmax=2, *, errors="raise".to_string(), progress=false,
    up="y".to_string(), layout="auto".to_string(), method="quadrature".to_string(),
    samples=None, sampler=None, seed=None, window=None, quantity="radiance".to_string(),
    mirror=false, sanitize=false, rotate=None, layer=None, max_pixels=None,
    encoding="sh".to_string()))]
pub fn project_many(
    py: Python<'_>,
    paths: Vec<PathBuf>,
    lmax: usize,
    errors: String,
    progress: bool,
    up: String,
    layout: String,
    method: String,
    samples: Option<usize>,
    sampler: Option<String>,
    seed: Option<u64>,
    window: Option<String>,
    quantity: String,
    mirror: bool,
    sanitize: bool,
    rotate: Option<String>,
    layer: Option<String>,
    max_pixels: Option<usize>,
    encoding: String,
) -> PyResult<Vec<Option<Sh>>> {
    let raise = match errors.as_str() {
        "raise" => true,
        "none" => false,
        other => {
            return Err(shlight_error(format!(
                "errors={other:?}: expected \"raise\" (one exception listing every failed path) or \"none\" (None in its place, and a warning)"
            )));
        }
    };
    let options = RawOptions {
        lmax,
        up,
        layout,
        method,
        samples,
        sampler,
        seed,
        window,
        quantity,
        mirror,
        sanitize,
        rotate,
        layer,
        max_pixels,
        encoding,
    }
    .resolve()?;
    let results: Vec<Result<(CoeffFile, Vec<String>), String>> = py.detach(|| {
        let bar = if progress {
            let bar = ProgressBar::with_draw_target(
                Some(paths.len() as u64),
                ProgressDrawTarget::stderr(),
            );
            bar.set_style(
                ProgressStyle::with_template("{bar:40} {pos}/{len} maps {elapsed} (eta {eta})")
                    .expect("a valid template"),
            );
            bar
        } else {
            ProgressBar::hidden()
        };
        let out = paths
            .par_iter()
            .map(|path| {
                let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                    project_with_warnings(MapSource::Path(path), &options)
                }));
                bar.inc(1);
                match r {
                    Ok(Ok(done)) => Ok(done),
                    Ok(Err(e)) => {
                        // As the CLI's batch: every message names its input.
                        let (msg, input) = (e.to_string(), path.display().to_string());
                        Err(if msg.contains(&input) {
                            msg
                        } else {
                            format!("{input}: {msg}")
                        })
                    }
                    Err(p) => Err(format!(
                        "{}: internal error (please report it): {}",
                        path.display(),
                        panic_text(p.as_ref())
                    )),
                }
            })
            .collect();
        bar.finish_and_clear();
        out
    });
    let failed: Vec<&String> = results.iter().filter_map(|r| r.as_ref().err()).collect();
    if raise && !failed.is_empty() {
        let list: Vec<String> = failed.iter().map(|m| format!("  {m}")).collect();
        return Err(shlight_error(format!(
            "{} of {} inputs failed:\n{}",
            failed.len(),
            paths.len(),
            list.join("\n")
        )));
    }
    let mut out = Vec::with_capacity(results.len());
    for r in results {
        match r {
            Ok((file, warnings)) => {
                warn_all(py, &warnings, 2)?;
                out.push(Some(Sh::new(file)));
            }
            Err(msg) => {
                warn_all(py, std::slice::from_ref(&msg), 2)?;
                out.push(None);
            }
        }
    }
    Ok(out)
}
