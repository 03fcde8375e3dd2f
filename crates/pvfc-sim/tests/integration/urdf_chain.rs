//! The URDF reader for serial chains: the shipped arms load, every unsupported or malformed
//! element is a typed `SimError::Urdf` naming it, and the SCARA's URDF read as a chain gives
//! the closed form's M and C.

use nalgebra::{SVector, Vector2};
use pvfc_core::lie::Torus;
use pvfc_core::mechanics::{MechanicalSystem, Scara};
use pvfc_sim::urdf::{scara_from_urdf, ChainDescription};
use pvfc_sim::SimError;
use std::path::{Path, PathBuf};

fn models() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../models")
}

fn ur5_text() -> String {
    std::fs::read_to_string(models().join("ur5/ur5_robot.urdf")).unwrap()
}

/// Reads mutated UR5 text; returns the error's element and message.
fn error(text: &str, base: Option<&str>, tip: Option<&str>) -> (String, String) {
    match ChainDescription::from_str(text, Path::new("test.urdf"), base, tip) {
        Err(SimError::Urdf {
            element, message, ..
        }) => (element, message),
        other => panic!("expected a URDF error, got {other:?}"),
    }
}

#[test]
fn the_shipped_arms_load_with_their_limits_and_names() {
    let ur5 =
        ChainDescription::from_file(&models().join("ur5/ur5_robot.urdf"), None, Some("tool0"))
            .unwrap();
    assert_eq!(ur5.dof(), 6);
    assert_eq!(ur5.joints[0].limits.effort, Some(150.0));
    assert_eq!(ur5.joints[0].limits.velocity, Some(3.15));
    // The mesh files are not there (package:// paths): loading does not need them.
    assert!(ur5_text().contains("package://"));
    let panda = ChainDescription::from_file(
        &models().join("panda/panda.urdf"),
        None,
        Some("panda_link8"),
    )
    .unwrap();
    assert_eq!(panda.dof(), 7);
    // With panda_link8 as the tip, the hand and fingers are a side branch: locked and folded.
    assert_eq!(panda.locked_joints.len(), 2);
    panda.chain::<7>().unwrap();
    assert!(panda.chain::<6>().is_err());
}

