//! `shlight.SH`: a coefficient file (coefficients, frame, quantity,
//! provenance, standard errors) with the operations of the command line.

use std::path::PathBuf;

use glam::{DMat3, DQuat, DVec3};
use numpy::ndarray::Array2;
use numpy::{
    AllowTypeChange, IntoPyArray, PyArray2, PyArrayLike1, PyArrayLike2, PyUntypedArrayMethods,
};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use shlight_core::encoding::Encoding;
use shlight_core::sh::{ORTHONORMAL_TOLERANCE, ShCoeffs, ShRotation, WindowTarget};
use shlight_format::{CoeffFile, ExportFormat, Quantity};

use crate::errors::{chained, shlight_error, warn_all};
use crate::guard::guard;

/// SH lighting: real orthonormal SH coefficients (Condon-Shortley phase,
/// index l*(l+1)+m) of RGB radiance or irradiance in a y-up or z-up frame,
/// as shlight's coefficient file holds them. See help(shlight.SH).
#[pyclass(name = "SH", module = "shlight", frozen)]
pub struct Sh {
    file: CoeffFile,
}

impl Sh {
    /// The SH of a coefficient file.
    pub fn new(file: CoeffFile) -> Self {
        Self { file }
    }

    /// The coefficient file.
    pub fn file(&self) -> &CoeffFile {
        &self.file
    }

    /// Refuses `what` on an encoded light, whose coefficients alone are
    /// not the light (as `shlight project` refuses `--encoding` with
    /// `--window` and `--rotate`).
    pub fn plain(&self, what: &str) -> PyResult<()> {
        let e = self.file.encoding.encoding();
        if e == Encoding::Sh {
            return Ok(());
        }
        Err(shlight_error(format!(
            "{what}: the light is kept as {e}, whose coefficients alone are not the light; irradiance_at(dirs) evaluates it"
        )))
    }
}

/// Directions from Python, (N, 3) or (3,) (`true`: one), checked and
/// normalised.
fn directions(dirs: &Bound<'_, PyAny>) -> PyResult<(Vec<DVec3>, bool)> {
    let (rows, one) = direction_rows(dirs)?;
    if let Some(i) = rows.iter().position(|d| {
        let v = DVec3::from(*d);
        !v.is_finite() || v.length_squared() == 0.0
    }) {
        return Err(PyValueError::new_err(format!(
            "dirs[{i}] = {:?} is not a direction (zero or not finite)",
            rows[i]
        )));
    }
    let normalised = rows.into_iter().map(|d| DVec3::from(d).normalize());
    Ok((normalised.collect(), one))
}

/// The rows of an (N, 3) array, or the one row of a (3,) array (`true`).
fn direction_rows(dirs: &Bound<'_, PyAny>) -> PyResult<(Vec<[f64; 3]>, bool)> {
    if let Ok(d) = dirs.extract::<PyArrayLike1<'_, f64, AllowTypeChange>>()
        && d.shape() == [3]
    {
        let a = d.as_array();
        return Ok((vec![[a[0], a[1], a[2]]], true));
    }
    let m = dirs
        .extract::<PyArrayLike2<'_, f64, AllowTypeChange>>()
        .map_err(|_| PyValueError::new_err("dirs must be an (N, 3) array of directions"))?;
    if m.shape()[1] != 3 {
        return Err(PyValueError::new_err(format!(
            "dirs must have shape (N, 3), not {:?}",
            m.shape()
        )));
    }
    let a = m.as_array();
    let rows = (0..a.nrows()).map(|i| [a[[i, 0]], a[[i, 1]], a[[i, 2]]]);
    Ok((rows.collect(), false))
}

