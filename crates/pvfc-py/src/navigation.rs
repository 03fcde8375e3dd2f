//! Navigation functions: `pvfc.TorusNavigation`, `So3Navigation`, `JointNavigation`.

use crate::convert::{any_array, dyn_vector, matrix, out1, rotation, vector};
use crate::errors::core_err;
use nalgebra::{SVector, Vector2};
use numpy::PyArray1;
use pvfc_core::lie::JointKind;
use pvfc_core::prelude::*;
use pvfc_sim::model::MAX_JOINTS;
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
    pub(crate) n: pvfc_core::navigation::So3Navigation<f64>,
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
        let e = rotation(e, "e")?;
        Ok(self.n.value(&e))
    }

    /// grad U(E) in body coordinates, shape (3,).
    fn gradient<'py>(
        &self,
        py: Python<'py>,
        e: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let e = rotation(e, "e")?;
        Ok(out1(py, self.n.gradient(&e).iter().cloned().collect()))
    }

    /// The eigenvalues π₁ < π₂ < π₃ of P.
    #[getter]
    fn eigenvalues(&self) -> (f64, f64, f64) {
        let e = self.n.eigenvalues();
        (e[0], e[1], e[2])
    }
}

/// U(E) = Σ h_i u_i(E_i) on a robot's joint space: `½(1 − cos E_i)` on revolute joints,
/// `¼E_i²` on prismatic ones (`pvfc_core::navigation::JointNavigation`). `kinds` ("revolute"
/// or "prismatic" per joint) is for evaluating it on its own; composed with a robot
/// (`Controller.compose`), the robot's joints decide, and given kinds must match them.
#[pyclass(module = "pvfc", frozen, from_py_object)]
#[derive(Clone)]
pub(crate) struct JointNavigation {
    pub(crate) h: Vec<f64>,
    pub(crate) kinds: Option<Vec<JointKind>>,
}

/// `U`, its gradient and its differential for `N` joints.
fn joint_navigation<const N: usize>(
    h: &[f64],
    kinds: &[JointKind],
    e: &[f64],
) -> pvfc_core::Result<NavigationAt> {
    let mut ks = [JointKind::Circular; N];
    ks.copy_from_slice(kinds);
    let nav = pvfc_core::navigation::JointNavigation::new(SVector::from_column_slice(h), ks)?;
    let x = JointSpace::new(SVector::<f64, N>::from_column_slice(e), ks);
    let s = nav.evaluate(&x, &Tangent::<f64, N>::zeros());
    Ok(NavigationAt {
        value: s.value,
        gradient: s.gradient.as_slice().to_vec(),
        differential: s.differential.as_slice().to_vec(),
    })
}

/// A navigation function's value, gradient and differential at one error.
struct NavigationAt {
    value: f64,
    gradient: Vec<f64>,
    differential: Vec<f64>,
}

impl JointNavigation {
    /// `U` and its gradient at the errors `e` (length checked by the caller).
    fn at(&self, e: &[f64]) -> PyResult<NavigationAt> {
        let n = self.h.len();
        let kinds = self
            .kinds
            .clone()
            .unwrap_or_else(|| vec![JointKind::Circular; n]);
        macro_rules! on_n {
            ($($n:literal),*) => {
                match n {
                    $($n => joint_navigation::<$n>(&self.h, &kinds, e).map_err(core_err),)*
                    _ => Err(PyValueError::new_err(format!(
                        "h: 1 to {MAX_JOINTS} weights, got {n}"
                    ))),
                }
            };
        }
        on_n!(1, 2, 3, 4, 5, 6, 7, 8)
    }

    fn evaluate(&self, e: &Bound<'_, PyAny>) -> PyResult<NavigationAt> {
        self.at(&dyn_vector(e, "e", self.h.len())?)
    }
}

#[pymethods]
impl JointNavigation {
    #[new]
    #[pyo3(signature = (h, kinds=None))]
    fn new(h: &Bound<'_, PyAny>, kinds: Option<Vec<String>>) -> PyResult<Self> {
        let h = any_array(h, "h", 1)?.1;
        if !(1..=MAX_JOINTS).contains(&h.len()) {
            return Err(PyValueError::new_err(format!(
                "h: 1 to {MAX_JOINTS} weights, got {}",
                h.len()
            )));
        }
        let kinds = kinds
            .map(|ks| {
                if ks.len() != h.len() {
                    return Err(PyValueError::new_err(format!(
                        "kinds: {} entries for {} weights",
                        ks.len(),
                        h.len()
                    )));
                }
                ks.iter()
                    .map(|k| match k.as_str() {
                        "revolute" => Ok(JointKind::Circular),
                        "prismatic" => Ok(JointKind::Linear),
                        other => Err(PyValueError::new_err(format!(
                            "kinds: expected 'revolute' or 'prismatic', got {other:?}"
                        ))),
                    })
                    .collect::<PyResult<Vec<_>>>()
            })
            .transpose()?;
        let nav = JointNavigation { h, kinds };
        // The core's checks of the weights (finite, > 0).
        nav.at(&vec![0.0; nav.h.len()])?;
        Ok(nav)
    }

    /// The weights h_i.
    #[getter]
    fn h<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        out1(py, self.h.clone())
    }

    /// U(E) for joint errors E, shape (n,).
    fn value(&self, e: &Bound<'_, PyAny>) -> PyResult<f64> {
        Ok(self.evaluate(e)?.value)
    }

    /// grad U(E), shape (n,), in the navigation function's metric of weight ½ (the
    /// convention of eq. 17, as the field uses it): twice the differential.
    fn gradient<'py>(
        &self,
        py: Python<'py>,
        e: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(out1(py, self.evaluate(e)?.gradient))
    }

    /// dU(E), shape (n,): the partial derivatives ∂U/∂E_i.
    fn differential<'py>(
        &self,
        py: Python<'py>,
        e: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(out1(py, self.evaluate(e)?.differential))
    }
}
