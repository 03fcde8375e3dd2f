//! Contact as plain data, a scenario's `[contact]` table: the obstacles (shapes, positions,
//! keyframed motion), the robot's collision radii, the law and the schedule.

use super::law::{ContactLaw, ForceSchedule};
use crate::error::{Result, SimError};
use nalgebra::{SVector, Vector2};
use serde::{Deserialize, Serialize};

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
