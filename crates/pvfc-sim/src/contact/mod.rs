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
use nalgebra::{SVector, Vector2};
use pvfc_core::lie::{LieGroup, Torus};
use pvfc_core::mechanics::ScaraParameters;
use serde::{Deserialize, Serialize};

pub mod spatial;
#[cfg(feature = "contact")]
mod world;
#[cfg(feature = "contact")]
pub use world::ContactWorld;

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

/// The shape of an obstacle, in its own frame.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum ShapeSpec {
    /// A box (a wall, a workpiece) with half extents along its local x and y (m).
    Box {
        /// Half extents (m).
        half_extents: [f64; 2],
    },
    /// A disc (a post, a pushing body) of radius (m).
    Ball {
        /// Radius (m).
        radius: f64,
    },
    /// A capsule from `a` to `b` (local, m) with radius (m).
    Capsule {
        /// First end.
        a: [f64; 2],
        /// Second end.
        b: [f64; 2],
        /// Radius (m).
        radius: f64,
    },
}

/// A keyframe of an obstacle's motion: at time `t` the obstacle is displaced by `offset` from
/// its `position`. Between keyframes it moves with a smoothstep (`3s² − 2s³`), so its velocity
/// is continuous and zero at every keyframe; before the first and after the last it rests.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Keyframe {
    /// Time (s).
    pub t: f64,
    /// Displacement from the obstacle's position (m).
    pub offset: [f64; 2],
}

/// The smoothstep motion through `n` keyframes `key(i) = (t_i, offset_i)` (strictly increasing
/// times): the displacement and velocity at `t` (see [`Keyframe`]; in the plane and in space).
pub(crate) fn keyframe_motion<const D: usize>(
    n: usize,
    key: impl Fn(usize) -> (f64, SVector<f64, D>),
    t: f64,
) -> (SVector<f64, D>, SVector<f64, D>) {
    if n == 0 {
        return (SVector::zeros(), SVector::zeros());
    }
    let (first, last) = (key(0), key(n - 1));
    if t <= first.0 {
        return (first.1, SVector::zeros());
    }
    if t >= last.0 {
        return (last.1, SVector::zeros());
    }
    for i in 1..n {
        let (a, b) = (key(i - 1), key(i));
        if t < b.0 {
            let span = b.0 - a.0;
            let s = (t - a.0) / span;
            let (pa, pb) = (a.1, b.1);
            let shape = s * s * (3.0 - 2.0 * s);
            let rate = 6.0 * s * (1.0 - s) / span;
            return (pa + (pb - pa) * shape, (pb - pa) * rate);
        }
    }
    (last.1, SVector::zeros())
}

/// Keyframe times and offsets are finite, the times strictly increasing.
pub(crate) fn keyframes_ok<const D: usize>(
    keys: impl Iterator<Item = (f64, [f64; D])> + Clone,
) -> bool {
    let finite = keys
        .clone()
        .all(|(t, o)| t.is_finite() && o.iter().all(|x| x.is_finite()));
    let times: Vec<f64> = keys.map(|(t, _)| t).collect();
    finite && times.windows(2).all(|w| w[1] > w[0])
}

/// An obstacle or workpiece.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObstacleSpec {
    /// A name (for errors and logs).
    pub name: String,
    /// Its shape.
    pub shape: ShapeSpec,
    /// Position of its frame in the base frame of the arm (m).
    pub position: [f64; 2],
    /// Orientation of its frame (rad).
    #[serde(default)]
    pub angle: f64,
    /// Its own contact law (a compliant workpiece); default: the scenario's.
    #[serde(default)]
    pub law: Option<ContactLaw>,
    /// Its motion (a pushing body, an obstacle that is taken away); empty: fixed.
    #[serde(default)]
    pub motion: Vec<Keyframe>,
}

impl ObstacleSpec {
    /// The displacement and velocity of the obstacle at time `t` (see [`Keyframe`]).
    pub fn motion_at(&self, t: f64) -> (Vector2<f64>, Vector2<f64>) {
        let k = &self.motion;
        keyframe_motion(k.len(), |i| (k[i].t, Vector2::from(k[i].offset)), t)
    }

