//! The plant's joint friction: Coulomb + viscous with a regularised sign, and the Stribeck
//! peak (stiction): its curve, its power, its settings' errors, and the energy audit of a run
//! with it.

use nalgebra::Vector2;
use pvfc_sim::error::SimError;
use pvfc_sim::plant::friction::{JointFriction, Stribeck};
use pvfc_sim::run::simulate;
use pvfc_sim::scenario::{presets, Scenario};
use pvfc_sim::trace::metrics::energy_audit;
use std::path::Path;

fn stribeck() -> JointFriction {
    JointFriction {
        coulomb: vec![2.0, 3.0],
        viscous: vec![0.1, 0.0],
        stiction_velocity: 1e-3,
        stribeck: Some(Stribeck {
            breakaway: vec![3.0, 6.0],
            velocity: 0.1,
        }),
    }
}

#[test]
fn the_stribeck_curve_falls_from_breakaway_to_coulomb() {
    let f = stribeck();
    // Just past the regularised sign's band the level is the breakaway one.
    let near = f.torque(&Vector2::new(0.02, 0.02));
    let expect = |fs: f64, fc: f64, b: f64, v: f64| {
        -(b * v + (fc + (fs - fc) * (-(v / 0.1f64).powi(2)).exp()) * (v / 1e-3f64).tanh())
    };
    assert!((near[0] - expect(3.0, 2.0, 0.1, 0.02)).abs() < 1e-12);
    assert!((near[1] - expect(6.0, 3.0, 0.0, 0.02)).abs() < 1e-12);
    assert!(near[1] < -5.7, "near breakaway: {}", near[1]);
    // Far past the Stribeck velocity, Coulomb + viscous.
    let far = f.torque(&Vector2::new(-2.0, 1.0));
    assert!((far[0] - (0.2 + 2.0)).abs() < 1e-9, "{}", far[0]);
    assert!((far[1] + 3.0).abs() < 1e-9, "{}", far[1]);
    // It always opposes the motion (the friction power is never positive), and is odd.
    for k in -200..=200 {
        let v = Vector2::new(f64::from(k) * 0.013, f64::from(-k) * 0.007);
        let t = f.torque(&v);
        assert!(t.dot(&v) <= 0.0);
        assert_eq!(f.torque(&-v), -t);
    }
    // Without the peak, the model is the Coulomb one.
    let coulomb = JointFriction {
        stribeck: None,
        ..stribeck()
    };
    let v = Vector2::new(0.5, -0.05);
    let diff = f.torque(&v) - coulomb.torque(&v);
    assert!(
        diff[0] < 0.0 && diff[1] > 0.0,
        "the peak adds to the level: {diff}"
    );
}

#[test]
fn bad_stribeck_settings_are_named_errors() {
    let mut f = stribeck();
    f.stribeck.as_mut().unwrap().breakaway[1] = 2.5;
    let m = f.validate().unwrap_err().to_string();
    assert!(m.contains("breakaway[1]") && m.contains("Coulomb"), "{m}");
    let mut f = stribeck();
    f.stribeck.as_mut().unwrap().velocity = 0.0;
    let m = f.validate().unwrap_err().to_string();
    assert!(m.contains("stribeck.velocity"), "{m}");
    let mut f = stribeck();
    f.stribeck.as_mut().unwrap().breakaway = vec![3.0];
    let m = f.validate_for(2).unwrap_err().to_string();
    assert!(
        m.contains("stribeck.breakaway") && m.contains("1 entries"),
        "{m}"
    );
    let text = "name = \"x\"\nduration = 1.0\n[plant.friction]\ncoulomb = [1.0, 1.0]\n[plant.friction.stribeck]\nbreakaway = [2.0, 2.0]\nspeed = 0.1\n";
    match Scenario::from_toml(text, Path::new("x.toml")) {
        Err(SimError::Scenario { message, .. }) => {
            assert!(message.contains("speed"), "{message}")
        }
        other => panic!("an unknown key is an error: {other:?}"),
    }
}

#[test]
fn a_run_with_stiction_keeps_its_energy_audit() {
    // Fig. 9's run with the peak, without the add-on (36), continuous at 10 kHz: the energy
    // changes only by the friction's work.
    let mut unforced = presets::stribeck(false, 100);
    unforced.duration = 5.0;
    unforced.controller.nominal_speed = None;
    unforced.simulation.mode = pvfc_sim::scenario::Mode::Continuous;
    unforced.simulation.plant_substeps = 1;
    unforced.controller.rate = 10_000.0;
    let u = simulate(&unforced, &mut |_| {}).expect("the run is valid");
    let audit = energy_audit(&u);
    println!("energy audit residual {audit:.1e} of κ_a(0)");
    assert!(audit < 1e-6, "energy audit residual {audit:e}");
    assert!(
        u.energy[u.len() - 1] < u.energy[0] - 1.0,
        "friction took energy"
    );
}
