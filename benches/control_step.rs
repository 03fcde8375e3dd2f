//! The control step as it runs in a 1 kHz loop: a fresh controller steps through 1000
//! measured states recorded from a closed-loop run (1 s, from q = (0, 0) onto the contour),
//! so states, branches and τ are those of a real run. Criterion reports the time of the
//! 1000 steps; divide by 1000 for one step (the throughput line gives steps per second).
//! Also: the same for f32, for a rigid body on SO(3), and one RK4 step of the closed loop.
//!
//! After criterion's groups (with `--bench`, not in `cargo test`'s quick pass), the passive
//! step's overhead over `Controller::step` is measured **interleaved**: 1,000 steps of each,
//! alternately, for many rounds, and the median of the per-round ratios is printed. Criterion
//! times one benchmark after the other, so on a shared machine a change of load between the
//! two shifts their ratio; two batches run back to back see the same load.

use criterion::{criterion_group, Criterion, Throughput};
use nalgebra::{Matrix3, Vector2, Vector3};
use pvfc::prelude::*;
use pvfc::sim::ClosedLoop;
use std::hint::black_box;
use std::time::Instant;

#[path = "common/machine.rs"]
mod machine;

const STEPS: usize = 1000;
const DT: f64 = 1e-3;

/// Measured states `(q, q̇)` of the SCARA, one per 1 kHz sample.
type Samples<T> = Vec<(Torus<T, 2>, Vector2<T>)>;

/// Records (q, q̇) along a closed-loop run of `sys` from `s`.
fn record<G, Sys, F, const D: usize>(
    sys: &ClosedLoop<f64, G, Sys, Sys, F, D>,
    mut s: AugmentedState<f64, G, D>,
) -> Vec<(G, Tangent<f64, D>)>
where
    G: LieGroup<f64, D>,
    Sys: MechanicalSystem<f64, G, D>,
    F: VelocityField<f64, G, D>,
{
    let zero = Tangent::<f64, D>::zeros();
    (0..STEPS)
        .map(|_| {
            let sample = (s.q, s.v);
            s = sys
                .rk4_step(&s, DT, &zero)
                .expect("the recorded run is valid");
            sample
        })
        .collect()
}

/// The paper's SCARA controller (the `pelican_example` scenario's, as the core builds it:
/// `tests/closed_loop.rs` checks they are equal), and the states recorded along its
/// closed-loop run from `q = (0, 0)`.
fn scara_f64() -> (ScaraLissajousController<f64>, Samples<f64>) {
    let scara = ScaraLissajousController::<f64>::pelican_example().expect("the example is valid");
    let sys = ClosedLoop::matched(scara);
    let i = *scara.state();
    let start = AugmentedState {
        q: Torus::new(Vector2::new(0.0, 0.0)),
        v: Vector2::zeros(),
        tau: i.tau,
        tau_dot: i.tau_dot,
        flywheel_speed: i.flywheel_speed,
    };
    (scara, record(&sys, start))
}

/// The paper's SCARA controller in f32, and the recorded states rounded to f32.
fn scara_f32(
    samples: &[(Torus<f64, 2>, Vector2<f64>)],
) -> (ScaraLissajousController<f32>, Samples<f32>) {
    let scara32 = ScaraLissajousController::<f32>::pelican_example().expect("valid");
    let samples32: Vec<_> = samples
        .iter()
        .map(|(q, v)| {
            (
                Torus::new(q.angles().map(|x| x as f32)),
                v.map(|x| x as f32),
            )
        })
        .collect();
    (scara32, samples32)
}

/// One pass of a fresh copy of `ctl` (`Controller::step`) through the recorded states.
fn run_steps<T, G, Sys, F, const D: usize>(
    mut ctl: Controller<T, G, Sys, F, D>,
    samples: &[(G, Tangent<T, D>)],
    dt: T,
) where
    T: Real,
    G: LieGroup<T, D>,
    Sys: MechanicalSystem<T, G, D>,
    F: VelocityField<T, G, D>,
{
    for (q, v) in samples {
        black_box(ctl.step(black_box(q), black_box(v), dt).expect("valid"));
    }
}