    fn validate(&self) -> Result<()> {
        let bad = |what: &str| {
            Err(SimError::Setting(format!(
                "obstacle {:?}: {what}",
                self.name
            )))
        };
        let pos = |x: f64| x.is_finite() && x > 0.0;
        let shape_ok = match self.shape {
            ShapeSpec::Box { half_extents } => half_extents.iter().all(|&h| pos(h)),
            ShapeSpec::Ball { radius } => pos(radius),
            ShapeSpec::Capsule { a, b, radius } => {
                pos(radius) && a.iter().chain(b.iter()).all(|x| x.is_finite())
            }
        };
        if !shape_ok {
            return bad("shape dimensions must be finite and > 0");
        }
        if !(self.position.iter().all(|x| x.is_finite()) && self.angle.is_finite()) {
            return bad("position and angle must be finite");
        }
        if let Some(l) = &self.law {
            l.validate()
                .map_err(|e| SimError::Setting(format!("obstacle {:?}: {e}", self.name)))?;
        }
        if !keyframes_ok(self.motion.iter().map(|k| (k.t, k.offset))) {
            return bad("motion keyframes must be finite, with strictly increasing times");
        }
        Ok(())
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

/// Contact with the world, as a scenario's `[contact]` table.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSpec {
    /// Radii of the capsules around link 1 and link 2 (m).
    #[serde(default = "default_link_radius")]
    pub link_radius: [f64; 2],
    /// Radius of the tool, a disc at the end effector (m).
    #[serde(default = "default_tool_radius")]
    pub tool_radius: f64,
    /// The contact law of the obstacles that do not give their own.
    #[serde(default)]
    pub law: ContactLaw,
    /// The obstacles and workpieces.
    #[serde(default)]
    pub obstacles: Vec<ObstacleSpec>,
    /// Schedules the nominal speed of (36) on the contact force (needs
    /// `controller.nominal_speed`).
    #[serde(default)]
    pub force_schedule: Option<ForceSchedule>,
}

impl Default for ContactSpec {
    /// The default robot shapes and contact law, no obstacles.
    fn default() -> Self {
        ContactSpec {
            link_radius: default_link_radius(),
            tool_radius: default_tool_radius(),
            law: ContactLaw::default(),
            obstacles: Vec::new(),
            force_schedule: None,
        }
    }
}

fn default_link_radius() -> [f64; 2] {
    [0.04, 0.03]
}

fn default_tool_radius() -> f64 {
    0.015
}

impl ContactSpec {
    /// Checks the settings.
    pub fn validate(&self) -> Result<()> {
        let radii_ok = self
            .link_radius
            .iter()
            .chain([self.tool_radius].iter())
            .all(|r| r.is_finite() && *r > 0.0);
        if !radii_ok {
            return Err(SimError::Setting(
                "contact: link_radius and tool_radius must be finite and > 0".into(),
            ));
        }
        self.law.validate()?;
        for o in &self.obstacles {
            o.validate()?;
        }
        if let Some(f) = &self.force_schedule {
            f.validate()?;
        }
        Ok(())
    }
}

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
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlanarArm {
    /// Length of link 1 (m).
    pub l1: f64,
    /// Length of link 2 (m).
    pub l2: f64,
}

impl From<&ScaraParameters<f64>> for PlanarArm {
    fn from(p: &ScaraParameters<f64>) -> Self {
        PlanarArm { l1: p.l1, l2: p.l2 }
    }
}

fn cross(a: &Vector2<f64>, b: &Vector2<f64>) -> f64 {
    a.x * b.y - a.y * b.x
}

impl PlanarArm {
    /// The elbow (joint 2) position.
    pub fn elbow(&self, q: &Torus<f64, 2>) -> Vector2<f64> {
        let a = q.angles();
        Vector2::new(a[0].cos(), a[0].sin()) * self.l1
    }

    /// The end effector (tool centre).
    pub fn tip(&self, q: &Torus<f64, 2>) -> Vector2<f64> {
        let a = q.angles();
        let s = a[0] + a[1];
        self.elbow(q) + Vector2::new(s.cos(), s.sin()) * self.l2
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

#[cfg(all(test, not(feature = "contact")))]
#[allow(clippy::panic)]
mod without_rapier {
    #[test]
    fn a_contact_scenario_is_a_clear_error_without_the_feature() {
        let s = crate::presets::contact_wall();
        match crate::simulate::simulate(&s, &mut |_| {}) {
            Err(crate::SimError::Setting(m)) => assert!(m.contains("`contact` feature"), "{m}"),
            other => panic!("expected a setting error, got {other:?}"),
        }
        // The scenarios without contact still run.
        let mut s = crate::presets::fig6();
        s.duration = 0.1;
        assert!(crate::simulate::simulate(&s, &mut |_| {}).is_ok());
    }
}
