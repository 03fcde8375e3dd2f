//! The tool's frame along a path (`[contour.cartesian.tool_frame]`): the frame's axes and its
//! rate against finite differences, the part's pose carried into it, bad frames refused by
//! name, and the UR5 on its rectangle with a tool leaning towards the direction of travel,
//! by the joint contour (inverse kinematics to the axis) and by the task-space field, its
//! axis on the path's and its joints periodic.

use nalgebra::{Matrix3, Vector3};
use pvfc_sim::model::cartesian::{TaskSpec, ToolFrameSpec};
use pvfc_sim::model::path_orientation::{OrientationLaw, PathFrame};
use pvfc_sim::model::pose::PoseSpec;
use pvfc_sim::model::tool_path::ToolPath;
use pvfc_sim::run::simulate;
use pvfc_sim::scenario::Scenario;
use pvfc_sim::trace::path_budget::{path_budget, steady_passes};
use std::path::Path;

const CORNERS: [[f64; 3]; 4] = [
    [0.45, -0.15, 0.30],
    [0.65, -0.15, 0.30],
    [0.65, 0.20, 0.30],
    [0.45, 0.20, 0.30],
];

fn rectangle(radius: f64) -> ToolPath {
    let c: Vec<Vector3<f64>> = CORNERS.iter().map(|p| Vector3::from(*p)).collect();
    ToolPath::rounded_polygon(&c, radius).unwrap()
}

/// Without angles the frame is the path's (x its tangent, z against the normal) and turns at
/// the curvature (1/ρ on the rounded corners, 0 on the sides); with a lead and a tilt the
/// tool's axis leans by their combined angle. Everywhere a rotation, and its body rate the
/// central difference of the rotation by arc length.
#[test]
fn the_path_frame_has_its_axes_and_its_rate() {
    let path = rectangle(0.03);
    let up = Vector3::z();
    let plain = PathFrame::new(&path, up, 0.0, 0.0).unwrap();
    let (lead, tilt) = (0.2, -0.1);
    let leaning = PathFrame::new(&path, up * 2.5, lead, tilt).unwrap();
    let length = path.length();
    let h = 1e-6;
    let mut checked = 0;
    for k in 0..1999 {
        let s = length * (k as f64 + 0.29) / 1999.0;
        let (r, rate) = plain.at(s);
        assert!((r.transpose() * r - Matrix3::identity()).amax() < 1e-12);
        assert!((r.determinant() - 1.0).abs() < 1e-12);
        assert!((r.column(0) - path.tangent(s)).norm() < 1e-12);
        assert!((r.column(2) + up).norm() < 1e-12);
        let curvature = path.frame(s).2.norm();
        assert!(
            (rate.norm() - curvature).abs() < 1e-9,
            "{s}: {rate} {curvature}"
        );
        let (rl, rate_l) = leaning.at(s);
        let lean = rl.column(2).angle(&-up);
        assert!((lean.cos() - lead.cos() * tilt.cos()).abs() < 1e-12);
        // The rate, away from where a side meets a corner (the curvature jumps there).
        let (rp, _) = leaning.at(s + h);
        let (rm, _) = leaning.at(s - h);
        if (path.frame(s + h).2 - path.frame(s - h).2).norm() > 1.0 {
            continue;
        }
        checked += 1;
        let fd = (crate::common::small_rotation(&rl, &rp)
            - crate::common::small_rotation(&rl, &rm))
            / (2.0 * h);
        assert!(
            (fd - rate_l).norm() < 1e-6 * (1.0 + rate_l.norm()),
            "{k}: {fd} {rate_l}"
        );
    }
    assert!(checked > 1900, "{checked}");
}

