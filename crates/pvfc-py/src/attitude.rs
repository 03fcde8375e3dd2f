//! `pvfc.Controller.attitude`: PVFC of a rigid body's attitude on SO(3), the paper's "control
//! of satellite orientation": the body's inertia, a contour of attitudes, the navigation
//! function of eq. (26), exponential self-pacing.

use crate::contours::So3ConstantRate;
use crate::controller::{Controller, Law};
use crate::convert::matrix;
use crate::errors::core_err;
use crate::navigation::So3Navigation;
use nalgebra::Matrix3;
use pvfc_core::prelude::{ExponentialPacing, Flywheel, PvfcLaw, RigidBody, SuspendedField};
use pvfc_sim::scenario::AttitudeController;
use pyo3::prelude::*;

#[pymethods]
impl Controller {
    /// PVFC of a rigid body's attitude (`J ω̇ + ω × Jω = T`, `ω` in the body frame) along a
    /// contour on SO(3): the body's inertia `J` (3, 3), the contour, the navigation function
    /// of eq. (26), exponential self-pacing (eq. 21), the flywheel and γ. Its `step` and
    /// `evaluate` take the attitude as a rotation matrix (3, 3) and ω (3,).
    #[staticmethod]
    #[pyo3(signature = (inertia, contour, navigation, self_pacing = 20.0, energy = 20.0, flywheel_inertia = 1.0, gamma = 0.1, tau0 = 0.0))]
    #[allow(clippy::too_many_arguments)]
    fn attitude(
        inertia: &Bound<'_, PyAny>,
        contour: &So3ConstantRate,
        navigation: &So3Navigation,
        self_pacing: f64,
        energy: f64,
        flywheel_inertia: f64,
        gamma: f64,
        tau0: f64,
    ) -> PyResult<Controller> {
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
        let ctl: AttitudeController =
            pvfc_core::controller::Controller::new(law).starting_at_rest(tau0);
        Ok(Controller::of(Law::Attitude(Box::new(ctl))))
    }
}
