//! `pvfc.PassiveController`: a scenario's controller or a `pvfc.Controller` (the SCARA's or an
//! arm's) in the passive digital mode (`pvfc_core::passive`), to drive one's own plant (MuJoCo, hardware) from
//! Python.

use crate::controller::{Controller, Law};
use crate::convert::{dyn_vector, out1, vector};
use crate::errors::{core_err, sim_err};
use crate::runs::Scenario;
use nalgebra::Vector2;
use numpy::PyArray1;
use pvfc_core::passive::EnergyAccount;
use pvfc_core::prelude::*;
use pvfc_core::supervision::Fault;
use pvfc_sim::model::arm::{PassiveArm, PassiveOptions, SupervisionOptions};
use pvfc_sim::model::pace::{PaceLearningSpec, SpeedScaling};
use pvfc_sim::scenario::PaperPassiveController;
use pvfc_sim::scenario::System;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The controller behind a `pvfc.PassiveController`: the paper's SCARA (from a scenario or a
/// `pvfc.Controller`) or any arm (from a `pvfc.Controller`).
#[derive(Clone)]
enum Inner {
    Scara(Box<PaperPassiveController>),
    Arm(Box<PassiveArm>),
}

/// A controller, passive for any sampling period: it accounts the energy it gives the robot
/// at the samples from the positions and the applied torque, and pays it from its flywheel
/// and τ̇. From an arm's scenario, the SCARA's or a URDF arm's (settings default to its
/// `[controller.passive]`, the encoder's counts on the revolute joints), or from a
/// `pvfc.Controller` of the SCARA or of an arm (its internal states as they are; settings
/// default to none). The arguments override the settings.
///
/// With `max_speed` (one bound per joint, rad/s or m/s) and `period` (`(min, max)`, s), and
/// optionally `max_acceleration`, every sample is supervised: a NaN or infinite reading, a
/// period out of bounds, a reading no motion can make or a frozen encoder is a fault, not an
/// exception: `step` returns the safe torque (zeros), `fault` says which, and the
/// controller resumes at the next good sample.
///
/// With `pace_throttle=(threshold, time_constant, floor)` (and torque limits) the field's
/// pace is slowed on the torque margin: while the command uses more than `threshold` of a
/// limit, the pace's scale falls towards 0 (never below `floor`) with the time constant (s),
/// and it comes back to 1 when the margin returns (`pace_scale`). Passivity is untouched.
///
/// With `pace_learning=(target, fall, rise, slope, floor)` (and torque limits, on a controller
/// whose pace is planned along a closed contour) the pace is learned lap over lap: each 64th
/// of the period slows where the command passed a limit (at most `fall` a lap), speeds up
/// where its peak share of a limit stayed below `target` (at most `rise` a lap), within
/// `slope` of its neighbours and `[floor, 1]` of the plan. A sixth number `miss` in (0, 1]
/// learns the torque the model misses beside it (the share of each lap's measurement taken
/// in): the pace is planned again against it once a lap and caps each stretch's scale. It
/// plans on the controller's pace: a `pvfc.Controller.arm` with a pace (`speed` or
/// `torque_limit`) on a closed contour, or a scenario with `[controller.pace]`.
#[pyclass(module = "pvfc")]
pub(crate) struct PassiveController {
    ctl: Inner,
    initial: Inner,
    last: Option<EnergyAccount<f64>>,
    fault: Option<Fault>,
}

