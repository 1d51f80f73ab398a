//! `shlight.sample`: what a baked file shades with at points, file to
//! file, as `shlight sample` writes it (shlight-pipeline's `sample` job).

use std::path::PathBuf;

use glam::DVec3;
use pyo3::prelude::*;
use shlight_pipeline::{SampleRequest, Spelling, sample as sample_job, sample_at, scene_points};
use shlight_volume::Lookup;

use crate::errors::{pipeline_error, warn_all};
use crate::guard::guard;
use crate::hooks::PyHooks;
use crate::options::albedo_of;
use crate::options::frame_of;
use crate::scene::SceneArg;

/// sample(file, output, *, points=None, env=None, light=None, up="y",
/// lookup="shlight", view=None, eye=None, albedo=None, lmax=None) -> None
/// --
///
/// See the package documentation (`help(shlight.sample)`).
#[pyfunction]
#[pyo3(signature = (file, output, *, points=None, env=None, light=None, up="y".to_string(),
    lookup="shlight".to_string(), view=None, eye=None, albedo=None, lmax=None))]
pub fn sample(
    py: Python<'_>,
    file: PathBuf,
    output: PathBuf,
    points: Option<SceneArg>,
    env: Option<PathBuf>,
    light: Option<PathBuf>,
    up: String,
    lookup: String,
    view: Option<[f64; 3]>,
    eye: Option<[f64; 3]>,
    albedo: Option<&Bound<'_, PyAny>>,
    lmax: Option<usize>,
) -> PyResult<()> {
    let (points, scene) = points.map(|p| p.split(py)).unzip();
    let scene = scene.flatten();
    let lookup: Lookup = Spelling::Python
        .parse("lookup", &lookup)
        .map_err(pipeline_error)?;
    let plan = SampleRequest {
        file: &file,
        output: &output,
        points: points.as_deref(),
        env: env.as_deref(),
        light: light.as_deref(),
        frame: frame_of(&up)?,
        lookup,
        view: view.map(DVec3::from_array),
        eye: eye.map(DVec3::from_array),
        albedo: albedo.map(albedo_of).transpose()?,
        lmax,
    }
    .check(Spelling::Python)
    .map_err(pipeline_error)?;
    let hooks = PyHooks::new(false);
    let done = py.detach(|| {
        guard(|| {
            match &scene {
                Some(s) => scene_points(s).and_then(|p| sample_at(&plan, &p, &hooks)),
                None => sample_job(&plan, &hooks),
            }
            .map_err(pipeline_error)
        })
    });
    warn_all(py, &hooks.warnings(), 1)?;
    warn_all(py, &hooks.notes(), 1)?;
    done.map(|_| ())
}
