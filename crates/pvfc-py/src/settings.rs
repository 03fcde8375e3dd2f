//! `pvfc.ControllerSettings`: the numbers of a controller apart from its robot, contour and
//! navigation function (`Controller.compose`).

use crate::convert::any_array;
use numpy::PyArray1;
use pvfc_sim::model::arm::{ArmSettings, JointContourSpec};
use pyo3::prelude::*;

/// The settings of a PVFC controller: self-pacing `R` (eq. 21), the energy level `Ē` and the
/// flywheel's inertia `M_F` (eq. 6), the coupling gain `γ` (eq. 7) or the coupling rate `γβĒ`
/// (1/s, Remark 1: `γ = coupling_rate / (βĒ)` with `β` the nominal speed `r` or 1, also when
/// `Ē` is sized from the pace with `energy=0`), and the add-ons: gravity
/// compensation, friction compensation (eq. 35, one Coulomb level per joint, with a velocity
/// band), nominal speed `(c, r)` (eq. 36) with the gain of its integral (`nominal_speed_integral`,
/// 1/s; 0: none), the contour parameter to start at, and a bound on the field's kinetic
/// energy as a share of `Ē` (`field_energy_bound`, in (0, 1); None: no bound): where the field
/// would carry more (an arm far off its contour) it is scaled onto it, and the law is defined
/// at every state. Checked when composed with a robot.
#[pyclass(module = "pvfc", frozen, from_py_object)]
#[derive(Clone)]
pub(crate) struct ControllerSettings {
    #[pyo3(get)]
    pub(crate) self_pacing: f64,
    #[pyo3(get)]
    pub(crate) energy: f64,
    #[pyo3(get)]
    pub(crate) flywheel_inertia: f64,
    #[pyo3(get)]
    pub(crate) gamma: f64,
    #[pyo3(get)]
    pub(crate) coupling_rate: Option<f64>,
    #[pyo3(get)]
    pub(crate) gravity_compensation: bool,
    pub(crate) friction_compensation: Option<Vec<f64>>,
    #[pyo3(get)]
    pub(crate) friction_band: f64,
    #[pyo3(get)]
    pub(crate) nominal_speed: Option<(f64, f64)>,
    #[pyo3(get)]
    pub(crate) nominal_speed_integral: f64,
    #[pyo3(get)]
    pub(crate) tau0: f64,
    #[pyo3(get)]
    pub(crate) field_energy_bound: Option<f64>,
}

impl ControllerSettings {
    /// The settings of an arm's controller with this contour and these navigation weights.
    pub(crate) fn arm_settings(&self, contour: JointContourSpec, h: Vec<f64>) -> ArmSettings {
        ArmSettings {
            field: pvfc_sim::model::arm_field::FieldSpec::Joint,
            contour,
            h,
            self_pacing: self.self_pacing,
            energy: self.energy,
            flywheel_inertia: self.flywheel_inertia,
            gamma: self.gamma,
            coupling_rate: self.coupling_rate,
            gravity_compensation: self.gravity_compensation,
            friction_compensation: self.friction_compensation.clone(),
            friction_band: self.friction_band,
            nominal_speed: self.nominal_speed,
            nominal_speed_integral: self.nominal_speed_integral,
            tau0: self.tau0,
            field_energy_bound: self.field_energy_bound,
            obstacles: None,
            pace: None,
        }
    }
}

impl Default for ControllerSettings {
    fn default() -> Self {
        ControllerSettings {
            self_pacing: 0.0,
            energy: 10.0,
            flywheel_inertia: 1.0,
            gamma: 1.0,
            coupling_rate: None,
            gravity_compensation: true,
            friction_compensation: None,
            friction_band: 0.0,
            nominal_speed: None,
            nominal_speed_integral: 0.0,
            tau0: 0.0,
            field_energy_bound: None,
        }
    }
}

#[pymethods]
impl ControllerSettings {
    #[new]
    #[pyo3(signature = (*, self_pacing=0.0, energy=10.0, flywheel_inertia=1.0, gamma=1.0,
        coupling_rate=None, gravity_compensation=true, friction_compensation=None, friction_band=0.0,
        nominal_speed=None, nominal_speed_integral=0.0, tau0=0.0, field_energy_bound=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        self_pacing: f64,
        energy: f64,
        flywheel_inertia: f64,
        gamma: f64,
        coupling_rate: Option<f64>,
        gravity_compensation: bool,
        friction_compensation: Option<&Bound<'_, PyAny>>,
        friction_band: f64,
        nominal_speed: Option<(f64, f64)>,
        nominal_speed_integral: f64,
        tau0: f64,
        field_energy_bound: Option<f64>,
    ) -> PyResult<Self> {
        Ok(ControllerSettings {
            self_pacing,
            energy,
            flywheel_inertia,
            gamma,
            coupling_rate,
            gravity_compensation,
            friction_compensation: friction_compensation
                .map(|f| any_array(f, "friction_compensation", 1).map(|a| a.1))
                .transpose()?,
            friction_band,
            nominal_speed,
            nominal_speed_integral,
            tau0,
            field_energy_bound,
        })
    }

    /// The Coulomb levels of the friction compensation, one per joint, or None.
    #[getter]
    fn friction_compensation<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<f64>>> {
        self.friction_compensation
            .clone()
            .map(|f| crate::convert::out1(py, f))
    }
}
