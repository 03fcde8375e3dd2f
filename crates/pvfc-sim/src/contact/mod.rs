//! Contact with the world: the arm's links and tool touch obstacles and workpieces, and the
//! environment force `F_e = Jᵀf` enters the closed loop (eqs. 1, 9 of the paper: the loop is
//! passive with respect to the supply rate `F_eᵀq̇`).
//!
//! * [`ContactSpec`] (plain data, in a scenario's `[contact]` table): the robot's collision
//!   shapes, the obstacles (boxes, balls, capsules; fixed or moved along keyframes), the
//!   contact law and an optional schedule of the nominal speed `r` of (36) on the measured
//!   contact force (section V-A).
//! * [`ContactLaw`]: a Hunt–Crossley normal force with regularised Coulomb friction,
//!   evaluated on contact geometry (depth, normal, point).
//! * [`PlanarArm`]: the planar arm's kinematics for contact, from the robot model (`Scara`).
//! * [`Environment`]: anything that gives the contact forces on the arm at `(t, q, q̇)`. The
//!   simulation loops take one. [`HalfPlane`] is an analytic one (for tests and as a
//!   reference), and `ContactWorld` (feature `contact`, on by default) is the one on Rapier:
//!   its narrow phase finds the contacts between the arm's colliders and the world's.
//!
//! Why a compliant law and not Rapier's impulses: the arm's dynamics stay in the analytic
//! model (the same one the controller and the energy audit use), and its colliders are moved
//! kinematically from `q`. Rapier's solver computes no impulses between kinematic and fixed
//! bodies, so the force is computed from the contact manifolds Rapier finds, with a
//! stiffness that is the workpiece's (or the wall's) own compliance. The force is then a
//! continuous function of the state, RK4 keeps its order, and the energy audit's residual is
//! integration error only.

use crate::error::{Result, SimError};
use nalgebra::Vector2;
use pvfc_core::lie::{LieGroup, Torus};

mod kinematics;
mod law;
pub mod spatial;
mod spec;
#[cfg(feature = "contact")]
mod world;

pub use kinematics::{ContactForces, ContactPoint, PlanarArm, RobotPart};
pub use law::{ContactLaw, ForceSchedule};
pub(crate) use spec::{keyframe_motion, keyframes_ok};
pub use spec::{ContactSpec, Keyframe, ObstacleSpec, ShapeSpec};
#[cfg(feature = "contact")]
pub use world::ContactWorld;

/// What the arm touches: the contact forces at time `t` and state `(q, q̇)`. The simulation
/// calls it at every integration stage, so it must be a function of its arguments (no
/// hidden state that changes between calls).
pub trait Environment {
    /// The contact forces on the arm.
    fn contact(&mut self, t: f64, q: &Torus<f64, 2>, v: &Vector2<f64>) -> Result<ContactForces>;
}

/// An analytic environment: a fixed half-plane `{x : n·x ≤ c}` touched by the tool disc
/// only, with a [`ContactLaw`]. A reference for the Rapier world in tests, and the simplest
/// environment to write by hand.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HalfPlane {
    /// The arm's kinematics.
    pub arm: PlanarArm,
    /// Unit normal pointing out of the solid (into free space).
    pub normal: Vector2<f64>,
    /// Offset: the surface is `n·x = offset`.
    pub offset: f64,
    /// Tool radius (m).
    pub tool_radius: f64,
    /// The contact law.
    pub law: ContactLaw,
}

impl Environment for HalfPlane {
    fn contact(&mut self, _t: f64, q: &Torus<f64, 2>, v: &Vector2<f64>) -> Result<ContactForces> {
        check_state(q, v)?;
        let c = self.arm.tip(q);
        let depth = self.offset - (self.normal.dot(&c) - self.tool_radius);
        let mut out = ContactForces::default();
        if depth > 0.0 {
            let p = c - self.normal * self.tool_radius;
            let vel = self.arm.point_velocity(RobotPart::Tool, q, v, &p);
            let (force, normal_force) = self.law.force(depth, &self.normal, &vel);
            let c = ContactPoint {
                part: RobotPart::Tool,
                point: p,
                force,
                normal_force,
                depth,
            };
            out.add(&self.arm, q, &c);
        }
        Ok(out)
    }
}

/// A NaN or infinite state is a typed error, not a contact query.
pub(crate) fn check_state(q: &Torus<f64, 2>, v: &Vector2<f64>) -> Result<()> {
    if q.is_finite() && v.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(SimError::Core(pvfc_core::Error::new(
            pvfc_core::ErrorKind::NonFinite,
            "contact: the arm's state is not finite",
        )))
    }
}
