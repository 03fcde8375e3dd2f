//! `pvfc.ArmController`: PVFC for any `pvfc.Robot`, to drive a user's own simulator (MuJoCo,
//! PyBullet) or hardware loop from Python.

use crate::contours::{Ellipse, Lissajous, WaypointCurve};
use crate::convert::{array, dyn_vector, out1};
use crate::errors::sim_err;
use crate::navigation::JointNavigation;
use crate::robots::Robot;
use crate::settings::ControllerSettings;
use numpy::PyArray1;
use pvfc_sim::model::arm::{ArmController as SimArm, ArmSettings, JointContourSpec};
use pvfc_sim::model::MAX_WAYPOINTS;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// PVFC for a robot: a closed joint-space contour through waypoints (a periodic C² spline),
/// the navigation function (`1 − cos` on revolute joints, quadratic on prismatic ones),
/// self-pacing, the flywheel, and the add-ons (gravity and friction compensation, nominal
/// speed). `step` keeps the internal states τ, τ̇, q̇_F; `evaluate` is pure.
#[pyclass(module = "pvfc")]
pub struct ArmController {
    pub(crate) ctl: SimArm,
    initial: SimArm,
}

impl ArmController {
    fn build(robot: &Robot, settings: ArmSettings) -> PyResult<Self> {
        let ctl = SimArm::new(&robot.robot, &settings).map_err(sim_err)?;
        Ok(ArmController {
            initial: ctl.clone(),
            ctl,
        })
    }
}

