//! A rigid body's attitude from a scenario (`kind = "rigid_body"`, section IV-B's satellite):
//! the scenario's run is the core's closed loop driven by hand, it converges and keeps its
//! energy in both modes, a disturbance's work is counted, the MCAP log carries the body's
//! attitude for Foxglove's 3-D panel, and bad settings are named.

use nalgebra::{Matrix3, Vector3};
use pvfc_core::prelude::*;
use pvfc_sim::log::read_mcap;
use pvfc_sim::log::scene::{Scene, BODY_FRAME, BODY_TOPIC, DESIRED_FRAME, FRAMES_TOPIC};
use pvfc_sim::plant::disturbance::Disturbance;
use pvfc_sim::run::integrate::ClosedLoop;
use pvfc_sim::run::simulate;
use pvfc_sim::scenario::{presets, Mode, RobotSpec, Scenario};
use pvfc_sim::trace::metrics::{attitude_errors, energy_drift};
use std::path::Path;

fn shipped() -> Scenario {
    Scenario::from_file(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/satellite.toml"),
    )
    .unwrap()
}

/// The scenario route (TOML → spec → controller → the generic continuous loop) gives the
/// numbers of the core's closed loop built by hand from the same parameters and integrated
/// with the same RKMK4 step.
#[test]
fn the_scenario_is_the_cores_closed_loop() {
    let mut s = shipped();
    s.duration = 5.0;
    let t = simulate(&s, &mut |_| {}).unwrap();

    let j = Matrix3::new(1.2, 0.05, 0.0, 0.05, 1.0, 0.02, 0.0, 0.02, 0.8);
    let field = SuspendedField::new(
        ConstantRate::new(So3::identity(), Vector3::new(0.2, 0.1, 0.5)).unwrap(),
        So3Navigation::new(Matrix3::from_diagonal(&Vector3::new(1.0, 2.0, 3.0))).unwrap(),
        ExponentialPacing::new(20.0).unwrap(),
    );
    let law = PvfcLaw::new(
        RigidBody::new(j).unwrap(),
        field,
        Flywheel::new(1.0, 20.0).unwrap(),
        0.1,
    )
    .unwrap();
    let ctl = Controller::new(law).starting_at_rest(0.0);
    let sys = ClosedLoop::matched(ctl);
    let mut st = AugmentedState {
        q: So3::exp(&Vector3::new(1.2, -0.8, 0.5)),
        v: Vector3::zeros(),
        tau: 0.0,
        tau_dot: 0.0,
        flywheel_speed: ctl.state().flywheel_speed,
    };
    let zero = Vector3::zeros();
    let h = 1e-3 / 5.0;
    for k in 0..t.len() {
        let r = st.q.log();
        for i in 0..3 {
            assert!(
                (t.q[k][i] - r[i]).abs() < 1e-12 && (t.v[k][i] - st.v[i]).abs() < 1e-12,
                "sample {k}: {:?} {:?} against {r:?} {:?}",
                &t.q[k],
                &t.v[k],
                st.v
            );
        }
        assert!((t.tau[k] - st.tau).abs() < 1e-12, "sample {k}: τ");
        assert!((t.energy[k] - sys.kinetic_energy(&st)).abs() < 1e-12);
        for _ in 0..5 {
            st = sys.rk4_step(&st, h, &zero).unwrap();
        }
    }
}

