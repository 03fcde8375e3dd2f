//! The Rapier world: the arm's colliders, moved kinematically from `q`, and the obstacles.

use super::{
    check_state, ContactForces, ContactLaw, ContactPoint, ContactSpec, Environment, ObstacleSpec,
    PlanarArm, RobotPart, ShapeSpec,
};
use crate::error::Result;
use nalgebra::Vector2;
use pvfc_core::lie::Torus;
use pvfc_core::mechanics::ScaraParameters;
use rapier2d_f64::prelude::{
    ActiveCollisionTypes, BroadPhaseBvh, ColliderBuilder, ColliderHandle, ColliderSet,
    CollisionPipeline, Group, InteractionGroups, InteractionTestMode, IslandManager, NarrowPhase,
    Pose, RigidBodySet, Vector,
};

/// The contact layer on Rapier (2-D, f64). The arm's two links are capsules (link 2's ends
/// at the tool's centre) and the tool is a disc at the end effector; they are parentless colliders placed from `q` at every call,
/// and the obstacles are colliders placed from their keyframed motion at `t`. Rapier's
/// collision pipeline (broad phase + narrow phase, no dynamics) finds the contact manifolds
/// between the arm and the world; every contact point with penetration gives a force by the
/// obstacle's [`ContactLaw`], and `F_e = Σ Jᵀf` (see the [module](super) documentation).
///
/// The robot does not collide with itself and obstacles do not collide with each other
/// (collision groups), so the narrow phase only works on robot–world pairs.
pub struct ContactWorld {
    arm: PlanarArm,
    bodies: RigidBodySet,
    colliders: ColliderSet,
    pipeline: CollisionPipeline,
    broad_phase: BroadPhaseBvh,
    narrow_phase: NarrowPhase,
    islands: IslandManager,
    robot: [(ColliderHandle, RobotPart); 3],
    obstacles: Vec<(ColliderHandle, ObstacleSpec, ContactLaw)>,
}

impl std::fmt::Debug for ContactWorld {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ContactWorld")
            .field("arm", &self.arm)
            .field("obstacles", &self.obstacles.len())
            .finish_non_exhaustive()
    }
}

fn vec(v: Vector2<f64>) -> Vector {
    Vector::new(v.x, v.y)
}

fn na(v: Vector) -> Vector2<f64> {
    Vector2::new(v.x, v.y)
}

impl ContactWorld {
    /// Builds the world of `spec` around an arm with the given parameters.
    pub fn new(spec: &ContactSpec, arm: &ScaraParameters<f64>) -> Result<Self> {
        spec.validate()?;
        let arm = PlanarArm::of(arm)?;
        let (l1, l2) = arm.lengths();
        let mut colliders = ColliderSet::new();
        let types = ActiveCollisionTypes::all();
        let robot_groups =
            InteractionGroups::new(Group::GROUP_1, Group::GROUP_2, InteractionTestMode::And);
        let world_groups =
            InteractionGroups::new(Group::GROUP_2, Group::GROUP_1, InteractionTestMode::And);
        let zero = Vector::new(0.0, 0.0);
        let [r1, r2] = spec.link_radius;
        let link = |len: f64, r: f64| {
            ColliderBuilder::capsule_from_endpoints(zero, Vector::new(len, 0.0), r)
                .active_collision_types(types)
                .collision_groups(robot_groups)
                .build()
        };
        // Link 2's capsule ends at the tool's centre; the tool disc protrudes beyond it.
        let link1 = colliders.insert(link(l1, r1));
        let link2 = colliders.insert(link((l2 - r2).max(0.0), r2));
        let tool = colliders.insert(
            ColliderBuilder::ball(spec.tool_radius)
                .active_collision_types(types)
                .collision_groups(robot_groups)
                .build(),
        );
        let obstacles = spec
            .obstacles
            .iter()
            .map(|o| {
                let builder = match o.shape {
                    ShapeSpec::Box {
                        half_extents: [hx, hy],
                    } => ColliderBuilder::cuboid(hx, hy),
                    ShapeSpec::Ball { radius } => ColliderBuilder::ball(radius),
                    ShapeSpec::Capsule { a, b, radius } => ColliderBuilder::capsule_from_endpoints(
                        Vector::new(a[0], a[1]),
                        Vector::new(b[0], b[1]),
                        radius,
                    ),
                };
                let h = colliders.insert(
                    builder
                        .position(Pose::new(
                            Vector::new(o.position[0], o.position[1]),
                            o.angle,
                        ))
                        .active_collision_types(types)
                        .collision_groups(world_groups)
                        .build(),
                );
                (h, o.clone(), o.law.unwrap_or(spec.law))
            })
            .collect();
        Ok(ContactWorld {
            arm,
            bodies: RigidBodySet::new(),
            colliders,
            pipeline: CollisionPipeline::new(),
            broad_phase: BroadPhaseBvh::new(),
            narrow_phase: NarrowPhase::new(),
            islands: IslandManager::new(),
            robot: [
                (link1, RobotPart::Link1),
                (link2, RobotPart::Link2),
                (tool, RobotPart::Tool),
            ],
            obstacles,
        })
    }

