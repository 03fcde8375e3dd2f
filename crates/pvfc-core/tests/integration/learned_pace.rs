//! The pace learned lap over lap (`pvfc_core::pace::learned`) in the passive controller: on
//! drives too weak for the field it slows the stretches where the command passed a limit,
//! and it creates no energy (the balance of one held period closes as without it).

use nalgebra::Vector2;
use proptest::prelude::*;
use pvfc_core::pace::{LearnedPace, PaceLearning, Paced, UniformPace};
use pvfc_core::passive::PassiveController;
use pvfc_core::prelude::*;

use crate::common;
use common::held::{held_balance, plant};

const K: usize = 32;
type Pacing = Paced<ExponentialPacing<f64>, LearnedPace<f64, UniformPace, K>>;
type Field =
    SuspendedField<f64, Torus<f64, 2>, Lissajous<f64, 2>, TorusNavigation<f64, 2>, Pacing, 2>;
type Passive = PassiveController<f64, Torus<f64, 2>, Scara<f64>, Field, 2>;

fn rule() -> PaceLearning<f64> {
    PaceLearning::new(1.0, 0.3, 0.1, 0.05, 0.1).unwrap()
}

fn learning(limit: f64, energy: f64) -> Passive {
    let contour = Lissajous::<f64, 2>::paper();
    let period = Contour::<f64, Torus<f64, 2>, 2>::period(&contour).unwrap();
    let field = SuspendedField::new(
        contour,
        TorusNavigation::paper(Vector2::new(1.0, 1.0)).unwrap(),
        Paced::new(
            ExponentialPacing::new(5.0).unwrap(),
            LearnedPace::periodic(UniformPace, period).unwrap(),
        ),
    );
    let law = PvfcLaw::new(
        Scara::pelican(),
        field,
        Flywheel::new(1.0, energy).unwrap(),
        0.5,
    )
    .unwrap();
    PassiveController::new(Controller::new(law).starting_at_rest(0.0))
        .with_torque_limits(Vector2::new(limit, limit))
        .unwrap()
        .with_pace_learning(rule())
        .unwrap()
}

fn scales(ctl: &Passive) -> [f64; K] {
    *ctl.controller().law().field().pacing().profile().scales()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 100, ..ProptestConfig::default() })]

    /// Over random states, periods and limits, after steps that taught the pace: the
    /// robot's kinetic energy plus the storage changes over a held period by exactly the
    /// add-ons' work (none here), as without learning.
    #[test]
    fn a_period_with_a_learned_pace_creates_no_energy(
        q in prop::array::uniform2(-3.0f64..3.0),
        v in prop::array::uniform2(-2.0f64..2.0),
        h in 1e-4f64..1e-2,
        limit in 0.5f64..20.0,
        warm in 0usize..400,
    ) {
        let mut ctl = learning(limit, 100.0);
        let mut step = |q: &Torus<f64, 2>, v: &Vector2<f64>, h: f64| {
            let out = ctl.step(q, Some(v), None, h).unwrap();
            (out.torque, out.energy.storage, out.energy.add_ons)
        };
        let (q0, v0) = (Torus::new(Vector2::from(q)), Vector2::from(v));
        let (residual, before) = held_balance(&mut step, q0, v0, h, warm);
        prop_assert!(residual.abs() <= 1e-9 * (1.0 + before), "residual {residual:e} of {before}");
        prop_assert!(scales(&ctl).iter().all(|s| (0.1..=1.0).contains(s)));
    }
}

/// On drives far too weak for the field's pace (0.3 N·m), the command is at a limit nearly
/// all of the first ten seconds; the pace learns where to slow, and ten seconds at a time the
/// drives are at a limit less and less, with `τ` moving on all the while.
#[test]
fn weak_drives_teach_the_pace_where_to_slow() {
    let mut ctl = learning(0.3, 400.0);
    let (mut q, mut v) = (Torus::new(Vector2::new(0.0, 1.0)), Vector2::zeros());
    let h = 1e-3;
    // Per ten seconds: the share of samples at a limit.
    let mut shares = Vec::new();
    let mut least_rate = f64::INFINITY;
    for window in 0..8 {
        let mut saturated = 0;
        for _ in 0..10_000 {
            let out = ctl.step(&q, Some(&v), None, h).unwrap();
            saturated += usize::from(out.energy.saturated);
            if window >= 3 {
                least_rate = least_rate.min(ctl.controller().state().tau_dot);
            }
            (q, v) = plant(q, v, out.torque, h, 10);
        }
        shares.push(saturated as f64 / 10_000.0);
    }
    let s = scales(&ctl);
    assert!(
        s.iter().all(|&x| x < 0.6),
        "the pace did not come down: {s:?}"
    );
    assert!(shares[0] > 0.8, "{shares:?}");
    assert!(shares[6] + shares[7] < 0.1, "{shares:?}");
    assert!(least_rate > 0.0, "τ stopped");
}

/// Without limits there is no margin to learn from, and a field without a learned pace
/// (here the paper's uniform pace, or a learned one with no period) has nothing to learn:
/// both are named errors.
#[test]
fn learning_needs_limits_and_a_field_that_learns() {
    let e = PassiveController::new(*learning(5.0, 50.0).controller())
        .with_pace_learning(rule())
        .unwrap_err();
    assert_eq!(e.kind(), ErrorKind::InvalidParameter);
    assert!(e.to_string().contains("torque limits"), "{e}");
    let field = SuspendedField::new(
        Lissajous::<f64, 2>::paper(),
        TorusNavigation::paper(Vector2::new(1.0, 1.0)).unwrap(),
        Paced::new(
            ExponentialPacing::new(5.0).unwrap(),
            LearnedPace::<f64, UniformPace, K>::new(UniformPace),
        ),
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
        .with_pace_learning(rule())
        .unwrap_err();
    assert!(e.to_string().contains("no pace to learn"), "{e}");
}
