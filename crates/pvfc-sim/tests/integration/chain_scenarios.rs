//! Scenarios of URDF arms (`kind = "serial_chain"`) through the generic run loop: the shipped
//! UR5 and Panda files parse and run, the frictionless continuous loop keeps κ_a, the
//! sampled one converges, and bad settings are errors that name the field.

use pvfc_sim::run::simulate;
use pvfc_sim::scenario::{Mode, Scenario};
use std::path::{Path, PathBuf};

fn file(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios")
        .join(name)
}

fn ur5() -> Scenario {
    Scenario::from_file(&file("ur5_waypoints.toml")).unwrap()
}

#[test]
fn the_shipped_arm_scenarios_parse_and_have_their_dimensions() {
    let s = ur5();
    assert_eq!(
        s.plant.robot.kind(),
        pvfc_sim::scenario::RobotKind::SerialChain
    );
    assert_eq!(s.dof().unwrap(), 6);
    assert_eq!(s.period(), 9.0);
    let p = Scenario::from_file(&file("panda_waypoints.toml")).unwrap();
    assert_eq!(p.dof().unwrap(), 7);
    // The scenario round-trips through TOML (written beside the original, so that the
    // URDF's relative path resolves the same way).
    let p = file("roundtrip_check.toml");
    std::fs::write(&p, s.to_toml().unwrap()).unwrap();
    let again = Scenario::from_file(&p);
    let _ = std::fs::remove_file(&p);
    let again = again.unwrap();
    assert_eq!(again.controller, s.controller);
    assert_eq!(again.contour, s.contour);
    assert_eq!(again.plant, s.plant);
    assert_eq!(again.initial, s.initial);
}

#[test]
fn frictionless_continuous_run_keeps_the_augmented_energy() {
    let mut s = ur5();
    s.duration = 3.0;
    s.plant.friction = Default::default();
    s.controller.friction_compensation = None;
    s.controller.nominal_speed = None;
    s.simulation.mode = Mode::Continuous;
    s.simulation.plant_substeps = 4;
    let t = simulate(&s, &mut |_| {}).unwrap();
    assert_eq!(t.q.dof(), 6);
    let e0 = t.energy[0];
    let drift = t.energy.iter().map(|e| (e - e0).abs()).fold(0.0, f64::max) / e0;
    assert!(drift < 1e-8, "κ_a drift {drift:e}");
    let u_end = *t.potential.last().unwrap();
    assert!(
        u_end < 1e-3 * t.potential[0],
        "U {} -> {u_end}",
        t.potential[0]
    );
}

#[test]
fn sampled_run_with_friction_follows_the_contour() {
    let mut s = ur5();
    s.duration = 6.0;
    let t = simulate(&s, &mut |_| {}).unwrap();
    let u_end = *t.potential.last().unwrap();
    assert!(
        u_end < 1e-2 * t.potential[0],
        "U {} -> {u_end}",
        t.potential[0]
    );
    assert!(
        *t.tau.last().unwrap() > 3.0,
        "τ advanced {}",
        t.tau.last().unwrap()
    );
}

#[test]
fn bad_arm_settings_name_the_field() {
    let text = std::fs::read_to_string(file("ur5_waypoints.toml")).unwrap();
    let base = file("");
    let parse = |t: &str| {
        let p = base.join("bad.toml");
        std::fs::write(&p, t).unwrap();
        let r = Scenario::from_file(&p)
            .map(|_| ())
            .map_err(|e| e.to_string());
        let _ = std::fs::remove_file(&p);
        r
    };
    let e = parse(&text.replace("q = [0.3, -0.9, 1.7, -1.5, -1.3, 0.3]", "q = [0.3, -0.9]"))
        .unwrap_err();
    assert!(e.contains("initial.q"), "{e}");
    let e =
        parse(&text.replace("h = [4.0, 4.0, 4.0, 4.0, 4.0, 4.0]", "h = [4.0, 4.0]")).unwrap_err();
    assert!(e.contains("h:"), "{e}");
    let e = parse(&text.replace("tip = \"tool0\"", "tip = \"nowhere\"")).unwrap_err();
    assert!(e.contains("link nowhere"), "{e}");
    let e = parse(&text.replace("spacing = 1.5\n", "")).unwrap_err();
    assert!(
        e.contains("contour.waypoints") && e.contains("spacing"),
        "{e}"
    );
    let e = parse(&text.replace(
        "coulomb = [3.0, 3.0, 2.0, 0.8, 0.8, 0.8]",
        "coulomb = [3.0, 3.0]",
    ))
    .unwrap_err();
    assert!(e.contains("plant.friction.coulomb"), "{e}");
}

