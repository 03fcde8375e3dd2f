//! The passive digital controller (`pvfc_core::passive`): its energy balance over one held
//! period against a finely integrated plant, at random states, periods, limits and external
//! torques; its errors; its convergence to the ZOH controller as the period goes to zero.

use nalgebra::Vector2;
use proptest::prelude::*;
use pvfc_core::passive::PassiveController;
use pvfc_core::prelude::*;

type Field = SuspendedField<
    f64,
    Torus<f64, 2>,
    Lissajous<f64, 2>,
    TorusNavigation<f64, 2>,
    ExponentialPacing<f64>,
    2,
>;
type Passive = PassiveController<f64, Torus<f64, 2>, Scara<f64>, Field, 2>;

fn controller(energy: f64, gamma: f64) -> Controller<f64, Torus<f64, 2>, Scara<f64>, Field, 2> {
    let field = SuspendedField::new(
        Lissajous::<f64, 2>::paper(),
        TorusNavigation::paper(Vector2::new(1.0, 1.0)).unwrap(),
        ExponentialPacing::new(5.0).unwrap(),
    );
    let law = PvfcLaw::new(
        Scara::pelican(),
        field,
        Flywheel::new(1.0, energy).unwrap(),
        gamma,
    )
    .unwrap();
    Controller::new(law)
}

/// The plant over one held period: RK4 in `n` substeps under `u + f_e`, frictionless.
fn plant(
    q: Torus<f64, 2>,
    v: Vector2<f64>,
    u: Vector2<f64>,
    h: f64,
    n: usize,
) -> (Torus<f64, 2>, Vector2<f64>) {
    let arm = Scara::<f64>::pelican();
    let dt = h / n as f64;
    let (mut q, mut v) = (q, v);
    let acc = |q: &Torus<f64, 2>, v: &Vector2<f64>| arm.acceleration(q, v, &u).unwrap();
    for _ in 0..n {
        let a1 = acc(&q, &v);
        let (q2, v2) = (q.retract(&v, 0.5 * dt), v + a1 * (0.5 * dt));
        let a2 = acc(&q2, &v2);
        let (q3, v3) = (q.retract(&v2, 0.5 * dt), v + a2 * (0.5 * dt));
        let a3 = acc(&q3, &v3);
        let (q4, v4) = (q.retract(&v3, dt), v + a3 * dt);
        let a4 = acc(&q4, &v4);
        q = q.retract(&((v + v2 * 2.0 + v3 * 2.0 + v4) / 6.0), dt);
        v += (a1 + a2 * 2.0 + a3 * 2.0 + a4) * (dt / 6.0);
    }
    (q, v)
}

fn kinetic(q: &Torus<f64, 2>, v: &Vector2<f64>) -> f64 {
    Scara::<f64>::pelican().kinetic_energy(q, v)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    /// Over random states, periods, limits, add-ons and external torques, two steps of the
    /// controller around one held period: the robot's kinetic energy plus the storage changes
    /// by exactly the environment's work plus the add-ons' (to the plant integrator's error),
    /// and the storage is the internal states' energy.
    #[test]
    fn one_period_creates_no_energy(
        q in prop::array::uniform2(-3.0f64..3.0),
        v in prop::array::uniform2(-2.0f64..2.0),
        tau in 0.0f64..6.0,
        tau_dot in -1.0f64..1.0,
        flywheel in 0.5f64..12.0,
        h in 1e-4f64..2e-2,
        limit in prop::option::of(0.5f64..20.0),
        fe in prop::array::uniform2(-5.0f64..5.0),
        add_ons in any::<bool>(),
        positions_only in any::<bool>(),
    ) {
        let mut c = controller(100.0, 0.5).with_state(InternalState {
            tau, tau_dot, flywheel_speed: flywheel, laps: 0,
        });
        if add_ons {
            c = c
                .with_nominal_speed(NominalSpeed::new(0.5, 1.0).unwrap())
                .with_friction_compensation(FrictionCompensation::new(Vector2::new(2.0, 3.0)).unwrap().with_band(0.1).unwrap());
        }
        let mut ctl: Passive = PassiveController::new(c);
        if let Some(l) = limit {
            ctl = ctl.with_torque_limits(Vector2::new(l, l)).unwrap();
        }
        let (q0, v0) = (Torus::new(Vector2::from(q)), Vector2::from(v));
        let vel = (!positions_only).then_some(&v0);
        let first = ctl.step(&q0, vel, None, h).unwrap();
        prop_assert!(first.torque.iter().all(|t| limit.is_none_or(|l| t.abs() <= l)));
        let s0 = first.energy.storage;
        let fe = Vector2::from(fe);
        let (q1, v1) = plant(q0, v0, first.torque + fe, h, 200);
        let second = ctl.step(&q1, Some(&v1), None, h).unwrap();
        let env = fe.dot(&(q1.angles() - q0.angles()));
        let before = kinetic(&q0, &v0) + s0;
        let after = kinetic(&q1, &v1) + second.energy.storage;
        let residual = after - before - env - second.energy.add_ons;
        prop_assert!(residual.abs() <= 1e-9 * (1.0 + before), "residual {residual:e} of {before}");
        // The storage is what the internal states hold (it did not run dry here).
        let st = second.state;
        let held = 0.5 * (st.tau_dot * st.tau_dot + st.flywheel_speed * st.flywheel_speed);
        if second.energy.storage >= 0.0 {
            prop_assert!((held - second.energy.storage).abs() <= 1e-9 * (1.0 + held));
        }
    }
}

