//! `shlight.bake_lightmap` and `shlight.Lightmap`: a glTF scene's
//! lightmap baked by the job `shlight lightmap` runs
//! (`shlight_pipeline::lightmap`), its layers as numpy arrays.

use std::path::PathBuf;

use numpy::ndarray::{Array3, Array4};
use numpy::{IntoPyArray, PyArray3, PyArray4};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use shlight_lightmap::LightmapSettings;
use shlight_mesh::LightUnits;
use shlight_pipeline::{
    LightmapBaked, LightmapRequest, Spelling, engine_by_name, lightmap, lightmap_of_scene,
    lightmap_size, reconstruction, texel_basis,
};
use shlight_volume::VolumeOptions;

use crate::errors::pipeline_error;
use crate::options::albedo_of;
use crate::scene::SceneArg;
use crate::scene::bake_scene_arg;

/// A baked lightmap: one square atlas, a region per placed node, its
/// texels packed for an engine (`layers`, named by `layer_names`), and
/// the irradiance each texel holds (`irradiance`).
#[pyclass(name = "Lightmap", module = "shlight", frozen)]
pub struct Lightmap {
    baked: LightmapBaked,
}

#[pymethods]
impl Lightmap {
    /// Texels a side.
    #[getter]
    fn side(&self) -> u32 {
        self.baked.lightmap.side
    }

    /// Texels per metre of surface.
    #[getter]
    fn texels_per_metre(&self) -> f64 {
        self.baked.lightmap.density
    }

    /// The layers' names, in the order of `layers`.
    #[getter]
    fn layer_names(&self) -> Vec<&'static str> {
        self.baked.format.layer_names().to_vec()
    }

    /// The texels as the engine reads them: float32 of shape `(layers,
    /// side, side, 4)`, row 0 at v = 0 (glTF's top row).
    #[getter]
    fn layers<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray4<f32>> {
        let side = self.baked.lightmap.side as usize;
        let n = self.baked.layers.len();
        let flat: Vec<f32> = self
            .baked
            .layers
            .iter()
            .flat_map(|l| l.iter().flatten().copied())
            .collect();
        Array4::from_shape_vec((n, side, side, 4), flat)
            .expect("layers of side x side texels")
            .into_pyarray(py)
    }

    /// The irradiance gathered at each texel for its surface's normal
    /// (W/m2 for radiance in W/(m2 sr)), float64 of shape `(side, side,
    /// 3)`; NaN where no surface is.
    #[getter]
    fn irradiance<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray3<f64>> {
        let side = self.baked.lightmap.side as usize;
        let flat: Vec<f64> = self
            .baked
            .lightmap
            .texels
            .iter()
            .flat_map(|t| t.map_or([f64::NAN; 3], |t| t.irradiance.to_array()))
            .collect();
        Array3::from_shape_vec((side, side, 3), flat)
            .expect("side x side texels")
            .into_pyarray(py)
    }

    /// One dict per placed node: `node` (its index in the glTF file),
    /// `label`, `rect` (x, y, side in texels) and `scale_offset` (the
    /// node's `TEXCOORD_1 * scale + offset` in the atlas: su, sv, ou, ov).
    #[getter]
    fn regions<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        self.baked
            .lightmap
            .regions
            .iter()
            .map(|r| {
                let d = PyDict::new(py);
                d.set_item("node", r.node)?;
                d.set_item("label", &r.label)?;
                d.set_item("rect", (r.rect.x, r.rect.y, r.rect.side))?;
                d.set_item(
                    "scale_offset",
                    (
                        r.placement.scale.x,
                        r.placement.scale.y,
                        r.placement.offset.x,
                        r.placement.offset.y,
                    ),
                )?;
                d.set_item("covered", r.covered)?;
                Ok(d)
            })
            .collect()
    }

    /// Texels found inside geometry and filled from their neighbours.
    #[getter]
    fn invalid(&self) -> usize {
        self.baked.lightmap.invalid
    }

    /// Rays per texel.
    #[getter]
    fn samples(&self) -> usize {
        self.baked.lightmap.samples
    }

    /// UV seams stitched.
    #[getter]
    fn seams(&self) -> usize {
        self.baked.lightmap.seams
    }

    fn __repr__(&self) -> String {
        let m = &self.baked.lightmap;
        format!(
            "Lightmap({} x {}, {} regions, {:.1} texels per metre, layers {:?})",
            m.side,
            m.side,
            m.regions.len(),
            m.density,
            self.baked.format.layer_names()
        )
    }
}

/// bake_lightmap(scene, env, ...) -> Lightmap
/// --
///
/// See the package documentation (`help(shlight.bake_lightmap)`).
#[pyfunction]
#[pyo3(signature = (scene, env, output=None, basis="irradiance", engine="threejs",
    non_linear=false, size=None, texel_density=None, padding=2, denoise=2, samples=256, bounces=8,
    surface_samples=512, max_edge=None, lmax=2, albedo=None, invalid_backfaces=0.5,
    light_units="blender", seed=0, unshare_instances=false, exr=None, preview=None))]
pub fn bake_lightmap(
    py: Python<'_>,
    scene: SceneArg,
    env: PathBuf,
    output: Option<PathBuf>,
    basis: &str,
    engine: &str,
    non_linear: bool,
    size: Option<u32>,
    texel_density: Option<f64>,
    padding: u32,
    denoise: u32,
    samples: usize,
    bounces: u32,
    surface_samples: usize,
    max_edge: Option<f32>,
    lmax: usize,
    albedo: Option<&Bound<'_, PyAny>>,
    invalid_backfaces: f32,
    light_units: &str,
    seed: u64,
    unshare_instances: bool,
    exr: Option<PathBuf>,
    preview: Option<PathBuf>,
) -> PyResult<Lightmap> {
    let (scene, loaded) = scene.split(py);
    let py_spelling = Spelling::Python;
    let light_units: LightUnits = py_spelling
        .parse("light_units", light_units)
        .map_err(pipeline_error)?;
    let plan = LightmapRequest {
        scene: &scene,
        env: &env,
        output: output.as_deref(),
        basis: texel_basis(basis, py_spelling).map_err(pipeline_error)?,
        engine: engine_by_name(engine, py_spelling).map_err(pipeline_error)?,
        reconstruction: reconstruction(non_linear),
        settings: LightmapSettings {
            size: lightmap_size(size, texel_density, py_spelling).map_err(pipeline_error)?,
            padding,
            denoise,
            gather: VolumeOptions {
                lmax,
                samples,
                bounces,
                surface_samples,
                max_edge,
                invalid_backfaces,
                seed,
                light_units,
                ..LightmapSettings::default().gather
            },
            ..LightmapSettings::default()
        },
        albedo: albedo.map(albedo_of).transpose()?.unwrap_or([0.8; 3]),
        unshare_instances,
        exr: exr.as_deref(),
        preview: preview.as_deref(),
    }
    .check(Spelling::Python)
    .map_err(pipeline_error)?;
    let baked = bake_scene_arg(
        py,
        loaded.as_deref(),
        |hooks| lightmap(&plan, hooks),
        |scene, hooks| lightmap_of_scene(&plan, scene, hooks),
    )?;
    Ok(Lightmap { baked })
}
