//! A disturbance torque on the plant's joints, for the robustness properties of section II
//! (after Theorem 1): under a bounded external torque the velocity-field error `e_β` is
//! ultimately bounded, and the bound shrinks as `γ` grows.
//!
//! The disturbance acts on the simulated arm as part of its environment: the plant's external
//! torque is `F_e = F_contact + τ_d(t)`, and its work is in the trace's `work_contact` ("the
//! work the environment did on the arm"), so the energy audit counts it. The controller does
//! not know it.

use crate::error::{Result, SimError};
use nalgebra::SVector;
use serde::{Deserialize, Serialize};

/// `τ_d,i(t) = amplitude_i · sin(2π frequency_i · t + phase_i)` on each joint (N·m, or N for a
/// prismatic joint): bounded by the amplitudes, smooth, so the fixed-step integrators keep
/// their order.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Disturbance {
    /// Amplitudes (N·m), one per joint.
    pub amplitude: Vec<f64>,
    /// Frequencies (Hz), one per joint.
    pub frequency: Vec<f64>,
    /// Phases (rad), one per joint; none: all zero.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub phase: Vec<f64>,
}

impl Disturbance {
    /// Checks the lists against a `dof`-joint robot: one entry per joint (`phase` may be
    /// empty), every entry finite; errors name the key.
    pub fn validate_for(&self, dof: usize) -> Result<()> {
        for (name, x, optional) in [
            ("amplitude", &self.amplitude, false),
            ("frequency", &self.frequency, false),
            ("phase", &self.phase, true),
        ] {
            if x.len() != dof && !(optional && x.is_empty()) {
                return Err(SimError::Setting(format!(
                    "plant.disturbance.{name}: {} entries for a {dof}-joint robot",
                    x.len()
                )));
            }
            if let Some(v) = x.iter().find(|v| !v.is_finite()) {
                return Err(SimError::Setting(format!(
                    "plant.disturbance.{name}: {v} is not finite"
                )));
            }
        }
        Ok(())
    }

    /// The torque at time `t` on an `N`-joint robot (the lengths checked by
    /// [`validate_for`](Self::validate_for)).
    pub fn torque<const N: usize>(&self, t: f64) -> SVector<f64, N> {
        SVector::from_fn(|i, _| {
            let phase = self.phase.get(i).copied().unwrap_or(0.0);
            let a = self.amplitude.get(i).copied().unwrap_or(0.0);
            let f = self.frequency.get(i).copied().unwrap_or(0.0);
            a * (core::f64::consts::TAU * f * t + phase).sin()
        })
    }
}

/// The torque of an optional disturbance at time `t` (zero without one).
pub(crate) fn torque_of<const N: usize>(d: Option<&Disturbance>, t: f64) -> SVector<f64, N> {
    d.map_or_else(SVector::zeros, |d| d.torque(t))
}
