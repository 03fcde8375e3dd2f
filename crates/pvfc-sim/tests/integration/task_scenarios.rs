//! The task-space field chosen per scenario (`[contour.cartesian.task]`): the exact path as a
//! contour on ℝ³ (its derivatives against finite differences), the UR5 rectangle followed
//! with the tool held pointing down (continuous: κ_a kept; sampled with friction: the
//! machining target), the audits with contact (continuous and the passive digital
//! controller), and bad settings named.

use nalgebra::Vector3;
use pvfc_core::contour::Contour;
use pvfc_sim::model::cartesian::TaskSpec;
use pvfc_sim::model::tool_path::{PathContour, ToolPath};
use pvfc_sim::run::simulate;
use pvfc_sim::scenario::{Mode, Scenario};
use pvfc_sim::trace::path_budget::path_budget;
use std::path::{Path, PathBuf};

fn file(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios")
        .join(name)
}

/// `ur5_cartesian.toml` with the task-space field (default gains), at `Ē = 40 J` (the file's
/// 400 J leaves room for its stiffer joint-space field's approach; the task-space field's
/// limits below are stated at 40 J), at the file's coupling rate (`γ = 10`).
fn ur5_task() -> Scenario {
    let mut s = Scenario::from_file(&file("ur5_cartesian.toml")).unwrap();
    s.controller.energy = 40.0;
    if let Some(c) = s.contour.cartesian_mut() {
        c.task = Some(TaskSpec::default());
    }
    s.validate().unwrap();
    s
}

/// `p_d'` and `p_d''` of the exact path against central differences of `p_d`, on a rounded
/// rectangle (lines and arcs) and an ellipse, away from the joints where the curvature jumps.
#[test]
fn the_path_contour_has_its_derivatives() {
    let rect = ToolPath::rounded_polygon(
        &[
            Vector3::new(0.45, -0.15, 0.3),
            Vector3::new(0.65, -0.15, 0.3),
            Vector3::new(0.65, 0.2, 0.3),
            Vector3::new(0.45, 0.2, 0.3),
        ],
        0.03,
    )
    .unwrap();
    let ellipse = ToolPath::ellipse(
        Vector3::new(0.5, 0.0, 0.4),
        Vector3::new(0.12, 0.0, 0.0),
        Vector3::new(0.0, 0.03, 0.04),
    );
    for path in [rect, ellipse] {
        let c = PathContour::new(path.clone(), 12.0).unwrap();
        assert_eq!(c.period(), Some(12.0));
        let h = 1e-4;
        let mut checked = 0;
        for k in 0..997 {
            let tau = 12.0 * (k as f64 + 0.31) / 997.0;
            let (m, s, p) = (c.sample(tau - h), c.sample(tau), c.sample(tau + h));
            let v = (p.point.coords() - m.point.coords()) / (2.0 * h);
            let a = (p.point.coords() - 2.0 * s.point.coords() + m.point.coords()) / (h * h);
            // Skip the samples whose stencil straddles a curvature jump.
            let jump = (p.acceleration - m.acceleration).norm();
            if jump > 1e-2 * (p.acceleration.norm() + m.acceleration.norm()) {
                continue;
            }
            checked += 1;
            let speed = path.length() / 12.0;
            assert!((s.velocity.norm() - speed).abs() < 1e-9);
            assert!((v - s.velocity).norm() < 1e-7, "{k}: {v} {}", s.velocity);
            assert!(
                (a - s.acceleration).norm() < 1e-4,
                "{k}: {a} {}",
                s.acceleration
            );
        }
        assert!(checked > 900, "{checked}");
    }
    assert!(PathContour::new(
        ToolPath::ellipse(Vector3::zeros(), Vector3::x(), Vector3::y()),
        0.0
    )
    .is_err());
}

/// The UR5 rectangle's corner orientations: the tool pointing down as at the seed, turned
/// about the vertical by a different angle at each corner (up to 0.4 rad).
fn turned_corners(s: &Scenario) -> Vec<[f64; 3]> {
    let robot = s.robot().unwrap();
    let seed = s.contour.cartesian().unwrap().seed.clone();
    let (r0, _) = robot.tool_pose(&seed).unwrap();
    [0.0, 0.4, -0.3, 0.2]
        .iter()
        .map(|yaw| {
            let r = nalgebra::Rotation3::from_axis_angle(&Vector3::z_axis(), *yaw)
                * nalgebra::Rotation3::from_matrix_unchecked(r0);
            let (a, b, c) = r.euler_angles();
            [a, b, c]
        })
        .collect()
}

