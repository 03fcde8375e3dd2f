//! The pace a user asks for (`[controller.pace] speed`): a UR5 on its Cartesian rectangle
//! (`scenarios/ur5_cartesian.toml`, friction 80 % compensated, γĒ = 400/s) asked for a tool
//! speed, the energy held by the nominal speed (eq. 36, r = 1: the friction the compensation
//! leaves drains it), starting on the path at rest: over the steady passes the tool makes the
//! speed asked for, within 2 %, on the path. With `controller.energy = 0` the energy level is
//! sized from the pace.

use pvfc_sim::model::pace::PathSpeed;
use pvfc_sim::run::simulate_chain_with;
use pvfc_sim::scenario::{ArmSystem, NominalSpeedSpec, PaceSpec, Scenario};
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

/// Starts `s` on its path: at its first waypoint (τ = 0), at rest.
fn on_the_path(s: &mut Scenario) {
    let probe = ArmSystem::build(s).expect("the system");
    let pvfc_sim::model::arm::JointContourSpec::Waypoints { points, .. } = &probe.settings.contour
    else {
        panic!("a Cartesian path becomes waypoints");
    };
    s.initial.q = points[0].clone();
}

#[test]
fn the_tool_makes_the_speed_asked_for() {
    for speed in [0.1, 0.25] {
        let mut s = ur5_at(speed);
        on_the_path(&mut s);
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
/// level; at the coupling rate `γβĒ = 400/s` (`controller.coupling_rate`, γ taken for the
/// sized level) the run follows the path without the flywheel running dry and makes the
/// speed asked for within 2 %. The nominal speed (36) holds `β` by a proportional law: the
/// friction the compensation leaves keeps `β` under `r` by about `P_f / (c κ_a)`, so the
/// smaller sized level (8.8 J against the file's 40 J) needs a larger `c`: measured 0.2306 /
/// 0.2394 / 0.2445 / 0.2472 m/s of 0.25 at c = 0.5 / 1 / 2 / 4.
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
    // At the sized level the friction the compensation leaves drains a larger share of the
    // energy: the proportional law (36) leaves β short by about P_f/(c κ_a), within 2 % at
    // c = 4, 8 % at c = 0.5; with an integral (c = 0.5, k_i = 0.5) the deficit goes, and over
    // ten laps (its transient included) the tool makes the speed within 0.5 %.
    for (c, integral, tolerance, within) in [
        (4.0, 0.0, 0.02, true),
        (0.5, 0.5, 0.005, true),
        (0.5, 0.0, 0.02, false),
    ] {
        let mut s = ur5_at(0.25);
        s.duration *= 3.0;
        s.controller.energy = 0.0;
        s.controller.coupling_rate = Some(400.0);
        s.controller.nominal_speed = Some(NominalSpeedSpec {
            c,
            r: 1.0,
            integral,
        });
        on_the_path(&mut s);
        let system = ArmSystem::build(&s).expect("the system");
        assert_eq!(system.controller.energy_level(), fast);
        let t = simulate_chain_with(&s, &system, &mut |_| {}).expect("the run, Ē never too low");
        let b = path_budget(&s, &system.robot, &t)
            .expect("the budget")
            .expect("steady passes");
        assert!(b.surface.expect("planar").mean < 3e-4, "{b:?}");
        assert_eq!(
            (b.speed - 0.25).abs() <= tolerance * 0.25,
            within,
            "c = {c}, k_i = {integral}: asked 0.25 m/s, made {} m/s",
            b.speed
        );
    }
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

/// A part program's feeds are the pace (`scenarios/ur5_gcode.toml`: the bracket's outline at
/// F6000, its relief at F1800, with a tilted cone as the TCP): on every stretch the tool holds
/// the feed within 5 % (its median speed there), and it stays on the path (0.1 mm mean and
/// 0.3 mm at most, along the part's surface and in 3-D). A program without F takes `controller.pace.speed`, and without
/// either a move's speed is an error naming its line.
#[test]
fn a_part_programs_feeds_are_the_pace() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios");
    // The same program on a Panda (`scenarios/panda_gcode.toml`, the hand's TCP pointing down;
    // measured 0.064 / 0.131 mm in 3-D, every stretch within 0.7 % of its feed).
    let mut panda = Scenario::from_file(&dir.join("panda_gcode.toml")).expect("the Panda's");
    panda.baseline = None;
    followed_at_its_feeds(&panda, 14, [30.0, 100.0]);
    // A program of straight moves whose sharp corners G64 blends (`scenarios/ur5_plate.toml`:
    // measured 0.029 / 0.052 mm in 3-D, every stretch, the blends' included, within 1.7 % of
    // its feed).
    let mut plate = Scenario::from_file(&dir.join("ur5_plate.toml")).expect("the plate's");
    plate.baseline = None;
    followed_at_its_feeds(&plate, 16, [20.0, 50.0]);
    let mut s = Scenario::from_file(&dir.join("ur5_gcode.toml")).expect("the scenario");
    s.baseline = None;
    followed_at_its_feeds(&s, 14, [30.0, 100.0]);
    without_feeds(&dir, s);
}

/// The timed tracker beside PVFC on a part program follows its feeds, as a user would
/// program it (not one rate for the whole program): on every stretch of `ur5_gcode`'s
/// bracket its tool holds the feed within 5 %.
#[test]
fn the_timed_tracker_follows_a_part_programs_feeds() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios");
    let s = Scenario::from_file(&dir.join("ur5_gcode.toml")).expect("the scenario");
    let b = s.baseline.clone().expect("a baseline");
    assert!(b.tau_rate.is_none(), "the tracker's rate is not fixed");
    let system = ArmSystem::build(&s).expect("the system");
    let t = pvfc_sim::run::simulate_tracker(
        &s,
        &pvfc_sim::scenario::System::SerialChain(Box::new(system.clone())),
        &b,
        1.0,
        pvfc_sim::run::Tracker::Timed,
        &mut |_| {},
    )
    .expect("the tracker's run");
    let speeds = pvfc_sim::trace::feed_speeds::feed_speeds(&s, &system.robot, &t)
        .expect("the speeds")
        .expect("a program with feeds");
    assert_eq!(speeds.len(), 14, "{speeds:?}");
    for x in &speeds {
        assert!(x.error().abs() < 0.05, "{x:?}");
    }
}

