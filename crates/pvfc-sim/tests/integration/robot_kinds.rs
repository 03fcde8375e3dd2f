//! The robot's kind named once (`[plant] kind`): each kind reads and writes back, keys of
//! another kind are refused by name, and the form before `kind` still reads, as the same
//! scenario, with a deprecation message.

use pvfc_sim::scenario::{presets, RobotKind, RobotSpec, ScaraSpec, Scenario};
use std::path::Path;

fn repo() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

fn parse(text: &str) -> Result<Scenario, String> {
    Scenario::parse(text, Path::new("k.toml"), repo().to_path_buf()).map_err(|e| e.to_string())
}

const HEAD: &str = "name = \"k\"\nduration = 1.0\n";

/// Every preset and every shipped scenario says its kind and reads back as itself, without a
/// deprecation.
#[test]
fn every_preset_names_its_kind_and_reads_back() {
    let mut kinds = std::collections::BTreeSet::new();
    let mut shipped: Vec<Scenario> = std::fs::read_dir(repo().join("scenarios"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .map(|p| Scenario::from_file(&p).unwrap())
        .collect();
    assert!(shipped.iter().all(|s| s.deprecations.is_empty()));
    shipped.extend(presets::all());
    for s in shipped {
        let text = s.to_toml().unwrap();
        let kind = s.plant.robot.kind();
        assert!(
            text.contains(&format!("kind = \"{}\"", kind.key())),
            "{}: {text}",
            s.name
        );
        let back = Scenario::parse(&text, Path::new("p.toml"), s.base_dir.clone()).unwrap();
        assert!(
            back.deprecations.is_empty(),
            "{}: {:?}",
            s.name,
            back.deprecations
        );
        assert_eq!(back.plant, s.plant, "{}", s.name);
        kinds.insert(format!("{kind:?}"));
    }
    assert_eq!(kinds.len(), 3, "the presets cover every kind: {kinds:?}");
}

/// The form before `kind` reads as the scenario that says it, and is named in a deprecation
/// message that gives the key to write.
#[test]
fn the_form_before_kind_still_reads_with_a_deprecation() {
    for name in [
        "ur5_waypoints.toml",
        "example_satellite.toml",
        "fig8_R100.toml",
    ] {
        let path = repo().join("scenarios").join(name);
        let new = std::fs::read_to_string(&path).unwrap();
        assert!(new.contains("\nkind = "), "{name} says its kind");
        let s = Scenario::from_file(&path).unwrap();
        assert!(s.deprecations.is_empty(), "{name}: {:?}", s.deprecations);
        let kind = s.plant.robot.kind().key();
        let old = match s.plant.robot {
            RobotSpec::RigidBody(_) => {
                new.replace("[plant]\nkind = \"rigid_body\"\n", "[plant.rigid_body]\n")
            }
            _ => new.replace(&format!("kind = \"{kind}\"\n"), ""),
        };
        assert_ne!(old, new);
        let mut o = Scenario::parse(&old, &path, s.base_dir.clone()).unwrap();
        assert_eq!(o.plant, s.plant, "{name}");
        assert!(
            o.deprecations
                .iter()
                .any(|d| d.contains(&format!("kind = \"{kind}\""))),
            "{name}: {:?}",
            o.deprecations
        );
        o.deprecations.clear();
        assert_eq!(o, s, "{name}");
    }
    // A legacy rigid body's table is named too.
    let sat = std::fs::read_to_string(repo().join("scenarios/example_satellite.toml")).unwrap();
    let old = sat.replace("[plant]\nkind = \"rigid_body\"\n", "[plant.rigid_body]\n");
    let o = Scenario::from_toml(&old, Path::new("sat.toml")).unwrap();
    assert!(
        o.deprecations.iter().any(|d| d.contains("plant.inertia")),
        "{:?}",
        o.deprecations
    );
    // No [plant] at all is the documented default, the direct-drive SCARA: not deprecated.
    let s = parse(HEAD).unwrap();
    assert_eq!(s.plant.robot, RobotSpec::Scara(ScaraSpec::DirectDrive));
    assert!(s.deprecations.is_empty());
}

/// A key of another kind, a missing key of the kind, an unknown kind, and two robots in the
/// form before `kind` are errors that name the key.
#[test]
fn keys_of_another_kind_are_refused_by_name() {
    let cases = [
        ("kind = \"scara\"\nurdf = \"models/ur5/ur5_robot.urdf\"", "plant.urdf"),
        (
            "kind = \"rigid_body\"\ninertia = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]\nmass_scale = [1.0]",
            "plant.mass_scale",
        ),
        ("kind = \"scara\"\ntcp = { xyz = [0.0, 0.0, 0.1] }", "plant.tcp"),
        ("kind = \"serial_chain\"\narm = \"pelican\"", "plant.arm"),
        ("kind = \"serial_chain\"", "plant.urdf"),
        ("kind = \"rigid_body\"", "plant.inertia"),
        (
            "kind = \"rigid_body\"\ninertia = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]\ntip = \"tool0\"",
            "plant.tip",
        ),
        ("kind = \"delta\"", "unknown variant `delta`"),
        (
            "urdf = \"models/ur5/ur5_robot.urdf\"\nrigid_body = { inertia = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]] }",
            "plant.rigid_body and plant.urdf",
        ),
    ];
    for (plant, expected) in cases {
        let e = parse(&format!("{HEAD}[plant]\n{plant}\n")).unwrap_err();
        assert!(e.contains(expected), "{plant}: {e}");
        assert!(e.contains("k.toml"), "{plant}: {e}");
    }
}

/// The kind decides the number of coordinates and the kind of system built.
#[test]
fn the_kind_decides_the_system() {
    use pvfc_sim::scenario::System;
    for (s, kind, dof) in [
        (presets::pelican_example(), RobotKind::Scara, 2),
        (presets::satellite(), RobotKind::RigidBody, 3),
        (
            Scenario::from_file(&repo().join("scenarios/ur5_waypoints.toml")).unwrap(),
            RobotKind::SerialChain,
            6,
        ),
    ] {
        let system = System::build(&s).unwrap();
        assert_eq!(s.plant.robot.kind(), kind);
        assert_eq!(system.dof(), dof);
        assert_eq!(s.dof().unwrap(), dof);
        assert_eq!(system.chain().is_some(), kind == RobotKind::SerialChain);
    }
}

/// `plant.tcp` puts the tool centre point on the path: every joint waypoint of the part
/// program's contour puts the TCP (a cone 120 mm out of the flange, tilted) on the placed
/// path, and the flange itself 120 mm away from it; a TCP that is not finite is refused by
/// its key.
#[test]
fn the_tcp_is_the_point_on_the_path() {
    let s = Scenario::from_file(&repo().join("scenarios/ur5_gcode.toml")).unwrap();
    let robot = s.robot().unwrap();
    let pvfc_sim::model::contour::ContourSpec::Cartesian(spec) = &s.contour else {
        panic!("ur5_gcode has a Cartesian contour");
    };
    let path = spec.path(&s.base_dir).unwrap();
    let bare = robot
        .clone()
        .with_tool(pvfc_core::mechanics::Pose::identity())
        .unwrap();
    let waypoints = spec.joint_waypoints(&robot, &s.base_dir).unwrap();
    assert!(waypoints.len() > 100, "{}", waypoints.len());
    for q in &waypoints {
        let (_, tcp) = robot.tool_pose(q).unwrap();
        let (_, flange) = bare.tool_pose(q).unwrap();
        assert!(path.closest(&tcp).distance < 1e-5);
        assert!(((flange - tcp).norm() - 0.12).abs() < 1e-12);
    }
    let text = std::fs::read_to_string(repo().join("scenarios/ur5_gcode.toml"))
        .unwrap()
        .replace("xyz = [0.0, 0.0, 0.12]", "xyz = [0.0, nan, 0.12]");
    let e = Scenario::parse(&text, Path::new("tcp.toml"), repo().join("scenarios"))
        .and_then(|s| s.robot())
        .unwrap_err()
        .to_string();
    assert!(e.contains("plant.tcp: xyz and rpy must be finite"), "{e}");
}
