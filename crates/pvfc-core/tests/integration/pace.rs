//! The pace profile along the contour (`pvfc_core::pace`): the table's interpolant (periodic,
//! `C¹`, its derivative against finite differences, never outside its knots' range), the
//! drive-limited rates (every torque along the profile within the limits, computed
//! independently from the model; the profile at a limit wherever it is below the rate asked
//! for, with and without viscous friction), and the errors.

use crate::common;

use common::setups::test_pace;
use nalgebra::Vector2;
use proptest::prelude::*;
use pvfc_core::pace::{
    drive_limited_rates, drive_limited_rates_on_rows, drive_limited_rates_with_miss, DriveLimits,
    MissLearner, MotionRow, PaceProfile, PaceTable,
};
use pvfc_core::prelude::*;
use pvfc_core::ErrorKind;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2_000))]

    /// Between knots k and k+1 the interpolant stays within [min, max](σ_k, σ_{k+1}), its
    /// derivative is the finite difference of its values, and it repeats with the period.
    #[test]
    fn table_is_monotone_c1_and_periodic(
        knots in proptest::collection::vec(0.05..3.0f64, 3..40),
        period in 0.5..20.0f64,
        x in -3.0..3.0f64,
    ) {
        let t = PaceTable::<f64, 64>::new(&knots, period).unwrap();
        let tau = x * period;
        let (s, ds) = t.pace(tau);
        let n = knots.len() as f64;
        let k = (tau * n / period).floor() as i64;
        let at = |k: i64| knots[k.rem_euclid(knots.len() as i64) as usize];
        let (lo, hi) = (at(k).min(at(k + 1)), at(k).max(at(k + 1)));
        prop_assert!(s >= lo - 1e-12 && s <= hi + 1e-12, "σ = {s} outside [{lo}, {hi}]");
        let (p, _) = t.pace(tau + period);
        prop_assert!((p - s).abs() <= 1e-9 * (1.0 + s), "not periodic: {s} vs {p}");
        // Central difference, away from the knots (where σ'' jumps).
        let h = 1e-6 * period / n;
        let frac = tau * n / period - k as f64;
        if frac > 1e-3 && frac < 1.0 - 1e-3 {
            let fd = (t.pace(tau + h).0 - t.pace(tau - h).0) / (2.0 * h);
            prop_assert!((fd - ds).abs() <= 1e-5 * (1.0 + ds.abs()), "σ' {ds} vs FD {fd}");
        }
    }
}

#[test]
fn table_is_continuous_in_value_and_slope_across_knots() {
    let t = test_pace::<f64>();
    let spacing = 6.0 / 12.0;
    for k in 0..12 {
        let tau = k as f64 * spacing;
        let (a, da) = t.pace(tau - 1e-12);
        let (b, db) = t.pace(tau);
        assert!((a - b).abs() < 1e-9, "σ jumps at knot {k}: {a} vs {b}");
        assert!((da - db).abs() < 1e-6, "σ' jumps at knot {k}: {da} vs {db}");
        assert_eq!(b, t.values()[k], "σ at knot {k} is its value");
    }
}

#[test]
fn table_refuses_bad_input() {
    let kind = |r: Result<PaceTable<f64, 4>, pvfc_core::Error>| r.unwrap_err().kind();
    assert_eq!(
        kind(PaceTable::new(&[1.0, 1.0], 1.0)),
        ErrorKind::DimensionMismatch
    );
    assert_eq!(
        kind(PaceTable::new(&[1.0; 5], 1.0)),
        ErrorKind::DimensionMismatch
    );
    assert_eq!(
        kind(PaceTable::new(&[1.0, f64::NAN, 1.0], 1.0)),
        ErrorKind::NonFinite
    );
    assert_eq!(
        kind(PaceTable::new(&[1.0, 0.0, 1.0], 1.0)),
        ErrorKind::InvalidParameter
    );
    assert_eq!(
        kind(PaceTable::new(&[1.0; 3], 0.0)),
        ErrorKind::InvalidParameter
    );
    assert_eq!(
        kind(PaceTable::new(&[1.0; 3], f64::INFINITY)),
        ErrorKind::InvalidParameter
    );
    let t = PaceTable::<f64, 4>::new(&[1.0, 0.5, 2.0], 3.0).unwrap();
    assert_eq!(
        t.pace(f64::NAN),
        (1.0, 0.0),
        "a non-finite τ gives the first knot, no panic"
    );
}

