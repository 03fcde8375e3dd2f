//! `pvfc.PassiveController`: a scenario's controller or a `pvfc.Controller` (the SCARA's or an
//! arm's) in the passive digital mode (`pvfc_core::passive`), to drive one's own plant (MuJoCo, hardware) from
//! Python.

use crate::controller::{Controller, Law};
use crate::convert::{dyn_vector, out1, vector};
use crate::errors::{core_err, sim_err};
use crate::runs::Scenario;
use nalgebra::Vector2;
use numpy::PyArray1;
use pvfc_core::passive::{EnergyAccount, PassiveController as CorePassive};
use pvfc_core::prelude::*;
use pvfc_sim::model::arm::{ArmController as SimArm, PassiveArm, PassiveOptions};
use pvfc_sim::scenario::PaperPassiveController;
use pvfc_sim::scenario::System;
use pyo3::exceptions::PyTypeError;
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
#[pyclass(module = "pvfc")]
pub(crate) struct PassiveController {
    ctl: Inner,
    initial: Inner,
    last: Option<EnergyAccount<f64>>,
}

fn pair(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vector2<f64>> {
    Ok(Vector2::from(vector::<2>(obj, name)?))
}

#[pymethods]
impl PassiveController {
    #[new]
    #[pyo3(signature = (controller, torque_limit=None, encoder_resolution=None, velocity_filter=None, reserve=None))]
    fn new(
        controller: &Bound<'_, PyAny>,
        torque_limit: Option<&Bound<'_, PyAny>>,
        encoder_resolution: Option<&Bound<'_, PyAny>>,
        velocity_filter: Option<f64>,
        reserve: Option<f64>,
    ) -> PyResult<Self> {
        let overrides = Overrides {
            torque_limit,
            encoder_resolution,
            velocity_filter,
            reserve,
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
                    Inner::Arm(Box::new(arm(&system.controller, base, &overrides)?))
                }
                System::Scara(_) => {
                    let base = s
                        .passive_controller()
                        .map_err(sim_err)?
                        .ok_or_else(|| PyTypeError::new_err("no passive controller"))?;
                    Inner::Scara(Box::new(scara(base, &overrides)?))
                }
            }
        } else if let Ok(c) = controller.cast::<Controller>() {
            let c = c.borrow();
            match &c.law {
                Law::Scara(ctl) => {
                    Inner::Scara(Box::new(scara(CorePassive::new(**ctl), &overrides)?))
                }
                Law::Arm(a) => Inner::Arm(Box::new(arm(a, PassiveOptions::default(), &overrides)?)),
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
    /// for `dt`, shape (dof,). On error nothing changes.
    #[pyo3(signature = (q, qdot, dt, applied=None))]
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        qdot: Option<&Bound<'py, PyAny>>,
        dt: f64,
        applied: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let (torque, energy) = match &mut self.ctl {
            Inner::Scara(c) => {
                let q = Torus::new(pair(q, "q")?);
                let v = qdot.map(|v| pair(v, "qdot")).transpose()?;
                let u = applied.map(|u| pair(u, "applied")).transpose()?;
                let out = c.step(&q, v.as_ref(), u.as_ref(), dt).map_err(core_err)?;
                (out.torque.as_slice().to_vec(), out.energy)
            }
            Inner::Arm(c) => {
                let n = c.dof();
                let q = dyn_vector(q, "q", n)?;
                let v = qdot.map(|v| dyn_vector(v, "qdot", n)).transpose()?;
                let u = applied.map(|u| dyn_vector(u, "applied", n)).transpose()?;
                let out = c
                    .step(&q, v.as_deref(), u.as_deref(), dt)
                    .map_err(sim_err)?;
                (out.torque, out.energy)
            }
        };
        self.last = Some(energy);
        Ok(out1(py, torque))
    }

    /// The last step's energy account: storage, to_robot, add_ons, correction, scale,
    /// saturated, quantisation (J, except scale and saturated); `None` before the first step.
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
        Ok(Some(d))
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
            Inner::Scara(c) => crate::convert::internal_state(c.controller().state()),
            Inner::Arm(c) => c.state(),
        }
    }

    /// Back to the initial internal states and storage.
    fn reset(&mut self) {
        self.ctl = self.initial.clone();
        self.last = None;
    }
}

/// The settings given as arguments, overriding the scenario's or the defaults.
struct Overrides<'a, 'py> {
    torque_limit: Option<&'a Bound<'py, PyAny>>,
    encoder_resolution: Option<&'a Bound<'py, PyAny>>,
    velocity_filter: Option<f64>,
    reserve: Option<f64>,
}

fn no_body() -> PyErr {
    PyTypeError::new_err(
        "PassiveController: a rigid body's attitude controller has no passive mode here; give a SCARA or an arm",
    )
}

/// An arm's passive controller: `base` with the arguments overriding it.
fn arm(ctl: &SimArm, mut base: PassiveOptions, o: &Overrides<'_, '_>) -> PyResult<PassiveArm> {
    let n = ctl.dof();
    if let Some(l) = o.torque_limit {
        base.torque_limit = Some(dyn_vector(l, "torque_limit", n)?);
    }
    if let Some(d) = o.encoder_resolution {
        base.encoder_resolution = Some(dyn_vector(d, "encoder_resolution", n)?);
    }
    if let Some(f) = o.velocity_filter {
        base.velocity_filter = f;
    }
    if let Some(r) = o.reserve {
        base.reserve = r;
    }
    ctl.passive(&base).map_err(sim_err)
}

/// The SCARA's passive controller `ctl` with the arguments overriding its settings.
fn scara(
    mut ctl: PaperPassiveController,
    o: &Overrides<'_, '_>,
) -> PyResult<PaperPassiveController> {
    if let Some(l) = o.torque_limit {
        ctl = ctl
            .with_torque_limits(pair(l, "torque_limit")?)
            .map_err(core_err)?;
    }
    if let Some(d) = o.encoder_resolution {
        ctl = ctl
            .with_encoder_resolution(pair(d, "encoder_resolution")?)
            .map_err(core_err)?;
    }
    if let Some(f) = o.velocity_filter {
        ctl = ctl.with_velocity_filter(f).map_err(core_err)?;
    }
    if let Some(r) = o.reserve {
        ctl = ctl.with_reserve(r).map_err(core_err)?;
    }
    Ok(ctl)
}
