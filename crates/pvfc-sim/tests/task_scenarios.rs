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

/// `ur5_cartesian.toml` with the task-space field (default gains).
fn ur5_task() -> Scenario {
    let mut s = Scenario::from_file(&file("ur5_cartesian.toml")).unwrap();
    if let Some(c) = s.contour.cartesian.as_mut() {
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
    use pvfc_sim::contact::spatial::{SpatialContactSpec, SpatialObstacle, SpatialShape};
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
        s.contact_3d = Some(SpatialContactSpec {
            arm: Default::default(),
            packages: Default::default(),
            force_schedule: None,
            link_radius: 0.0,
            link_radii: vec![],
            tool_radius: 0.01,
            obstacles: vec![SpatialObstacle {
                shape: SpatialShape::Box {
                    half_extents: [0.3, 0.4, 0.05],
                },
                position: [0.55, 0.0, 0.30 - 0.01 + 0.003 - 0.05],
                rpy: [0.0; 3],
                law: None,
                motion: vec![],
            }],
            law: pvfc_sim::contact::ContactLaw {
                stiffness: 2.0e4,
                damping: 0.5,
                friction: 0.2,
                slip_velocity: 0.01,
            },
        });
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
        if let Some(c) = s.contour.cartesian.as_mut() {
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
    // Orientations along the path are the joint contour's.
    let mut s = ur5_task();
    if let Some(c) = s.contour.cartesian.as_mut() {
        c.fixed_orientation = false;
        c.orientations = vec![[std::f64::consts::PI, 0.0, 0.0]; 4];
    }
    let e = s.validate().unwrap_err().to_string();
    assert!(e.contains("orientations"), "{e}");
}
