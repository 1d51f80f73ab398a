//! `shlight.bake_volume` and `shlight.Volume`: an irradiance volume baked
//! by the library call `shlight volume` makes
//! (`shlight_volume::bake_file`), its `.shvol` file, relit as `shlight
//! sample --env` relights it and read at points by the lookups of `shlight
//! sample --lookup` (`shlight_volume::PreparedLookup`).

use std::path::PathBuf;

use glam::Vec3;
use numpy::ndarray::{Array2, Array3};
use numpy::{
    AllowTypeChange, IntoPyArray, PyArray1, PyArray2, PyArray3, PyArrayLike2, PyUntypedArrayMethods,
};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use shlight_baked::ProbeGrid;
use shlight_format::threejs_volume::Precision;
use shlight_format::{SamplePoints, ShvolFile, VolumeFormat};
use shlight_mesh::LightUnits;
use shlight_pipeline::{
    Spelling, VolumeRequest, relight_volume, visibility_size, volume, volume_irradiance,
    volume_lookup, volume_of_scene,
};
use shlight_volume::{Lookup, VolumeBakeSettings, VolumeOptions};

use crate::errors::{chained, pipeline_error, shlight_error, warn_all};
use crate::guard::guard;
use crate::hooks::PyHooks;
use crate::options::albedo_of;
use crate::scene::SceneArg;
use crate::scene::bake_scene_arg;

/// An irradiance volume (a `.shvol` file, docs/shvol.md): SH probes on a
/// grid through a scene, with their validity, positions, distance maps
/// and, when relightable, transfer matrices. `shlight.bake_volume` bakes
/// one, `Volume.load(path)` reads one; `relight(env)` gives it under
/// another light, `irradiance(points, normals)` reads it at points, and
/// `write(path)` saves it.
#[pyclass(name = "Volume", module = "shlight", frozen)]
pub struct Volume {
    file: ShvolFile,
}

/// `format=` and `precision=` of a volume written from Python.
fn volume_format(
    format: Option<&str>,
    precision: &str,
) -> PyResult<(Option<VolumeFormat>, Precision)> {
    let format = format
        .map(|f| Spelling::Python.parse("format", f))
        .transpose()
        .map_err(pipeline_error)?;
    let precision = Spelling::Python
        .parse("precision", precision)
        .map_err(pipeline_error)?;
    Ok((format, precision))
}

