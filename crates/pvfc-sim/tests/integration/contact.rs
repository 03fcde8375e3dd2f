//! The contact layer: kinematics, the contact law, Rapier against an analytic wall, the
//! energy audit and passivity with friction, typed errors, logs.
#![cfg(feature = "contact")]

use nalgebra::Vector2;
use proptest::prelude::*;
use pvfc_core::lie::{LieGroup, Torus};
use pvfc_core::mechanics::ScaraParameters;
use pvfc_core::ErrorKind;
use pvfc_sim::contact::{
    ContactLaw, ContactWorld, Environment, HalfPlane, Keyframe, ObstacleSpec, PlanarArm, RobotPart,
    ShapeSpec,
};
use pvfc_sim::log::{read_mcap, write_mcap, CONTACT_TOPIC};
use pvfc_sim::run::{simulate, simulate_in};
use pvfc_sim::scenario::presets;
use pvfc_sim::scenario::Scenario;
use pvfc_sim::trace::metrics::contact_summary;
use pvfc_sim::SimError;
use std::path::Path;

/// A two-link arm with links of 0.4 and 0.35 m.
fn arm() -> PlanarArm {
    PlanarArm::of(&ScaraParameters {
        l1: 0.4,
        l2: 0.35,
        ..ScaraParameters::pelican()
    })
    .unwrap()
}

/// A point attached to a part, given in the part's frame (along the link, across it).
fn attached(part: RobotPart, q: &Torus<f64, 2>, along: f64, across: f64) -> Vector2<f64> {
    let a = q.angles();
    let (origin, angle) = match part {
        RobotPart::Link1 => (Vector2::zeros(), a[0]),
        _ => (arm().elbow(q), a[0] + a[1]),
    };
    let (c, s) = (angle.cos(), angle.sin());
    origin + Vector2::new(c * along - s * across, s * along + c * across)
}

fn part(i: usize) -> RobotPart {
    [RobotPart::Link1, RobotPart::Link2, RobotPart::Tool][i]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// `Jᵀf` is the transpose of the point's velocity map: `fᵀv_p = τᵀq̇` (the identity the
    /// energy audit rests on), and the velocity is the derivative of the point's position.
    #[test]
    fn joint_torque_is_the_transpose_of_the_point_velocity(
        q1 in -3.0..3.0f64, q2 in -3.0..3.0f64, v1 in -3.0..3.0f64, v2 in -3.0..3.0f64,
        along in 0.0..0.4f64, across in -0.05..0.05f64, fx in -50.0..50.0f64,
        fy in -50.0..50.0f64, i in 0usize..3,
    ) {
        let (q, v, f) = (Torus::new(Vector2::new(q1, q2)), Vector2::new(v1, v2), Vector2::new(fx, fy));
        let p = attached(part(i), &q, along, across);
        let vp = arm().point_velocity(part(i), &q, &v, &p);
        let tau = arm().joint_torque(part(i), &q, &p, &f);
        prop_assert!((f.dot(&vp) - tau.dot(&v)).abs() <= 1e-12 * (1.0 + f.norm() * v.norm()));
        let h = 1e-6;
        let fwd = attached(part(i), &q.retract(&v, h), along, across);
        let bwd = attached(part(i), &q.retract(&v, -h), along, across);
        let fd = (fwd - bwd) / (2.0 * h);
        prop_assert!((fd - vp).norm() <= 1e-7 * (1.0 + vp.norm()), "fd {fd} vs {vp}");
    }

    /// The Rapier world and the analytic half-plane give the same force when only the tool
    /// touches a wall (the arm nearly straight towards it, so the capsules stay clear).
    #[test]
    fn rapier_agrees_with_the_analytic_wall(
        q1 in -0.3..0.3f64, q2 in -0.3..0.3f64, v1 in -2.0..2.0f64, v2 in -2.0..2.0f64,
        depth in 1e-5..5e-3f64,
    ) {
        let q = Torus::new(Vector2::new(q1, q2));
        let v = Vector2::new(v1, v2);
        let law = ContactLaw { stiffness: 1e5, damping: 0.7, friction: 0.3, slip_velocity: 0.02 };
        let face = arm().tip(&q).x + 0.015 - depth;
        let spec = pvfc_sim::contact::ContactSpec {
            link_radius: [0.04, 0.03],
            tool_radius: 0.015,
            law,
            obstacles: vec![ObstacleSpec {
                name: "wall".into(),
                shape: ShapeSpec::Box { half_extents: [0.2, 2.0] },
                position: [face + 0.2, 0.0],
                angle: 0.0,
                law: None,
                motion: vec![],
            }],
            force_schedule: None,
        };
        let mut world = ContactWorld::new(&spec, &presets_arm()).unwrap();
        let mut plane = HalfPlane {
            arm: arm(),
            normal: Vector2::new(-1.0, 0.0),
            offset: -face,
            tool_radius: 0.015,
            law,
        };
        let a = world.contact(0.0, &q, &v).unwrap();
        let b = plane.contact(0.0, &q, &v).unwrap();
        prop_assert_eq!(a.contacts, 1);
        prop_assert_eq!(b.contacts, 1);
        prop_assert!((a.depth - depth).abs() < 1e-12, "depth {} vs {}", a.depth, depth);
        let scale = 1.0 + b.force.norm();
        prop_assert!((a.force - b.force).norm() <= 1e-9 * scale, "{} vs {}", a.force, b.force);
        prop_assert!((a.torque - b.torque).norm() <= 1e-9 * scale, "{} vs {}", a.torque, b.torque);
    }
}

