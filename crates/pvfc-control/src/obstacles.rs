//! `[obstacles]`: obstacles the field keeps the robot away from (the paper's Remark 3), as
//! plain data, and the builder of the core's [`ObstacleSet`] from it.
//!
//! ```toml
//! [obstacles]
//! kappa = 2.0          # Rimon–Koditschek's exponent κ ≥ 1
//! speed = 3.0          # optional: the gradient term's speed limit (rad/s)
//! # scale = 4.0        # optional: γ₀, by default U's value at E = (π, …, π)
//!
//! [[obstacles.joint]]  # a region of the joint space (rad)
//! center = [-1.6, 0.0]
//! radius = 0.3         # a ball; or semi_axes = [0.3, 0.4] with exponent = 1 (ellipsoid) … 8
//! influence = 0.4
//!
//! [[obstacles.body]]   # a sphere on the robot, in its link's frame (m)
//! link = 1
//! offset = [0.26, 0.0, 0.0]
//! radius = 0.02
//!
//! [[obstacles.world]]  # a shape in the world (m)
//! shape = "cylinder"   # "sphere", "capsule" (with end = [x, y, z]),
//! center = [-0.1, 0.33, 0.0]   # or "box" (with half_extents = [..], rpy = [..])
//! axis = [0.0, 0.0, 1.0]
//! radius = 0.05
//! margin = 0.01
//! influence = 0.1
//! ```

use crate::error::{Result, SimError};
use nalgebra::{SVector, Vector3};
use pvfc_core::mechanics::Pose;
use pvfc_core::obstacle::{
    BodySphere, Composition, JointRegion, ObstacleSet, WorldObstacle, WorldShape,
};
use pvfc_core::prelude::*;
use serde::{Deserialize, Serialize};

/// `[obstacles]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObstacleSpec {
    /// Rimon–Koditschek's exponent `κ ≥ 1` (default 2).
    #[serde(default = "default_kappa")]
    pub kappa: f64,
    /// The scale `γ₀` of the composition; by default the navigation function's value at
    /// `E = (π, …, π)` (its largest on a torus).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scale: Option<f64>,
    /// The gradient term's speed limit (joint units per second); none by default.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub speed: Option<f64>,
    /// Regions of the joint space.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub joint: Vec<JointRegionSpec>,
    /// Spheres on the robot kept away from the world's shapes.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub body: Vec<BodySphereSpec>,
    /// Shapes in the world.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub world: Vec<WorldObstacleSpec>,
}

fn default_kappa() -> f64 {
    2.0
}

fn default_exponent() -> u8 {
    1
}

fn default_axis() -> [f64; 3] {
    [0.0, 0.0, 1.0]
}

/// `[[obstacles.joint]]`: a ball (`radius`) or a superellipsoid (`semi_axes`, `exponent`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointRegionSpec {
    /// The centre, one entry per joint.
    pub center: Vec<f64>,
    /// A ball's radius.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
    /// The semi-axes, one entry per joint (instead of `radius`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub semi_axes: Option<Vec<f64>>,
    /// The exponent `p` (1: an ellipsoid; up to 8: a rounded box).
    #[serde(default = "default_exponent")]
    pub exponent: u8,
    /// The influence width beyond the surface.
    pub influence: f64,
}

/// `[[obstacles.body]]`: a sphere fixed on a link.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySphereSpec {
    /// The link (from 0: joint `i` moves link `i`).
    pub link: usize,
    /// The centre in the link's frame (m).
    #[serde(default)]
    pub offset: [f64; 3],
    /// The radius (m).
    pub radius: f64,
}

/// The kind of a world shape.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ShapeKind {
    /// A ball about `center`.
    Sphere,
    /// An infinite cylinder through `center` along `axis`.
    Cylinder,
    /// A capsule from `center` to `end`.
    Capsule,
    /// A box of `half_extents` about `center`, turned by `rpy`, edges rounded by `radius`.
    Box,
}

/// `[[obstacles.world]]`: a shape in the world frame.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WorldObstacleSpec {
    /// `"sphere"`, `"cylinder"`, `"capsule"` or `"box"`.
    pub shape: ShapeKind,
    /// A sphere's or a box's centre, a point on a cylinder's axis, a capsule's first end (m).
    pub center: [f64; 3],
    /// A cylinder's axis (default `z`).
    #[serde(default = "default_axis")]
    pub axis: [f64; 3],
    /// A capsule's second end (m).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub end: Option<[f64; 3]>,
    /// A box's half extents along its axes (m).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub half_extents: Option<[f64; 3]>,
    /// A box's roll, pitch, yaw (rad, URDF's convention).
    #[serde(default)]
    pub rpy: [f64; 3],
    /// The radius (m; a box's rounding, ≥ 0).
    pub radius: f64,
    /// The margin kept between it and the robot's spheres (m).
    #[serde(default)]
    pub margin: f64,
    /// The influence width beyond the margin (m).
    pub influence: f64,
}

