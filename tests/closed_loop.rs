//! The closed loop of plant + PVFC integrated with RK4 (RKMK4 on SO(3)): energy balance and
//! convergence (Theorem 1, eq. 9; Theorem 2).

use nalgebra::{Matrix3, Vector2, Vector3};
use pvfc::prelude::*;
use pvfc::sim::scenario::presets::pelican_example;
use pvfc::sim::ClosedLoop;

fn paper_start(
    ctl: &pvfc::sim::scenario::PaperController,
) -> AugmentedState<f64, Torus<f64, 2>, 2> {
    let i = ctl.state();
    AugmentedState {
        q: Torus::new(Vector2::new(0.0, 0.0)),
        v: Vector2::zeros(),
        tau: i.tau,
        tau_dot: i.tau_dot,
        flywheel_speed: i.flywheel_speed,
    }
}

/// 10 s at 1 kHz, no environment force, from q = (0, 0) at rest with the energy in the
/// flywheel: κ_a stays constant (relative drift ≤ 1e-6), U(E) falls towards 0, and
/// τ̇ → βλ₁ (Theorem 2). For R = 0 (no self-pacing) and R = 100.
#[test]
fn scara_on_lissajous_conserves_energy_and_converges() {
    for r in [0.0, 100.0] {
        let mut example = pelican_example();
        example.controller.self_pacing = r;
        let ctl = example.controller().unwrap();
        let sys = ClosedLoop::matched(ctl);
        let mut s = paper_start(&ctl);
        let zero = Vector2::zeros();
        let e0 = sys.kinetic_energy(&s);
        let u0 = sys.evaluate(&s, &zero).unwrap().coupling.field.potential;
        let mut worst_drift: f64 = 0.0;
        let mut u_max_late: f64 = 0.0;
        for k in 0..10_000 {
            s = sys.rk4_step(&s, 1e-3, &zero).unwrap();
            worst_drift = worst_drift.max((sys.kinetic_energy(&s) - e0).abs() / e0);
            if k >= 9_000 {
                u_max_late =
                    u_max_late.max(sys.evaluate(&s, &zero).unwrap().coupling.field.potential);
            }
        }
        let out = sys.evaluate(&s, &zero).unwrap().coupling;
        assert!(worst_drift <= 1e-6, "R = {r}: energy drift {worst_drift:e}");
        assert!(u0 > 0.4, "starts off the contour: U(0) = {u0}");
        assert!(
            u_max_late < 1e-4 * u0,
            "R = {r}: U over the last second up to {u_max_late:e} (U(0) = {u0})"
        );
        let expected = out.beta * out.field.lambda1;
        assert!(
            (s.tau_dot - expected).abs() < 1e-3,
            "R = {r}: τ̇ = {} vs βλ₁ = {expected}",
            s.tau_dot
        );
        assert!(
            (out.beta - 1.0).abs() < 1e-6,
            "β stays 1 without environment force"
        );
        // The robot actually went round the contour (τ advanced by more than one period).
        assert!(s.tau > 6.0, "R = {r}: τ = {}", s.tau);
    }
}

/// Self-pacing: from (0, 0) with R = 100, τ barely advances while U is large.
#[test]
fn self_pacing_holds_tau_while_far_from_the_contour() {
    let zero = Vector2::zeros();
    let run = |r: f64| {
        let mut example = pelican_example();
        example.controller.self_pacing = r;
        let ctl = example.controller().unwrap();
        let sys = ClosedLoop::matched(ctl);
        let mut s = paper_start(&ctl);
        for _ in 0..500 {
            s = sys.rk4_step(&s, 1e-3, &zero).unwrap();
        }
        s.tau
    };
    let (paced, free) = (run(100.0), run(0.0));
    assert!(
        paced < 0.01 && free > 0.3,
        "τ(0.5 s): R = 100 → {paced}, R = 0 → {free}"
    );
}

/// Passivity with an environment force (eq. 9): κ_a(t) − κ_a(0) = ∫ F_eᵀ q̇ dt. The force is
/// held over each step, so the work of a step is exactly F_eᵀ Δq on the torus.
#[test]
fn energy_balance_with_an_environment_force() {
    let ctl = pelican_example().controller().unwrap();
    let sys = ClosedLoop::matched(ctl);
    let mut s = paper_start(&ctl);
    let e0 = sys.kinetic_energy(&s);
    let mut work = 0.0;
    let mut worst: f64 = 0.0;
    let mut min_work: f64 = 0.0;
    for k in 0..5_000 {
        let t = k as f64 * 1e-3;
        // A disturbance that pushes and brakes: 0.3 N·m-scale, changing sign.
        let f = Vector2::new(
            0.3 * (3.0 * t).sin(),
            -0.2 * (5.0 * t).cos() - 0.05 * s.v[1],
        );
        let next = sys.rk4_step(&s, 1e-3, &f).unwrap();
        work += f.dot(&(next.q.angles() - s.q.angles()));
        s = next;
        worst = worst.max((sys.kinetic_energy(&s) - e0 - work).abs() / e0);
        min_work = min_work.min(work);
    }
    assert!(worst < 1e-8, "energy audit residual {worst:e}");
    // Passivity (eq. 1): the environment can take out at most what was stored.
    assert!(min_work >= -e0);
    assert!(work.abs() > 1e-3, "the force did work: {work}");
}

