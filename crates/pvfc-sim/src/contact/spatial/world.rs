//! The 3-D contact world on Rapier's collision layer (feature `contact`).

use super::{setting, ArmGeometry, SpatialContact, SpatialContactSpec, SpatialShape};
use crate::contact::ContactLaw;
use crate::error::{Result, SimError};
use crate::model::robot::Robot;
use crate::urdf::collision::{resolve_mesh, CollisionGeometry, LinkCollision};
use nalgebra::{Rotation3, UnitQuaternion, Vector3};
use pvfc_core::lie::JointKind;
use pvfc_core::mechanics::Pose;
use rapier3d_f64::math::{Pose as RPose, Vector as RVector};
use rapier3d_f64::parry::query;
use rapier3d_f64::parry::shape::{Ball, Capsule, ConvexPolyhedron, Cuboid, Cylinder, Shape};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// One of the arm's collision shapes, fixed to a link at an offset from its frame.
#[derive(Clone, Debug)]
struct ArmShape {
    link: usize,
    offset: Pose<f64>,
    shape: Solid,
    /// A sphere around it (centre in the shape's frame, radius), to skip the exact query of
    /// a pair whose spheres are apart.
    bound: Bound,
}

/// A sphere around a shape: its centre in the shape's frame, and its radius.
#[derive(Clone, Copy, Debug)]
struct Bound {
    center: Vector3<f64>,
    radius: f64,
}

impl Bound {
    fn of(shape: &Solid) -> Self {
        let b = shape.shape().compute_local_bounding_sphere();
        Bound {
            center: na(b.center()),
            radius: b.radius(),
        }
    }

    /// Its centre in the base frame, the shape's frame at `pose`.
    fn center_at(&self, pose: &Pose<f64>) -> Vector3<f64> {
        pose.rotation * self.center + pose.translation
    }
}

/// A shape as parry's queries take it.
#[derive(Clone, Debug)]
enum Solid {
    Capsule(Capsule),
    Ball(Ball),
    Cuboid(Cuboid),
    Cylinder(Cylinder),
    Convex(ConvexPolyhedron),
}

impl Solid {
    fn shape(&self) -> &dyn Shape {
        match self {
            Solid::Capsule(s) => s,
            Solid::Ball(s) => s,
            Solid::Cuboid(s) => s,
            Solid::Cylinder(s) => s,
            Solid::Convex(s) => s,
        }
    }

    /// A URDF-style solid along z (cylinder, capsule: parry's run along y), placed at `pose`:
    /// the solid and the pose of parry's frame.
    fn along_z(solid: Solid, pose: Pose<f64>) -> (Solid, Pose<f64>) {
        let y_to_z = Rotation3::from_axis_angle(&Vector3::x_axis(), std::f64::consts::FRAC_PI_2);
        let mut pose = pose;
        pose.rotation *= y_to_z.matrix();
        (solid, pose)
    }

    /// An obstacle's shape at `pose` (its frame in the base frame); mesh files relative to
    /// `base_dir`.
    fn obstacle(
        shape: &SpatialShape,
        pose: Pose<f64>,
        name: &str,
        base_dir: &Path,
    ) -> Result<(Solid, Pose<f64>)> {
        Ok(match shape {
            SpatialShape::Box { half_extents } => (
                Solid::Cuboid(Cuboid::new(RVector::from_array(*half_extents))),
                pose,
            ),
            SpatialShape::Ball { radius } => (Solid::Ball(Ball::new(*radius)), pose),
            SpatialShape::Cylinder { radius, length } => {
                Self::along_z(Solid::Cylinder(Cylinder::new(0.5 * length, *radius)), pose)
            }
            SpatialShape::Convex { points } => {
                let points: Vec<RVector> = points.iter().map(|p| RVector::from_array(*p)).collect();
                (Self::hull(&points, name)?, pose)
            }
            SpatialShape::Mesh { file, scale } => {
                let path = base_dir.join(file);
                let what = format!("{name}: mesh {}", path.display());
                (
                    Self::hull(&stl_vertices(&path, scale, &what)?, &what)?,
                    pose,
                )
            }
        })
    }

