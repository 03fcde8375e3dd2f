//! Running a rigid body's attitude scenario (`kind = "rigid_body"`, section IV-B's satellite):
//! the body on SO(3) in the sampled-data or continuous PVFC loop, through the same generic
//! loops as the arms (`run/loops.rs`). The body is in free space; a disturbance torque
//! is its only environment.

use crate::error::Result;
use crate::run::loops::{self, Surroundings};
use crate::scenario::{joint_vector, AttitudeController, Mode, Scenario};
use crate::trace::{ContactSample, ContactTrace, Trace, Work};
use nalgebra::Vector3;
use pvfc_core::prelude::*;

/// Runs the PVFC loop of a rigid body's scenario from its controller `ctl` (which holds the
/// body). `progress` is called with the fraction done.
pub fn simulate_body_with(
    s: &Scenario,
    ctl: &AttitudeController,
    progress: &mut dyn FnMut(f64),
) -> Result<Trace> {
    let ctl = *ctl;
    let plant = *ctl.law().system();
    let (q, v) = initial_state(s)?;
    let mut env = Space;
    // A disturbed run keeps the environment's columns (its work is `work_contact`).
    let columns = s.plant.disturbance.is_some().then_some(3);
    match s.simulation.mode {
        Mode::Sampled => loops::sampled(s, &plant, ctl, (q, v), &mut env, columns, progress),
        Mode::Continuous => loops::continuous(s, ctl, (q, v), &mut env, columns, progress),
    }
}

/// The scenario's initial attitude `exp(r̂)` (`initial.q = r`, rad) and body angular velocity
/// (`initial.v`, rad/s); zeros when left out.
pub fn initial_state(s: &Scenario) -> Result<(So3<f64>, Vector3<f64>)> {
    let r = joint_vector::<3>(&s.initial.q, "initial.q")?;
    let w = joint_vector::<3>(&s.initial.v, "initial.v")?;
    Ok((So3::exp(&r), w))
}

/// Free space: nothing to touch.
struct Space;

impl Surroundings<So3<f64>, 3> for Space {
    type Contact = ();

    fn contact(&mut self, _: f64, _: &So3<f64>, _: &Vector3<f64>) -> Result<()> {
        Ok(())
    }

    fn torque(_: &()) -> Vector3<f64> {
        Vector3::zeros()
    }

    fn normal_force(_: &()) -> f64 {
        0.0
    }

    fn log(
        &self,
        ct: &mut ContactTrace,
        _: &So3<f64>,
        _: &(),
        work: &Work,
        nominal_speed: f64,
    ) -> Result<()> {
        ct.push_sample(
            &ContactSample {
                force: &[0.0; 3],
                normal_force: 0.0,
                depth: 0.0,
                torque: &[0.0; 3],
                tool: &[0.0; 3],
            },
            work,
            nominal_speed,
        );
        Ok(())
    }
}
