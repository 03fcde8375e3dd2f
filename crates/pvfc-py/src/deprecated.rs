//! The controller classes of earlier releases, kept as thin subclasses of `pvfc.Controller`
//! that warn (`DeprecationWarning`) when built and keep their old signatures and dicts:
//! `pvfc.ArmController` (now `Controller.arm` and `Controller.compose`) and
//! `pvfc.AttitudeController` (now `Controller.attitude`). A scenario's controller was and is
//! `pvfc.Controller(scenario)`.

use crate::controller::{evaluation_dict, Controller};
use crate::convert::out1;
use numpy::PyArray1;
use pyo3::exceptions::PyDeprecationWarning;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use std::ffi::CString;

/// Warns that `pvfc.{old}` is deprecated in favour of `pvfc.Controller.{new}` (at the caller's
/// line), and builds the controller as `Controller.{new}(*args, **kwargs)`.
fn forward(
    py: Python<'_>,
    (old, new): (&str, &str),
    args: &Bound<'_, PyTuple>,
    kwargs: Option<&Bound<'_, PyDict>>,
) -> PyResult<Controller> {
    let message = format!(
        "pvfc.{old} is deprecated: use pvfc.Controller.{new} (pvfc.Controller is the controller of any robot)"
    );
    let message = CString::new(message).unwrap_or_default();
    PyErr::warn(py, &py.get_type::<PyDeprecationWarning>(), &message, 1)?;
    let built = py
        .get_type::<Controller>()
        .getattr(new)?
        .call(args, kwargs)?
        .cast_into::<Controller>()?;
    let law = built.borrow().law.clone();
    Ok(Controller::of(law))
}

/// Deprecated: `pvfc.Controller.arm` and `pvfc.Controller.compose` build the same controller.
/// Its `evaluate` gives the robot's torque, shape (dof,), as `torque`.
#[pyclass(module = "pvfc", extends = Controller)]
pub(crate) struct ArmController;

#[pymethods]
impl ArmController {
    /// `Controller.arm(robot, waypoints, spacing, ...)`, with a `DeprecationWarning`.
    #[new]
    #[pyo3(signature = (*args, **kwargs))]
    fn new(
        py: Python<'_>,
        args: &Bound<'_, PyTuple>,
        kwargs: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<PyClassInitializer<Self>> {
        let c = forward(py, ("ArmController", "arm"), args, kwargs)?;
        Ok(PyClassInitializer::from(c).add_subclass(ArmController))
    }

    /// Deprecated: `pvfc.Controller.compose`.
    #[staticmethod]
    #[pyo3(signature = (*args, **kwargs))]
    fn compose(
        py: Python<'_>,
        args: &Bound<'_, PyTuple>,
        kwargs: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Py<ArmController>> {
        let c = forward(py, ("ArmController.compose", "compose"), args, kwargs)?;
        Py::new(py, PyClassInitializer::from(c).add_subclass(ArmController))
    }

    /// `Controller.evaluate`'s dict with `torque` the robot's torque, shape (dof,), as this
    /// class gave it.
    fn evaluate<'py>(
        slf: PyRef<'py, Self>,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        qdot: &Bound<'py, PyAny>,
        tau: f64,
        tau_dot: f64,
        flywheel_speed: f64,
    ) -> PyResult<Bound<'py, PyDict>> {
        let e =
            slf.as_super()
                .evaluation((q, qdot), ("q", "qdot"), (tau, tau_dot, flywheel_speed))?;
        let d = evaluation_dict(py, &e)?;
        d.set_item("torque", out1(py, e.robot_torque().to_vec()))?;
        Ok(d)
    }
}

/// Deprecated: `pvfc.Controller.attitude` builds the same controller.
#[pyclass(module = "pvfc", extends = Controller)]
pub(crate) struct AttitudeController;

#[pymethods]
impl AttitudeController {
    /// `Controller.attitude(inertia, contour, navigation, ...)`, with a `DeprecationWarning`.
    #[new]
    #[pyo3(signature = (*args, **kwargs))]
    fn new(
        py: Python<'_>,
        args: &Bound<'_, PyTuple>,
        kwargs: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<PyClassInitializer<Self>> {
        let c = forward(py, ("AttitudeController", "attitude"), args, kwargs)?;
        Ok(PyClassInitializer::from(c).add_subclass(AttitudeController))
    }

    /// `Controller.evaluate` with the old argument names.
    fn evaluate<'py>(
        slf: PyRef<'py, Self>,
        py: Python<'py>,
        rotation: &Bound<'py, PyAny>,
        omega: &Bound<'py, PyAny>,
        tau: f64,
        tau_dot: f64,
        flywheel_speed: f64,
    ) -> PyResult<Bound<'py, PyDict>> {
        let e = slf.as_super().evaluation(
            (rotation, omega),
            ("rotation", "omega"),
            (tau, tau_dot, flywheel_speed),
        )?;
        evaluation_dict(py, &e)
    }

    /// `Controller.step` with the old argument names.
    fn step<'py>(
        mut slf: PyRefMut<'py, Self>,
        py: Python<'py>,
        rotation: &Bound<'py, PyAny>,
        omega: &Bound<'py, PyAny>,
        dt: f64,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let t = slf
            .as_super()
            .step_law((rotation, omega), ("rotation", "omega"), dt)?;
        Ok(out1(py, t))
    }
}
