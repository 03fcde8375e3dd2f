//! `pvfc.Controller`: the scenario's controller (the paper's SCARA).

use crate::convert::{internal_state, out1, out_matrix, vector};
use crate::errors::{core_err, sim_err};
use crate::runs::Scenario;
use nalgebra::Vector2;
use numpy::PyArray1;
use pvfc_core::prelude::*;
use pvfc_sim::scenario::PaperController;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The PVFC controller of a scenario (SCARA, its contour, its settings and add-ons).
/// `step` keeps the internal states τ, τ̇, q̇_F; `evaluate`/`torque` are pure.
#[pyclass(module = "pvfc")]
pub(crate) struct Controller {
    ctl: PaperController,
    initial: PaperController,
}

pub(crate) fn state(
    q: &Bound<'_, PyAny>,
    qdot: &Bound<'_, PyAny>,
    tau: f64,
    tau_dot: f64,
    flywheel_speed: f64,
) -> PyResult<AugmentedState<f64, Torus<f64, 2>, 2>> {
    Ok(AugmentedState {
        q: Torus::new(Vector2::from(vector::<2>(q, "q")?)),
        v: Vector2::from(vector::<2>(qdot, "qdot")?),
        tau,
        tau_dot,
        flywheel_speed,
    })
}

#[pymethods]
impl Controller {
    #[new]
    fn new(scenario: &Scenario) -> PyResult<Self> {
        let ctl = scenario.s.controller().map_err(sim_err)?;
        Ok(Controller { ctl, initial: ctl })
    }

    /// The augmented torque (T₁, T₂, T_τ, T_F) at a full state, shape (4,): coupling (eq. 7)
    /// plus the scenario's nominal-speed and friction-compensation terms.
    fn torque<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        qdot: &Bound<'py, PyAny>,
        tau: f64,
        tau_dot: f64,
        flywheel_speed: f64,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let (t, _) = self
            .ctl
            .evaluate(&state(q, qdot, tau, tau_dot, flywheel_speed)?)
            .map_err(core_err)?;
        Ok(out1(py, vec![t.robot[0], t.robot[1], t.tau, t.flywheel]))
    }

    /// Everything about the control law at a full state, as a dict of numbers and arrays.
    fn evaluate<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        qdot: &Bound<'py, PyAny>,
        tau: f64,
        tau_dot: f64,
        flywheel_speed: f64,
    ) -> PyResult<Bound<'py, PyDict>> {
        let (t, o) = self
            .ctl
            .evaluate(&state(q, qdot, tau, tau_dot, flywheel_speed)?)
            .map_err(core_err)?;
        let aug =
            |a: &AugmentedVector<f64, 2>| out1(py, vec![a.robot[0], a.robot[1], a.tau, a.flywheel]);
        let d = PyDict::new(py);
        d.set_item("torque", aug(&t))?;
        d.set_item("coupling_torque", aug(&o.torque))?;
        d.set_item("field_velocity", aug(&o.field_velocity))?;
        d.set_item("desired_momentum", aug(&o.desired_momentum))?;
        d.set_item("momentum", aug(&o.momentum))?;
        d.set_item("w", aug(&o.w))?;
        d.set_item("kinetic_energy", o.kinetic_energy)?;
        d.set_item("beta", o.beta)?;
        d.set_item("potential", o.field.potential)?;
        d.set_item("lambda1", o.field.lambda1)?;
        d.set_item("lambda2", o.field.lambda2)?;
        let (g, r) = o.coupling_matrices::<4>().map_err(core_err)?;
        d.set_item("G", out_matrix(py, &g))?;
        d.set_item("R", out_matrix(py, &r))?;
        Ok(d)
    }

    /// One control step at the measured (q, q̇): returns the motor torques, shape (2,), and
    /// advances τ, τ̇, q̇_F over dt (semi-implicit Euler). On error the state is unchanged.
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        qdot: &Bound<'py, PyAny>,
        dt: f64,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let q = Torus::new(Vector2::from(vector::<2>(q, "q")?));
        let v = Vector2::from(vector::<2>(qdot, "qdot")?);
        let out = self.ctl.step(&q, &v, dt).map_err(core_err)?;
        Ok(out1(py, vec![out.torque[0], out.torque[1]]))
    }

    /// The internal states (τ, τ̇, q̇_F, laps).
    #[getter]
    fn state(&self) -> (f64, f64, f64, i64) {
        internal_state(self.ctl.state())
    }

    /// Back to the scenario's initial internal states.
    fn reset(&mut self) {
        self.ctl = self.initial;
    }
}
