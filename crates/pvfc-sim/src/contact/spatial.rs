//! Contact in 3-D for URDF arms, on Rapier's collision layer (`rapier3d-f64`, whose parry3d
//! contact queries give the deepest point, normal and depth of each arm–obstacle pair).
//!
//! * The arm: every moving link is a capsule from its frame's origin to the next link's frame
//!   origin (the last link's to the tool frame), and the tool is a ball at the tool frame.
//!   Meshes are not read. The UR5 and Panda of `example-robot-data` describe their collision
//!   geometry only as meshes, so a capsule along the link's kinematic segment, with a radius
//!   the scenario sets, stands in for each one. This is an approximation: a convex hull of the
//!   mesh would follow the link's real shape.
//! * The world: boxes, balls and cylinders, each with a position and roll–pitch–yaw in the
//!   robot's base frame, fixed, each with its own [`ContactLaw`].
//! * The force: at each arm–obstacle pair in penetration, the law's force `f` at the arm's
//!   contact point `p` on link `k`, and `F_e = Σ J_p(q)ᵀ f` with the point's Jacobian
//!   `J_p = [a_j × (p − o_j)]` (revolute joint `j ≤ k`, axis `a_j` through `o_j`) or `[a_j]`
//!   (prismatic). So `F_eᵀq̇ = Σ f·ṗ`: the supply rate of the paper's eqs. (1), (9) is the
//!   contact forces' power.

use super::ContactLaw;
use crate::error::{Result, SimError};
use crate::robot::Robot;
use nalgebra::{Rotation3, UnitQuaternion, Vector3};
use pvfc_core::lie::JointKind;
use pvfc_core::mechanics::Pose;
use rapier3d_f64::math::{Pose as RPose, Vector as RVector};
use rapier3d_f64::parry::query;
use rapier3d_f64::parry::shape::{Ball, Capsule, Cuboid, Cylinder, Shape};
use serde::{Deserialize, Serialize};

/// The shape of a 3-D obstacle, in its own frame.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
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
}

/// A fixed obstacle or workpiece.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpatialObstacle {
    /// Its shape.
    pub shape: SpatialShape,
    /// Its frame's origin in the robot's base frame (m).
    pub position: [f64; 3],
    /// Its frame's roll, pitch, yaw (rad, URDF's convention `R = R_z(y) R_y(p) R_x(r)`).
    #[serde(default)]
    pub rpy: [f64; 3],
    /// Its contact law (default: the world's).
    #[serde(default)]
    pub law: Option<ContactLaw>,
}

/// The 3-D contact of a URDF arm: its collision capsules, the obstacles and the law.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpatialContactSpec {
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
}

fn default_link_radius() -> f64 {
    0.04
}

fn default_tool_radius() -> f64 {
    0.01
}

fn setting(m: impl Into<String>) -> SimError {
    SimError::Setting(m.into())
}