#[test]
fn unsupported_joints_are_named() {
    let t = ur5_text();
    for (kind, what) in [("floating", "Floating"), ("planar", "Planar")] {
        let bad = t.replace(
            r#"<joint name="elbow_joint" type="revolute">"#,
            &format!(r#"<joint name="elbow_joint" type="{kind}">"#),
        );
        let (element, message) = error(&bad, None, Some("tool0"));
        assert_eq!(element, "joint elbow_joint");
        assert!(message.contains(what), "{message}");
    }
    let mimic = t.replace(
        r#"<dynamics damping="0.0" friction="0.0"/>
  </joint>
  <link name="forearm_link">"#,
        r#"<dynamics damping="0.0" friction="0.0"/>
    <mimic joint="shoulder_lift_joint"/>
  </joint>
  <link name="forearm_link">"#,
    );
    assert_ne!(mimic, t);
    let (element, message) = error(&mimic, None, Some("tool0"));
    assert_eq!(element, "joint elbow_joint");
    assert!(message.contains("mimic"), "{message}");
}

#[test]
fn bad_inertias_and_missing_inertials_are_named() {
    let t = ur5_text();
    let start = t.find(r#"<link name="upper_arm_link">"#).unwrap();
    let (a, b) = (
        start + t[start..].find("<inertial>").unwrap(),
        start + t[start..].find("</inertial>").unwrap() + "</inertial>".len(),
    );
    let missing = format!("{}{}", &t[..a], &t[b..]);
    let (element, message) = error(&missing, None, Some("tool0"));
    assert_eq!(element, "link upper_arm_link");
    assert!(message.contains("<inertial>"), "{message}");

    let indefinite = t.replace(
        r#"<inertia ixx="0.22689067591" ixy="0.0" ixz="0.0" iyy="0.22689067591" iyz="0.0" izz="0.0151074"/>"#,
        r#"<inertia ixx="0.22689067591" ixy="0.0" ixz="0.0" iyy="-0.1" iyz="0.0" izz="0.0151074"/>"#,
    );
    assert_ne!(indefinite, t);
    let (element, message) = error(&indefinite, None, Some("tool0"));
    assert_eq!(element, "link upper_arm_link");
    assert!(message.contains("positive definite"), "{message}");

    let zero = t.replace(
        r#"<inertia ixx="0.22689067591" ixy="0.0" ixz="0.0" iyy="0.22689067591" iyz="0.0" izz="0.0151074"/>"#,
        r#"<inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/>"#,
    );
    assert_eq!(error(&zero, None, Some("tool0")).0, "link upper_arm_link");
}

#[test]
fn bad_base_and_tip_choices_are_named() {
    let t = ur5_text();
    let (element, message) = error(&t, Some("wrist_3_link"), Some("shoulder_link"));
    assert_eq!(element, "link shoulder_link");
    assert!(message.contains("not below"), "{message}");
    let (element, _) = error(&t, None, Some("no_such_link"));
    assert_eq!(element, "link no_such_link");
    let (element, message) = error(&t, None, None);
    assert_eq!(element, "robot");
    assert!(message.contains("choose the tip"), "{message}");
    let (element, message) = error("<robot name='x'><link name='a'/></robot>", None, None);
    assert_eq!(element, "robot");
    assert!(message.contains("no moving joint"), "{message}");
    let (element, message) = error("<robot name='x'><link", None, None);
    assert!(element.starts_with("line 1, column "), "{element}");
    assert!(message.contains("not well-formed XML"), "{message}");
}

/// `models/scara.urdf` read as a serial chain gives the closed form's `M` and `C` to 1e-12.
#[test]
fn the_scara_urdf_as_a_chain_matches_the_closed_form() {
    let path = models().join("scara.urdf");
    let scara = Scara::new(scara_from_urdf(&path).unwrap()).unwrap();
    let chain = ChainDescription::from_file(&path, None, Some("tool"))
        .unwrap()
        .chain::<2>()
        .unwrap();
    for k in 0..500 {
        let t = k as f64 * 0.173;
        let q = Torus::new(Vector2::new(3.0 * t.sin(), 3.0 * (0.7 * t).cos()));
        let v = Vector2::new(2.0 * (1.3 * t).cos(), 4.0 * t.sin());
        let (m1, c1) = scara.inertia_and_coriolis(&q, &v);
        let (m2, c2) = chain.inertia_and_coriolis(&q, &v);
        assert!((m1 - m2).amax() <= 1e-12 * m1.amax(), "M: {m1} vs {m2}");
        assert!(
            (c1 - c2).amax() <= 1e-12 * (1.0 + c1.amax()),
            "C: {c1} vs {c2}"
        );
        // Vertical axes: gravity does no work on this arm.
        assert!(chain.gravity_torque(&SVector::from(*q.angles())).amax() < 1e-12);
    }
}

/// A point mass (mass > 0, zero rotational inertia: a payload, a sensor, a flange) fixed to a
/// link is accepted, as Pinocchio accepts it, and folds in by the parallel-axis theorem; what
/// must be positive definite is each moving body with what is folded into it.
#[test]
fn a_point_mass_fixed_to_a_link_folds_in() {
    let t = ur5_text();
    let massless = r#"<link name="tool0">
    <inertial>
      <mass value="0"/>"#;
    assert!(t.contains(massless));
    let payload = t.replace(
        massless,
        r#"<link name="tool0">
    <inertial>
      <mass value="0.5"/>"#,
    );
    let read = |text: &str| {
        ChainDescription::from_str(text, Path::new("test.urdf"), None, Some("tool0")).unwrap()
    };
    let (bare, loaded) = (read(&t), read(&payload));
    let (w, p) = (&bare.links[5], &loaded.links[5]);
    assert!((p.mass - w.mass - 0.5).abs() < 1e-12);
    // tool0 sits 0.0823 m along wrist_3's y axis: the COM and the inertia about it move as
    // the parallel-axis theorem says.
    let at = nalgebra::Vector3::new(0.0, 0.0823, 0.0);
    let com = (w.com * w.mass + at * 0.5) / p.mass;
    assert!((p.com - com).norm() < 1e-12, "{} vs {com}", p.com);
    let shift = |m: f64, d: nalgebra::Vector3<f64>| {
        (nalgebra::Matrix3::identity() * d.dot(&d) - d * d.transpose()) * m
    };
    let expected = w.inertia + shift(w.mass, w.com - com) + shift(0.5, at - com);
    assert!((p.inertia - expected).amax() < 1e-12);
    // The other bodies are untouched.
    assert_eq!(bare.links[..5], loaded.links[..5]);

    // A moving link that is a point mass with nothing folded into it is refused, by name.
    let w3 = t.find(r#"<link name="wrist_3_link">"#).unwrap();
    let inertia_at = w3 + t[w3..].find("<inertia ").unwrap();
    let inertia_end = inertia_at + t[inertia_at..].find("/>").unwrap() + 2;
    let point = format!(
        "{}{}{}",
        &t[..inertia_at],
        r#"<inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/>"#,
        &t[inertia_end..]
    );
    let (element, message) = error(&point, None, Some("tool0"));
    assert_eq!(element, "link wrist_3_link");
    assert!(message.contains("body's inertia"), "{message}");
    // With the payload folded in it is still a point-mass body (two points on a line): refused.
    // A payload with its own inertia makes the body positive definite again.
    let tool0 = r#"<link name="tool0">
    <inertial>
      <mass value="0"/>
      <origin rpy="0 0 0" xyz="0 0 0"/>
      <inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/>"#;
    assert!(point.contains(tool0));
    let solid = point.replace(
        tool0,
        r#"<link name="tool0">
    <inertial>
      <mass value="0.5"/>
      <origin rpy="0 0 0" xyz="0 0 0"/>
      <inertia ixx="1e-3" ixy="0" ixz="0" iyy="1e-3" iyz="0" izz="1e-3"/>"#,
    );
    assert!(ChainDescription::from_str(&solid, Path::new("t.urdf"), None, Some("tool0")).is_ok());
}

#[test]
fn an_empty_urdf_says_so() {
    let (element, message) = error("<robot name='x'></robot>", None, None);
    assert_eq!(element, "robot");
    assert!(message.contains("no <link>"), "{message}");
}

/// A `<texture/>` without `filename` (invalid, visual only; iCub's and Romeo's URDFs have
/// them) does not stop the chain from loading: urdf-rs alone refuses it without naming it.
#[test]
fn an_empty_texture_is_ignored() {
    let t = ur5_text();
    let at = t.find("<link ").unwrap();
    let textured = format!(
        "{}<material name=\"metal\"><texture /><color rgba=\"0.7 0.7 0.7 1\"/></material>\n{}",
        &t[..at],
        &t[at..]
    );
    let read = |text: &str| {
        ChainDescription::from_str(text, Path::new("test.urdf"), None, Some("tool0")).unwrap()
    };
    assert_eq!(read(&textured).links, read(&t).links);
    assert!(urdf_rs::read_from_string(&textured).is_err());
}
