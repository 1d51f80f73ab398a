//! `shlight.project` and `shlight.project_many`.

use std::borrow::Cow;
use std::path::PathBuf;

use pyo3::prelude::*;
use shlight_core::map::{CubeFaces, Layout, contiguous_pixels};
use shlight_format::{CoeffFile, ExportFormat};
use shlight_pipeline::{
    CpuProjector, GLTF_SPECULAR_SIZE, PreviewOptions, ProjectRequest, Settings,
    Source as MapSource, Spelling, StdoutForm, layout_for_size, project_each, project_files,
    project_with_warnings,
};
use shlight_specular::PrefilterSettings;

use crate::errors::{pipeline_error, shlight_error, warn_all};
use crate::guard::guard;
use crate::hooks::PyHooks;
use crate::options::RawOptions;
use crate::sh::Sh;
use crate::source::{ArrayMap, Source};

/// The name arrays go by in messages and in the file's provenance.
const ARRAY_NAME: &str = "<array>";

/// project(source, lmax=2, *, up="y", layout="auto", method="quadrature",
/// samples=None, sampler=None, seed=None, window=None, quantity="radiance",
/// mirror=False, sanitize=False, rotate=None, layer=None, max_pixels=None,
/// encoding="sh", output=None, format=None, preview=None,
/// preview_size=(512, 256), preview_exposure=None, preview_tone_map="aces",
/// specular_size=64, specular_samples=1024)
/// --
///
/// See the package documentation (`help(shlight.project)`).
#[pyfunction]
#[pyo3(signature = (source, lmax=2, *, up="y".to_string(), layout="auto".to_string(),
    method="quadrature".to_string(), samples=None, sampler=None, seed=None, window=None,
    quantity="radiance".to_string(), mirror=false, sanitize=false, rotate=None, layer=None,
    max_pixels=None, encoding="sh".to_string(), output=None, format=None, preview=None,
    preview_size=(512, 256), preview_exposure=None, preview_tone_map="aces".to_string(),
    specular_size=GLTF_SPECULAR_SIZE, specular_samples=PrefilterSettings::DEFAULT_SAMPLES))]
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
    output: Option<PathBuf>,
    format: Option<String>,
    preview: Option<PathBuf>,
    preview_size: (usize, usize),
    preview_exposure: Option<f32>,
    preview_tone_map: String,
    specular_size: usize,
    specular_samples: u32,
) -> PyResult<Sh> {
    let raw = RawOptions {
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
    };
    let outputs = Outputs {
        output,
        format,
        preview,
        preview_size,
        preview_exposure,
        preview_tone_map,
        specular_size,
        specular_samples,
    };
    let source = Source::from_py(source)?;
    if outputs.any() {
        let Source::Path(path) = &source else {
            return Err(shlight_error(
                "output, format and preview write what shlight project writes of a map file: give its path, or save the SH (SH.save, SH.export)",
            ));
        };
        let done = project_to_files(py, &raw, &outputs, std::slice::from_ref(path), false)?;
        let [one] = <[_; 1]>::try_from(done).expect("one input");
        return one.map(Sh::new).map_err(shlight_error);
    }
    let options = raw.resolve()?;
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

/// `project`'s and `project_many`'s writing options, as given from Python.
pub struct Outputs {
    output: Option<PathBuf>,
    format: Option<String>,
    preview: Option<PathBuf>,
    preview_size: (usize, usize),
    preview_exposure: Option<f32>,
    preview_tone_map: String,
    specular_size: usize,
    specular_samples: u32,
}

impl Outputs {
    /// Whether anything is written; `format` only with `output`.
    fn any(&self) -> bool {
        self.output.is_some() || self.format.is_some() || self.preview.is_some()
    }
}

/// Maps projected and written as `shlight project` writes them
/// (shlight-pipeline's `project_files`, one result per path, its error
/// text naming the path), with the warnings and notes issued; progress on
/// stderr if `progress`.
fn project_to_files(
    py: Python<'_>,
    raw: &RawOptions,
    outputs: &Outputs,
    paths: &[PathBuf],
    progress: bool,
) -> PyResult<Vec<Result<CoeffFile, String>>> {
    let mut options = raw.options()?;
    options.format = outputs
        .format
        .as_deref()
        .map(|f| Spelling::Python.parse::<ExportFormat>("format", f))
        .transpose()
        .map_err(pipeline_error)?;
    let request = ProjectRequest {
        options,
        inputs: paths,
        output: outputs.output.as_deref(),
        preview: outputs.preview.as_deref(),
        preview_options: PreviewOptions {
            panel: outputs.preview_size,
            exposure: outputs.preview_exposure,
            tone_map: Spelling::Python
                .parse("preview_tone_map", &outputs.preview_tone_map)
                .map_err(pipeline_error)?,
        },
        specular_size: outputs.specular_size,
        specular_samples: outputs.specular_samples,
        stdout: StdoutForm::Json,
    };
    let plan = request.check(Spelling::Python).map_err(pipeline_error)?;
    let hooks = PyHooks::new(progress);
    let done = py.detach(|| project_files(&plan, &CpuProjector, &hooks));
    warn_all(py, &hooks.warnings(), 2)?;
    warn_all(py, &hooks.notes(), 2)?;
    Ok(done
        .map_err(pipeline_error)?
        .into_iter()
        .map(|r| r.map(|p| p.file).map_err(|e| e.to_string()))
        .collect())
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
        Spelling::Python,
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

/// The size of six face arrays: square and of one size, read with the
/// faces layout (or `auto`).
fn face_size(faces: &[ArrayMap<'_>], o: &Settings) -> PyResult<usize> {
    if !matches!(
        o.read.layout,
        shlight_pipeline::InputLayout::Auto | shlight_pipeline::InputLayout::Faces
    ) {
        return Err(shlight_error(
            "six face arrays need layout=\"faces\" or \"auto\"",
        ));
    }
    let n = faces[0].width;
    match faces
        .iter()
        .position(|f| f.width != f.height || f.width != n)
    {
        Some(k) => Err(shlight_error(format!(
            "face {k} ({}): {}x{}; the six faces must be square and of one size ({n}x{n} like the first)",
            shlight_pipeline::FACE_NAMES[k],
            faces[k].width,
            faces[k].height
        ))),
        None => Ok(n),
    }
}

/// The projection of six `(N, N, 3)` face arrays (+X -X +Y -Y +Z -Z), read
/// in place when they are C-contiguous float32.
fn project_faces(
    py: Python<'_>,
    faces: &[ArrayMap<'_>],
    o: &Settings,
) -> PyResult<(CoeffFile, Vec<String>)> {
    let n = face_size(faces, o)?;
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

/// project_many(paths, lmax=2, *, errors="raise", progress=False, output=None, format=None, preview=None, **options)
/// --
///
/// See the package documentation (`help(shlight.project_many)`).
#[pyfunction]
#[pyo3(signature = (paths, lmax=2, *, errors="raise".to_string(), progress=false,
    up="y".to_string(), layout="auto".to_string(), method="quadrature".to_string(),
    samples=None, sampler=None, seed=None, window=None, quantity="radiance".to_string(),
    mirror=false, sanitize=false, rotate=None, layer=None, max_pixels=None,
    encoding="sh".to_string(), output=None, format=None, preview=None,
    preview_size=(512, 256), preview_exposure=None, preview_tone_map="aces".to_string(),
    specular_size=GLTF_SPECULAR_SIZE, specular_samples=PrefilterSettings::DEFAULT_SAMPLES))]
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
    output: Option<PathBuf>,
    format: Option<String>,
    preview: Option<PathBuf>,
    preview_size: (usize, usize),
    preview_exposure: Option<f32>,
    preview_tone_map: String,
    specular_size: usize,
    specular_samples: u32,
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
    let raw = RawOptions {
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
    };
    let outputs = Outputs {
        output,
        format,
        preview,
        preview_size,
        preview_exposure,
        preview_tone_map,
        specular_size,
        specular_samples,
    };
    let results = if outputs.any() {
        project_to_files(py, &raw, &outputs, &paths, progress)?
    } else {
        project_in_memory(py, &raw.resolve()?, &paths, progress)?
    };
    many_results(py, results, raise)
}

/// Maps projected in parallel by shlight-pipeline's `project_each`, with
/// the warnings issued; progress on stderr if `progress`.
fn project_in_memory(
    py: Python<'_>,
    settings: &Settings,
    paths: &[PathBuf],
    progress: bool,
) -> PyResult<Vec<Result<CoeffFile, String>>> {
    let hooks = PyHooks::new(progress && paths.len() > 1);
    let done = py.detach(|| project_each(paths, settings, &CpuProjector, &hooks));
    warn_all(py, &hooks.warnings(), 2)?;
    Ok(done
        .into_iter()
        .map(|r| r.map_err(|e| e.to_string()))
        .collect())
}

/// `project_many`'s answer: the SH of each path in order; a failed path
/// raises (with `raise`, one error listing every failure) or is None with
/// a warning.
fn many_results(
    py: Python<'_>,
    results: Vec<Result<CoeffFile, String>>,
    raise: bool,
) -> PyResult<Vec<Option<Sh>>> {
    let failed: Vec<&String> = results.iter().filter_map(|r| r.as_ref().err()).collect();
    if raise && !failed.is_empty() {
        let list: Vec<String> = failed.iter().map(|m| format!("  {m}")).collect();
        return Err(shlight_error(format!(
            "{} of {} inputs failed:\n{}",
            failed.len(),
            results.len(),
            list.join("\n")
        )));
    }
    results
        .into_iter()
        .map(|r| match r {
            Ok(file) => Ok(Some(Sh::new(file))),
            Err(msg) => warn_all(py, std::slice::from_ref(&msg), 2).map(|()| None),
        })
        .collect()
}