/// `s` run: `stretches` stretches, among them the `feeds` (mm/s), each at its feed within
/// 5 %; the tool within 0.1 mm mean and 0.3 mm at most of the path, along the part's surface
/// and in 3-D.
fn followed_at_its_feeds(s: &Scenario, stretches: usize, feeds: [f64; 2]) {
    let system = ArmSystem::build(s).expect("the system");
    let t = simulate_chain_with(s, &system, &mut |_| {}).expect("the run");
    let speeds = pvfc_sim::trace::feed_speeds::feed_speeds(s, &system.robot, &t)
        .expect("the speeds")
        .expect("a program with feeds");
    assert_eq!(speeds.len(), stretches, "{speeds:?}");
    let asked: Vec<f64> = speeds.iter().map(|x| (x.asked * 1e3).round()).collect();
    assert!(feeds.iter().all(|f| asked.contains(f)), "{asked:?}");
    for x in &speeds {
        assert!(x.error().abs() < 0.05, "{x:?}");
    }
    // On the path: 0.1 mm mean and 0.3 mm at most, along the part's surface and in 3-D
    // (measured on the UR5 0.017 / 0.046 and 0.031 / 0.055 mm).
    let b = path_budget(s, &system.robot, &t).unwrap().unwrap();
    let surface = b.surface.expect("a planar path");
    assert!(surface.mean < 1e-4 && surface.max < 3e-4, "{surface:?}");
    assert!(
        b.spread.mean < 1e-4 && b.spread.max < 3e-4,
        "{:?}",
        b.spread
    );
}

/// The program of `s` without feeds: the scenario's speed, or an error naming the line.
fn without_feeds(dir: &Path, mut s: Scenario) {
    let text = std::fs::read_to_string(dir.join("parts/bracket.nc"))
        .unwrap()
        .replace(" F6000", "")
        .replace(" F1800", "");
    let tmp = std::env::temp_dir().join(format!("pvfc-feeds-{}", std::process::id()));
    std::fs::create_dir_all(tmp.join("parts")).unwrap();
    std::fs::write(tmp.join("parts/bracket.nc"), &text).unwrap();
    // Feeds from line 15 on only; and a feed of zero on line 15.
    std::fs::write(
        tmp.join("parts/half.nc"),
        text.replace("N120 G1 Y320", "N120 G1 Y320 F6000"),
    )
    .unwrap();
    std::fs::write(
        tmp.join("parts/zero.nc"),
        text.replace("N120 G1 Y320", "N120 G1 Y320 F0"),
    )
    .unwrap();
    s.base_dir = tmp.clone();
    s.plant = Scenario::from_file(&dir.join("ur5_gcode.toml"))
        .unwrap()
        .plant;
    if let pvfc_sim::scenario::RobotSpec::SerialChain(c) = &mut s.plant.robot {
        c.urdf = dir.join(&c.urdf);
    }
    assert!(
        s.drive_pace().unwrap().is_none(),
        "no feed, no pace table: no pace"
    );
    s.controller.pace = Some(PaceSpec {
        speed: Some(0.05),
        ..PaceSpec::default()
    });
    assert_eq!(
        s.drive_pace().unwrap().unwrap().speed,
        Some(PathSpeed::Tool(0.05))
    );
    let pvfc_sim::model::contour::ContourSpec::Cartesian(c) = &mut s.contour else {
        panic!("a Cartesian contour");
    };
    c.gcode = Some("parts/half.nc".into());
    // The moves before line 15 take the scenario's speed; without one, the first is named.
    let Some(PathSpeed::Feeds(f)) = s.drive_pace().unwrap().unwrap().speed else {
        panic!("feeds");
    };
    let asked: Vec<f64> = f.stretches().map(|(_, _, v)| v).collect();
    assert_eq!(asked[..8], [0.05; 8]);
    assert_eq!(asked[8..], [0.1; 6]);
    s.controller.pace = None;
    let e = s.drive_pace().unwrap_err().to_string();
    assert!(e.contains("line 7 has no feed"), "{e}");
    let pvfc_sim::model::contour::ContourSpec::Cartesian(c) = &mut s.contour else {
        panic!("a Cartesian contour");
    };
    c.gcode = Some("parts/zero.nc".into());
    let e = s.drive_pace().unwrap_err().to_string();
    assert!(
        e.contains("line 15, column 14: F0: a feed must be > 0"),
        "{e}"
    );
    std::fs::remove_dir_all(tmp).ok();
}
