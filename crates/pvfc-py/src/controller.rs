//! `pvfc.Controller`: PVFC for any robot, the one controller class of the Python API. It is
//! built from a scenario (the paper's SCARA, a URDF arm or a rigid body), or composed in
//! Python: [`Controller.arm`/`compose`](crate::arm) for any `pvfc.Robot`,
//! [`Controller.attitude`](crate::attitude) for a rigid body's attitude on SO(3).

use crate::convert::{dyn_vector, internal_state, out1, out_dmatrix, rotation, vector};
use crate::errors::{core_err, sim_err};
use crate::runs::Scenario;
use nalgebra::{Vector2, Vector3};
use numpy::{PyArray1, PyArray2};
use pvfc_core::prelude::*;
use pvfc_sim::model::arm::{ArmController as SimArm, ArmSettings};
use pvfc_sim::model::evaluation::Evaluation;
use pvfc_sim::scenario::{AttitudeController, PaperController, System};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::sync::Arc;

/// The law behind a `pvfc.Controller`, one per kind of robot: the dispatch on the robot
/// happens here and nowhere else in the Python API.
#[derive(Clone)]
pub(crate) enum Law {
    /// The paper's SCARA (closed-form model, on the torus).
    Scara(Box<PaperController>),
    /// A serial arm of 1 to 8 joints (a URDF or arrays), and the settings it was built from
    /// (its passive mode's learner of the torque the model misses plans on their pace).
    Arm(Box<SimArm>, Arc<ArmSettings>),
    /// A rigid body's attitude on SO(3).
    Attitude(Box<AttitudeController>),
}

/// PVFC for any robot: the paper's SCARA, a serial arm (`pvfc.Robot`) or a rigid body's
/// attitude, with its contour, navigation function, self-pacing, flywheel and add-ons.
/// `step` keeps the internal states τ, τ̇, q̇_F; `evaluate` and `torque` are pure.
#[pyclass(module = "pvfc", subclass)]
pub(crate) struct Controller {
    pub(crate) law: Law,
    initial: Law,
}

impl Controller {
    /// A controller starting from `law`'s internal states.
    pub(crate) fn of(law: Law) -> Self {
        Controller {
            initial: law.clone(),
            law,
        }
    }

    /// The robot's number of coordinates (joints; 3 for a rigid body).
    pub(crate) fn dof_of(&self) -> usize {
        match &self.law {
            Law::Scara(_) => 2,
            Law::Arm(c, _) => c.dof(),
            Law::Attitude(_) => 3,
        }
    }

    /// The law at a full state; `q` is the joint vector, or the rotation matrix of a rigid
    /// body; `names` name `q` and `qdot` in errors.
    pub(crate) fn evaluation(
        &self,
        (q, qdot): (&Bound<'_, PyAny>, &Bound<'_, PyAny>),
        names: (&str, &str),
        internal: (f64, f64, f64),
    ) -> PyResult<Evaluation> {
        let (tau, tau_dot, flywheel_speed) = internal;
        let (qn, vn) = names;
        match &self.law {
            Law::Scara(c) => {
                let s = AugmentedState {
                    q: Torus::new(Vector2::from(vector::<2>(q, qn)?)),
                    v: Vector2::from(vector::<2>(qdot, vn)?),
                    tau,
                    tau_dot,
                    flywheel_speed,
                };
                let (t, o) = c.evaluate(&s).map_err(core_err)?;
                Evaluation::from_core::<_, 2, 4>(&t, &o).map_err(sim_err)
            }
            Law::Arm(c, _) => {
                let n = c.dof();
                let (q, v) = (dyn_vector(q, qn, n)?, dyn_vector(qdot, vn, n)?);
                c.evaluate(&q, &v, internal).map_err(sim_err)
            }
            Law::Attitude(c) => {
                let s = AugmentedState {
                    q: rotation(q, qn)?,
                    v: Vector3::from(vector::<3>(qdot, vn)?),
                    tau,
                    tau_dot,
                    flywheel_speed,
                };
                let (t, o) = c.evaluate(&s).map_err(core_err)?;
                Evaluation::from_core::<_, 3, 5>(&t, &o).map_err(sim_err)
            }
        }
    }

