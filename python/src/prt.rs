//! `shlight.bake_transfer` and `shlight.Transfer`: precomputed radiance
//! transfer of a mesh, baked by shlight-pipeline's `prt` job as `shlight
//! prt` bakes it (diffuse or glossy, compressed, to `.shprt` or glTF, with
//! a preview), and its `.shprt` file.

use std::path::PathBuf;

use glam::DVec3;
use numpy::ndarray::{Array2, Array3, Array4};
use numpy::{IntoPyArray, PyArray2, PyArray3, PyArray4};
use pyo3::prelude::*;
use shlight_format::ShprtFile;
use shlight_mesh::LightUnits;
use shlight_pipeline::{
    PrtRequest, Shading, Silent, Spelling, prt, prt_of_scene, transfer_radiance,
};
use shlight_prt::Observer;

use crate::errors::{chained, pipeline_error, shlight_error, warn_all};
use crate::guard::guard;
use crate::options::albedo_of;
use crate::scene::SceneArg;
use crate::scene::bake_scene_arg;

/// Per-vertex transfer of a mesh (a `.shprt` file): diffuse transfer
/// vectors, whose exit radiance under distant radiance SH `L` is
/// `coefficients[v] @ L[:(lmax+1)**2]` per channel, or glossy transfer
/// matrices, shaded toward a view by `exit_radiance`. See
/// help(shlight.Transfer).
#[pyclass(name = "Transfer", module = "shlight", frozen)]
pub struct Transfer {
    file: ShprtFile,
}

#[pymethods]
impl Transfer {
    /// Highest SH degree ((lmax+1)**2 coefficients per channel).
    #[getter]
    fn lmax(&self) -> usize {
        self.file.lmax
    }

    /// 1 (a grey albedo, applied to each colour of the light) or 3 (RGB).
    #[getter]
    fn channels(&self) -> usize {
        self.file.channels
    }

    /// "unshadowed", "shadowed", "interreflected" or "glossy".
    #[getter]
    fn mode(&self) -> &str {
        &self.file.mode
    }

    /// Reads a `.shprt` file (docs/shprt.md; diffuse version 1, glossy
    /// version 2). Raises ShlightError for a missing or malformed file.
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Transfer> {
        let file = py.detach(|| guard(|| ShprtFile::read(&path).map_err(|e| chained(&e))))?;
        Ok(Transfer { file })
    }

    /// A glossy file's vertex positions, (vertex_count, 3) float32; None for
    /// diffuse transfer (which does not keep them).
    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray2<f32>>> {
        let g = self.file.glossy.as_ref()?;
        let flat: Vec<f32> = g.positions.iter().flatten().copied().collect();
        Some(
            Array2::from_shape_vec((g.positions.len(), 3), flat)
                .expect("N x 3 positions")
                .into_pyarray(py),
        )
    }

    /// A glossy file's unit vertex normals, (vertex_count, 3) float32; None
    /// for diffuse transfer.
    #[getter]
    fn normals<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray2<f32>>> {
        let g = self.file.glossy.as_ref()?;
        let flat: Vec<f32> = g.normals.iter().flatten().copied().collect();
        Some(
            Array2::from_shape_vec((g.normals.len(), 3), flat)
                .expect("N x 3 normals")
                .into_pyarray(py),
        )
    }

    /// A glossy file's BRDF ("phong:32", "ggx:0.3,0.04"); None for diffuse
    /// transfer.
    #[getter]
    fn brdf(&self) -> Option<&str> {
        self.file.glossy.as_ref().map(|g| g.brdf.as_str())
    }