/// Sharp corners, a path along the normal, a zero or non-finite normal or angle, and a tool
/// frame beside another orientation: refused, saying what and where.
#[test]
fn bad_tool_frames_are_refused() {
    let err = PathFrame::new(&rectangle(0.0), Vector3::z(), 0.0, 0.0).unwrap_err();
    assert!(
        err.contains("turns sharply by 90.0°") && err.contains("(0.4500, -0.1500, 0.3000)"),
        "{err}"
    );
    let err = PathFrame::new(&rectangle(0.03), Vector3::x(), 0.0, 0.0).unwrap_err();
    assert!(err.contains("runs along the surface normal"), "{err}");
    assert!(PathFrame::new(&rectangle(0.03), Vector3::zeros(), 0.0, 0.0).is_err());
    assert!(PathFrame::new(&rectangle(0.03), Vector3::new(0.0, f64::NAN, 1.0), 0.0, 0.0).is_err());
    assert!(PathFrame::new(&rectangle(0.03), Vector3::z(), f64::INFINITY, 0.0).is_err());
    let mut s = ur5_leaning();
    s.contour.cartesian_mut().unwrap().fixed_orientation = true;
    let c = s.contour.cartesian().unwrap();
    let err = c
        .orientation_law_on(&c.path(Path::new(".")).unwrap())
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("give one of orientations, tool_frame and fixed_orientation"),
        "{err}"
    );
    assert!(
        s.validate().is_err()
            || s.robot().is_err()
            || pvfc_sim::run::simulate(&s, &mut |_| {}).is_err()
    );
}

/// The part placed turned and moved: the frame along the placed path is the part's frame
/// turned with it (the normal is the part's).
#[test]
fn the_part_frame_turns_the_tool_frame_with_the_path() {
    let spec = |part: Option<PoseSpec>| pvfc_sim::model::cartesian::CartesianSpec {
        points: CORNERS.to_vec(),
        corner_radius: 0.03,
        tool_frame: Some(ToolFrameSpec {
            normal: None,
            lead: 0.2,
            tilt: 0.1,
        }),
        part,
        ..Default::default()
    };
    let pose = PoseSpec {
        xyz: [0.1, -0.05, 0.02],
        rpy: [0.2, -0.1, 0.7],
    };
    let turned = pose.isometry("part").unwrap().rotation;
    let (a, b) = (spec(None), spec(Some(pose)));
    let (pa, pb) = (
        a.path(Path::new(".")).unwrap(),
        b.path(Path::new(".")).unwrap(),
    );
    let (Some(OrientationLaw::Frame(fa)), Some(OrientationLaw::Frame(fb))) = (
        a.orientation_law_on(&pa).unwrap(),
        b.orientation_law_on(&pb).unwrap(),
    ) else {
        panic!("a tool frame gives a path frame");
    };
    for k in 0..200 {
        let s = pa.length() * (k as f64 + 0.5) / 200.0;
        let (ra, wa) = fa.at(s);
        let (rb, wb) = fb.at(s);
        assert!((turned.to_rotation_matrix().into_inner() * ra - rb).amax() < 1e-12);
        // Body rates do not depend on where the part is.
        assert!((wa - wb).norm() < 1e-9);
    }
}

/// The shipped scenario `name` with the tool leaning 0.2 rad towards the direction of travel
/// (its axis against the part's normal otherwise), the roll free, without a baseline.
fn leaning(name: &str) -> Scenario {
    let file = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios")
        .join(name);
    let mut s = Scenario::from_file(&file).unwrap();
    let c = s.contour.cartesian_mut().unwrap();
    c.fixed_orientation = false;
    c.tool_frame = Some(ToolFrameSpec {
        normal: None,
        lead: 0.2,
        tilt: 0.0,
    });
    s.baseline = None;
    s
}

/// `ur5_cartesian.toml` with the tool leaning 0.2 rad towards the direction of travel (its
/// axis against the table's normal otherwise), the roll free.
fn ur5_leaning() -> Scenario {
    let mut s = leaning("ur5_cartesian.toml");
    // Four passes: three steady ones to compare.
    s.duration = 50.0;
    s.validate().unwrap();
    s
}

/// The largest angle between the tool's axis and the path's at its closest point over the
/// steady passes, and the largest change of a joint from one pass to the next.
fn axis_and_laps(s: &Scenario) -> (f64, f64, pvfc_sim::trace::path_budget::PathBudget) {
    let t = simulate(s, &mut |_| {}).unwrap();
    let robot = s.robot().unwrap();
    let b = path_budget(s, &robot, &t).unwrap().unwrap();
    let c = s.contour.cartesian().unwrap();
    let path = c.path(Path::new(".")).unwrap();
    let law = c.orientation_law_on(&path).unwrap().unwrap();
    let range = steady_passes(&t, s.period()).unwrap();
    let mut worst = 0.0f64;
    for q in t.q.rows(range.clone()) {
        let (r, p) = robot.tool_pose(q).unwrap();
        let (want, _) = law.at(path.closest(&p).along);
        worst = worst.max(r.column(2).angle(&want.column(2)));
    }
    // The joints where τ crosses the start of each steady pass.
    let period = s.period();
    let starts: Vec<usize> = std::iter::once(range.start)
        .chain(
            range
                .clone()
                .skip(1)
                .filter(|&i| (t.tau[i] / period).floor() > (t.tau[i - 1] / period).floor()),
        )
        .collect();
    assert!(starts.len() >= 2, "{} passes", starts.len());
    let mut moved = 0.0f64;
    for w in starts.windows(2) {
        let (a, b) = (t.q.get(w[0]).unwrap(), t.q.get(w[1]).unwrap());
        let most = a
            .iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        moved = moved.max(most);
    }
    (worst, moved, b)
}