/// From 1.52 rad off, the attitude reaches its contour, `τ̇ → βλ₁`, `κ_a` is constant; the
/// sampled-data loop (1 kHz, zero-order hold) follows too, not exactly passive.
#[test]
fn the_satellite_reaches_its_contour_in_both_modes() {
    let mut s = shipped();
    s.base_dir = Default::default();
    assert_eq!(s, presets::satellite());
    let contour = s.attitude_contour().unwrap();
    for mode in [Mode::Continuous, Mode::Sampled] {
        let mut s = s.clone();
        s.simulation.mode = mode;
        let t = simulate(&s, &mut |_| {}).unwrap();
        let angle = attitude_errors(&t, &contour);
        let n = t.len() - 1;
        let drift = energy_drift(&t);
        let pace = (t.tau_dot[n] - t.beta[n] * t.lambda1[n]).abs();
        println!(
            "{mode:?}: angle {:.3} → {:.2e} rad, U {:.2e}, |τ̇ − βλ₁| {pace:.1e}, drift {drift:.1e}",
            angle[0], angle[n], t.potential[n]
        );
        assert!((angle[0] - 1.5264).abs() < 1e-3, "{}", angle[0]);
        assert!(angle[n] < 1e-4, "{mode:?}: {}", angle[n]);
        assert!(pace < 1e-4, "{mode:?}: {pace}");
        // Theorem 1 in continuous time; the sampled loop drifts a little.
        let limit = if mode == Mode::Continuous { 1e-8 } else { 1e-3 };
        assert!(drift < limit, "{mode:?}: drift {drift:e}");
        // The angle falls steadily once near the contour: halved at least every 5 s.
        let at = |x: f64| angle[t.t.iter().position(|&y| y >= x).unwrap()];
        for w in [10.0, 15.0, 20.0, 25.0] {
            assert!(at(w + 5.0) < 0.5 * at(w), "{mode:?}: at {w} s");
        }
    }
}

/// A disturbance torque on the body: its work goes into the audit, which closes.
#[test]
fn a_disturbance_on_the_body_is_counted_in_the_audit() {
    let mut s = presets::satellite();
    s.duration = 10.0;
    s.plant.disturbance = Some(Disturbance {
        amplitude: vec![0.3, 0.2, 0.25],
        frequency: vec![0.5, 0.3, 0.7],
        phase: vec![],
    });
    s.validate().unwrap();
    let t = simulate(&s, &mut |_| {}).unwrap();
    let c = t
        .contact
        .as_ref()
        .expect("a disturbed run keeps its work columns");
    let e0 = t.energy[0];
    let residual = c
        .audit_residual(&t.energy)
        .iter()
        .fold(0.0_f64, |m, r| m.max(r.abs()))
        / e0;
    let work = c.work_contact.iter().fold(0.0_f64, |m, w| m.max(w.abs())) / e0;
    println!("disturbed satellite: audit {residual:.1e}, work {work:.1e} of κ_a(0)");
    assert!(work > 1e-3, "{work}");
    assert!(residual < 1e-8, "{residual}");
    assert!(energy_drift(&t) > 1e-4, "the disturbance changed κ_a");
}

