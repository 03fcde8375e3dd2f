//! Joint friction of the simulated plant: Coulomb + viscous, with a regularised sign, and an
//! optional Stribeck peak (stiction).

use crate::error::{Result, SimError};
use nalgebra::SVector;
use serde::{Deserialize, Serialize};

/// Friction torque on each joint, opposing its velocity:
/// `F_i = −(b_i q̇_i + f_i tanh(q̇_i / v_s))`.
///
/// **Stiction.** The Coulomb term's sign is regularised by `tanh(q̇/v_s)`: below the
/// stiction velocity `v_s` the friction acts as a steep viscous damper (slope `f_i/v_s`), which
/// holds a joint almost still against torques smaller than `f_i` and lets it break away above.
/// It is smooth, so the fixed-step integrators stay 4th order; the price is the steep slope,
/// which is why the plant is integrated in substeps finer than the controller's period
/// (0.1 ms for `v_s = 0.01 rad/s`). A Karnopp model with its switching logic was the
/// alternative; the smooth sign keeps the energy audit exact (the friction power is a plain
/// function of the state).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointFriction {
    /// Coulomb levels `f_i` (N·m), one per joint.
    #[serde(default)]
    pub coulomb: Vec<f64>,
    /// Viscous coefficients `b_i` (N·m·s/rad), one per joint.
    #[serde(default)]
    pub viscous: Vec<f64>,
    /// Stiction velocity `v_s` of the regularised sign (rad/s).
    #[serde(default = "default_stiction_velocity")]
    pub stiction_velocity: f64,
    /// A Stribeck peak: the breakaway levels above Coulomb's at low speed. None: Coulomb and
    /// viscous only.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stribeck: Option<Stribeck>,
}

/// Stiction as a Stribeck curve: the friction level falls from the breakaway level `f_s,i` at
/// rest to the Coulomb level `f_i` as the speed grows past the Stribeck velocity `v_st`,
/// `F_i = −(b_i q̇_i + (f_i + (f_s,i − f_i) e^{−(q̇_i/v_st)²}) tanh(q̇_i/v_s))`. Still a function
/// of the velocity alone, so the friction power `F_fᵀq̇ ≤ 0` keeps the energy audit exact.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Stribeck {
    /// Breakaway levels `f_s,i ≥ f_i` (N·m), one per joint.
    pub breakaway: Vec<f64>,
    /// The Stribeck velocity `v_st > 0` (rad/s).
    pub velocity: f64,
}

fn default_stiction_velocity() -> f64 {
    0.01
}

impl Default for JointFriction {
    fn default() -> Self {
        JointFriction {
            coulomb: vec![0.0; 2],
            viscous: vec![0.0; 2],
            stiction_velocity: default_stiction_velocity(),
            stribeck: None,
        }
    }
}

impl JointFriction {
    /// Checks the levels against a robot of `dof` joints: one per joint (a list of zeros of
    /// any length means no friction), finite, `≥ 0`, and `v_s > 0`.
    pub fn validate_for(&self, dof: usize) -> Result<()> {
        for (name, x) in [("coulomb", &self.coulomb), ("viscous", &self.viscous)] {
            if x.len() != dof && x.iter().any(|v| *v != 0.0) {
                return Err(SimError::Setting(format!(
                    "plant.friction.{name}: {} entries for a {dof}-joint robot",
                    x.len()
                )));
            }
        }
        if let Some(st) = &self.stribeck {
            if st.breakaway.len() != dof {
                return Err(SimError::Setting(format!(
                    "plant.friction.stribeck.breakaway: {} entries for a {dof}-joint robot",
                    st.breakaway.len()
                )));
            }
        }
        self.validate()
    }

    /// Checks the levels: finite, `≥ 0`, and `v_s > 0`; a Stribeck peak's breakaway levels at
    /// least the Coulomb levels and its velocity `> 0`.
    pub fn validate(&self) -> Result<()> {
        let ok = self
            .coulomb
            .iter()
            .chain(self.viscous.iter())
            .all(|x| x.is_finite() && *x >= 0.0)
            && self.stiction_velocity.is_finite()
            && self.stiction_velocity > 0.0;
        if let Some(st) = &self.stribeck {
            let level = |i: usize| self.coulomb.get(i).copied().unwrap_or(0.0);
            if let Some((i, f)) = st
                .breakaway
                .iter()
                .enumerate()
                .find(|(i, f)| !(f.is_finite() && **f >= level(*i)))
            {
                return Err(SimError::Setting(format!(
                    "plant.friction.stribeck.breakaway[{i}] = {f}: finite and at least the Coulomb level {}",
                    level(i)
                )));
            }
            if !(st.velocity.is_finite() && st.velocity > 0.0) {
                return Err(SimError::Setting(format!(
                    "plant.friction.stribeck.velocity = {}: finite and > 0",
                    st.velocity
                )));
            }
        }
        if ok {
            Ok(())
        } else {
            Err(SimError::Setting(format!(
                "friction: levels must be finite and ≥ 0, stiction_velocity > 0 (got {self:?})"
            )))
        }
    }

    /// The friction torque at joint velocity `v` (a joint without a level has none).
    #[inline]
    pub fn torque<const N: usize>(&self, v: &SVector<f64, N>) -> SVector<f64, N> {
        SVector::from_fn(|i, _| {
            let b = self.viscous.get(i).copied().unwrap_or(0.0);
            let mut f = self.coulomb.get(i).copied().unwrap_or(0.0);
            if let Some(st) = &self.stribeck {
                let fs = st.breakaway.get(i).copied().unwrap_or(f);
                let x = v[i] / st.velocity;
                f += (fs - f) * (-x * x).exp();
            }
            -(b * v[i] + f * (v[i] / self.stiction_velocity).tanh())
        })
    }

    /// `true` when there is no friction at all.
    pub fn is_zero(&self) -> bool {
        self.coulomb
            .iter()
            .chain(self.viscous.iter())
            .all(|x| *x == 0.0)
    }
}
