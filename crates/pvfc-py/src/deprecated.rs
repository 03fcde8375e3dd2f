//! The controller classes of earlier releases, kept as thin subclasses of `pvfc.Controller`
//! that warn (`DeprecationWarning`) when built and keep their old signatures and dicts:
//! `pvfc.ArmController` (now `Controller.arm` and `Controller.compose`) and
//! `pvfc.AttitudeController` (now `Controller.attitude`). A scenario's controller was and is
//! `pvfc.Controller(scenario)`.

use crate::arm::{composed, through_waypoints};
use crate::attitude::of_body;
use crate::contours::So3ConstantRate;
use crate::controller::{evaluation_dict, Controller};
use crate::convert::out1;
use crate::navigation::JointNavigation;
use crate::navigation::So3Navigation;
use crate::robots::Robot;
use crate::settings::ControllerSettings;
use numpy::PyArray1;
use pyo3::exceptions::PyDeprecationWarning;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::ffi::CString;

/// Warns that `pvfc.{old}` is deprecated in favour of `pvfc.{new}`, at the caller's line.
fn deprecated(py: Python<'_>, old: &str, new: &str) -> PyResult<()> {
    let message = format!(
        "pvfc.{old} is deprecated: use pvfc.{new} (pvfc.Controller is the controller of any robot)"
    );
    let message = CString::new(message).unwrap_or_default();
    PyErr::warn(py, &py.get_type::<PyDeprecationWarning>(), &message, 1)
}

/// Deprecated: `pvfc.Controller.arm` and `pvfc.Controller.compose` build the same controller.
/// Its `evaluate` gives the robot's torque, shape (dof,), as `torque`.
#[pyclass(module = "pvfc", extends = Controller)]
pub(crate) struct ArmController;

#[pymethods]
impl ArmController {
    #[new]
    #[pyo3(signature = (robot, waypoints, spacing, *, h=None, self_pacing=0.0, energy=10.0,
        flywheel_inertia=1.0, gamma=1.0, gravity_compensation=true, friction_compensation=None,
        friction_band=0.0, nominal_speed=None, tau0=0.0))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        robot: &Robot,
        waypoints: &Bound<'_, PyAny>,
        spacing: f64,
        h: Option<&Bound<'_, PyAny>>,
        self_pacing: f64,
        energy: f64,
        flywheel_inertia: f64,
        gamma: f64,
        gravity_compensation: bool,
        friction_compensation: Option<&Bound<'_, PyAny>>,
        friction_band: f64,
        nominal_speed: Option<(f64, f64)>,
        tau0: f64,
    ) -> PyResult<PyClassInitializer<Self>> {
        deprecated(py, "ArmController", "Controller.arm")?;
        let c = through_waypoints(
            robot,
            waypoints,
            spacing,
            h,
            self_pacing,
            energy,
            flywheel_inertia,
            gamma,
            gravity_compensation,
            friction_compensation,
            friction_band,
            nominal_speed,
            tau0,
        )?;
        Ok(PyClassInitializer::from(c).add_subclass(ArmController))
    }

    /// Deprecated: `pvfc.Controller.compose`.
    #[staticmethod]
    #[pyo3(signature = (robot, contour, navigation=None, settings=None))]
    fn compose(
        py: Python<'_>,
        robot: &Robot,
        contour: &Bound<'_, PyAny>,
        navigation: Option<&JointNavigation>,
        settings: Option<&ControllerSettings>,
    ) -> PyResult<Py<ArmController>> {
        deprecated(py, "ArmController.compose", "Controller.compose")?;
        let c = composed(robot, contour, navigation, settings)?;
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
    #[new]
    #[pyo3(signature = (inertia, contour, navigation, self_pacing = 20.0, energy = 20.0, flywheel_inertia = 1.0, gamma = 0.1, tau0 = 0.0))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        inertia: &Bound<'_, PyAny>,
        contour: &So3ConstantRate,
        navigation: &So3Navigation,
        self_pacing: f64,
        energy: f64,
        flywheel_inertia: f64,
        gamma: f64,
        tau0: f64,
    ) -> PyResult<PyClassInitializer<Self>> {
        deprecated(py, "AttitudeController", "Controller.attitude")?;
        let c = of_body(
            inertia,
            contour,
            navigation,
            self_pacing,
            energy,
            flywheel_inertia,
            gamma,
            tau0,
        )?;
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
