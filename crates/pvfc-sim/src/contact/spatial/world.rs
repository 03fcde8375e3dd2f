//! The 3-D contact world on Rapier's collision layer (feature `contact`).

use super::{setting, SpatialContact, SpatialContactSpec, SpatialShape};
use crate::contact::ContactLaw;
use crate::error::{Result, SimError};
use crate::robot::Robot;
use nalgebra::{Rotation3, UnitQuaternion, Vector3};
use pvfc_core::lie::JointKind;
use pvfc_core::mechanics::Pose;
use rapier3d_f64::math::{Pose as RPose, Vector as RVector};
use rapier3d_f64::parry::query;
use rapier3d_f64::parry::shape::{Ball, Capsule, Cuboid, Cylinder, Shape};

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

/// An obstacle as the queries take it: its pose at rest, its shape, law and motion.
#[derive(Clone, Debug)]
struct Obstacle {
    pose: Pose<f64>,
    shape: ObstacleShape,
    law: ContactLaw,
    spec: super::SpatialObstacle,
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

/// The 3-D contact world of a URDF arm (see the [module](super) documentation).
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
                    pose,
                    shape,
                    law: o.law.unwrap_or(spec.law),
                    spec: o.clone(),
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

    /// The contact forces at time `t` (the obstacles' motion) and `(q, q̇)`.
    pub fn contact(&self, t: f64, q: &[f64], v: &[f64]) -> Result<SpatialContact> {
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
        let obstacles: Vec<(RPose, Vector3<f64>)> = self
            .obstacles
            .iter()
            .map(|o| {
                let (offset, velocity) = o.spec.motion_at(t);
                let mut pose = o.pose;
                pose.translation += offset;
                (rpose(&pose), velocity)
            })
            .collect();
        for s in &self.shapes {
            let pose = rpose(&poses[s.link].compose(&s.offset));
            for (o, (o_pose, o_velocity)) in self.obstacles.iter().zip(&obstacles) {
                let c = query::contact(&pose, s.shape.shape(), o_pose, o.shape.shape(), 0.0)
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
                let (f, f_n) = o.law.force(depth, &normal, &(velocity - o_velocity));
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