    /// The convex hull of `points`; `what` names them in the error.
    fn hull(points: &[RVector], what: &str) -> Result<Solid> {
        if !spans_space(points) {
            return Err(setting(format!(
                "{what}: its {} points have no convex hull with a volume (all in one plane?)",
                points.len()
            )));
        }
        ConvexPolyhedron::from_convex_hull(points)
            .map(Solid::Convex)
            .ok_or_else(|| {
                setting(format!(
                    "{what}: no convex hull of its {} points (all in one plane?)",
                    points.len()
                ))
            })
    }

    /// A URDF `<collision>` element at `origin` on its body: the solid and its offset.
    fn collision(
        c: &LinkCollision,
        urdf_dir: &Path,
        packages: &BTreeMap<String, PathBuf>,
    ) -> Result<(Solid, Pose<f64>)> {
        c.geometry.check(&c.link)?;
        Ok(match &c.geometry {
            CollisionGeometry::Box { size } => (
                Solid::Cuboid(Cuboid::new(RVector::from_array(*size) * 0.5)),
                c.origin,
            ),
            CollisionGeometry::Sphere { radius } => (Solid::Ball(Ball::new(*radius)), c.origin),
            CollisionGeometry::Cylinder { radius, length } => Self::along_z(
                Solid::Cylinder(Cylinder::new(0.5 * length, *radius)),
                c.origin,
            ),
            CollisionGeometry::Capsule { radius, length } => (
                Solid::Capsule(Capsule::new_z(0.5 * length, *radius)),
                c.origin,
            ),
            CollisionGeometry::Mesh { filename, scale } => {
                let path = resolve_mesh(filename, &c.link, urdf_dir, packages)?;
                let what = format!("link {}: mesh {}", c.link, path.display());
                (
                    Self::hull(&stl_vertices(&path, scale, &what)?, &what)?,
                    c.origin,
                )
            }
        })
    }
}

/// The vertices of an STL file (binary or ASCII), scaled; `what` names it in errors.
fn stl_vertices(path: &Path, scale: &[f64; 3], what: &str) -> Result<Vec<RVector>> {
    let file = std::fs::File::open(path).map_err(|e| SimError::io(path, e))?;
    let mesh = stl_io::read_stl(&mut std::io::BufReader::new(file))
        .map_err(|e| setting(format!("{what}: not a readable STL file: {e}")))?;
    Ok(mesh
        .vertices
        .iter()
        .map(|v| {
            RVector::new(
                f64::from(v[0]) * scale[0],
                f64::from(v[1]) * scale[1],
                f64::from(v[2]) * scale[2],
            )
        })
        .collect())
}

/// Whether `points` are not all in one plane: the farthest point from the first, the farthest
/// from their line, and the farthest from their plane are each a millionth of the extent away.
fn spans_space(points: &[RVector]) -> bool {
    let Some(&p0) = points.first() else {
        return false;
    };
    let farthest = |f: &dyn Fn(RVector) -> f64| {
        points
            .iter()
            .map(|&p| (f(p), p))
            .fold((0.0, p0), |a, b| if b.0 > a.0 { b } else { a })
    };
    let (extent, p1) = farthest(&|p| (p - p0).length());
    let axis = (p1 - p0).normalize_or_zero();
    let (_, p2) = farthest(&|p| (p - p0).cross(axis).length());
    let normal = axis.cross(p2 - p0).normalize_or_zero();
    let (height, _) = farthest(&|p| (p - p0).dot(normal).abs());
    extent > 0.0 && height > 1e-6 * extent
}

/// An obstacle as the queries take it: its pose at rest, its shape, law and motion.
#[derive(Clone, Debug)]
struct Obstacle {
    pose: Pose<f64>,
    shape: Solid,
    bound: Bound,
    law: ContactLaw,
    spec: super::SpatialObstacle,
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
    /// The world of `spec` around `robot`, with `package://` directories relative to the
    /// working directory (see [`new_in`](Self::new_in)).
    pub fn new(spec: &SpatialContactSpec, robot: &Robot) -> Result<Self> {
        Self::new_in(spec, robot, Path::new("."))
    }

