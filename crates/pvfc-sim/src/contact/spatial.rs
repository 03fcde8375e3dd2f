//! Contact in 3-D for URDF arms, on Rapier's collision layer (`rapier3d-f64`, whose parry3d
//! contact queries give the deepest point, normal and depth of each arm–obstacle pair).
//!
//! * The arm, one of two ways ([`ArmGeometry`]), and a ball at the tool frame in both:
//!   - `capsules` (the default): every moving link is a capsule from its frame's origin to
//!     the next link's frame origin (the last link's to the tool frame), with a radius the
//!     scenario sets. Nothing of the URDF's geometry is read.
//!   - `urdf`: the URDF's `<collision>` elements on the moving bodies. Boxes, spheres,
//!     cylinders and capsules are taken as they are; a mesh (STL, binary or ASCII) is replaced
//!     by the convex hull of its vertices (parry's quickhull), which contains the mesh: a
//!     concave link (a fork, a hollow) touches a little earlier than the real one would. The
//!     UR5 and Panda of `example-robot-data` give their collision geometry only as meshes.
//! * The world: boxes, balls, cylinders, convex hulls of points or of an STL mesh, each with a
//!   position and roll–pitch–yaw in the robot's base frame or in the part's
//!   ([`ObstacleFrame`]), fixed or moved on keyframes, each with its own [`ContactLaw`].
//! * The force: at each arm–obstacle pair in penetration, the law's force `f` at the arm's
//!   contact point `p` on link `k`, and `F_e = Σ J_p(q)ᵀ f` with the point's Jacobian
//!   `J_p = [a_j × (p − o_j)]` (revolute joint `j ≤ k`, axis `a_j` through `o_j`) or `[a_j]`
//!   (prismatic). So `F_eᵀq̇ = Σ f·ṗ`: the supply rate of the paper's eqs. (1), (9) is the
//!   contact forces' power.

use super::ContactLaw;
use crate::error::{Result, SimError};
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::PathBuf;

#[cfg(feature = "contact")]
mod world;
#[cfg(feature = "contact")]
pub use world::SpatialWorld;

/// The shape of a 3-D obstacle, in its own frame.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum SpatialShape {
    /// A box with these half extents along its x, y, z (m).
    Box {
        /// Half extents (m).
        half_extents: [f64; 3],
    },
    /// A ball (m).
    Ball {
        /// Radius (m).
        radius: f64,
    },
    /// A cylinder along its z axis, as in URDF (m).
    Cylinder {
        /// Radius (m).
        radius: f64,
        /// Length along z (m).
        length: f64,
    },
    /// The convex hull of these points (m, in the obstacle's frame; at least 4, not all in
    /// one plane).
    Convex {
        /// The points.
        points: Vec<[f64; 3]>,
    },
    /// The convex hull of an STL mesh's vertices (binary or ASCII), in the obstacle's frame.
    Mesh {
        /// The file, relative to the scenario file.
        file: PathBuf,
        /// Scale along x, y, z (default 1; e.g. 0.001 for a mesh in millimetres).
        #[serde(default = "unit_scale")]
        scale: [f64; 3],
    },
}

fn unit_scale() -> [f64; 3] {
    [1.0; 3]
}

/// Where the arm's collision shapes come from (the tool ball is added in both cases).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ArmGeometry {
    /// A capsule along each link's kinematic segment (`link_radius`, `link_radii`).
    #[default]
    Capsules,
    /// The URDF's `<collision>` elements, meshes as their convex hulls (`packages` resolves
    /// `package://` names); `link_radius` and `link_radii` are not used.
    Urdf,
}

/// The frame an obstacle's position, orientation and motion are given in.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ObstacleFrame {
    /// The robot's base frame (the default).
    #[default]
    Base,
    /// The part's frame, `contour.cartesian.part`: a workpiece given where its path is, so
    /// that moving the part moves both.
    Part,
}

