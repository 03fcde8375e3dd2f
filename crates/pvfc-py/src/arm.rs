//! `pvfc.Controller.arm` and `pvfc.Controller.compose`: PVFC for any `pvfc.Robot`, to drive
//! a user's own simulator (MuJoCo, PyBullet) or hardware loop from Python.

use crate::contours::joint_contour_spec;
use crate::controller::{Controller, Law};
use crate::convert::{array, dyn_vector};
use crate::errors::sim_err;
use crate::navigation::JointNavigation;
use crate::robots::Robot;
use crate::settings::ControllerSettings;
use pvfc_sim::model::arm::{ArmController as SimArm, ArmSettings, JointContourSpec};
use pvfc_sim::model::pace::{PaceSettings, PathSpeed};
use pvfc_sim::model::MAX_WAYPOINTS;
use pvfc_sim::scenario::obstacles::ObstacleSpec;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::sync::Arc;

fn build(robot: &Robot, settings: ArmSettings) -> PyResult<Controller> {
    let ctl = SimArm::new(&robot.robot, &settings).map_err(sim_err)?;
    Ok(Controller::of(Law::Arm(Box::new(ctl), Arc::new(settings))))
}

/// The controller of `Controller.arm`: a closed joint-space contour through `waypoints`,
/// `spacing` apart in τ, with navigation weights `h` (default 1) and `settings`.
fn through_waypoints(
    robot: &Robot,
    waypoints: &Bound<'_, PyAny>,
    spacing: f64,
    h: Option<&Bound<'_, PyAny>>,
    settings: &ControllerSettings,
) -> PyResult<Controller> {
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
    build(robot, settings.arm_settings(contour, h))
}

/// The controller of `Controller.compose`: a robot, a joint-space contour or a task-space
/// field, a navigation function and settings.
fn composed(
    robot: &Robot,
    contour: &Bound<'_, PyAny>,
    navigation: Option<&JointNavigation>,
    settings: Option<&ControllerSettings>,
    (obstacles, pace): (Option<ObstacleSpec>, Option<&Bound<'_, PyDict>>),
) -> PyResult<Controller> {
    let n = robot.robot.dof();
    let d = ControllerSettings::default();
    let settings = settings.unwrap_or(&d);
    let level = settings.nominal_speed.map_or(1.0, |(_, r)| r);
    let pace = pace.map(|p| pace_settings(p, level)).transpose()?;
    let with_obstacles = |mut s: ArmSettings| {
        s.obstacles = obstacles.clone();
        s.pace = pace.clone();
        build(robot, s)
    };
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
        return with_obstacles(s);
    }
    let spec = joint_contour_spec(contour).map_err(|_| {
        PyTypeError::new_err(
            "contour: expected a pvfc.WaypointCurve, pvfc.Lissajous, pvfc.Ellipse or pvfc.TaskSpaceField",
        )
    })?;
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
    with_obstacles(settings.arm_settings(spec, h))
}

/// `Controller.compose`'s `obstacles`: a dict with the layout of a scenario's `[obstacles]`
/// table.
fn obstacle_spec(py: Python<'_>, d: &Bound<'_, PyDict>) -> PyResult<ObstacleSpec> {
    let text: String = py.import("json")?.call_method1("dumps", (d,))?.extract()?;
    serde_json::from_str(&text).map_err(|e| PyValueError::new_err(format!("obstacles: {e}")))
}