/// The torque the motion along the contour needs at `τ` with rate `τ̇` and `τ̈`, from the
/// model's `M` and `C` written out (`M q̈ + C(q, q̇) q̇`, q̈ = ξ τ̈ + ξ' τ̇²), plus friction
/// compensation `f ∘ sign(q̇)` and viscous friction `b ∘ q̇`.
fn motion_torque(
    scara: &Scara<f64>,
    tau: f64,
    rate: f64,
    accel: f64,
    fric: [f64; 2],
    viscous: [f64; 2],
) -> Vector2<f64> {
    let c = Lissajous::<f64, 2>::paper().sample(tau);
    let v = c.velocity * rate;
    let a = c.velocity * accel + c.acceleration * rate * rate;
    let m = scara.inertia(&c.point);
    let cor = scara.coriolis(&c.point, &v);
    let mut t = m * a + cor * v;
    for i in 0..2 {
        t[i] += fric[i] * v[i].signum() * f64::from(u8::from(v[i] != 0.0)) + viscous[i] * v[i];
    }
    t
}

/// The drive-limited profile of the paper's Lissajous curve at τ̇ ≤ 4 on 15 / 5 N·m with
/// headroom 0.8, Coulomb levels 2 / 3 N·m and viscous coefficients `viscous`: every torque
/// along it (computed independently from the model) within the limits, the profile at a
/// limit wherever it is below the rate asked for; returns the lap time.
fn check_profile(viscous: [f64; 2]) -> f64 {
    let scara = Scara::<f64>::pelican();
    let contour = Lissajous::<f64, 2>::paper();
    let fric = [2.0, 3.0];
    let (l, h) = ([15.0, 5.0], 0.8);
    let limits = DriveLimits::new(Vector2::from(l))
        .unwrap()
        .with_headroom(h)
        .unwrap()
        .with_friction_compensation(Vector2::from(fric))
        .unwrap()
        .with_viscous_friction(Vector2::from(viscous))
        .unwrap();
    let n = 3000;
    let period = 6.0;
    let asked = 4.0;
    let mut rates = vec![asked; n];
    drive_limited_rates(&scara, &contour, &limits, period, &mut rates).unwrap();
    let step = period / n as f64;
    let (mut below, mut at_limit) = (0, 0);
    let mut lap = 0.0;
    for j in 0..n {
        let (x0, x1) = (rates[j].powi(2), rates[(j + 1) % n].powi(2));
        let accel = (x1 - x0) / (2.0 * step);
        let t = motion_torque(&scara, j as f64 * step, rates[j], accel, fric, viscous);
        let use_ = (0..2).map(|i| t[i].abs() / (h * l[i])).fold(0.0, f64::max);
        assert!(
            rates[j] <= asked * (1.0 + 1e-12),
            "rate above the one asked for at {j}"
        );
        assert!(
            use_ <= 1.0 + 1e-6,
            "τ = {}: {use_} of the limits",
            j as f64 * step
        );
        if rates[j] < asked * (1.0 - 1e-9) {
            below += 1;
            if use_ >= 1.0 - 1e-6 {
                at_limit += 1;
            }
        }
        lap += 2.0 * step / (rates[j] + rates[(j + 1) % n]);
    }
    // The drives cannot make τ̇ = 4 all round (the paper's Lissajous, 15 / 5 N·m), and
    // wherever the profile is below it, a joint is at its limit (the time-optimal profile is
    // bang-bang) but at the few points where it switches from accelerating to braking.
    assert!(
        below > n / 4,
        "only {below} points below the rate asked for"
    );
    assert!(
        at_limit as f64 >= 0.99 * below as f64,
        "{at_limit} of {below} at a limit"
    );
    // Not a profile that stops: the lap takes less than twice what the slowest point's rate
    // would take all round, and more than the rate asked for would.
    let slowest = rates.iter().copied().fold(f64::INFINITY, f64::min);
    assert!(slowest > 0.1, "the profile nearly stops: {slowest}");
    assert!(
        lap > period / asked && lap < period / slowest,
        "lap {lap} s"
    );
    lap
}

