//! The paper's contour in closed loop, without friction: prints how U(E) falls and how the
//! augmented kinetic energy stays put. `cargo run --release --example lissajous`
//! (optional arguments: R, γ, seconds).

use nalgebra::Vector2;
use pvfc::prelude::*;
use pvfc::sim::scenario::presets::pelican_example;
use pvfc::sim::ClosedLoop;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let mut example = pelican_example();
    if let Some(r) = args.first() {
        example.controller.self_pacing = *r;
    }
    if let Some(g) = args.get(1) {
        example.controller.gamma = *g;
    }
    let seconds = args.get(2).copied().unwrap_or(10.0);
    let ctl = example.controller()?;
    let sys = ClosedLoop::matched(ctl);
    let init = ctl.state();
    let mut s = AugmentedState {
        q: Torus::new(Vector2::new(0.0, 0.0)),
        v: Vector2::zeros(),
        tau: init.tau,
        tau_dot: init.tau_dot,
        flywheel_speed: init.flywheel_speed,
    };
    let dt = 1e-3;
    let steps = (seconds / dt).round() as usize;
    let e0 = sys.kinetic_energy(&s);
    println!(
        "PVFC on the paper's Lissajous contour (Pelican SCARA, no friction), R = {}, γ = {}",
        example.controller.self_pacing, example.controller.gamma
    );
    println!(
        "{:>6} {:>9} {:>10} {:>8} {:>8} {:>8} {:>12}",
        "t [s]", "τ", "U(E)", "λ₁", "τ̇", "β", "κ_a − κ_a(0)"
    );
    let zero = Vector2::zeros();
    for k in 0..=steps {
        if k % (steps / 20).max(1) == 0 {
            let out = sys.evaluate(&s, &zero)?.coupling;
            println!(
                "{:>6.2} {:>9.4} {:>10.3e} {:>8.4} {:>8.4} {:>8.5} {:>12.3e}",
                k as f64 * dt,
                s.tau,
                out.field.potential,
                out.field.lambda1,
                s.tau_dot,
                out.beta,
                sys.kinetic_energy(&s) - e0
            );
        }
        if k < steps {
            s = sys.rk4_step(&s, dt, &zero)?;
        }
    }
    Ok(())
}