/// `Controller.compose`'s `pace`: `tool_speed` (m/s) or `joint_speed` (rad/s), or `feeds`
/// (a `pvfc.CartesianPath` read from a part program: its moves' F, `tool_speed` on moves
/// without), and/or the drives' `torque_limit` with its `headroom` (default 0.8), at the
/// energy level `level`.
fn pace_settings(d: &Bound<'_, PyDict>, level: f64) -> PyResult<PaceSettings> {
    let mut pace = PaceSettings {
        speed: None,
        torque_limit: Vec::new(),
        headroom: 0.8,
        level,
    };
    let mut feeds = None;
    for (key, value) in d.iter() {
        let key: String = key.extract()?;
        match key.as_str() {
            "tool_speed" => pace.speed = Some(PathSpeed::Tool(value.extract()?)),
            "joint_speed" => pace.speed = Some(PathSpeed::Joint(value.extract()?)),
            "feeds" => feeds = Some(value),
            "torque_limit" => pace.torque_limit = value.extract()?,
            "headroom" => pace.headroom = value.extract()?,
            other => {
                return Err(PyValueError::new_err(format!(
                    "pace: unknown key {other:?} (tool_speed, joint_speed, feeds, torque_limit, headroom)"
                )))
            }
        }
    }
    if d.contains("tool_speed")? && d.contains("joint_speed")? {
        return Err(PyValueError::new_err(
            "pace: give tool_speed or joint_speed, not both",
        ));
    }
    if let Some(f) = feeds {
        let path = f.cast::<crate::cartesian::CartesianPath>().map_err(|_| {
            PyTypeError::new_err(
                "pace: feeds is a pvfc.CartesianPath read from a part program (gcode=)",
            )
        })?;
        let fallback = match pace.speed {
            Some(PathSpeed::Tool(v)) => Some(v),
            None => None,
            Some(_) => {
                return Err(PyValueError::new_err(
                    "pace: feeds are the tool's speeds; give tool_speed for moves without F, not joint_speed",
                ))
            }
        };
        let profile = path.borrow().feeds(fallback)?.ok_or_else(|| {
            PyValueError::new_err("pace: feeds: the path is not a part program with F words")
        })?;
        pace.speed = Some(PathSpeed::Feeds(profile));
    }
    if pace.speed.is_none() && pace.torque_limit.is_empty() {
        return Err(PyValueError::new_err(
            "pace: give a speed (tool_speed, joint_speed or feeds) or the drives' torque_limit",
        ));
    }
    Ok(pace)
}

#[pymethods]
impl Controller {
    /// PVFC for a robot along a closed joint-space contour through waypoints (a periodic C²
    /// spline, `spacing` apart in τ), with the navigation function (`1 − cos` on revolute
    /// joints, quadratic on prismatic ones, weights `h`), self-pacing, the flywheel and the
    /// add-ons (gravity and friction compensation, nominal speed). The keyword arguments
    /// after `h` are `pvfc.ControllerSettings`'s (`self_pacing`, `energy`,
    /// `flywheel_inertia`, `gamma`, `coupling_rate`, `gravity_compensation`, `friction_compensation`,
    /// `friction_band`, `nominal_speed`, `nominal_speed_integral`, `tau0`,
    /// `field_energy_bound`).
    #[staticmethod]
    #[pyo3(signature = (robot, waypoints, spacing, *, h=None, **settings))]
    fn arm(
        py: Python<'_>,
        robot: &Robot,
        waypoints: &Bound<'_, PyAny>,
        spacing: f64,
        h: Option<&Bound<'_, PyAny>>,
        settings: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Controller> {
        let settings = py
            .get_type::<ControllerSettings>()
            .call((), settings)?
            .cast_into::<ControllerSettings>()?;
        let settings = settings.borrow();
        through_waypoints(robot, waypoints, spacing, h, &settings)
    }

    /// A controller composed of a robot, a joint-space contour (`WaypointCurve`, `Lissajous`
    /// or `Ellipse` with one coordinate per joint), a navigation function (`JointNavigation`;
    /// default: every weight 1) and settings (`ControllerSettings`; default: its defaults).
    /// The contour and the navigation function take the robot's joint kinds (prismatic joints
    /// are lengths). In place of the contour, a `TaskSpaceField` (`CartesianPath.task_field`)
    /// makes the controller follow the tool path itself, with no navigation function.
    /// `obstacles`, a dict with the layout of a scenario's `[obstacles]` table (`kappa`,
    /// `scale`, `speed`, and lists `joint`, `body`, `world`), keeps the arm away from them
    /// through the navigation function (the paper's Remark 3; joint-space contours only).
    /// `pace`, a dict, sets the pace along the contour: `tool_speed` (m/s of the tool) or
    /// `joint_speed` (rad/s), bounded by the drives' `torque_limit` (one per joint) of which
    /// the motion uses `headroom` (default 0.8), at the energy level of the nominal speed (or
    /// 1); with `energy=0` in the settings the energy level is sized from it.
    #[staticmethod]
    #[pyo3(signature = (robot, contour, navigation=None, settings=None, obstacles=None, pace=None))]
    fn compose(
        py: Python<'_>,
        robot: &Robot,
        contour: &Bound<'_, PyAny>,
        navigation: Option<&JointNavigation>,
        settings: Option<&ControllerSettings>,
        obstacles: Option<&Bound<'_, PyDict>>,
        pace: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Controller> {
        let obstacles = obstacles.map(|d| obstacle_spec(py, d)).transpose()?;
        composed(robot, contour, navigation, settings, (obstacles, pace))
    }
}
