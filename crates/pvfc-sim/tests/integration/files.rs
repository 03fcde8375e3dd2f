//! Scenario files, URDF models and MCAP logs: parsing, typed errors, round trips.

use pvfc_sim::log::{read_mcap, write_mcap, CONTROLLER_TOPIC, JOINT_STATE_TOPIC};
use pvfc_sim::scenario::preset_id::{Digital, DigitalCase, PresetId};
use pvfc_sim::scenario::presets;
use pvfc_sim::scenario::{direct_drive_arm, Scenario};
use pvfc_sim::urdf::{scara_from_urdf, scara_from_urdf_str};
use pvfc_sim::SimError;
use std::path::{Path, PathBuf};

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

#[test]
fn shipped_scenarios_are_the_presets() {
    for p in presets::all() {
        let path = repo().join("scenarios").join(format!("{}.toml", p.name));
        let mut s = Scenario::from_file(&path).unwrap_or_else(|e| panic!("{e}"));
        s.base_dir = Default::default();
        assert_eq!(
            s,
            p,
            "{} differs from the preset: run `pvfc presets`",
            path.display()
        );
    }
    let ex = Scenario::from_file(&repo().join("scenarios/example_urdf_arm.toml")).unwrap();
    assert_eq!(ex.scara().unwrap(), direct_drive_arm());
    let ex = Scenario::from_file(&repo().join("scenarios/example_contact.toml")).unwrap();
    let c = ex
        .contact
        .as_ref()
        .expect("the contact example has a [contact] table");
    assert_eq!(c.obstacles.len(), 2);
    assert_eq!(c.obstacles[1].motion.len(), 3);
    let ex = Scenario::from_file(&repo().join("scenarios/example_satellite.toml")).unwrap();
    assert_eq!(
        ex.plant.robot.kind(),
        pvfc_sim::scenario::RobotKind::RigidBody
    );
    assert!(ex.plant.disturbance.is_some());
    assert_eq!(ex.dof().unwrap(), 3);
}

/// Every preset is named by its typed id, in `pvfc reproduce`'s order, and every id names
/// one preset: the report and the figures find their runs by these ids.
#[test]
fn the_presets_are_named_by_their_typed_ids() {
    let mut scenarios = presets::all();
    scenarios.extend(presets::arms_3d().unwrap());
    scenarios.extend(presets::tool_paths().unwrap());
    let names: Vec<String> = scenarios.iter().map(|s| s.name.clone()).collect();
    let ids = PresetId::all();
    let from_ids: Vec<String> = ids.iter().map(PresetId::name).collect();
    assert_eq!(names, from_ids);
    for id in ids {
        assert_eq!(PresetId::from_name(&id.name()), Some(id));
        assert_eq!(id.to_string(), id.name());
    }
    assert_eq!(PresetId::from_name("fig8_R150"), None);
    assert_eq!(
        PresetId::Digital {
            case: DigitalCase::Wall,
            rate: 250,
            controller: Digital::Passive
        }
        .name(),
        "digital_wall_250hz_passive"
    );
}

fn scenario_error(text: &str) -> String {
    match Scenario::from_toml(text, Path::new("test.toml")) {
        Err(SimError::Scenario { message, .. }) => message,
        other => panic!("expected a scenario error, got {other:?}"),
    }
}

#[test]
fn bad_scenarios_name_the_field_and_the_line() {
    let m = scenario_error("name = \"x\"\nduration = 5.0\n[controller]\ngama = 0.1\n");
    assert!(m.contains("gama") && m.contains("line 4"), "{m}");
    let m = scenario_error("name = \"x\"\nduration = \"ten\"\n");
    assert!(m.contains("line 2") && m.contains("expected f64"), "{m}");
    let m = scenario_error("name = \"x\"\n");
    assert!(m.contains("duration"), "{m}");
    let m = scenario_error("name = \"x\"\nduration = -1.0\n");
    assert!(m.contains("duration"), "{m}");
    let m = scenario_error("name = \"x\"\nduration = 1.0\n[controller]\nenergy = 0.0\n");
    assert!(m.contains("Ē"), "{m}");
    let m =
        scenario_error("name = \"x\"\nduration = 1.0\n[plant]\narm = { urdf = \"nope.urdf\" }\n");
    assert!(m.contains("nope.urdf"), "{m}");
}

#[test]
fn the_shipped_urdf_is_the_default_arm() {
    assert_eq!(
        scara_from_urdf(&repo().join("models/scara.urdf")).unwrap(),
        direct_drive_arm()
    );
}

fn urdf_error(text: &str) -> (String, String) {
    match scara_from_urdf_str(text, Path::new("t.urdf")) {
        Err(SimError::Urdf {
            element, message, ..
        }) => (element, message),
        other => panic!("expected a URDF error, got {other:?}"),
    }
}