#[test]
fn drive_limited_rates_keep_every_torque_within_the_limits_and_reach_them() {
    check_profile([0.0, 0.0]);
}

/// Viscous friction (a term in `√x`) takes its share of the limits: the profile still keeps
/// every torque within them and reaches them, and the lap is longer than without it.
#[test]
fn drive_limited_rates_with_viscous_friction_stay_within_the_limits() {
    let coulomb_only = check_profile([0.0, 0.0]);
    let viscous = check_profile([0.5, 0.3]);
    assert!(
        viscous > coulomb_only * 1.01,
        "viscous friction should slow the lap: {viscous} s against {coulomb_only} s"
    );
}

#[test]
fn drive_limited_rates_are_the_rate_asked_for_when_the_drives_suffice() {
    let scara = Scara::<f64>::pelican();
    let limits = DriveLimits::new(Vector2::new(1e4, 1e4)).unwrap();
    let mut rates = vec![0.5; 500];
    drive_limited_rates(
        &scara,
        &Lissajous::<f64, 2>::paper(),
        &limits,
        6.0,
        &mut rates,
    )
    .unwrap();
    assert!(rates.iter().all(|r| *r == 0.5));
}

#[test]
fn drive_limited_rates_refuse_bad_input_and_drives_that_cannot_hold() {
    let scara = Scara::<f64>::pelican();
    let contour = Lissajous::<f64, 2>::paper();
    let limits = DriveLimits::new(Vector2::new(15.0, 5.0)).unwrap();
    let run = |limits: &DriveLimits<f64, 2>, rates: &mut [f64], period: f64| {
        drive_limited_rates(&scara, &contour, limits, period, rates).map_err(|e| e.kind())
    };
    assert_eq!(
        run(&limits, &mut [1.0; 2], 6.0),
        Err(ErrorKind::DimensionMismatch)
    );
    assert_eq!(
        run(&limits, &mut [1.0, f64::NAN, 1.0], 6.0),
        Err(ErrorKind::NonFinite)
    );
    assert_eq!(
        run(&limits, &mut [1.0, 0.0, 1.0], 6.0),
        Err(ErrorKind::InvalidParameter)
    );
    assert_eq!(
        run(&limits, &mut [1.0; 3], -1.0),
        Err(ErrorKind::InvalidParameter)
    );
    // Friction compensation of 6 N·m on a 5 N·m drive: not even at rest.
    let weak = limits
        .with_friction_compensation(Vector2::new(0.0, 6.0))
        .unwrap();
    let mut rates = [1.0; 10];
    assert_eq!(
        run(&weak, &mut rates, 6.0),
        Err(ErrorKind::InvalidParameter)
    );
    assert_eq!(
        rates, [1.0; 10],
        "an error leaves the rates as they were asked"
    );
    assert!(DriveLimits::new(Vector2::new(1.0, -1.0)).is_err());
    assert!(limits.with_headroom(0.0).is_err() && limits.with_headroom(1.5).is_err());
    assert_eq!(
        limits
            .with_viscous_friction(Vector2::new(0.1, -0.1))
            .unwrap_err()
            .kind(),
        ErrorKind::InvalidParameter
    );
    assert_eq!(
        limits
            .with_viscous_friction(Vector2::new(f64::NAN, 0.1))
            .unwrap_err()
            .kind(),
        ErrorKind::NonFinite
    );
}