/// `[controller.passive]` on a URDF arm: the UR5 with encoders, position-only measurement and
/// torque limits runs and converges; limits of the wrong length are a setting error.
#[test]
fn a_urdf_arm_runs_with_the_passive_digital_controller() {
    let mut s = ur5();
    s.duration = 4.0;
    s.controller.passive = Some(pvfc_sim::scenario::PassiveSpec {
        torque_limit: vec![150.0, 150.0, 150.0, 28.0, 28.0, 28.0],
        encoder_counts: Some(131_072.0),
        positions_only: true,
        velocity_filter: 0.002,
        reserve: 0.0,
        supervision: None,
        pace_throttle: None,
        pace_learning: None,
    });
    s.validate().unwrap();
    let t = simulate(&s, &mut |_| {}).unwrap();
    let u = &t.potential;
    assert!(
        u[u.len() - 1] < 0.1 * u[0],
        "U {} -> {}",
        u[0],
        u[u.len() - 1]
    );
    assert!(t.torque.iter().all(|r| r
        .iter()
        .zip([150.0, 150.0, 150.0, 28.0, 28.0, 28.0])
        .all(|(x, l)| x.abs() <= l)));
    if let Some(p) = s.controller.passive.as_mut() {
        p.torque_limit = vec![10.0; 2];
    }
    let e = s.validate().unwrap_err().to_string();
    assert!(e.contains("controller.passive.torque_limit"), "{e}");
}

/// `[contour.cartesian]`: the UR5's rounded rectangle becomes joint waypoints whose tool
/// positions are the sampled path points; a circle works too; every failure is a typed error
/// that names the waypoint.
#[test]
fn a_cartesian_tool_path_becomes_joint_waypoints_or_a_named_error() {
    use pvfc_sim::error::{SimError, WaypointProblem};
    use pvfc_sim::model::cartesian::CircleSpec;
    let s = Scenario::from_file(&file("ur5_cartesian.toml")).unwrap();
    s.validate().unwrap();
    assert_eq!(s.period(), 12.0);
    // The file samples adaptively; 24 fixed samples here, for a quick check.
    let mut c = s.contour.cartesian().cloned().unwrap();
    assert_eq!(c.samples, 0);
    c.samples = 24;
    let robot = s.robot().unwrap();
    let check = |c: &pvfc_sim::model::cartesian::CartesianSpec| {
        let points = c.sample(&s.base_dir).unwrap();
        let q = c.joint_waypoints(&robot, &s.base_dir).unwrap();
        assert_eq!(q.len(), c.samples);
        for (p, q) in points.iter().zip(&q) {
            let (_, x) = robot.tool_pose(q).unwrap();
            assert!((x - p).norm() < 1e-6, "{x} vs {p}");
        }
    };
    check(&c);
    let mut circle = c.clone();
    circle.points.clear();
    circle.circle = Some(CircleSpec {
        center: [0.55, 0.02, 0.30],
        radius: 0.1,
        normal: [0.0, 0.0, 1.0],
        semi_minor: None,
        major_axis: None,
    });
    check(&circle);
    let problem = |c: &pvfc_sim::model::cartesian::CartesianSpec| match c
        .joint_waypoints(&robot, &s.base_dir)
    {
        Err(SimError::Waypoint { index, problem, .. }) => (index, problem),
        other => panic!("expected a waypoint error, got {other:?}"),
    };
    let mut far = c.clone();
    far.points[2] = [3.0, 0.2, 0.3];
    far.max_jump = Some(10.0); // only the reach is in question here
    let (index, p) = problem(&far);
    assert!(
        index > 0 && matches!(p, WaypointProblem::Unreachable(d) if d > 1e-3),
        "{index}: {p}"
    );
    let mut jumpy = c.clone();
    jumpy.max_jump = Some(1e-3);
    assert!(matches!(
        problem(&jumpy),
        (1, WaypointProblem::BranchJump { .. })
    ));
    let mut strict = c.clone();
    strict.min_manipulability = Some(10.0);
    assert!(matches!(
        problem(&strict),
        (0, WaypointProblem::Singular(..))
    ));
    let mut both = c.clone();
    both.circle = circle.circle;
    assert!(both.sample(&s.base_dir).is_err());
    let mut few = c;
    few.samples = 2;
    assert!(few.sample(&s.base_dir).is_err());
}