#[test]
fn bad_urdfs_name_the_element() {
    let good = std::fs::read_to_string(repo().join("models/scara.urdf")).unwrap();
    // urdf-rs reads a missing <inertial> as mass 0.
    let start = good.find("<link name=\"forearm\">").unwrap();
    let end = start + good[start..].find("</link>").unwrap();
    let no_inertial = format!("{}<link name=\"forearm\">{}", &good[..start], &good[end..]);
    let (el, msg) = urdf_error(&no_inertial);
    assert_eq!(el, "link forearm");
    assert!(msg.contains("inertial"), "{msg}");
    // urdf-rs reads a missing <axis> as x.
    let no_axis = good.replacen("<axis xyz=\"0 0 1\"/>", "", 1);
    let (el, msg) = urdf_error(&no_axis);
    assert_eq!(el, "joint shoulder");
    assert!(msg.contains("axis"), "{msg}");
    let tilted = good.replacen("<axis xyz=\"0 0 1\"/>", "<axis xyz=\"0 1 0\"/>", 1);
    assert_eq!(urdf_error(&tilted).0, "joint shoulder");
    let prismatic = good.replacen("type=\"continuous\"", "type=\"prismatic\"", 1);
    assert!(urdf_error(&prismatic).1.contains("revolute"));
    let one_joint = good.replacen("type=\"continuous\"", "type=\"fixed\"", 1);
    assert!(urdf_error(&one_joint).1.contains("exactly 2"));
    let no_tool = good.replacen("type=\"fixed\"", "type=\"floating\"", 1);
    assert!(urdf_error(&no_tool).1.contains("2 moving joints"));
    let (el, message) = urdf_error("<robot name=\"x\"><link name=\"a\"/><joint");
    assert!(el.starts_with("line 1, column "), "{el}");
    assert!(message.contains("not well-formed XML"), "{message}");
    let off_axis = good.replacen("<origin xyz=\"0.15 0 0\"", "<origin xyz=\"0.15 0.05 0\"", 1);
    assert_eq!(urdf_error(&off_axis).0, "link forearm");
    assert!(matches!(
        scara_from_urdf(Path::new("/nonexistent.urdf")),
        Err(SimError::Io { .. })
    ));
}

#[test]
fn mcap_logs_read_back_with_counts_and_values() {
    let mut s = presets::fig8(100);
    s.duration = 0.5;
    let t = pvfc_sim::run::simulate(&s, &mut |_| {}).unwrap();
    let dir = std::env::temp_dir().join(format!("pvfc-mcap-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("run.mcap");
    write_mcap(&t, &path).unwrap();
    let msgs = read_mcap(&path).unwrap();
    assert_eq!(msgs.len(), 2 * t.len());
    let joints: Vec<_> = msgs
        .iter()
        .filter(|m| m.topic == JOINT_STATE_TOPIC)
        .collect();
    let ctl: Vec<_> = msgs
        .iter()
        .filter(|m| m.topic == CONTROLLER_TOPIC)
        .collect();
    assert_eq!(joints.len(), t.len());
    assert_eq!(ctl.len(), t.len());
    for (i, (j, c)) in joints.iter().zip(&ctl).enumerate() {
        assert_eq!(j.log_time, (t.t[i] * 1e9).round() as u64);
        // Plot values are float32, the audit's energy float64 (log module).
        let f32_of = |x: f64| x as f32 as f64;
        assert_eq!(j.data["q"][0].as_f64().unwrap(), f32_of(t.q[i][0]));
        assert_eq!(
            j.data["torque"][1].as_f64().unwrap(),
            f32_of(t.torque[i][1])
        );
        assert_eq!(
            c.data["potential"].as_f64().unwrap(),
            f32_of(t.potential[i])
        );
        assert_eq!(c.data["beta"].as_f64().unwrap(), f32_of(t.beta[i]));
        assert_eq!(c.data["tau"].as_f64().unwrap(), f32_of(t.tau[i]));
        assert_eq!(c.data["energy"].as_f64().unwrap(), t.energy[i]);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn so3_stays_on_the_group_over_1e5_steps() {
    use nalgebra::{Matrix3, Vector3};
    use pvfc_core::prelude::*;
    let field = SuspendedField::new(
        ConstantRate::new(So3::identity(), Vector3::new(0.2, 0.5, 0.9)).unwrap(),
        So3Navigation::new(Matrix3::from_diagonal(&Vector3::new(1.0, 2.0, 3.0))).unwrap(),
        ExponentialPacing::new(20.0).unwrap(),
    );
    let law = PvfcLaw::new(
        RigidBody::new(Matrix3::<f64>::from_diagonal(&Vector3::new(0.8, 1.2, 1.5))).unwrap(),
        field,
        Flywheel::new(1.0, 20.0).unwrap(),
        0.1,
    )
    .unwrap();
    let ctl = Controller::new(law).starting_at_rest(0.0);
    let sys = pvfc_sim::ClosedLoop::matched(ctl);
    let mut s = AugmentedState {
        q: So3::exp(&Vector3::new(1.2, -0.8, 0.5)),
        v: Vector3::zeros(),
        tau: 0.0,
        tau_dot: 0.0,
        flywheel_speed: ctl.state().flywheel_speed,
    };
    let e0 = sys.kinetic_energy(&s);
    for _ in 0..100_000 {
        s = sys.rk4_step(&s, 1e-3, &Vector3::zeros()).unwrap();
    }
    assert!(
        s.q.orthogonality_error() <= 1e-12,
        "orthogonality {:e}",
        s.q.orthogonality_error()
    );
    assert!(((sys.kinetic_energy(&s) - e0) / e0).abs() < 1e-6);
}
