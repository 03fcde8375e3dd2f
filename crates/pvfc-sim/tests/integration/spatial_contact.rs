//! 3-D contact of a URDF arm (`contact::spatial`): the joint torques `F_e = Σ J_pᵀ f` are the
//! negative gradient of the contact's elastic energy when the law is a pure spring, the point
//! Jacobian is the derivative of the material point, the damping and friction only take
//! energy, and bad settings are errors that name the field.
#![cfg(feature = "contact")]

use nalgebra::Vector3;
use pvfc_sim::contact::spatial::{
    ArmGeometry, ObstacleFrame, SpatialContactSpec, SpatialObstacle, SpatialShape, SpatialWorld,
};
use pvfc_sim::contact::ContactLaw;
use pvfc_sim::model::robot::Robot;
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
        frame: ObstacleFrame::Base,
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
        arm: ArmGeometry::Capsules,
        packages: Default::default(),
        force_schedule: None,
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
                frame: ObstacleFrame::Base,
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
        assert_spring_gradient(&world, k);
    }
}

/// `F_e` at `Q0` equals minus the central-difference gradient of the elastic energy.
fn assert_spring_gradient(world: &SpatialWorld, k: f64) {
    {
        let c = world.contact(0.0, &Q0, &[0.0; 6]).unwrap();
        assert!(!c.points.is_empty() && c.depth > 1e-3, "{c:?}");
        for j in 0..6 {
            let h = 1e-6;
            let (mut qp, mut qm) = (Q0, Q0);
            qp[j] += h;
            qm[j] -= h;
            let grad = (elastic_energy(world, &qp, k) - elastic_energy(world, &qm, k)) / (2.0 * h);
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

/// The UR5 with its URDF's collision meshes as convex hulls (`arm = "urdf"`), the meshes
/// resolved through `packages` as ROS resolves `package://`.
fn urdf_spec(obstacles: Vec<SpatialObstacle>, law: ContactLaw) -> SpatialContactSpec {
    let mut s = spec(obstacles, 0.0, law);
    s.arm = ArmGeometry::Urdf;
    s.packages.insert(
        "example-robot-data".into(),
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../models/example-robot-data"),
    );
    s
}

#[test]
fn the_urdf_meshes_become_convex_hulls_that_obey_the_energy_gradient() {
    let robot = ur5();
    // Six meshes on the moving bodies (shoulder … wrist 3; the base's does not move),
    // ee_link's 1 cm box folded onto wrist 3, and the tool ball.
    let d = robot.description();
    assert_eq!(d.collisions.len(), 7, "{:?}", d.collisions);
    let k = 2.0e4;
    let world = SpatialWorld::new(&urdf_spec(vec![], spring(k)), &robot).unwrap();
    assert_eq!(world.arm_shapes(), 8);
    // A pillar pressed into the forearm's hull (not its capsule: 2 cm beside the segment
    // that a 5 cm capsule would cover, the mesh is there too).
    let poses = robot.link_poses(&Q0).unwrap();
    let mid = (poses[2].translation + poses[3].translation) * 0.5;
    let pillar = |x: f64| SpatialObstacle {
        frame: ObstacleFrame::Base,
        shape: SpatialShape::Cylinder {
            radius: 0.05,
            length: 2.0,
        },
        position: [mid.x + x, mid.y, mid.z],
        rpy: [0.0, 0.0, 0.0],
        law: None,
        motion: vec![],
    };
    // Find where the pillar first touches the hull, then press 3 mm further.
    let touches = |x: f64| {
        let w = SpatialWorld::new(&urdf_spec(vec![pillar(x)], spring(k)), &robot).unwrap();
        !w.contact(0.0, &Q0, &[0.0; 6]).unwrap().points.is_empty()
    };
    let (mut inside, mut outside) = (0.0, 0.3);
    assert!(touches(inside) && !touches(outside));
    for _ in 0..40 {
        let m = 0.5 * (inside + outside);
        if touches(m) {
            inside = m
        } else {
            outside = m
        }
    }
    let world =
        SpatialWorld::new(&urdf_spec(vec![pillar(inside - 0.003)], spring(k)), &robot).unwrap();
    let c = world.contact(0.0, &Q0, &[0.0; 6]).unwrap();
    // 3 mm along x; along the face's normal a little less (the face is not square to x).
    assert!(c.depth > 0.002 && c.depth <= 0.003 + 1e-9, "{c:?}");
    assert_spring_gradient(&world, k);
}

#[test]
fn urdf_collision_primitives_are_placed_on_their_bodies() {
    // A two-joint arm: link1 carries a box and, through a fixed joint, a sphere; link2 a
    // cylinder and a capsule; the base's mesh (a file that does not exist) is never opened.
    let urdf = r#"<robot name="prims">
      <link name="base"><collision><geometry><mesh filename="package://nowhere/base.stl"/></geometry></collision></link>
      <link name="link1">
        <inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
        <collision><origin xyz="0 0 0.2"/><geometry><box size="0.1 0.1 0.4"/></geometry></collision>
      </link>
      <link name="knob"><collision><geometry><sphere radius="0.03"/></geometry></collision></link>
      <link name="link2">
        <inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
        <collision><origin xyz="0.15 0 0" rpy="0 1.5707963267948966 0"/><geometry><cylinder radius="0.04" length="0.3"/></geometry></collision>
        <collision><origin xyz="0.15 0 0.1" rpy="0 1.5707963267948966 0"/><geometry><capsule radius="0.02" length="0.2"/></geometry></collision>
      </link>
      <link name="tip"/>
      <joint name="j1" type="revolute"><parent link="base"/><child link="link1"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="10" velocity="1"/></joint>
      <joint name="knob_fix" type="fixed"><parent link="link1"/><child link="knob"/><origin xyz="0.2 0 0.3"/></joint>
      <joint name="j2" type="revolute"><parent link="link1"/><child link="link2"/><origin xyz="0 0 0.4"/><axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="10" velocity="1"/></joint>
      <joint name="tip_fix" type="fixed"><parent link="link2"/><child link="tip"/><origin xyz="0.3 0 0"/></joint>
    </robot>"#;
    let d = pvfc_sim::urdf::ChainDescription::from_str(
        urdf,
        Path::new("prims.urdf"),
        None,
        Some("tip"),
    )
    .unwrap();
    let robot = Robot::from_description(d).unwrap();
    let bodies: Vec<(usize, &str)> = robot
        .description()
        .collisions
        .iter()
        .map(|c| (c.body, c.link.as_str()))
        .collect();
    assert_eq!(bodies.len(), 4, "{bodies:?}");
    assert!(bodies.contains(&(0, "knob")) && bodies.contains(&(0, "link1")));
    assert_eq!(bodies.iter().filter(|b| **b == (1, "link2")).count(), 2);
    // Each primitive is where the URDF puts it: probe with a small ball obstacle at a point
    // just inside each shape's surface, for q = (0.4, -0.3).
    let q = [0.4, -0.3];
    let poses = robot.link_poses(&q).unwrap();
    let at = |body: usize, p: Vector3<f64>| {
        let pose = &poses[body];
        pose.rotation * p + pose.translation
    };
    let mut s = spec(vec![], 0.0, spring(1e4));
    s.arm = ArmGeometry::Urdf;
    s.tool_radius = 1e-3;
    let probe = |p: Vector3<f64>| {
        let mut s = s.clone();
        s.obstacles = vec![SpatialObstacle {
            frame: ObstacleFrame::Base,
            shape: SpatialShape::Ball { radius: 0.005 },
            position: [p.x, p.y, p.z],
            rpy: [0.0; 3],
            law: None,
            motion: vec![],
        }];
        let w = SpatialWorld::new(&s, &robot).unwrap();
        w.contact(0.0, &q, &[0.0; 2]).unwrap()
    };
    // (body, a point in its frame 4 mm outside a face, the depth expected: 1 mm).
    let cases = [
        (0, Vector3::new(0.054, 0.0, 0.1)), // the box's +x face (half 0.05)
        (0, Vector3::new(0.2, 0.0, 0.3 + 0.034)), // the fixed knob's top (r 0.03)
        (1, Vector3::new(0.15, 0.044, 0.0)), // the cylinder's side (r 0.04, along x)
        (1, Vector3::new(0.27 + 0.004, 0.0, 0.1)), // the capsule's end cap (0.15 + 0.1 + r)
    ];
    for (body, p) in cases {
        let c = probe(at(body, p));
        assert_eq!(c.points.len(), 1, "{body} {p:?}: {c:?}");
        assert!(
            (c.depth - 0.001).abs() < 1e-9,
            "{body} {p:?}: depth {}",
            c.depth
        );
        assert_eq!(c.points[0].0, body);
    }
    // Bad sizes name the link when a contact world uses them; the chain's dynamics still
    // load (a malformed <collision> does not stop a robot that touches nothing). An unknown
    // package names the link, the mesh and the fix.
    let bad = urdf.replace(r#"radius="0.03""#, r#"radius="-0.03""#);
    let d =
        pvfc_sim::urdf::ChainDescription::from_str(&bad, Path::new("p.urdf"), None, Some("tip"))
            .unwrap();
    let e = SpatialWorld::new(&s, &Robot::from_description(d).unwrap())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("link knob <collision>") && e.contains("> 0"),
        "{e}"
    );
    let with_mesh = urdf.replace(
        r#"<link name="knob"><collision><geometry><sphere radius="0.03"/>"#,
        r#"<link name="knob"><collision><geometry><mesh filename="package://tools/knob.stl"/>"#,
    );
    let d = pvfc_sim::urdf::ChainDescription::from_str(
        &with_mesh,
        Path::new("p.urdf"),
        None,
        Some("tip"),
    )
    .unwrap();
    let robot = Robot::from_description(d).unwrap();
    let e = SpatialWorld::new(&s, &robot).unwrap_err().to_string();
    assert!(
        e.contains("link knob")
            && e.contains("package://tools/knob.stl")
            && e.contains("contact_3d.packages"),
        "{e}"
    );
    // Capsules (the default) do not read the URDF's geometry at all.
    s.arm = ArmGeometry::Capsules;
    assert!(SpatialWorld::new(&s, &robot).is_ok());
}

#[test]
fn a_convex_obstacle_of_a_boxs_corners_or_its_stl_file_touches_as_the_box_does() {
    let robot = ur5();
    let table = table_under_tool(&robot, 0.004, 0.01);
    let SpatialShape::Box { half_extents: h } = table.shape else {
        unreachable!()
    };
    let mut corners = vec![];
    for sx in [-1.0, 1.0] {
        for sy in [-1.0, 1.0] {
            for sz in [-1.0, 1.0] {
                corners.push([sx * h[0], sy * h[1], sz * h[2]]);
            }
        }
    }
    let hull = SpatialObstacle {
        frame: ObstacleFrame::Base,
        shape: SpatialShape::Convex { points: corners },
        ..table.clone()
    };
    let v = [0.1, -0.2, 0.3, 0.1, 0.0, 0.2];
    let by = |o: SpatialObstacle| {
        SpatialWorld::new(&spec(vec![o], 0.0, spring(2.0e4)), &robot)
            .unwrap()
            .contact(0.0, &Q0, &v)
            .unwrap()
    };
    // The same box as an ASCII STL file in millimetres (12 triangles), scaled to metres.
    let dir = std::env::temp_dir().join(format!("pvfc-stl-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let SpatialShape::Convex { points } = &hull.shape else {
        unreachable!()
    };
    let mm = |i: usize| points[i].map(|x| x * 1e3);
    let mut stl = String::from("solid box\n");
    // Corner i has bits (x, y, z) = (i >> 2, i >> 1, i) & 1; two triangles per face.
    for f in [
        [0, 1, 3, 2],
        [4, 6, 7, 5],
        [0, 4, 5, 1],
        [2, 3, 7, 6],
        [0, 2, 6, 4],
        [1, 5, 7, 3],
    ] {
        for t in [[f[0], f[1], f[2]], [f[0], f[2], f[3]]] {
            stl.push_str("facet normal 0 0 0\nouter loop\n");
            for i in t {
                let p = mm(i);
                stl.push_str(&format!("vertex {} {} {}\n", p[0], p[1], p[2]));
            }
            stl.push_str("endloop\nendfacet\n");
        }
    }
    stl.push_str("endsolid box\n");
    std::fs::write(dir.join("box.stl"), stl).unwrap();
    let mesh = SpatialObstacle {
        frame: ObstacleFrame::Base,
        shape: SpatialShape::Mesh {
            file: "box.stl".into(),
            scale: [1e-3; 3],
        },
        ..table.clone()
    };
    let from_file = SpatialWorld::new_in(&spec(vec![mesh], 0.0, spring(2.0e4)), &robot, &dir)
        .unwrap()
        .contact(0.0, &Q0, &v)
        .unwrap();
    let (b, c) = (by(table), by(hull));
    assert!((b.depth - c.depth).abs() < 1e-12 && (b.depth - 0.004).abs() < 1e-9);
    for other in [&c, &from_file] {
        for (x, y) in b.torque.iter().zip(&other.torque) {
            assert!((x - y).abs() < 1e-9, "{:?} vs {:?}", b.torque, other.torque);
        }
    }
    // A file that is not there: an I/O error naming it.
    let missing = SpatialObstacle {
        frame: ObstacleFrame::Base,
        shape: SpatialShape::Mesh {
            file: "nowhere.stl".into(),
            scale: [1.0; 3],
        },
        ..table_under_tool(&robot, 0.004, 0.01)
    };
    let e = SpatialWorld::new_in(&spec(vec![missing], 0.0, spring(1.0)), &robot, &dir)
        .unwrap_err()
        .to_string();
    assert!(e.contains("nowhere.stl"), "{e}");
    std::fs::remove_dir_all(&dir).ok();
    // Points in one plane have no hull: an error naming the obstacle.
    let flat = SpatialObstacle {
        frame: ObstacleFrame::Base,
        shape: SpatialShape::Convex {
            points: vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0]],
        },
        ..table_under_tool(&robot, 0.004, 0.01)
    };
    let e = SpatialWorld::new(&spec(vec![flat], 0.0, spring(1.0)), &robot)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("contact_3d.obstacles[0]") && e.contains("convex hull"),
        "{e}"
    );
}