#[test]
fn a_table_below_fine_rates_stays_below_them_everywhere() {
    // A profile with a sharp dip, on 5,000 points; 64 knots.
    let n = 5000;
    let period = 6.0;
    let fine: Vec<f64> = (0..n)
        .map(|j| {
            let tau = j as f64 * period / n as f64;
            2.0 - 1.5 * (-((tau - 4.0) / 0.05).powi(2)).exp() + 0.3 * (tau * 2.0).sin()
        })
        .collect();
    let t = PaceTable::<f64, 64>::below(&fine, 2.0, 64, period).unwrap();
    for (j, r) in fine.iter().enumerate() {
        let (s, _) = t.pace(j as f64 * period / n as f64);
        assert!(
            s <= r / 2.0 + 1e-12,
            "σ {s} above rate/β {} at point {j}",
            r / 2.0
        );
    }
    // ... and not far below away from the dip.
    let (s, _) = t.pace(1.0);
    assert!(
        s > 0.95 * fine[n / 6] / 2.0,
        "σ {s} far below {}",
        fine[n / 6] / 2.0
    );
    assert!(PaceTable::<f64, 64>::below(&fine, 0.0, 64, period).is_err());
    assert!(PaceTable::<f64, 64>::below(&fine[..10], 1.0, 64, period).is_err());
    assert!(PaceTable::<f64, 64>::below(&fine, 1.0, 65, period).is_err());
}

/// The drives' limits of `check_profile` with friction compensation `fric`.
fn lissajous_limits(fric: [f64; 2]) -> DriveLimits<f64, 2> {
    DriveLimits::new(Vector2::new(15.0, 5.0))
        .unwrap()
        .with_headroom(0.8)
        .unwrap()
        .with_friction_compensation(Vector2::from(fric))
        .unwrap()
}

/// `more ∘ sign(ξ_d(τ_j))` at `n` points of the paper's Lissajous contour over `period`.
fn coulomb_miss(n: usize, period: f64, more: [f64; 2]) -> Vec<Vector2<f64>> {
    let contour = Lissajous::<f64, 2>::paper();
    let step = period / n as f64;
    (0..n)
        .map(|j| {
            let v = Contour::<f64, Torus<f64, 2>, 2>::sample(&contour, j as f64 * step).velocity;
            Vector2::from_fn(|i, _| {
                if v[i] > 0.0 {
                    more[i]
                } else if v[i] < 0.0 {
                    -more[i]
                } else {
                    0.0
                }
            })
        })
        .collect()
}

/// The plan on rows computed once is the plan on the model: bit for bit without a miss, to
/// rounding with one (the miss is added in another order).
#[test]
fn a_plan_on_rows_is_the_plan_on_the_model() {
    let scara = Scara::<f64>::pelican();
    let contour = Lissajous::<f64, 2>::paper();
    let limits = lissajous_limits([2.0, 3.0]);
    let (n, period) = (512, 6.0);
    let step = period / n as f64;
    let rows: Vec<MotionRow<f64, 2>> = (0..n)
        .map(|j| MotionRow::at(&scara, &contour, &limits, j as f64 * step))
        .collect();
    let miss = coulomb_miss(n, period, [0.5, 0.75]);
    let (mut on_model, mut on_rows) = (vec![4.0; n], vec![4.0; n]);
    drive_limited_rates(&scara, &contour, &limits, period, &mut on_model).unwrap();
    drive_limited_rates_on_rows(&rows, None, period, &mut on_rows).unwrap();
    assert_eq!(on_model, on_rows);
    let (mut on_model, mut on_rows) = (vec![4.0; n], vec![4.0; n]);
    drive_limited_rates_with_miss(&scara, &contour, &limits, period, &mut on_model, &miss).unwrap();
    drive_limited_rates_on_rows(&rows, Some(&miss), period, &mut on_rows).unwrap();
    for (j, (a, b)) in on_model.iter().zip(&on_rows).enumerate() {
        assert!((a - b).abs() <= 1e-12 * a.abs(), "τ_{j}: {a} against {b}");
    }
    assert_eq!(
        drive_limited_rates_on_rows(&rows[..n - 1], None, period, &mut on_rows)
            .map_err(|e| e.kind()),
        Err(ErrorKind::DimensionMismatch)
    );
}