fn presets_arm() -> pvfc_core::mechanics::ScaraParameters<f64> {
    pvfc_sim::scenario::direct_drive_arm()
}

#[test]
fn contact_law_is_continuous_never_pulls_and_friction_opposes_sliding() {
    let law = ContactLaw {
        stiffness: 1e4,
        damping: 2.0,
        friction: 0.5,
        slip_velocity: 0.01,
    };
    let n = Vector2::new(0.0, 1.0);
    // Continuous at first touch, whatever the velocity.
    for v in [Vector2::new(0.3, -1.0), Vector2::new(-0.2, 0.5)] {
        assert_eq!(law.force(0.0, &n, &v).1, 0.0);
        assert!(law.force(1e-9, &n, &v).0.norm() < 1e-4);
    }
    // Separating fast: the damping would pull; the force is clamped to zero.
    let (f, f_n) = law.force(1e-3, &n, &Vector2::new(0.0, 10.0));
    assert_eq!((f.norm(), f_n), (0.0, 0.0));
    // Friction opposes the sliding velocity and is bounded by μ f_n.
    let v = Vector2::new(0.4, 0.0);
    let (f, f_n) = law.force(2e-3, &n, &v);
    assert!(f.x < 0.0 && f.x.abs() <= 0.5 * f_n + 1e-12);
    assert!((f_n - 1e4 * 2e-3).abs() < 1e-9);
}

#[test]
fn obstacle_motion_velocity_is_the_derivative_of_its_displacement() {
    let o = ObstacleSpec {
        name: "pusher".into(),
        shape: ShapeSpec::Ball { radius: 0.05 },
        position: [0.0, 0.0],
        angle: 0.0,
        law: None,
        motion: vec![
            Keyframe {
                t: 1.0,
                offset: [0.0, 0.0],
            },
            Keyframe {
                t: 1.4,
                offset: [0.5, -0.2],
            },
            Keyframe {
                t: 2.0,
                offset: [0.1, 0.3],
            },
        ],
    };
    for k in 0..300 {
        let t = 0.5003 + k as f64 * 0.006; // off the keyframes, where the acceleration jumps
        let h = 1e-6;
        let fd = (o.motion_at(t + h).0 - o.motion_at(t - h).0) / (2.0 * h);
        assert!((fd - o.motion_at(t).1).norm() < 1e-6, "t = {t}");
    }
    assert_eq!(o.motion_at(0.0).0, Vector2::zeros());
    assert_eq!(o.motion_at(9.0).0, Vector2::new(0.1, 0.3));
}