#[test]
fn an_arm_log_carries_its_3d_scene_for_foxglove() {
    use pvfc_sim::log::scene::{Scene, ARM_TOPIC, FRAMES_TOPIC, PATH_TOPIC};
    use pvfc_sim::log::{read_mcap, write_mcap_with, LogOptions};
    let mut s = ur5();
    s.duration = 0.2;
    let t = pvfc_sim::run::simulate(&s, &mut |_| {}).unwrap();
    let scene = Scene::of_run(&s, &t).unwrap().unwrap();
    assert_eq!(scene.frames.len(), 7);
    assert_eq!(scene.frames.last().map(String::as_str), Some("tool"));
    let dir = std::env::temp_dir().join(format!("pvfc-scene-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("ur5.mcap");
    write_mcap_with(
        &t,
        &LogOptions {
            scene: Some(&scene),
            rate: None,
        },
        &p,
    )
    .unwrap();
    let msgs = read_mcap(&p).unwrap();
    let count = |topic: &str| msgs.iter().filter(|m| m.topic == topic).count();
    // 0.2 s at the controller's rate, frames at 50 Hz (t = 0 and 0.2 included).
    assert_eq!(count(FRAMES_TOPIC), 11);
    assert_eq!(count(ARM_TOPIC), 11);
    assert_eq!(count(PATH_TOPIC), 1);
    let robot = s.robot().unwrap();
    for m in msgs.iter().filter(|m| m.topic == FRAMES_TOPIC) {
        let i =
            t.t.iter()
                .position(|x| (x * 1e9).round() as u64 == m.log_time)
                .unwrap();
        let tool = &m.data["transforms"][6]["translation"];
        let (_, p) = robot.tool_pose(&t.q[i]).unwrap();
        for (k, axis) in ["x", "y", "z"].iter().enumerate() {
            assert!((tool[*axis].as_f64().unwrap() - p[k]).abs() < 1e-12);
        }
    }
    // A planar run has no scene.
    let mut planar = pvfc_sim::scenario::presets::fig8(100);
    planar.duration = 0.01;
    let tp = pvfc_sim::run::simulate(&planar, &mut |_| {}).unwrap();
    assert!(Scene::of_run(&planar, &tp).unwrap().is_none());
    std::fs::remove_dir_all(&dir).ok();
}

#[cfg(feature = "contact")]
fn ur5_on_a_table(mode: Mode) -> Scenario {
    let mut s = Scenario::from_file(&file("ur5_cartesian.toml")).unwrap();
    s.simulation.mode = mode;
    if mode == Mode::Sampled {
        // The passive digital controller: its account is exact at the samples.
        s.controller.passive = Some(Default::default());
    }
    s.duration = 3.0;
    // A table whose top is 3 mm above the tool ball's lowest point on the path (z = 0.30).
    s.contact_3d = Some(crate::common::table_under_the_rectangle());
    s.validate().unwrap();
    s
}

#[cfg(feature = "contact")]
#[test]
fn a_urdf_arm_on_a_table_keeps_its_energy_audit() {
    for (mode, tolerance) in [(Mode::Continuous, 1e-6), (Mode::Sampled, 1e-6)] {
        let s = ur5_on_a_table(mode);
        let t = simulate(&s, &mut |_| {}).unwrap();
        let c = t.contact.as_ref().unwrap();
        assert_eq!((c.force.dof(), c.torque.dof(), c.tool.dof()), (3, 6, 3));
        let peak = c.normal_force.iter().fold(0.0_f64, |m, f| m.max(*f));
        assert!(
            peak > 1.0,
            "{mode:?}: the tool never pressed on the table ({peak} N)"
        );
        assert!(c.work_gravity.iter().any(|w| w.abs() > 1e-3));
        let audit = c
            .audit_residual(&t.energy)
            .iter()
            .fold(0.0_f64, |m, r| m.max(r.abs()));
        println!(
            "{mode:?}: peak force {peak:.2} N, audit {audit:.2e} of {:.1} J",
            t.energy[0]
        );
        assert!(audit < tolerance * t.energy[0], "{mode:?}: audit {audit:e}");
    }
}

#[cfg(feature = "contact")]
#[test]
fn the_press_scenario_runs_beside_its_timed_baseline() {
    let mut s = Scenario::from_file(&file("ur5_press.toml")).unwrap();
    s.duration = 4.0;
    let runs = pvfc_sim::run::run_scenario(&s, &mut |_| {}).unwrap();
    assert_eq!(runs.len(), 2);
    assert_eq!(runs[1].name, "ur5_press-timed");
    for t in &runs {
        let c = t.contact.as_ref().unwrap();
        let peak = c.normal_force.iter().fold(0.0_f64, |m, f| m.max(*f));
        let audit = c
            .audit_residual(&t.energy)
            .iter()
            .fold(0.0_f64, |m, r| m.max(r.abs()));
        println!("{}: peak {peak:.2} N, audit {audit:.1e} J", t.name);
        assert!(peak > 1.0, "{}: no contact", t.name);
        assert!(audit < 1e-8, "{}: audit {audit:e} J", t.name);
    }
    // PVFC's nominal speed follows the force schedule at every sample, and the schedule acts:
    // r goes below its nominal 1 while the tool presses.
    let sch = s.contact_3d.as_ref().unwrap().force_schedule.unwrap();
    let r0 = s.controller.nominal_speed.unwrap().r;
    let c = runs[0].contact.as_ref().unwrap();
    for (r, f) in c.nominal_speed.iter().zip(&c.normal_force) {
        assert!((r - sch.speed(r0, *f)).abs() < 1e-12, "r = {r} at {f} N");
    }
    assert!(c.nominal_speed.iter().any(|r| *r < 0.9 * r0));
    // The schedule needs the nominal-speed add-on.
    let mut bad = s.clone();
    bad.controller.nominal_speed = None;
    let e = bad.validate().unwrap_err().to_string();
    assert!(e.contains("contact_3d.force_schedule"), "{e}");
    // A gain per joint, or a named error.
    let mut bad = s.clone();
    if let Some(b) = bad.baseline.as_mut() {
        b.kp.pop();
    }
    assert!(bad
        .validate()
        .unwrap_err()
        .to_string()
        .contains("baseline.kp"));
}

#[test]
fn the_path_error_says_how_far_and_where_along_the_path() {
    use nalgebra::Vector3;
    let s = Scenario::from_file(&file("ur5_cartesian.toml")).unwrap();
    let mut c = s.contour.cartesian().cloned().unwrap();
    // A square 0.2 m a side, no rounding: 0.8 m around, starting at (0.4, −0.1, 0.3).
    c.points = vec![
        [0.4, -0.1, 0.3],
        [0.6, -0.1, 0.3],
        [0.6, 0.1, 0.3],
        [0.4, 0.1, 0.3],
    ];
    c.corner_radius = 0.0;
    let tool = [
        Vector3::new(0.45, -0.1, 0.301), // 1 mm above the first side, 50 mm along
        Vector3::new(0.6 + 0.004, 0.05, 0.3), // 4 mm outside the second side, 350 mm along
        Vector3::new(0.5, 0.1, 0.302),   // 2 mm above the third side
    ];
    let e = c.path_error(&s.base_dir, &tool).unwrap();
    assert!((e.length - 0.8).abs() < 1e-12, "{}", e.length);
    assert_eq!(e.worst, 1);
    assert!((e.max - 0.004).abs() < 1e-12);
    assert!((e.along - 0.35).abs() < 1e-12, "{}", e.along);
    assert!((e.mean - 0.007 / 3.0).abs() < 1e-12);
}

/// A URDF arm's contour can be a Lissajous curve or an ellipse in its joint space, not only a
/// spline through waypoints: the Panda's shipped Lissajous scenario samples the formula, a UR5
/// on an ellipse keeps κ_a in continuous time and converges onto it, and bad lists are named.
#[test]
fn a_urdf_arm_follows_a_joint_space_lissajous_curve_or_ellipse() {
    use pvfc_sim::model::arm::ArmController;
    use pvfc_sim::model::arm::JointContourSpec;
    use pvfc_sim::scenario::ContourSpec;
    let p = Scenario::from_file(&file("panda_lissajous.toml")).unwrap();
    assert_eq!(p.dof().unwrap(), 7);
    assert_eq!(p.period(), 9.0);
    let ctl = ArmController::new(&p.robot().unwrap(), &p.arm_settings().unwrap()).unwrap();
    let ContourSpec::Joint(JointContourSpec::Lissajous {
        amplitude,
        periods,
        phase,
        offset,
        ..
    }) = &p.contour
    else {
        panic!("the Panda's contour is a Lissajous curve: {:?}", p.contour);
    };
    for tau in [0.0, 1.3, 4.0, 8.9] {
        let x = ctl.contour_point(tau);
        for (i, xi) in x.iter().enumerate() {
            let want = offset[i]
                + amplitude[i] * (2.0 * std::f64::consts::PI * tau / periods[i] + phase[i]).sin();
            assert!((xi - want).abs() < 1e-6, "joint {i} at τ = {tau}");
        }
        assert_eq!(x.len(), 7);
        // Closed over the common period.
        let again = ctl.contour_point(tau + 9.0);
        assert!(x.iter().zip(&again).all(|(a, b)| (a - b).abs() < 1e-9));
    }

    let mut s = ur5();
    s.contour = ContourSpec::Joint(JointContourSpec::Ellipse {
        center: vec![0.0, -1.4, 1.6, -1.8, -1.57, 0.0],
        u: vec![0.5, 0.2, 0.0, 0.2, 0.0, 0.3],
        w: vec![0.0, 0.2, 0.3, 0.0, 0.3, 0.0],
        period: 8.0,
    });
    assert_eq!(s.period(), 8.0);
    s.validate().unwrap();
    s.duration = 3.0;
    s.plant.friction = Default::default();
    s.controller.friction_compensation = None;
    s.controller.nominal_speed = None;
    s.simulation.mode = Mode::Continuous;
    s.simulation.plant_substeps = 4;
    let t = simulate(&s, &mut |_| {}).unwrap();
    let e0 = t.energy[0];
    let drift = t.energy.iter().map(|e| (e - e0).abs()).fold(0.0, f64::max) / e0;
    assert!(drift < 1e-8, "κ_a drift {drift:e}");
    let u_end = *t.potential.last().unwrap();
    assert!(
        u_end < 1e-3 * t.potential[0],
        "U {} -> {u_end}",
        t.potential[0]
    );

    // One contour, each list one entry per joint.
    let both = format!(
        "{}\n[contour.waypoints]\npoints = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]\nspacing = 1.0\n",
        s.to_toml().unwrap()
    );
    let e = Scenario::parse(&both, Path::new("both.toml"), s.base_dir.clone())
        .unwrap_err()
        .to_string();
    assert!(e.contains("one kind of contour"), "{e}");
    let mut short = s.clone();
    if let ContourSpec::Joint(JointContourSpec::Ellipse { u, .. }) = &mut short.contour {
        *u = vec![0.5, 0.2];
    }
    let e = short.validate().unwrap_err().to_string();
    assert!(e.contains("ellipse.u"), "{e}");
    let text = std::fs::read_to_string(file("panda_lissajous.toml")).unwrap();
    let bad = file("bad_lissajous.toml");
    std::fs::write(
        &bad,
        text.replace("periods = [9.0, 4.5, 9.0", "periods = [9.0, 0.0, 9.0"),
    )
    .unwrap();
    let e = Scenario::from_file(&bad)
        .map(|_| ())
        .map_err(|e| e.to_string());
    let _ = std::fs::remove_file(&bad);
    assert!(e.unwrap_err().contains("period"));
}

/// A model error (`plant.mass_scale`): the simulated arm's links heavier than the controller's
/// model. The plant is the scaled model (its kinetic energy and gravity are the scaled
/// chain's), the audit still closes (the coupling is workless whatever its model, and the
/// add-ons' and gravity's work are logged), the contact force grows with the uncompensated
/// weight, and bad factors are errors that name the field.
#[cfg(feature = "contact")]
#[test]
fn a_model_error_keeps_the_audit_and_shows_in_the_force() {
    use pvfc_sim::scenario::ArmSystem;
    let mut nominal = ur5_on_a_table(Mode::Sampled);
    nominal.duration = 2.0;
    let mut heavy = nominal.clone();
    heavy.plant.mass_scale = Some(vec![1.0, 1.0, 1.2, 1.0, 1.0, 1.0]);
    heavy.validate().unwrap();
    let sys = ArmSystem::build(&heavy).unwrap();
    let (q, v) = (
        nalgebra::DVector::from_vec(vec![0.1, -1.1, 1.3, -1.7, -1.5, 0.1]),
        nalgebra::DVector::from_vec(vec![0.2, -0.1, 0.3, 0.1, -0.2, 0.1]),
    );
    let m_model = sys.robot.inertia(q.as_slice()).unwrap();
    let m_plant = sys.plant.inertia(q.as_slice()).unwrap();
    assert!((m_plant.clone() - m_model.clone()).norm() > 1e-3 * m_model.norm());
    let ke = |m: &nalgebra::DMatrix<f64>| 0.5 * v.dot(&(m * &v));
    assert!(ke(&m_plant) > ke(&m_model));
    let peak = |t: &pvfc_sim::Trace| {
        let c = t.contact.as_ref().unwrap();
        let audit = c
            .audit_residual(&t.energy)
            .iter()
            .fold(0.0_f64, |m, r| m.max(r.abs()));
        (
            c.normal_force.iter().fold(0.0_f64, |m, f| m.max(*f)),
            audit / t.energy[0],
        )
    };
    let (f0, a0) = peak(&simulate(&nominal, &mut |_| {}).unwrap());
    let t = simulate(&heavy, &mut |_| {}).unwrap();
    let (f1, a1) = peak(&t);
    println!("peak force {f0:.2} → {f1:.2} N, audit {a0:.1e} → {a1:.1e}");
    assert!(a0 < 1e-9 && a1 < 1e-9, "audit {a0:e}, {a1:e}");
    assert!(f1 > f0, "a heavier forearm presses harder: {f0} → {f1} N");
    // Bad factors name the field.
    for (scale, mode) in [
        (vec![1.0; 5], Mode::Sampled),
        (vec![1.0, 1.0, 0.0, 1.0, 1.0, 1.0], Mode::Sampled),
        (vec![1.0, 1.0, f64::NAN, 1.0, 1.0, 1.0], Mode::Sampled),
        (vec![1.1; 6], Mode::Continuous),
    ] {
        let mut s = heavy.clone();
        s.plant.mass_scale = Some(scale);
        s.simulation.mode = mode;
        if mode == Mode::Continuous {
            s.controller.passive = None;
        }
        let e = s.validate().unwrap_err().to_string();
        assert!(e.contains("plant.mass_scale"), "{e}");
    }
}

/// A SCARA's model error (`plant.mass_scale`, one factor per link): the simulated arm is the
/// scaled one while PVFC and the trackers keep the model, so the runs differ from the
/// nominal ones; PVFC still follows the contour; a rigid body has no links to scale; the
/// continuous mode (which integrates the controller's own model) refuses it.
#[test]
fn a_scara_model_error_changes_the_plant_not_the_controller() {
    use pvfc_sim::scenario::preset_id::Fig1Contour;
    use pvfc_sim::scenario::presets::fig1_saturated;
    use pvfc_sim::trace::metrics::mean_potential_over_pass;
    let mut nominal = fig1_saturated(Fig1Contour::Circle, 100);
    nominal.duration = 15.0;
    let mut off = nominal.clone();
    off.plant.mass_scale = Some(vec![1.15, 0.85]);
    let text = off.to_toml().unwrap();
    assert!(text.contains("mass_scale = [1.15, 0.85]"), "{text}");
    let back = Scenario::from_toml(&text, Path::new("off.toml")).unwrap();
    assert_eq!(back.plant.mass_scale, off.plant.mass_scale);
    let a = pvfc_sim::run::run_scenario(&nominal, &mut |_| {}).unwrap();
    let b = pvfc_sim::run::run_scenario(&off, &mut |_| {}).unwrap();
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(&b) {
        assert_ne!(x.q, y.q, "{}: the model error changed nothing", x.name);
    }
    let u = |t: &pvfc_sim::Trace| mean_potential_over_pass(t, nominal.period()).unwrap();
    println!(
        "mean U: nominal {:.2e}, 15 % off {:.2e}",
        u(&a[0]),
        u(&b[0])
    );
    assert!(
        u(&b[0]) < 1e-4,
        "PVFC left the contour: mean U {:.2e}",
        u(&b[0])
    );
    // Bad factors and the continuous mode are named.
    for scale in [vec![1.0], vec![1.0, -1.0], vec![f64::NAN, 1.0]] {
        let mut s = off.clone();
        s.plant.mass_scale = Some(scale);
        // Before anything runs (a study checks every run so), and at the run.
        let e = s.validate().unwrap_err().to_string();
        assert!(e.contains("plant.mass_scale"), "{e}");
        let e = pvfc_sim::run::run_scenario(&s, &mut |_| {})
            .unwrap_err()
            .to_string();
        assert!(e.contains("plant.mass_scale"), "{e}");
    }
    let mut continuous = off.clone();
    continuous.simulation.mode = Mode::Continuous;
    continuous.controller.passive = None;
    continuous.controller.pace = None;
    continuous.baseline = None;
    let e = pvfc_sim::run::run_scenario(&continuous, &mut |_| {})
        .unwrap_err()
        .to_string();
    assert!(e.contains("sampled mode"), "{e}");
}

/// The part frame moves the whole task: `ur5_deburr.toml` with its path and its workpiece
/// given in a part's frame turned 0.3 rad about the base's vertical axis (the UR5's first
/// joint), the seed and the start turned with it, runs the same motion with the first joint
/// 0.3 rad on: the same tool-path distance, the same contact forces (turned), the same
/// energy. Gravity is along that axis, so nothing else may change.
#[cfg(feature = "contact")]
#[test]
fn the_part_frame_moves_the_path_and_the_workpiece_together() {
    use pvfc_sim::contact::spatial::ObstacleFrame;
    use pvfc_sim::model::pose::PoseSpec;
    let turn = 0.3;
    let base = || {
        let mut s = Scenario::from_file(&file("ur5_deburr.toml")).unwrap();
        s.duration = 4.0;
        s.baseline = None;
        // Beside the box, whose top the turn leaves as it was, a burr: a ball the tool grazes
        // 5 mm deep on the path's first straight.
        let contact = s.contact_3d.as_mut().unwrap();
        let mut burr = contact.obstacles[0].clone();
        burr.shape = pvfc_sim::contact::spatial::SpatialShape::Ball { radius: 0.01 };
        burr.position = [0.55, -0.165, 0.30];
        contact.obstacles.push(burr);
        s
    };
    let a = base();
    let mut b = base();
    let c = b.contour.cartesian_mut().unwrap();
    c.part = Some(PoseSpec {
        xyz: [0.0, 0.0, 0.0],
        rpy: [0.0, 0.0, turn],
    });
    c.seed[0] += turn;
    b.initial.q[0] += turn;
    for o in &mut b.contact_3d.as_mut().unwrap().obstacles {
        o.frame = ObstacleFrame::Part;
    }
    b.validate().unwrap();
    let (ta, tb) = (
        simulate(&a, &mut |_| {}).unwrap(),
        simulate(&b, &mut |_| {}).unwrap(),
    );
    let (ca, cb) = (ta.contact.as_ref().unwrap(), tb.contact.as_ref().unwrap());
    let peak = ca.normal_force.iter().fold(0.0_f64, |m, f| m.max(*f));
    assert!(
        peak > 1.0,
        "the tool never pressed on the workpiece ({peak} N)"
    );
    let r = nalgebra::Rotation3::from_euler_angles(0.0, 0.0, turn);
    let mut worst = [0.0_f64; 3];
    for i in 0..ta.q.len() {
        let (qa, qb) = (&ta.q[i], &tb.q[i]);
        worst[0] = worst[0].max((qb[0] - qa[0] - turn).abs());
        for j in 1..6 {
            worst[0] = worst[0].max((qb[j] - qa[j]).abs());
        }
        let fa = r * nalgebra::Vector3::from_column_slice(&ca.force[i]);
        let fb = nalgebra::Vector3::from_column_slice(&cb.force[i]);
        worst[1] = worst[1].max((fa - fb).norm());
        worst[2] = worst[2].max((ca.normal_force[i] - cb.normal_force[i]).abs());
    }
    assert!(worst[0] < 1e-7, "joints apart by {:e} rad", worst[0]);
    assert!(
        worst[1] < 1e-5 * (1.0 + peak),
        "forces apart by {:e} N",
        worst[1]
    );
    assert!(
        worst[2] < 1e-5 * (1.0 + peak),
        "normal forces apart by {:e} N",
        worst[2]
    );

    // A world is built from obstacles placed in the base frame only.
    let robot = b.robot().unwrap();
    let e = pvfc_sim::contact::spatial::SpatialWorld::new(b.contact_3d.as_ref().unwrap(), &robot)
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("in_base_frame"), "{e}");
    // In the part's frame without a part: the obstacle is named.
    let mut c = base();
    c.contact_3d.as_mut().unwrap().obstacles[0].frame = ObstacleFrame::Part;
    let e = c.validate().unwrap_err().to_string();
    assert!(
        e.contains("contact_3d.obstacles[0]") && e.contains("part"),
        "{e}"
    );
}