impl ObstacleFrame {
    fn is_base(&self) -> bool {
        *self == ObstacleFrame::Base
    }
}

/// A fixed obstacle or workpiece.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpatialObstacle {
    /// Its shape.
    pub shape: SpatialShape,
    /// The frame `position`, `rpy` and `motion` are in (default: the base frame).
    #[serde(default, skip_serializing_if = "ObstacleFrame::is_base")]
    pub frame: ObstacleFrame,
    /// Its frame's origin in `frame` (m).
    pub position: [f64; 3],
    /// Its frame's roll, pitch, yaw in `frame` (rad, URDF's convention
    /// `R = R_z(y) R_y(p) R_x(r)`).
    #[serde(default)]
    pub rpy: [f64; 3],
    /// Its contact law (default: the world's).
    #[serde(default)]
    pub law: Option<ContactLaw>,
    /// Its motion: displacements at keyframes, a smoothstep between them (as in the plane,
    /// [`Keyframe`](super::Keyframe)); empty: fixed.
    #[serde(default)]
    pub motion: Vec<SpatialKeyframe>,
}

/// A keyframe of a 3-D obstacle's motion: at time `t` it is displaced by `offset` (in the
/// obstacle's `frame`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpatialKeyframe {
    /// Time (s).
    pub t: f64,
    /// Displacement from the obstacle's position (m).
    pub offset: [f64; 3],
}

impl SpatialObstacle {
    /// The displacement and velocity of the obstacle at time `t`.
    pub fn motion_at(&self, t: f64) -> (Vector3<f64>, Vector3<f64>) {
        let k = &self.motion;
        super::keyframe_motion(k.len(), |i| (k[i].t, Vector3::from(k[i].offset)), t)
    }
}

/// The 3-D contact of a URDF arm: its collision capsules, the obstacles and the law.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpatialContactSpec {
    /// Where the arm's shapes come from: capsules along the links (default) or the URDF's
    /// `<collision>` elements.
    #[serde(default)]
    pub arm: ArmGeometry,
    /// The directories of the packages that `package://NAME/…` mesh names refer to, by name
    /// (relative to the scenario file), for `arm = "urdf"`.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub packages: BTreeMap<String, PathBuf>,
    /// The radius of every link's capsule (m; 0: links do not collide, only the tool does).
    #[serde(default = "default_link_radius")]
    pub link_radius: f64,
    /// Per-link radii overriding `link_radius`, base to tip (m).
    #[serde(default)]
    pub link_radii: Vec<f64>,
    /// The tool ball's radius (m, > 0).
    #[serde(default = "default_tool_radius")]
    pub tool_radius: f64,
    /// The obstacles and workpieces.
    #[serde(default)]
    pub obstacles: Vec<SpatialObstacle>,
    /// The contact law of obstacles without their own.
    #[serde(default)]
    pub law: ContactLaw,
    /// Scheduling of the nominal speed `r` of (36) on the total normal force (as in the
    /// plane, [`ForceSchedule`](super::ForceSchedule); needs `controller.nominal_speed`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub force_schedule: Option<super::ForceSchedule>,
}

fn default_link_radius() -> f64 {
    0.04
}

fn default_tool_radius() -> f64 {
    0.01
}

pub(crate) fn setting(m: impl Into<String>) -> SimError {
    SimError::Setting(m.into())
}

