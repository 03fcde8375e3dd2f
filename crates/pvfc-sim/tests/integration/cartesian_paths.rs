//! Cartesian tool paths in SE(3) and for redundant arms (`[contour.cartesian]`): with
//! `orientations` every joint waypoint puts the tool at the sampled position *and* the
//! interpolated orientation; with a `rest` posture a 7-joint arm's waypoints stay nearer to
//! it (the null-space pull) while still reaching every point; bad settings are named errors.

use nalgebra::{Rotation3, SVector, UnitQuaternion, Vector3};
use pvfc_sim::model::cartesian::{CartesianSpec, CircleSpec};
use pvfc_sim::model::robot::Robot;
use std::path::Path;

fn robot(path: &str, tip: &str) -> Robot {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(path);
    Robot::from_urdf(&p, None, Some(tip)).unwrap()
}

const UR5_SEED: [f64; 6] = [0.0, -1.2, 1.4, -1.8, -1.57, 0.0];

fn rectangle() -> CartesianSpec {
    CartesianSpec {
        points: vec![
            [0.45, -0.15, 0.30],
            [0.65, -0.15, 0.30],
            [0.65, 0.20, 0.30],
            [0.45, 0.20, 0.30],
        ],
        corner_radius: 0.03,
        samples: 24,
        seed: UR5_SEED.to_vec(),
        ..CartesianSpec::default()
    }
}

#[test]
fn an_se3_path_puts_the_tool_at_its_position_and_orientation() {
    let ur5 = robot("models/ur5/ur5_robot.urdf", "tool0");
    let (seed_rotation, _) = ur5.tool_pose(&UR5_SEED).unwrap();
    // The tool pointing down as at the seed, turned about the vertical by a different angle
    // at each corner (up to 0.4 rad).
    let mut spec = rectangle();
    spec.orientations = [0.0, 0.4, -0.3, 0.2]
        .iter()
        .map(|yaw| {
            let r = Rotation3::from_axis_angle(&Vector3::z_axis(), *yaw)
                * Rotation3::from_matrix_unchecked(seed_rotation);
            let (r, p, y) = r.euler_angles();
            [r, p, y]
        })
        .collect();
    let base = Path::new(".");
    let samples = spec.sample(base).unwrap();
    let wanted = spec.sampled_orientations(&samples).unwrap().unwrap();
    // At a corner's own sample the orientation is the corner's.
    let corner0 = UnitQuaternion::from_euler_angles(
        spec.orientations[0][0],
        spec.orientations[0][1],
        spec.orientations[0][2],
    );
    let q0 = UnitQuaternion::from_matrix(&wanted[0]);
    assert!(
        q0.angle_to(&corner0) < 0.2,
        "the first sample is near corner 0"
    );
    let q = spec.joint_waypoints(&ur5, base).unwrap();
    let mut turned = 0.0f64;
    for (i, qi) in q.iter().enumerate() {
        let (r, p) = ur5.tool_pose(qi).unwrap();
        assert!((p - samples[i]).norm() < 1e-6, "waypoint {i}: position");
        let err = UnitQuaternion::from_matrix(&(r * wanted[i].transpose())).angle();
        assert!(err < 1e-5, "waypoint {i}: orientation off by {err} rad");
        turned = turned.max(UnitQuaternion::from_matrix(&(r * seed_rotation.transpose())).angle());
    }
    assert!(
        turned > 0.3,
        "the orientations are followed, not the seed's: {turned}"
    );
    // Without orientations (position only) the tool's orientation is free and differs.
    let free = rectangle().joint_waypoints(&ur5, base).unwrap();
    assert_ne!(free, q);
}

#[test]
fn bad_orientations_are_named_errors() {
    let ur5 = robot("models/ur5/ur5_robot.urdf", "tool0");
    let base = Path::new(".");
    let err = |spec: &CartesianSpec| spec.joint_waypoints(&ur5, base).unwrap_err().to_string();
    let mut spec = rectangle();
    spec.orientations = vec![[std::f64::consts::PI, 0.0, 0.0]; 3];
    assert!(err(&spec).contains("one (roll, pitch, yaw) per point"));
    spec.orientations = vec![[std::f64::consts::PI, 0.0, 0.0]; 4];
    spec.fixed_orientation = true;
    assert!(err(&spec).contains("give one of orientations, tool_frame and fixed_orientation"));
    spec.fixed_orientation = false;
    spec.orientations[2] = [0.0, 0.0, 0.0]; // half a turn from its neighbours
    assert!(err(&spec).contains("half a turn"), "{}", err(&spec));
    let mut spec = rectangle();
    spec.rest = Some(vec![0.0; 5]);
    assert!(err(&spec).contains("rest"));
}