/// A rigid body on SO(3) following a constant-rate rotation: energy is conserved, the
/// attitude stays a rotation, and the error converges.
#[test]
fn rigid_body_on_so3_conserves_energy_and_converges() {
    let j = Matrix3::<f64>::from_diagonal(&Vector3::new(0.8, 1.2, 1.5));
    let p = Matrix3::from_diagonal(&Vector3::new(1.0, 2.0, 3.0));
    let field = SuspendedField::new(
        ConstantRate::new(So3::identity(), Vector3::new(0.0, 0.3, 0.6)).unwrap(),
        So3Navigation::new(p).unwrap(),
        ExponentialPacing::new(20.0).unwrap(),
    );
    let law = PvfcLaw::new(
        RigidBody::new(j).unwrap(),
        field,
        Flywheel::new(1.0, 20.0).unwrap(),
        0.1,
    )
    .unwrap();
    let ctl = Controller::new(law).starting_at_rest(0.0);
    let sys = ClosedLoop::matched(ctl);
    let mut s = AugmentedState {
        q: So3::exp(&Vector3::new(1.2, -0.8, 0.5)),
        v: Vector3::zeros(),
        tau: 0.0,
        tau_dot: 0.0,
        flywheel_speed: ctl.state().flywheel_speed,
    };
    let zero = Vector3::zeros();
    let e0 = sys.kinetic_energy(&s);
    let u0 = sys.evaluate(&s, &zero).unwrap().coupling.field.potential;
    let mut drift: f64 = 0.0;
    for _ in 0..20_000 {
        s = sys.rk4_step(&s, 1e-3, &zero).unwrap();
        drift = drift.max((sys.kinetic_energy(&s) - e0).abs() / e0);
    }
    let u = sys.evaluate(&s, &zero).unwrap().coupling.field.potential;
    assert!(drift < 1e-6, "energy drift {drift:e}");
    assert!(u < 1e-6 * u0, "U: {u0} → {u}");
    assert!(
        s.q.orthogonality_error() < 1e-12,
        "orthogonality {:e}",
        s.q.orthogonality_error()
    );
}

/// The digital controller (`step`, semi-implicit Euler on its internal states, torque held
/// for 1 ms) on the same plant integrated finely also converges; its energy is not exactly
/// conserved (the sampled loop is not exactly passive) but stays within 1 %.
#[test]
fn sampled_data_controller_follows_the_contour() {
    let mut ctl = pelican_example().controller().unwrap();
    let plant = Scara::<f64>::pelican();
    let (mut q, mut v) = (Torus::new(Vector2::new(0.0, 0.0)), Vector2::<f64>::zeros());
    let sub = 10;
    let mut u_last = f64::INFINITY;
    let mut e_rel: f64 = 0.0;
    let mf = ctl.law().flywheel().inertia();
    let e0 = 0.5 * mf * ctl.state().flywheel_speed.powi(2);
    for _ in 0..10_000 {
        let out = ctl.step(&q, &v, 1e-3).unwrap();
        u_last = out.diagnostics.potential;
        for _ in 0..sub {
            // semi-implicit Euler for the plant at 0.1 ms
            let a = plant.acceleration(&q, &v, &out.torque).unwrap();
            v += a * 1e-4;
            q = q.retract(&v, 1e-4);
        }
        let st = ctl.state();
        let e = plant.kinetic_energy(&q, &v)
            + 0.5 * st.tau_dot.powi(2)
            + 0.5 * mf * st.flywheel_speed.powi(2);
        e_rel = e_rel.max((e - e0).abs() / e0);
    }
    assert!(u_last < 1e-4, "U at 10 s: {u_last:e}");
    // τ went once round the period-6 contour and was wrapped back into [0, 6).
    let st = ctl.state();
    assert!(
        st.laps >= 1 && (0.0..6.0).contains(&st.tau),
        "τ = {}, laps = {}",
        st.tau,
        st.laps
    );
    assert!(st.unwrapped_tau(Some(6.0)) > 6.0);
    assert!(e_rel < 1e-2, "energy error of the sampled loop {e_rel:e}");
}

/// The core's example controller is the scenario `pelican_example`'s, number for number (the
/// firmware, the benches and the f32 tests build the former; the simulator the latter, whose
/// field takes the scenario's obstacles: none here).
#[test]
fn the_core_example_controller_is_the_scenarios() {
    let mut from_scenario = pvfc::sim::scenario::presets::pelican_example()
        .controller()
        .unwrap();
    let mut core =
        pvfc::core::controller::ScaraLissajousController::<f64>::pelican_example().unwrap();
    let (a, b) = (core.law(), from_scenario.law());
    assert!(b.field().obstacles().is_empty());
    assert_eq!(a.system(), b.system());
    assert_eq!(a.field().contour(), b.field().contour());
    assert_eq!(a.field().navigation(), b.field().navigation());
    assert_eq!(a.field().pacing(), b.field().pacing().pacing());
    assert!(
        b.field().pacing().profile().profile().profile().is_none(),
        "the paper's uniform pace"
    );
    assert_eq!(a.field().convention(), b.field().convention());
    assert_eq!(a.flywheel(), b.flywheel());
    assert_eq!(a.gamma(), b.gamma());
    assert_eq!(core.state(), from_scenario.state());
    // The add-ons (friction compensation, nominal speed) by their torques: equal bit for bit.
    for k in 0..200 {
        let t = k as f64 * 0.013;
        let q = Torus::new(Vector2::new(0.3 * t.sin(), 1.4 - 0.2 * t));
        let v = Vector2::new(0.5 * t.cos(), -0.2);
        let x = core.step(&q, &v, 1e-3).unwrap();
        let y = from_scenario.step(&q, &v, 1e-3).unwrap();
        assert_eq!(x.torque, y.torque, "step {k}");
    }
}