impl SpatialContactSpec {
    /// The same world with every obstacle in the base frame: those given in the part's frame
    /// placed by `part` (the part's pose in the base frame: their pose composed with it, their
    /// motion's offsets turned by it).
    ///
    /// Errors: `Setting` naming the obstacle when one is in the part's frame and there is no
    /// `part`.
    pub fn in_base_frame(&self, part: Option<&nalgebra::Isometry3<f64>>) -> Result<Self> {
        let mut out = self.clone();
        for (k, o) in out.obstacles.iter_mut().enumerate() {
            if o.frame == ObstacleFrame::Base {
                continue;
            }
            let Some(part) = part else {
                return Err(setting(format!(
                    "contact_3d.obstacles[{k}]: frame = \"part\" needs the part's pose \
                     (contour.cartesian.part)"
                )));
            };
            let local = crate::model::pose::PoseSpec {
                xyz: o.position,
                rpy: o.rpy,
            }
            .isometry(&format!("contact_3d.obstacles[{k}]"))?;
            let placed = part * local;
            let (r, p, y) = placed.rotation.euler_angles();
            o.position = placed.translation.vector.into();
            o.rpy = [r, p, y];
            for key in &mut o.motion {
                key.offset = (part.rotation * Vector3::from(key.offset)).into();
            }
            o.frame = ObstacleFrame::Base;
        }
        Ok(out)
    }

    /// Checks the numbers (radii, shapes, poses, laws) for a robot of `dof` joints.
    pub fn validate(&self, dof: usize) -> Result<()> {
        let finite = |x: &[f64]| x.iter().all(|v| v.is_finite());
        if !(self.link_radius.is_finite() && self.link_radius >= 0.0) {
            return Err(setting("contact_3d.link_radius: finite and ≥ 0 (m)"));
        }
        if !(self.link_radii.is_empty() || self.link_radii.len() == dof) {
            return Err(setting(format!(
                "contact_3d.link_radii: one radius per moving link ({dof}), or none"
            )));
        }
        if !self.link_radii.iter().all(|r| r.is_finite() && *r >= 0.0) {
            return Err(setting("contact_3d.link_radii: each finite and ≥ 0 (m)"));
        }
        if !(self.tool_radius.is_finite() && self.tool_radius > 0.0) {
            return Err(setting("contact_3d.tool_radius: finite and > 0 (m)"));
        }
        self.law.validate()?;
        if let Some(f) = &self.force_schedule {
            f.validate()?;
        }
        for (k, o) in self.obstacles.iter().enumerate() {
            let name = format!("contact_3d.obstacles[{k}]");
            if !(finite(&o.position) && finite(&o.rpy)) {
                return Err(setting(format!("{name}: position and rpy must be finite")));
            }
            let ok = match &o.shape {
                SpatialShape::Box { half_extents } => {
                    finite(half_extents) && half_extents.iter().all(|h| *h > 0.0)
                }
                SpatialShape::Ball { radius } => radius.is_finite() && *radius > 0.0,
                SpatialShape::Cylinder { radius, length } => {
                    radius.is_finite() && *radius > 0.0 && length.is_finite() && *length > 0.0
                }
                SpatialShape::Convex { points } => {
                    points.len() >= 4 && points.iter().all(|p| finite(p))
                }
                SpatialShape::Mesh { scale, .. } => finite(scale) && scale.iter().all(|x| *x > 0.0),
            };
            if !ok {
                return Err(setting(format!("{name}: sizes must be finite and > 0")));
            }
            if let Some(l) = &o.law {
                l.validate()?;
            }
            if !super::keyframes_ok(o.motion.iter().map(|k| (k.t, k.offset))) {
                return Err(setting(format!(
                    "{name}: motion keyframes must be finite, with strictly increasing times"
                )));
            }
        }
        Ok(())
    }
}

/// The contact forces on a URDF arm at one instant.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SpatialContact {
    /// The environment's joint torques `F_e = Σ J_pᵀ f` (N·m, N).
    pub torque: Vec<f64>,
    /// The sum of the contact forces on the arm (N, base frame).
    pub force: Vector3<f64>,
    /// The sum of the normal forces (N).
    pub normal_force: f64,
    /// The deepest penetration (m; 0 without contact).
    pub depth: f64,
    /// The contact points: `(link, point, force)` (the tool is the last link's).
    pub points: Vec<(usize, Vector3<f64>, Vector3<f64>)>,
}