    /// One control step: the robot's torques; the internal states advance over `dt`. `names`
    /// name `q` and `qdot` in errors.
    pub(crate) fn step_law(
        &mut self,
        (q, qdot): (&Bound<'_, PyAny>, &Bound<'_, PyAny>),
        names: (&str, &str),
        dt: f64,
    ) -> PyResult<Vec<f64>> {
        let (qn, vn) = names;
        Ok(match &mut self.law {
            Law::Scara(c) => {
                let q = Torus::new(Vector2::from(vector::<2>(q, qn)?));
                let v = Vector2::from(vector::<2>(qdot, vn)?);
                c.step(&q, &v, dt)
                    .map_err(core_err)?
                    .torque
                    .as_slice()
                    .to_vec()
            }
            Law::Arm(c, _) => {
                let n = c.dof();
                let (q, v) = (dyn_vector(q, qn, n)?, dyn_vector(qdot, vn, n)?);
                c.step(&q, &v, dt).map_err(sim_err)?.torque
            }
            Law::Attitude(c) => {
                let q = rotation(q, qn)?;
                let v = Vector3::from(vector::<3>(qdot, vn)?);
                c.step(&q, &v, dt)
                    .map_err(core_err)?
                    .torque
                    .as_slice()
                    .to_vec()
            }
        })
    }
}

/// The evaluation as the dict `Controller.evaluate` returns.
pub(crate) fn evaluation_dict<'py>(
    py: Python<'py>,
    e: &Evaluation,
) -> PyResult<Bound<'py, PyDict>> {
    let n = e.dof();
    let d = PyDict::new(py);
    d.set_item("torque", out1(py, e.torque.clone()))?;
    d.set_item("robot_torque", out1(py, e.robot_torque().to_vec()))?;
    d.set_item("tau_torque", e.torque[n])?;
    d.set_item("flywheel_torque", e.torque[n + 1])?;
    d.set_item("coupling_torque", out1(py, e.coupling_torque.clone()))?;
    d.set_item("field_velocity", out1(py, e.field_velocity.clone()))?;
    d.set_item("desired_momentum", out1(py, e.desired_momentum.clone()))?;
    d.set_item("momentum", out1(py, e.momentum.clone()))?;
    d.set_item("w", out1(py, e.w.clone()))?;
    d.set_item("kinetic_energy", e.kinetic_energy)?;
    d.set_item("beta", e.beta)?;
    d.set_item("energy_level", e.energy_level)?;
    d.set_item("potential", e.potential)?;
    d.set_item("lambda1", e.lambda1)?;
    d.set_item("lambda2", e.lambda2)?;
    d.set_item("velocity_field_error_energy", e.velocity_field_error_energy)?;
    d.set_item("convergence_factor", e.convergence_factor)?;
    d.set_item("G", out_dmatrix(py, &e.g))?;
    d.set_item("R", out_dmatrix(py, &e.r))?;
    Ok(d)
}

#[pymethods]
impl Controller {
    /// The controller of a scenario, at its initial internal states (`[initial]`): the
    /// paper's SCARA, a serial chain from a URDF or a rigid body (`[plant] kind`).
    #[new]
    fn new(scenario: &Scenario) -> PyResult<Self> {
        let s = &scenario.s;
        let law = match System::build(s).map_err(sim_err)? {
            System::Scara(arm) => Law::Scara(Box::new(s.controller_with(arm).map_err(sim_err)?)),
            System::SerialChain(sys) => Law::Arm(Box::new(sys.controller), Arc::new(sys.settings)),
            System::RigidBody(ctl) => Law::Attitude(ctl),
        };
        Ok(Controller::of(law))
    }