#[test]
fn a_rest_posture_pulls_a_redundant_arm_in_the_null_space() {
    let panda = robot("models/panda/panda.urdf", "panda_hand_tcp");
    let seed = [0.0, -0.3, 0.0, -2.2, 0.0, 2.0, 0.8];
    let (_, p0) = panda.tool_pose(&seed).unwrap();
    let circle = CartesianSpec {
        circle: Some(CircleSpec {
            center: [p0.x, p0.y + 0.1, p0.z],
            radius: 0.1,
            normal: [0.0, 0.0, 1.0],
            semi_minor: None,
            major_axis: None,
        }),
        samples: 16,
        seed: seed.to_vec(),
        ..CartesianSpec::default()
    };
    // A rest posture away from the seed in the elbow's redundancy (joint 3 turned).
    let rest = [0.0, -0.3, 0.8, -2.2, 0.0, 2.0, 0.8];
    let pulled = CartesianSpec {
        rest: Some(rest.to_vec()),
        rest_gain: Some(0.5),
        ..circle.clone()
    };
    let base = Path::new(".");
    let samples = circle.sample(base).unwrap();
    let distance = |q: &[Vec<f64>]| -> f64 {
        q.iter()
            .map(|qi| (SVector::<f64, 7>::from_column_slice(qi) - SVector::from(rest)).norm())
            .sum::<f64>()
            / q.len() as f64
    };
    let (free, with_rest) = (
        circle.joint_waypoints(&panda, base).unwrap(),
        pulled.joint_waypoints(&panda, base).unwrap(),
    );
    for (q, label) in [(&free, "free"), (&with_rest, "with rest")] {
        for (i, qi) in q.iter().enumerate() {
            let (_, p) = panda.tool_pose(qi).unwrap();
            assert!(
                (p - samples[i]).norm() < 1e-6,
                "{label}: waypoint {i} not reached"
            );
        }
    }
    let (d_free, d_rest) = (distance(&free), distance(&with_rest));
    assert!(
        d_rest < 0.7 * d_free,
        "mean distance to rest: {d_rest:.3} with the pull, {d_free:.3} without"
    );
}

#[test]
fn an_ellipse_in_a_tilted_plane_is_sampled_on_the_ellipse() {
    let (a, b) = (0.12, 0.05);
    let center = Vector3::new(0.5, 0.1, 0.3);
    let normal = Vector3::new(0.0, 0.3, 1.0).normalize();
    let spec = CartesianSpec {
        circle: Some(CircleSpec {
            center: center.into(),
            radius: a,
            normal: normal.into(),
            semi_minor: Some(b),
            major_axis: Some([1.0, 0.0, 0.0]),
        }),
        samples: 32,
        ..CartesianSpec::default()
    };
    let p = spec.sample(Path::new(".")).unwrap();
    // In the plane, on the ellipse (x/a)² + (y/b)² = 1 along the major axis and across it,
    // starting at the end of the major axis, and at equal arc length.
    let u = Vector3::x();
    let w = normal.cross(&u);
    for x in &p {
        let d = x - center;
        assert!(d.dot(&normal).abs() < 1e-12);
        let (xu, xw) = (d.dot(&u) / a, d.dot(&w) / b);
        assert!((xu * xu + xw * xw - 1.0).abs() < 1e-3, "{xu} {xw}");
    }
    assert!((p[0] - (center + u * a)).norm() < 1e-12);
    let steps: Vec<f64> = (0..p.len())
        .map(|i| (p[(i + 1) % p.len()] - p[i]).norm())
        .collect();
    let (lo, hi) = steps
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(l, h), s| (l.min(*s), h.max(*s)));
    // Chords of the arc-length samples: equal to 3 % where the curvature is highest.
    assert!(hi / lo < 1.03, "arc-length spacing: {lo} to {hi}");
    // A major axis along the normal has no direction in the plane.
    let mut bad = spec.clone();
    if let Some(c) = bad.circle.as_mut() {
        c.major_axis = Some(normal.into());
    }
    assert!(bad
        .sample(Path::new("."))
        .unwrap_err()
        .to_string()
        .contains("major_axis"));
}