fn setting(message: String) -> SimError {
    SimError::Setting(message)
}

fn joints<const N: usize>(x: &[f64], key: String) -> Result<SVector<f64, N>> {
    if x.len() != N {
        return Err(setting(format!(
            "{key}: {} entries for a {N}-joint robot",
            x.len()
        )));
    }
    Ok(SVector::from_column_slice(x))
}

impl ObstacleSpec {
    /// The set for an `N`-joint robot whose kinematics is `chain` (needed by `body` and
    /// `world`), with `scale` as `γ₀` unless the spec gives one. Every error names its key.
    pub fn build<const N: usize>(
        &self,
        chain: Option<SerialChain<f64, N>>,
        scale: f64,
    ) -> Result<ObstacleSet<f64, N>> {
        let composition = Composition::new(self.kappa, self.scale.unwrap_or(scale), self.speed)
            .map_err(|e| setting(format!("obstacles: {e}")))?;
        let mut set = ObstacleSet::new(composition);
        for (i, r) in self.joint.iter().enumerate() {
            let key = format!("obstacles.joint[{i}]");
            let center = joints::<N>(&r.center, format!("{key}.center"))?;
            let region = match (&r.radius, &r.semi_axes) {
                (Some(radius), None) => JointRegion::ball(center, *radius, r.influence),
                (None, Some(a)) => JointRegion::new(
                    center,
                    joints::<N>(a, format!("{key}.semi_axes"))?,
                    r.exponent,
                    r.influence,
                ),
                _ => {
                    return Err(setting(format!(
                        "{key}: give either radius (a ball) or semi_axes"
                    )))
                }
            }
            .map_err(|e| setting(format!("{key}: {e}")))?;
            set.add_region(region)
                .map_err(|e| setting(format!("{key}: {e}")))?;
        }
        if self.body.is_empty() != self.world.is_empty() {
            return Err(setting(
                "obstacles: world shapes need spheres on the robot ([[obstacles.body]]) and spheres on the robot need world shapes".into(),
            ));
        }
        if !self.world.is_empty() {
            let chain = chain.ok_or_else(|| {
                setting(
                    "obstacles.world: this robot has no kinematic chain to place its spheres"
                        .into(),
                )
            })?;
            set.set_chain(chain);
        }
        for (i, b) in self.body.iter().enumerate() {
            let key = format!("obstacles.body[{i}]");
            if b.link >= N {
                return Err(setting(format!(
                    "{key}.link = {}: the robot's links are 0 to {}",
                    b.link,
                    N.saturating_sub(1)
                )));
            }
            let sphere = BodySphere::new(b.link, Vector3::from(b.offset), b.radius)
                .map_err(|e| setting(format!("{key}: {e}")))?;
            set.add_body_sphere(sphere)
                .map_err(|e| setting(format!("{key}: {e}")))?;
        }
        for (i, w) in self.world.iter().enumerate() {
            let key = format!("obstacles.world[{i}]");
            let shape = match w.shape {
                ShapeKind::Sphere => WorldShape::Sphere {
                    center: Vector3::from(w.center),
                    radius: w.radius,
                },
                ShapeKind::Cylinder => WorldShape::Cylinder {
                    point: Vector3::from(w.center),
                    axis: Vector3::from(w.axis),
                    radius: w.radius,
                },
                ShapeKind::Capsule => WorldShape::Capsule {
                    a: Vector3::from(w.center),
                    b: Vector3::from(w.end.ok_or_else(|| {
                        setting(format!("{key}.end: a capsule needs its second end"))
                    })?),
                    radius: w.radius,
                },
                ShapeKind::Box => WorldShape::Box {
                    center: Vector3::from(w.center),
                    rotation: Pose::from_xyz_rpy([0.0; 3], w.rpy).rotation,
                    half_extents: Vector3::from(w.half_extents.ok_or_else(|| {
                        setting(format!("{key}.half_extents: a box needs its half extents"))
                    })?),
                    radius: w.radius,
                },
            };
            let obstacle = WorldObstacle::new(shape, w.margin, w.influence)
                .map_err(|e| setting(format!("{key}: {e}")))?;
            set.add_world_obstacle(obstacle)
                .map_err(|e| setting(format!("{key}: {e}")))?;
        }
        Ok(set)
    }
}
