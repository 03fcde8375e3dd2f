//! The tool centre point (TCP): the tool pose is the tip link's composed with the TCP, the
//! Jacobian is the derivative of that pose (against finite differences), dynamics and gravity
//! do not change, a second TCP replaces the first, inverse kinematics puts the TCP on its
//! target, and a bad TCP is refused.

use nalgebra::{Matrix3, Vector3};
use proptest::prelude::*;
use pvfc_control::model::robot::Robot;
use pvfc_core::mechanics::Pose;
use std::path::Path;

fn ur5() -> Robot {
    let urdf = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../models/ur5/ur5_robot.urdf");
    Robot::from_urdf(&urdf, None, Some("tool0")).expect("the UR5 reads")
}

/// A deburring cone 120 mm out from the flange, off-axis and tilted.
fn cone() -> Pose<f64> {
    Pose::from_xyz_rpy([0.015, -0.02, 0.12], [0.3, -0.45, 0.8])
}

/// The rotation vector of `r` (log map), for small angles.
fn log(r: &Matrix3<f64>) -> Vector3<f64> {
    let s = r - r.transpose();
    Vector3::new(s[(2, 1)], s[(0, 2)], s[(1, 0)]) / 2.0
}

fn joints() -> impl Strategy<Value = Vec<f64>> {
    proptest::collection::vec(-3.0..3.0f64, 6)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn the_tool_pose_is_the_tip_links_composed_with_the_tcp(q in joints()) {
        let bare = ur5();
        let tool = bare.clone().with_tool(cone()).unwrap();
        let (r0, p0) = bare.tool_pose(&q).unwrap();
        let expected = Pose { rotation: r0, translation: p0 }.compose(&cone());
        let (r, p) = tool.tool_pose(&q).unwrap();
        prop_assert!((r - expected.rotation).amax() < 1e-12);
        prop_assert!((p - expected.translation).amax() < 1e-12);
        // The link poses end with the TCP; the links themselves do not move.
        let links = tool.link_poses(&q).unwrap();
        let bare_links = bare.link_poses(&q).unwrap();
        prop_assert!((links[6].translation - expected.translation).amax() < 1e-12);
        for (a, b) in links[..6].iter().zip(&bare_links[..6]) {
            prop_assert!((a.translation - b.translation).amax() == 0.0);
        }
    }

    #[test]
    fn the_jacobian_is_the_derivative_of_the_tcps_pose(q in joints()) {
        let tool = ur5().with_tool(cone()).unwrap();
        let j = tool.jacobian(&q, true).unwrap();
        let (r, _) = tool.tool_pose(&q).unwrap();
        let h = 1e-6;
        for i in 0..6 {
            let (mut plus, mut minus) = (q.clone(), q.clone());
            plus[i] += h;
            minus[i] -= h;
            let (rp, pp) = tool.tool_pose(&plus).unwrap();
            let (rm, pm) = tool.tool_pose(&minus).unwrap();
            let linear = (pp - pm) / (2.0 * h);
            // The world-frame angular velocity: log(R₊ Rᵀ) and log(R₋ Rᵀ), central.
            let angular = (log(&(rp * r.transpose())) - log(&(rm * r.transpose()))) / (2.0 * h);
            for k in 0..3 {
                prop_assert!((j[(k, i)] - linear[k]).abs() < 1e-8, "linear {k},{i}: {} {}", j[(k, i)], linear[k]);
                prop_assert!((j[(k + 3, i)] - angular[k]).abs() < 1e-8, "angular {k},{i}");
            }
        }
    }

    #[test]
    fn the_tcp_moves_no_mass(q in joints(), v in joints()) {
        let bare = ur5().with_gravity(Vector3::new(0.3, -1.0, -9.7)).unwrap();
        let tool = bare.clone().with_tool(cone()).unwrap();
        prop_assert_eq!(bare.inertia(&q).unwrap(), tool.inertia(&q).unwrap());
        prop_assert_eq!(bare.coriolis(&q, &v).unwrap(), tool.coriolis(&q, &v).unwrap());
        // Gravity is kept through with_tool.
        prop_assert_eq!(bare.gravity(&q).unwrap(), tool.gravity(&q).unwrap());
    }
}

#[test]
fn a_second_tcp_replaces_the_first() {
    let q = [0.1, -1.2, 1.3, -0.4, 0.9, 0.2];
    let once = ur5().with_tool(cone()).unwrap();
    let twice = ur5()
        .with_tool(Pose::from_xyz_rpy([0.0, 0.0, 0.3], [1.0, 0.0, 0.0]))
        .unwrap()
        .with_tool(cone())
        .unwrap();
    assert_eq!(once.tool_pose(&q).unwrap(), twice.tool_pose(&q).unwrap());
    assert_eq!(*twice.tcp(), cone());
    let back = twice.with_tool(Pose::identity()).unwrap();
    assert_eq!(back.tool_pose(&q).unwrap(), ur5().tool_pose(&q).unwrap());
}

#[test]
fn inverse_kinematics_puts_the_tcp_on_its_target() {
    let tool = ur5().with_tool(cone()).unwrap();
    let seed = [0.1, -1.2, 1.3, -0.4, 0.9, 0.2];
    let (r, p) = tool.tool_pose(&[0.2, -1.1, 1.2, -0.5, 1.0, 0.3]).unwrap();
    let q = tool
        .inverse_kinematics(p, Some(r), &seed, 1e-10)
        .expect("reachable");
    let (rq, pq) = tool.tool_pose(q.as_slice()).unwrap();
    assert!((pq - p).amax() < 1e-9, "{}", (pq - p).amax());
    assert!((rq - r).amax() < 1e-8);
}

#[test]
fn a_tcp_that_is_not_a_rigid_transform_is_refused() {
    let mut nan = cone();
    nan.translation[1] = f64::NAN;
    assert!(ur5().with_tool(nan).is_err());
    let mut sheared = cone();
    sheared.rotation[(0, 1)] += 0.1;
    let e = ur5().with_tool(sheared).unwrap_err().to_string();
    assert!(e.contains("tool pose"), "{e}");
}
