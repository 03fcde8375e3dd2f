//! The clearance a run kept from the scenario's obstacles (`[obstacles]`, Remark 3).

use crate::error::{Result, SimError};
use crate::scenario::{Scenario, System};
use crate::trace::Trace;
use nalgebra::SVector;
use pvfc_core::obstacle::ObstacleSet;

/// The smallest clearance of a run and when.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Clearance {
    /// The smallest clearance over the run: to joint-space regions in joint units, between
    /// the robot's spheres and the world's shapes in metres (negative: overlapping).
    pub smallest: f64,
    /// When it was reached (s).
    pub time: f64,
}

fn smallest<const N: usize>(set: &ObstacleSet<f64, N>, t: &Trace) -> Option<Clearance> {
    t.q.iter()
        .zip(&t.t)
        .filter_map(|(q, time)| {
            let q = SVector::<f64, N>::from_column_slice(q);
            set.clearance(&q).map(|c| (c, *time))
        })
        .fold(None, |best: Option<Clearance>, (c, time)| match best {
            Some(b) if b.smallest <= c => Some(b),
            _ => Some(Clearance { smallest: c, time }),
        })
}

/// The smallest clearance of the run `t` of `s` (its system built as `system`) from its
/// obstacles; `None` without `[obstacles]`.
pub fn clearance(s: &Scenario, system: &System, t: &Trace) -> Result<Option<Clearance>> {
    let Some(spec) = &s.obstacles else {
        return Ok(None);
    };
    match system {
        System::RigidBody(_) => Ok(None),
        System::Scara(_) => Ok(smallest(s.field()?.obstacles(), t)),
        System::SerialChain(sys) => crate::with_dof!(sys.robot.dof(), N => {
            let set = spec.build::<N>(Some(sys.robot.description().chain::<N>()?), 1.0)?;
            Ok(smallest(&set, t))
        }, otherwise Err(SimError::Setting(format!(
            "obstacles: a {}-joint robot (1 to 8 are supported)",
            sys.robot.dof()
        )))),
    }
}