/// Laps of the Lissajous contour at `τ̇ = rate` (τ̈ = 0), the command at each step the model's
/// motion torque at `τ` plus `miss` at the knot nearest `τ`; counts the wraps at which the
/// caps changed.
fn run_laps<const K: usize, const N: usize>(
    learner: &mut MissLearner<f64, 2, K, N>,
    laps: usize,
    rate: f64,
    period: f64,
    miss: &[Vector2<f64>],
) -> usize {
    let dt = 1e-3;
    let steps = (laps as f64 * period / (rate * dt)).round() as usize;
    let mut changes = 0;
    for i in 0..steps {
        let tau = (i as f64 * rate * dt) % period;
        let k = ((tau / period * K as f64).round() as usize) % K;
        let command = learner.model_torque(tau, rate, 0.0) + miss[k];
        let before = *learner.caps();
        if learner.record(tau, rate, 0.0, &command, dt) {
            assert_ne!(&before, learner.caps());
            changes += 1;
        }
    }
    changes
}

/// What the drives give beyond the model's torque is learned knot by knot from the second
/// lap on, and the pace's caps are the plan with that miss over the plan without it,
/// computed here on the model at the same points.
#[test]
fn the_miss_learner_measures_the_missed_torque_and_caps_the_pace_by_it() {
    const K: usize = 64;
    const N: usize = 256;
    let scara = Scara::<f64>::pelican();
    let contour = Lissajous::<f64, 2>::paper();
    let limits = lissajous_limits([2.0, 3.0]);
    let period = 6.0;
    let truth = coulomb_miss(K, period, [0.25, 0.4]);
    let new = |asked: [f64; N], weight: f64, period: f64| {
        MissLearner::<f64, 2, K, N>::new(&scara, &contour, &limits, period, asked, weight)
    };
    let mut learner = new([4.0; N], 1.0, period).unwrap();
    // The start and the first whole lap: nothing learned, whatever the drives gave.
    let huge = vec![Vector2::new(100.0, -100.0); K];
    assert_eq!(run_laps(&mut learner, 1, 1.0, period, &huge), 0);
    assert_eq!(learner.caps(), &[1.0; K]);
    // Laps with the true miss: learned at each wrap after the start's lap.
    assert!(run_laps(&mut learner, 3, 1.0, period, &truth) >= 1);
    for (k, (m, t)) in learner.miss().iter().zip(&truth).enumerate() {
        assert!((m - t).norm() <= 1e-9, "knot {k}: {m} against {t}");
    }
    // The same plan on the model: the miss interpolated between the knots.
    let per = N / K;
    let spread: Vec<Vector2<f64>> = (0..N)
        .map(|j| {
            let (k, f) = (j / per, (j % per) as f64 / per as f64);
            truth[k] + (truth[(k + 1) % K] - truth[k]) * f
        })
        .collect();
    let (mut with, mut without) = ([4.0; N], [4.0; N]);
    drive_limited_rates_with_miss(&scara, &contour, &limits, period, &mut with, &spread).unwrap();
    drive_limited_rates(&scara, &contour, &limits, period, &mut without).unwrap();
    let caps = learner.caps();
    for (k, cap) in caps.iter().enumerate() {
        let expected = (0..per)
            .map(|i| (k * per + N - per / 2 + i) % N)
            .map(|j| with[j] / without[j])
            .fold(1.0f64, f64::min);
        assert!(
            (cap - expected).abs() <= 1e-9,
            "knot {k}: cap {cap} against {expected}"
        );
    }
    assert!(
        caps.iter().any(|&c| c < 0.97) && caps.iter().all(|&c| c > 0.1),
        "{caps:?}"
    );
    // A plant that needs no more than the model: every cap back at 1.
    let none = vec![Vector2::zeros(); K];
    run_laps(&mut learner, 2, 1.0, period, &none);
    assert!(
        learner.caps().iter().all(|&c| c == 1.0),
        "{:?}",
        learner.caps()
    );
    // Bad settings and readings.
    assert!(new([4.0; N], 0.0, period).is_err());
    assert!(new([4.0; N], 1.0, -1.0).is_err());
    let mut asked = [4.0; N];
    asked[3] = f64::NAN;
    assert!(new(asked, 1.0, period).is_err());
    assert!(!learner.record(f64::NAN, 1.0, 0.0, &Vector2::zeros(), 1e-3));
    assert!(!learner.record(0.1, 1.0, 0.0, &Vector2::new(f64::INFINITY, 0.0), 1e-3));
}