    /// The robot's number of coordinates: its joints (2 for the SCARA), 3 for a rigid body.
    #[getter]
    fn dof(&self) -> usize {
        self.dof_of()
    }

    /// The kind of robot: `"scara"`, `"arm"` or `"rigid_body"`.
    #[getter]
    fn robot(&self) -> &'static str {
        match &self.law {
            Law::Scara(_) => "scara",
            Law::Arm(_, _) => "arm",
            Law::Attitude(_) => "rigid_body",
        }
    }

    /// One control step at the measured configuration `q` (joint positions, shape (dof,); a
    /// rigid body's rotation matrix, (3, 3)) and velocity `qdot` (joint rates; the body rate
    /// ω in the body frame): the motor torques, shape (dof,). τ, τ̇, q̇_F advance over dt
    /// (semi-implicit Euler). On error the state is unchanged.
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        qdot: &Bound<'py, PyAny>,
        dt: f64,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(out1(py, self.step_law((q, qdot), ("q", "qdot"), dt)?))
    }

    /// The law at a full state (pure), as a dict: the full augmented `torque` (the robot's
    /// entries, τ's, the flywheel's; shape (dof + 2,)) with its add-ons, `robot_torque`
    /// (dof,), `tau_torque`, `flywheel_torque`; the coupling's `coupling_torque`,
    /// `field_velocity`, `desired_momentum`, `momentum`, `w` (dof + 2,) and its skew-symmetric
    /// `G` and `R` (eq. 7); `kinetic_energy` κ_a, `beta`, `energy_level` Ē, `potential` U,
    /// `lambda1`, `lambda2`, `velocity_field_error_energy` W_β (eq. 12) and
    /// `convergence_factor` μ (eq. 13).
    fn evaluate<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        qdot: &Bound<'py, PyAny>,
        tau: f64,
        tau_dot: f64,
        flywheel_speed: f64,
    ) -> PyResult<Bound<'py, PyDict>> {
        evaluation_dict(
            py,
            &self.evaluation((q, qdot), ("q", "qdot"), (tau, tau_dot, flywheel_speed))?,
        )
    }

    /// The full augmented torque at a full state (pure), shape (dof + 2,): the coupling
    /// (eq. 7) plus the add-ons.
    fn torque<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        qdot: &Bound<'py, PyAny>,
        tau: f64,
        tau_dot: f64,
        flywheel_speed: f64,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let e = self.evaluation((q, qdot), ("q", "qdot"), (tau, tau_dot, flywheel_speed))?;
        Ok(out1(py, e.torque))
    }

    /// The contour's point x_d(τ): joint positions, shape (dof,); a rigid body's rotation
    /// matrix, (3, 3).
    fn contour_point<'py>(&self, py: Python<'py>, tau: f64) -> Bound<'py, PyAny> {
        match &self.law {
            Law::Scara(c) => {
                let p: Torus<f64, 2> = c.law().field().contour().point(tau);
                out1(py, p.angles().as_slice().to_vec()).into_any()
            }
            Law::Arm(c, _) => out1(py, c.contour_point(tau)).into_any(),
            Law::Attitude(c) => {
                let r = *c.law().field().contour().point(tau).matrix();
                let m = nalgebra::DMatrix::from_column_slice(3, 3, r.as_slice());
                let a: Bound<'py, PyArray2<f64>> = out_dmatrix(py, &m);
                a.into_any()
            }
        }
    }

    /// The internal states (τ, τ̇, q̇_F, laps).
    #[getter]
    fn state(&self) -> (f64, f64, f64, i64) {
        match &self.law {
            Law::Scara(c) => internal_state(c.state()),
            Law::Arm(c, _) => c.state(),
            Law::Attitude(c) => internal_state(c.state()),
        }
    }

    /// Back to the initial internal states.
    fn reset(&mut self) {
        self.law = self.initial.clone();
    }
}