/// The same with the passive digital controller (`pvfc_core::passive`), measured velocities.
fn run_passive<T, G, Sys, F, const D: usize>(
    mut ctl: PassiveController<T, G, Sys, F, D>,
    samples: &[(G, Tangent<T, D>)],
    dt: T,
) where
    T: Real,
    G: VectorGroup<T, D>,
    Sys: MechanicalSystem<T, G, D>,
    F: VelocityField<T, G, D>,
{
    for (q, v) in samples {
        black_box(
            ctl.step(black_box(q), Some(black_box(v)), None, dt)
                .expect("valid"),
        );
    }
}

fn control_step(c: &mut Criterion) {
    let mut g = c.benchmark_group("control_step_x1000");
    g.throughput(Throughput::Elements(STEPS as u64));

    let (scara, samples) = scara_f64();
    let sys = ClosedLoop::matched(scara);
    g.bench_function("scara_lissajous_f64", |b| {
        b.iter(|| run_steps(scara, &samples, DT))
    });

    // The passive digital controller (pvfc_core::passive) on the same states, measured
    // velocities, right after the step it is compared with (the budget: ≤ 15 % over
    // it), so that the two medians of a pair are taken as close together as criterion can.
    let passive = PassiveController::new(scara);
    g.bench_function("scara_lissajous_f64_passive", |b| {
        b.iter(|| run_passive(passive, &samples, DT))
    });

    let (scara32, samples32) = scara_f32(&samples);
    g.bench_function("scara_lissajous_f32", |b| {
        b.iter(|| run_steps(scara32, &samples32, 1e-3))
    });
    let passive32 = PassiveController::new(scara32);
    g.bench_function("scara_lissajous_f32_passive", |b| {
        b.iter(|| run_passive(passive32, &samples32, 1e-3))
    });

    let field = SuspendedField::new(
        ConstantRate::new(So3::<f64>::identity(), Vector3::new(0.0, 0.3, 0.6)).expect("valid"),
        So3Navigation::new(Matrix3::from_diagonal(&Vector3::new(1.0, 2.0, 3.0))).expect("valid"),
        ExponentialPacing::new(20.0).expect("valid"),
    );
    let law = PvfcLaw::new(
        RigidBody::new(Matrix3::from_diagonal(&Vector3::new(0.8, 1.2, 1.5))).expect("valid"),
        field,
        Flywheel::new(1.0, 20.0).expect("valid"),
        0.1,
    )
    .expect("valid");
    let body = Controller::new(law).starting_at_rest(0.0);
    let body_sys = ClosedLoop::matched(body);
    let body_start = AugmentedState {
        q: So3::exp(&Vector3::new(1.2, -0.8, 0.5)),
        v: Vector3::zeros(),
        tau: 0.0,
        tau_dot: 0.0,
        flywheel_speed: body.state().flywheel_speed,
    };
    let body_samples = record(&body_sys, body_start);
    g.bench_function("rigid_body_so3_f64", |b| {
        b.iter(|| run_steps(body, &body_samples, DT))
    });
    g.finish();

    let s = AugmentedState {
        q: Torus::new(Vector2::new(0.1, -0.2)),
        v: Vector2::new(0.3, 0.1),
        tau: 0.3,
        tau_dot: 0.5,
        flywheel_speed: 9.0,
    };
    c.bench_function("closed_loop_rk4_step_scara_f64", |b| {
        b.iter(|| sys.rk4_step(black_box(&s), DT, &Vector2::zeros()))
    });
}

/// `a` and `b` run alternately, `rounds` times: the median time of each (µs per call) and
/// the median of the per-round ratios `b/a`, with its quartiles.
fn interleaved(rounds: usize, mut a: impl FnMut(), mut b: impl FnMut()) -> [f64; 5] {
    let time = |f: &mut dyn FnMut()| {
        let start = Instant::now();
        f();
        start.elapsed().as_secs_f64() * 1e6
    };
    let (mut ta, mut tb, mut ratios) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..rounds {
        let x = time(&mut a);
        let y = time(&mut b);
        ta.push(x);
        tb.push(y);
        ratios.push(y / x);
    }
    let quantile = |v: &mut Vec<f64>, p: f64| {
        v.sort_by(f64::total_cmp);
        v[((v.len() - 1) as f64 * p).round() as usize]
    };
    [
        quantile(&mut ta, 0.5),
        quantile(&mut tb, 0.5),
        quantile(&mut ratios, 0.5),
        quantile(&mut ratios, 0.25),
        quantile(&mut ratios, 0.75),
    ]
}