/// An `(N, 3)` array of `what` from Python, each value rounded to f32 as a
/// points file's numbers are.
fn rows3(array: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<[f32; 3]>> {
    let m = array
        .extract::<PyArrayLike2<'_, f64, AllowTypeChange>>()
        .map_err(|_| PyValueError::new_err(format!("{what} must be an (N, 3) array of numbers")))?;
    if m.shape()[1] != 3 {
        return Err(PyValueError::new_err(format!(
            "{what} must have shape (N, 3), not {:?}",
            m.shape()
        )));
    }
    let a = m.as_array();
    Ok(a.rows()
        .into_iter()
        .map(|r| [r[0] as f32, r[1] as f32, r[2] as f32])
        .collect())
}

#[pymethods]
impl Volume {
    /// Reads a `.shvol` file (docs/shvol.md; versions 1 and 2). Raises
    /// ShlightError for a missing or malformed file.
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Volume> {
        let file = py.detach(|| guard(|| ShvolFile::read(&path).map_err(|e| chained(&e))))?;
        Ok(Volume { file })
    }

    /// Highest SH degree of every probe ((lmax+1)**2 coefficients).
    #[getter]
    fn lmax(&self) -> usize {
        self.file.lmax
    }

    /// Probes along x, y and z (x fastest in every per-probe array).
    #[getter]
    fn resolution(&self) -> (usize, usize, usize) {
        let [x, y, z] = self.file.resolution;
        (x, y, z)
    }

    /// The grid's box, ((x0, y0, z0), (x1, y1, z1)); a probe sits at each
    /// cell's centre (moved by `offsets`).
    #[getter]
    fn bounds(&self) -> ([f32; 3], [f32; 3]) {
        self.file.bounds
    }

    /// Number of probes, nx * ny * nz.
    #[getter]
    fn probe_count(&self) -> usize {
        self.file.probe_count()
    }

    /// (N,) bool: whether a lookup may use each probe (False: inside
    /// geometry).
    #[getter]
    fn valid<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<bool>> {
        self.file.valid.clone().into_pyarray(py)
    }

    /// (N, 3) float32: where each probe's rays were cast from (its cell's
    /// centre plus its offset).
    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f32>> {
        let flat: Vec<f32> = self.file.positions().into_iter().flatten().collect();
        Array2::from_shape_vec((self.file.probe_count(), 3), flat)
            .expect("N x 3 positions")
            .into_pyarray(py)
    }

    /// (N, 3) float32: each probe's move from its cell's centre, out of
    /// geometry; None for a volume baked without relocation.
    #[getter]
    fn offsets<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray2<f32>>> {
        self.file.offsets.as_ref().map(|o| {
            Array2::from_shape_vec((self.file.probe_count(), 3), o.clone())
                .expect("N x 3 offsets")
                .into_pyarray(py)
        })
    }

    /// Whether the file keeps transfer matrices (False: baked static, it
    /// cannot be relit).
    #[getter]
    fn relightable(&self) -> bool {
        self.file.relightable()
    }

    /// Whether the file holds the probes' distance maps (the shlight
    /// lookup's visibility; without them it is trilinear).
    #[getter]
    fn has_visibility(&self) -> bool {
        self.file.visibility.is_some()
    }

    /// (N, (lmax+1)**2, 3) float32: each probe's incident radiance SH, row
    /// l*(l+1)+m, columns R, G, B (under the bake's environment, or the
    /// last relight's).
    #[getter]
    fn radiance<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray3<f32>> {
        let f = &self.file;
        Array3::from_shape_vec(
            (f.probe_count(), f.coeffs_per_channel(), 3),
            f.radiance.clone(),
        )
        .expect("N x (lmax+1)^2 x 3 values")
        .into_pyarray(py)
    }

    /// The frame of the probes' coefficients ("y-up").
    #[getter]
    fn frame(&self) -> &str {
        &self.file.frame
    }

    /// The scene's file name, as the file records it.
    #[getter]
    fn scene(&self) -> &str {
        &self.file.scene
    }

    /// The environment's file name, as the file records it.
    #[getter]
    fn environment(&self) -> &str {
        &self.file.environment
    }

    /// Rays per probe of the bake.
    #[getter]
    fn samples(&self) -> u64 {
        self.file.rays_per_probe
    }

    /// Interreflection bounces of the surfaces' light.
    #[getter]
    fn bounces(&self) -> u32 {
        self.file.bounces
    }

    /// Seed of the ray directions.
    #[getter]
    fn seed(&self) -> u64 {
        self.file.seed
    }

    /// The punctual lights the bake took, as the file records them:
    /// {"units": "blender" | "as-written", "point": n, "spot": n,
    /// "directional": n}; None for a scene without lights.
    #[getter]
    fn lights<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(l) = &self.file.lights else {
            return Ok(None);
        };
        let dict = PyDict::new(py);
        dict.set_item("units", &l.units)?;
        dict.set_item("point", l.point)?;
        dict.set_item("spot", l.spot)?;
        dict.set_item("directional", l.directional)?;
        Ok(Some(dict))
    }

    /// A new Volume, its probes relit under another light (`shlight
    /// sample VOLUME --env ENV`; this Volume is left as it is): per probe
    /// and channel `L = M L_env + L_emitted`, the transfer matrices of the
    /// bake applied to the light's radiance SH (kept to the volume's lmax,
    /// higher degrees zero where the light stops below it).
    ///
    /// `env` is a path (an equirect map, projected with its top row facing
    /// `up`, or a radiance coefficient file) or an `SH` of plain radiance;
    /// coefficients are taken as they are stored, in the volume's frame,
    /// as the command line takes them. To turn the light, rotate an `SH`
    /// first (`SH.rotate`).
    ///
    /// Raises ShlightError for a volume baked with static=True (no
    /// transfer matrices), an unreadable light, an SH of irradiance or of
    /// an encoding.
    #[pyo3(signature = (env, *, up="y"))]
    fn relight(&self, py: Python<'_>, env: &Bound<'_, PyAny>, up: &str) -> PyResult<Volume> {
        let (light, warnings) = crate::light::light_of(py, env, up)?;
        warn_all(py, &warnings, 2)?;
        let mut file = self.file.clone();
        py.detach(|| {
            guard(|| {
                relight_volume(&mut file, None, &light, Spelling::Python).map_err(pipeline_error)
            })
        })?;
        Ok(Volume { file })
    }

    /// The irradiance E(p, n) = sum A_l L_lm(p) Y_lm(n) at each point p
    /// facing its normal n (`shlight sample VOLUME --points P --lookup L`):
    /// what a renderer shades with there (a Lambertian surface of albedo a
    /// leaves a E / pi).
    ///
    /// `points` and `normals` are (N, 3) arrays (any float dtype; rounded to
    /// float32 as a points file's numbers are; normals normalised). `lookup`
    /// is how L(p) is read off the probes: "shlight" (trilinear weights
    /// times each probe's visibility of the point, from the distance maps;
    /// trilinear for a volume without them), "trilinear" (the valid probes
    /// among the eight around p, weights renormalised), "bevy" (Bevy's
    /// lookup of the KTX2 export: half-float ambient cubes; 0 outside the
    /// box) or "threejs" (three.js's LightProbeGrid: p moved half a probe
    /// spacing along n, L2 SH; 0 where that leaves the box). `lmax`: the
    /// highest degree shaded (default: the volume's, at most 4 for shlight
    /// and trilinear, at most 2 for threejs, with a UserWarning when
    /// degrees are left out). Runs on every core with the GIL released.
    ///
    /// Returns (N, 3) float64 RGB. Raises ValueError for a shape that is
    /// not (N, 3), ShlightError for counts that differ, a point or normal
    /// that is not finite (or a zero normal), an unknown lookup or an lmax
    /// the lookup cannot shade.
    #[pyo3(signature = (points, normals, lookup="shlight", lmax=None))]
    fn irradiance<'py>(
        &self,
        py: Python<'py>,
        points: &Bound<'py, PyAny>,
        normals: &Bound<'py, PyAny>,
        lookup: &str,
        lmax: Option<usize>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let lookup: Lookup = Spelling::Python
            .parse("lookup", lookup)
            .map_err(pipeline_error)?;
        let settled = volume_lookup(&self.file, None, lookup, lmax, Spelling::Python)
            .map_err(pipeline_error)?;
        let at = SamplePoints::new(
            rows3(points, "points")?,
            rows3(normals, "normals")?,
            "points and normals",
        )
        .map_err(|e| chained(&e))?;
        let hooks = PyHooks::new(false);
        let values: Vec<f64> = py.detach(|| {
            guard(|| {
                let values = volume_irradiance(&self.file, None, lookup, &settled, &at, &hooks);
                Ok(values.into_iter().flatten().collect())
            })
        })?;
        warn_all(py, &hooks.notes(), 2)?;
        Ok(Array2::from_shape_vec((at.points.len(), 3), values)
            .expect("N x 3 values")
            .into_pyarray(py))
    }

    /// Writes the file atomically: `.shvol` (docs/shvol.md), its JSON form
    /// for a `.json` name, Bevy's KTX2 texture for `.ktx2`, or `format`
    /// ("shvol", "json", "bevy", "threejs", three.js's grid at `precision`
    /// "half" or "f32"); the bytes `shlight volume -o PATH --format F`
    /// writes. Returns the writer's notes.
    #[pyo3(signature = (path, format=None, precision="half"))]
    fn write(
        &self,
        py: Python<'_>,
        path: PathBuf,
        format: Option<&str>,
        precision: &str,
    ) -> PyResult<Vec<String>> {
        let (format, precision) = volume_format(format, precision)?;
        let format = format.unwrap_or_else(|| VolumeFormat::from_path(&path));
        py.detach(|| {
            guard(|| {
                self.file
                    .write_as(&path, format, precision)
                    .map_err(|e| chained(&e))
            })
        })
    }

    fn __repr__(&self) -> String {
        let f = &self.file;
        let [x, y, z] = f.resolution;
        format!(
            "Volume(resolution=({x}, {y}, {z}), lmax={}, probes={}, invalid={}, relightable={}, visibility={}, scene={:?})",
            f.lmax,
            f.probe_count(),
            f.valid.iter().filter(|v| !**v).count(),
            if f.relightable() { "True" } else { "False" },
            if f.visibility.is_some() {
                "True"
            } else {
                "False"
            },
            f.scene
        )
    }
}

