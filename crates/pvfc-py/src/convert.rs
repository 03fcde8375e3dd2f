//! numpy input adapters that check shapes, and fresh output arrays.

use numpy::ndarray::Array2;
use numpy::{
    AllowTypeChange, IntoPyArray, PyArray1, PyArray2, PyArrayLikeDyn, PyUntypedArrayMethods,
};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyString};

/// Any array-like of numbers (list, tuple, numpy array of any layout, f32 or f64) as `f64`
/// values with the given shape; `ValueError` naming the argument for a wrong shape,
/// `TypeError` for strings or non-numbers.
pub fn array(obj: &Bound<'_, PyAny>, name: &str, shape: &[usize]) -> PyResult<Vec<f64>> {
    let (got, values) = shaped(obj, name, &format!("shape {shape:?}"))?;
    if got != shape {
        return Err(PyValueError::new_err(format!(
            "{name}: expected shape {shape:?}, got {got:?}"
        )));
    }
    Ok(values)
}

/// Any array-like of numbers with its shape (`expected` says what was asked, for the errors).
fn shaped(obj: &Bound<'_, PyAny>, name: &str, expected: &str) -> PyResult<(Vec<usize>, Vec<f64>)> {
    if obj.is_instance_of::<PyString>() || obj.is_instance_of::<PyBytes>() {
        return Err(PyTypeError::new_err(format!(
            "{name}: expected numbers with {expected}, got a string"
        )));
    }
    let a: PyArrayLikeDyn<'_, f64, AllowTypeChange> = obj.extract().map_err(|e| {
        PyTypeError::new_err(format!("{name}: expected numbers with {expected} ({e})"))
    })?;
    Ok((a.shape().to_vec(), a.as_array().iter().cloned().collect()))
}

/// An array-like with `ndim` dimensions, of any size: its shape and values (row-major).
pub fn any_array(
    obj: &Bound<'_, PyAny>,
    name: &str,
    ndim: usize,
) -> PyResult<(Vec<usize>, Vec<f64>)> {
    let (shape, values) = shaped(obj, name, &format!("{ndim} dimension(s)"))?;
    if shape.len() != ndim {
        return Err(PyValueError::new_err(format!(
            "{name}: expected {ndim} dimension(s), got shape {shape:?}"
        )));
    }
    Ok((shape, values))
}

/// A vector of length `N`.
pub fn vector<const N: usize>(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<[f64; N]> {
    let v = array(obj, name, &[N])?;
    let mut out = [0.0; N];
    out.copy_from_slice(&v);
    Ok(out)
}

/// An `R × C` matrix, row-major.
pub fn matrix<const R: usize, const C: usize>(
    obj: &Bound<'_, PyAny>,
    name: &str,
) -> PyResult<nalgebra::SMatrix<f64, R, C>> {
    let v = array(obj, name, &[R, C])?;
    Ok(nalgebra::SMatrix::<f64, R, C>::from_row_slice(&v))
}

/// A fresh 1-D array.
pub fn out1<'py>(py: Python<'py>, v: Vec<f64>) -> Bound<'py, PyArray1<f64>> {
    v.into_pyarray(py)
}

/// A fresh matrix.
pub fn out_matrix<'py, const R: usize, const C: usize>(
    py: Python<'py>,
    m: &nalgebra::SMatrix<f64, R, C>,
) -> Bound<'py, PyArray2<f64>> {
    Array2::from_shape_fn((R, C), |(i, j)| m[(i, j)]).into_pyarray(py)
}

/// A vector whose length is known at run time (a robot's number of joints).
pub fn dyn_vector(obj: &Bound<'_, PyAny>, name: &str, n: usize) -> PyResult<Vec<f64>> {
    array(obj, name, &[n])
}

/// A fresh 2-D array from a run-time-sized matrix.
pub fn out_dmatrix<'py>(py: Python<'py>, m: &nalgebra::DMatrix<f64>) -> Bound<'py, PyArray2<f64>> {
    Array2::from_shape_fn((m.nrows(), m.ncols()), |(i, j)| m[(i, j)]).into_pyarray(py)
}

/// A fresh `(n, dof)` array from a joint series.
pub fn out_series<'py>(
    py: Python<'py>,
    s: &pvfc_sim::trace::series::JointSeries,
) -> Bound<'py, PyArray2<f64>> {
    Array2::from_shape_vec((s.len(), s.dof()), s.as_flat().to_vec())
        .map(|a| a.into_pyarray(py))
        .unwrap_or_else(|_| Array2::<f64>::zeros((0, s.dof())).into_pyarray(py))
}

/// A trace column as a fresh array: shape `(n,)` for a scalar column, `(n, width)` for a
/// vector column.
pub fn out_column<'py>(py: Python<'py>, v: pvfc_sim::trace::Values<'_>) -> Bound<'py, PyAny> {
    match v {
        pvfc_sim::trace::Values::Scalar(x) => out1(py, x.to_vec()).into_any(),
        pvfc_sim::trace::Values::Vectors(s) => out_series(py, s).into_any(),
    }
}

/// A rotation matrix `name`, shape (3, 3), checked (orthonormal to 1e-6, determinant +1).
pub fn rotation(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<pvfc_core::lie::So3<f64>> {
    pvfc_core::lie::So3::from_matrix(matrix::<3, 3>(obj, name)?, 1e-6)
        .map_err(crate::errors::core_err)
}

/// A controller's internal states as Python sees them: (τ, τ̇, q̇_F, laps).
pub fn internal_state(s: &pvfc_core::controller::InternalState<f64>) -> (f64, f64, f64, i64) {
    (s.tau, s.tau_dot, s.flywheel_speed, s.laps)
}
