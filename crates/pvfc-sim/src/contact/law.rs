//! The contact force law (Hunt–Crossley normal force, regularised Coulomb friction) and the
//! schedule of the nominal speed on the measured contact force (section V-A).

use crate::error::{Result, SimError};
use nalgebra::SVector;
use serde::{Deserialize, Serialize};

/// The contact law: a Hunt–Crossley normal force `f_n = k·d·max(0, 1 + c·ḋ)` (depth `d`,
/// its rate `ḋ`) and Coulomb friction regularised as `f_t = −μ f_n tanh(v_t / v_s)`. `f_n`
/// is continuous at first touch (`d = 0`) and never pulls; the damping part `k c d ḋ²` and
/// the friction only take energy out of the robot–environment pair.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactLaw {
    /// Contact stiffness `k` (N/m).
    pub stiffness: f64,
    /// Hunt–Crossley damping factor `c` (s/m).
    #[serde(default)]
    pub damping: f64,
    /// Coulomb friction coefficient `μ` between the robot and the surface.
    #[serde(default)]
    pub friction: f64,
    /// Slip velocity `v_s` of the regularised friction (m/s).
    #[serde(default = "default_slip")]
    pub slip_velocity: f64,
}

fn default_slip() -> f64 {
    0.01
}

impl Default for ContactLaw {
    fn default() -> Self {
        ContactLaw {
            stiffness: 5.0e4,
            damping: 0.5,
            friction: 0.2,
            slip_velocity: default_slip(),
        }
    }
}

impl ContactLaw {
    /// Checks the parameters.
    pub fn validate(&self) -> Result<()> {
        let ok = self.stiffness.is_finite()
            && self.stiffness > 0.0
            && self.damping.is_finite()
            && self.damping >= 0.0
            && self.friction.is_finite()
            && self.friction >= 0.0
            && self.slip_velocity.is_finite()
            && self.slip_velocity > 0.0;
        if ok {
            Ok(())
        } else {
            Err(SimError::Setting(
                "contact law: stiffness must be finite and > 0, damping and friction finite and ≥ 0, slip_velocity finite and > 0".into(),
            ))
        }
    }

    /// The force on the robot at one contact: `depth ≥ 0` (m), `normal` the unit normal
    /// pointing from the environment into the robot, `relative_velocity` the velocity of the
    /// robot's material point minus the environment's. Returns the force (N) and its normal
    /// part `f_n ≥ 0`.
    /// The same in the plane (`D = 2`) and in space (`D = 3`).
    pub fn force<const D: usize>(
        &self,
        depth: f64,
        normal: &SVector<f64, D>,
        relative_velocity: &SVector<f64, D>,
    ) -> (SVector<f64, D>, f64) {
        if depth <= 0.0 {
            return (SVector::zeros(), 0.0);
        }
        let vn = relative_velocity.dot(normal);
        let depth_rate = -vn;
        let fn_ = self.stiffness * depth * (1.0 + self.damping * depth_rate).max(0.0);
        let vt = relative_velocity - normal * vn;
        let speed = vt.norm();
        let ft = if speed > 0.0 {
            -vt * (self.friction * fn_ * (speed / self.slip_velocity).tanh() / speed)
        } else {
            SVector::zeros()
        };
        (normal * fn_ + ft, fn_)
    }
}

/// Schedules the nominal speed `r` of (36) on the measured contact force `F` (section V-A:
/// "r can be scheduled"): `r = r₀ · clamp((F_limit − F)/(F_limit − F_onset), r_min/r₀, 1)`.
/// Below `onset` the speed is the nominal one; as `F` approaches `limit` it is cut down to
/// `min_fraction · r₀`; the energy the add-on (36) then takes out slows the robot, and with it
/// the force it presses with. Updated at the controller's rate.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ForceSchedule {
    /// Force below which `r` is the nominal `r₀` (N).
    pub onset: f64,
    /// The force limit (N).
    pub limit: f64,
    /// The smallest `r`, as a fraction of `r₀` (`> 0`, so that the tool keeps moving).
    pub min_fraction: f64,
}

impl ForceSchedule {
    /// The scheduled nominal speed for the nominal speed `r0` and the force `force`.
    pub fn speed(&self, r0: f64, force: f64) -> f64 {
        let x = (self.limit - force) / (self.limit - self.onset);
        r0 * x.clamp(self.min_fraction, 1.0)
    }

    pub(crate) fn validate(&self) -> Result<()> {
        let ok = self.onset.is_finite()
            && self.limit.is_finite()
            && self.onset >= 0.0
            && self.limit > self.onset
            && self.min_fraction > 0.0
            && self.min_fraction <= 1.0;
        if ok {
            Ok(())
        } else {
            Err(SimError::Setting(
                "contact.force_schedule: need 0 ≤ onset < limit (finite) and 0 < min_fraction ≤ 1"
                    .into(),
            ))
        }
    }
}