/// The log carries the body's and the desired attitude's frames (quaternions of the trace's
/// attitudes) and the body's boxes, read back with Foxglove's own decoding.
#[test]
fn the_log_shows_the_attitude_in_foxgloves_3d_panel() {
    let mut s = presets::satellite();
    s.duration = 2.0;
    let t = simulate(&s, &mut |_| {}).unwrap();
    let scene = Scene::of_run(&s, &t).unwrap().expect("a body has a scene");
    assert_eq!(scene.frames, [BODY_FRAME, DESIRED_FRAME]);
    assert_eq!(scene.poses.len(), 101, "50 Hz over 2 s");
    let dir = std::env::temp_dir().join(format!("pvfc-body-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("satellite.mcap");
    let options = pvfc_sim::log::LogOptions {
        scene: Some(&scene),
        rate: Some(50.0),
    };
    pvfc_sim::log::write_mcap_with(&t, &options, &p).unwrap();
    let messages = read_mcap(&p).unwrap();
    let frames: Vec<_> = messages
        .iter()
        .filter(|m| m.topic == FRAMES_TOPIC)
        .collect();
    assert_eq!(frames.len(), 101);
    // The body's quaternion at 1 s is that of exp(q̂) of the trace's sample at 1 s.
    let m = frames.iter().find(|m| m.log_time == 1_000_000_000).unwrap();
    let k = t.t.iter().position(|&x| (x - 1.0).abs() < 1e-9).unwrap();
    let r = So3::exp(&Vector3::new(t.q[k][0], t.q[k][1], t.q[k][2]));
    let [w, x, y, z] = r.quaternion();
    let tf = &m.data["transforms"][0];
    assert_eq!(tf["child_frame_id"], BODY_FRAME);
    assert_eq!(tf["parent_frame_id"], "world");
    let q = &tf["rotation"];
    let got = [&q["w"], &q["x"], &q["y"], &q["z"]].map(|v| v.as_f64().unwrap());
    let sign = if got[0] * w < 0.0 { -1.0 } else { 1.0 };
    for (g, e) in got.iter().zip([w, x, y, z]) {
        assert!(
            (g - sign * e).abs() < 1e-12,
            "{got:?} against {:?}",
            [w, x, y, z]
        );
    }
    let boxes: Vec<_> = messages.iter().filter(|m| m.topic == BODY_TOPIC).collect();
    assert_eq!(boxes.len(), 1);
    let entities = boxes[0].data["entities"].as_array().unwrap();
    assert_eq!(entities.len(), 2);
    assert_eq!(entities[0]["frame_id"], BODY_FRAME);
    assert_eq!(entities[1]["frame_id"], DESIRED_FRAME);
    assert_eq!(entities[0]["cubes"].as_array().unwrap().len(), 1);
    std::fs::remove_dir_all(&dir).ok();
}

/// Settings a rigid body cannot have are refused, naming the key.
#[test]
fn bad_settings_of_a_body_are_named() {
    let check = |edit: &dyn Fn(&mut Scenario), key: &str| {
        let mut s = presets::satellite();
        edit(&mut s);
        let e = s.validate().unwrap_err().to_string();
        assert!(e.contains(key), "{key}: {e}");
    };
    check(
        &|s| {
            if let RobotSpec::RigidBody(b) = &mut s.plant.robot {
                b.inertia[2][2] = -1.0;
            }
        },
        "plant.inertia",
    );
    check(
        &|s| {
            if let RobotSpec::RigidBody(b) = &mut s.plant.robot {
                b.inertia[0][1] = 0.5;
            }
        },
        "plant.inertia",
    );
    check(&|s| s.controller.h = vec![1.0, 1.0], "controller.h");
    check(&|s| s.controller.h = vec![1.0, 1.0, 1.0], "controller.h");
    check(&|s| s.initial.q = vec![0.0, 1.5], "initial.q");
    check(&|s| s.initial.v = vec![0.0, f64::NAN, 0.0], "initial");
    check(
        &|s| {
            if let pvfc_sim::scenario::ContourSpec::Attitude(a) = &mut s.contour {
                a.rate = [0.0; 3];
            }
        },
        "contour.attitude.rate",
    );
    check(
        &|s| s.contour = pvfc_sim::scenario::ContourSpec::default(),
        "contour.attitude",
    );
    check(
        &|s| s.controller.passive = Some(Default::default()),
        "controller.passive",
    );
    check(
        &|s| {
            s.baseline = Some(pvfc_sim::scenario::BaselineSpec {
                kp: vec![1.0; 3],
                kd: vec![1.0; 3],
                tau_rate: None,
                torque_limit: vec![],
                speed_scaling: None,
            })
        },
        "baseline",
    );
    check(
        &|s| {
            s.plant.disturbance = Some(Disturbance {
                amplitude: vec![0.1; 2],
                frequency: vec![1.0; 2],
                phase: vec![],
            })
        },
        "plant.disturbance.amplitude",
    );
    // And from a file: the key and the line.
    let text = shipped()
        .to_toml()
        .unwrap()
        .replace("h = [1.0, 2.0, 3.0]", "h = [1.0, 2.0]");
    let e = Scenario::from_toml(&text, Path::new("sat.toml"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("sat.toml") && e.contains("controller.h"), "{e}");
}
