//! Bad input is refused where it enters, with a message naming what is wrong and where, and
//! never reaches a panic, an abort or a loop without end (issue "Faults survived"): a URDF whose
//! joints form a cycle, a URDF's bad number or joint named by element, attribute and line, a
//! tool path whose geometry overflows, settings each finite but together beyond a double, a
//! contour start that is not a number.

use proptest::prelude::*;
use pvfc_control::model::arm::{ArmController, ArmSettings, JointContourSpec};
use pvfc_control::model::cartesian::{CartesianSpec, CircleSpec};
use pvfc_control::model::robot::Robot;
use pvfc_control::urdf::ChainDescription;
use std::path::Path;
use std::time::Duration;

/// Runs `f` on a thread and gives its result, or fails the test if it takes over 20 s (the
/// walk up a cycle never ended).
fn within_20_s<T: Send + 'static>(f: impl FnOnce() -> T + Send + 'static) -> T {
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(f());
    });
    rx.recv_timeout(Duration::from_secs(20))
        .unwrap_or_else(|_| panic!("did not return within 20 s"))
}

const LINK: &str = r#"<inertial><mass value="1"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial>"#;

fn urdf(links: &[&str], joints: &[(&str, &str, &str, &str)]) -> String {
    let mut s = String::from("<?xml version=\"1.0\"?>\n<robot name=\"r\">\n");
    for l in links {
        s += &format!("  <link name=\"{l}\">{LINK}</link>\n");
    }
    for (name, kind, parent, child) in joints {
        s += &format!(
            "  <joint name=\"{name}\" type=\"{kind}\">\n    <parent link=\"{parent}\"/>\n    <child link=\"{child}\"/>\n    <origin xyz=\"0 0 0.1\" rpy=\"0 0 0\"/>\n    <axis xyz=\"0 0 1\"/>\n  </joint>\n"
        );
    }
    s + "</robot>\n"
}

fn read(text: String, base: Option<&'static str>, tip: Option<&'static str>) -> String {
    within_20_s(move || {
        ChainDescription::from_str(&text, Path::new("c.urdf"), base, tip)
            .map(|_| ())
            .map_err(|e| e.to_string())
    })
    .expect_err("refused")
}

#[test]
fn joints_in_a_cycle_are_refused_not_walked_for_ever() {
    // Two links whose fixed joints point at each other: no root at all.
    let two = urdf(
        &["a", "b"],
        &[("ab", "fixed", "a", "b"), ("ba", "fixed", "b", "a")],
    );
    let e = read(two.clone(), None, Some("a"));
    assert!(e.contains("cycle"), "{e}");
    // A root elsewhere, the tip in a loop that never reaches it (the walk that hung).
    let three = urdf(
        &["r", "a", "b"],
        &[
            ("ab", "continuous", "a", "b"),
            ("ba", "continuous", "b", "a"),
        ],
    );
    let e = read(three, Some("r"), Some("a"));
    assert!(e.contains("cycle") && e.contains("joint"), "{e}");
}

#[test]
fn a_bad_urdf_names_the_element_the_attribute_and_the_line() {
    let good = urdf(&["base", "arm"], &[("shoulder", "revolute", "base", "arm")]);
    let good = good.replace(
        "<axis xyz=\"0 0 1\"/>",
        "<axis xyz=\"0 0 1\"/><limit lower=\"-1\" upper=\"1\" effort=\"10\" velocity=\"1\"/>",
    );
    ChainDescription::from_str(&good, Path::new("g.urdf"), None, Some("arm"))
        .expect("the good one reads");
    let cases = [
        (
            good.replace("xyz=\"0 0 0.1\"", "xyz=\"0 0 x\""),
            &[
                "<origin> of joint shoulder",
                "xyz=\"0 0 x\"",
                "is not a number",
                "line ",
            ][..],
        ),
        (
            good.replace("xyz=\"0 0 0.1\"", "xyz=\"0 0\""),
            &["<origin> of joint shoulder", "wrong number of entries"][..],
        ),
        (
            good.replacen("<mass value=\"1\"/>", "<mass value=\"heavy\"/>", 1),
            &["<mass> of link base", "value=\"heavy\"", "line 3"][..],
        ),
        (
            good.replace("effort=\"10\"", "effort=\"ten\""),
            &["<limit> of joint shoulder", "effort"][..],
        ),
        (
            good.replace(" type=\"revolute\"", ""),
            &["joint shoulder", "has no type"][..],
        ),
        (
            good.replace("type=\"revolute\"", "type=\"hinge\""),
            &["joint shoulder", "type=\"hinge\" is not a joint type"][..],
        ),
        (
            good.replace("</robot>", ""),
            &["line ", "not well-formed XML"][..],
        ),
    ];
    for (text, expected) in cases {
        let e = ChainDescription::from_str(&text, Path::new("b.urdf"), None, Some("arm"))
            .map(|_| ())
            .expect_err("refused")
            .to_string();
        for x in expected {
            assert!(e.contains(x), "{x:?} in {e}");
        }
        assert!(e.contains("b.urdf"), "{e}");
    }
}