fn pair(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vector2<f64>> {
    Ok(Vector2::from(vector::<2>(obj, name)?))
}

#[pymethods]
impl PassiveController {
    #[new]
    #[pyo3(signature = (controller, torque_limit=None, encoder_resolution=None, velocity_filter=None, reserve=None, max_speed=None, max_acceleration=None, period=None, pace_throttle=None, pace_learning=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        controller: &Bound<'_, PyAny>,
        torque_limit: Option<&Bound<'_, PyAny>>,
        encoder_resolution: Option<&Bound<'_, PyAny>>,
        velocity_filter: Option<f64>,
        reserve: Option<f64>,
        max_speed: Option<&Bound<'_, PyAny>>,
        max_acceleration: Option<&Bound<'_, PyAny>>,
        period: Option<(f64, f64)>,
        pace_throttle: Option<(f64, f64, f64)>,
        pace_learning: Option<Vec<f64>>,
    ) -> PyResult<Self> {
        let overrides = Overrides {
            torque_limit,
            encoder_resolution,
            velocity_filter,
            reserve,
            supervision: (max_speed, max_acceleration, period),
            pace_throttle: pace_throttle.map(|(threshold, time_constant, floor)| SpeedScaling {
                threshold,
                time_constant,
                floor,
            }),
            pace_learning: pace_learning.as_deref().map(learning).transpose()?,
        };
        let ctl = if let Ok(scenario) = controller.cast::<Scenario>() {
            let mut s = scenario.borrow().s.clone();
            let spec = s
                .controller
                .passive
                .get_or_insert_with(Default::default)
                .clone();
            match System::build(&s).map_err(sim_err)? {
                System::RigidBody(_) => return Err(no_body()),
                System::SerialChain(system) => {
                    let circular: Vec<bool> = system
                        .robot
                        .joint_kinds()
                        .iter()
                        .map(|k| *k == JointKind::Circular)
                        .collect();
                    let base = spec.options(&circular).map_err(sim_err)?;
                    let o = overrides.over(base, circular.len())?;
                    let ctl = system.controller.passive(&o, &system.settings);
                    Inner::Arm(Box::new(ctl.map_err(sim_err)?))
                }
                System::Scara(_) => {
                    let o = overrides.over(spec.options(&[true; 2]).map_err(sim_err)?, 2)?;
                    Inner::Scara(Box::new(s.passive_controller_with(&o).map_err(sim_err)?))
                }
            }
        } else if let Ok(c) = controller.cast::<Controller>() {
            let c = c.borrow();
            match &c.law {
                Law::Scara(ctl) => {
                    let o = overrides.over(PassiveOptions::default(), 2)?;
                    if o.miss_weight().is_some() {
                        return Err(PyValueError::new_err(
                            "PassiveController: the SCARA's learner of the torque its model misses (pace_learning's miss) plans on its scenario's pace: build it from the pvfc.Scenario",
                        ));
                    }
                    Inner::Scara(Box::new(o.controller(**ctl, None).map_err(sim_err)?))
                }
                Law::Arm(a, settings) => {
                    let o = overrides.over(PassiveOptions::default(), a.dof())?;
                    Inner::Arm(Box::new(a.passive(&o, settings).map_err(sim_err)?))
                }
                Law::Attitude(_) => return Err(no_body()),
            }
        } else {
            return Err(PyTypeError::new_err(
                "PassiveController: expected a pvfc.Scenario or a pvfc.Controller",
            ));
        };
        Ok(PassiveController {
            initial: ctl.clone(),
            ctl,
            last: None,
            fault: None,
        })
    }

    /// The number of joints.
    #[getter]
    fn dof(&self) -> usize {
        match &self.ctl {
            Inner::Scara(_) => 2,
            Inner::Arm(a) => a.dof(),
        }
    }

    /// One control step at the measured positions `q` (and velocities `qdot`, or `None` to
    /// estimate them from the positions), with `applied` the torque the drive applied over
    /// the last period (`None`: what this controller commanded). Returns the torque to hold
    /// for `dt`, shape (dof,). On error nothing changes. With supervision, a fault returns
    /// the safe torque (zeros) and sets `fault`.
    #[pyo3(signature = (q, qdot, dt, applied=None))]
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        qdot: Option<&Bound<'py, PyAny>>,
        dt: f64,
        applied: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let (torque, energy, fault) = match &mut self.ctl {
            Inner::Scara(c) => {
                let q = Torus::new(pair(q, "q")?);
                let v = qdot.map(|v| pair(v, "qdot")).transpose()?;
                let u = applied.map(|u| pair(u, "applied")).transpose()?;
                let out = c.step(&q, v.as_ref(), u.as_ref(), dt).map_err(core_err)?;
                (out.torque.as_slice().to_vec(), out.energy, out.fault)
            }
            Inner::Arm(c) => {
                let n = c.dof();
                let q = dyn_vector(q, "q", n)?;
                let v = qdot.map(|v| dyn_vector(v, "qdot", n)).transpose()?;
                let u = applied.map(|u| dyn_vector(u, "applied", n)).transpose()?;
                let out = c
                    .step(&q, v.as_deref(), u.as_deref(), dt)
                    .map_err(sim_err)?;
                (out.torque, out.energy, out.fault)
            }
        };
        self.last = Some(energy);
        self.fault = fault;
        Ok(out1(py, torque))
    }

    /// The last step's energy account: storage, to_robot, add_ons, correction, scale,
    /// saturated, quantisation, unseen, set_aside (J, except scale and saturated); `None`
    /// before the first step.
    #[getter]
    fn energy<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(e) = self.last else {
            return Ok(None);
        };
        let d = PyDict::new(py);
        d.set_item("storage", e.storage)?;
        d.set_item("to_robot", e.to_robot)?;
        d.set_item("add_ons", e.add_ons)?;
        d.set_item("correction", e.correction)?;
        d.set_item("scale", e.scale)?;
        d.set_item("saturated", e.saturated)?;
        d.set_item("quantisation", e.quantisation)?;
        d.set_item("unseen", e.unseen)?;
        d.set_item("set_aside", e.set_aside)?;
        Ok(Some(d))
    }

    /// The fault the supervision found at the last step, as `(kind, joint)`: kind one of
    /// "non_finite", "period", "speed", "acceleration", "frozen"; joint the 0-based joint it
    /// names, or `None`. `None` without a fault.
    #[getter]
    fn fault(&self) -> Option<(&'static str, Option<usize>)> {
        self.fault.map(|f| {
            let kind = match f {
                Fault::NonFinite => "non_finite",
                Fault::Period => "period",
                Fault::Speed { .. } => "speed",
                Fault::Acceleration { .. } => "acceleration",
                Fault::Frozen { .. } => "frozen",
            };
            (kind, f.joint())
        })
    }

    /// Whether every sample is supervised (`max_speed` and `period` given, or the scenario's
    /// `[controller.passive.supervision]`).
    #[getter]
    fn supervised(&self) -> bool {
        match &self.ctl {
            Inner::Scara(c) => c.controller().supervision().is_some(),
            Inner::Arm(c) => c.supervised(),
        }
    }

    /// The scale of the field's pace the next step uses: the pace throttle's, in
    /// `[floor, 1]` (1 without `pace_throttle`).
    #[getter]
    fn pace_scale(&self) -> f64 {
        match &self.ctl {
            Inner::Scara(c) => c.controller().pace_throttle().map_or(1.0, |t| t.scale()),
            Inner::Arm(c) => c.pace_scale(),
        }
    }

    /// The storage ½τ̇² + ½M_F q̇_F² as accounted (J).
    #[getter]
    fn storage(&self) -> f64 {
        match &self.ctl {
            Inner::Scara(c) => c.storage(),
            Inner::Arm(c) => c.storage(),
        }
    }

    /// The internal states (τ, τ̇, q̇_F, laps).
    #[getter]
    fn state(&self) -> (f64, f64, f64, i64) {
        match &self.ctl {
            Inner::Scara(c) => crate::convert::internal_state(c.controller().controller().state()),
            Inner::Arm(c) => c.state(),
        }
    }

    /// Back to the initial internal states and storage.
    fn reset(&mut self) {
        self.ctl = self.initial.clone();
        self.last = None;
        self.fault = None;
    }
}

