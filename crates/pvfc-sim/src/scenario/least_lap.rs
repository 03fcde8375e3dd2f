//! The least lap any controller can make on a scenario's plant: the time-optimal
//! parameterisation of its contour under the drives' limits (`pvfc_core::pace`, checked against
//! TOPP-RA), at full use of the limits, against the plant's own Coulomb and viscous friction,
//! with its model error (`plant.mass_scale`) and, for a serial chain, gravity, at no rate above
//! the one the scenario asks for. A controller's lap time is measured against it.

use crate::error::{Result, SimError};
use crate::model::arm::minimum_lap;
use crate::model::pace::DriveFriction;
use crate::scenario::{RobotSpec, Scenario};
use pvfc_core::prelude::Scara;

impl Scenario {
    /// The least lap time (s) of the scenario's contour on its plant (module documentation).
    /// A Stribeck peak, which adds torque only near rest, is left out, so the lap is never
    /// longer than the true least. Errors: no drive-limited pace (`[controller.pace]` and
    /// torque limits), no closed contour, or a rigid body.
    pub fn least_lap(&self) -> Result<f64> {
        let pace = self.drive_pace()?.ok_or_else(|| {
            SimError::Setting(format!(
                "run `{}`: a least lap needs a drive-limited pace ([controller.pace])",
                self.name
            ))
        })?;
        let plant = DriveFriction {
            coulomb: self.plant.friction.coulomb.clone(),
            viscous: self.plant.friction.viscous.clone(),
        };
        match &self.plant.robot {
            RobotSpec::Scara(_) => pace.minimum_lap(
                &self.plant_scara(Scara::new(self.scara()?)?)?,
                &self.contour()?,
                self.period(),
                &plant,
                false,
            ),
            RobotSpec::SerialChain(_) => {
                let robot = self.robot()?;
                let settings = self.arm_settings_for(&robot)?;
                minimum_lap(&self.plant_robot(&robot)?, &settings, &pace, &plant)
            }
            RobotSpec::RigidBody(_) => Err(SimError::Setting(
                "a least lap is for arms driven at their joints, not a rigid body".into(),
            )),
        }
    }
}
