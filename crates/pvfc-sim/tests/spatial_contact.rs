//! 3-D contact of a URDF arm (`contact::spatial`): the joint torques `F_e = Σ J_pᵀ f` are the
//! negative gradient of the contact's elastic energy when the law is a pure spring, the point
//! Jacobian is the derivative of the material point, the damping and friction only take
//! energy, and bad settings are errors that name the field.
#![cfg(feature = "contact")]

use nalgebra::Vector3;
use pvfc_sim::contact::spatial::{SpatialContactSpec, SpatialObstacle, SpatialShape, SpatialWorld};
use pvfc_sim::contact::ContactLaw;
use pvfc_sim::robot::Robot;
use std::path::Path;

fn ur5() -> Robot {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../models/ur5/ur5_robot.urdf");
    Robot::from_urdf(&p, None, Some("tool0")).unwrap()
}

const Q0: [f64; 6] = [0.3, -1.2, 1.4, -1.8, -1.57, 0.2];

fn spring(k: f64) -> ContactLaw {
    ContactLaw {
        stiffness: k,
        damping: 0.0,
        friction: 0.0,
        slip_velocity: 0.01,
    }
}

/// A table under the tool whose top face is `depth` above the tool ball's lowest point.
fn table_under_tool(robot: &Robot, depth: f64, tool_radius: f64) -> SpatialObstacle {
    let (_, p) = robot.tool_pose(&Q0).unwrap();
    let top = p.z - tool_radius + depth;
    SpatialObstacle {
        shape: SpatialShape::Box {
            half_extents: [0.3, 0.3, 0.05],
        },
        position: [p.x, p.y, top - 0.05],
        rpy: [0.0, 0.0, 0.0],
        law: None,
        motion: vec![],
    }
}

fn spec(obstacles: Vec<SpatialObstacle>, link_radius: f64, law: ContactLaw) -> SpatialContactSpec {
    SpatialContactSpec {
        link_radius,
        link_radii: vec![],
        tool_radius: 0.01,
        obstacles,
        law,
    }
}

/// The elastic energy `Σ ½ k d²` of a pure-spring contact, from its forces `|f| = k d`.
fn elastic_energy(world: &SpatialWorld, q: &[f64], k: f64) -> f64 {
    let c = world.contact(0.0, q, &[0.0; 6]).unwrap();
    c.points
        .iter()
        .map(|(_, _, f)| f.norm_squared() / (2.0 * k))
        .sum()
}

#[test]
fn a_spring_contact_pushes_down_its_energy_gradient() {
    let robot = ur5();
    let k = 2.0e4;
    for (link_radius, obstacle) in [
        // The tool ball on a table.
        (0.0, table_under_tool(&robot, 0.004, 0.01)),
        // A vertical pillar through the forearm: capsules against a cylinder.
        (0.05, {
            let poses = robot.link_poses(&Q0).unwrap();
            let mid = (poses[2].translation + poses[3].translation) * 0.5;
            SpatialObstacle {
                shape: SpatialShape::Cylinder {
                    radius: 0.05,
                    length: 2.0,
                },
                position: [mid.x + 0.08, mid.y, mid.z],
                rpy: [0.0, 0.0, 0.0],
                law: None,
                motion: vec![],
            }
        }),
    ] {
        let world =
            SpatialWorld::new(&spec(vec![obstacle], link_radius, spring(k)), &robot).unwrap();
        let c = world.contact(0.0, &Q0, &[0.0; 6]).unwrap();
        assert!(!c.points.is_empty() && c.depth > 1e-3, "{c:?}");
        for j in 0..6 {
            let h = 1e-6;
            let (mut qp, mut qm) = (Q0, Q0);
            qp[j] += h;
            qm[j] -= h;
            let grad =
                (elastic_energy(&world, &qp, k) - elastic_energy(&world, &qm, k)) / (2.0 * h);
            let scale = c.torque.iter().fold(1.0_f64, |m, t| m.max(t.abs()));
            assert!(
                (c.torque[j] + grad).abs() < 1e-5 * scale,
                "joint {j}: F_e = {}, −∂V/∂q = {}",
                c.torque[j],
                -grad
            );
        }
    }
}

#[test]
fn the_table_pushes_the_tool_up_with_the_spring_force() {
    let robot = ur5();
    let world = SpatialWorld::new(
        &spec(
            vec![table_under_tool(&robot, 0.004, 0.01)],
            0.0,
            spring(2.0e4),
        ),
        &robot,
    )
    .unwrap();
    let c = world.contact(0.0, &Q0, &[0.0; 6]).unwrap();
    assert_eq!(c.points.len(), 1);
    assert!((c.depth - 0.004).abs() < 1e-9, "{}", c.depth);
    assert!((c.normal_force - 80.0).abs() < 1e-5);
    assert!((c.force - Vector3::new(0.0, 0.0, 80.0)).norm() < 1e-5);
    // Lifted clear of the table: no contact.
    let mut up = Q0;
    up[1] -= 0.1;
    assert!(world
        .contact(0.0, &up, &[0.0; 6])
        .unwrap()
        .points
        .is_empty());
}

#[test]
fn the_point_jacobian_is_the_material_points_derivative() {
    let robot = ur5();
    let world = SpatialWorld::new(&spec(vec![], 0.04, spring(1e4)), &robot).unwrap();
    let qd = [0.3, -0.7, 0.5, 1.1, -0.4, 0.9];
    let poses = robot.link_poses(&Q0).unwrap();
    for k in 0..6 {
        let p = poses[k].translation + poses[k].rotation * Vector3::new(0.03, -0.02, 0.05);
        let local = poses[k].inverse().transform_point(&p);
        let jac = world.point_jacobian(&poses, k, &p);
        let v: Vector3<f64> = jac.iter().zip(&qd).map(|(c, x)| c * *x).sum();
        let at = |s: f64| {
            let q: Vec<f64> = Q0.iter().zip(&qd).map(|(q, d)| q + s * d).collect();
            robot.link_poses(&q).unwrap()[k].transform_point(&local)
        };
        let h = 1e-6;
        let fd = (at(h) - at(-h)) / (2.0 * h);
        assert!((v - fd).norm() < 1e-8, "link {k}: {v} vs {fd}");
    }
}