fn finite_or_extreme() -> impl Strategy<Value = f64> {
    prop_oneof![
        -2.0..2.0f64,
        Just(0.0),
        Just(1e308),
        Just(-1e308),
        Just(1e-308),
        Just(f64::MAX),
        Just(f64::MIN_POSITIVE),
        Just(f64::NAN),
        Just(f64::INFINITY),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 3000, ..ProptestConfig::default() })]

    /// Any corners, radius, circle or ellipse: a path or an error, never a panic (the fuzzing
    /// of Python's `CartesianPath` found `Piece::at`'s clamp panicking on a NaN length).
    #[test]
    fn any_tool_path_is_a_path_or_an_error(
        points in prop::collection::vec([finite_or_extreme(), finite_or_extreme(), finite_or_extreme()], 0..6),
        radius in finite_or_extreme(),
        circle in prop::option::of(([finite_or_extreme(), finite_or_extreme(), finite_or_extreme()], finite_or_extreme(), prop::option::of(finite_or_extreme()))),
        s in finite_or_extreme(),
    ) {
        let spec = CartesianSpec {
            points: if circle.is_some() { vec![] } else { points },
            corner_radius: radius,
            circle: circle.map(|(center, r, semi_minor)| CircleSpec {
                center,
                radius: r,
                normal: [0.0, 0.0, 1.0],
                major_axis: None,
                semi_minor,
            }),
            ..CartesianSpec::default()
        };
        if let Ok(path) = spec.path(Path::new(".")) {
            prop_assert!(path.length().is_finite() && path.length() > 0.0);
            let p = path.point(s);
            prop_assert!(p.iter().all(|x| x.is_finite()) || !s.is_finite());
        }
    }
}

fn scara() -> Robot {
    Robot::from_urdf(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("../../models/scara.urdf"),
        None,
        Some("tool"),
    )
    .expect("the SCARA")
}

fn settings() -> ArmSettings {
    let contour = JointContourSpec::Waypoints {
        points: vec![vec![0.0, 0.5], vec![0.5, 0.8], vec![0.2, 1.2]],
        spacing: 1.0,
    };
    ArmSettings {
        self_pacing: 5.0,
        energy: 20.0,
        ..ArmSettings::new(contour, vec![1.0, 1.0])
    }
}

/// Settings each finite but together beyond a double are refused where the controller is
/// built, naming them, or the controller steps: never a controller whose every step fails.
#[test]
fn settings_beyond_a_double_are_refused_where_the_controller_is_built() {
    let robot = scara();
    ArmController::new(&robot, &settings()).expect("the good settings");
    type Edit = fn(&mut ArmSettings);
    let edits: [(&str, Edit); 12] = [
        ("tau0", |s| s.tau0 = f64::NAN),
        ("coupling_rate", |s| s.coupling_rate = Some(f64::NAN)),
        ("coupling_rate", |s| s.coupling_rate = Some(0.0)),
        ("coupling_rate", |s| s.coupling_rate = Some(-400.0)),
        ("coupling_rate", |s| s.coupling_rate = Some(1e308)),
        ("tau0", |s| s.tau0 = f64::INFINITY),
        ("energy", |s| s.energy = 1e308),
        ("flywheel_inertia", |s| s.flywheel_inertia = 1e-308),
        ("gamma", |s| s.gamma = 1e308),
        ("spacing", |s| {
            s.contour = JointContourSpec::Waypoints {
                points: vec![vec![0.0, 0.5], vec![0.5, 0.8], vec![0.2, 1.2]],
                spacing: 1e-300,
            }
        }),
        ("energy", |s| s.energy = f64::MAX),
        ("self_pacing", |s| s.self_pacing = 1e308),
    ];
    for (what, edit) in edits {
        let mut s = settings();
        edit(&mut s);
        match ArmController::new(&robot, &s) {
            Err(e) => {
                let e = e.to_string();
                assert!(e.contains(what) || e.contains("settings"), "{what}: {e}");
            }
            Ok(mut ctl) => {
                // Accepted: then it steps, from rest on its contour and from off it.
                let start = ctl.contour_point(0.0);
                for q in [start.clone(), vec![start[0] + 0.1, start[1] - 0.1]] {
                    let r = ctl.step(&q, &[0.0, 0.0], 1e-3);
                    assert!(r.is_ok(), "{what}: accepted, but a step fails: {r:?}");
                }
            }
        }
    }
}
