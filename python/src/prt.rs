//! `shlight.bake_transfer` and `shlight.Transfer`: precomputed radiance
//! transfer of a mesh, baked by the library call `shlight prt` makes
//! (`shlight_prt::bake_file::bake_file`), and its `.shprt` file.

use std::path::PathBuf;

use numpy::ndarray::Array3;
use numpy::{IntoPyArray, PyArray3};
use pyo3::prelude::*;
use shlight_format::ShprtFile;
use shlight_prt::bake_file::{BakeRequest, DEFAULT_BOUNCES, MAX_BAKE_LMAX, bake_file};
use shlight_prt::transfer::Mode;

use crate::errors::{chained, shlight_error, warn_all};
use crate::guard::guard;

/// Per-vertex diffuse transfer vectors of a mesh (a `.shprt` file): the
/// exit radiance of a vertex under distant radiance SH `L` is
/// `coefficients[v] @ L[:(lmax+1)**2]` per channel. See
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

    /// "unshadowed", "shadowed" or "interreflected".
    #[getter]
    fn mode(&self) -> &str {
        &self.file.mode
    }

    /// Bounces of interreflection gathered (0 unless interreflected).
    #[getter]
    fn bounces(&self) -> u32 {
        self.file.bounces
    }

    /// Directions in the shared set (the stratified grid's size).
    #[getter]
    fn samples(&self) -> u64 {
        self.file.samples
    }

    /// Vertices, in the mesh file's order.
    #[getter]
    fn vertex_count(&self) -> usize {
        self.file.vertex_count
    }

    /// (vertex_count, channels, (lmax+1)**2) float32: row l*(l+1)+m of a
    /// channel is the transfer of Y_l^m, albedo / pi folded in.
    #[getter]
    fn coefficients<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray3<f32>> {
        let f = &self.file;
        let n = (f.lmax + 1) * (f.lmax + 1);
        Array3::from_shape_vec((f.vertex_count, f.channels, n), f.transfer.clone())
            .expect("vertex_count x channels x (lmax+1)^2 values")
            .into_pyarray(py)
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

/// `mode=` and `bounces=` as the library's mode, refused as `shlight prt`
/// refuses `--mode` and `--bounces`.
fn mode_of(mode: &str, bounces: Option<u32>) -> PyResult<Mode> {
    match (mode.trim(), bounces) {
        ("interreflected", b) => Ok(Mode::Interreflected {
            bounces: b.unwrap_or(DEFAULT_BOUNCES),
        }),
        ("unshadowed" | "shadowed", Some(_)) => {
            Err(shlight_error("bounces needs mode=\"interreflected\""))
        }
        ("unshadowed", None) => Ok(Mode::Unshadowed),
        ("shadowed", None) => Ok(Mode::Shadowed),
        (other, _) => Err(shlight_error(format!(
            "mode={other:?}: expected \"unshadowed\", \"shadowed\" or \"interreflected\""
        ))),
    }
}

/// An albedo from Python: one value or (R, G, B) (`bake_transfer`'s and
/// `bake_volume`'s).
pub fn albedo_of(albedo: &Bound<'_, PyAny>) -> PyResult<[f32; 3]> {
    let rgb = if let Ok(v) = albedo.extract::<f32>() {
        [v; 3]
    } else {
        albedo.extract::<[f32; 3]>().map_err(|_| {
            shlight_error("albedo is one value or (R, G, B), linear, each in [0, 1]")
        })?
    };
    if !rgb.iter().all(|v| (0.0..=1.0).contains(v)) {
        return Err(shlight_error(format!(
            "albedo={rgb:?}: each value must lie in [0, 1]"
        )));
    }
    Ok(rgb)
}

/// bake_transfer(mesh, mode="shadowed", lmax=4, *, samples=1024,
/// bounces=None, albedo=None, seed=0) -> Transfer
/// --
///
/// See the package documentation (`help(shlight.bake_transfer)`).
#[pyfunction]
#[pyo3(signature = (mesh, mode="shadowed".to_string(), lmax=4, *, samples=1024, bounces=None,
    albedo=None, seed=0))]
pub fn bake_transfer(
    py: Python<'_>,
    mesh: PathBuf,
    mode: String,
    lmax: usize,
    samples: usize,
    bounces: Option<u32>,
    albedo: Option<&Bound<'_, PyAny>>,
    seed: u64,
) -> PyResult<Transfer> {
    let mode = mode_of(&mode, bounces)?;
    if samples == 0 {
        return Err(shlight_error("samples must be at least 1"));
    }
    if lmax > MAX_BAKE_LMAX {
        return Err(shlight_error(format!(
            "lmax={lmax} is beyond {MAX_BAKE_LMAX} (diffuse transfer needs 2 to 6)"
        )));
    }
    let request = BakeRequest {
        lmax,
        samples,
        mode,
        albedo: albedo.map(albedo_of).transpose()?,
        seed,
    };
    let (file, warnings) = py.detach(|| {
        guard(|| {
            let loaded = shlight_mesh::load(&mesh).map_err(|e| chained(&e))?;
            let mut warnings = Vec::new();
            if loaded.report.degenerate_triangles > 0 {
                warnings.push(format!(
                    "{}: skipped {} degenerate triangles",
                    mesh.display(),
                    loaded.report.degenerate_triangles
                ));
            }
            let (_, file) = bake_file(&loaded, &mesh, &request, &|_, _, _| {});
            Ok((file, warnings))
        })
    })?;
    warn_all(py, &warnings, 2)?;
    Ok(Transfer { file })
}