#[test]
fn bad_input_is_a_typed_error_and_changes_nothing() {
    let mut ctl: Passive = PassiveController::new(controller(50.0, 1.0).starting_at_rest(0.0));
    let q = Torus::new(Vector2::new(0.1, 0.2));
    ctl.step(&q, None, None, 1e-3).unwrap();
    let before = ctl;
    let nan = Vector2::new(f64::NAN, 0.0);
    for (q, v, u, dt, kind) in [
        (q, None, None, 0.0, ErrorKind::InvalidParameter),
        (q, None, None, f64::INFINITY, ErrorKind::InvalidParameter),
        (Torus::new(nan), None, None, 1e-3, ErrorKind::NonFinite),
        (q, Some(&nan), None, 1e-3, ErrorKind::NonFinite),
        (q, None, Some(&nan), 1e-3, ErrorKind::NonFinite),
    ] {
        assert_eq!(ctl.step(&q, v, u, dt).unwrap_err().kind(), kind);
        assert_eq!(ctl, before, "an error changed the controller");
    }
    let c = PassiveController::new(controller(50.0, 1.0));
    assert!(c.with_torque_limits(Vector2::new(1.0, 0.0)).is_err());
    assert!(c.with_torque_limits(Vector2::new(1.0, f64::NAN)).is_err());
    assert!(c.with_velocity_filter(-1.0).is_err());
    assert!(c.with_reserve(f64::NAN).is_err());
    assert!(c
        .with_encoder_resolution(Vector2::new(-1e-5, 1e-5))
        .is_err());
}

/// Without a measured velocity and `T_f = 0`, the law sees the backward difference of the
/// positions (wrapped across ±π).
#[test]
fn the_velocity_estimate_is_the_backward_difference() {
    let mut ctl: Passive = PassiveController::new(controller(50.0, 1.0).starting_at_rest(0.0));
    let h = 1e-3;
    let q0 = Torus::new(Vector2::new(3.1, -0.5));
    let q1 = Torus::new(Vector2::new(-3.1, -0.49));
    ctl.step(&q0, None, None, h).unwrap();
    let out = ctl.step(&q1, None, None, h).unwrap();
    let expect = Vector2::new(2.0 * std::f64::consts::PI - 6.2, 0.01) / h;
    assert!((out.velocity - expect).amax() < 1e-9, "{:?}", out.velocity);
}

/// The tank: with a reserve just below the storage, the coupling that would accelerate the
/// robot (drawing from the storage) is scaled down, and the storage stays at the reserve up
/// to the one-period prediction's error.
#[test]
fn a_dry_tank_scales_the_coupling() {
    let c = controller(50.0, 1.0).starting_at_rest(0.0);
    let reserve = 50.0 - 0.01;
    let mut ctl: Passive = PassiveController::new(c).with_reserve(reserve).unwrap();
    let (mut q, mut v) = (Torus::new(Vector2::new(0.5, 1.0)), Vector2::new(0.0, 0.0));
    let h = 1e-3;
    let mut scaled = 0;
    let mut lowest = f64::INFINITY;
    for _ in 0..2000 {
        let out = ctl.step(&q, Some(&v), None, h).unwrap();
        scaled += usize::from(out.energy.scale < 1.0);
        lowest = lowest.min(out.energy.storage);
        (q, v) = plant(q, v, out.torque, h, 10);
    }
    assert!(
        scaled > 100,
        "the tank scaled the coupling at {scaled} steps only"
    );
    assert!(
        lowest > reserve - 1e-4,
        "the storage fell to {lowest} below the reserve {reserve}"
    );
    assert!(
        kinetic(&q, &v) <= 0.01 + 1e-4,
        "the robot got more than the tank could give"
    );
}