/// The settings given as arguments, overriding the scenario's or the defaults.
struct Overrides<'a, 'py> {
    torque_limit: Option<&'a Bound<'py, PyAny>>,
    encoder_resolution: Option<&'a Bound<'py, PyAny>>,
    velocity_filter: Option<f64>,
    reserve: Option<f64>,
    /// `max_speed`, `max_acceleration`, `period`.
    supervision: SupervisionArgs<'a, 'py>,
    /// `pace_throttle`: `(threshold, time_constant, floor)`.
    pace_throttle: Option<SpeedScaling>,
    /// `pace_learning`: `(target, fall, rise, slope, floor[, miss])`.
    pace_learning: Option<PaceLearningSpec>,
}

/// The supervision's arguments: `max_speed`, `max_acceleration`, `period`.
type SupervisionArgs<'a, 'py> = (
    Option<&'a Bound<'py, PyAny>>,
    Option<&'a Bound<'py, PyAny>>,
    Option<(f64, f64)>,
);

impl Overrides<'_, '_> {
    /// `base` (a scenario's options or the defaults, for `n` joints) with the arguments
    /// overriding it.
    fn over(&self, mut base: PassiveOptions, n: usize) -> PyResult<PassiveOptions> {
        if let Some(l) = self.torque_limit {
            base.torque_limit = Some(dyn_vector(l, "torque_limit", n)?);
        }
        if let Some(d) = self.encoder_resolution {
            base.encoder_resolution = Some(dyn_vector(d, "encoder_resolution", n)?);
        }
        if let Some(f) = self.velocity_filter {
            base.velocity_filter = f;
        }
        if let Some(r) = self.reserve {
            base.reserve = r;
        }
        if let Some(s) = self.supervision(n)? {
            base.supervision = Some(s);
        }
        if let Some(t) = self.pace_throttle {
            base.pace_throttle = Some(t);
        }
        if let Some(l) = self.pace_learning {
            base.pace_learning = Some(l);
        }
        Ok(base)
    }

