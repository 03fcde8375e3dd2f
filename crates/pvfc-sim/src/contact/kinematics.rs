//! The planar arm's kinematics as the contact layer needs them, from the robot model: where
//! its bodies are, the velocity of a point on a link, and `Jᵀf` for a force there; and the
//! contact forces they add up to.

use crate::error::Result;
use nalgebra::Vector2;
use pvfc_core::lie::Torus;
use pvfc_core::mechanics::{Scara, ScaraParameters};

/// The robot's collision bodies, in the order a [`ContactForces`] part names them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RobotPart {
    /// The capsule around link 1 (moves with joint 1 only).
    Link1,
    /// The capsule around link 2.
    Link2,
    /// The tool disc at the end effector.
    Tool,
}

/// The planar kinematics the contact layer needs: link frames, and `Jᵀf` for a force at a
/// point on a link (for a revolute chain, `τ_j = (p − o_j) × f` for every joint `j` at or
/// before the link).
/// The link frames come from the robot model's forward kinematics ([`Scara::elbow`],
/// [`Scara::end_effector`]), the same model the controller and the plant use.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlanarArm {
    model: Scara<f64>,
}

impl From<Scara<f64>> for PlanarArm {
    fn from(model: Scara<f64>) -> Self {
        PlanarArm { model }
    }
}

fn cross(a: &Vector2<f64>, b: &Vector2<f64>) -> f64 {
    a.x * b.y - a.y * b.x
}

impl PlanarArm {
    /// The kinematics of the arm with these parameters (an error for non-physical ones).
    pub fn of(p: &ScaraParameters<f64>) -> Result<Self> {
        Ok(Scara::new(*p)?.into())
    }

    /// The robot model.
    pub fn model(&self) -> &Scara<f64> {
        &self.model
    }

    /// The link lengths `(l₁, l₂)` (m).
    pub fn lengths(&self) -> (f64, f64) {
        let p = self.model.parameters();
        (p.l1, p.l2)
    }

    /// The elbow (joint 2) position.
    pub fn elbow(&self, q: &Torus<f64, 2>) -> Vector2<f64> {
        self.model.elbow(q)
    }

    /// The end effector (tool centre).
    pub fn tip(&self, q: &Torus<f64, 2>) -> Vector2<f64> {
        self.model.end_effector(q)
    }

    /// The velocity of the material point at `p` (world) attached to `part`.
    pub fn point_velocity(
        &self,
        part: RobotPart,
        q: &Torus<f64, 2>,
        v: &Vector2<f64>,
        p: &Vector2<f64>,
    ) -> Vector2<f64> {
        let perp = |r: Vector2<f64>| Vector2::new(-r.y, r.x);
        match part {
            RobotPart::Link1 => perp(*p) * v[0],
            RobotPart::Link2 | RobotPart::Tool => perp(*p) * v[0] + perp(p - self.elbow(q)) * v[1],
        }
    }

    /// The joint torques `Jᵀf` of a force `f` at the point `p` (world) of `part`.
    pub fn joint_torque(
        &self,
        part: RobotPart,
        q: &Torus<f64, 2>,
        p: &Vector2<f64>,
        f: &Vector2<f64>,
    ) -> Vector2<f64> {
        match part {
            RobotPart::Link1 => Vector2::new(cross(p, f), 0.0),
            RobotPart::Link2 | RobotPart::Tool => {
                Vector2::new(cross(p, f), cross(&(p - self.elbow(q)), f))
            }
        }
    }
}

/// The contact forces on the arm at one instant.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactForces {
    /// The environment's joint torques `F_e = Σ Jᵀf` (N·m).
    pub torque: Vector2<f64>,
    /// The sum of the Cartesian contact forces on the arm (N).
    pub force: Vector2<f64>,
    /// The sum of the normal force magnitudes (N): what a force sensor at the contacts reads.
    pub normal_force: f64,
    /// The deepest penetration (m; 0 without contact).
    pub depth: f64,
    /// The number of contact points.
    pub contacts: usize,
}

/// One contact point: where on the robot, and the force there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactPoint {
    /// The robot's body that is touched.
    pub part: RobotPart,
    /// The contact point on the robot (world, m).
    pub point: Vector2<f64>,
    /// The force on the robot (N).
    pub force: Vector2<f64>,
    /// Its normal part `f_n ≥ 0` (N).
    pub normal_force: f64,
    /// The penetration (m).
    pub depth: f64,
}

impl ContactForces {
    /// Adds one contact point of the arm at `q`.
    pub fn add(&mut self, arm: &PlanarArm, q: &Torus<f64, 2>, c: &ContactPoint) {
        self.torque += arm.joint_torque(c.part, q, &c.point, &c.force);
        self.force += c.force;
        self.normal_force += c.normal_force;
        self.depth = self.depth.max(c.depth);
        self.contacts += 1;
    }
}