/// As the period goes to zero the passive controller becomes the ZOH controller: the energy
/// the projection corrects falls at least as h² per step, and the two runs' contour errors
/// agree.
#[test]
fn the_correction_vanishes_as_the_period_goes_to_zero() {
    let run = |h: f64| {
        let c = controller(50.0, 1.0).starting_at_rest(0.0);
        let mut passive: Passive = PassiveController::new(c);
        let mut zoh = c;
        let (mut q, mut v) = (Torus::new(Vector2::new(0.3, 1.0)), Vector2::zeros());
        let (mut qz, mut vz) = (q, v);
        let mut correction = 0.0f64;
        let steps = (0.5 / h).round() as usize;
        let mut u = (0.0, 0.0);
        for _ in 0..steps {
            let out = passive.step(&q, Some(&v), None, h).unwrap();
            correction = correction.max(out.energy.correction.abs());
            u.0 = out.diagnostics.potential;
            (q, v) = plant(q, v, out.torque, h, 4);
            let oz = zoh.step(&qz, &vz, h).unwrap();
            u.1 = oz.diagnostics.potential;
            (qz, vz) = plant(qz, vz, oz.torque, h, 4);
        }
        (correction, u)
    };
    let (c1, u1) = run(2e-3);
    let (c2, u2) = run(1e-3);
    assert!(
        c2 < c1 / 3.0,
        "max correction per step {c1:e} at 2 ms, {c2:e} at 1 ms"
    );
    for (a, b) in [u1, u2] {
        assert!(
            (a - b).abs() <= 0.05 * a.max(b) + 1e-9,
            "U passive {a:e}, ZOH {b:e}"
        );
    }
}

/// Torque limits clamp each joint's command to `±limit` and report it: at states where the
/// law asks for more than the limit on one joint only, that joint is clamped, the other is
/// the unlimited controller's torque, and `saturated` is set; within the limits nothing
/// changes and `saturated` is clear.
#[test]
fn torque_limits_clamp_each_joint_and_report_it() {
    let free = PassiveController::new(controller(50.0, 1.0).starting_at_rest(0.0));
    let (mut clamped_some, mut clear_some) = (false, false);
    for k in 0..40 {
        let q = Torus::new(Vector2::new(0.1 * k as f64 - 2.0, 0.3 - 0.05 * k as f64));
        let v = Vector2::new(0.2 * (k % 7) as f64 - 0.6, 0.1 * (k % 5) as f64 - 0.2);
        let mut unlimited = free; // (a copy)
        let want = unlimited.step(&q, Some(&v), None, 1e-3).unwrap().torque;
        // Joint 0 limited below what the law asks (when it asks anything), joint 1 above it.
        let limits = Vector2::new(0.5 * want[0].abs(), 2.0 * want[1].abs() + 1.0);
        if limits[0] <= 0.0 {
            continue;
        }
        let mut ctl = free.with_torque_limits(limits).unwrap();
        let out = ctl.step(&q, Some(&v), None, 1e-3).unwrap();
        assert_eq!(
            out.torque[0],
            limits[0].copysign(want[0]),
            "joint 0 at step {k}"
        );
        assert_eq!(out.torque[1], want[1], "joint 1 at step {k}");
        assert!(out.energy.saturated);
        clamped_some = true;
        let mut ctl = free
            .with_torque_limits(want.abs() * 2.0 + Vector2::repeat(1.0))
            .unwrap();
        let out = ctl.step(&q, Some(&v), None, 1e-3).unwrap();
        assert_eq!(out.torque, want);
        assert!(!out.energy.saturated);
        clear_some = true;
    }
    assert!(clamped_some && clear_some);
}
