//! What `project` accepts as a map: a path, an `(H, W, 3)` numpy array, or
//! six face arrays; arrays are read in place where numpy allows it.

use std::path::PathBuf;

use numpy::{PyArrayDescrMethods, PyReadonlyArray3, PyUntypedArray, PyUntypedArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyList, PyTuple};
use shlight_core::map::{Layout, TexelSource};

/// The texels of one array: float32 in place, float64 in place (read as
/// f32 texel by texel), or a float32 copy (an array numpy cannot hand over
/// as one C-contiguous block).
pub enum Texels<'py> {
    F32(PyReadonlyArray3<'py, f32>),
    F64(PyReadonlyArray3<'py, f64>),
    Copied(Vec<[f32; 3]>),
}

/// One `(H, W, 3)` array.
pub struct ArrayMap<'py> {
    pub width: usize,
    pub height: usize,
    pub texels: Texels<'py>,
}

/// A map given from Python.
pub enum Source<'py> {
    Path(PathBuf),
    Array(ArrayMap<'py>),
    Faces(Vec<ArrayMap<'py>>),
}

impl<'py> Source<'py> {
    /// A path (str or os.PathLike), an array, or a list or tuple of six
    /// arrays.
    pub fn from_py(obj: &Bound<'py, PyAny>) -> PyResult<Self> {
        if let Ok(array) = obj.cast::<PyUntypedArray>() {
            return Ok(Source::Array(ArrayMap::from_array(array, "source")?));
        }
        if obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>() {
            let items: Vec<Bound<'py, PyAny>> = obj.try_iter()?.collect::<PyResult<_>>()?;
            if items.len() != 6 {
                return Err(PyValueError::new_err(format!(
                    "a cube map is six face arrays (+X -X +Y -Y +Z -Z), not {}",
                    items.len()
                )));
            }
            let mut faces = Vec::with_capacity(6);
            for (k, item) in items.iter().enumerate() {
                let name = format!("face {} ({})", k, shlight_pipeline::FACE_NAMES[k]);
                let array = item
                    .cast::<PyUntypedArray>()
                    .map_err(|_| PyTypeError::new_err(format!("{name} is not a numpy array")))?;
                faces.push(ArrayMap::from_array(array, &name)?);
            }
            return Ok(Source::Faces(faces));
        }
        match obj.extract::<PathBuf>() {
            Ok(p) => Ok(Source::Path(p)),
            Err(_) => Err(PyTypeError::new_err(format!(
                "source must be a path, an (H, W, 3) float32/float64 array or six face arrays, not {}",
                obj.get_type().name()?
            ))),
        }
    }
}

/// The texels of a float32 or float64 array: borrowed when C-contiguous
/// (and of native byte order), else copied (rounded to float32).
fn texels_of<'py>(array: &Bound<'py, PyUntypedArray>, what: &str) -> PyResult<Texels<'py>> {
    let dtype = array.dtype();
    let contiguous = array.is_c_contiguous();
    Ok(match (dtype.kind(), dtype.itemsize()) {
        (b'f', 4) => match array.extract::<PyReadonlyArray3<'py, f32>>() {
            Ok(a) if contiguous => Texels::F32(a),
            Ok(a) => Texels::Copied(copy_texels(a.as_array().iter().copied())),
            Err(_) => Texels::Copied(copy_any(array)?),
        },
        (b'f', 8) => match array.extract::<PyReadonlyArray3<'py, f64>>() {
            Ok(a) if contiguous => Texels::F64(a),
            Ok(a) => Texels::Copied(copy_texels(a.as_array().iter().map(|v| *v as f32))),
            Err(_) => Texels::Copied(copy_any(array)?),
        },
        _ => {
            return Err(PyTypeError::new_err(format!(
                "{what} must be float32 or float64 (linear radiance), not {}",
                dtype.str()?
            )));
        }
    })
}

impl<'py> ArrayMap<'py> {
    /// Checks the shape `(H, W, 3)` and the dtype (float32 or float64) of
    /// `array`, named `what` in messages, and borrows its texels (in place
    /// when C-contiguous and of native byte order, else copied).
    pub fn from_array(array: &Bound<'py, PyUntypedArray>, what: &str) -> PyResult<Self> {
        let shape = array.shape().to_vec();
        if shape.len() != 3 || shape[2] != 3 {
            return Err(PyValueError::new_err(format!(
                "{what} must have shape (H, W, 3) (rows, columns, linear RGB), not {shape:?}"
            )));
        }
        let (height, width) = (shape[0], shape[1]);
        let texels = texels_of(array, what)?;
        Ok(Self {
            width,
            height,
            texels,
        })
    }

    /// The texels as a [`TexelSource`] in `layout`, read in place.
    pub fn view(&self, layout: Layout) -> ArrayView<'_> {
        let data = match &self.texels {
            Texels::F32(a) => Data::F32(as_rgb(a.as_slice().expect("checked C-contiguous"))),
            Texels::F64(a) => Data::F64(as_rgb(a.as_slice().expect("checked C-contiguous"))),
            Texels::Copied(v) => Data::F32(v),
        };
        ArrayView {
            layout,
            width: self.width,
            height: self.height,
            data,
        }
    }
}

/// An array of another byte order: converted by numpy to native float32.
fn copy_any(array: &Bound<'_, PyUntypedArray>) -> PyResult<Vec<[f32; 3]>> {
    let converted = array.call_method1("astype", ("=f4",))?;
    let a = converted.extract::<PyReadonlyArray3<'_, f32>>()?;
    Ok(copy_texels(a.as_array().iter().copied()))
}

/// Values in row-major `(H, W, 3)` order as texels.
fn copy_texels(values: impl Iterator<Item = f32>) -> Vec<[f32; 3]> {
    let flat: Vec<f32> = values.collect();
    as_rgb(&flat).to_vec()
}

/// `[r, g, b, r, g, b, ...]` as texels.
fn as_rgb<T>(flat: &[T]) -> &[[T; 3]] {
    flat.as_chunks::<3>().0
}

/// Texel storage of an [`ArrayView`].
#[derive(Clone, Copy)]
pub enum Data<'a> {
    F32(&'a [[f32; 3]]),
    F64(&'a [[f64; 3]]),
}

/// A borrowed `(H, W, 3)` array in a layout: a [`TexelSource`] the
/// projection reads in place (float32 rows whole, float64 texel by texel).
#[derive(Clone, Copy)]
pub struct ArrayView<'a> {
    pub layout: Layout,
    pub width: usize,
    pub height: usize,
    pub data: Data<'a>,
}

impl TexelSource for ArrayView<'_> {
    fn layout(&self) -> Layout {
        self.layout
    }
    fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }
    fn texel(&self, x: usize, y: usize) -> [f32; 3] {
        let i = y * self.width + x;
        match self.data {
            Data::F32(p) => p[i],
            Data::F64(p) => p[i].map(|v| v as f32),
        }
    }
    fn row(&self, y: usize) -> Option<&[[f32; 3]]> {
        match self.data {
            Data::F32(p) => p.get(y * self.width..(y + 1) * self.width),
            Data::F64(_) => None,
        }
    }
}

impl ArrayView<'_> {
    /// The texels as one contiguous float32 slice, when they are stored so.
    pub fn contiguous(&self) -> Option<&[[f32; 3]]> {
        match self.data {
            Data::F32(p) => Some(p),
            Data::F64(_) => None,
        }
    }
}