/// `values` as an (N, 3) float64 array, or (3,) when `one`.
fn rgb_rows<'py>(py: Python<'py>, values: &[DVec3], one: bool) -> PyResult<Bound<'py, PyAny>> {
    let flat: Vec<f64> = values.iter().flat_map(|v| v.to_array()).collect();
    let out = Array2::from_shape_vec((values.len(), 3), flat)
        .expect("n x 3")
        .into_pyarray(py);
    if one {
        Ok(out.call_method1("reshape", (3,))?)
    } else {
        Ok(out.into_any())
    }
}

/// `((lmax+1)^2, 3)` float64 array of an RGB expansion.
fn to_array<'py>(py: Python<'py>, c: &ShCoeffs<DVec3>) -> Bound<'py, PyArray2<f64>> {
    let flat: Vec<f64> = c.as_slice().iter().flat_map(|v| v.to_array()).collect();
    Array2::from_shape_vec((c.as_slice().len(), 3), flat)
        .expect("n x 3 values")
        .into_pyarray(py)
}

/// A rotation given as a 3x3 matrix or a quaternion `(x, y, z, w)`, and its
/// record for the file.
fn rotation_of(r: &Bound<'_, PyAny>) -> PyResult<(DMat3, String)> {
    if let Ok(m) = r.extract::<PyArrayLike2<'_, f64, AllowTypeChange>>()
        && m.shape() == [3, 3]
    {
        let a = m.as_array();
        return matrix_rotation(std::array::from_fn(|i| std::array::from_fn(|j| a[[i, j]])));
    }
    if let Ok(q) = r.extract::<PyArrayLike1<'_, f64, AllowTypeChange>>()
        && q.shape() == [4]
    {
        let v = q.as_array();
        return quaternion_rotation([v[0], v[1], v[2], v[3]]);
    }
    Err(PyValueError::new_err(
        "a rotation is a 3x3 matrix or a quaternion (x, y, z, w)",
    ))
}

/// A rotation matrix given by rows, refused unless shlight-core takes it
/// as a rotation ([`ShRotation::try_from_mat3`]: orthonormal within
/// [`ORTHONORMAL_TOLERANCE`], determinant +1).
fn matrix_rotation(rows: [[f64; 3]; 3]) -> PyResult<(DMat3, String)> {
    if !rows.iter().flatten().all(|v| v.is_finite()) {
        return Err(PyValueError::new_err("the rotation matrix is not finite"));
    }
    let m = DMat3::from_cols_array_2d(&rows).transpose();
    if ShRotation::try_from_mat3(0, m).is_none() {
        let off = (m.transpose() * m - DMat3::IDENTITY)
            .to_cols_array()
            .iter()
            .fold(0.0_f64, |a, v| a.max(v.abs()));
        return Err(PyValueError::new_err(format!(
            "{rows:?} is not a rotation (R^T R differs from I by {off:.2e}, det R = {:.6}; \
             both are held to {ORTHONORMAL_TOLERANCE:e}); a mirror or a scale cannot rotate SH lighting",
            m.determinant()
        )));
    }
    Ok((m, format!("matrix:{rows:?}")))
}

/// A rotation given as a quaternion `(x, y, z, w)`, normalised.
fn quaternion_rotation(v: [f64; 4]) -> PyResult<(DMat3, String)> {
    let q = DQuat::from_array(v);
    if !q.is_finite() || q.length_squared() == 0.0 {
        return Err(PyValueError::new_err(format!(
            "quaternion {v:?} is no rotation (zero or not finite)"
        )));
    }
    Ok((
        DMat3::from_quat(q.normalize()),
        format!("quat:{},{},{},{}", v[0], v[1], v[2], v[3]),
    ))
}