impl SpatialContactSpec {
    /// Checks the numbers (radii, shapes, poses, laws) for a robot of `dof` joints.
    pub fn validate(&self, dof: usize) -> Result<()> {
        let finite = |x: &[f64]| x.iter().all(|v| v.is_finite());
        if !(self.link_radius.is_finite() && self.link_radius >= 0.0) {
            return Err(setting("contact.link_radius: finite and ≥ 0 (m)"));
        }
        if !(self.link_radii.is_empty() || self.link_radii.len() == dof) {
            return Err(setting(format!(
                "contact.link_radii: one radius per moving link ({dof}), or none"
            )));
        }
        if !self.link_radii.iter().all(|r| r.is_finite() && *r >= 0.0) {
            return Err(setting("contact.link_radii: each finite and ≥ 0 (m)"));
        }
        if !(self.tool_radius.is_finite() && self.tool_radius > 0.0) {
            return Err(setting("contact.tool_radius: finite and > 0 (m)"));
        }
        self.law.validate()?;
        for (k, o) in self.obstacles.iter().enumerate() {
            let name = format!("contact.obstacles[{k}]");
            if !(finite(&o.position) && finite(&o.rpy)) {
                return Err(setting(format!("{name}: position and rpy must be finite")));
            }
            let ok = match o.shape {
                SpatialShape::Box { half_extents } => {
                    finite(&half_extents) && half_extents.iter().all(|h| *h > 0.0)
                }
                SpatialShape::Ball { radius } => radius.is_finite() && radius > 0.0,
                SpatialShape::Cylinder { radius, length } => {
                    radius.is_finite() && radius > 0.0 && length.is_finite() && length > 0.0
                }
            };
            if !ok {
                return Err(setting(format!("{name}: sizes must be finite and > 0")));
            }
            if let Some(l) = &o.law {
                l.validate()?;
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

/// One of the arm's collision shapes, fixed to a link at an offset from its frame.
#[derive(Clone, Debug)]
struct ArmShape {
    link: usize,
    offset: Pose<f64>,
    shape: ShapeKind,
}

#[derive(Clone, Debug)]
enum ShapeKind {
    Capsule(Capsule),
    Ball(Ball),
}

impl ShapeKind {
    fn shape(&self) -> &dyn Shape {
        match self {
            ShapeKind::Capsule(c) => c,
            ShapeKind::Ball(b) => b,
        }
    }
}

/// An obstacle as the queries take it.
#[derive(Clone, Debug)]
struct Obstacle {
    pose: RPose,
    shape: ObstacleShape,
    law: ContactLaw,
}

#[derive(Clone, Debug)]
enum ObstacleShape {
    Box(Cuboid),
    Ball(Ball),
    Cylinder(Cylinder),
}

impl ObstacleShape {
    fn shape(&self) -> &dyn Shape {
        match self {
            ObstacleShape::Box(s) => s,
            ObstacleShape::Ball(s) => s,
            ObstacleShape::Cylinder(s) => s,
        }
    }
}

fn rvec(v: &Vector3<f64>) -> RVector {
    RVector::new(v.x, v.y, v.z)
}

fn na(v: RVector) -> Vector3<f64> {
    Vector3::new(v.x, v.y, v.z)
}

fn rpose(p: &Pose<f64>) -> RPose {
    let q = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(p.rotation));
    RPose::from_parts(
        rvec(&p.translation),
        rapier3d_f64::math::Rotation::from_xyzw(q.i, q.j, q.k, q.w),
    )
}

/// The 3-D contact world of a URDF arm (see the [module](self) documentation).
#[derive(Clone, Debug)]
pub struct SpatialWorld {
    robot: Robot,
    shapes: Vec<ArmShape>,
    obstacles: Vec<Obstacle>,
    /// Per joint: circular (revolute) or linear, and its axis in its link's frame.
    joints: Vec<(JointKind, Vector3<f64>)>,
}

impl SpatialWorld {
    /// The world of `spec` around `robot`.
    pub fn new(spec: &SpatialContactSpec, robot: &Robot) -> Result<Self> {
        let n = robot.dof();
        spec.validate(n)?;
        // Each link's segment, from its frame's origin to the next frame's, in its own frame
        // (constant: the next joint's origin is fixed in this link).
        let poses = robot.link_poses(&vec![0.0; n])?;
        let mut shapes = Vec::new();
        for k in 0..n {
            let radius = spec.link_radii.get(k).copied().unwrap_or(spec.link_radius);
            let next = poses[k].inverse().compose(&poses[k + 1]).translation;
            if radius > 0.0 && next.norm() > 1e-9 {
                shapes.push(ArmShape {
                    link: k,
                    offset: Pose::identity(),
                    shape: ShapeKind::Capsule(Capsule::new(RVector::ZERO, rvec(&next), radius)),
                });
            }
        }
        // The tool ball, on the last link at the tool frame's origin.
        let tool = poses[n - 1].inverse().compose(&poses[n]).translation;
        shapes.push(ArmShape {
            link: n - 1,
            offset: Pose {
                rotation: nalgebra::Matrix3::identity(),
                translation: tool,
            },
            shape: ShapeKind::Ball(Ball::new(spec.tool_radius)),
        });
        let obstacles = spec
            .obstacles
            .iter()
            .map(|o| {
                let r = Rotation3::from_euler_angles(o.rpy[0], o.rpy[1], o.rpy[2]);
                let mut pose = Pose {
                    rotation: *r.matrix(),
                    translation: Vector3::from(o.position),
                };
                let shape = match o.shape {
                    SpatialShape::Box { half_extents } => {
                        ObstacleShape::Box(Cuboid::new(RVector::from_array(half_extents)))
                    }
                    SpatialShape::Ball { radius } => ObstacleShape::Ball(Ball::new(radius)),
                    SpatialShape::Cylinder { radius, length } => {
                        // parry's cylinder runs along its y axis: turn it onto z.
                        let y_to_z = Rotation3::from_axis_angle(
                            &Vector3::x_axis(),
                            std::f64::consts::FRAC_PI_2,
                        );
                        pose.rotation *= y_to_z.matrix();
                        ObstacleShape::Cylinder(Cylinder::new(0.5 * length, radius))
                    }
                };
                Obstacle {
                    pose: rpose(&pose),
                    shape,
                    law: o.law.unwrap_or(spec.law),
                }
            })
            .collect();
        let joints = robot
            .description()
            .joints
            .iter()
            .map(|j| (j.joint.kind, j.joint.axis))
            .collect();
        Ok(SpatialWorld {
            robot: robot.clone(),
            shapes,
            obstacles,
            joints,
        })
    }

    /// The number of the arm's collision shapes (capsules of the links with a radius, and the
    /// tool).
    pub fn arm_shapes(&self) -> usize {
        self.shapes.len()
    }

    /// The Jacobian of a point `p` (base frame) fixed to link `k`, column by column: the
    /// velocity of that material point per unit speed of each joint.
    pub fn point_jacobian(
        &self,
        poses: &[Pose<f64>],
        k: usize,
        p: &Vector3<f64>,
    ) -> Vec<Vector3<f64>> {
        self.joints
            .iter()
            .enumerate()
            .map(|(j, (kind, axis))| {
                if j > k {
                    return Vector3::zeros();
                }
                let a = poses[j].rotation * axis;
                match kind {
                    JointKind::Circular => a.cross(&(p - poses[j].translation)),
                    JointKind::Linear => a,
                }
            })
            .collect()
    }

    /// The contact forces at `(q, q̇)`.
    pub fn contact(&self, q: &[f64], v: &[f64]) -> Result<SpatialContact> {
        let n = self.robot.dof();
        if v.len() != n {
            return Err(setting(format!(
                "contact: {} velocities for {n} joints",
                v.len()
            )));
        }
        if !(q.iter().chain(v).all(|x| x.is_finite())) {
            return Err(SimError::Core(pvfc_core::Error::new(
                pvfc_core::ErrorKind::NonFinite,
                "contact: the arm's state is not finite",
            )));
        }
        let poses = self.robot.link_poses(q)?;
        let mut out = SpatialContact {
            torque: vec![0.0; n],
            ..Default::default()
        };
        for s in &self.shapes {
            let pose = rpose(&poses[s.link].compose(&s.offset));
            for o in &self.obstacles {
                let c = query::contact(&pose, s.shape.shape(), &o.pose, o.shape.shape(), 0.0)
                    .map_err(|e| setting(format!("contact query: {e:?}")))?;
                let Some(c) = c else { continue };
                let depth = -c.dist;
                if depth <= 0.0 {
                    continue;
                }
                // The arm's point, and the normal from the obstacle into the arm.
                let p = na(c.point1);
                let normal = -na(c.normal1);
                let jac = self.point_jacobian(&poses, s.link, &p);
                let velocity: Vector3<f64> = jac.iter().zip(v).map(|(col, qd)| col * *qd).sum();
                let (f, f_n) = o.law.force(depth, &normal, &velocity);
                for (t, col) in out.torque.iter_mut().zip(&jac) {
                    *t += col.dot(&f);
                }
                out.force += f;
                out.normal_force += f_n;
                out.depth = out.depth.max(depth);
                out.points.push((s.link, p, f));
            }
        }
        Ok(out)
    }
}
