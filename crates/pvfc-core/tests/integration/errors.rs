//! Bad input gives a typed error, never a panic or a NaN.

use nalgebra::{Matrix3, Vector2, Vector3};
use pvfc_core::prelude::*;

type Law = PvfcLaw<
    f64,
    Torus<f64, 2>,
    Scara<f64>,
    SuspendedField<
        f64,
        Torus<f64, 2>,
        Lissajous<f64, 2>,
        TorusNavigation<f64, 2>,
        ExponentialPacing<f64>,
        2,
    >,
    2,
>;

fn law(energy: f64) -> Law {
    let field = SuspendedField::new(
        Lissajous::paper(),
        TorusNavigation::paper(Vector2::new(1.0, 1.0)).unwrap(),
        ExponentialPacing::new(100.0).unwrap(),
    );
    PvfcLaw::new(
        Scara::pelican(),
        field,
        Flywheel::new(1.0, energy).unwrap(),
        0.05,
    )
    .unwrap()
}

fn state(q: [f64; 2], v: [f64; 2]) -> AugmentedState<f64, Torus<f64, 2>, 2> {
    AugmentedState {
        q: Torus::new(q.into()),
        v: v.into(),
        tau: 0.3,
        tau_dot: 0.1,
        flywheel_speed: 5.0,
    }
}

#[test]
fn non_finite_states_are_errors() {
    let law = law(50.0);
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        for s in [
            state([bad, 0.0], [0.0, 0.0]),
            state([0.0, 0.0], [0.0, bad]),
            AugmentedState {
                tau: bad,
                ..state([0.0, 0.0], [0.0, 0.0])
            },
            AugmentedState {
                tau_dot: bad,
                ..state([0.0, 0.0], [0.0, 0.0])
            },
            AugmentedState {
                flywheel_speed: bad,
                ..state([0.0, 0.0], [0.0, 0.0])
            },
        ] {
            assert_eq!(law.evaluate(&s).unwrap_err().kind(), ErrorKind::NonFinite);
        }
    }
}

#[test]
fn energy_too_low_is_an_error_with_the_deficit() {
    // The field's kinetic energy at this state: ½ V̄ᵀM̄V̄ ≈ 0.6 (λ₁² / 2 plus the arm's).
    let low = law(0.05);
    let err = low.evaluate(&state([0.0, 0.0], [0.0, 0.0])).unwrap_err();
    assert_eq!(err.kind(), ErrorKind::EnergyTooLow);
    assert!(err.value().unwrap() > 0.0);
    assert!(format!("{err}").contains("Ē"));
    // The controller keeps its state on that error.
    let mut ctl = Controller::new(law(1e-3)).starting_at_rest(0.0);
    let before = *ctl.state();
    assert!(ctl
        .step(&Torus::new(Vector2::zeros()), &Vector2::zeros(), 1e-3)
        .is_err());
    assert_eq!(*ctl.state(), before);
}

#[test]
fn invalid_parameters_are_errors() {
    assert_eq!(
        Flywheel::new(0.0, 1.0).unwrap_err().kind(),
        ErrorKind::InvalidParameter
    );
    assert_eq!(
        Flywheel::new(1.0, -1.0).unwrap_err().kind(),
        ErrorKind::InvalidParameter
    );
    assert_eq!(
        Flywheel::new(f64::NAN, 1.0).unwrap_err().kind(),
        ErrorKind::NonFinite
    );
    assert_eq!(
        ExponentialPacing::new(-1.0).unwrap_err().kind(),
        ErrorKind::InvalidParameter
    );
    assert_eq!(
        TorusNavigation::paper(Vector2::new(1.0, 0.0))
            .unwrap_err()
            .kind(),
        ErrorKind::InvalidParameter
    );
    assert_eq!(
        Lissajous::<f64, 2>::new(
            Vector2::new(1.0, 1.0),
            Vector2::new(0.0, 1.0),
            Vector2::zeros(),
            Vector2::zeros()
        )
        .unwrap_err()
        .kind(),
        ErrorKind::InvalidParameter
    );
    assert_eq!(
        NominalSpeed::new(0.0, 1.0).unwrap_err().kind(),
        ErrorKind::InvalidParameter
    );
    assert_eq!(
        FrictionCompensation::new(Vector2::new(-1.0, 1.0))
            .unwrap_err()
            .kind(),
        ErrorKind::InvalidParameter
    );
    let mut bad = ScaraParameters::<f64>::pelican();
    bad.m2 = -1.0;
    assert_eq!(
        Scara::new(bad).unwrap_err().kind(),
        ErrorKind::InvalidParameter
    );
    bad.m2 = f64::NAN;
    assert_eq!(Scara::new(bad).unwrap_err().kind(), ErrorKind::NonFinite);
    assert_eq!(
        RigidBody::new(Matrix3::from_diagonal(&Vector3::new(1.0, -1.0, 1.0)))
            .unwrap_err()
            .kind(),
        ErrorKind::InvalidParameter
    );
    assert_eq!(
        So3Navigation::new(Matrix3::new(1.0, 2.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0, 3.0))
            .unwrap_err()
            .kind(),
        ErrorKind::InvalidNavigationMatrix
    );
    // π₁ + π₂ < 0: the identity would not be the minimum.
    assert_eq!(
        So3Navigation::new(Matrix3::from_diagonal(&Vector3::new(-3.0, 1.0, 4.0)))
            .unwrap_err()
            .kind(),
        ErrorKind::InvalidNavigationMatrix
    );
    let field = SuspendedField::new(
        Lissajous::paper(),
        TorusNavigation::paper(Vector2::new(1.0, 1.0)).unwrap(),
        ExponentialPacing::off(),
    );
    assert_eq!(
        PvfcLaw::new(
            Scara::pelican(),
            field,
            Flywheel::new(1.0, 50.0).unwrap(),
            -0.1
        )
        .unwrap_err()
        .kind(),
        ErrorKind::InvalidParameter
    );
}

