//! The coupling rate `γβĒ` (Remark 1) in place of `γ`: the controller it builds is the one of
//! `γ = rate / (βĒ)`, at the nominal speed's level `β = r` and at an energy level sized from
//! the pace, and a faster level or a larger energy keeps the rate, not the gain.

use pvfc_control::model::arm::{coupling_gain, ArmController, ArmSettings, JointContourSpec};
use pvfc_control::model::pace::{PaceSettings, PathSpeed};
use pvfc_control::model::robot::Robot;
use std::path::Path;

fn ur5() -> Robot {
    Robot::from_urdf(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("../../models/ur5/ur5_robot.urdf"),
        None,
        Some("tool0"),
    )
    .expect("the UR5")
}

fn settings() -> ArmSettings {
    let points = vec![
        vec![0.0, -1.2, 1.4, -1.8, -1.5, 0.0],
        vec![0.4, -1.0, 1.2, -1.7, -1.4, 0.3],
        vec![0.2, -1.4, 1.7, -1.9, -1.6, -0.2],
        vec![-0.2, -1.3, 1.5, -1.6, -1.5, 0.1],
    ];
    ArmSettings {
        energy: 40.0,
        nominal_speed: Some((0.5, 2.0)),
        ..ArmSettings::new(
            JointContourSpec::Waypoints {
                points,
                spacing: 1.0,
            },
            vec![1.0; 6],
        )
    }
}

/// 40 steps of both controllers from a state off the contour: the same torques to the bit.
fn same_steps(a: &mut ArmController, b: &mut ArmController) {
    let start = a.contour_point(0.3);
    let q: Vec<f64> = start
        .iter()
        .enumerate()
        .map(|(i, x)| x + 0.01 * i as f64)
        .collect();
    let v = vec![0.05; 6];
    for _ in 0..40 {
        let (ta, tb) = (a.step(&q, &v, 1e-3).unwrap(), b.step(&q, &v, 1e-3).unwrap());
        assert_eq!(ta, tb);
    }
}

#[test]
fn a_coupling_rate_is_the_gain_rate_over_beta_energy() {
    let robot = ur5();
    let rate = 400.0;
    let by_rate = ArmSettings {
        coupling_rate: Some(rate),
        gamma: 1e9, // not read
        ..settings()
    };
    // β = r = 2, Ē = 40: γ = 400 / 80 = 5.
    assert_eq!(coupling_gain(rate, 2.0, 40.0).unwrap(), 5.0);
    assert_eq!(by_rate.gamma_at(40.0).unwrap(), 5.0);
    let by_gain = ArmSettings {
        gamma: 5.0,
        ..settings()
    };
    same_steps(
        &mut ArmController::new(&robot, &by_rate).unwrap(),
        &mut ArmController::new(&robot, &by_gain).unwrap(),
    );
    // Without a nominal speed the level is 1.
    let level_one = ArmSettings {
        nominal_speed: None,
        ..by_rate.clone()
    };
    assert_eq!(level_one.gamma_at(40.0).unwrap(), 10.0);
}

/// With `energy = 0` the energy level is sized from the pace; the rate then sets `γ` for the
/// sized level, so a faster pace (a larger `Ē`) keeps the controller's stiffness.
#[test]
fn a_coupling_rate_follows_an_energy_level_sized_from_the_pace() {
    let robot = ur5();
    for speed in [0.5, 1.5] {
        let sized = ArmSettings {
            energy: 0.0,
            coupling_rate: Some(400.0),
            nominal_speed: None,
            pace: Some(PaceSettings {
                speed: Some(PathSpeed::Joint(speed)),
                torque_limit: Vec::new(),
                headroom: 0.8,
                level: 1.0,
            }),
            ..settings()
        };
        let mut a = ArmController::new(&robot, &sized).unwrap();
        let energy = a.energy_level();
        assert!(energy > 0.0);
        let given = ArmSettings {
            energy,
            coupling_rate: None,
            gamma: 400.0 / energy,
            ..sized.clone()
        };
        same_steps(&mut a, &mut ArmController::new(&robot, &given).unwrap());
    }
}