/// The wall with the presets' joint friction (no add-ons): the audit accounts for the
/// friction too, and the world still never receives more than `κ_a(0)`.
#[test]
fn wall_with_friction_audit_and_passivity() {
    let mut s = presets::contact_wall();
    s.plant.friction = presets::plant_friction();
    s.duration = 8.0;
    let t = simulate(&s, &mut |_| {}).unwrap();
    let c = t.contact.as_ref().unwrap();
    let sum = contact_summary(&t).unwrap();
    let friction = *c.work_friction.last().unwrap();
    assert!(
        friction < -1.0,
        "friction must do real work here: {friction}"
    );
    assert!(c.work_controller.iter().all(|w| *w == 0.0), "no add-ons");
    assert!(sum.audit <= 1e-3, "audit {:.2e}", sum.audit);
    assert!(sum.audit <= 1e-6, "measured ~1e-9; audit {:.2e}", sum.audit);
    let e0 = t.energy[0];
    for i in 0..t.len() {
        assert!(
            c.work_contact[i] >= -e0,
            "t = {}: W_e = {}",
            t.t[i],
            c.work_contact[i]
        );
        assert!(t.energy[i] <= e0 + c.work_contact[i] + 1e-6 * e0);
    }
    // The audit can fail: leaving out the friction work breaks it by orders of magnitude.
    let mut broken = c.clone();
    broken.work_friction.iter_mut().for_each(|w| *w = 0.0);
    let worst = broken
        .audit_residual(&t.energy)
        .iter()
        .fold(0.0f64, |a, r| a.max(r.abs()));
    assert!(worst / e0 > 1e-2, "{worst}");
}

/// The environment is pluggable: the analytic half-plane runs through the same loop, and
/// agrees with the Rapier wall on the whole run while only the tool touches.
#[test]
fn analytic_wall_and_rapier_wall_give_the_same_run() {
    let mut s = presets::contact_wall();
    s.duration = 3.0;
    s.baseline = None;
    let rapier = simulate(&s, &mut |_| {}).unwrap();
    let spec = s.contact.clone().unwrap();
    let mut plane = HalfPlane {
        arm: PlanarArm::of(&s.scara().unwrap()).unwrap(),
        normal: Vector2::new(-1.0, 0.0),
        offset: -0.68,
        tool_radius: spec.tool_radius,
        law: spec.law,
    };
    let analytic = simulate_in(&s, &mut plane, &mut |_| {}).unwrap();
    let (a, b) = (rapier.contact.unwrap(), analytic.contact.unwrap());
    assert!(a.normal_force.iter().cloned().fold(0.0, f64::max) > 50.0);
    for i in 0..rapier.t.len() {
        assert!(
            (rapier.q[i][0] - analytic.q[i][0]).abs() < 1e-8
                && (rapier.q[i][1] - analytic.q[i][1]).abs() < 1e-8,
            "t = {}",
            rapier.t[i]
        );
        assert!((a.normal_force[i] - b.normal_force[i]).abs() < 1e-4 * (1.0 + b.normal_force[i]));
    }
}

#[test]
fn obstacle_stops_the_robot_until_release() {
    let s = presets::contact_obstacle();
    let t = simulate(&s, &mut |_| {}).unwrap();
    let at = |time: f64| t.t.iter().position(|x| *x >= time).unwrap();
    let (blocked, released) = (at(2.0)..at(5.0), at(12.0)..t.len());
    // Blocked: τ waits (self-pacing), the robot presses, U is large.
    assert!(blocked.clone().all(|i| t.tau_dot[i] < 0.05));
    assert!(blocked.clone().all(|i| t.potential[i] > 1e-2));
    // Released: back on the contour, at speed.
    assert!(released.clone().all(|i| t.potential[i] < 1e-6));
    assert!(released.clone().all(|i| t.tau_dot[i] > 0.9));
    let c = t.contact.as_ref().unwrap();
    assert!(released.clone().all(|i| c.normal_force[i] == 0.0));
}

#[test]
fn nan_state_is_a_typed_error() {
    let s = presets::contact_wall();
    let mut world = ContactWorld::new(s.contact.as_ref().unwrap(), &s.scara().unwrap()).unwrap();
    let q = Torus::new(Vector2::new(f64::NAN, 0.0));
    match world.contact(0.0, &q, &Vector2::zeros()) {
        Err(SimError::Core(e)) => assert_eq!(e.kind(), ErrorKind::NonFinite),
        other => panic!("expected NonFinite, got {other:?}"),
    }
    let q = Torus::new(Vector2::new(0.0, 0.0));
    assert!(world
        .contact(0.0, &q, &Vector2::new(f64::INFINITY, 0.0))
        .is_err());
}

fn scenario_error(text: &str) -> String {
    match Scenario::from_toml(text, Path::new("contact.toml")) {
        Err(SimError::Scenario { message, .. }) => message,
        other => panic!("expected a scenario error, got {other:?}"),
    }
}

