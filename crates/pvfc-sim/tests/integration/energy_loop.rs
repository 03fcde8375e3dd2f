//! The energy loop of eq. (36): "T^forced tends to cause the velocity q̇_a to stabilize at
//! rV_a". On the field (`q̇_a = β V̄_a`, so `Pᵀq̇_a = 2Ēβ`), the forced term's power is
//! `c (Pᵀq̇_a)(r − Pᵀq̇_a/2Ē) = 2Ē c β (r − β)` and `κ_a = Ē β²`, hence `β̇ = c (r − β)`:
//! `β` reaches `r` exponentially with the time constant `1/c`, from above or below. Tested on
//! the frictionless SCARA (the paper's arm, Fig. 8's controller) for several `c` and `r`:
//! the measured rate of `ln|β − r|` once the arm is on the field, and `|β − r|` at the end.

use pvfc_sim::run::simulate;
use pvfc_sim::scenario::{presets, Mode, NominalSpeedSpec};
use pvfc_sim::trace::metrics::{log_gap_slope, settling_time_constant};

/// `β(t)` of the frictionless SCARA with the energy loop `(c, r)` over `duration` s.
fn beta(c: f64, r: f64, duration: f64) -> (Vec<f64>, Vec<f64>) {
    let mut s = presets::energy_check(Mode::Continuous);
    s.duration = duration;
    s.controller.nominal_speed = Some(NominalSpeedSpec {
        c,
        r,
        integral: 0.0,
    });
    let t = simulate(&s, &mut |_| {}).expect("the run is valid");
    (t.t.clone(), t.beta.clone())
}

#[test]
fn beta_reaches_r_at_the_rate_c() {
    for (c, r) in [(0.5, 2.0), (1.0, 1.5), (2.0, 3.0), (1.0, 0.6)] {
        let duration = 6.0 + 8.0 / c;
        let (t, b) = beta(c, r, duration);
        // The arm converges onto the field within the first seconds (γβĒ ≫ c); from then on,
        // β − r decays as e^{−c t}.
        let from = 4.0;
        let to = from + 4.0 / c;
        let measured = -log_gap_slope(&t, &b, r, from..=to).expect("samples in the window");
        let end = (b.last().unwrap() - r).abs();
        println!(
            "c = {c}, r = {r}: β from {:.3} to {:.5}, rate of ln|β − r| {measured:.4} (c = {c}), |β − r| at {duration} s {end:.2e}",
            b[0],
            b.last().unwrap()
        );
        assert!(
            (measured - c).abs() < 0.01 * c,
            "rate {measured} for c = {c}"
        );
        assert!(end < 1e-3 * r, "|β − r| = {end} at the end");
    }
}

#[test]
fn the_settling_time_constant_of_an_exponential_is_its_own() {
    let t: Vec<f64> = (0..40_000).map(|i| f64::from(i) * 1e-3).collect();
    for (y0, level, tc) in [(1.0, 2.0, 2.0), (3.0, 0.5, 0.7), (-1.0, -4.0, 2.5)] {
        let y: Vec<f64> = t
            .iter()
            .map(|t: &f64| level + (y0 - level) * (-t / tc).exp())
            .collect();
        let measured = settling_time_constant(&t, &y).expect("it settles");
        assert!((measured - tc).abs() < 1e-3 * tc, "{measured} for {tc}");
        let slope = log_gap_slope(&t, &y, level, 1.0..=3.0).expect("samples");
        assert!((slope + 1.0 / tc).abs() < 1e-6 / tc, "slope {slope}");
    }
    // A signal at its level has no time constant.
    assert_eq!(settling_time_constant(&t, &vec![1.5; t.len()]), None);
}
