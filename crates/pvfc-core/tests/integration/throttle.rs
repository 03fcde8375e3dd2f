//! The pace throttled on the torque margin (`pvfc_core::pace::throttle`) in the passive
//! controller: it slows the field's pace when the command nears a limit, by the scale it
//! reports, and it creates no energy (the balance of one held period closes as without it).

use nalgebra::Vector2;
use proptest::prelude::*;
use pvfc_core::pace::{PaceThrottle, Paced, Throttled, UniformPace};
use pvfc_core::passive::PassiveController;
use pvfc_core::prelude::*;

use crate::common;
use common::held::{held_balance, plant};

type Pacing = Paced<ExponentialPacing<f64>, Throttled<f64, UniformPace>>;
type Field =
    SuspendedField<f64, Torus<f64, 2>, Lissajous<f64, 2>, TorusNavigation<f64, 2>, Pacing, 2>;
type Passive = PassiveController<f64, Torus<f64, 2>, Scara<f64>, Field, 2>;

fn controller(energy: f64) -> Controller<f64, Torus<f64, 2>, Scara<f64>, Field, 2> {
    let field = SuspendedField::new(
        Lissajous::<f64, 2>::paper(),
        TorusNavigation::paper(Vector2::new(1.0, 1.0)).unwrap(),
        Paced::new(
            ExponentialPacing::new(5.0).unwrap(),
            Throttled::new(UniformPace),
        ),
    );
    let law = PvfcLaw::new(
        Scara::pelican(),
        field,
        Flywheel::new(1.0, energy).unwrap(),
        0.5,
    )
    .unwrap();
    Controller::new(law)
}

fn throttled(limit: f64, energy: f64) -> Passive {
    PassiveController::new(controller(energy).starting_at_rest(0.0))
        .with_torque_limits(Vector2::new(limit, limit))
        .unwrap()
        .with_pace_throttle(PaceThrottle::new(0.8, 0.01, 0.05).unwrap())
        .unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

    /// Over random states, periods and limits, after steps that moved the throttle: the
    /// robot's kinetic energy plus the storage changes over a held period by exactly the
    /// add-ons' work (none here), as without a throttle.
    #[test]
    fn a_throttled_period_creates_no_energy(
        q in prop::array::uniform2(-3.0f64..3.0),
        v in prop::array::uniform2(-2.0f64..2.0),
        h in 1e-4f64..1e-2,
        limit in 0.5f64..20.0,
        warm in 0usize..20,
    ) {
        let mut ctl = throttled(limit, 100.0);
        let mut step = |q: &Torus<f64, 2>, v: &Vector2<f64>, h: f64| {
            let out = ctl.step(q, Some(v), None, h).unwrap();
            (out.torque, out.energy.storage, out.energy.add_ons)
        };
        let (q0, v0) = (Torus::new(Vector2::from(q)), Vector2::from(v));
        let (residual, before) = held_balance(&mut step, q0, v0, h, warm);
        prop_assert!(residual.abs() <= 1e-9 * (1.0 + before), "residual {residual:e} of {before}");
        let s = ctl.pace_throttle().unwrap().scale();
        prop_assert!((0.05..=1.0).contains(&s), "scale {s}");
    }
}

/// On drives too weak for the field, the scale falls below 1, and the field's `λ₁` (the
/// desired `τ̇` is `βλ₁`) is the unthrottled one times the scale the step reports.
#[test]
fn a_saturated_drive_slows_the_field_by_the_reported_scale() {
    let mut ctl = throttled(1.0, 400.0);
    let (mut q, mut v) = (Torus::new(Vector2::new(0.0, 1.0)), Vector2::zeros());
    let mut slowed = 0;
    for _ in 0..2000 {
        // The same state through a copy without a throttle (the field at the scale 1).
        let mut free = ctl;
        assert!(free.controller_mut().set_pace_scale(1.0));
        let reference = free.step(&q, Some(&v), None, 1e-3).unwrap();
        let out = ctl.step(&q, Some(&v), None, 1e-3).unwrap();
        let ratio = out.diagnostics.lambda1 / reference.diagnostics.lambda1;
        assert!(
            (ratio - out.pace_scale).abs() <= 1e-12,
            "λ₁ ratio {ratio} against the scale {}",
            out.pace_scale
        );
        if out.pace_scale < 0.5 {
            slowed += 1;
        }
        (q, v) = plant(q, v, out.torque, 1e-3, 10);
    }
    assert!(
        slowed > 100,
        "the throttle hardly acted: {slowed} slowed steps"
    );
    // The next step's scale is the throttle's.
    let next = ctl.pace_throttle().unwrap().scale();
    let out = ctl.step(&q, Some(&v), None, 1e-3).unwrap();
    assert_eq!(out.pace_scale, next);
}

/// Without limits the throttle has nothing to read, and a field without a pace scale has no
/// lever: both are named errors.
#[test]
fn a_throttle_needs_limits_and_a_scalable_field() {
    let t = PaceThrottle::new(0.8, 0.05, 0.05).unwrap();
    let e = PassiveController::new(controller(50.0))
        .with_pace_throttle(t)
        .unwrap_err();
    assert_eq!(e.kind(), ErrorKind::InvalidParameter);
    assert!(e.to_string().contains("torque limits"), "{e}");
    // The paper's field (eq. 21 without a profile) has no scale.
    let field = SuspendedField::new(
        Lissajous::<f64, 2>::paper(),
        TorusNavigation::paper(Vector2::new(1.0, 1.0)).unwrap(),
        ExponentialPacing::new(5.0).unwrap(),
    );
    let law = PvfcLaw::new(
        Scara::pelican(),
        field,
        Flywheel::new(1.0, 50.0).unwrap(),
        0.5,
    )
    .unwrap();
    let e = PassiveController::new(Controller::new(law))
        .with_torque_limits(Vector2::new(5.0, 5.0))
        .unwrap()
        .with_pace_throttle(t)
        .unwrap_err();
    assert!(e.to_string().contains("no pace scale"), "{e}");
}