#[test]
fn damping_and_friction_only_take_energy() {
    // Power of the contact on the arm ≤ −dV/dt for any velocity: Hunt–Crossley damping and
    // Coulomb friction dissipate.
    let robot = ur5();
    let k = 2.0e4;
    let law = ContactLaw {
        stiffness: k,
        damping: 2.0,
        friction: 0.5,
        slip_velocity: 0.01,
    };
    let lossy = SpatialWorld::new(
        &spec(vec![table_under_tool(&robot, 0.004, 0.01)], 0.0, law),
        &robot,
    )
    .unwrap();
    let elastic = SpatialWorld::new(
        &spec(vec![table_under_tool(&robot, 0.004, 0.01)], 0.0, spring(k)),
        &robot,
    )
    .unwrap();
    let mut seed = 7u64;
    let mut next = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    for _ in 0..50 {
        let qd: Vec<f64> = (0..6).map(|_| next()).collect();
        let c = lossy.contact(0.0, &Q0, &qd).unwrap();
        let power: f64 = c.torque.iter().zip(&qd).map(|(t, v)| t * v).sum();
        let h = 1e-6;
        let shift = |s: f64| -> Vec<f64> { Q0.iter().zip(&qd).map(|(q, v)| q + s * v).collect() };
        let dv = (elastic_energy(&elastic, &shift(h), k) - elastic_energy(&elastic, &shift(-h), k))
            / (2.0 * h);
        assert!(power <= -dv + 1e-6, "power {power} > −dV/dt {}", -dv);
    }
}

#[test]
fn bad_settings_name_the_field() {
    let robot = ur5();
    let mut s = spec(
        vec![table_under_tool(&robot, 0.004, 0.01)],
        0.04,
        ContactLaw::default(),
    );
    let err = |s: &SpatialContactSpec| SpatialWorld::new(s, &robot).unwrap_err().to_string();
    s.tool_radius = 0.0;
    assert!(err(&s).contains("tool_radius"));
    s.tool_radius = 0.01;
    s.link_radii = vec![0.05; 5];
    assert!(err(&s).contains("link_radii"));
    s.link_radii = vec![];
    s.obstacles[0].shape = SpatialShape::Ball { radius: -1.0 };
    assert!(err(&s).contains("obstacles[0]"));
    s.obstacles[0].shape = SpatialShape::Ball { radius: 0.1 };
    s.obstacles[0].position[2] = f64::NAN;
    assert!(err(&s).contains("obstacles[0]"));
    s.obstacles[0].position[2] = 0.0;
    let world = SpatialWorld::new(&s, &robot).unwrap();
    assert!(world.contact(0.0, &[f64::NAN; 6], &[0.0; 6]).is_err());
    assert!(world.contact(0.0, &Q0, &[0.0; 5]).is_err());
}

#[test]
fn a_moving_obstacle_is_where_its_keyframes_put_it_and_its_speed_counts() {
    use pvfc_sim::contact::spatial::SpatialKeyframe;
    let robot = ur5();
    let k = 2.0e4;
    let c = 2.0;
    let law = ContactLaw {
        stiffness: k,
        damping: c,
        friction: 0.0,
        slip_velocity: 0.01,
    };
    // A table 1 mm below touching that rises by 5 mm between t = 1 and t = 2 s.
    let mut moving = table_under_tool(&robot, -0.001, 0.01);
    moving.motion = vec![
        SpatialKeyframe {
            t: 1.0,
            offset: [0.0; 3],
        },
        SpatialKeyframe {
            t: 2.0,
            offset: [0.0, 0.0, 0.005],
        },
    ];
    let world = SpatialWorld::new(&spec(vec![moving.clone()], 0.0, law), &robot).unwrap();
    assert!(world
        .contact(0.5, &Q0, &[0.0; 6])
        .unwrap()
        .points
        .is_empty());
    // Mid-way (t = 1.5 s): displaced by 2.5 mm (depth 1.5 mm), rising at 7.5 mm/s.
    let (offset, speed) = moving.motion_at(1.5);
    assert!((offset.z - 0.0025).abs() < 1e-15 && (speed.z - 0.0075).abs() < 1e-15);
    let at = world.contact(1.5, &Q0, &[0.0; 6]).unwrap();
    assert!((at.depth - 0.0015).abs() < 1e-9, "{}", at.depth);
    // Hunt–Crossley with the table's speed as the depth rate: f = k d (1 + c ḋ).
    let expected = k * 0.0015 * (1.0 + c * 0.0075);
    assert!(
        (at.normal_force - expected).abs() < 1e-6,
        "{} vs {expected}",
        at.normal_force
    );
    // At rest at the end (t = 3 s): depth 4 mm, a pure spring.
    let end = world.contact(3.0, &Q0, &[0.0; 6]).unwrap();
    assert!((end.normal_force - k * 0.004).abs() < 1e-6);
    // Keyframes out of order are an error naming the obstacle.
    let mut bad = moving;
    bad.motion.reverse();
    assert!(SpatialWorld::new(&spec(vec![bad], 0.0, law), &robot)
        .unwrap_err()
        .to_string()
        .contains("obstacles[0]"));
}