/// The orientation along an SE(3) path: the corner's own at the path's point closest to it,
/// continuous along the path, and its body rate the derivative of the rotation by arc length.
#[test]
fn corner_orientations_are_continuous_with_their_rate() {
    let mut s = ur5_task();
    let c = s.contour.cartesian_mut().unwrap();
    c.fixed_orientation = false;
    let turned = turned_corners(&s);
    let c = s.contour.cartesian_mut().unwrap();
    c.orientations = turned;
    let corners = c.corner_orientations().unwrap();
    let path = c.path(Path::new(".")).unwrap();
    for (p, [r, pi, y]) in c.points.iter().zip(&c.orientations) {
        let want = nalgebra::UnitQuaternion::from_euler_angles(*r, *pi, *y);
        let (got, _) = corners.at(path.closest(&Vector3::from(*p)).along);
        let err = nalgebra::UnitQuaternion::from_matrix(
            &(got * want.to_rotation_matrix().into_inner().transpose()),
        )
        .angle();
        assert!(err < 1e-9, "{err}");
    }
    let h = 1e-5;
    for k in 0..2000 {
        let s = path.length() * (k as f64 + 0.37) / 2000.0;
        let (r, rate) = corners.at(s);
        let (rp, _) = corners.at(s + h);
        let (rm, _) = corners.at(s - h);
        let step = crate::common::small_rotation;
        // Continuous: neighbours within the rate's turn; the rate is the central difference.
        assert!(step(&rm, &rp).norm() < 2.0 * h * rate.norm() + 1e-9);
        let fd = (step(&r, &rp) - step(&r, &rm)) / (2.0 * h);
        assert!(
            (fd - rate).norm() < 1e-6 * (1.0 + rate.norm()),
            "{k}: {fd} {rate}"
        );
    }
}

/// The worst angle (rad) over the steady passes between the tool's orientation and the SE(3)
/// path's at the tool's closest point, and the budget, of `s` run.
fn se3_run(s: &Scenario) -> (f64, pvfc_sim::trace::path_budget::PathBudget) {
    let t = simulate(s, &mut |_| {}).unwrap();
    let robot = s.robot().unwrap();
    let b = path_budget(s, &robot, &t).unwrap().unwrap();
    let c = s.contour.cartesian().unwrap();
    let corners = c.corner_orientations().unwrap();
    let path = c.path(Path::new(".")).unwrap();
    let range = pvfc_sim::trace::path_budget::steady_passes(&t, s.period()).unwrap();
    let mut worst = 0.0f64;
    for q in t.q.rows(range) {
        let (r, p) = robot.tool_pose(q).unwrap();
        let (want, _) = corners.at(path.closest(&p).along);
        let err = nalgebra::UnitQuaternion::from_matrix(&(r * want.transpose())).angle();
        worst = worst.max(err);
    }
    (worst, b)
}

/// An SE(3) path: the UR5 rectangle whose tool turns about the vertical from corner to
/// corner, with friction. With the task-space field (at `Ē = 40 J`) the tool stays within the
/// machining target along the surface and within 4 mrad of the path's orientation over the
/// steady passes (measured 3.4 mrad); so does the file's joint contour (`h = 16`, `Ē = 400 J`:
/// 2.7 mrad, of which its spline's rounding of the orientation's kinks at the corners is
/// 1.9 mrad of geometry).
#[test]
fn the_task_space_field_follows_an_se3_path() {
    let mut s = ur5_task();
    let turned = turned_corners(&s);
    let c = s.contour.cartesian_mut().unwrap();
    c.fixed_orientation = false;
    c.orientations = turned;
    s.baseline = None;
    s.duration = 25.0;
    s.validate().unwrap();
    let (task, b) = se3_run(&s);
    let mut joint = s.clone();
    joint.contour.cartesian_mut().unwrap().task = None;
    // The file's level: the joint-space field's approach from the seed needs it.
    joint.controller.energy = 400.0;
    let (by_joint, bj) = se3_run(&joint);
    println!("task-space field: orientation {task:.2e} rad at most; {b}");
    println!("joint contour: orientation {by_joint:.2e} rad at most; {bj}");
    let surface = b.surface.unwrap();
    assert!(surface.mean <= 1e-4 && surface.max <= 3e-4, "{b}");
    assert!(task < 4e-3 && by_joint < 4e-3, "{task} vs {by_joint}");
}

