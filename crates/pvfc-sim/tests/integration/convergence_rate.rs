//! Remark 1: the velocity-field tracking error `e_β = q̇_a − βV_a` converges exponentially,
//! with the Lyapunov function `W_β = ½‖e_β‖²_a` (eq. 12) obeying `Ẇ_β = −4Ēγβμ W_β`
//! (eq. 13), `μ ∈ [0, 1]` nondecreasing, so that near the field `‖e_β‖_a` converges at the
//! rate `2γβĒ`. Tested on the frictionless SCARA (the paper's arm and contour, the continuous
//! closed loop, RK4 at 1 kHz), from rest with the energy in the flywheel, over several `γĒ`,
//! `Ē` and `β`: eq. (13) at every sample, and the rate near the field against `2γβĒ`.

use pvfc_core::coupling::convergence_factor;
use pvfc_sim::run::simulate;
use pvfc_sim::scenario::{presets, Mode};
use pvfc_sim::trace::metrics::velocity_field_convergence;
use pvfc_sim::trace::Trace;

/// The frictionless SCARA with `γ = gamma_e / Ē`, starting at `q = 0` with the joint
/// velocities `v0` and the flywheel at `fly` times its speed for `β = 1` at rest
/// (`√(2Ē/M_F)`), for `duration` s.
fn run(gamma_e: f64, energy: f64, v0: [f64; 2], fly: f64, duration: f64) -> Trace {
    let mut s = presets::energy_check(Mode::Continuous);
    s.duration = duration;
    s.controller.energy = energy;
    s.controller.gamma = gamma_e / energy;
    let inertia = s.controller.flywheel_inertia;
    s.initial.v = v0.to_vec();
    s.initial.flywheel_speed = Some(fly * (2.0 * energy / inertia).sqrt());
    simulate(&s, &mut |_| {}).expect("the run is valid")
}

#[test]
fn the_velocity_field_error_converges_at_two_gamma_beta_e_bar() {
    // From rest with the energy in the flywheel (μ(0) near 1), and with the arm thrown
    // against the field with little in the flywheel (μ(0) small: eq. (13) far from the field).
    for (gamma_e, energy, v0, fly) in [
        (2.0, 2000.0, [0.0, 0.0], 1.0),
        (10.0, 500.0, [0.0, 0.0], 2.0),
        (40.0, 2000.0, [0.0, 0.0], 1.0),
        (5.0, 50.0, [0.0, 0.0], 0.5),
        (10.0, 50.0, [-4.0, 3.0], 0.2),
        (2.0, 20.0, [3.0, -6.0], 0.1),
    ] {
        let beta = run(gamma_e, energy, v0, fly, 0.002).beta[0];
        let rate = 2.0 * gamma_e * beta;
        // Long enough for W_β to fall from its start to its rounding.
        let t = run(gamma_e, energy, v0, fly, 1.0 + 40.0 / rate);
        let c = velocity_field_convergence(&t, gamma_e / energy, energy).expect("it converges");
        let mu: Vec<f64> = t
            .w_beta
            .iter()
            .zip(&t.energy)
            .map(|(w, k)| convergence_factor(*k, *w))
            .collect();
        println!(
            "γĒ = {gamma_e}, Ē = {energy}, β = {beta:.3}, μ(0) = {:.3}: ‖e_β‖ rate {:.4} (2γβĒ = {:.4}) over {} samples; W_β {:.2e} → {:.2e}; largest deviation from (13) {:.2e}",
            mu[0],
            c.measured_rate,
            c.predicted_rate,
            c.samples,
            t.w_beta[0],
            t.w_beta.last().unwrap(),
            c.worst_deviation
        );
        assert!((c.predicted_rate - rate).abs() < 1e-9 * rate);
        assert!(c.samples >= 20, "{} samples near the field", c.samples);
        assert!(
            (c.measured_rate - rate).abs() < 5e-3 * rate,
            "rate {} for 2γβĒ = {rate}",
            c.measured_rate
        );
        assert!(
            c.worst_deviation < 1e-2,
            "eq. (13) off by {:.2e} of 4Ēγβ",
            c.worst_deviation
        );
        // μ = 1 − W_β/(4κ_a) stays in [0, 1] and never decreases (up to rounding).
        assert!(mu.iter().all(|m| (0.0..=1.0).contains(m)));
        assert!(mu.windows(2).all(|m| m[1] >= m[0] - 1e-12), "μ decreases");
    }
}

#[test]
fn w_beta_is_half_the_squared_error_in_the_augmented_metric() {
    // At rest with the energy in the flywheel, e_β = (−βV, −βV_I, q̇_F − βV_F): W_β is
    // ½‖e_β‖²_a = κ_a − βPᵀq̇_a + β²Ē = 2κ_a − β M_F V_F q̇_F.
    let t = run(10.0, 2000.0, [0.0, 0.0], 1.0, 0.01);
    let (w0, kappa) = (t.w_beta[0], t.energy[0]);
    assert!(w0 > 0.0 && w0 < 2.0 * kappa, "W_β(0) = {w0}, κ_a = {kappa}");
    // Once on the field (long after 1/(2γβĒ)), W_β is at its rounding.
    let t = run(40.0, 2000.0, [0.0, 0.0], 1.0, 1.0);
    let end = *t.w_beta.last().unwrap();
    assert!(end < 1e-10 * t.energy[0], "W_β = {end:e} on the field");
}
