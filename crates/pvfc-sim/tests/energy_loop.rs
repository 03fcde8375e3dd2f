//! The energy loop of eq. (36): "T^forced tends to cause the velocity q̇_a to stabilize at
//! rV_a". On the field (`q̇_a = β V̄_a`, so `Pᵀq̇_a = 2Ēβ`), the forced term's power is
//! `c (Pᵀq̇_a)(r − Pᵀq̇_a/2Ē) = 2Ē c β (r − β)` and `κ_a = Ē β²`, hence `β̇ = c (r − β)`:
//! `β` reaches `r` exponentially with the time constant `1/c`, from above or below. Tested on
//! the frictionless SCARA (the paper's arm, Fig. 8's controller) for several `c` and `r`:
//! the measured rate of `ln|β − r|` once the arm is on the field, and `|β − r|` at the end.

use pvfc_sim::run::simulate;
use pvfc_sim::scenario::{presets, Mode, NominalSpeedSpec};

/// `β(t)` of the frictionless SCARA with the energy loop `(c, r)` over `duration` s.
fn beta(c: f64, r: f64, duration: f64) -> (Vec<f64>, Vec<f64>) {
    let mut s = presets::energy_check(Mode::Continuous);
    s.duration = duration;
    s.controller.nominal_speed = Some(NominalSpeedSpec { c, r });
    let t = simulate(&s, &mut |_| {}).expect("the run is valid");
    (t.t.clone(), t.beta.clone())
}

/// The least-squares slope of `ln|β − r|` over `[from, to]` s.
fn rate(t: &[f64], b: &[f64], r: f64, from: f64, to: f64) -> f64 {
    let pts: Vec<(f64, f64)> = t
        .iter()
        .zip(b)
        .filter(|(t, _)| (from..=to).contains(*t))
        .map(|(t, b)| (*t, (b - r).abs().ln()))
        .collect();
    let n = pts.len() as f64;
    let (mt, my) = pts
        .iter()
        .fold((0.0, 0.0), |(a, b), (t, y)| (a + t / n, b + y / n));
    let (num, den) = pts.iter().fold((0.0, 0.0), |(num, den), (t, y)| {
        (num + (t - mt) * (y - my), den + (t - mt) * (t - mt))
    });
    num / den
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
        let measured = -rate(&t, &b, r, from, to);
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