/// Frictionless and in continuous time, PVFC with the task-space field keeps κ_a (the audit
/// of the coupling's worklessness): what drifts is the RK4 integration's error, which falls
/// as dt⁴ (halving the plant's step divides it by ~16) and is below 1e-8 of κ_a(0) at
/// 32 plant steps per control period; the tool comes onto the path.
#[test]
fn the_task_space_field_keeps_the_augmented_energy() {
    let drift = |substeps: usize| {
        let mut s = ur5_task();
        s.duration = 2.0;
        s.plant.friction = Default::default();
        s.controller.friction_compensation = None;
        s.controller.nominal_speed = None;
        s.simulation.mode = Mode::Continuous;
        s.simulation.plant_substeps = substeps;
        let t = simulate(&s, &mut |_| {}).unwrap();
        let e0 = t.energy[0];
        let u = &t.potential;
        assert!(
            u[u.len() - 1] < 1e-2 * u[0],
            "U {} -> {}",
            u[0],
            u[u.len() - 1]
        );
        t.energy.iter().map(|e| (e - e0).abs()).fold(0.0, f64::max) / e0
    };
    let (d8, d16, d32) = (drift(8), drift(16), drift(32));
    println!("κ_a drift of κ_a(0): {d8:.2e}, {d16:.2e}, {d32:.2e} at 8, 16, 32 steps per period");
    assert!(d8 / d16 > 10.0 && d16 / d32 > 10.0, "not fourth order");
    assert!(d32 < 1e-8, "κ_a drift {d32:e}");
}

/// The UR5 rectangle with joint friction (80 % compensated), the tool held pointing down:
/// over the steady passes the tool is within the machining target along the surface (mean
/// ≤ 0.1 mm, max ≤ 0.3 mm) at ≥ 50 mm/s. The budget says the field follows the exact path;
/// the timed tracker's still reports the joint contour's geometry.
#[test]
fn the_task_space_field_holds_the_tool_on_the_path() {
    let s = ur5_task();
    let runs = pvfc_sim::run::run_scenario(&s, &mut |_| {}).unwrap();
    let robot = s.robot().unwrap();
    let b = path_budget(&s, &robot, &runs[0]).unwrap().unwrap();
    println!("{b}");
    assert!(b.geometry.is_none());
    let surface = b.surface.unwrap();
    assert!(surface.mean <= 1e-4 && surface.max <= 3e-4, "{b}");
    assert!(b.speed >= 0.05, "{b}");
    let timed = path_budget(&s, &robot, &runs[1]).unwrap().unwrap();
    assert!(timed.geometry.is_some());
}

/// With contact on a table, the audits hold with the task-space field: continuous (the
/// energy balance to 1e-8 of κ_a(0)) and the passive digital controller (exact at the
/// samples).
#[cfg(feature = "contact")]
#[test]
fn the_audits_hold_with_the_task_space_field() {
    for mode in [Mode::Continuous, Mode::Sampled] {
        let mut s = ur5_task();
        s.simulation.mode = mode;
        match mode {
            // RK4's error at 32 plant steps per period (see above).
            Mode::Continuous => s.simulation.plant_substeps = 32,
            _ => s.controller.passive = Some(Default::default()),
        }
        s.duration = 3.0;
        // A table whose top is 3 mm above the tool ball's lowest point on the path.
        s.contact_3d = Some(crate::common::table_under_the_rectangle());
        s.validate().unwrap();
        let t = simulate(&s, &mut |_| {}).unwrap();
        let c = t.contact.as_ref().unwrap();
        let peak = c.normal_force.iter().fold(0.0_f64, |m, f| m.max(*f));
        let audit = c
            .audit_residual(&t.energy)
            .iter()
            .fold(0.0_f64, |m, r| m.max(r.abs()));
        println!(
            "{mode:?}: peak {peak:.2} N, audit {audit:.1e} of {:.1} J",
            t.energy[0]
        );
        assert!(peak > 1.0, "{mode:?}: no contact");
        assert!(audit < 1e-8 * t.energy[0], "{mode:?}: audit {audit:e} J");
    }
}

