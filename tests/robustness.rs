//! The robustness properties of section II (after Theorem 1): under a bounded disturbance
//! torque the velocity-field error `e_β = q̇_a − βV_a` is ultimately bounded, and the bound
//! shrinks as the gain `γ` grows (properties 1 and 2) and as the energy `β` grows (property
//! 3). The Pelican SCARA on the paper's Lissajous contour, frictionless, in closed loop (RK4
//! at 1 kHz, the disturbance held over each step): `‖e_β‖_a = √(2W_β)` (eq. 12) over the last
//! 10 s of 20 s, for disturbances along the desired momentum `P` (property 1), across the
//! field (`⟨F_e, V⟩ = 0`, property 2), and in fixed joint directions.

use nalgebra::{Matrix2, Vector2};
use pvfc::prelude::*;
use pvfc::sim::scenario::presets::pelican_example;
use pvfc::sim::ClosedLoop;

/// The direction of the disturbance.
#[derive(Clone, Copy, Debug)]
enum Disturbance {
    /// Along the robot's part of the desired momentum `P = M V` (property 1).
    AlongMomentum,
    /// Across the field, `⟨F_e, V⟩ = 0` (property 2).
    AcrossField,
    /// `(sin 3t, cos 5t)` in joint space.
    Joint,
}

/// What a disturbed run shows: the largest `‖e_β‖_a` over 10–15 s and over 15–20 s, and the
/// mean `β` over 10–20 s.
#[derive(Clone, Copy, Debug)]
struct Bound {
    early: f64,
    late: f64,
    beta: f64,
}

impl Bound {
    /// The ultimate bound: the largest `‖e_β‖_a` over the last 10 s.
    fn ultimate(&self) -> f64 {
        self.early.max(self.late)
    }
}

/// A 20 s run for `γĒ = gamma_e` (`Ē = 50`), starting at rest with `β = beta` (the flywheel at
/// `β√(2Ē/M_F)`), under a disturbance of `amplitude` N·m.
fn disturbed(gamma_e: f64, beta: f64, kind: Disturbance, amplitude: f64) -> Bound {
    let mut example = pelican_example();
    example.controller.gamma = gamma_e / example.controller.energy;
    let ctl = example.controller().unwrap();
    let sys = ClosedLoop::matched(ctl);
    let init = ctl.state();
    let mut s = AugmentedState {
        q: Torus::new(Vector2::new(0.0, 1.5)),
        v: Vector2::zeros(),
        tau: init.tau,
        tau_dot: init.tau_dot,
        flywheel_speed: beta * init.flywheel_speed,
    };
    let quarter = Matrix2::new(0.0, -1.0, 1.0, 0.0);
    let unit = |x: Vector2<f64>| x / x.norm().max(1e-12);
    let mut out = Bound {
        early: 0.0,
        late: 0.0,
        beta: 0.0,
    };
    let mut n = 0.0;
    for k in 0..20_000 {
        let t = k as f64 * 1e-3;
        let c = sys.evaluate(&s, &Vector2::zeros()).unwrap().coupling;
        let f = amplitude
            * match kind {
                Disturbance::AlongMomentum => unit(c.desired_momentum.robot) * (2.0 * t).sin(),
                Disturbance::AcrossField => {
                    unit(quarter * c.field_velocity.robot) * (2.0 * t).sin()
                }
                Disturbance::Joint => Vector2::new((3.0 * t).sin(), (5.0 * t).cos()),
            };
        let e = (2.0 * c.velocity_field_error_energy()).sqrt();
        if t >= 15.0 {
            out.late = out.late.max(e);
        } else if t >= 10.0 {
            out.early = out.early.max(e);
        }
        if t >= 10.0 {
            out.beta += c.beta;
            n += 1.0;
        }
        s = sys.rk4_step(&s, 1e-3, &f).unwrap();
    }
    out.beta /= n;
    out
}

const KINDS: [Disturbance; 3] = [
    Disturbance::AlongMomentum,
    Disturbance::AcrossField,
    Disturbance::Joint,
];