/// The passive step over `Controller::step` (the budget: ≤ 15 %), SCARA f64 and
/// f32, 1,000 recorded steps per call, measured interleaved (see the header).
fn passive_overhead() {
    const ROUNDS: usize = 2000;
    let (scara, samples) = scara_f64();
    let (scara32, samples32) = scara_f32(&samples);
    let passive = PassiveController::new(scara);
    let passive32 = PassiveController::new(scara32);
    let f64_ratio = interleaved(
        ROUNDS,
        || run_steps(scara, &samples, DT),
        || run_passive(passive, &samples, DT),
    );
    let f32_ratio = interleaved(
        ROUNDS,
        || run_steps(scara32, &samples32, 1e-3),
        || run_passive(passive32, &samples32, 1e-3),
    );
    println!("passive step ÷ Controller::step, interleaved, {ROUNDS} rounds of 1,000 steps each:");
    for (name, [a, b, r, lo, hi]) in [("f64", f64_ratio), ("f32", f32_ratio)] {
        println!(
            "  SCARA {name}: step {a:.1} µs, passive {b:.1} µs (medians); ratio {:+.1} % \
             (quartiles {:+.1} %, {:+.1} %; budget +15 %)",
            (r - 1.0) * 100.0,
            (lo - 1.0) * 100.0,
            (hi - 1.0) * 100.0
        );
    }
}

/// Sets or clears the SSE flush-to-zero and denormals-are-zero bits of this thread (x86-64).
#[cfg(target_arch = "x86_64")]
#[allow(deprecated, unsafe_code)]
fn flush_to_zero(on: bool) {
    use std::arch::x86_64::{_mm_getcsr, _mm_setcsr};
    // SAFETY: only the FTZ (bit 15) and DAZ (bit 6) control bits change.
    unsafe {
        let csr = _mm_getcsr();
        _mm_setcsr(if on { csr | 0x8040 } else { csr & !0x8040 });
    }
}

/// The f32 SCARA step over the f64 one, interleaved, and again with flush-to-zero set: on an
/// Intel core a step that meets subnormal numbers is slower without it.
fn f32_over_f64() {
    const ROUNDS: usize = 1000;
    let (scara, samples) = scara_f64();
    let (scara32, samples32) = scara_f32(&samples);
    let measure = || {
        interleaved(
            ROUNDS,
            || run_steps(scara, &samples, DT),
            || run_steps(scara32, &samples32, 1e-3),
        )
    };
    let plain = measure();
    #[cfg(target_arch = "x86_64")]
    let ftz = {
        flush_to_zero(true);
        let r = measure();
        flush_to_zero(false);
        Some(r)
    };
    #[cfg(not(target_arch = "x86_64"))]
    let ftz: Option<[f64; 5]> = None;
    println!("SCARA step f32 ÷ f64, interleaved, {ROUNDS} rounds of 1,000 steps each:");
    for (name, r) in [
        ("as the caller leaves the FPU", Some(plain)),
        ("flush-to-zero set", ftz),
    ] {
        if let Some([a, b, r, lo, hi]) = r {
            println!(
                "  {name}: f64 {:.1} ns, f32 {:.1} ns per step (medians); f32/f64 {r:.2} (quartiles {lo:.2}, {hi:.2})",
                a, b
            );
        }
    }
}

criterion_group!(benches, control_step);

fn main() {
    machine::print_machine();
    benches();
    Criterion::default().configure_from_args().final_summary();
    // Only when benchmarking (`cargo test` runs this target once, quickly), and unless a
    // filter excludes it.
    let args: Vec<String> = std::env::args().skip(1).collect();
    let filters: Vec<&String> = args.iter().filter(|a| !a.starts_with('-')).collect();
    let wanted = filters.is_empty()
        || filters
            .iter()
            .any(|f| "scara_lissajous_passive_interleaved".contains(f.as_str()));
    if args.iter().any(|a| a == "--bench") && wanted {
        passive_overhead();
    }
    let wanted = filters.is_empty()
        || filters
            .iter()
            .any(|f| "scara_f32_over_f64_interleaved".contains(f.as_str()));
    if args.iter().any(|a| a == "--bench") && wanted {
        f32_over_f64();
    }
}
