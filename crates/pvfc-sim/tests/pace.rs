//! The pace a user asks for (`[controller.pace] speed`): a UR5 on its Cartesian rectangle
//! (`scenarios/ur5_cartesian.toml`, friction 80 % compensated, γĒ = 400/s) asked for a tool
//! speed, the energy held by the nominal speed (eq. 36, r = 1: the friction the compensation
//! leaves drains it), starting on the path at rest: over the steady passes the tool makes the
//! speed asked for, within 2 %, on the path. With `controller.energy = 0` the energy level is
//! sized from the pace.

use pvfc_sim::model::pace::PathSpeed;
use pvfc_sim::run::simulate_chain_with;
use pvfc_sim::scenario::{ArmSystem, PaceSpec, Scenario};
use pvfc_sim::trace::path_budget::path_budget;
use std::path::Path;

fn ur5_at(speed: f64) -> Scenario {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios");
    let mut s = Scenario::from_file(&dir.join("ur5_cartesian.toml")).expect("the scenario");
    s.name = format!("ur5_speed_{speed}");
    // Three and a half laps of the 1.06 m rectangle: two steady passes after the first.
    s.duration = 3.5 * 1.06 / speed;
    s.controller.energy = 40.0;
    s.controller.pace = Some(PaceSpec {
        speed: Some(speed),
        ..PaceSpec::default()
    });
    s.baseline = None;
    s
}

#[test]
fn the_tool_makes_the_speed_asked_for() {
    for speed in [0.1, 0.25] {
        let mut s = ur5_at(speed);
        let probe = ArmSystem::build(&s).expect("the system");
        // Start on the path: at its first waypoint (τ = 0), at rest.
        let pvfc_sim::model::arm::JointContourSpec::Waypoints { points, .. } =
            &probe.settings.contour
        else {
            panic!("a Cartesian path becomes waypoints");
        };
        s.initial.q = points[0].clone();
        assert_eq!(
            s.drive_pace().expect("pace").expect("a pace").speed,
            Some(PathSpeed::Tool(speed)),
            "a Cartesian path's speed is the tool's"
        );
        let system = ArmSystem::build(&s).expect("the system");
        let t = simulate_chain_with(&s, &system, &mut |_| {}).expect("the run");
        let b = path_budget(&s, &system.robot, &t)
            .expect("the budget")
            .expect("steady passes");
        assert!(
            (b.speed - speed).abs() <= 0.02 * speed,
            "asked {speed} m/s, made {} m/s",
            b.speed
        );
        let surface = b.surface.expect("a planar path");
        assert!(surface.mean < 3e-4, "{surface:?}");
    }
}

/// `energy = 0`: the energy level is twice the field's largest kinetic energy on the path at
/// the pace asked for (eq. 6 holds with room for corrections), so a faster pace gets a higher
/// level, and the run (γ scaled to keep γĒ = 400/s) follows the path without the flywheel
/// running dry.
#[test]
fn the_energy_level_is_sized_from_the_pace() {
    let level = |speed: f64| {
        let mut s = ur5_at(speed);
        s.controller.energy = 0.0;
        ArmSystem::build(&s)
            .expect("the system")
            .controller
            .energy_level()
    };
    let (slow, fast) = (level(0.1), level(0.25));
    // The field's energy grows as the pace squared (the 1 of τ's own inertia aside).
    assert!(fast > 5.0 * slow && fast < 6.5 * slow, "Ē {slow} → {fast}");
    let mut s = ur5_at(0.25);
    s.controller.energy = 0.0;
    s.controller.gamma = 400.0 / fast;
    let probe = ArmSystem::build(&s).expect("the system");
    let pvfc_sim::model::arm::JointContourSpec::Waypoints { points, .. } = &probe.settings.contour
    else {
        panic!("a Cartesian path becomes waypoints");
    };
    s.initial.q = points[0].clone();
    let system = ArmSystem::build(&s).expect("the system");
    let t = simulate_chain_with(&s, &system, &mut |_| {}).expect("the run, Ē never too low");
    let b = path_budget(&s, &system.robot, &t)
        .expect("the budget")
        .expect("steady passes");
    assert!(b.surface.expect("planar").mean < 3e-4, "{b:?}");
}

#[test]
fn a_pace_needs_a_speed_or_limits_and_energy_zero_needs_a_pace() {
    let mut s = ur5_at(0.1);
    s.controller.pace = Some(PaceSpec::default());
    let e = ArmSystem::build(&s).unwrap_err().to_string();
    assert!(e.contains("controller.pace"), "{e}");
    s.controller.pace = None;
    s.controller.energy = 0.0;
    let e = ArmSystem::build(&s).unwrap_err().to_string();
    assert!(e.contains("energy = 0"), "{e}");
    s.controller.energy = 40.0;
    s.controller.pace = Some(PaceSpec {
        speed: Some(-1.0),
        ..PaceSpec::default()
    });
    let e = ArmSystem::build(&s).unwrap_err().to_string();
    assert!(e.contains("pace.speed"), "{e}");
}