/// Properties 1 and 2: a disturbance of 0.5 N·m (a sixth of the forearm's friction in the
/// paper's experiment) leaves `‖e_β‖_a` bounded (it does not grow from 10–15 s to 15–20 s),
/// and the bound falls as `γ` grows: by more than 5× from `γĒ = 1` to 40 in every direction,
/// at every step for the disturbances across the field and in joint space.
#[test]
fn the_velocity_field_error_is_ultimately_bounded_and_shrinks_as_gamma_grows() {
    for kind in KINDS {
        let runs: Vec<(f64, Bound)> = [1.0, 2.5, 10.0, 40.0]
            .into_iter()
            .map(|g| (g, disturbed(g, 1.0, kind, 0.5)))
            .collect();
        println!(
            "{kind:?}: {}",
            runs.iter()
                .map(|(g, b)| format!("γĒ = {g}: ‖e_β‖ ≤ {:.3e} (β {:.3})", b.ultimate(), b.beta))
                .collect::<Vec<_>>()
                .join("; ")
        );
        for (g, b) in &runs {
            assert!(
                b.late <= 1.2 * b.early && b.ultimate().is_finite(),
                "{kind:?}, γĒ = {g}: ‖e_β‖ grows from {} to {}",
                b.early,
                b.late
            );
        }
        let (first, last) = (runs[0].1.ultimate(), runs[3].1.ultimate());
        assert!(
            last < first / 5.0,
            "{kind:?}: bound {first} at γĒ = 1, {last} at 40"
        );
        if !matches!(kind, Disturbance::AlongMomentum) {
            assert!(
                runs.windows(2)
                    .all(|w| w[1].1.ultimate() < w[0].1.ultimate()),
                "{kind:?}: the bound does not fall at every step of γ"
            );
        }
    }
}

/// Property 3: with more energy (`β` from 0.5 to 2, `γĒ = 2.5`) the bound falls relative to
/// the speed `β` (in joint space also in absolute terms; across the field it does not:
/// 0.30, 0.39, 0.33 — reported in the manual).
#[test]
fn the_bound_shrinks_relative_to_the_speed_as_the_energy_grows() {
    for kind in [Disturbance::AcrossField, Disturbance::Joint] {
        let runs: Vec<(f64, Bound)> = [0.5, 1.0, 2.0]
            .into_iter()
            .map(|b0| (b0, disturbed(2.5, b0, kind, 0.5)))
            .collect();
        println!(
            "{kind:?}: {}",
            runs.iter()
                .map(|(b0, b)| format!(
                    "β(0) = {b0}: ‖e_β‖ ≤ {:.3e}, ÷ β = {:.3e} (β {:.3})",
                    b.ultimate(),
                    b.ultimate() / b.beta,
                    b.beta
                ))
                .collect::<Vec<_>>()
                .join("; ")
        );
        assert!(
            runs.windows(2)
                .all(|w| w[1].1.ultimate() / w[1].1.beta < w[0].1.ultimate() / w[0].1.beta),
            "{kind:?}: ‖e_β‖/β does not fall as β grows"
        );
    }
}

/// The disturbance of a scenario (`[plant.disturbance]`, the presets `robustness_g*` that
/// `pvfc reproduce` runs for its claim and figure) is the one of the loop above: the same
/// ultimate bound within 0.1 % (the scenario evaluates the torque at every RK stage, the loop
/// above holds it over each step).
#[test]
fn the_scenario_disturbance_gives_the_loops_bound() {
    use pvfc::sim::trace::metrics::velocity_field_error_bound;
    for gamma_energy in [1, 10, 40] {
        let s = pvfc::sim::scenario::presets::robustness(gamma_energy);
        let t = pvfc::sim::run::simulate(&s, &mut |_| {}).unwrap();
        let scenario = velocity_field_error_bound(&t, 10.0, 20.1).unwrap();
        let by_hand = disturbed(f64::from(gamma_energy), 1.0, Disturbance::Joint, 0.5).ultimate();
        println!("γĒ = {gamma_energy}: scenario {scenario:.4e}, by hand {by_hand:.4e}");
        assert!(
            (scenario / by_hand - 1.0).abs() < 1e-3,
            "γĒ = {gamma_energy}: scenario {scenario}, by hand {by_hand}"
        );
    }
}
