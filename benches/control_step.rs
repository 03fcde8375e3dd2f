//! One control step: SCARA + Lissajous + self-pacing (f64, f32), the SO(3) rigid body, and
//! one RK4 step of the closed loop.
//!
//! Every iteration starts from the same controller state (a copy, ~100 bytes): stepping one
//! controller millions of times at a fixed (q, q̇) would drive its internal τ to values no
//! real loop reaches.

use criterion::{criterion_group, criterion_main, Criterion};
use nalgebra::{Matrix3, Vector2, Vector3};
use pvfc::paper::{controller, PaperSettings};
use pvfc::prelude::*;
use pvfc::sim::ClosedLoop;
use std::hint::black_box;

fn control_step(c: &mut Criterion) {
    let mut g = c.benchmark_group("control_step");

    let scara = controller(&PaperSettings::default()).expect("paper settings are valid");
    let (q, v) = (Torus::new(Vector2::new(0.1, -0.2)), Vector2::new(0.3, 0.1));
    g.bench_function("scara_lissajous_f64", |b| {
        b.iter(|| black_box(scara).step(black_box(&q), black_box(&v), 1e-3))
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
    let (q32, v32) = (
        Torus::new(Vector2::new(0.1f32, -0.2)),
        Vector2::new(0.3f32, 0.1),
    );
    g.bench_function("scara_lissajous_f32", |b| {
        b.iter(|| black_box(scara32).step(black_box(&q32), black_box(&v32), 1e-3))
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
    let (r, w) = (
        So3::exp(&Vector3::new(0.3, 0.2, 0.1)),
        Vector3::new(0.1, 0.0, -0.2),
    );
    g.bench_function("rigid_body_so3_f64", |b| {
        b.iter(|| black_box(body).step(black_box(&r), black_box(&w), 1e-3))
    });
    g.finish();

    let ctl = controller(&PaperSettings::default()).expect("valid");
    let sys = ClosedLoop::matched(ctl);
    let s = AugmentedState {
        q,
        v,
        tau: 0.3,
        tau_dot: 0.5,
        flywheel_speed: 9.0,
    };
    c.bench_function("closed_loop_rk4_step_scara_f64", |b| {
        b.iter(|| sys.rk4_step(black_box(&s), 1e-3, &Vector2::zeros()))
    });
}

criterion_group!(benches, control_step);
criterion_main!(benches);