    /// A glossy file's matrices, (vertex_count, channels, n, n) float32 with
    /// n = (lmax+1)**2: the transferred radiance is `matrices[v, c] @ L[:n,
    /// c]` (a CPCA-compressed file's reconstructed). None for diffuse
    /// transfer.
    #[getter]
    fn matrices<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray4<f32>>> {
        let f = &self.file;
        let g = f.glossy.as_ref()?;
        let n = (f.lmax + 1) * (f.lmax + 1);
        let values = match &g.cpca {
            None => f.transfer.clone(),
            Some(z) => shlight_prt::reconstruct_data(z, f.channels * n * n),
        };
        Some(
            Array4::from_shape_vec((f.vertex_count, f.channels, n, n), values)
                .expect("vertex_count x channels x n x n values")
                .into_pyarray(py),
        )
    }

    /// exit_radiance(light, view=None, eye=None, albedo=None) ->
    /// (vertex_count, 3) float64
    /// --
    ///
    /// Each vertex's exit radiance [r, g, b] under `light` (a path to an
    /// equirect map or a radiance coefficient file, y up, or an SH of
    /// radiance), as `shlight sample FILE --light LIGHT` gives it: a diffuse
    /// file's `T . L` (view and eye ignored); a glossy file's
    /// `sum Lambda_l (M L)_lm Y_lm(R)` (phong) with `R` the mirror about
    /// the vertex normal of `w_o`, or the GGX BRDF's tabulated projection
    /// dotted with `M L` in the vertex's frame (ggx; docs/shprt.md):
    /// `w_o` is `view` (x, y, z), one direction from every vertex toward
    /// the eye, or from each vertex to the point `eye`.
    /// `albedo` (one value or (R, G, B), linear) adds a glossy file's
    /// diffuse base, `albedo / pi sum A_l (M L)_lm Y_lm(n)`, as `shlight
    /// sample --albedo` and `render-mesh --prt --albedo` do; a diffuse
    /// file refuses it (its albedo is in its transfer).
    #[pyo3(signature = (light, view=None, eye=None, albedo=None))]
    fn exit_radiance<'py>(
        &self,
        py: Python<'py>,
        light: &Bound<'py, PyAny>,
        view: Option<[f64; 3]>,
        eye: Option<[f64; 3]>,
        albedo: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let albedo = albedo.map(albedo_of).transpose()?;
        let view = match (view, eye) {
            (Some(_), Some(_)) => return Err(shlight_error("give view or eye, not both")),
            (Some(d), None) => Some(Observer::Direction(DVec3::from_array(d))),
            (None, Some(e)) => Some(Observer::Eye(DVec3::from_array(e))),
            (None, None) => None,
        };
        let (light, warnings) = crate::light::light_of(py, light, "y")?;
        warn_all(py, &warnings, 2)?;
        let shading = Shading {
            view,
            albedo,
            lmax: None,
        };
        let (values, _) = py.detach(|| {
            guard(|| {
                transfer_radiance(
                    &self.file,
                    None,
                    &light,
                    &shading,
                    Spelling::Python,
                    &Silent,
                )
                .map_err(pipeline_error)
            })
        })?;
        let flat: Vec<f64> = values.iter().flat_map(|v| v.to_array()).collect();
        Ok(Array2::from_shape_vec((values.len(), 3), flat)
            .expect("vertex_count x 3 values")
            .into_pyarray(py))
    }

    /// Bounces of interreflection gathered (0 unless interreflected).
    #[getter]
    fn bounces(&self) -> u32 {
        self.file.bounces
    }

    /// Directions in the shared set (the stratified grid's size).
    #[getter]
    fn samples(&self) -> u64 {
        self.file.rays_per_vertex
    }

    /// Vertices, in the mesh file's order.
    #[getter]
    fn vertex_count(&self) -> usize {
        self.file.vertex_count
    }

    /// A glTF scene's static term (its punctual lights and emission):
    /// (vertex_count, 3) float32 exit radiance added to `T . L`
    /// (docs/shprt.md, "glTF scenes"); None without one.
    #[getter]
    fn static_radiance<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray2<f32>>> {
        let s = self.file.static_light.as_ref()?;
        let flat: Vec<f32> = s.radiance.iter().flatten().copied().collect();
        Some(
            Array2::from_shape_vec((s.radiance.len(), 3), flat)
                .expect("3 values per vertex")
                .into_pyarray(py),
        )
    }

    /// (vertex_count, channels, (lmax+1)**2) float32: row l*(l+1)+m of a
    /// channel is the transfer of Y_l^m, albedo / pi folded in.
    /// Raises ShlightError for a glossy file (see `matrices`).
    #[getter]
    fn coefficients<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray3<f32>>> {
        let f = &self.file;
        if let Some(g) = &f.glossy {
            return Err(shlight_error(format!(
                "glossy transfer ({}) holds matrices, not coefficient vectors: read .matrices",
                g.brdf
            )));
        }
        let n = (f.lmax + 1) * (f.lmax + 1);
        Ok(
            Array3::from_shape_vec((f.vertex_count, f.channels, n), f.transfer.clone())
                .expect("vertex_count x channels x (lmax+1)^2 values")
                .into_pyarray(py),
        )
    }

    /// Writes the `.shprt` file (docs/shprt.md), atomically: the same bytes
    /// as `shlight prt MESH -o FILE.shprt` with the same options.
    fn save(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        py.detach(|| guard(|| self.file.write(&path).map_err(|e| chained(&e))))
    }

    fn __repr__(&self) -> String {
        let f = &self.file;
        format!(
            "Transfer(mode={:?}, lmax={}, channels={}, vertex_count={}, mesh={:?})",
            f.mode, f.lmax, f.channels, f.vertex_count, f.mesh
        )
    }
}

