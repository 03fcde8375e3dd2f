//! The control step as it runs in a 1 kHz loop: a fresh controller steps through 1000
//! measured states recorded from a closed-loop run (1 s, from q = (0, 0) onto the contour),
//! so states, branches and τ are those of a real run. Criterion reports the time of the
//! 1000 steps; divide by 1000 for one step (the throughput line gives steps per second).
//! Also: the same for f32, for a rigid body on SO(3), and one RK4 step of the closed loop.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use nalgebra::{Matrix3, Vector2, Vector3};
use pvfc::prelude::*;
use pvfc::sim::presets::pelican_example;
use pvfc::sim::ClosedLoop;
use std::hint::black_box;

const STEPS: usize = 1000;
const DT: f64 = 1e-3;

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

fn control_step(c: &mut Criterion) {
    let mut g = c.benchmark_group("control_step_x1000");
    g.throughput(Throughput::Elements(STEPS as u64));

    let scara = pelican_example()
        .controller()
        .expect("the example is valid");
    let sys = ClosedLoop::matched(scara);
    let i = *scara.state();
    let start = AugmentedState {
        q: Torus::new(Vector2::new(0.0, 0.0)),
        v: Vector2::zeros(),
        tau: i.tau,
        tau_dot: i.tau_dot,
        flywheel_speed: i.flywheel_speed,
    };
    let samples = record(&sys, start);
    g.bench_function("scara_lissajous_f64", |b| {
        b.iter(|| {
            let mut ctl = scara;
            for (q, v) in &samples {
                black_box(ctl.step(black_box(q), black_box(v), DT).expect("valid"));
            }
        })
    });

    let field32 = SuspendedField::new(
        Lissajous::<f32, 2>::paper(),
        TorusNavigation::paper(Vector2::new(1.0f32, 1.0)).expect("valid"),
        ExponentialPacing::new(100.0f32).expect("valid"),
    );
    let law32 = PvfcLaw::new(
        Scara::<f32>::pelican(),
        field32,
        Flywheel::new(1.0f32, 50.0).expect("valid"),
        0.05,
    )
    .expect("valid");
    let scara32 = Controller::new(law32).starting_at_rest(0.0);
    let samples32: Vec<_> = samples
        .iter()
        .map(|(q, v)| {
            (
                Torus::new(q.angles().map(|x| x as f32)),
                v.map(|x| x as f32),
            )
        })
        .collect();
    g.bench_function("scara_lissajous_f32", |b| {
        b.iter(|| {
            let mut ctl = scara32;
            for (q, v) in &samples32 {
                black_box(ctl.step(black_box(q), black_box(v), 1e-3).expect("valid"));
            }
        })
    });

    // The passive digital controller (pvfc_core::passive) on the same states, measured
    // velocities, beside the step above (the budget: ≤ 15 % over it).
    let passive = PassiveController::new(scara);
    g.bench_function("scara_lissajous_f64_passive", |b| {
        b.iter(|| {
            let mut ctl = passive;
            for (q, v) in &samples {
                black_box(
                    ctl.step(black_box(q), Some(black_box(v)), None, DT)
                        .expect("valid"),
                );
            }
        })
    });
    let passive32 = PassiveController::new(scara32);
    g.bench_function("scara_lissajous_f32_passive", |b| {
        b.iter(|| {
            let mut ctl = passive32;
            for (q, v) in &samples32 {
                black_box(
                    ctl.step(black_box(q), Some(black_box(v)), None, 1e-3)
                        .expect("valid"),
                );
            }
        })
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
        b.iter(|| {
            let mut ctl = body;
            for (q, v) in &body_samples {
                black_box(ctl.step(black_box(q), black_box(v), DT).expect("valid"));
            }
        })
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

criterion_group!(benches, control_step);
criterion_main!(benches);