    /// The world of `spec` around `robot`; the directories of `spec.packages` are relative to
    /// `base_dir` (the scenario file's directory).
    pub fn new_in(spec: &SpatialContactSpec, robot: &Robot, base_dir: &Path) -> Result<Self> {
        let n = robot.dof();
        spec.validate(n)?;
        if let Some(k) = spec
            .obstacles
            .iter()
            .position(|o| o.frame != super::ObstacleFrame::Base)
        {
            return Err(setting(format!(
                "contact_3d.obstacles[{k}]: in the part's frame; place it first \
                 (SpatialContactSpec::in_base_frame)"
            )));
        }
        // Each link's segment, from its frame's origin to the next frame's, in its own frame
        // (constant: the next joint's origin is fixed in this link).
        let poses = robot.link_poses(&vec![0.0; n])?;
        let mut shapes = Vec::new();
        match spec.arm {
            ArmGeometry::Capsules => {
                for k in 0..n {
                    let radius = spec.link_radii.get(k).copied().unwrap_or(spec.link_radius);
                    let next = poses[k].inverse().compose(&poses[k + 1]).translation;
                    if radius > 0.0 && next.norm() > 1e-9 {
                        let capsule = Capsule::new(RVector::ZERO, rvec(&next), radius);
                        let shape = Solid::Capsule(capsule);
                        shapes.push(ArmShape {
                            link: k,
                            offset: Pose::identity(),
                            bound: Bound::of(&shape),
                            shape,
                        });
                    }
                }
            }
            ArmGeometry::Urdf => {
                let d = robot.description();
                let packages: BTreeMap<String, PathBuf> = spec
                    .packages
                    .iter()
                    .map(|(name, dir)| (name.clone(), base_dir.join(dir)))
                    .collect();
                for c in &d.collisions {
                    let (shape, offset) = Solid::collision(c, &d.urdf_dir, &packages)?;
                    shapes.push(ArmShape {
                        link: c.body,
                        offset,
                        bound: Bound::of(&shape),
                        shape,
                    });
                }
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
            bound: Bound {
                center: Vector3::zeros(),
                radius: spec.tool_radius,
            },
            shape: Solid::Ball(Ball::new(spec.tool_radius)),
        });
        let obstacles = spec
            .obstacles
            .iter()
            .enumerate()
            .map(|(k, o)| {
                let r = Rotation3::from_euler_angles(o.rpy[0], o.rpy[1], o.rpy[2]);
                let at = Pose {
                    rotation: *r.matrix(),
                    translation: Vector3::from(o.position),
                };
                let name = format!("contact_3d.obstacles[{k}]");
                let (shape, pose) = Solid::obstacle(&o.shape, at, &name, base_dir)?;
                Ok(Obstacle {
                    pose,
                    bound: Bound::of(&shape),
                    shape,
                    law: o.law.unwrap_or(spec.law),
                    spec: o.clone(),
                })
            })
            .collect::<Result<Vec<_>>>()?;
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

    /// The number of the arm's collision shapes (the links' capsules or the URDF's elements,
    /// and the tool ball).
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
        let obstacles: Vec<(RPose, Vector3<f64>, Vector3<f64>)> = self
            .obstacles
            .iter()
            .map(|o| {
                let (offset, velocity) = o.spec.motion_at(t);
                let mut pose = o.pose;
                pose.translation += offset;
                (rpose(&pose), velocity, o.bound.center_at(&pose))
            })
            .collect();
        for s in &self.shapes {
            let at = poses[s.link].compose(&s.offset);
            let center = s.bound.center_at(&at);
            let pose = rpose(&at);
            for (o, (o_pose, o_velocity, o_center)) in self.obstacles.iter().zip(&obstacles) {
                // Apart (the spheres, then the shape's sphere from the obstacle itself): no
                // contact; the exact query would say so, at more cost.
                if (center - o_center).norm() > s.bound.radius + o.bound.radius
                    || o.shape
                        .shape()
                        .distance_to_point(o_pose, rvec(&center), true)
                        > s.bound.radius
                {
                    continue;
                }
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