    /// The supervision the arguments ask for (`None`: none asked), for `n` joints.
    fn supervision(&self, n: usize) -> PyResult<Option<SupervisionOptions>> {
        let (speed, acceleration, period) = self.supervision;
        let Some(speed) = speed else {
            if acceleration.is_some() || period.is_some() {
                return Err(pyo3::exceptions::PyValueError::new_err(
                    "PassiveController: max_acceleration and period supervise with max_speed: give max_speed too",
                ));
            }
            return Ok(None);
        };
        let period = period.ok_or_else(|| {
            pyo3::exceptions::PyValueError::new_err(
                "PassiveController: max_speed needs period=(min, max) (s)",
            )
        })?;
        Ok(Some(SupervisionOptions {
            max_speed: dyn_vector(speed, "max_speed", n)?,
            max_acceleration: acceleration
                .map(|a| dyn_vector(a, "max_acceleration", n))
                .transpose()?,
            period,
        }))
    }
}

fn no_body() -> PyErr {
    PyTypeError::new_err(
        "PassiveController: a rigid body's attitude controller has no passive mode here; give a SCARA or an arm",
    )
}

/// `pace_learning=(target, fall, rise, slope, floor[, miss])`.
fn learning(x: &[f64]) -> PyResult<PaceLearningSpec> {
    let miss = match x.len() {
        5 => 0.0,
        6 => x[5],
        n => {
            return Err(PyValueError::new_err(format!(
                "pace_learning: (target, fall, rise, slope, floor) or (target, fall, rise, slope, floor, miss), got {n} numbers"
            )))
        }
    };
    Ok(PaceLearningSpec {
        target: x[0],
        fall: x[1],
        rise: x[2],
        slope: x[3],
        floor: x[4],
        miss,
    })
}