/// bake_transfer(mesh, mode="shadowed", lmax=4, *, samples=1024,
/// bounces=None, albedo=None, seed=0, brdf=None, compress=None, output=None,
/// light=None, preview=None, preview_size=(512, 512), preview_exposure=None,
/// light_units=None) -> Transfer
/// --
///
/// See the package documentation (`help(shlight.bake_transfer)`).
#[pyfunction]
#[pyo3(signature = (mesh, mode="shadowed".to_string(), lmax=4, *, samples=1024, bounces=None,
    albedo=None, seed=0, brdf=None, compress=None, output=None, light=None, preview=None,
    preview_size=(512, 512), preview_exposure=None, light_units=None))]
pub fn bake_transfer(
    py: Python<'_>,
    mesh: SceneArg,
    mode: String,
    lmax: usize,
    samples: usize,
    bounces: Option<u32>,
    albedo: Option<&Bound<'_, PyAny>>,
    seed: u64,
    brdf: Option<String>,
    compress: Option<String>,
    output: Option<PathBuf>,
    light: Option<PathBuf>,
    preview: Option<PathBuf>,
    preview_size: (usize, usize),
    preview_exposure: Option<f32>,
    light_units: Option<&str>,
) -> PyResult<Transfer> {
    let (mesh, scene) = mesh.split(py);
    let light_units: Option<LightUnits> = light_units
        .map(|u| Spelling::Python.parse("light_units", u))
        .transpose()
        .map_err(pipeline_error)?;
    let plan = PrtRequest {
        mesh: &mesh,
        lmax,
        samples,
        mode: Spelling::Python
            .parse("mode", &mode)
            .map_err(pipeline_error)?,
        bounces,
        brdf: brdf.as_deref(),
        compress: compress.as_deref(),
        albedo: albedo.map(albedo_of).transpose()?,
        light_units,
        seed,
        output: output.as_deref(),
        light: light.as_deref(),
        preview: preview.as_deref(),
        preview_size,
        preview_exposure,
    }
    .check(Spelling::Python)
    .map_err(pipeline_error)?;
    let baked = bake_scene_arg(
        py,
        scene.as_deref(),
        |hooks| prt(&plan, hooks),
        |scene, hooks| prt_of_scene(&plan, scene, hooks),
    )?;
    Ok(Transfer { file: baked.file })
}