/// `resolution=`: (nx, ny, nz) or "NXxNYxNZ".
fn resolution_of(resolution: &Bound<'_, PyAny>) -> PyResult<[usize; 3]> {
    if let Ok(text) = resolution.extract::<String>() {
        return ProbeGrid::parse_resolution(&text).map_err(shlight_error);
    }
    resolution.extract::<[usize; 3]>().map_err(|_| {
        PyValueError::new_err("resolution must be (nx, ny, nz), whole numbers of at least 1")
    })
}

/// `bounds=`: None, ((x0, y0, z0), (x1, y1, z1)) or "X0,Y0,Z0:X1,Y1,Z1".
fn bounds_of(bounds: Option<&Bound<'_, PyAny>>) -> PyResult<Option<(Vec3, Vec3)>> {
    let Some(bounds) = bounds else {
        return Ok(None);
    };
    if let Ok(text) = bounds.extract::<String>() {
        return ProbeGrid::parse_bounds(&text)
            .map(Some)
            .map_err(shlight_error);
    }
    let (min, max) = bounds.extract::<([f32; 3], [f32; 3])>().map_err(|_| {
        PyValueError::new_err("bounds must be ((x0, y0, z0), (x1, y1, z1)) or None")
    })?;
    Ok(Some((Vec3::from_array(min), Vec3::from_array(max))))
}