/// The UR5 on its rectangle with the tool leaning 0.2 rad towards the direction of travel: a
/// frame that turns once about the vertical a pass. By the joint contour (the waypoints
/// solved for the axis, the roll free) and by the task-space field, the tool is within the
/// machining target along the surface (mean ≤ 0.1 mm, max ≤ 0.3 mm), its axis within 4 mrad
/// of the path's, and its joints come back to within 10 mrad after each pass: no joint
/// winds.
#[test]
fn the_ur5_follows_its_rectangle_with_a_leaning_tool() {
    let joint = ur5_leaning();
    let mut task = joint.clone();
    task.controller.energy = 40.0;
    task.contour.cartesian_mut().unwrap().task = Some(TaskSpec::default());
    for (name, s) in [("joint contour", &joint), ("task-space field", &task)] {
        let (axis, moved, b) = axis_and_laps(s);
        println!("{name}: axis within {axis:.2e} rad, joints back to {moved:.1e} rad a pass; {b}");
        let surface = b.surface.unwrap();
        assert!(surface.mean <= 1e-4 && surface.max <= 3e-4, "{name}: {b}");
        assert!(axis < 4e-3, "{name}: {axis}");
        assert!(moved < 1e-2, "{name}: {moved}");
    }
}

/// The plate of `ur5_plate.toml` (sharp corners blended by G64 P0.5, the smallest blend 1.9 mm
/// long) with the tool leaning 0.2 rad: round each blend the tool's axis turns with the path,
/// by up to 90° about the normal in under 2 mm, and 1,024 samples evenly spaced leave the
/// joint contour 80 µm from the path. The adaptive sampling then places its samples by the
/// joints' motion: the contour is within its 10 µm, the samples close up in the blends, and
/// the tool follows within the machining target.
#[test]
fn a_leaning_tool_round_tight_blends_takes_samples_where_the_joints_move() {
    let mut s = leaning("ur5_plate.toml");
    // The wrist turns fast round the blends: the field's energy there is higher.
    s.controller.energy = 2000.0;
    s.validate().unwrap();
    let robot = s.robot().unwrap();
    let c = s.contour.cartesian().unwrap();
    let joints = c.joint_path(&robot, &s.base_dir).unwrap();
    let g = joints.geometry;
    println!(
        "{} samples, the contour {:.2} µm from the path at most, the axis {:.1} mrad",
        g.samples,
        g.max * 1e6,
        g.max_angle.unwrap_or(0.0) * 1e3
    );
    assert!(g.max <= 1e-5, "{} µm", g.max * 1e6);
    // Not evenly spaced: the shortest step along the path is a small part of the mean.
    let path = c.path(&s.base_dir).unwrap();
    let along: Vec<f64> = joints
        .waypoints
        .iter()
        .map(|q| path.closest(&robot.tool_pose(q).unwrap().1).along)
        .collect();
    let steps: Vec<f64> = along
        .windows(2)
        .map(|w| w[1] - w[0])
        .filter(|d| *d > 0.0)
        .collect();
    let mean = path.length() / along.len() as f64;
    let shortest = steps.iter().copied().fold(f64::INFINITY, f64::min);
    assert!(
        shortest < 0.25 * mean,
        "shortest {shortest:e} m, mean {mean:e} m"
    );
    let t = simulate(&s, &mut |_| {}).unwrap();
    let b = path_budget(&s, &robot, &t).unwrap().unwrap();
    println!("{b}");
    let surface = b.surface.unwrap();
    assert!(surface.mean <= 1e-4 && surface.max <= 3e-4, "{b}");
}