#[pymethods]
impl Sh {
    /// Coefficients as a ((lmax+1)**2, 3) float64 array: row l*(l+1)+m is
    /// the coefficient of Y_l^m, columns linear R, G, B.
    #[getter]
    fn coefficients<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        to_array(py, &self.file.coeffs)
    }

    /// Highest SH degree (lmax 2 = 9 coefficients).
    #[getter]
    fn lmax(&self) -> usize {
        self.file.coeffs.lmax()
    }

    /// The frame the coefficients live in: "y-up" or "z-up" (docs/conventions.md).
    #[getter]
    fn frame(&self) -> String {
        self.file.frame.to_string()
    }

    /// Whether the map was read mirrored (the pbrt / google mapping).
    #[getter]
    fn mirror(&self) -> bool {
        self.file.mirror
    }

    /// How the light is kept: "sh" (plain SH, the coefficients are the
    /// light) or an encoding of `shlight project --encoding` ("dominant+sh",
    /// "sloan+sh", "zh3", "zh3-hallucinated", "l1-nonlinear",
    /// "ambient-cube"), evaluated by irradiance_at.
    #[getter]
    fn encoding(&self) -> &'static str {
        self.file.encoding.encoding().name()
    }

    /// "radiance" (L) or "irradiance" (E = A_l L_l^m).
    #[getter]
    fn quantity(&self) -> &'static str {
        self.file.quantity.name()
    }

    /// One standard error per coefficient, ((lmax+1)**2, 3) float64
    /// (Monte Carlo projections), else None.
    #[getter]
    fn std_error<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray2<f64>>> {
        self.file.std_error.as_ref().map(|se| to_array(py, se))
    }

    /// The coefficient file as JSON text (what save writes).
    fn to_json(&self) -> String {
        self.file.to_json_string()
    }

    /// Irradiance E_l^m = A_l L_l^m (Ramamoorthi & Hanrahan 2001; A_0 = pi,
    /// A_1 = 2 pi / 3, A_2 = pi / 4): what a white Lambertian surface facing
    /// each direction receives. An SH that holds irradiance is returned as
    /// it is. An encoded light is refused (irradiance_at evaluates it).
    fn irradiance(&self) -> PyResult<Sh> {
        self.plain("irradiance")?;
        self.file
            .to_irradiance()
            .map(Sh::new)
            .map_err(|e| chained(&e))
    }

    /// The expansion at unit directions: dirs (N, 3) (or (3,)) float64 in
    /// the SH's frame, normalised here; returns (N, 3) (or (3,)) float64 RGB.
    /// An encoded light (`encoding` other than "sh") is refused: its
    /// coefficients alone are not the light (irradiance_at evaluates it).
    fn eval<'py>(&self, py: Python<'py>, dirs: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        self.plain("eval")?;
        let (dirs, one) = directions(dirs)?;
        let coeffs = &self.file.coeffs;
        let values: Vec<DVec3> = py.detach(|| dirs.iter().map(|d| coeffs.eval(*d)).collect());
        rgb_rows(py, &values, one)
    }

    /// The irradiance E(n) the file's light gives at unit normals: dirs
    /// (N, 3) (or (3,)) float64 in the SH's frame, normalised here; returns
    /// (N, 3) (or (3,)) float64 RGB. Every encoding evaluates its own way
    /// (dominant lights plus SH, ZH3, non-linear L1, the ambient cube);
    /// plain SH radiance is convolved (E_l^m = A_l L_l^m); an SH that
    /// holds irradiance is evaluated as it is.
    fn irradiance_at<'py>(
        &self,
        py: Python<'py>,
        dirs: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (dirs, one) = directions(dirs)?;
        let values: Vec<DVec3> = if self.file.quantity == Quantity::Irradiance {
            let coeffs = &self.file.coeffs;
            py.detach(|| dirs.iter().map(|d| coeffs.eval(*d)).collect())
        } else {
            let encoded = self.file.encoded().ok_or_else(|| {
                shlight_error(format!(
                    "the file's {} coefficients (lmax {}) are too few for its encoding {}",
                    self.file.quantity.name(),
                    self.file.coeffs.lmax(),
                    self.encoding()
                ))
            })?;
            py.detach(|| guard(|| Ok(encoded.irradiance_at(&dirs))))?
        };
        rgb_rows(py, &values, one)
    }

    /// The same light rotated by R: a 3x3 rotation matrix (acting on column
    /// vectors) or a unit quaternion (x, y, z, w). A light from a comes from
    /// R a afterwards, as `shlight project --rotate`; standard errors are
    /// rotated too.
    fn rotate(&self, r: &Bound<'_, PyAny>) -> PyResult<Sh> {
        self.plain("rotate")?;
        let (m, spec) = rotation_of(r)?;
        guard(|| Ok(Sh::new(self.file.rotated(m, &spec))))
    }

    /// The same light with ringing suppressed: window is "none",
    /// "hanning:W", "lanczos:W", "laplacian:LAMBDA", or "auto" (per colour
    /// channel the weakest Hanning window that makes these coefficients'
    /// function non-negative), as `shlight project --window`.
    fn window(&self, window: &str) -> PyResult<Sh> {
        self.plain("window")?;
        let windows = self
            .file
            .windows_for(window, WindowTarget::Function)
            .map_err(|e| shlight_error(e.to_string()))?;
        Ok(Sh::new(self.file.windowed(windows, window)))
    }

    /// Writes shlight's JSON coefficient file (the same as `shlight project
    /// -o FILE.json`), atomically.
    fn save(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        py.detach(|| guard(|| self.file.write(&path).map_err(|e| chained(&e))))
    }

    /// The coefficients in an engine or shader format, as `shlight project
    /// --format NAME` writes them (shlight.EXPORT_FORMATS lists the names).
    /// The exporter's notes come as warnings.
    #[pyo3(signature = (format, irradiance_only=false))]
    fn export(&self, py: Python<'_>, format: &str, irradiance_only: bool) -> PyResult<String> {
        let f: ExportFormat = format
            .parse()
            .map_err(|e: String| shlight_error(format!("format={format:?}: {e}")))?;
        let out = guard(|| {
            match f {
                // Coefficients hold no map for the specular images: only
                // asked for knowingly.
                ExportFormat::Gltf if irradiance_only => {
                    shlight_format::export_gltf(&self.file, None)
                }
                _ => shlight_format::export(&self.file, f),
            }
            .map_err(|e| chained(&e))
        })?;
        let notes: Vec<String> = out
            .notes
            .iter()
            .map(|n| format!("{}: {n}", self.file.provenance.input))
            .collect();
        warn_all(py, &notes, 1)?;
        Ok(out.text)
    }

    /// An SH from the JSON text of a coefficient file (what to_json gives).
    #[staticmethod]
    fn from_json(text: &str) -> PyResult<Sh> {
        CoeffFile::from_json_str(text, "<json>")
            .map(Sh::new)
            .map_err(|e| chained(&e))
    }

    /// Pickling (Dask, multiprocessing) through the coefficient file's JSON,
    /// which keeps every float64 bit.
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<(Bound<'py, PyAny>, (String,))> {
        let from_json = slf.get_type().getattr("from_json")?;
        Ok((from_json, (slf.get().file.to_json_string(),)))
    }

    fn __repr__(&self) -> String {
        let input = &self.file.provenance.input;
        let encoding = self.file.encoding.encoding();
        format!(
            "SH(lmax={}, quantity={:?}, frame={:?}{}{})",
            self.file.coeffs.lmax(),
            self.file.quantity.name(),
            self.file.frame.to_string(),
            if encoding == Encoding::Sh {
                String::new()
            } else {
                format!(", encoding={:?}", encoding.name())
            },
            if input.is_empty() {
                String::new()
            } else {
                format!(", input={input:?}")
            }
        )
    }
}

/// load(path) -> SH
/// --
///
/// Reads a coefficient file, or any engine file `shlight convert` reads.
#[pyfunction]
pub fn load(py: Python<'_>, path: PathBuf) -> PyResult<Sh> {
    py.detach(|| {
        guard(|| {
            shlight_format::read_coefficients(&path)
                .map(Sh::new)
                .map_err(|e| chained(&e))
        })
    })
}
