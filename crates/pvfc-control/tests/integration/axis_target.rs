//! Inverse kinematics to an axis (`IkTarget::Axis`): the tool's origin on its point and its
//! `z` axis along the target's, the roll about it free, on the UR5 from random postures; the
//! roll is left where the seed puts it (not asked for); bad targets are refused.

use nalgebra::{SVector, Vector3};
use proptest::prelude::*;
use pvfc_control::model::robot::Robot;
use pvfc_core::mechanics::{IkSettings, IkTarget, SerialChain};
use pvfc_core::ErrorKind;
use std::path::Path;

fn ur5() -> SerialChain<f64, 6> {
    let urdf = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../models/ur5/ur5_robot.urdf");
    let robot = Robot::from_urdf(&urdf, None, Some("tool0")).expect("the UR5 reads");
    SerialChain::try_from(robot.model()).expect("a serial chain")
}

/// Postures around the UR5 scenarios' seed, away from its singularities.
fn postures() -> impl Strategy<Value = [f64; 6]> {
    proptest::array::uniform6(-0.5..0.5f64).prop_map(|d| {
        let seed = [0.0, -1.2, 1.4, -1.8, -1.57, 0.0];
        core::array::from_fn(|i| seed[i] + d[i])
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// From a seed 0.1–0.2 rad away in every joint, the tool reaches the target's point and
    /// axis; a target that also turned the roll by 0.5 rad is reached as well, with the roll
    /// where the seed left it, not the target's.
    #[test]
    fn the_tool_reaches_the_point_and_the_axis(q in postures(), off in proptest::array::uniform6(0.1..0.2f64)) {
        let chain = ur5();
        let q = SVector::from(q);
        let pose = chain.tool_pose(&q);
        let axis = pose.rotation.column(2).into_owned();
        let target = IkTarget::Axis { position: pose.translation, axis: axis * 3.0 };
        let seed = q + SVector::from(off);
        let settings = IkSettings { tolerance: 1e-10, ..IkSettings::default() };
        let got = chain.inverse_kinematics(&target, &seed, &settings).expect("reachable");
        let reached = chain.tool_pose(&got);
        prop_assert!((reached.translation - pose.translation).norm() < 1e-9);
        // The sine of the angle between the axes (an angle from a dot product would carry
        // √ε of rounding).
        let off = reached.rotation.column(2).cross(&axis).norm();
        prop_assert!(off < 1e-9, "axis off by {off:e} rad");
    }
}

/// The roll is free: the axis target is met with another roll than the posture it was read
/// from (the seed's), which a pose target would not allow.
#[test]
fn the_roll_about_the_axis_is_left_free() {
    let chain = ur5();
    let q = SVector::from([0.1, -1.1, 1.3, -1.7, -1.5, 0.2]);
    let pose = chain.tool_pose(&q);
    let axis = pose.rotation.column(2).into_owned();
    // The seed turns the last joint (the roll, here about the tool's axis) by 0.8 rad.
    let mut seed = q;
    seed[5] += 0.8;
    let settings = IkSettings {
        tolerance: 1e-10,
        ..IkSettings::default()
    };
    let target = IkTarget::Axis {
        position: pose.translation,
        axis,
    };
    let got = chain.inverse_kinematics(&target, &seed, &settings).unwrap();
    let reached = chain.tool_pose(&got);
    let roll = reached.rotation.column(0).angle(&pose.rotation.column(0));
    assert!((roll - 0.8).abs() < 1e-6, "roll {roll}");
    assert!(reached.rotation.column(2).cross(&axis).norm() < 1e-9);
}

#[test]
fn a_bad_axis_is_refused() {
    let chain = ur5();
    let seed = SVector::from([0.0, -1.2, 1.4, -1.8, -1.57, 0.0]);
    let at = |position: Vector3<f64>, axis: Vector3<f64>| {
        chain
            .inverse_kinematics(
                &IkTarget::Axis { position, axis },
                &seed,
                &IkSettings::default(),
            )
            .map_err(|e| e.kind())
    };
    let p = Vector3::new(0.5, 0.0, 0.3);
    assert_eq!(at(p, Vector3::zeros()), Err(ErrorKind::InvalidParameter));
    assert_eq!(
        at(p, Vector3::new(0.0, f64::NAN, -1.0)),
        Err(ErrorKind::NonFinite)
    );
    assert_eq!(
        at(p * f64::INFINITY, -Vector3::z()),
        Err(ErrorKind::NonFinite)
    );
}