/// bake_volume(scene, env, resolution=(8, 4, 8), bounds=None, lmax=2,
/// samples=1024, bounces=2, surface_samples=512, albedo=0.8,
/// invalid_backfaces=0.5, seed=0, relocate=True, visibility=True,
/// static_only=False, output=None, format=None, precision="half", preview=None,
/// preview_ball=32, light_units="blender", max_edge=None) -> Volume
/// --
///
/// See the package documentation (`help(shlight.bake_volume)`).
#[pyfunction]
#[pyo3(signature = (scene, env, resolution=None, bounds=None, lmax=2, samples=1024, bounces=2,
    surface_samples=512, albedo=None, invalid_backfaces=0.5, seed=0, relocate=true,
    visibility=true, static_only=false, output=None, format=None, precision="half", preview=None,
    preview_ball=32, light_units="blender", max_edge=None))]
pub fn bake_volume(
    py: Python<'_>,
    scene: SceneArg,
    env: PathBuf,
    resolution: Option<&Bound<'_, PyAny>>,
    bounds: Option<&Bound<'_, PyAny>>,
    lmax: usize,
    samples: usize,
    bounces: u32,
    surface_samples: usize,
    albedo: Option<&Bound<'_, PyAny>>,
    invalid_backfaces: f32,
    seed: u64,
    relocate: bool,
    visibility: bool,
    static_only: bool,
    output: Option<PathBuf>,
    format: Option<&str>,
    precision: &str,
    preview: Option<PathBuf>,
    preview_ball: usize,
    light_units: &str,
    max_edge: Option<f32>,
) -> PyResult<Volume> {
    let (scene, loaded) = scene.split(py);
    let (format, precision) = volume_format(format, precision)?;
    let light_units: LightUnits = Spelling::Python
        .parse("light_units", light_units)
        .map_err(pipeline_error)?;
    let resolution = match resolution {
        Some(r) => resolution_of(r)?,
        None => [8, 4, 8],
    };
    let plan = VolumeRequest {
        scene: &scene,
        env: &env,
        output: output.as_deref(),
        format,
        precision,
        bake: VolumeBakeSettings {
            resolution,
            bounds: bounds_of(bounds)?,
            options: VolumeOptions {
                lmax,
                samples,
                bounces,
                surface_samples,
                max_edge,
                albedo: albedo.map(albedo_of).transpose()?.unwrap_or([0.8; 3]),
                invalid_backfaces,
                seed,
                relocate,
                visibility_size: visibility_size(visibility),
                light_units,
            },
            relightable: !static_only,
        },
        preview: preview.as_deref(),
        preview_ball,
    }
    .check(Spelling::Python)
    .map_err(pipeline_error)?;
    let baked = bake_scene_arg(
        py,
        loaded.as_deref(),
        |hooks| volume(&plan, hooks),
        |scene, hooks| volume_of_scene(&plan, scene, hooks),
    )?;
    Ok(Volume { file: baked.file })
}
