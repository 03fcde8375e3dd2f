//! `pvfc.AttitudeController`: PVFC of a rigid body's attitude on SO(3), the paper's "control
//! of satellite orientation": the body's inertia, a contour of attitudes, the navigation
//! function of eq. (26), exponential self-pacing.

use crate::contours::So3ConstantRate;
use crate::convert::{internal_state, matrix, out1, vector};
use crate::errors::core_err;
use crate::navigation::So3Navigation;
use nalgebra::{Matrix3, Vector3};
use numpy::PyArray1;
use pvfc_core::prelude::*;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The scenario's attitude controller type: the same field (eq. 26, eq. 21) and law.
type Attitude = pvfc_sim::scenario::AttitudeController;

/// PVFC of a rigid body's attitude (`J ω̇ + ω × Jω = T`, `ω` in the body frame) along a contour
/// on SO(3). `step` keeps the internal states τ, τ̇, q̇_F; `evaluate` is pure.
#[pyclass(module = "pvfc")]
pub(crate) struct AttitudeController {
    ctl: Attitude,
    initial: Attitude,
}

#[pymethods]
impl AttitudeController {
    #[new]
    #[pyo3(signature = (inertia, contour, navigation, self_pacing = 20.0, energy = 20.0, flywheel_inertia = 1.0, gamma = 0.1, tau0 = 0.0))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        inertia: &Bound<'_, PyAny>,
        contour: &So3ConstantRate,
        navigation: &So3Navigation,
        self_pacing: f64,
        energy: f64,
        flywheel_inertia: f64,
        gamma: f64,
        tau0: f64,
    ) -> PyResult<Self> {
        let body =
            RigidBody::new(Matrix3::from(matrix::<3, 3>(inertia, "inertia")?)).map_err(core_err)?;
        let field = SuspendedField::new(
            contour.c,
            navigation.n,
            ExponentialPacing::new(self_pacing).map_err(core_err)?,
        );
        let law = PvfcLaw::new(
            body,
            field,
            Flywheel::new(flywheel_inertia, energy).map_err(core_err)?,
            gamma,
        )
        .map_err(core_err)?;
        if !tau0.is_finite() {
            return Err(pyo3::exceptions::PyValueError::new_err("tau0: not finite"));
        }
        let ctl = Controller::new(law).starting_at_rest(tau0);
        Ok(AttitudeController { ctl, initial: ctl })
    }

    /// Everything about the control law at a full state (attitude (3, 3), body rate ω (3,),
    /// τ, τ̇, q̇_F), as a dict: the augmented `torque` (ω part, τ, flywheel; shape (5,)), the
    /// coupling's `coupling_torque` and `field_velocity` (5,), `kinetic_energy` κ_a, `beta`,
    /// `potential` U, `lambda1`, `lambda2`.
    fn evaluate<'py>(
        &self,
        py: Python<'py>,
        rotation: &Bound<'py, PyAny>,
        omega: &Bound<'py, PyAny>,
        tau: f64,
        tau_dot: f64,
        flywheel_speed: f64,
    ) -> PyResult<Bound<'py, PyDict>> {
        let s = AugmentedState {
            q: crate::convert::rotation(rotation, "rotation")?,
            v: Vector3::from(vector::<3>(omega, "omega")?),
            tau,
            tau_dot,
            flywheel_speed,
        };
        let (t, o) = self.ctl.evaluate(&s).map_err(core_err)?;
        let aug = |a: &AugmentedVector<f64, 3>| {
            out1(
                py,
                vec![a.robot[0], a.robot[1], a.robot[2], a.tau, a.flywheel],
            )
        };
        let d = PyDict::new(py);
        d.set_item("torque", aug(&t))?;
        d.set_item("coupling_torque", aug(&o.torque))?;
        d.set_item("field_velocity", aug(&o.field_velocity))?;
        d.set_item("kinetic_energy", o.kinetic_energy)?;
        d.set_item("beta", o.beta)?;
        d.set_item("potential", o.field.potential)?;
        d.set_item("lambda1", o.field.lambda1)?;
        d.set_item("lambda2", o.field.lambda2)?;
        Ok(d)
    }

    /// One control step at the measured attitude (3, 3) and body rate ω (3,): returns the
    /// body torque, shape (3,), and advances τ, τ̇, q̇_F over dt. On error the state is
    /// unchanged.
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        rotation: &Bound<'py, PyAny>,
        omega: &Bound<'py, PyAny>,
        dt: f64,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let q = crate::convert::rotation(rotation, "rotation")?;
        let v = Vector3::from(vector::<3>(omega, "omega")?);
        let out = self.ctl.step(&q, &v, dt).map_err(core_err)?;
        Ok(out1(py, out.torque.iter().cloned().collect()))
    }

    /// The internal states (τ, τ̇, q̇_F, laps).
    #[getter]
    fn state(&self) -> (f64, f64, f64, i64) {
        internal_state(self.ctl.state())
    }

    /// Back to the initial internal states.
    fn reset(&mut self) {
        self.ctl = self.initial;
    }
}