#[test]
fn step_rejects_bad_dt_and_keeps_state() {
    let mut ctl = Controller::new(law(50.0)).starting_at_rest(0.0);
    let before = *ctl.state();
    for dt in [0.0, -1e-3, f64::NAN, f64::INFINITY] {
        assert_eq!(
            ctl.step(&Torus::new(Vector2::zeros()), &Vector2::zeros(), dt)
                .unwrap_err()
                .kind(),
            ErrorKind::InvalidParameter
        );
    }
    assert_eq!(*ctl.state(), before);
}

#[test]
fn coupling_matrices_check_the_dimension() {
    let out = law(50.0).evaluate(&state([0.1, 0.2], [0.3, 0.4])).unwrap();
    assert!(out.coupling_matrices::<4>().is_ok());
    assert_eq!(
        out.coupling_matrices::<5>().unwrap_err().kind(),
        ErrorKind::DimensionMismatch
    );
}

#[test]
fn starting_at_rest_gives_unit_beta_and_starts_moving() {
    let mut ctl = Controller::new(law(50.0)).starting_at_rest(0.0);
    let out = ctl
        .step(&Torus::new(Vector2::new(0.0, 0.0)), &Vector2::zeros(), 1e-3)
        .unwrap();
    assert!((out.diagnostics.beta - 1.0).abs() < 1e-12);
    assert!(
        out.torque.norm() > 0.0,
        "at rest with a charged flywheel the coupling must push"
    );
    // With everything at rest, nothing moves (the manual's control law, `docs/src/reference/control-law.md` §5).
    let mut still = Controller::new(law(50.0));
    let out = still
        .step(&Torus::new(Vector2::new(0.0, 0.0)), &Vector2::zeros(), 1e-3)
        .unwrap();
    assert_eq!(out.torque.norm(), 0.0);
}

#[test]
fn a_huge_dt_is_an_error_not_a_hang() {
    // A fuzzer found this: a huge dt made τ ~ 1e300, where wrapping by subtracting the period
    // never ends. Now it is a NonFinite error and the state is kept.
    let mut ctl = Controller::new(law(50.0)).starting_at_rest(0.0);
    let before = *ctl.state();
    for dt in [1e300, 1e200, 1e30] {
        let r = ctl.step(
            &Torus::new(Vector2::new(0.0, 1.5)),
            &Vector2::new(0.5, 0.5),
            dt,
        );
        assert_eq!(r.unwrap_err().kind(), ErrorKind::NonFinite, "dt = {dt}");
        assert_eq!(*ctl.state(), before);
    }
    // A large but representable step still wraps τ into [0, 6) and counts the laps.
    let out = ctl.step(
        &Torus::new(Vector2::new(0.0, 1.5)),
        &Vector2::new(0.5, 0.5),
        10.0,
    );
    assert!(out.is_ok());
    let s = ctl.state();
    assert!((0.0..6.0).contains(&s.tau), "τ = {}", s.tau);
}

#[test]
fn the_forward_dynamics_of_a_diverged_state_say_it_is_not_finite() {
    let arm = Scara::<f64>::pelican();
    let q = Torus::<f64, 2>::new(Vector2::new(0.3, 0.5));
    let ok = arm.acceleration(&q, &Vector2::new(0.1, 0.2), &Vector2::new(1.0, -1.0));
    assert!(ok.is_ok_and(|a| a.iter().all(|x| x.is_finite())));
    for (v, f) in [
        (Vector2::new(f64::NAN, 0.0), Vector2::zeros()),
        (Vector2::zeros(), Vector2::new(f64::INFINITY, 0.0)),
    ] {
        match arm.acceleration(&q, &v, &f) {
            Err(e) => assert_eq!(e.kind(), ErrorKind::NonFinite, "{e}"),
            Ok(a) => assert!(a.iter().any(|x| !x.is_finite()), "{a}"),
        }
    }
    let nan_q = Torus::<f64, 2>::new(Vector2::new(0.3, f64::NAN));
    let e = arm
        .acceleration(&nan_q, &Vector2::zeros(), &Vector2::zeros())
        .expect_err("a NaN elbow angle");
    assert_eq!(e.kind(), ErrorKind::NonFinite, "{e}");
}