#[pymethods]
impl ArmController {
    #[new]
    #[pyo3(signature = (robot, waypoints, spacing, *, h=None, self_pacing=0.0, energy=10.0,
        flywheel_inertia=1.0, gamma=1.0, gravity_compensation=true, friction_compensation=None,
        friction_band=0.0, nominal_speed=None, tau0=0.0))]
    #[allow(clippy::too_many_arguments)]
    fn new(
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
    ) -> PyResult<Self> {
        let n = robot.robot.dof();
        let k = waypoints.len().unwrap_or(0);
        if !(3..=MAX_WAYPOINTS).contains(&k) {
            return Err(PyValueError::new_err(format!(
                "waypoints: expected 3 to {MAX_WAYPOINTS} rows, got {k}"
            )));
        }
        let flat = array(waypoints, "waypoints", &[k, n])?;
        let contour = JointContourSpec::Waypoints {
            points: flat.chunks(n).map(|c| c.to_vec()).collect(),
            spacing,
        };
        let h = match h {
            Some(h) => dyn_vector(h, "h", n)?,
            None => vec![1.0; n],
        };
        let settings = ControllerSettings {
            self_pacing,
            energy,
            flywheel_inertia,
            gamma,
            gravity_compensation,
            friction_compensation: friction_compensation
                .map(|f| dyn_vector(f, "friction_compensation", n))
                .transpose()?,
            friction_band,
            nominal_speed,
            tau0,
        };
        Self::build(robot, settings.arm_settings(contour, h))
    }

    /// A controller composed of a robot, a joint-space contour (`WaypointCurve`, `Lissajous`
    /// or `Ellipse` with one coordinate per joint), a navigation function (`JointNavigation`;
    /// default: every weight 1) and settings (`ControllerSettings`; default: its defaults).
    /// The contour and the navigation function take the robot's joint kinds (prismatic joints
    /// are lengths). In place of the contour, a `TaskSpaceField` (`CartesianPath.task_field`)
    /// makes the controller follow the tool path itself, with no navigation function.
    #[staticmethod]
    #[pyo3(signature = (robot, contour, navigation=None, settings=None))]
    fn compose(
        robot: &Robot,
        contour: &Bound<'_, PyAny>,
        navigation: Option<&JointNavigation>,
        settings: Option<&ControllerSettings>,
    ) -> PyResult<Self> {
        let n = robot.robot.dof();
        let d = ControllerSettings::default();
        let settings = settings.unwrap_or(&d);
        if let Ok(t) = contour.cast::<crate::cartesian::TaskSpaceField>() {
            let t = t.get();
            if t.image.dim() != n {
                return Err(PyValueError::new_err(format!(
                    "contour: a task-space field made for {} joints, the robot has {n}",
                    t.image.dim()
                )));
            }
            if navigation.is_some() {
                return Err(PyValueError::new_err(
                    "navigation: the task-space field has its own (its stiffness); give none",
                ));
            }
            let mut s = settings.arm_settings(t.image.clone(), vec![1.0; n]);
            s.field = t.field.clone();
            return Self::build(robot, s);
        }
        let spec = if let Ok(c) = contour.cast::<WaypointCurve>() {
            c.get().c.spec.clone()
        } else if let Ok(c) = contour.cast::<Lissajous>() {
            c.get().c.spec.clone()
        } else if let Ok(c) = contour.cast::<Ellipse>() {
            c.get().c.spec.clone()
        } else {
            return Err(PyTypeError::new_err(
                "contour: expected a pvfc.WaypointCurve, pvfc.Lissajous, pvfc.Ellipse or pvfc.TaskSpaceField",
            ));
        };
        if spec.dim() != n {
            return Err(PyValueError::new_err(format!(
                "contour: {} coordinates for the {n}-joint robot",
                spec.dim()
            )));
        }
        let kinds = robot.robot.joint_kinds();
        let h = match navigation {
            Some(nav) => {
                if nav.h.len() != n {
                    return Err(PyValueError::new_err(format!(
                        "navigation: {} weights for the {n}-joint robot",
                        nav.h.len()
                    )));
                }
                if nav.kinds.as_ref().is_some_and(|k| *k != kinds) {
                    return Err(PyValueError::new_err(
                        "navigation: its joint kinds differ from the robot's",
                    ));
                }
                nav.h.clone()
            }
            None => vec![1.0; n],
        };
        Self::build(robot, settings.arm_settings(spec, h))
    }

    /// The number of joints.
    #[getter]
    fn dof(&self) -> usize {
        self.ctl.dof()
    }

    /// One control step at the measured (q, q̇): the motor torques, shape (dof,); τ, τ̇, q̇_F
    /// advance over dt. On error the state is unchanged.
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        qdot: &Bound<'py, PyAny>,
        dt: f64,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let n = self.ctl.dof();
        let (q, v) = (dyn_vector(q, "q", n)?, dyn_vector(qdot, "qdot", n)?);
        let out = self.ctl.step(&q, &v, dt).map_err(sim_err)?;
        Ok(out1(py, out.torque))
    }

    /// The law at a full state (pure): a dict with `torque` (dof,), `tau_torque`,
    /// `flywheel_torque`, `potential` (U) and `beta`.
    fn evaluate<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        qdot: &Bound<'py, PyAny>,
        tau: f64,
        tau_dot: f64,
        flywheel_speed: f64,
    ) -> PyResult<Bound<'py, PyDict>> {
        let n = self.ctl.dof();
        let (q, v) = (dyn_vector(q, "q", n)?, dyn_vector(qdot, "qdot", n)?);
        let (t, t_tau, t_f, u, beta) = self
            .ctl
            .evaluate(&q, &v, (tau, tau_dot, flywheel_speed))
            .map_err(sim_err)?;
        let d = PyDict::new(py);
        d.set_item("torque", out1(py, t))?;
        d.set_item("tau_torque", t_tau)?;
        d.set_item("flywheel_torque", t_f)?;
        d.set_item("potential", u)?;
        d.set_item("beta", beta)?;
        Ok(d)
    }

    /// The contour's point x_d(τ), shape (dof,).
    fn contour_point<'py>(&self, py: Python<'py>, tau: f64) -> Bound<'py, PyArray1<f64>> {
        out1(py, self.ctl.contour_point(tau))
    }

    /// The internal states (τ, τ̇, q̇_F, laps).
    #[getter]
    fn state(&self) -> (f64, f64, f64, i64) {
        self.ctl.state()
    }

    /// Back to the initial internal states.
    fn reset(&mut self) {
        self.ctl = self.initial.clone();
    }
}