/// Bad task settings are errors that name the key.
#[test]
fn bad_task_settings_name_the_key() {
    let err = |f: &dyn Fn(&mut TaskSpec)| {
        let mut s = ur5_task();
        if let Some(c) = s.contour.cartesian_mut() {
            let mut t = TaskSpec::default();
            f(&mut t);
            c.task = Some(t);
        }
        s.validate().unwrap_err().to_string()
    };
    assert!(err(&|t| t.stiffness = Some(-1.0)).contains("task.stiffness"));
    assert!(err(&|t| t.damping = Some(0.0)).contains("task.damping"));
    assert!(
        err(&|t| t.orientation_stiffness = Some(f64::NAN)).contains("task.orientation_stiffness")
    );
    assert!(err(&|t| t.rest_gain = Some(f64::INFINITY)).contains("task.rest_gain"));
    // Orientations along the path and a fixed orientation: one or the other.
    let mut s = ur5_task();
    let turned = turned_corners(&s);
    if let Some(c) = s.contour.cartesian_mut() {
        c.orientations = turned;
    }
    let e = s.validate().unwrap_err().to_string();
    assert!(
        e.contains("give one of orientations, tool_frame and fixed_orientation"),
        "{e}"
    );
}

/// A stiff field far from the path: with `k = 10/s` the UR5's start (17 cm off the rectangle)
/// asks more than `Ē = 40 J` of `U = ½k|e|²`'s field, a typed error; saturated at 2 cm
/// (`[contour.cartesian.task] saturation`) the pull is bounded, the run starts, reaches the
/// path, and the start's torque peak falls.
#[test]
fn a_saturated_field_starts_far_from_the_path() {
    let with = |saturation: Option<f64>, k: f64| {
        let mut s = ur5_task();
        s.duration = 12.0;
        s.baseline = None;
        if let Some(c) = s.contour.cartesian_mut() {
            c.task = Some(TaskSpec {
                stiffness: Some(k),
                saturation,
                ..TaskSpec::default()
            });
        }
        s
    };
    let e = simulate(&with(None, 10.0), &mut |_| {}).unwrap_err();
    assert!(e.to_string().contains("energy level too low"), "{e}");
    let peak = |t: &pvfc_sim::trace::Trace| {
        (0..t.len())
            .flat_map(|i| t.torque[i].iter().map(|x| x.abs()).collect::<Vec<_>>())
            .fold(0.0, f64::max)
    };
    let stiff = simulate(&with(Some(0.02), 10.0), &mut |_| {}).unwrap();
    let plain = simulate(&with(None, 4.0), &mut |_| {}).unwrap();
    let soft = simulate(&with(Some(0.02), 4.0), &mut |_| {}).unwrap();
    let n = stiff.len() - 1;
    println!(
        "k = 10, ℓ = 2 cm: U {:.2e} → {:.2e}, peak torque {:.0} N·m; k = 4: peak {:.0} N·m plain, {:.0} saturated",
        stiff.potential[0],
        stiff.potential[n],
        peak(&stiff),
        peak(&plain),
        peak(&soft)
    );
    assert!(stiff.potential[n] < 1e-3 * stiff.potential[0]);
    assert!(peak(&soft) < 0.5 * peak(&plain));
    // The field bounded at 90 % of Ē instead (`controller.field_energy_bound`): the same stiff
    // field from the same start runs, scaled onto the bound while far, and reaches the path.
    let mut bounded = with(None, 10.0);
    bounded.controller.field_energy_bound = Some(0.9);
    let b = simulate(&bounded, &mut |_| {}).unwrap();
    let m = b.len() - 1;
    println!(
        "k = 10 bounded at 0.9 Ē: U {:.2e} → {:.2e}, peak torque {:.0} N·m",
        b.potential[0],
        b.potential[m],
        peak(&b)
    );
    assert!(b.potential[m] < 1e-3 * b.potential[0]);
    for share in [0.0, 1.0, f64::NAN] {
        let mut bad = with(None, 10.0);
        bad.controller.field_energy_bound = Some(share);
        let e = bad.validate().unwrap_err().to_string();
        assert!(e.contains("controller.field_energy_bound"), "{e}");
        let e = simulate(&bad, &mut |_| {}).unwrap_err().to_string();
        assert!(e.contains("field_energy_bound"), "{e}");
    }
    // Bad distances are named.
    let mut bad = with(Some(-0.01), 4.0);
    bad.duration = 0.1;
    let e = bad.validate().unwrap_err().to_string();
    assert!(e.contains("task.saturation"), "{e}");
}
