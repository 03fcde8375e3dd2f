//! A disturbance torque in scenarios (`[plant.disturbance]`): the sinusoids it gives, its
//! work counted as the environment's in the energy audit (the SCARA and a URDF arm, continuous
//! and sampled), and bad lists named.

use pvfc_sim::plant::disturbance::Disturbance;
use pvfc_sim::run::simulate;
use pvfc_sim::scenario::{presets, Mode, Scenario};
use pvfc_sim::trace::Trace;
use std::path::Path;

fn ur5() -> Scenario {
    Scenario::from_file(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/ur5_waypoints.toml"),
    )
    .unwrap()
}

/// The largest audit residual relative to `κ_a(0)`, and the largest magnitude of the
/// environment's (here: the disturbance's) work relative to it.
fn audit(t: &Trace) -> (f64, f64) {
    let c = t
        .contact
        .as_ref()
        .expect("a disturbed run keeps the work columns");
    let e0 = t.energy[0];
    let max_abs = |x: &mut dyn Iterator<Item = f64>| x.fold(0.0_f64, |m, r| m.max(r.abs()));
    (
        max_abs(&mut c.audit_residual(&t.energy).into_iter()) / e0,
        max_abs(&mut c.work_contact.iter().copied()) / e0,
    )
}

#[test]
fn the_torque_is_the_sinusoid_of_each_joint() {
    let d = Disturbance {
        amplitude: vec![0.5, 2.0],
        frequency: vec![1.0, 0.25],
        phase: vec![0.0, 1.0],
    };
    for t in [0.0, 0.1, 0.37, 2.0] {
        let tau = d.torque::<2>(t);
        assert_eq!(tau[0], 0.5 * (std::f64::consts::TAU * t).sin());
        assert_eq!(tau[1], 2.0 * (std::f64::consts::TAU * 0.25 * t + 1.0).sin());
    }
    let no_phase = Disturbance {
        phase: vec![],
        ..d.clone()
    };
    assert_eq!(no_phase.torque::<2>(0.0), nalgebra::Vector2::zeros());
    no_phase.validate_for(2).unwrap();
}

#[test]
fn the_disturbances_work_is_the_environments_in_the_audit() {
    // The SCARA in continuous time (the robustness preset, 5 s).
    let mut s = presets::robustness(10);
    s.duration = 5.0;
    let t = simulate(&s, &mut |_| {}).unwrap();
    let (residual, work) = audit(&t);
    println!("SCARA, continuous: audit {residual:.2e}, work {work:.2e} of κ_a(0)");
    assert!(work > 1e-3, "the disturbance did no work ({work:e})");
    assert!(residual < 1e-6, "audit {residual:e}");
    // Without it the loop is the undisturbed one (no work columns, the same first sample).
    let mut calm = s.clone();
    calm.plant.disturbance = None;
    let c = simulate(&calm, &mut |_| {}).unwrap();
    assert!(c.contact.is_none());
    assert_eq!(c.energy[0], t.energy[0]);
    assert!(c.w_beta.last() != t.w_beta.last());

    // A URDF arm, frictionless, in continuous time and with the passive sampled controller
    // (whose account is exact at the samples).
    for mode in [Mode::Continuous, Mode::Sampled] {
        let mut s = ur5();
        s.duration = 2.0;
        s.plant.friction = Default::default();
        s.controller.friction_compensation = None;
        s.simulation.mode = mode;
        s.simulation.plant_substeps = 4;
        if mode == Mode::Sampled {
            s.controller.passive = Some(Default::default());
        }
        s.plant.disturbance = Some(Disturbance {
            amplitude: vec![2.0, 2.0, 1.0, 0.5, 0.5, 0.2],
            frequency: vec![0.5, 0.7, 1.1, 1.3, 1.7, 1.9],
            phase: vec![],
        });
        let t = simulate(&s, &mut |_| {}).unwrap();
        let c = t.contact.as_ref().unwrap();
        assert_eq!((c.force.dof(), c.torque.dof(), c.tool.dof()), (3, 6, 3));
        assert!(c.normal_force.iter().all(|f| *f == 0.0));
        let (residual, work) = audit(&t);
        println!("UR5, {mode:?}: audit {residual:.2e}, work {work:.2e} of κ_a(0)");
        assert!(
            work > 1e-3,
            "{mode:?}: the disturbance did no work ({work:e})"
        );
        assert!(residual < 1e-6, "{mode:?}: audit {residual:e}");
    }
}

#[test]
fn bad_disturbances_are_named() {
    let error = |s: &Scenario| s.validate().unwrap_err().to_string();
    let d = |amplitude: Vec<f64>, phase: Vec<f64>| {
        Some(Disturbance {
            frequency: vec![1.0; amplitude.len()],
            amplitude,
            phase,
        })
    };
    let mut s = presets::robustness(1);
    s.plant.disturbance = d(vec![1.0; 3], vec![]);
    let e = error(&s);
    assert!(
        e.contains("plant.disturbance.amplitude: 3 entries for a 2-joint robot"),
        "{e}"
    );
    s.plant.disturbance = d(vec![1.0; 2], vec![0.0, f64::NAN]);
    let e = error(&s);
    assert!(
        e.contains("plant.disturbance.phase: NaN is not finite"),
        "{e}"
    );
    let mut arm = ur5();
    arm.plant.disturbance = d(vec![1.0; 2], vec![]);
    let e = error(&arm);
    assert!(
        e.contains("plant.disturbance.amplitude: 2 entries for a 6-joint robot"),
        "{e}"
    );
    // From TOML, an unknown key is named too.
    let text = presets::robustness(1)
        .to_toml()
        .unwrap()
        .replace("phase = ", "phases = ");
    let e = Scenario::from_toml(&text, Path::new("robustness.toml"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("phases"), "{e}");
}