    /// The arm's kinematics.
    pub fn arm(&self) -> &PlanarArm {
        &self.arm
    }

    /// Places the colliders for `(t, q)` and runs Rapier's collision detection.
    fn place(&mut self, t: f64, q: &Torus<f64, 2>) {
        let a = q.angles();
        let elbow = self.arm.elbow(q);
        let poses = [
            Pose::new(Vector::new(0.0, 0.0), a[0]),
            Pose::new(vec(elbow), a[0] + a[1]),
            Pose::new(vec(self.arm.tip(q)), a[0] + a[1]),
        ];
        for ((h, _), pose) in self.robot.iter().zip(poses) {
            if let Some(c) = self.colliders.get_mut(*h) {
                c.set_position(pose);
            }
        }
        for (h, o, _) in &self.obstacles {
            if o.motion.is_empty() {
                continue;
            }
            let (d, _) = o.motion_at(t);
            if let Some(c) = self.colliders.get_mut(*h) {
                c.set_position(Pose::new(
                    Vector::new(o.position[0] + d.x, o.position[1] + d.y),
                    o.angle,
                ));
            }
        }
        self.pipeline.step(
            0.0,
            &mut self.islands,
            &mut self.broad_phase,
            &mut self.narrow_phase,
            &mut self.bodies,
            &mut self.colliders,
            &(),
            &(),
        );
    }
}

impl Environment for ContactWorld {
    fn contact(&mut self, t: f64, q: &Torus<f64, 2>, v: &Vector2<f64>) -> Result<ContactForces> {
        check_state(q, v)?;
        self.place(t, q);
        let mut out = ContactForces::default();
        for (rh, part) in self.robot {
            for (oh, o, law) in &self.obstacles {
                let Some(pair) = self.narrow_phase.contact_pair(rh, *oh) else {
                    continue;
                };
                let robot_first = pair.collider1 == rh;
                let (Some(c1), Some(c2)) = (
                    self.colliders.get(pair.collider1),
                    self.colliders.get(pair.collider2),
                ) else {
                    continue;
                };
                let (pose1, pose2) = (*c1.position(), *c2.position());
                let (_, obstacle_velocity) = o.motion_at(t);
                for m in pair.manifolds() {
                    // The manifold's normal points out of collider 1, towards collider 2.
                    let n1 = na(pose1.rotation.transform_vector(m.local_n1));
                    let normal = if robot_first { -n1 } else { n1 };
                    for c in &m.points {
                        if c.dist >= 0.0 {
                            continue;
                        }
                        let p = if robot_first {
                            na(pose1.transform_point(c.local_p1))
                        } else {
                            na(pose2.transform_point(c.local_p2))
                        };
                        let rel = self.arm.point_velocity(part, q, v, &p) - obstacle_velocity;
                        let (force, normal_force) = law.force(-c.dist, &normal, &rel);
                        let point = ContactPoint {
                            part,
                            point: p,
                            force,
                            normal_force,
                            depth: -c.dist,
                        };
                        out.add(&self.arm, q, &point);
                    }
                }
            }
        }
        Ok(out)
    }
}
