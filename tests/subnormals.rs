//! The `f32` step stays out of subnormal numbers. On Intel cores every operation on a
//! subnormal operand takes a microcode assist of ~100 cycles, and self-pacing at a large error
//! makes `exp(−R U)`, `τ`, `τ̇` and the contour's `sin` arguments tiny: without care half the
//! SCARA's steps met one (474 of 1,000 steps of this run) and the `f32` step took twice the
//! `f64` one. The x86 SSE status register records a denormal operand (flag DE, bit 1) and an
//! underflow (UE, bit 4) since it was last cleared: each step here runs with the flags
//! cleared, and the steps that raised DE are counted, for the continuous-time and the
//! passive step, along the recorded run the benchmark uses (`benches/control_step.rs`).
#![cfg(target_arch = "x86_64")]
// Reading and clearing the SSE status register (`_mm_getcsr`, `_mm_setcsr`, deprecated in
// favour of inline assembly, and unsafe).
#![allow(deprecated, unsafe_code)]

use nalgebra::Vector2;
use pvfc::prelude::*;
use pvfc::sim::scenario::presets::pelican_example;
use pvfc::sim::ClosedLoop;
use std::arch::x86_64::{_mm_getcsr, _mm_setcsr};

/// Runs `f` with the SSE exception flags cleared; whether it met a denormal operand.
fn met_a_subnormal(f: impl FnOnce()) -> bool {
    // SAFETY: only the six sticky exception flags are cleared; the control bits (rounding,
    // masks, flush-to-zero) are kept.
    unsafe { _mm_setcsr(_mm_getcsr() & !0x3F) };
    f();
    // SAFETY: reading the status register.
    unsafe { _mm_getcsr() & 0x2 != 0 }
}

/// The SCARA's states along 1 s of the closed loop from `q = (0, 0)`, in `f32`.
fn recorded_run() -> Vec<(Torus<f32, 2>, Vector2<f32>)> {
    let scara = pelican_example().controller().expect("valid");
    let sys = ClosedLoop::matched(scara);
    let i = *scara.state();
    let mut s = AugmentedState {
        q: Torus::new(Vector2::new(0.0, 0.0)),
        v: Vector2::zeros(),
        tau: i.tau,
        tau_dot: i.tau_dot,
        flywheel_speed: i.flywheel_speed,
    };
    (0..1000)
        .map(|_| {
            let sample = (
                Torus::new(s.q.angles().map(|x| x as f32)),
                s.v.map(|x| x as f32),
            );
            s = sys.rk4_step(&s, 1e-3, &Vector2::zeros()).expect("valid");
            sample
        })
        .collect()
}

fn scara_f32() -> ScaraLissajousController<f32> {
    ScaraLissajousController::pelican_example().expect("valid")
}

#[test]
fn the_f32_step_meets_almost_no_subnormal_number() {
    let run = recorded_run();
    let mut ctl = scara_f32();
    let mut passive = PassiveController::new(scara_f32());
    let (mut law, mut tank) = (0, 0);
    for (q, v) in &run {
        law += usize::from(met_a_subnormal(|| {
            ctl.step(q, v, 1e-3).expect("valid");
        }));
        tank += usize::from(met_a_subnormal(|| {
            passive.step(q, Some(v), None, 1e-3).expect("valid");
        }));
    }
    println!("steps that met a subnormal operand: {law} of 1000 (law), {tank} (passive)");
    // Today 6 and 6, where the pacing gain crosses its floor (2⁻⁴⁰): the contour's
    // acceleration times τ̇ times λ₁ for a few steps. Without the floor and the sine's small-
    // argument path, 474.
    assert!(law <= 10 && tank <= 10, "{law}, {tank}");
}