/// A missed torque the size of more Coulomb friction is more friction compensation: the
/// rates planned with `miss[j] = m ∘ sign(ξ_d(τ_j))` are those planned with the compensation
/// raised by `m`; and with no miss, those of `drive_limited_rates`.
#[test]
fn a_missed_torque_is_planned_as_the_torque_it_is() {
    let scara = Scara::<f64>::pelican();
    let contour = Lissajous::<f64, 2>::paper();
    let (n, period) = (1500, 6.0);
    let (fric, more) = ([2.0, 3.0], [0.5, 0.75]);
    let step = period / n as f64;
    let miss: Vec<Vector2<f64>> = (0..n)
        .map(|j| {
            let v = Contour::<f64, Torus<f64, 2>, 2>::sample(&contour, j as f64 * step).velocity;
            Vector2::from_fn(|i, _| {
                let sign = if v[i] > 0.0 {
                    1.0
                } else if v[i] < 0.0 {
                    -1.0
                } else {
                    0.0
                };
                more[i] * sign
            })
        })
        .collect();
    let plan = |limits: &DriveLimits<f64, 2>, miss: Option<&[Vector2<f64>]>| {
        let mut rates = vec![4.0; n];
        match miss {
            Some(m) => {
                drive_limited_rates_with_miss(&scara, &contour, limits, period, &mut rates, m)
            }
            None => drive_limited_rates(&scara, &contour, limits, period, &mut rates),
        }
        .unwrap();
        rates
    };
    let base = lissajous_limits(fric);
    let raised = lissajous_limits([fric[0] + more[0], fric[1] + more[1]]);
    let with_miss = plan(&base, Some(&miss));
    let as_friction = plan(&raised, None);
    for (j, (a, b)) in with_miss.iter().zip(&as_friction).enumerate() {
        assert!((a - b).abs() <= 1e-12 * b.abs(), "τ_{j}: {a} against {b}");
    }
    // The miss slows the plan (the drives give it part of their torque)...
    let plain = plan(&base, None);
    let lap = |r: &[f64]| {
        (0..n)
            .map(|j| 2.0 * step / (r[j] + r[(j + 1) % n]))
            .sum::<f64>()
    };
    assert!(
        lap(&with_miss) > 1.01 * lap(&plain),
        "{} against {}",
        lap(&with_miss),
        lap(&plain)
    );
    // ...and a miss of zero changes nothing.
    let zero = vec![Vector2::zeros(); n];
    assert_eq!(plan(&base, Some(&zero)), plain);
}

#[test]
fn a_missed_torque_of_the_wrong_length_or_not_finite_is_refused() {
    let scara = Scara::<f64>::pelican();
    let contour = Lissajous::<f64, 2>::paper();
    let limits = lissajous_limits([2.0, 3.0]);
    let mut rates = vec![1.0; 10];
    let run = |rates: &mut [f64], miss: &[Vector2<f64>]| {
        drive_limited_rates_with_miss(&scara, &contour, &limits, 6.0, rates, miss)
            .map_err(|e| e.kind())
    };
    assert_eq!(
        run(&mut rates, &[Vector2::zeros(); 9]),
        Err(ErrorKind::DimensionMismatch)
    );
    let mut bad = [Vector2::zeros(); 10];
    bad[3][1] = f64::NAN;
    assert_eq!(run(&mut rates, &bad), Err(ErrorKind::NonFinite));
}