#[test]
fn bad_contact_settings_are_clear_errors() {
    let base = "name = \"x\"\nduration = 1.0\n[simulation]\nmode = \"continuous\"\n";
    let obstacle = |shape: &str, extra: &str| {
        format!("{base}[contact]\n[[contact.obstacles]]\nname = \"w\"\nshape = {shape}\nposition = [0.7, 0.0]\n{extra}")
    };
    // A valid one parses.
    Scenario::from_toml(
        &obstacle("{ box = { half_extents = [0.05, 0.5] } }", ""),
        Path::new("x"),
    )
    .unwrap();
    let m = scenario_error(&obstacle("{ box = { half_extents = [0.05, -0.5] } }", ""));
    assert!(m.contains("\"w\"") && m.contains("shape"), "{m}");
    let m = scenario_error(&obstacle("{ cylinder = { radius = 1.0 } }", ""));
    assert!(m.contains("cylinder"), "{m}");
    let m = scenario_error(&obstacle(
        "{ ball = { radius = 0.1 } }",
        "motion = [{ t = 2.0, offset = [0, 0] }, { t = 1.0, offset = [1, 0] }]",
    ));
    assert!(m.contains("keyframes"), "{m}");
    let m = scenario_error(&format!("{base}[contact]\nstifness = 3.0\n"));
    assert!(m.contains("stifness"), "{m}");
    let m = scenario_error(&format!("{base}[contact.law]\nstiffness = -1.0\n"));
    assert!(m.contains("stiffness"), "{m}");
    let m = scenario_error(&format!(
        "{base}[contact]\nforce_schedule = {{ onset = 1.0, limit = 5.0, min_fraction = 0.1 }}\n"
    ));
    assert!(m.contains("nominal_speed"), "{m}");
    // Sampled mode with contact is allowed.
    Scenario::from_toml("name = \"x\"\nduration = 1.0\n[contact]\n", Path::new("x")).unwrap();
}

/// The sampled-data loop (1 kHz controller with zero-order hold) runs against any
/// environment too; it is passive only up to its sampling, which the audit measures.
#[test]
fn sampled_controller_at_the_wall() {
    let mut s = presets::contact_wall_sampled();
    s.duration = 4.0;
    let mut plane = HalfPlane {
        arm: PlanarArm::of(&s.scara().unwrap()).unwrap(),
        normal: Vector2::new(-1.0, 0.0),
        offset: -0.68,
        tool_radius: 0.015,
        law: s.contact.as_ref().unwrap().law,
    };
    let analytic = simulate_in(&s, &mut plane, &mut |_| {}).unwrap();
    let rapier = simulate(&s, &mut |_| {}).unwrap();
    let (a, r) = (
        contact_summary(&analytic).unwrap(),
        contact_summary(&rapier).unwrap(),
    );
    assert!(a.peak_force > 100.0);
    assert!((a.peak_force - r.peak_force).abs() < 1e-3 * a.peak_force);
    // Not exact as the continuous loop (1e-9), but within 2 % of κ_a(0) (measured 6.4e-3,
    // most of it the start-up transient in free motion).
    assert!(r.audit < 2e-2 && r.audit > 1e-6, "audit {:.2e}", r.audit);
    let mut cont = presets::contact_wall();
    cont.duration = 4.0;
    cont.baseline = None;
    let c = contact_summary(&simulate(&cont, &mut |_| {}).unwrap()).unwrap();
    assert!(
        r.audit > 100.0 * c.audit,
        "sampling is what the residual measures"
    );
}

#[test]
fn contact_columns_round_trip_through_mcap() {
    let mut s = presets::contact_wall();
    s.duration = 2.0;
    let t = simulate(&s, &mut |_| {}).unwrap();
    let dir = std::env::temp_dir().join(format!("pvfc-contact-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("wall.mcap");
    write_mcap(&t, &p).unwrap();
    let msgs: Vec<_> = read_mcap(&p)
        .unwrap()
        .into_iter()
        .filter(|m| m.topic == CONTACT_TOPIC)
        .collect();
    let c = t.contact.as_ref().unwrap();
    assert_eq!(msgs.len(), t.len());
    for (i, m) in msgs.iter().enumerate() {
        // The works (the audit) in float64, plot values in float32.
        assert_eq!(
            m.data["normal_force"].as_f64(),
            Some(c.normal_force[i] as f32 as f64)
        );
        assert_eq!(m.data["work_contact"].as_f64(), Some(c.work_contact[i]));
        assert_eq!(
            m.data["work_controller"].as_f64(),
            Some(c.work_controller[i])
        );
        assert_eq!(m.data["tool"][1].as_f64(), Some(c.tool[i][1] as f32 as f64));
    }
    std::fs::remove_dir_all(&dir).ok();
}
