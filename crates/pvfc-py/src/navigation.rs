//! Navigation functions: `pvfc.TorusNavigation`, `So3Navigation`.

use crate::convert::{matrix, out1, vector};
use crate::errors::core_err;
use nalgebra::Vector2;
use numpy::PyArray1;
use pvfc_core::prelude::*;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// U(E) = k Σ h_i (1 − cos E_i) on the torus; k = ½ (eq. 17, default) or 1 (eq. 28).
#[pyclass(module = "pvfc", frozen, from_py_object)]
#[derive(Clone)]
pub(crate) struct TorusNavigation {
    n: pvfc_core::navigation::TorusNavigation<f64, 2>,
}

#[pymethods]
impl TorusNavigation {
    #[new]
    #[pyo3(signature = (h, convention="eq17"))]
    fn new(h: &Bound<'_, PyAny>, convention: &str) -> PyResult<Self> {
        let conv = match convention {
            "eq17" => TorusConvention::HalfSum,
            "eq28" => TorusConvention::Sum,
            other => {
                return Err(PyValueError::new_err(format!(
                    "convention: expected 'eq17' or 'eq28', got {other:?}"
                )))
            }
        };
        Ok(TorusNavigation {
            n: pvfc_core::navigation::TorusNavigation::new(
                Vector2::from(vector::<2>(h, "h")?),
                conv,
            )
            .map_err(core_err)?,
        })
    }

    /// U(E) for joint-angle errors E, shape (2,).
    fn value(&self, e: &Bound<'_, PyAny>) -> PyResult<f64> {
        Ok(self
            .n
            .value(&Torus::new(Vector2::from(vector::<2>(e, "e")?))))
    }

    /// grad U(E), shape (2,).
    fn gradient<'py>(
        &self,
        py: Python<'py>,
        e: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let g = self
            .n
            .gradient(&Torus::new(Vector2::from(vector::<2>(e, "e")?)));
        Ok(out1(py, g.iter().cloned().collect()))
    }
}

/// U(E) = tr(P(I − E))/π' on SO(3) (eq. 26); P is validated.
#[pyclass(module = "pvfc", frozen, from_py_object)]
#[derive(Clone)]
pub(crate) struct So3Navigation {
    n: pvfc_core::navigation::So3Navigation<f64>,
}

#[pymethods]
impl So3Navigation {
    #[new]
    fn new(p: &Bound<'_, PyAny>) -> PyResult<Self> {
        Ok(So3Navigation {
            n: pvfc_core::navigation::So3Navigation::new(matrix::<3, 3>(p, "p")?)
                .map_err(core_err)?,
        })
    }

    /// U(E) for a rotation matrix E, shape (3, 3).
    fn value(&self, e: &Bound<'_, PyAny>) -> PyResult<f64> {
        let e = So3::from_matrix(matrix::<3, 3>(e, "e")?, 1e-6).map_err(core_err)?;
        Ok(self.n.value(&e))
    }

    /// grad U(E) in body coordinates, shape (3,).
    fn gradient<'py>(
        &self,
        py: Python<'py>,
        e: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let e = So3::from_matrix(matrix::<3, 3>(e, "e")?, 1e-6).map_err(core_err)?;
        Ok(out1(py, self.n.gradient(&e).iter().cloned().collect()))
    }

    /// The eigenvalues π₁ < π₂ < π₃ of P.
    #[getter]
    fn eigenvalues(&self) -> (f64, f64, f64) {
        let e = self.n.eigenvalues();
        (e[0], e[1], e[2])
    }
}
